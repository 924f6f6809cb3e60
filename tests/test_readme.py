"""README's commands and Python snippet run as written (shortened where needed).

Every `fpd ...` line of README's code blocks (fenced and indented; `a && fpd
...` counts) runs in one scratch folder, in order, with a short
solver.duration and plots off for `fpd run` (the commands are otherwise
unchanged); every ```python block runs as a script. A command or key that
README shows and the program rejects fails here.
"""
from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
ENV = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")


def code_blocks(text: str):
    """(language, body) of each fenced block, and ("", body) of each indented one."""
    blocks, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        m = re.match(r"```(\w*)", lines[i])
        if m:
            j = i + 1
            while not lines[j].startswith("```"):
                j += 1
            blocks.append((m.group(1), "\n".join(lines[i + 1:j])))
            i = j + 1
        elif lines[i].startswith("    ") and (i == 0 or not lines[i - 1].strip()):
            j = i
            while j < len(lines) and (lines[j].startswith("    ") or not lines[j].strip()):
                j += 1
            blocks.append(("", "\n".join(x[4:] for x in lines[i:j])))
            i = j
        else:
            i += 1
    return blocks


def fpd_commands(text: str) -> list[list[str]]:
    out = []
    for lang, body in code_blocks(text):
        if lang not in ("", "sh", "console", "bash"):
            continue
        for line in body.splitlines():
            for part in line.split("&&"):
                words = shlex.split(part, comments=True)
                if words and words[0] == "fpd":
                    out.append(words[1:])
    return out


def test_readme_lists_the_commands_it_should():
    cmds = [" ".join(c) for c in fpd_commands(README)]
    for expected in ("run", "scenes", "check lab-sine", "run stability/tall-pad",
                     "run default --set solver.dt=5e-4 --set friction.mu_ref=0.08 --out mu08"):
        assert any(c == expected or c.startswith(expected + " ") for c in cmds), (expected, cmds)


def test_readme_commands_run(tmp_path):
    for args in fpd_commands(README):
        if args and args[0] == "run":
            args = args + ["--set", "solver.duration=0.5", "--set", "output.plots=false", "--quiet", "--force"]
        r = subprocess.run([sys.executable, "-m", "fpd", *args], cwd=tmp_path, env=ENV, capture_output=True,
                           text=True, timeout=600)
        assert r.returncode == 0, (args, r.stderr[-2000:])


def test_readme_python_runs(tmp_path):
    snippets = [body for lang, body in code_blocks(README) if lang == "python"]
    assert snippets
    for code in snippets:
        r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=ENV, capture_output=True, text=True,
                           timeout=600)
        assert r.returncode == 0, r.stderr[-2000:]
