"""Is a numba compile coming? The one-line notice before it.

numba caches each compiled kernel (``cache=True``) as an index file
``<module>.<function>-<line>.py<ver>.nbi`` in the ``__pycache__`` folder next
to the module's source (or under ``NUMBA_CACHE_DIR``); the first run after an
install or an edit of a kernel source finds none newer than the source and
compiles, about 15 s in all (the default scene, on two cores; each device's engine compiles on its first use). ``needs_compile(names)`` says so without
importing numba or the kernels; the loader (fpd.kernels ``compiled()``)
calls ``announce(names)`` just before it loads, which prints the notice once per process when the
command line (or ``fpd.run(progress=True)``) has ``enable()``-d it: never
with ``--quiet``.
"""
from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

NOTICE = "fpd: compiling kernels once, about 15 s (cached for later runs)"
_write = None          # where the notice goes; None: nowhere (the default for library use)
_done = False


def enable(write=None) -> None:
    """Show the notice (on stderr unless ``write`` is given) before a compile."""
    global _write
    _write = write or (lambda line: (sys.stderr.write(line + "\n"), sys.stderr.flush()))


def disable() -> None:
    global _write
    _write = None


def _source(name: str) -> Path | None:
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        return None
    return Path(spec.origin) if spec is not None and spec.origin else None


def _index_dirs(src: Path):
    cache = os.environ.get("NUMBA_CACHE_DIR")
    if cache:                       # numba then writes its caches there only
        yield Path(cache)
    else:
        yield src.parent / "__pycache__"


def cached(src: Path) -> bool:
    """True when numba has an index for this source file newer than the file."""
    try:
        stamp = src.stat().st_mtime
    except OSError:
        return False
    for folder in _index_dirs(src):
        if not folder.is_dir():
            continue
        pattern = f"{src.stem}.*.nbi"
        found = folder.glob(pattern) if folder.name == "__pycache__" else folder.rglob(pattern)
        if any(p.stat().st_mtime >= stamp for p in found):
            return True
    return False


def needs_compile(names) -> bool:
    """Would loading these kernel modules (dotted names) compile at least one of them?"""
    for name in names:
        src = _source(name)
        if src is not None and not cached(src):
            return True
    return False


_uncached: set = set()      # kernel modules found without a cache when first loaded in this process


def note(name: str) -> None:
    """Record whether numba had a cache for kernel module ``name`` when this
    process first loaded it (fpd.kernels ``compiled()`` calls this before
    loading, when numba may write empty index files that ``cached`` cannot
    tell from full ones); ``uncached_at_load`` answers later."""
    if needs_compile([name]):
        _uncached.add(name)


def uncached_at_load(names) -> bool:
    """Did any of these kernel modules lack a cache when first loaded (and
    has nothing compiled them since: ``compiled_now``)?"""
    return any(n in _uncached for n in names)


def compiled_now(names) -> None:
    """These kernel modules are compiled (and cached) in this process now."""
    _uncached.difference_update(names)


def announce(names) -> None:
    """The notice, once per process, if enabled and a compile is coming."""
    global _done
    if _write is None or _done or os.environ.get("FPD_NO_JIT"):
        return
    if "numba" not in sys.modules and importlib.util.find_spec("numba") is None:
        return                       # no numba: the pure path, nothing compiles
    if needs_compile(names):
        _done = True
        _write(NOTICE)
