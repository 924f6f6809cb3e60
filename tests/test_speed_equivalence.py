"""The speed work changes no number: the packaged scenes reproduce the
histories recorded from the pre-optimisation code (tests/speed_cases.py)
within 1e-12 relative (per column, against the column's scale)."""
from pathlib import Path

import numpy as np
import pytest

from tests.speed_cases import CASES, fingerprint, run_case

DATA = Path(__file__).parent / "data" / "speed_fingerprints.npz"


@pytest.fixture(scope="module")
def ref():
    return np.load(DATA)


def assert_same(data, want):
    assert data.shape == want.shape
    assert np.array_equal(np.isnan(data), np.isnan(want))
    scale = np.nanmax(np.abs(want), axis=0)
    scale[~np.isfinite(scale)] = 0.0
    err = np.abs(np.nan_to_num(data) - np.nan_to_num(want))
    assert np.all(err <= 1e-12 * np.maximum(np.abs(want), scale) + 1e-300), \
        f"max relative difference {np.max(err / np.maximum(scale, 1e-300)):.3g}"


@pytest.mark.parametrize("name", list(CASES))
def test_history_matches_pre_optimisation(ref, name):
    data, cols, n = fingerprint(run_case(name))
    assert list(cols) == list(ref[f"{name}/columns"])
    assert n == int(ref[f"{name}/n_rows"])
    assert_same(data, ref[f"{name}/data"])


def test_chunked_csv_writes_the_bytes_savetxt_wrote(tmp_path):
    from fpd.outputs.output import write_csv
    from fpd.machines.seated import PHASES

    class R:
        columns = ["t_s", "u_m", "phase", "T1_C"]
        data = np.random.default_rng(0).standard_normal((9000, 4))
    R.data[:, 2] = np.arange(9000) % 3
    R.data[5, 1], R.data[6, 3], R.data[7, 2] = np.nan, np.inf, np.nan
    write_csv(tmp_path / "a.csv", R, chunk=1000)
    with open(tmp_path / "b.csv", "w", newline="") as fh:
        fh.write(",".join(R.columns) + "\n")
        obj = R.data.astype(object)
        obj[:, 2] = np.array(PHASES, dtype=object)[np.nan_to_num(R.data[:, 2]).astype(int)]
        np.savetxt(fh, obj, fmt=["%.10g", "%.10g", "%s", "%.10g"], delimiter=",")
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
