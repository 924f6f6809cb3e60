"""docs/tutorial.md runs as written: its blocks, in order, in an empty folder.

```toml file=NAME``` blocks are written to NAME, every line of a ```sh```
block is run by the shell (each must exit 0), ```python``` blocks run in one
namespace (their asserts check the numbers the page states)."""
from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TUTORIAL = ROOT / "docs" / "tutorial.md"
FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```\s*$", flags=re.M | re.S)


def blocks(text: str) -> list[tuple[str, str]]:
    """(info string, body) of every fenced block, in order."""
    return [(m.group(1).strip(), m.group(2)) for m in FENCE.finditer(text)]


def test_tutorial_has_every_kind_of_block():
    kinds = [info.split()[0] for info, _ in blocks(TUTORIAL.read_text()) if info]
    assert kinds.count("sh") >= 2 and kinds.count("python") >= 3 and "toml" in kinds
    assert all(k in ("sh", "python", "toml") for k in kinds), kinds      # nothing left unrun


def test_tutorial_runs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg")
    ns: dict = {}
    ran = {"sh": 0, "python": 0, "toml": 0}
    for info, body in blocks(TUTORIAL.read_text()):
        kind = info.split()[0] if info else ""
        if kind == "toml":
            name = dict(w.split("=", 1) for w in info.split()[1:] if "=" in w)["file"]
            (tmp_path / name).write_text(body)
        elif kind == "sh":
            for line in body.splitlines():
                line = line.split("  #")[0].strip()
                if not line or line.startswith("#"):
                    continue
                argv = shlex.split(line)
                assert argv[:3] == ["python3", "-m", "fpd"], line     # the page's commands use this checkout
                r = subprocess.run([sys.executable, *argv[1:]], cwd=tmp_path, env=env, capture_output=True,
                                   text=True, timeout=600)
                assert r.returncode == 0, f"{line}\n{r.stderr}"
        elif kind == "python":
            exec(compile(body, f"{TUTORIAL.name} python block {ran['python'] + 1}", "exec"), ns)
        else:
            pytest.fail(f"a block the test cannot run: {info!r}")
        ran[kind] += 1
    assert all(ran.values()), ran
    # what the page says the run writes
    out = tmp_path / "results" / "my-bearing"
    for f in ("timeseries.csv", "summary.json", "cycles.csv", "scene.toml", "plots/hysteresis.png",
              "plots/cycles.png", "plots/temperature.png", "plots/friction.png", "plots/response.png",
              "plots/lower_plate_hottest.png"):
        assert (out / f).exists(), f
    assert (tmp_path / "my-bearing-loop.png").stat().st_size > 10_000
    import matplotlib.pyplot as plt
    plt.close("all")
