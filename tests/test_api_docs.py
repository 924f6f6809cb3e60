"""The Python API's documentation: docs/api.md is the generator's output, every
public function is typed and documented, help(fpd)'s example runs, and
Result.plot() gives the run's figures."""
from __future__ import annotations

import inspect
import os
import re
from pathlib import Path

import pytest

import fpd
from fpd.frontends import api, apidoc

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt
    plt.close("all")


def test_api_md_is_current():
    text = (ROOT / "docs" / "api.md").read_text()
    assert text == apidoc.render(), "docs/api.md is stale: python3 -m fpd.frontends.apidoc > docs/api.md"


def _callables():
    for name in api.__all__:
        obj = getattr(api, name)
        if inspect.isfunction(obj):
            yield f"fpd.{name}", obj
        elif inspect.isclass(obj):
            for m, member in apidoc.members(obj):
                yield f"fpd.{name}.{m}", member.fget if isinstance(member, property) else member


def test_every_public_function_is_typed_and_documented():
    seen = 0
    for name, fn in _callables():
        seen += 1
        assert (inspect.getdoc(fn) or "").strip(), f"{name} has no docstring"
        sig = inspect.signature(fn)
        assert sig.return_annotation is not sig.empty, f"{name}: no return type"
        for p in sig.parameters.values():
            if p.name != "self":
                assert p.annotation is not p.empty, f"{name}: parameter {p.name} has no type"
    assert seen >= 12
    for name in api.__all__:            # the classes, too
        assert (inspect.getdoc(getattr(api, name)) or "").strip(), f"fpd.{name} has no docstring"
    # and every public name is in the page
    text = (ROOT / "docs" / "api.md").read_text()
    for name in api.__all__:
        assert f"fpd.{name}" in text


def _example(doc: str) -> str:
    """The indented block after the first '::' of a docstring."""
    after = doc.split("::", 1)[1]
    lines = []
    for line in after.splitlines()[1:]:
        if line.strip() and not line.startswith("    "):
            break
        lines.append(line[4:])
    return "\n".join(lines).strip() + "\n"


@pytest.mark.parametrize("doc", ["fpd", "fpd.frontends.api"])
def test_help_example_runs(doc, tmp_path, monkeypatch):
    """The example help(fpd) shows (and the API module's) runs as written."""
    monkeypatch.chdir(tmp_path)          # it saves loop.png in the working folder
    monkeypatch.setenv("MPLBACKEND", "Agg")
    code = _example((fpd if doc == "fpd" else api).__doc__)
    assert "fpd.run(" in code
    exec(compile(code, f"<{doc} docstring>", "exec"), {})
    if "savefig" in code:
        assert (tmp_path / "loop.png").stat().st_size > 10_000


def test_result_plot_returns_the_run_figures():
    from matplotlib.figure import Figure
    r = fpd.run("default", solver={"duration": 6.0})
    figs = r.plot()
    assert list(figs) == ["hysteresis", "response", "temperature", "friction"] == r.figure_names()
    assert all(isinstance(f, Figure) for f in figs.values())
    fig = r.plot("hysteresis")
    (ax,) = fig.axes
    x, y = ax.lines[0].get_data()
    # the loop drawn is the run's F-u (every row up to the drawn envelope)
    assert x.min() == pytest.approx(1e3 * r.history["u_m"].min())
    assert y.max() == pytest.approx(1e-3 * r.history["F_N"].max())
    with pytest.raises(ValueError, match="hysteresis, response"):
        r.plot("loops")


def test_result_plot_bidirectional_has_signed_x_and_y_loops():
    r = fpd.run("impvall-bidirectional", solver={"duration": 8.0})
    fig = r.plot("hysteresis")
    ax_x, ax_y = fig.axes
    assert "u_x" in ax_x.get_xlabel() and "F_x" in ax_x.get_ylabel()
    assert "u_y" in ax_y.get_xlabel() and "F_y" in ax_y.get_ylabel()
    ux, Fx = ax_x.lines[0].get_data()
    assert ux.min() < 0 < ux.max() and Fx.min() < 0 < Fx.max()       # signed, not |F| against |u|
    # each loop's title gives its integral of F du; their sum is the bearing's work on the
    # relative motion, integral of (Fx dux + Fy duy), computed here from the history
    h = r.history
    tot = sum(float(((h[f"F{d}_N"][1:] + h[f"F{d}_N"][:-1]) / 2 * (h[f"u{d}_m"][1:] - h[f"u{d}_m"][:-1])).sum())
              for d in "xy")
    shown = sum(float(re.search(r"= (-?[\d.e+-]+) kJ", a.get_title()).group(1)) for a in (ax_x, ax_y))
    assert shown == pytest.approx(1e-3 * tot, rel=2e-3, abs=0.05)
    assert {"orbit", "force_orbit", "heat_path"} <= set(r.plot())


def test_plot_of_test_machine_has_cycles():
    r = fpd.run("lab-sine", solver={"duration": 5.0})
    assert r.figure_names()[-1] == "cycles"
    fig = r.plot("cycles")
    assert any("surface T" in a.get_ylabel() for a in fig.axes)
    legend = r.plot("hysteresis").axes[0].get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["cycle 1", "cycle 2"]


def test_no_pyplot_figures_left_by_fpd_run(tmp_path):
    """fpd run's plots go through Agg without pyplot: nothing is left open."""
    import matplotlib.pyplot as plt
    before = len(plt.get_fignums())
    fpd.run("default", out=tmp_path / "r", solver={"duration": 3.0})
    assert len(plt.get_fignums()) == before
    assert os.path.exists(tmp_path / "r" / "plots" / "hysteresis.png")
