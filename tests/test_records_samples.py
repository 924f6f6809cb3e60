"""Records without times: acceleration samples with loading.dt (one value
per line as OpenSees users keep them, or several per line as PEER-processed
data without its header), and errors that name the first real problem
(issue 18)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fpd.loading.ground_motion import RecordError, read_record

ROOT = Path(__file__).resolve().parents[1]
DT = 0.01


def _accel(n=700):
    k = np.arange(n)
    return 0.3 * np.sin(2 * np.pi * 1.1 * k * DT) * np.exp(-0.3 * k * DT) + 0.05 * np.cos(7.3 * k * DT)


def _write(tmp_path):
    a = _accel().tolist()            # plain floats: repr gives the shortest round-trip digits
    one = tmp_path / "one.txt"
    one.write_text("".join(f"{x!r}\n" for x in a))
    two = tmp_path / "two.txt"
    two.write_text("".join(f"{k * DT!r} {x!r}\n" for k, x in enumerate(a)))   # times k dt, to the last digit
    five = tmp_path / "five.txt"
    rows = [a[i:i + 5] for i in range(0, len(a), 5)]
    five.write_text("PEER-processed, header removed by hand\nacceleration in g\n"
                    + "".join("  ".join(f"{x!r}" for x in r) + "\n" for r in rows))
    return one, two, five


def _scene(tmp_path, path, extra=""):
    """The default scene with the record file in place of its packaged record."""
    from fpd.schema.scene import SCENES_DIR

    text = (SCENES_DIR / "default.toml").read_text()
    text = text.replace('record = "elcentro-1940"', f'file = "{path}"\nunits = "g"\n{extra}')
    f = tmp_path / f"{Path(path).stem}.toml"
    f.write_text(text)
    return f


def _run(path, extra=""):
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate

    sc = scn.load(str(_scene(Path(path).parent, path, extra)), ["solver.duration=4.0", 'thermal.model="lumped"'])
    res = simulate(build(sc))
    assert res.status == "ok", res.message
    return res


def test_one_column_with_dt_is_the_two_column_run_bit_for_bit(tmp_path):
    one, two, five = _write(tmp_path)
    r1 = _run(one, f"dt = {DT!r}")
    r2 = _run(two)
    r5 = _run(five, f"dt = {DT!r}")
    assert r1.columns == r2.columns
    assert np.array_equal(r1.data, r2.data)          # bit for bit, every column of every step
    assert np.array_equal(r5.data, r2.data)
    assert np.max(np.abs(r1["u_m"])) > 1e-3          # the record moved the device


def test_samples_reader(tmp_path):
    one, two, five = _write(tmp_path)
    a = read_record(one, "g", DT)
    b = read_record(five, "g", DT)
    np.testing.assert_array_equal(a.t, np.arange(700) * DT)
    np.testing.assert_array_equal(a.a_g, b.a_g)
    assert "PEER-processed" in b.source
    m = read_record(one, "m/s2", DT)
    np.testing.assert_allclose(m.a_g * 9.80665, a.a_g, rtol=1e-15)


@pytest.mark.parametrize("content,units,dt,tokens,absent", [
    # one value per line, nothing else given: the missing interval first, not the units
    ("0.1\n0.2\n0.3\n", None, None, ["1 value per line", "loading.dt", "line 1"], ["not named"]),
    ("# acc\n0.1 0.2 0.3\n0.4 0.5 0.6\n", None, None, ["3 values per line", "loading.dt", "line 2"], ["expected 2 columns", "not named"]),
    # with the interval, then the units
    ("0.1\n0.2\n0.3\n", None, 0.01, ["acceleration samples", "loading.units"], ["expected 2 columns"]),
    ("0.1\n0.2\nabc\n", "g", 0.01, ["line 3", "'abc'", "not a number"], []),
    ("0.1\n0.2\ninf\n", "g", 0.01, ["line 3", "non-finite"], []),
    ("0.1\n", "g", 0.01, ["fewer than two"], []),
    ("header only\n", "g", 0.01, ["no line of numbers"], []),
    # two columns, units missing: that is the first problem
    ("0 0.1\n0.01 0.2\n", None, None, ["two-column record", "units not named"], []),
])
def test_errors_name_the_first_real_problem(tmp_path, content, units, dt, tokens, absent):
    f = tmp_path / "r.txt"
    f.write_text(content)
    with pytest.raises(RecordError) as exc:
        read_record(f, units, dt)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith(str(f))
    for tok in tokens:
        assert tok in msg, (tok, msg)
    for tok in absent:
        assert tok not in msg, (tok, msg)


def test_at2_with_dt_is_refused():
    from fpd.schema.scene import SCENES_DIR
    with pytest.raises(RecordError, match="remove loading.dt"):
        read_record(SCENES_DIR / "records" / "IELC180.AT2", None, 0.01)


def test_cli_one_line_exit_2(tmp_path):
    f = tmp_path / "acc.txt"
    f.write_text("0.1\n0.2\n0.3\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    sc = _scene(tmp_path, f).read_text().replace('units = "g"\n', "")
    (tmp_path / "s.toml").write_text(sc)
    for extra in ([], ["--set", "loading.dt=-1"]):
        r = subprocess.run([sys.executable, "-m", "fpd", "run", str(tmp_path / "s.toml"), *extra, "--out",
                            str(tmp_path / "out"), "--quiet"], env=env, capture_output=True, text=True, timeout=120)
        assert r.returncode == 2 and r.stderr.count("\n") == 1 and "loading.dt" in r.stderr, r.stderr
        assert "units" not in r.stderr.split("loading.dt")[0]
        assert not (tmp_path / "out").exists()
