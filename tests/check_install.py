"""Acceptance of issue 17, by hand or from the slow test:

    python3 tests/check_install.py [VENV_DIR]

A fresh venv, `pip install <repo>` (not editable), then from another folder:
the API runs the default scene, site-packages' top level holds only fpd and
its dist-info, `fpd run --help`, `fpd --version` and `fpd run stability/tall-pad`
work. Prints what it measured; exit 1 at the first failure.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def sh(*args, cwd=None, env=None):
    t0 = time.perf_counter()
    r = subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if r.returncode != 0:
        print(f"FAILED ({r.returncode}): {' '.join(map(str, args))}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}")
        sys.exit(1)
    return r, dt


def main():
    venv = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="fpd-venv-"))
    sh(sys.executable, "-m", "venv", venv)
    py, fpd = venv / "bin" / "python", venv / "bin" / "fpd"
    src = Path(tempfile.mkdtemp(prefix="fpd-src-")) / "fpd"     # setuptools builds in the source folder
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(
        ".git", "__pycache__", "build", "*.egg-info", "results", ".pytest_cache"))
    _, dt = sh(py, "-m", "pip", "install", "-q", src)
    print(f"pip install (not editable): {dt:.0f} s")
    work = Path(tempfile.mkdtemp(prefix="fpd-elsewhere-"))
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH",)}
    r, dt = sh(py, "-c", "import fpd; r = fpd.run('default', solver={'duration': 5.0}); "
                         "print(r.summary['peak_u_m']); print(fpd.__file__)", cwd=work, env=env)
    print(f"fpd.run('default', 5 s): peak_u_m = {r.stdout.split()[0]} ({dt:.1f} s, from {work}); "
          f"fpd from {r.stdout.split()[1]}")
    assert str(ROOT) not in r.stdout, "imported the checkout, not the install"
    site = Path(sh(py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])")[0].stdout.strip())
    before = {"pip", "_distutils_hack", "setuptools", "pkg_resources", "distutils-precedence.pth"}
    ours = sorted(p.name for p in site.iterdir()
                  if p.name.split("-")[0] not in before and not p.name.startswith(("pip-", "setuptools-"))
                  and p.name != "__pycache__")
    deps = sh(py, "-m", "pip", "show", "-f", "fpd-sim")[0].stdout
    mine = sorted({ln.strip().split("/")[0] for ln in deps.split("Files:")[1].splitlines()
                   if ln.strip() and not ln.strip().startswith("..")})
    print(f"site-packages entries installed by fpd-sim: {mine}")
    assert set(mine) <= {"fpd", "fpd_sim-0.2.0.dist-info"} and "fpd" in mine, mine
    r, _ = sh(fpd, "run", "--help", cwd=work, env=env)
    opts = [ln.split()[0] for ln in r.stdout.splitlines() if ln.startswith("  -")]
    print(f"fpd run --help: options {opts}")
    r, _ = sh(fpd, "--version", cwd=work, env=env)
    print(f"fpd --version: {r.stdout.strip()}")
    r, dt = sh(fpd, "run", "stability/tall-pad", "--out", work / "tall", cwd=work, env=env)
    print(f"fpd run stability/tall-pad: {dt:.1f} s: {r.stdout.strip().splitlines()[0]}")
    print(f"(all {len(ours)} top-level site-packages entries of the venv: dependencies and fpd)")
    print("OK")


if __name__ == "__main__":
    main()
