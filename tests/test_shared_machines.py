"""Issue 19: runs on shared machines, with real processes.

- a full file system (a 600 kB tmpfs when this machine lets us mount one;
  errors injected at the file layer in a subprocess otherwise, and for the
  causes a tmpfs cannot produce: quota, permission), the folder removed
  underneath a run;
- two writers of one results folder (outputs/claim.py): concurrent runs,
  --force against a live run, every writing command, a killed holder;
- SIGTERM (a batch scheduler's time limit) during the run and during the
  final write;
- byte-order marks and other encodings in scene and record files.
"""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from fpd.coupling.recording import CHUNK_ROWS

from fpd.frontends import cli
from fpd.outputs.claim import FolderBusy, claim, lock_path
from fpd.schema.scene import SCENES_DIR, SceneError, load
from fpd.loading.ground_motion import RecordError, read_record

from test_failures import _env, fpd, keep_sigterm, no_leftovers, read_rows  # noqa: F401 (a fixture)

BOM = b"\xef\xbb\xbf"


def one_line(proc, code):
    assert proc.returncode == code, (proc.returncode, proc.stderr)
    assert "Traceback" not in proc.stderr, proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and proc.stderr.endswith("\n"), proc.stderr
    return proc.stderr


def assert_failed_folder_consistent(out: Path, computed_at_least: int):
    """A DIR left by a write failure: a failed run's complete, consistent folder."""
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed" and "writing the results failed" in s["message"], s
    header, rows = read_rows(out / "timeseries.csv")          # whole lines only, all finite
    assert len(rows) == s["steps"] + 1 >= 2                   # csv_every = 1: one row per step
    assert float(rows[-1][header.index("t_s")]) == pytest.approx(s["steps"] * s["dt_s"])
    assert s["steps_computed"] >= computed_at_least and s["steps"] <= s["steps_computed"]
    assert sorted(p.name for p in out.iterdir()) == ["scene.toml", "summary.json", "timeseries.csv"]
    load(str(out / "scene.toml"))                              # the resolved scene, loadable
    return s


# -- a full disk -------------------------------------------------------------------------
@pytest.fixture
def small_fs(tmp_path):
    """A 600 kB tmpfs (root only; skipped where mounting is not allowed)."""
    mnt = tmp_path / "fs"
    mnt.mkdir()
    if shutil.which("mount") is None:
        pytest.skip("no mount command")
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=600k", "tmpfs", str(mnt)], capture_output=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {r.stderr.decode(errors='replace').strip()}")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], capture_output=True)


@pytest.mark.parametrize("extra", [(), ("--set", "output.vtk_every=50", "--set", "output.plots=true")],
                         ids=["csv", "vtk-and-plots"])
def test_disk_full_tmpfs(small_fs, tmp_path, extra):
    out = small_fs / "res"
    proc = fpd(["run", "northridge-dfp", "--set", "solver.duration=6", "--out", str(out), "--quiet", *extra],
               cwd=tmp_path)
    err = one_line(proc, 1)
    assert "No space left on device" in err and "steps computed" in err and str(out) in err
    assert ".partial" not in err                      # the file named as the user knows it: DIR/...
    if out.exists():                                  # what fitted is kept, as a failed run
        assert "kept in" in err and 'status "failed"' in err
        s = assert_failed_folder_consistent(out, 1)
        assert s["write_error"]["errno"] == "ENOSPC"
    else:
        assert "nothing kept" in err
    no_leftovers(small_fs, {"res"} if out.exists() else set())


def test_disk_full_force_keeps_earlier_results(small_fs, tmp_path):
    out = small_fs / "res"
    out.mkdir()
    (out / "summary.json").write_text('{"status": "ok", "scene": "earlier"}\n')
    before = (out / "summary.json").read_bytes()
    proc = fpd(["run", "sfp-harmonic", "--out", str(out), "--quiet", "--force"], cwd=tmp_path)
    err = one_line(proc, 1)
    assert "No space left on device" in err and "still holds the earlier results" in err
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"] and (out / "summary.json").read_bytes() == before
    no_leftovers(small_fs, {"res"})


def test_disk_already_full(small_fs, tmp_path):
    """Not even the header fits: nothing kept, nothing left behind."""
    filler = small_fs / "filler"
    with open(filler, "wb", buffering=0) as fh:
        with pytest.raises(OSError):
            while True:
                fh.write(b"x" * 4096)
    out = small_fs / "res"
    proc = fpd(["run", "sfp-harmonic", "--out", str(out), "--quiet"], cwd=tmp_path)
    err = one_line(proc, 1)
    assert "No space left on device" in err and "nothing kept" in err
    no_leftovers(small_fs, {"filler"})


# errors injected where the system would raise them: CSV writes beyond LIMIT bytes
# fail (a quota reached mid-run), or a file of the final write cannot be created
INJECT = r"""
import errno, os, pathlib, sys
from fpd.outputs import history
kind, limit = sys.argv[1], int(sys.argv[2])
del sys.argv[1:3]
if kind == "csv":
    code = getattr(errno, os.environ["FPD_TEST_ERRNO"])
    real = history._Sink.write
    def write(self, data):
        if self.path.name == "timeseries.csv":
            data = data.encode() if isinstance(data, str) else bytes(data)
            room = limit - self.size
            if len(data) > room:
                if room > 0:
                    real(self, data[:room])               # a part goes in, as on a real file system
                raise OSError(code, os.strerror(code))
        real(self, data)
    history._Sink.write = write
else:                                                     # the final write: the folder turned read-only
    real = pathlib.Path.write_text
    def write_text(self, *a, **k):
        if self.parent.name.startswith(".res.partial"):
            raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(self))
        return real(self, *a, **k)
    pathlib.Path.write_text = write_text
from fpd.frontends.cli import entry
entry()
"""


def fpd_injected(kind, limit, args, cwd, errname="EDQUOT"):
    return subprocess.run([sys.executable, "-c", INJECT, kind, str(limit), *args], cwd=cwd,
                          env=_env({"FPD_TEST_ERRNO": errname}), capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("errname,cause", [("EDQUOT", "Disk quota exceeded"), ("ENOSPC", "No space left on device"),
                                           ("EFBIG", "File too large")])
def test_write_error_injected_mid_csv(tmp_path, errname, cause):
    """The file layer fails after 200 kB of timeseries.csv: the rows written
    whole are kept, the run says where it got to."""
    out = tmp_path / "runs" / "res"
    proc = fpd_injected("csv", 200_000, ["run", "sfp-harmonic", "--out", str(out), "--quiet"], tmp_path, errname)
    err = one_line(proc, 1)
    assert cause in err and errname in err and str(out / "timeseries.csv") in err
    s = assert_failed_folder_consistent(out, 1)
    # stopped at the block of rows that failed, not at the end of the 10000 steps
    assert s["steps"] < s["steps_computed"] <= min(10000, s["steps"] + CHUNK_ROWS)
    assert f"{s['steps_computed']} steps computed" in err and "kept in" in err
    assert (out / "timeseries.csv").stat().st_size <= 200_000
    assert s["write_error"] == {"path": str(out / "timeseries.csv"), "errno": errname, "cause": cause}
    assert f"up to step {s['steps']} " in err
    no_leftovers(out.parent, {"res"})


def test_write_error_injected_long_run_reports_progress(tmp_path):
    """A long run (several blocks of rows): the failure stops it where it
    happened, not at the end, and says how far it got."""
    out = tmp_path / "res"
    proc = fpd_injected("csv", 4_000_000, ["run", "sfp-harmonic", "--out", str(out), "--quiet",
                                           "--set", "solver.dt=2e-4", "--set", "output.plots=false"], tmp_path)
    err = one_line(proc, 1)
    s = assert_failed_folder_consistent(out, 1)
    # stopped at the block of rows that failed (blocks of at most CHUNK_ROWS rows), not at the end
    assert s["steps"] < s["steps_computed"] <= s["steps"] + CHUNK_ROWS and s["steps_computed"] < 50_000
    assert f"{s['steps_computed']} steps computed" in err


def test_permission_denied_in_final_write(tmp_path):
    out = tmp_path / "runs" / "res"
    proc = fpd_injected("final", 0, ["run", "sfp-harmonic", "--out", str(out), "--quiet"], tmp_path)
    err = one_line(proc, 1)
    assert "Permission denied" in err and "EACCES" in err and str(out / "scene.toml") in err
    assert "10000 steps computed" in err and "nothing kept" in err
    assert not out.parent.exists()                   # nothing left, not even the folder made for DIR


def _start(tmp_path, args, out, wait_for=None):
    proc = subprocess.Popen([sys.executable, "-m", "fpd", "run", "--out", str(out), *args], cwd=tmp_path,
                            env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    partial = out.parent / f".{out.name}.partial-{proc.pid}"
    t0 = time.monotonic()
    while not (partial / (wait_for or "")).exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() - t0 < 60, "run did not start"
        time.sleep(0.005)
    return proc, partial


LONG = ("--set", "solver.dt=1e-4", "--set", "output.plots=false", "--quiet")


def test_folder_removed_underneath(tmp_path):
    out = tmp_path / "runs" / "res"
    out.parent.mkdir()
    proc, partial = _start(tmp_path, LONG, out, "timeseries.csv")
    time.sleep(0.3)
    shutil.rmtree(partial)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 1, stderr
    assert "Traceback" not in stderr and len(stderr.splitlines()) == 1, stderr
    assert "removed" in stderr and "steps computed" in stderr and "nothing kept" in stderr
    computed = int(stderr.split(" steps computed")[0].rsplit(" ", 1)[1])
    assert 0 < computed < 399_000                    # noticed at the next block, not at the end
    no_leftovers(out.parent, set())


# -- two writers ---------------------------------------------------------------------------
SHORT = {"sfp-harmonic": ("--set", "solver.duration=3"), "northridge-dfp": ("--set", "solver.duration=3")}


@pytest.mark.parametrize("attempt", [0, pytest.param(1, marks=pytest.mark.slow),
                                     pytest.param(2, marks=pytest.mark.slow)])
def test_two_runs_one_folder(tmp_path, attempt):
    """Started together (the same second): exactly one writes DIR, the other
    refuses with exit 2 and one line; DIR holds the winner's complete results."""
    out = tmp_path / "res"
    names = ["sfp-harmonic", "northridge-dfp"] if attempt % 2 == 0 else ["northridge-dfp", "sfp-harmonic"]
    procs = [subprocess.Popen([sys.executable, "-m", "fpd", "run", n, *SHORT[n], "--out", str(out), "--quiet"],
                              cwd=tmp_path, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for n in names]
    res = [(n, p, *p.communicate(timeout=120)) for n, p in zip(names, procs)]
    codes = sorted(p.returncode for _, p, _, _ in res)
    assert codes == [0, 2], [(n, p.returncode, e) for n, p, _, e in res]
    (winner, *_), = [r for r in res if r[1].returncode == 0]
    (loser, lp, _, lerr), = [r for r in res if r[1].returncode == 2]
    assert "Traceback" not in lerr and len(lerr.splitlines()) == 1 and str(out) in lerr, lerr
    assert "in use by pid" in lerr or "not empty" in lerr, lerr
    s = json.loads((out / "summary.json").read_text())
    assert s["scene"] == winner and s["status"] == "ok"
    header, rows = read_rows(out / "timeseries.csv")
    assert len(rows) == s["steps"] + 1 == 3001
    assert f'name = "{winner}"' in (out / "scene.toml").read_text()
    no_leftovers(tmp_path, {"res"})


def test_second_writer_refused_while_first_runs(tmp_path, capsys, keep_sigterm):
    """With the first run holding DIR: a second run, with or without --force,
    and every other writing command refuse at once, naming the holder; the
    first finishes undisturbed."""
    out = tmp_path / "res"
    first, partial = _start(tmp_path, LONG, out)
    try:
        proc = fpd(["run", "sfp-harmonic", "--out", str(out), "--force"], cwd=tmp_path)
        err = one_line(proc, 2)
        assert f"{out}: results folder in use by pid {first.pid} " in err, err
        assert "`fpd run --out" in err and "since" in err
        capsys.readouterr()
        for args in (["run", "sfp-harmonic", "--out", str(out)],       # in this process: quicker
                     ["compare", "sfp-harmonic", "--out", str(out), "--force", "--fast"],
                     ["converge", "heat-halfspace", "--out", str(out), "--force", "--fast"],
                     ["stability", "--out", str(out), "--force", "--fast"],
                     ["render", str(out)]):
            assert cli.main(args) == 2, args
            err = capsys.readouterr().err
            assert len(err.splitlines()) == 1 and f"{out}: results folder in use by pid {first.pid} " in err, err
            assert first.poll() is None, "the first run was disturbed"
    finally:
        first.send_signal(signal.SIGTERM)
        stdout, stderr = first.communicate(timeout=60)
    assert first.returncode == 130, stderr
    assert json.loads((out / "summary.json").read_text())["status"] == "interrupted"
    no_leftovers(tmp_path, {"res"})


def test_claim_api(tmp_path):
    """claim(): exclusive even within one process; released on exit, also on
    an exception; the lock file removed; checks DIR under the claim."""
    out = tmp_path / "a" / "res"
    with claim(out) as c:
        assert lock_path(out).is_file() and str(os.getpid()) in lock_path(out).read_text()
        with pytest.raises(FolderBusy, match=f"in use by pid {os.getpid()} "):
            with claim(out, force=True):
                pass
        assert c.fd is not None
    assert not lock_path(out).exists()
    assert not (tmp_path / "a").exists()               # made for a DIR that never came: removed again
    with pytest.raises(RuntimeError):
        with claim(out):
            raise RuntimeError
    with claim(out):                                   # free again
        out.mkdir()
        (out / "x").write_text("x")
    with pytest.raises(SceneError, match="not empty; use --force"):
        with claim(out):
            pass
    with claim(out, force=True):
        pass
    with claim(out, check=False):
        pass
    assert sorted(p.name for p in out.parent.iterdir()) == ["res"]


HOLD = r"""
import sys, time
from fpd.outputs.claim import claim
from fpd.outputs.output import ResultsFolder
with claim(sys.argv[1]):
    f = ResultsFolder(sys.argv[1])
    (f.path("timeseries.csv")).write_text("t_s\n0\n0.0")      # half a row, never committed
    print("held", flush=True)
    time.sleep(600)
"""


def test_killed_holder_leaves_no_stale_claim(tmp_path):
    """SIGKILL: the kernel drops the flock; the next run takes DIR over and
    removes the dead writer's partial folder."""
    out = tmp_path / "res"
    holder = subprocess.Popen([sys.executable, "-c", HOLD, str(out)], cwd=tmp_path, env=_env(),
                              stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "held"
    assert one_line(fpd(["run", "sfp-harmonic", "--out", str(out), "--quiet"], cwd=tmp_path), 2)
    holder.kill()
    holder.wait()
    assert lock_path(out).exists() and (tmp_path / f".res.partial-{holder.pid}").is_dir()   # what it left
    proc = fpd(["run", "sfp-harmonic", "--out", str(out), "--quiet", "--set", "solver.duration=1"], cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert json.loads((out / "summary.json").read_text())["status"] == "ok"
    no_leftovers(tmp_path, {"res"})


# -- SIGTERM -------------------------------------------------------------------------------
def test_sigterm_during_run_keeps_history(tmp_path):
    out = tmp_path / "res"
    proc, _ = _start(tmp_path, LONG, out, "timeseries.csv")
    time.sleep(0.4)
    proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130 and "Traceback" not in stderr, stderr
    assert len(stderr.splitlines()) == 1 and "interrupted at step" in stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "interrupted"
    header, rows = read_rows(out / "timeseries.csv")
    assert 10 < len(rows) == s["steps"] + 1 < 399_000
    no_leftovers(tmp_path, {"res"})


def test_sigterm_during_final_write_completes_folder(tmp_path):
    """The stepping is over, the folder is being written (scene.toml is, the
    plots are next): SIGTERM waits until DIR is complete, then exit 130."""
    out = tmp_path / "res"
    proc, partial = _start(tmp_path, ("sfp-harmonic", "--set", "output.plots=true", "--quiet"), out, "scene.toml")
    proc.send_signal(signal.SIGTERM)
    assert not (out / "summary.json").exists()           # it came while the folder was being written
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr and len(stderr.splitlines()) == 1
    assert "interrupted while writing; the complete results are in" in stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "ok" and s["plots"]
    assert all((out / "plots" / p).is_file() for p in s["plots"])
    header, rows = read_rows(out / "timeseries.csv")
    assert len(rows) == s["steps"] + 1
    no_leftovers(tmp_path, {"res"})


# -- encodings -----------------------------------------------------------------------------
PACKAGED = sorted(SCENES_DIR.glob("*.toml")) + sorted((SCENES_DIR / "stability").glob("*.toml"))


def test_bom_copy_of_every_packaged_scene_checks_identically(tmp_path, capsys, monkeypatch):
    """`fpd check` of a copy with a UTF-8 byte-order mark prints exactly what
    the original gives (the resolved scene; records read for record scenes)."""
    assert len(PACKAGED) >= 20
    for orig in PACKAGED:
        copy = tmp_path / orig.parent.name / orig.name
        copy.parent.mkdir(exist_ok=True)
        copy.write_bytes(BOM + orig.read_bytes())
        outs = []
        for p in (orig, copy):
            assert cli.main(["check", str(p)]) == 0, p
            outs.append(capsys.readouterr().out)
        assert outs[0] == outs[1] and outs[0].startswith("name = "), orig


@pytest.mark.parametrize("name", ["sfp-harmonic", "northridge-dfp"])
def test_bom_scene_runs_identically(tmp_path, name):
    """A short run of a BOM (and CRLF, as Windows writes) copy: the same
    bytes in timeseries.csv and scene.toml, the same summary."""
    copy = tmp_path / "in" / f"{name}.toml"
    copy.parent.mkdir()
    copy.write_bytes(BOM + (SCENES_DIR / f"{name}.toml").read_bytes().replace(b"\n", b"\r\n"))
    res = {}
    for tag, scene in (("orig", name), ("bom", str(copy))):
        proc = fpd(["run", scene, "--out", str(tmp_path / tag), "--quiet", "--set", "solver.duration=2",
                    "--set", "output.plots=false"], cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
        s = json.loads((tmp_path / tag / "summary.json").read_text())
        s.pop("runtime_s")
        res[tag] = (s, (tmp_path / tag / "timeseries.csv").read_bytes(), (tmp_path / tag / "scene.toml").read_bytes())
    assert res["orig"] == res["bom"]


@pytest.mark.parametrize("encode,tokens", [
    (lambda t: t.encode("utf-16"), ["UTF-16 (little-endian)", "byte-order mark FF FE at byte 0", "UTF-8"]),
    (lambda t: t.encode("utf-16-be"), ["NUL byte", "at byte offset 0 (line 1)", "UTF-16", "UTF-8"]),
    (lambda t: b"\xfe\xff" + t.encode("utf-16-be"), ["UTF-16 (big-endian)", "FE FF"]),
    (lambda t: t.encode("utf-32"), ["UTF-32 (little-endian)"]),
    (lambda t: t.replace("Single", "Caf\u00e9 single").encode("latin-1"),
     ["byte 0xE9", "byte offset", "(line 2)", "Latin-1", "UTF-8"]),
])
def test_scene_other_encodings_named(tmp_path, encode, tokens):
    text = (SCENES_DIR / "sfp-harmonic.toml").read_text()
    path = tmp_path / "scene.toml"
    path.write_bytes(encode(text))
    runs = tmp_path / "runs"
    runs.mkdir()
    proc = fpd(["run", str(path), "--out", str(runs / "res")], cwd=runs)
    err = one_line(proc, 2)
    assert err.startswith(f"fpd: error: {path}: ")
    for tok in tokens:
        assert tok in err, (tok, err)
    assert list(runs.iterdir()) == []


def test_records_bom_and_encodings(tmp_path):
    orig = SCENES_DIR / "records" / "IELC180.AT2"
    ref = read_record(orig)
    for name, data in (("bom.AT2", BOM + orig.read_bytes()),
                       ("bom-crlf.AT2", BOM + orig.read_bytes().replace(b"\n", b"\r\n")),
                       ("latin1.AT2", orig.read_bytes().replace(b"IMPERIAL VALLEY", b"IMPERIAL VALLEY \xb0 caf\xe9"))):
        (tmp_path / name).write_bytes(data)
        rec = read_record(tmp_path / name)
        assert (rec.t == ref.t).all() and (rec.a_g == ref.a_g).all(), name
    (tmp_path / "u16.AT2").write_bytes(orig.read_text().encode("utf-16"))
    with pytest.raises(RecordError,
                       match=r"u16.AT2: UTF-16 \(little-endian\) text \(byte-order mark FF FE at byte 0\)"):
        read_record(tmp_path / "u16.AT2")
    (tmp_path / "u16n.AT2").write_bytes(orig.read_text().encode("utf-16-le"))
    with pytest.raises(RecordError, match=r"u16n.AT2, line 1: binary file \(NUL byte at byte offset 1; UTF-16"):
        read_record(tmp_path / "u16n.AT2")
    # through the command: a scene whose record file has a byte-order mark runs
    scene = (SCENES_DIR / "northridge-dfp.toml").read_text().replace(
        'record = "northridge-1994"', 'file = "rec.dat"')
    (tmp_path / "rec.dat").write_bytes(BOM + (SCENES_DIR / "records" / "Northridge_CDMG24278_090.dat").read_bytes())
    (tmp_path / "s.toml").write_bytes(BOM + scene.encode())
    proc = fpd(["check", str(tmp_path / "s.toml")], cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr


STRESS = r"""
import os, sys, time
from fpd.outputs.claim import FolderBusy, claim
out, mark, until = sys.argv[1], sys.argv[2], time.monotonic() + float(sys.argv[3])
got = busy = 0
while time.monotonic() < until:
    try:
        with claim(out, check=False):
            fd = os.open(mark, os.O_CREAT | os.O_EXCL | os.O_WRONLY)   # fails if another holder is inside
            time.sleep(0.0005)
            os.close(fd)
            os.unlink(mark)
            got += 1
    except FolderBusy:
        busy += 1
print(got, busy)
"""


def test_claim_exclusive_under_contention(tmp_path):
    """Six processes claiming one DIR as fast as they can for 2 s (the lock
    file created, locked, removed thousands of times): never two holders."""
    out, mark = tmp_path / "res", tmp_path / "inside"
    procs = [subprocess.Popen([sys.executable, "-c", STRESS, str(out), str(mark), "2"], cwd=tmp_path, env=_env(),
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(6)]
    results = [p.communicate(timeout=60) for p in procs]
    for p, (so, se) in zip(procs, results):
        assert p.returncode == 0, se                 # a FileExistsError would mean two holders at once
    got = [int(so.split()[0]) for so, _ in results]
    assert sum(got) > 50 and sum(int(so.split()[1]) for so, _ in results) > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == []    # no lock file, no DIR, no marker left


# -- the studies and render: a failed write leaves DIR as it was ------------------------------
def test_study_write_failure_one_line_dir_unchanged(tmp_path, monkeypatch, capsys, keep_sigterm):
    from fpd.studies import stability

    def full(path, *a, **k):
        raise OSError(28, "No space left on device", str(path))

    monkeypatch.setattr(stability, "run_catalogue", lambda *a, **k: [])      # nothing to compute: the write is the test
    monkeypatch.setattr(stability, "write_rows", full)
    out = tmp_path / "runs" / "stab"
    capsys.readouterr()
    assert cli.main(["stability", "--out", str(out), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "No space left on device (ENOSPC)" in err
    assert f"stability wrote nothing, {out} unchanged" in err
    assert not (tmp_path / "runs").exists()
    out.mkdir(parents=True)
    (out / "summary.json").write_text("{}")
    assert cli.main(["stability", "--out", str(out), "--quiet", "--force"]) == 1
    assert [p.name for p in out.iterdir()] == ["summary.json"] and (out / "summary.json").read_text() == "{}"
    no_leftovers(out.parent, {"stab"})


def test_render_write_failure_keeps_old_render(tmp_path, monkeypatch, capsys, keep_sigterm):
    from fpd.outputs import render

    run = tmp_path / "run"
    (run / "vtk").mkdir(parents=True)
    (run / "vtk" / "device.pvd").write_text("")
    (run / "render").mkdir()
    (run / "render" / "device.gif").write_bytes(b"GIF89a old")

    def quota(pngs, path, *a, **k):
        Path(path).write_bytes(b"GIF89a half")                               # a part went in
        raise OSError(122, "Disk quota exceeded", str(path))

    monkeypatch.setattr(render, "read_device_series", lambda *a, **k: [])
    monkeypatch.setattr(render, "draw_frames", lambda frames, d, title, *a: [])
    monkeypatch.setattr(render, "write_gif", quota)
    capsys.readouterr()
    # an existing render/ is replaced only with --force (issue 18); a write failure keeps it whole
    assert cli.main(["render", str(run), "--force"]) == 1
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "Disk quota exceeded" in err and "render wrote nothing" in err
    assert sorted(p.name for p in run.iterdir()) == ["render", "vtk"]          # no partial render left
    assert [p.name for p in (run / "render").iterdir()] == ["device.gif"]
    assert (run / "render" / "device.gif").read_bytes() == b"GIF89a old"
    no_leftovers(tmp_path, {"run"})


def test_claim_without_flock(tmp_path, monkeypatch):
    """A file system without flock (ENOLCK): an O_EXCL lock file instead,
    exclusive, and taken over when its process is gone."""
    import errno
    import types

    from fpd.outputs import claim as claim_mod

    def no_flock(fd, op):
        raise OSError(errno.ENOLCK, "No locks available")

    monkeypatch.setattr(claim_mod, "fcntl", types.SimpleNamespace(flock=no_flock, LOCK_EX=2, LOCK_NB=4))
    out = tmp_path / "res"
    excl = tmp_path / ".res.lock-excl"
    with claim(out) as c:
        assert not c.flock and excl.is_file() and not lock_path(out).exists()
        with pytest.raises(FolderBusy, match=f"in use by pid {os.getpid()} "):
            with claim(out):
                pass
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    import socket
    excl.write_text(f"pid {int(dead.stdout)} on {socket.gethostname()}, `fpd run`, since then\n")
    with claim(out):                                   # a stale lock: its process is gone
        assert str(os.getpid()) in excl.read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == []
