"""One source, two backends: the per-step physics is written once.

A *kernel module* is an ordinary Python module that sets ``__kernel__ = True``
and defines its physics as plain functions over floats and float64 arrays (or
Python lists, on the pure path), in the subset of Python that numba compiles:
no classes, dicts, exceptions or keyword-only arguments inside the functions;
errors are returned as flags. It never imports numba.

- The pure path imports the module as usual and calls its functions.
- The compiled path calls ``compiled("fpd.mechanics.two_phase_kernel")``: the
  same source file is loaded a second time as a separate module, and every
  function it defines is replaced by ``numba.njit`` of itself; functions and
  modules it imported from other kernel modules are replaced by their compiled
  counterparts, so calls between kernels stay compiled. Nothing is translated
  by hand, so a change made in the source reaches both paths.
- A module of primitives whose pure and compiled forms must differ (BLAS
  through scipy against BLAS through pointers) names its compiled twin in
  ``__compiled_backend__``; the compiled kernels call the twin. Only those
  few primitives have two backends.

A kernel module may set ``__jit_options__`` (e.g. ``{"inline": "always"}``
for small functions passed many arrays: numba then inlines them into their
callers instead of calling them with reference-counted array arguments),
and name in ``__jit_no_inline__`` the functions of such a module that stay
calls: numba types an inlined function again at every call site, so a
function inlined at several sites (or inside another inlined one) costs its
compile time several times over. Inline what runs every step; call what runs
rarely.

``available()`` says whether the compiled path may be used (numba installed,
``FPD_NO_JIT`` unset) without importing numba.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
import sys
import types

JIT_OPTIONS = {"cache": True, "nogil": True, "error_model": "numpy"}
_SUFFIX = "__njit"
_compiled: dict[str, types.ModuleType] = {}
_deps: dict[str, list] = {}          # the source files a compiled module depends on
# the command line's own process (frontends/cli.py): the objects alive when numba is
# first loaded (the modules imported, the scene's arrays) are frozen out of the
# garbage collector's full passes (gc.freeze), which compiling triggers many times
LEAN = False
_frozen = False


def available() -> bool:
    """True when numba is installed and ``FPD_NO_JIT`` is unset (numba is not imported)."""
    if os.environ.get("FPD_NO_JIT"):
        return False
    return "numba" in sys.modules or importlib.util.find_spec("numba") is not None


def is_kernel_module(mod) -> bool:
    return isinstance(mod, types.ModuleType) and getattr(mod, "__kernel__", False) is True


def compiled(name: str, bind: dict | None = None) -> types.ModuleType:
    """The kernel module ``name`` with each of its functions compiled by numba.

    Module-level constants are taken from the pure module as it is now, so a
    value changed there before the first ``compiled()`` call reaches the
    compiled functions too (numba freezes globals at compile time; a cached
    kernel keeps the globals it was compiled with, see ``fresh``).

    ``bind``: module-level names of ``name`` to rebind to other kernel
    modules, ``{"dev": "fpd.mechanics.dev_tfp"}``: the same source loaded
    once more with those modules in place (the coupled engine, one source
    for every device: coupling/engine_kernel.py). Each binding is a module
    of its own, compiled and cached on its own (its functions' cache files
    carry the bound modules' names), so a scene compiles only its device."""
    tag = "".join("__" + v.rsplit(".", 1)[-1] for _, v in sorted((bind or {}).items()))
    key = name + tag
    if key in _compiled:
        return _compiled[key]
    import numba
    global _frozen
    if LEAN and not _frozen:
        import gc
        gc.freeze()
        _frozen = True

    pure = importlib.import_module(name)
    if not is_kernel_module(pure):
        raise TypeError(f"{name} is not a kernel module (it must set __kernel__ = True)")
    jit_options = getattr(pure, "__jit_options__", {})
    from fpd import jitcache
    jitcache.note(name)             # before numba may write its (empty) index files
    if jit_options.get("inline") != "always":     # inlined kernels leave no cache of their own
        jitcache.announce([name])   # "compiling kernels once", when numba has no cache for it yet
    spec = importlib.util.spec_from_file_location(key + _SUFFIX, pure.__file__)
    mod = importlib.util.module_from_spec(spec)
    mod.__package__ = pure.__package__      # relative imports resolve as in the pure module
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    for attr, target in (bind or {}).items():
        if not is_kernel_module(getattr(mod, attr, None)):
            raise TypeError(f"{name}.{attr} is not a kernel module: it cannot be bound to {target}")
        mod.__dict__[attr] = importlib.import_module(target)
    _compiled[key] = mod                    # before rewiring: kernel modules may import each other
    options = dict(JIT_OPTIONS, **jit_options)
    options["cache"] = options["cache"] and not os.environ.get("FPD_JIT_NO_CACHE")
    no_inline = set(getattr(pure, "__jit_no_inline__", ()))
    deps = [pure.__file__]
    for attr, val in list(vars(mod).items()):
        if attr.startswith("__"):
            continue
        if isinstance(val, types.FunctionType):
            owner = sys.modules.get(val.__module__)
            if val.__module__ == spec.name:
                if tag:                     # numba names its cache files after the qualname
                    val.__qualname__ += tag
                own = options if attr not in no_inline else {k: v for k, v in options.items() if k != "inline"}
                mod.__dict__[attr] = numba.njit(**own)(val)
            elif is_kernel_module(owner):
                mod.__dict__[attr] = getattr(compiled(val.__module__), val.__name__)
                deps += _deps[val.__module__]
            elif _backend(owner) is not None:
                mod.__dict__[attr] = getattr(_backend(owner), val.__name__)
                deps += [owner.__file__, _backend(owner).__file__]
        elif is_kernel_module(val):
            mod.__dict__[attr] = compiled(val.__name__)
            deps += _deps[val.__name__]
        elif _backend(val) is not None:
            mod.__dict__[attr] = _backend(val)
            deps += [val.__file__, _backend(val).__file__]
        elif attr in pure.__dict__ and not isinstance(val, (types.ModuleType, type)):
            mod.__dict__[attr] = pure.__dict__[attr]
    _deps[key] = sorted(set(deps))
    if options["cache"] and len(_deps[key]) > 1:
        _drop_stale_caches(mod, spec.name, _deps[key])
    return mod


def _backend(mod):
    """The compiled twin named by a primitives module's ``__compiled_backend__``
    (the few linear-algebra calls whose pure and compiled forms differ)."""
    name = getattr(mod, "__compiled_backend__", None) if isinstance(mod, types.ModuleType) else None
    return importlib.import_module(name) if name else None


def _drop_stale_caches(mod, modname: str, files: list) -> None:
    """numba keys a cached function on its own file only, yet a compiled
    kernel carries copies of the kernels it calls from other files: after an
    edit there it would run the old code. So the files it depends on are
    hashed together, and when the hash changes its caches are dropped."""
    import hashlib

    h = hashlib.sha256()
    for f in files:
        with open(f, "rb") as fh:
            h.update(fh.read())
    digest = h.hexdigest()
    disps = [v for v in vars(mod).values() if getattr(v, "py_func", None) is not None
             and v.py_func.__module__ == modname and getattr(v, "_cache", None) is not None]
    if not disps:
        return
    try:
        stamp = os.path.join(disps[0]._cache.cache_path, f"{modname}.deps.sha256")
        with open(stamp) as fh:
            if fh.read() == digest:
                return
    except (OSError, AttributeError):
        pass
    try:
        for d in disps:
            d._cache.flush()
        with open(stamp, "w") as fh:
            fh.write(digest)
    except (OSError, AttributeError, NameError):
        pass        # an unwritable cache: numba compiles in memory anyway


def fresh() -> None:
    """Forget the compiled modules (the next ``compiled()`` builds them again).

    Try a changed constant in a child process (tests/test_one_source.py):
    numba links a compiled callee by its symbol name, so after kernels were
    compiled with a patched constant, cached kernels loaded later in the same
    process may still call the patched copies."""
    for name in list(_compiled):
        sys.modules.pop(name + _SUFFIX, None)
    _compiled.clear()
    _deps.clear()
