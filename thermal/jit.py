"""The optional numba kernels: one loader for every compiled module.

A kernel module is imported on first use, never at start-up (lumped and
mechanics-only scenes must not pay numba's import), and only when numba is
installed and the environment variable FPD_NO_JIT is unset; otherwise the
callers take their pure numpy path, which gives the same numbers.
"""
from __future__ import annotations

import importlib
import os


class OptionalKernels:
    """``kernels()`` -> the named modules (a tuple), or None when unavailable.

    ``warm``: call each module's ``warm_up()`` once loaded (compile or load
    the cached kernels before the time-stepping loop, not on its first step).
    ``loaded`` is None before the first call, False when unavailable (tests
    set it to False to force the pure path)."""

    def __init__(self, *names: str, warm: bool = False):
        self.names = names
        self.warm = warm
        self.loaded = None

    def __call__(self):
        if self.loaded is None:
            self.loaded = False
            if not os.environ.get("FPD_NO_JIT"):
                from fpd import jitcache
                jitcache.announce(self.names)       # "compiling kernels once", before it happens
                try:
                    mods = tuple(importlib.import_module(n) for n in self.names)
                except ImportError:
                    return None
                if self.warm:
                    for m in mods:
                        m.warm_up()
                self.loaded = mods
        return self.loaded or None
