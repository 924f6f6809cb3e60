"""Record readers (issues 1 and 8): PEER .AT2 header variants, two-column
text, the shipped records, and the one-line RecordError for bad files."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fpd.loading.ground_motion import (RecordError, guess_format, parse_at2, parse_two_column,
                                     read_record)

ROOT = Path(__file__).resolve().parent.parent
RECORDS = ROOT / "scenes" / "records"
VALUES = "  .1000000E-01  -.2000000E-01   .3000000E-01\n  -.4000000E-01   .5000000E-01\n"


@pytest.mark.parametrize("header,npts,dt", [
    ("NPTS=  5, DT= .01000 SEC", 5, 0.01),                  # legacy PEER
    ("NPTS=   5, DT=   .0050 SEC,", 5, 0.005),              # NGA-West2, trailing comma
    ("5 0.0100 NPTS, DT", 5, 0.01),                          # values first
    ("   5    0.0200    NPTS, DT", 5, 0.02),
    ("NPTS=5, DT=.01", 5, 0.01),                             # no SEC, no spaces
    ("NPTS = 5 , DT = 0.01 SEC ,", 5, 0.01),                 # spaces around '=' and commas
    ("npts= 5, dt= 1.0E-02 sec", 5, 0.01),                   # lower case, exponent
    ("NPTS: 5, DT: 0.01", 5, 0.01),
])
def test_at2_header_variants(tmp_path, header, npts, dt):
    f = tmp_path / "rec.AT2"
    f.write_text(f"PEER NGA STRONG MOTION DATABASE RECORD\nSOMEWHERE, 1999\n"
                 f"ACCELERATION TIME SERIES IN UNITS OF G\n{header}\n{VALUES}")
    rec = read_record(f)
    assert len(rec.t) == npts
    assert rec.dt == pytest.approx(dt)
    np.testing.assert_allclose(rec.a_g, [0.01, -0.02, 0.03, -0.04, 0.05])
    assert rec.t[-1] == pytest.approx((npts - 1) * dt)


def test_at2_comma_separated_values(tmp_path):
    f = tmp_path / "rec.AT2"
    f.write_text("T\nT\nT\nNPTS=  4, DT= .01 SEC\n0.1, 0.2, 0.3,\n0.4\n")
    np.testing.assert_allclose(read_record(f).a_g, [0.1, 0.2, 0.3, 0.4])


def test_shipped_el_centro():
    rec = read_record(RECORDS / "IELC180.AT2")
    assert len(rec.t) == 4000
    assert rec.dt == pytest.approx(0.01)
    assert rec.pga_g == pytest.approx(0.3129, abs=5e-5)
    assert "IMPERIAL VALLEY" in rec.source


def test_shipped_northridge_two_column():
    rec = read_record(RECORDS / "Northridge_CDMG24278_090.dat")
    assert len(rec.t) == 3989
    assert rec.t[0] == 0.0 and np.all(np.diff(rec.t) > 0)
    assert np.all(np.isfinite(rec.a_g)) and 0.05 < rec.pga_g < 2.0


def test_guess_format():
    assert guess_format((RECORDS / "IELC180.AT2").read_text()) == "at2"
    assert guess_format((RECORDS / "Northridge_CDMG24278_090.dat").read_text()) == "two-column"


@pytest.mark.parametrize("sep", [" ", "\t", ",", ", ", ";"])
def test_two_column_separators(sep):
    text = f"# comment\nTime (s){sep}Accel (g)\n" + "".join(
        f"{0.01 * i:.2f}{sep}{0.1 * i:.2f}\n" for i in range(5))
    rec = parse_two_column(text, "x.txt", "g")
    np.testing.assert_allclose(rec.a_g, [0.0, 0.1, 0.2, 0.3, 0.4])
    np.testing.assert_allclose(rec.t, [0.0, 0.01, 0.02, 0.03, 0.04])


def test_two_column_units():
    text = "0.0 0.0\n0.5 9.80665\n1.0 0.0\n"
    assert parse_two_column(text, "x", "m/s2").a_g[1] == pytest.approx(1.0)
    assert parse_two_column(text, "x", "g").a_g[1] == pytest.approx(9.80665)


def test_two_column_units_from_header(tmp_path):
    for head, scale in (("Time[s] Accel[g]", 1.0), ("t (s), a (m/s2)", 1 / 9.80665),
                        ("time, acc [m/s^2]", 1 / 9.80665)):
        f = tmp_path / "r.txt"
        f.write_text(f"{head}\n0 0\n0.01 1.0\n0.02 0\n")
        assert read_record(f).a_g[1] == pytest.approx(scale)


def test_two_column_starting_late_is_shifted():
    rec = parse_two_column("5.0 0.1\n5.01 0.2\n5.02 0.3\n", "x", "g")
    np.testing.assert_allclose(rec.t, [0.0, 0.01, 0.02], atol=1e-12)


# -- bad files: one line, naming the file and the line --------------------------
AT2 = "T\nT\nUNITS OF G\nNPTS=  4, DT= .01 SEC\n0.1 0.2\n0.3 0.4\n"


@pytest.mark.parametrize("content,tokens", [
    (b"", ["empty"]),
    (b"   \n\t\n", ["empty"]),
    (b"NPTS\x00\x01\x02", ["binary"]),
    (AT2.replace("NPTS=  4", "NPTS=  5").encode(), ["NPTS = 5", "4 values follow"]),
    (AT2.replace("NPTS=  4", "NPTS=  3").encode(), ["NPTS = 3", "4 values follow"]),
    (AT2.replace("NPTS=  4", "NPTS=  1").encode(), ["line 4", "NPTS = 1", ">= 2"]),
    (AT2.replace("NPTS=  4", "NPTS=  1e999").encode(), ["line 4", "NPTS = inf", "whole number"]),
    (AT2.replace("DT= .01", "DT= -.01").encode(), ["line 4", "DT"]),
    (AT2.replace("DT= .01", "DT= 1e999").encode(), ["line 4", "DT = inf", "finite number > 0"]),
    (AT2.replace("NPTS=  4, DT= .01 SEC", "NPTS DT").encode(), ["line 4", "cannot read NPTS and DT"]),
    (AT2.replace("0.3 0.4", "0.3 -inf").encode(), ["line 6", "non-finite", "'-inf'"]),
    (AT2.replace("0.3 0.4", "0.3 zero").encode(), ["line 6", "'zero'", "not a number"]),
    (b"0 0\n0.01 nan\n0.02 0\n", ["line 2", "non-finite"]),
    (b"0 0\n0.01 0.1\n0.01 0\n", ["line 3", "does not increase"]),
    (b"0 0\n0.02 0.1\n0.01 0\n", ["line 3", "does not increase"]),
    (b"0 0\n0.01\n", ["line 2", "expected 2 columns", "found 1"]),
    (b"0 0\n", ["fewer than two"]),
    (b"-1e308 0\n1.7e308 0\n", ["times"]),
])
def test_bad_record_files(tmp_path, content, tokens):
    f = tmp_path / "bad.rec"
    f.write_bytes(content)
    with pytest.raises(RecordError) as exc:
        read_record(f, units="g")
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith(str(f))
    for tok in tokens:
        assert tok in msg, (tok, msg)


def test_missing_record(tmp_path):
    with pytest.raises(RecordError, match="file not found"):
        read_record(tmp_path / "nope.AT2")


def test_record_is_directory(tmp_path):
    with pytest.raises(RecordError, match="directory"):
        read_record(tmp_path)


def test_parse_at2_needs_header():
    with pytest.raises(RecordError, match="no NPTS/DT header"):
        parse_at2("0.1 0.2\n0.3\n", "x.AT2")
