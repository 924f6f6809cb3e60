"""The command line explains itself: a description and examples for every
command, a help line for every option, --version, every packaged scene listed."""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import fpd
from fpd.frontends import cli
from fpd.schema import scene as scn

ROOT = Path(__file__).resolve().parent.parent


def _fpd(*args, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


def _subparsers(p):
    for action in p._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices
    return {}


def test_every_command_and_option_is_explained():
    p = cli._parser()
    assert p.description and "examples:" in p.epilog
    subs = _subparsers(p)
    assert {"run", "check", "scenes", "compare", "converge", "stability", "render", "reference"} <= set(subs)
    helps = {a.dest: a.help for a in p._actions if isinstance(a, argparse._SubParsersAction)}
    assert helps
    for name, sub in subs.items():
        assert sub.description and len(sub.description) > 40, name
        assert sub.epilog and "examples:" in sub.epilog and f"fpd {name}" in sub.epilog, name
        for a in sub._actions:
            if a.dest != "help":
                assert a.help and len(a.help) > 10, (name, a.dest)
    for a in p._actions:
        if isinstance(a, argparse._SubParsersAction):
            for choice in a._choices_actions:
                assert choice.help, choice.dest


def test_version(tmp_path):
    r = _fpd("--version", cwd=tmp_path)
    assert r.returncode == 0 and r.stdout.strip() == f"fpd {fpd.__version__}"


def test_run_help_describes_each_option(tmp_path):
    r = _fpd("run", "--help", cwd=tmp_path)
    assert r.returncode == 0
    for opt, words in (("--out DIR", "results folder"), ("--force", "replace"), ("--quiet", "nothing"),
                       ("--set KEY=VALUE", "dotted")):
        line = [ln for ln in r.stdout.splitlines() if ln.strip().startswith(opt)]
        assert line and words in r.stdout, opt
    assert "examples:" in r.stdout


def test_scenes_lists_every_packaged_scene_and_each_resolves(tmp_path):
    r = _fpd("scenes", cwd=tmp_path)
    assert r.returncode == 0
    listed = [ln.split()[0] for ln in r.stdout.splitlines()]
    files = sorted(p.relative_to(scn.SCENES_DIR).with_suffix("").as_posix()
                   for p in scn.SCENES_DIR.rglob("*.toml"))
    assert listed == files and "stability/tall-pad" in listed
    for name in listed:
        assert scn.resolve_path(name).is_file()
        assert "(unreadable)" not in r.stdout


def test_a_local_file_wins_over_a_packaged_name(tmp_path):
    (tmp_path / "stability").mkdir()
    text = (scn.SCENES_DIR / "sfp-harmonic.toml").read_text()
    (tmp_path / "stability" / "tall-pad.toml").write_text(text)
    assert scn.resolve_path(str(tmp_path / "stability" / "tall-pad.toml")).read_text() == text
