"""summary.json reads every step, whatever rows the history keeps: peaks,
residuals and ledgers are the same with output.csv_every = 1, 10 and 100
(coupling/run.StepTracker, engine_kernel.track_row)."""
import pytest

from fpd.frontends import api


def _flat(d, prefix=""):
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out.update(_flat(v, prefix + k + "."))
        else:
            out[prefix + k] = v
    return out


def _summary(scene, every, **over):
    s = api.run(scene, output={"csv_every": every, "plots": False}, **over).summary
    return {k: v for k, v in _flat(s).items() if k not in ("runtime_s",)}


CASES = [
    ("default", {"solver": {"duration": 10.0}}),                                   # the compiled engine, fe1d
    ("default", {"solver": {"duration": 6.0}, "coupling": {"scheme": "iterated"}}),     # the Python loop
    ("impvall-bidirectional", {"solver": {"duration": 8.0}}),
    ("tfp-elcentro", {"solver": {"duration": 6.0}, "thermal": {"model": "lumped"}}),
]


@pytest.mark.parametrize("scene, over", CASES, ids=["default", "iterated", "bidirectional", "tfp"])
def test_summary_is_the_same_whatever_rows_are_kept(scene, over):
    every1 = _summary(scene, 1, **over)
    for every in (10, 100):
        other = _summary(scene, every, **over)
        diff = {k: (every1[k], other.get(k)) for k in every1 if every1[k] != other.get(k)}
        assert not diff, (every, diff)


def test_peak_force_of_the_default_scene_is_every_steps():
    """The default scene: the largest |F| is 70.20 kN on every step (69.25 kN
    on the rows of csv_every = 100 alone)."""
    s = api.run("default", output={"csv_every": 100, "plots": False}).summary
    assert s["peak_F_N"] == pytest.approx(70203.05, rel=1e-6)
