"""Vertical ground motion in sweeps (docs/sweeps.md "Vertical ground motion"):
a member gets a vertical record or a scaled copy of its horizontal one only
where the sweep (or the base scene, for the scale) names it; the scene key
loading.vertical_scale; bad input in one line."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.schema import scene as scn
from fpd.studies import sweep as swp

ROOT = Path(__file__).resolve().parents[1]
RECORDS = ROOT / "scenes" / "records"
PULSE = Path(__file__).resolve().parent / "data" / "pulse_z.txt"


def _zero(path: Path) -> Path:
    path.write_text("# [g]\n" + "".join(f"{0.004 * k:.3f} 0.0\n" for k in range(3000)))
    return path


def _write(d: Path, text: str, name="s.toml") -> Path:
    p = d / name
    p.write_text(text)
    return p


def test_zip_pairs_each_record_with_its_vertical(tmp_path):
    z0 = _zero(tmp_path / "zero.txt")
    s = _write(tmp_path, f'''scene = "default"
mode = "zip"
[set]
"solver.duration" = 3.0
[axes]
"loading.file" = ["{RECORDS / 'IELC180.AT2'}", "{RECORDS / 'Northridge_CDMG24278_090.dat'}"]
"loading.file_z" = ["{PULSE}", "{z0}"]
''')
    sw = swp.load_sweep(str(s))
    assert [Path(m.scene["loading"]["path_z"]).name for m in sw.members] == ["pulse_z.txt", "zero.txt"]
    assert len({m.hash for m in sw.members}) == 2
    # the member's run sees its own vertical: the pulse lifts the first, the zeros leave the second seated
    r = simulate(build(sw.members[0].scene))
    assert r["n_lift"][-1] == 1.0
    r = simulate(build(sw.members[1].scene))
    assert np.all(r["az_mps2"] == 0.0)


BASE_Z = f"""
name = "base-z"
[device]
kind = "DFP"
R1 = 2.2
R2 = 2.2
pad_height = 0.10
pad_diameter = 0.25
[superstructure]
mass = 1.0e5
[friction]
law = "constant"
mu = 0.06
[loading]
kind = "record"
record = "elcentro-1940"
file_z = "{PULSE}"
[thermal]
model = "none"
[solver]
duration = 3.0
"""


def test_a_base_vertical_is_not_paired_silently_with_other_records(tmp_path):
    _write(tmp_path, BASE_Z, "base.toml")
    s = _write(tmp_path, f'''scene = "base.toml"
[axes]
"loading.file" = ["{RECORDS / 'IELC180.AT2'}"]
''')
    with pytest.raises(scn.SceneError, match=r"^[^\n]*loading\.file changes the record[^\n]*file_z[^\n]*$"):
        swp.load_sweep(str(s))
    # naming it is fine: here the same vertical for every member
    _write(tmp_path, f'''scene = "base.toml"
[set]
"loading.file_z" = "{PULSE}"
[axes]
"loading.file" = ["{RECORDS / 'IELC180.AT2'}"]
''', "ok.toml")
    assert len(swp.load_sweep(str(tmp_path / "ok.toml")).members) == 1
    # a sweep that keeps the record keeps the base scene's vertical (the scene names it for its record)
    _write(tmp_path, 'scene = "base.toml"\n[axes]\n"friction.mu" = [0.05, 0.06]\n', "mu.toml")
    assert all(m.scene["loading"]["path_z"] == str(PULSE) for m in swp.load_sweep(str(tmp_path / "mu.toml")).members)


def test_vertical_scale_is_a_scaled_copy_of_the_horizontal_record():
    """vertical_scale = 1 is file_z = the horizontal record's own file, bit for
    bit (the same reading, baseline and integration, all linear); 0.5 gives
    az_mps2 = 0.5 times the horizontal step accelerations; the summary names it."""
    over = ["solver.duration=4", "thermal.model=none"]
    a = simulate(build(scn.load("default", over + ["loading.vertical_scale=1.0"])))
    b = simulate(build(scn.load("default", over + [f'loading.file_z="{RECORDS / "IELC180.AT2"}"'])))
    assert a.columns == b.columns
    np.testing.assert_array_equal(a.data, b.data)
    sim = build(scn.load("default", over + ["loading.vertical_scale=0.5"]))
    r = simulate(sim)
    ax = np.asarray(sim.mechanics._ax, dtype=float)
    np.testing.assert_array_equal(r["az_mps2"][1:], 0.5 * ax[:len(r["az_mps2"]) - 1])
    assert sim.info["record_z"] == {"name": "0.5 x elcentro-1940", "vertical_scale": 0.5, "of": "elcentro-1940"}


def test_vertical_scale_on_the_flat_bearing_and_refusals(tmp_path):
    flat = BASE_Z.replace('kind = "DFP"\nR1 = 2.2\nR2 = 2.2', 'kind = "flat"').replace(f'file_z = "{PULSE}"',
                                                                                         "vertical_scale = 0.67")
    r = simulate(build(scn.load(str(_write(tmp_path, flat, "flat.toml")))))
    assert r.status == "ok" and np.any(r["az_mps2"] != 0.0)
    with pytest.raises(scn.SceneError, match=r"^[^\n]*loading\.vertical_scale[^\n]*one vertical component[^\n]*$"):
        scn.load("default", ["loading.vertical_scale=0.5", f'loading.file_z="{PULSE}"'])
    # the TFP takes it too (tests/test_tfp3d_vertical.py)
    assert scn.load("tfp-elcentro", ["loading.vertical_scale=0.5"])["loading"]["vertical_scale"] == 0.5
    with pytest.raises(scn.SceneError, match=r"^[^\n]*loading\.vertical_scale = 0[^\n]*non-zero[^\n]*$"):
        scn.load("default", ["loading.vertical_scale=0"])
    with pytest.raises(scn.SceneError, match=r"loading\.vertical_scale"):
        scn.load("lab-sine", ["loading.vertical_scale=0.5"])         # a key of records only


def test_p695_members_take_a_vertical_only_as_a_named_scale(tmp_path):
    p695 = pytest.importorskip("fpd.loading.p695")
    try:
        p695.members("p695-far-field")
    except Exception as exc:                              # the record package not installed
        pytest.skip(str(exc))
    s = _write(tmp_path, '''scene = "default"
[set]
"loading.vertical_scale" = 0.67
"loading.component" = "a"
[axes]
"loading.record_set" = ["p695-far-field"]
''')
    sw = swp.load_sweep(str(s))
    assert len(sw.members) == 22
    assert all(m.scene["loading"]["vertical_scale"] == 0.67 and "path_z" not in m.scene["loading"]
               for m in sw.members)
    _write(tmp_path, 'scene = "default"\n[set]\n"loading.component" = "a"\n[axes]\n'
                     '"loading.record_set" = ["p695-far-field"]\n', "none.toml")
    assert all("vertical_scale" not in m.scene["loading"] for m in swp.load_sweep(str(tmp_path / "none.toml")).members)
