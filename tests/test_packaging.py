"""The project installs as the one import name `fpd`, with its licence and metadata.

Fast: pyproject's package list and package-dir put everything under `fpd`,
every folder with Python files is installed, every packaged scene and record
is in the package data. Slow (-m slow): the wheel's file list, and a fresh
venv with a non-editable install, used from another folder
(tests/check_install.py does the same by hand).
"""
from __future__ import annotations

import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_every_package_installs_under_fpd():
    st = PYPROJECT["tool"]["setuptools"]
    pkgs, dirs = st["packages"], st["package-dir"]
    assert {p.split(".")[0] for p in pkgs} == {"fpd"}
    assert set(pkgs) == set(dirs)
    for pkg, folder in dirs.items():
        assert (ROOT / folder / "__init__.py").is_file(), pkg
    # every folder of the repository that holds package code is installed
    code = {p.parent.relative_to(ROOT).as_posix() for p in ROOT.glob("*/*.py")}
    assert code - set(dirs.values()) <= {"tests", "benchmarks", "examples"}


def test_package_data_covers_every_scene_and_record():
    import fnmatch
    patterns = PYPROJECT["tool"]["setuptools"]["package-data"]["fpd.scenes"]
    scenes = ROOT / PYPROJECT["tool"]["setuptools"]["package-dir"]["fpd.scenes"]
    for f in scenes.rglob("*"):
        if f.is_file() and f.suffix != ".py" and "__pycache__" not in f.parts:
            rel = f.relative_to(scenes).as_posix()
            assert any(fnmatch.fnmatch(rel, p) for p in patterns), rel


def test_metadata_and_licence():
    proj = PYPROJECT["project"]
    assert proj["license"] == "MIT" and proj["license-files"] == ["LICENSE"]
    assert "MIT License" in (ROOT / "LICENSE").read_text()
    assert proj["authors"] and proj["keywords"] and proj["classifiers"]
    assert proj["scripts"]["fpd"] == "fpd.frontends.cli:entry"
    import fpd
    assert proj["version"] == fpd.__version__


def source_copy(dest: Path) -> Path:
    """The repository without git, caches and build output (setuptools builds in
    the source folder: its build/ and *.egg-info must not land in the checkout)."""
    import shutil
    shutil.copytree(ROOT, dest, ignore=shutil.ignore_patterns(
        ".git", "__pycache__", "build", "*.egg-info", "results", ".pytest_cache"))
    return dest


@pytest.mark.slow
def test_wheel_holds_only_fpd(tmp_path):
    src = source_copy(tmp_path / "src")
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(src)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    wheel, = tmp_path.glob("*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    top = {n.split("/")[0] for n in names}
    assert top == {"fpd", wheel.name.split("-")[0] + "-" + wheel.name.split("-")[1] + ".dist-info"}, top
    assert "fpd/scenes/stability/tall-pad.toml" in names
    assert any(n.endswith("licenses/LICENSE") for n in names)


@pytest.mark.slow
def test_fresh_venv_install(tmp_path):
    r = subprocess.run([sys.executable, str(ROOT / "tests" / "check_install.py"), str(tmp_path / "venv")],
                       capture_output=True, text=True, timeout=1800)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
