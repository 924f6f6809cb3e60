"""One writer per results folder.

Every command that writes a results folder DIR first *claims* it: an
exclusive ``fcntl.flock`` on a lock file beside DIR, ``.<name>.lock`` in
DIR's parent, held from the check "is DIR free?" until the new folder is in
place. A second process claiming the same DIR (``fpd run``, ``compare``,
``converge``, ``stability``, ``render``, ``sweep``, with or without
``--force``) is refused at once with exit 2 and one line naming DIR and the
holder (pid, host, command, start time, read from the lock file). Two runs
started in the same second cannot both get it: the kernel grants the lock to
one of them.

Why flock and not a lock file created with O_EXCL: the kernel drops the lock
when its holder dies, however it dies (SIGKILL, a node crash on NFS after the
lease), so a stale lock never blocks anyone; the file left behind by a killed
process is taken over by the next claimant. The lock file is removed by its
holder on release, while still locked; a claimant checks after locking that
the path still names the file it locked (else it locked a removed file and
tries again), so removal never lets two holders in.

File systems without flock (some FUSE or old NFS mounts, ENOLCK/EOPNOTSUPP):
an atomic ``O_CREAT | O_EXCL`` create of ``.<name>.lock-excl`` instead,
holding pid and host; a lock file of a process that is gone (same host, pid not
alive) is stale and replaced.

Under the claim, leftovers of earlier writers of DIR that died (SIGKILL,
power loss) are tidied: ``.<name>.partial-PID`` folders (never complete) are
removed; a ``.<name>.old-PID`` folder (the previous results, moved aside for
the instant of the swap) is put back if DIR is missing, else removed.

API (see docs/architecture.md, "Results folders"):

    with claim(out, force) as c:      # SceneError (exit 2) if DIR is taken or not free
        ... compute, write a ResultsFolder(out), commit ...

    hold(args, out)                   # the same, held until the command returns
                                      # (cli.main closes args.claims)
"""
from __future__ import annotations

import contextlib
import datetime
import errno
import os
import shutil
import socket
import sys
from pathlib import Path

from fpd.schema.scene import SceneError

try:
    import fcntl
except ImportError:                    # not on POSIX: the O_EXCL fallback only
    fcntl = None


class FolderBusy(SceneError):
    """DIR is claimed by another process (exit 2, one line)."""


def lock_path(out) -> Path:
    out = Path(os.path.abspath(out))
    return out.parent / f".{out.name}.lock"


def _who() -> str:
    cmd = " ".join(["fpd"] + [a for a in sys.argv[1:]])[:200]
    since = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    return f"pid {os.getpid()} on {socket.gethostname()}, `{cmd}`, since {since}"


def _holder(path: Path) -> str:
    """Who holds the lock, as it wrote itself into the lock file. A holder
    that has just taken the lock writes itself a moment later: wait for that
    moment (up to 0.5 s) rather than name nobody."""
    import time

    text = ""
    for _ in range(50):
        try:
            text = path.read_text(errors="replace").strip()
        except OSError:
            text = ""
        if text:
            break
        time.sleep(0.01)
    return text.splitlines()[0] if text else "another process (it has not said which yet)"


def _pid_alive(info: str) -> bool:
    """From "pid N on HOST, ...": is that process still there? (unknown: yes)"""
    try:
        head = info.split(",")[0].split()
        pid, host = int(head[1]), head[3]
    except (IndexError, ValueError):
        return True
    if host != socket.gethostname():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


class Claim:
    """The exclusive right to write DIR (see the module docstring)."""

    def __init__(self, out):
        self.out = Path(out)
        self.abs = Path(os.path.abspath(out))
        self.lock = lock_path(out)
        self.fd = None
        self.flock = True
        self.created = []              # folders this claim created (removed again if left empty)

    # -- taking and giving back ------------------------------------------------------
    def _parent(self) -> None:
        missing = []
        p = self.abs.parent
        while not p.exists() and p != p.parent:
            missing.append(p)
            p = p.parent
        try:
            self.abs.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:       # --out under a file, or where we may not write: a bad option
            raise self._cannot(exc) from None
        self.created = missing

    def _cannot(self, exc: OSError) -> Exception:
        """--out under a file, forbidden, read-only: a bad option (exit 2); a
        full disk or quota is not the option's fault: the OSError (exit 1)."""
        if exc.errno in (errno.ENOSPC, errno.EDQUOT):
            return exc
        return SceneError(f"{self.out}: cannot create the results folder there (--out): {exc.strerror}")

    def _open(self) -> int:
        flags = os.O_CREAT | getattr(os, "O_CLOEXEC", 0)
        try:
            return os.open(self.lock, os.O_RDWR | flags, 0o644)
        except PermissionError:        # another user's lock file: flock needs only a read descriptor
            return os.open(self.lock, os.O_RDONLY | flags)

    def acquire(self) -> "Claim":
        self._parent()
        for _ in range(50):            # retried only when the lock file vanished under us
            try:
                fd = self._open()
            except FileNotFoundError:          # the parent removed meanwhile (an empty one, by a claimant)
                with contextlib.suppress(OSError):
                    self.abs.parent.mkdir(parents=True, exist_ok=True)
                continue
            except OSError as exc:
                if exc.errno == errno.EEXIST:
                    continue
                raise self._cannot(exc) from None
            if fcntl is None:
                os.close(fd)
                return self._acquire_excl()
            if fcntl is not None:
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                except BlockingIOError:
                    os.close(fd)
                    raise FolderBusy(f"{self.out}: results folder in use by {_holder(self.lock)}; "
                                     "wait for it to finish or choose another --out") from None
                except OSError as exc:
                    os.close(fd)
                    if exc.errno not in (errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOSYS, errno.EINVAL):
                        raise
                    return self._acquire_excl()
            st = os.fstat(fd)
            try:
                now = os.stat(self.lock)
            except FileNotFoundError:
                now = None
            if now is None or (now.st_ino, now.st_dev) != (st.st_ino, st.st_dev):
                os.close(fd)           # we locked a file its holder had just removed: again
                continue
            self.fd = fd
            self._say_who()
            return self
        raise SceneError(f"{self.out}: could not take the lock {self.lock} (it keeps disappearing)")

    def _acquire_excl(self) -> "Claim":
        """No flock on this file system: an atomic create, stale if its pid is gone.
        Every claimant of a DIR there takes this path, on its own file name (the
        plain lock file, just created to try flock on, means nothing here)."""
        self.flock = False
        with contextlib.suppress(OSError):
            os.unlink(self.lock)
        self.lock = self.lock.with_name(self.lock.name + "-excl")
        for _ in range(3):
            try:
                fd = os.open(self.lock, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                info = _holder(self.lock)
                if _pid_alive(info):
                    raise FolderBusy(f"{self.out}: results folder in use by {info}; wait for it to "
                                     f"finish or choose another --out (a stale lock: remove {self.lock})") from None
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(self.lock)
                continue
            self.fd = fd
            self._say_who()
            return self
        raise FolderBusy(f"{self.out}: results folder in use (lock {self.lock})")

    def _say_who(self) -> None:
        with contextlib.suppress(OSError):       # who holds it is only information (a full disk: left empty)
            os.ftruncate(self.fd, 0)
            os.pwrite(self.fd, (_who() + "\n").encode(), 0)

    def release(self) -> None:
        if self.fd is None:
            return
        with contextlib.suppress(OSError):
            st, now = os.fstat(self.fd), os.stat(self.lock)
            if (now.st_ino, now.st_dev) == (st.st_ino, st.st_dev):
                os.unlink(self.lock)             # while still locked: see the module docstring
        os.close(self.fd)                        # drops the flock
        self.fd = None
        for d in self.created:                   # folders made for a DIR that never came: not left behind
            try:
                os.rmdir(d)
            except OSError:
                break

    # -- tidying under the claim -------------------------------------------------------
    def tidy(self, partials: bool = True) -> None:
        """Leftovers of writers of DIR that died (module docstring); only with
        the claim held, so none of them can belong to a live writer.
        ``partials=False``: the caller takes over dead writers' temporary
        folders itself (a sweep adopts their finished members)."""
        parent, name = self.abs.parent, self.abs.name
        for p in parent.glob(f".{name}.partial-*") if partials else ():
            shutil.rmtree(p, ignore_errors=True)
        for p in sorted(parent.glob(f".{name}.old-*")):
            if os.path.lexists(self.abs):
                shutil.rmtree(p, ignore_errors=True)
            else:                                # died between the two renames of a commit
                with contextlib.suppress(OSError):
                    os.replace(p, self.abs)


@contextlib.contextmanager
def claim(out, force: bool = False, check: bool = True, partials: bool = True):
    """Hold DIR = ``out`` exclusively for the block (FolderBusy, exit 2, if
    another process holds it). ``check``: then refuse a DIR that is not free
    (exists, not empty, without ``force``), now that nobody else can change
    that. Yields the Claim."""
    c = Claim(out).acquire()
    try:
        c.tidy(partials)
        if check:
            from .output import check_out_dir
            check_out_dir(c.out, force)
        yield c
    finally:
        c.release()


_PROCESS = contextlib.ExitStack()        # claims of commands called without cli.main
_registered = False


def hold(args, out, check: bool = True, partials: bool = True) -> Claim:
    """Claim ``out`` for the rest of the command: released when ``cli.main``
    returns (``args.claims``, an ExitStack), whatever happens."""
    args.claimed = getattr(args, "claimed", []) + [Path(out)]
    stack = getattr(args, "claims", None)
    if stack is None:
        global _registered
        if not _registered:
            import atexit
            atexit.register(_PROCESS.close)
            _registered = True
        stack = _PROCESS
    return stack.enter_context(claim(out, getattr(args, "force", False), check, partials))
