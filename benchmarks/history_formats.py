"""Cost of writing a long history (10^6 rows x 23 columns, blocks of 16384
rows as fpd run streams them): CSV text (the default), Parquet (pyarrow, no
compression) and netCDF-3 (scipy, a record dimension), best of 3.

    python3 benchmarks/history_formats.py [rows]
"""
from __future__ import annotations

import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from fpd.outputs.output import CsvWriter, ParquetWriter  # noqa: E402

COLS = ["t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad", "beta_rad", "s1_m", "s2_m", "N1_N", "N2_N",
        "mu1", "mu2", "T1_C", "T2_C", "W1_J", "W2_J", "phase", "E_input_J", "E_kin_J", "E_pot_J", "E_reseat_J"]
BLOCK = 1 << 14


def data(rows):
    rng = np.random.default_rng(1)
    d = rng.standard_normal((rows, len(COLS))) * 1e3
    d[:, COLS.index("phase")] = rng.integers(0, 3, rows)
    return d


def csv(path, d):
    with open(path, "w", newline="") as fh:
        w = CsvWriter(fh, COLS)
        for s in range(0, len(d), BLOCK):
            w.write(d[s:s + BLOCK])


def parquet(path, d):
    w = ParquetWriter(path, COLS)
    for s in range(0, len(d), BLOCK):
        w.write(d[s:s + BLOCK])
    w.close()


def netcdf(path, d):
    from scipy.io import netcdf_file
    f = netcdf_file(path, "w")
    f.createDimension("row", None)
    vs = [f.createVariable(c, "f8", ("row",)) for c in COLS]
    for s in range(0, len(d), BLOCK):
        b = d[s:s + BLOCK]
        for j, v in enumerate(vs):
            v[s:s + len(b)] = b[:, j]
    f.close()


def main():
    rows = int(sys.argv[1]) if len(sys.argv) > 1 else 10 ** 6
    d = data(rows)
    with tempfile.TemporaryDirectory() as tmp:
        for name, fn in (("csv", csv), ("parquet", parquet), ("netcdf3", netcdf)):
            best = float("inf")
            for _ in range(3):
                p = os.path.join(tmp, f"h.{name}")
                t0 = time.perf_counter()
                fn(p, d)
                best = min(best, time.perf_counter() - t0)
                size = os.path.getsize(p)
                os.unlink(p)
            print(f"{name:8s} {best:7.2f} s  {1e6 * best / rows:6.2f} us/row  {size / 2**20:7.1f} MiB")


if __name__ == "__main__":
    main()
