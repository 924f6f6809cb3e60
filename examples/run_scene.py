"""Run a packaged scene from Python and print its summary.

    python examples/run_scene.py [SCENE] [DURATION_S]

The summary holds the fields of summary.json; the history is timeseries.csv
as named numpy arrays (docs/reference.md describes both).
"""
import json
import sys

import fpd

scene = sys.argv[1] if len(sys.argv) > 1 else "default"
duration = float(sys.argv[2]) if len(sys.argv) > 2 else 5.0

r = fpd.run(scene, solver={"duration": duration})
print(json.dumps(r.summary, indent=2))
u = r.history["u_m"]
print(f"{r.history.n_rows} rows; |u| peaks at {1e3 * abs(u).max():.1f} mm")
