"""fpd sweep (studies/sweep.py): the sweep file, the table, resuming, and the
fault paths on a real 2-worker dask LocalCluster (failing members, a killed
worker, Ctrl-C then a rerun). Members are 1.5 s pulses on lumped plates
(about 0.05 s each) so each test takes a few seconds, most of it the cluster."""
from __future__ import annotations

import csv
import glob
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("dask.distributed")

from fpd.frontends import cli  # noqa: E402
from fpd.studies import sweep as swp  # noqa: E402
from tests.sweep_scenes import lite, with_loading  # noqa: E402
from fpd.studies import sweep_store as store  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "scenes" / "records" / "IELC180.AT2"

LITE = lite(1.5)


def _env(**extra):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    env.update(extra)
    return env


def _fpd(args, **env):
    return subprocess.run([sys.executable, "-m", "fpd", *args], capture_output=True, text=True,
                          env=_env(**env), timeout=240)


def _rows(out: Path) -> list[dict]:
    with open(out / "sweep.csv", newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture()
def lite(tmp_path):
    (tmp_path / "lite.toml").write_text(LITE)
    return tmp_path


def _write(d: Path, text: str, name="s.toml") -> Path:
    p = d / name
    p.write_text(text)
    return p


# -- the sweep file: bad input is one line, exit 2, nothing written ---------------------------
@pytest.mark.parametrize("body, needle", [
    ('mode = "zipp"', 'mode = \'zipp\': must be "product" or "zip"'),
    ('[axes]\n"loading.velocity_mp" = [1.0]', "did you mean loading.velocity_mps?"),
    ('[axes]\n"solver.dt" = []', "must be a non-empty list"),
    ('[axes]\n"solver.dt" = [-1.0]', "solver.dt = -1: must be > 0"),
    ('[axes]\n"nosuch.key" = [1]', "'nosuch' is not a scene table"),
    ('colour = 1', "colour = 1: unknown key"),
    ('mode = "zip"\n[axes]\n"solver.dt" = [1e-3]\n"friction.mu" = [0.05, 0.06]', "as many values"),
    ('[run]\nkeep = "all"', 'run.keep = \'all\': must be one of "summary", "timeseries"'),
    ('[set]\n"solver.dt" = 1e-3\n[axes]\n"solver.dt" = [1e-3]', "is an axis too"),
])
def test_bad_sweep_file_is_one_line_and_writes_nothing(lite, capsys, body, needle):
    s = _write(lite, 'scene = "lite.toml"\n' + body + "\n")
    out = lite / "out"
    assert cli.main(["sweep", str(s), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err
    assert not out.exists() and not list(lite.glob(".out*"))


def test_sweep_refuses_a_folder_another_command_writes(lite, capsys):
    """Two writers never share a sweep's DIR: with the folder claimed (as a
    running fpd run, sweep or map holds it), fpd sweep exits 2 with one line
    and writes nothing there."""
    from fpd.outputs.claim import claim

    s = _write(lite, 'scene = "lite.toml"\n[axes]\n"friction.mu" = [0.05]\n')
    out = lite / "out"
    with claim(out, False, False):
        assert cli.main(["sweep", str(s), "--out", str(out), "--workers", "1", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "in use by" in err, err
    assert not out.exists()


def test_expansion_product_zip_and_hash(lite):
    s = _write(lite, 'scene = "lite.toml"\n[axes]\n"friction.mu" = [0.05, 0.06]\n'
                     '"loading.velocity_mps" = [0.2, 0.4, 0.6]\n')
    sw = swp.load_sweep(str(s))
    assert len(sw.members) == 6
    assert [m.axes for m in sw.members[:2]] == [{"friction.mu": 0.05, "loading.velocity_mps": 0.2},
                                                {"friction.mu": 0.05, "loading.velocity_mps": 0.4}]
    assert sw.members[4].scene["friction"]["lower"]["mu"] == 0.06
    assert sw.members[4].scene["loading"]["velocity_mps"] == 0.4
    assert len({m.hash for m in sw.members}) == 6
    z = _write(lite, 'scene = "lite.toml"\nmode = "zip"\n[axes]\n"friction.mu" = [0.05, 0.06]\n'
                     '"loading.velocity_mps" = [0.2, 0.4]\n', "z.toml")
    zw = swp.load_sweep(str(z))
    assert [(m.axes["friction.mu"], m.axes["loading.velocity_mps"]) for m in zw.members] == [(0.05, 0.2), (0.06, 0.4)]
    # the hash is the resolved scene's: the same member in another sweep has the same hash, a changed key another
    assert zw.members[0].hash == sw.members[0].hash
    assert zw.members[1].hash != sw.members[1].hash


# -- the fault paths on a real 2-worker cluster ------------------------------------------------
def test_failing_members_are_rows_and_the_rest_complete(lite):
    """A bad record (read error) and a numerical failure (iterated coupling that
    cannot converge) become rows with their status and one-line message."""
    bad = lite / "bad.AT2"
    bad.write_text("PEER header\nno numbers here\nNPTS= 3, DT= .01 SEC\n0.1 zap 0.3\n")
    rec_scene = with_loading(LITE, 'kind = "record"\nrecord = "elcentro-1940"\n')
    (lite / "rec.toml").write_text(rec_scene)
    s = _write(lite, f'''scene = "rec.toml"
mode = "zip"
[set]
"solver.duration" = 3.0
[axes]
"loading.file" = ["{RECORD}", "{bad}", "{RECORD}"]
"coupling.scheme" = ["staggered", "staggered", "iterated"]
"coupling.tol_K" = [1e-3, 1e-3, 1e-12]
"coupling.max_iter" = [20, 20, 1]
''')
    assert cli.main(["sweep", str(s), "--out", str(lite / "out"), "--workers", "2", "--quiet"]) == swp.EXIT_MEMBERS
    rows = _rows(lite / "out")
    assert [x["status"] for x in rows] == ["ok", "error", "failed"]
    assert "zap" in rows[1]["message"] and "\n" not in rows[1]["message"]
    assert "did not converge" in rows[2]["message"]
    assert float(rows[0]["peak_u_m"]) > 0 and rows[0]["message"] == ""
    md = (lite / "out" / "sweep.md").read_text()
    assert "Members not ok" in md and "0001 | error" in md
    # theta (the line of centres: how far it slid) is not called the pad's tilt (beta, its rocking)
    theta = float(rows[0]["peak_theta_rad"])
    assert f"| peak sliding rotation theta (line of centres) | rad | {theta:.4g} |" in md
    assert "| peak pad rocking beta | rad |" in md and "pad tilt" not in md


def test_killed_worker_members_are_rerun(lite, tmp_path, monkeypatch):
    """A member kills its own worker process (SIGKILL) the first time it runs:
    the nanny restarts the worker, Dask reruns the member, every row is ok."""
    marker = tmp_path / "killed"
    s = _write(lite, 'scene = "lite.toml"\n[axes]\n"loading.velocity_mps" = [0.2, 0.3, 0.4, 0.5, 0.6, 0.7]\n')
    monkeypatch.setenv("FPD_SWEEP_TEST", f"kill:0002:{marker}")     # the workers inherit it
    assert cli.main(["sweep", str(s), "--out", str(lite / "out"), "--workers", "2", "--quiet"]) == 0
    killed_pid = int(marker.read_text())
    rows = _rows(lite / "out")
    assert [x["status"] for x in rows] == ["ok"] * 6
    rec = json.loads((lite / "out" / ".members" / f"{rows[2]['hash']}.json").read_text())
    assert rec["worker_pid"] != killed_pid          # it ran again, on a live worker


def test_interrupted_sweep_keeps_finished_members_and_resumes(lite, capsys):
    """Ctrl-C (SIGINT to the whole process group, as a terminal sends it) after
    two members: exit 130, the table lists them ok and the rest 'not run'; a
    rerun runs only the rest and leaves the stored ones untouched."""
    s = _write(lite, 'scene = "lite.toml"\n[axes]\n"loading.velocity_mps" = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8]\n')
    out = lite / "out"
    p = subprocess.Popen([sys.executable, "-m", "fpd", "sweep", str(s), "--out", str(out), "--workers", "2"],
                         env=_env(FPD_SWEEP_TEST="sleep:0.6"), start_new_session=True,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.time()
    while len(glob.glob(str(lite / ".out.partial-*" / ".members" / "*.json"))) < 2:
        assert time.time() - t0 < 60 and p.poll() is None, "no member finished"
        time.sleep(0.05)
    os.killpg(p.pid, signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    assert "Traceback" not in err
    rows = _rows(out)
    done = [x for x in rows if x["status"] == "ok"]
    assert 2 <= len(done) < 8
    assert all(x["status"] == "not run" for x in rows if x["status"] != "ok")
    before = {x["hash"]: os.stat(out / ".members" / f"{x['hash']}.json") for x in done}
    assert cli.main(["sweep", str(s), "--out", str(out), "--workers", "2"]) == 0
    assert f"{len(done)} already done, {8 - len(done)} to run" in capsys.readouterr().out
    rows = _rows(out)
    assert [x["status"] for x in rows] == ["ok"] * 8
    for h, st in before.items():             # the same file, not rewritten
        now = os.stat(out / ".members" / f"{h}.json")
        assert (now.st_ino, now.st_mtime_ns) == (st.st_ino, st.st_mtime_ns)
    # nothing new: no cluster, a fraction of a second
    t0 = time.perf_counter()
    assert cli.main(["sweep", str(s), "--out", str(out), "--quiet"]) == 0
    assert time.perf_counter() - t0 < 5


def test_keep_timeseries_and_force(lite):
    s = _write(lite, 'scene = "lite.toml"\n[axes]\n"friction.mu" = [0.04, 0.08]\n[run]\nkeep = "timeseries"\n')
    out = lite / "out"
    (out).mkdir()
    (out / "other.txt").write_text("not a sweep")
    assert cli.main(["sweep", str(s), "--out", str(out), "--workers", "2", "--quiet"]) == 2
    assert cli.main(["sweep", str(s), "--out", str(out), "--workers", "2", "--quiet", "--force"]) == 0
    assert not (out / "other.txt").exists()
    rows = _rows(out)
    for x in rows:
        d = out / "members" / x["member"]
        summ = json.loads((d / "summary.json").read_text())
        assert summ["peak_u_m"] == pytest.approx(float(x["peak_u_m"]), rel=1e-12)
        assert (d / "timeseries.csv").stat().st_size > 0 and (d / "scene.toml").is_file()
    # more friction, less displacement: the table is the members' own numbers
    assert float(rows[1]["peak_u_m"]) < float(rows[0]["peak_u_m"])


def test_members_of_a_killed_client_are_adopted(lite, capsys):
    """A sweep whose own process died outright (SIGKILL: no Ctrl-C handling)
    leaves its finished members in its temporary folder: the next run takes
    them over and runs only the rest (here: nothing, so no cluster starts)."""
    s = _write(lite, 'scene = "lite.toml"\n[axes]\n"friction.mu" = [0.05, 0.07]\n')
    sw = swp.load_sweep(str(s))
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True).stdout.strip()                 # a pid that no longer runs
    stale = lite / f".out.partial-{dead}" / ".members"
    stale.mkdir(parents=True)
    for m in sw.members:
        res = swp.run_member(swp.member_spec(m, "summary", lambda p: (None, None)))
        store.write(stale, m.hash, res)
    assert cli.main(["sweep", str(s), "--out", str(lite / "out")]) == 0
    assert "2 already done, 0 to run" in capsys.readouterr().out
    assert [x["status"] for x in _rows(lite / "out")] == ["ok", "ok"]


# -- the store cannot serve wrong numbers ---------------------------------------------------
def test_an_edited_stored_result_is_computed_again(lite, capsys):
    """A stored result edited to a wrong but valid value (valid JSON, a
    plausible number) does not match its checksum: the rerun says so in one
    line, computes that member again and the table holds the right number.
    Member folders are copies: editing one changes neither the store nor the
    next table."""
    s = _write(lite, 'scene = "lite.toml"\n[axes]\n"friction.mu" = [0.04, 0.08]\n[run]\nkeep = "timeseries"\n')
    out = lite / "out"
    assert cli.main(["sweep", str(s), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    right = [float(x["peak_u_m"]) for x in _rows(out)]
    h = _rows(out)[1]["hash"]
    f = out / ".members" / f"{h}.json"
    rec = json.loads(f.read_text())
    rec["summary"]["peak_u_m"] = 0.123
    f.write_text(json.dumps(rec))
    kept = out / "members" / "0000" / "summary.json"
    assert os.stat(kept).st_nlink == 1
    kept.write_text(kept.read_text().replace('"peak_u_m"', '"peak_u_m_edited"'))
    capsys.readouterr()
    assert cli.main(["sweep", str(s), "--out", str(out), "--workers", "1"]) == 0
    cap = capsys.readouterr()
    assert "2 members, 1 already done, 1 to run" in cap.out
    assert cap.err.count("\n") == 1 and "1 stored result refused and computed again (member 0001: its " \
        "checksum does not match" in cap.err, cap.err
    assert [float(x["peak_u_m"]) for x in _rows(out)] == right
    # the member folder written again from the store: the edit is gone
    assert '"peak_u_m"' in (out / "members" / "0000" / "summary.json").read_text()
    # a stored kept file edited: refused too
    d = out / ".members" / f"{h}.d" / "summary.json"
    d.write_text(d.read_text().replace("0", "1", 1))
    capsys.readouterr()
    assert cli.main(["sweep", str(s), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    assert "kept file summary.json does not match its checksum" in capsys.readouterr().err
    assert [float(x["peak_u_m"]) for x in _rows(out)] == right


def test_store_keys_and_checks():
    """A record answering another key, or computed by other code, is refused."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        st = Path(tmp)
        store.write(st, "aaaa", {"id": "0000", "status": "ok", "summary": {"peak_u_m": 0.05}})
        assert store.check(st, "aaaa")[0]["summary"]["peak_u_m"] == 0.05
        os.replace(st / "aaaa.json", st / "bbbb.json")
        assert "answers another member key" in store.check(st, "bbbb")[1]
        rec = json.loads((st / "bbbb.json").read_text())
        rec.update(key="bbbb", code="0" * 16)
        rec["checksum"] = store._digest(rec)
        (st / "bbbb.json").write_text(json.dumps(rec))
        assert store.check(st, "bbbb")[1] == "computed by another fpd code"
        assert store.check(st, "cccc") == (None, "")
    # the fingerprint is of the source: stable, and part of every member key
    assert store.code_fingerprint() == store.code_fingerprint() and len(store.code_fingerprint()) == 16


def test_a_huge_sweep_is_refused_before_it_is_expanded(lite, capsys):
    """1e10 members: one line naming the axes and the option, at once, in little memory."""
    vals = ", ".join(str(0.01 * (i + 1)) for i in range(100))
    s = _write(lite, 'scene = "lite.toml"\n[axes]\n' + "\n".join(
        f'"{k}" = [{vals}]' for k in ("friction.mu", "loading.velocity_mps", "loading.period_s", "loading.t0_s",
                                      "device.pad_mass")) + "\n")
    t0 = time.perf_counter()
    assert cli.main(["sweep", str(s), "--out", str(lite / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "axes: 1e+10 members (100 x 100 x 100 x 100 x 100)" in err, err
    assert "at most 100000 allowed: --max-members" in err
    assert time.perf_counter() - t0 < 2 and not (lite / "out").exists()
    # the cap can be lowered (or raised) on the command line
    s2 = _write(lite, 'scene = "lite.toml"\n[axes]\n"friction.mu" = [0.04, 0.05, 0.06]\n', "s2.toml")
    assert cli.main(["sweep", str(s2), "--out", str(lite / "out"), "--max-members", "2"]) == 2
    assert "3 members (3); at most 2 allowed" in capsys.readouterr().err
    assert cli.main(["sweep", str(s2), "--out", str(lite / "out"), "--max-members", "0"]) == 2
    assert "--max-members 0: must be >= 1" in capsys.readouterr().err


def test_sweep_reports_rim_impacts_against_the_intensity(lite):
    """A DFP with a 15 mm capacity under El Centro (6 s) scaled 0.2, 0.5, 1
    and 2: the members whose slide reaches the rim (capacity ratio 1) are
    counted per scale in sweep.md and drawn against it (rim_probability.png);
    every member's capacity ratio is a column of sweep.csv."""
    rec_scene = with_loading(LITE, 'kind = "record"\nrecord = "elcentro-1940"\n')
    (lite / "rec.toml").write_text(rec_scene)
    s = _write(lite, '''scene = "rec.toml"
[set]
"device.d1" = 0.015
"solver.duration" = 6.0
[axes]
"loading.scale" = [0.2, 0.5, 1.0, 2.0]
''')
    out = lite / "out"
    assert cli.main(["sweep", str(s), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    rows = {float(r["loading.scale"]): r for r in _rows(out)}
    ratio = {k: float(r["capacity_ratio"]) for k, r in rows.items()}
    assert ratio[0.2] < 1.0 and ratio[2.0] == pytest.approx(1.0, abs=1e-9), ratio
    hit = sum(1 for v in ratio.values() if v >= swp.RIM_REACHED)
    md = (out / "sweep.md").read_text()
    assert "## Rim impacts" in md and f"{hit} of 4 members" in md
    assert "| loading.scale | members ok | at a rim | probability |" in md
    assert "| 0.2 | 1 | 0 | 0 |" in md and "| 2 | 1 | 1 | 1 |" in md
    assert (out / "rim_probability.png").stat().st_size > 5000
