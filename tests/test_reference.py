"""docs/reference.md is generated from the code and must stay so.

Fails when the committed reference differs from what the code generates,
when a scene key, a column, a summary field or an exit status has no
description (frontends/descriptions.py), or when a description names
something that no longer exists.
"""
from __future__ import annotations

import csv
import errno
import fnmatch
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path


import fpd
from fpd.frontends import cli
from fpd.outputs import cycles
from fpd.frontends import descriptions as D
from fpd.frontends import reference as ref

ROOT = Path(__file__).resolve().parent.parent
REFERENCE = ROOT / "docs" / "reference.md"


def test_committed_reference_is_generated_from_the_code():
    assert REFERENCE.read_text() == ref.generate(), (
        f"docs/reference.md is out of date with the code: regenerate it with `{ref.REGENERATE}` "
        "(after describing any new key, column or summary field in frontends/descriptions.py)")


def test_every_declared_key_and_column_is_described():
    assert ref.missing_descriptions() == [], (
        "describe these (unit, meaning) in frontends/descriptions.py, then run " + ref.REGENERATE)
    assert ref.stale_descriptions() == [], "frontends/descriptions.py describes keys the schema no longer has"
    stale_cols = [c for c in D.COLUMNS if c not in ref.declared_columns()]
    assert stale_cols == [], "frontends/descriptions.py describes columns no stepper declares"
    for table in (D.KEYS, D.COLUMNS, D.SUMMARY):
        for name, entry in table.items():
            assert isinstance(entry, tuple) and len(entry) == 2 and entry[1].strip(), name


def test_every_exit_status_is_described():
    codes = {v for k, v in vars(cli).items() if k.startswith("EXIT_") and isinstance(v, int)}
    assert codes == set(D.EXIT)


def test_allowed_values_come_from_the_checks():
    from fpd.schema import scene as scn
    assert ref.allowed(scn.THERMAL_KEYS["n_elements"]) == ">= 2"
    assert ref.allowed(scn.TABLES["device"]["R1"]) == "> 0"
    assert ref.allowed(scn.FRICTION_KEYS["constant"]["mu"]) == "in [0, 1)"
    assert ref.allowed(scn.TABLES["mechanics"]["model"]) == '`"two-phase"` \\| `"seated"`'


def _sections(text: str) -> dict[str, set[str]]:
    """Keys listed under each '### `[table]`' heading (its #### variants included)."""
    out, cur = {}, None
    for line in text.splitlines():
        m = re.match(r"### `\[(\w+)\]`", line)
        if m:
            cur = out.setdefault(m.group(1), set())
        elif line.startswith("### ") or line.startswith("## "):
            cur = None
        elif cur is not None:
            k = re.match(r"\| `(\w+)` \|", line)
            if k:
                cur.add(k.group(1))
    return out


def _fpd(*args, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


def test_every_key_fpd_check_prints_is_in_the_reference(capsys):
    text = REFERENCE.read_text()
    sections = _sections(text)
    top = {m.group(1) for m in re.finditer(r"\| `(\w+)` \|", text.split("### `[device]`")[0])}
    names = ["default", "lab-sine", "heat-halfspace", "sfp-harmonic", "stability/near-fault",
             "stability/mu-drop-90"]
    for name in names:
        assert cli.main(["check", name]) == 0      # in-process: `fpd check NAME`'s output
        resolved = tomllib.loads(capsys.readouterr().out)
        for key, value in resolved.items():
            if not isinstance(value, dict):
                assert key in top, (name, key)
                continue
            tables = value.values() if key in ("friction", "thermal") else [value]
            for t in tables:
                for k in t:
                    assert k in sections.get(key, ()), f"{name}: {key}.{k} is not in docs/reference.md"


def _summary_paths(d, pre=""):
    """Dotted paths of the leaves; a list is a leaf, and a list of objects
    also yields its entries' fields as ``list[].field``."""
    for k, v in d.items():
        if isinstance(v, dict):
            yield from _summary_paths(v, f"{pre}{k}.")
        else:
            yield pre + k
            if isinstance(v, list):
                for item in v:
                    if isinstance(item, dict):
                        yield from _summary_paths(item, f"{pre}{k}[].")


def _field_matches(path: str, field: str) -> bool:
    """fnmatch with the description's ``[]`` (a list's entries) taken literally."""
    return fnmatch.fnmatchcase(path, field.replace("[]", "[[]]"))


def test_every_column_and_summary_field_is_in_the_reference(tmp_path, monkeypatch, capsys):
    """The default run's timeseries.csv columns and summary.json fields, and those
    of scenes that write the others (a thermal-only check, iterated coupling, a
    bidirectional record pair, a TFP, the flat bearing, a test-machine cycle,
    fe3d plates, a failed write of the results), are described; every
    described summary field is written by one of these runs (no stale entries)."""
    text = REFERENCE.read_text()
    out = tmp_path / "default"
    r = _fpd("run", "default", "--out", str(out), "--quiet", "--set", "solver.duration=1.0", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    with open(out / "timeseries.csv", newline="") as fh:
        header = next(csv.reader(fh))
    for c in header:
        assert f"| `{c}` |" in text, f"column {c} is not in docs/reference.md"
    import json
    summaries = [json.loads((out / "summary.json").read_text())]
    summaries.append(fpd.run("heat-halfspace", solver={"duration": 1.0}).summary)
    summaries.append(fpd.run("lab-sine", solver={"duration": 0.5}, coupling={"scheme": "iterated"}).summary)
    # the other steppers' own columns and fields: bidirectional (a record pair), TFP, flat
    # and the test machine's per-cycle block (one whole cycle: 4 Hz), fe3d's material point
    runs = [(name, {"solver": {"duration": 0.2}}) for name in ("impvall-bidirectional", "ferndale-3c", "tfp-lab",
                                                               "flat-lab")]
    # a vertical ground motion as a scaled copy of the horizontal record (loading.vertical_scale)
    runs.insert(0, ("default", {"solver": {"duration": 0.2}, "loading": {"vertical_scale": 0.5}}))
    # the wear columns and summary block
    runs.append(("lab-sine", {"solver": {"duration": 0.1}, "thermal": {"model": "lumped"},
                              "friction": {"wear_k_mm3_per_Nm": 1e-6}}))
    runs.append(("lab-sine", {"solver": {"duration": 0.3}, "loading": {"frequency_Hz": 4.0, "cycles": 1.0}}))
    # the test machine's axial-load programmes: a sine, a (t, N) series
    series = tmp_path / "axial.txt"
    series.write_text("0 6.0e6\n1 6.6e6\n")
    runs.append(("lab-sine", {"solver": {"duration": 0.25}, "thermal": {"model": "lumped"},
                              "loading": {"frequency_Hz": 4.0, "cycles": 1.0, "vertical": "sine",
                                          "vertical_amplitude_ratio": 0.2, "vertical_frequency_Hz": 8.0}}))
    runs.append(("lab-sine", {"solver": {"duration": 0.25}, "thermal": {"model": "lumped"},
                              "loading": {"frequency_Hz": 4.0, "cycles": 1.0, "vertical": "series",
                                          "vertical_file": str(series)}}))
    runs.append(("default", {"solver": {"duration": 0.02},
                             "thermal": {"model": "fe3d", "per_radius": 10, "nz": 4, "step_multiple": 5}}))
    for name, over in runs:
        r = fpd.run(name, output={"plots": False}, **over)
        assert r.ok, (name, r.summary["message"])
        for c in r.history:
            assert f"| `{c}` |" in text, f"{name}: column {c} is not in docs/reference.md"
        summaries.append(r.summary)
    assert "test_machine" in summaries[-4] and summaries[-4]["test_machine"]["cycles"]
    assert summaries[-3]["test_machine"]["axial_programme"]["kind"] == "sine"
    assert summaries[-2]["test_machine"]["axial_programme"]["kind"] == "series"
    for c in cycles.CSV_COLUMNS:            # cycles.csv: the per-cycle fields
        assert f"test_machine.cycles[].{c}" in D.SUMMARY, f"cycles.csv column {c} is not described"
    # writing the results fails after the run (a full disk): what the summary then says
    from fpd.outputs import output

    def full(folder, *a, **k):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(folder.path("summary.json")))
    monkeypatch.setattr(output, "write_all", full)
    out = tmp_path / "full"
    assert cli.main(["run", "sfp-harmonic", "--out", str(out), "--quiet", "--set", "solver.duration=0.05",
                     "--set", "output.plots=false"]) == cli.EXIT_FAILED
    capsys.readouterr()
    summaries.append(json.loads((out / "summary.json").read_text()))
    assert "write_error" in summaries[-1] and "run_status" in summaries[-1]
    seen = set()
    for s in summaries:
        for path in _summary_paths(s):
            match = [f for f in D.SUMMARY if _field_matches(path, f)]
            assert match, f"summary field {path} has no description in frontends/descriptions.py"
            assert f"| `{match[0]}` |" in text, f"summary field {path} is not in docs/reference.md"
            seen.update(match)
    assert set(D.SUMMARY) - seen == set(), "described summary fields that no run writes"


def test_fpd_reference_prints_it(tmp_path):
    r = _fpd("reference", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout == REFERENCE.read_text()


def test_no_document_or_message_points_outside_the_repository():
    hits = []
    for folder in ("docs", "coupling", "schema", "outputs", "studies", "frontends", "loading", "mechanics", "thermal",
                   "meshes",
                   "scenes", "fpd", "examples", "benchmarks"):
        for p in (ROOT / folder).rglob("*"):
            if p.suffix in (".py", ".md", ".toml", ".txt") and p.is_file():
                for i, line in enumerate(p.read_text(errors="replace").splitlines(), 1):
                    if "../shared" in line or "shared/design" in line or "interface.md" in line:
                        hits.append(f"{p.relative_to(ROOT)}:{i}")
    readme = (ROOT / "README.md").read_text()
    hits += ["README.md" for s in ("../shared", "shared/design", "interface.md") if s in readme]
    assert hits == []
