"""fpd: thermo-mechanical simulator of multiple friction pendulum isolators.

The Python API (what the ``fpd`` command does, for scripts and notebooks)::

    import fpd
    r = fpd.run("default", solver={"duration": 5.0})   # a packaged name, a path or a dict
    print(r.summary["peak_u_m"])                       # summary.json's fields
    r.history["u_m"], r.history["F_N"]                 # timeseries.csv's columns (numpy arrays)
    figs = r.plot()                                    # the run's figures (matplotlib), by name
    r.plot("hysteresis").savefig("loop.png")
    s = fpd.load_scene("lab-sine", friction={"mu_ref": 0.08})
    fpd.compare("default", fast=True).rows             # lumped / fe1d / axisym side by side
    fpd.converge("heat-disk", fast=True).rows          # observed orders

Every function and class: docs/api.md. Every scene key, output column,
summary.json field and exit status: docs/reference.md (``fpd reference``
prints it). A first bearing from its datasheet: docs/tutorial.md.

The names above are imported on first use, so ``import fpd`` itself stays
cheap (no numpy, scipy or numba). The subpackages live at the top of the
source repository (``loading/``, ``tribology/``, ``mechanics/``, ``machines/``, ``thermal/``, ``meshes/``, ``coupling/``,
``schema/``, ``outputs/``, ``studies/``, ``frontends/``, ``scenes/``) and are installed as ``fpd.mechanics``, ``fpd.thermal``, ...
(pyproject's ``package-dir``). Run from a source checkout without an install,
the repository root is added to this package's search path so that the same
names resolve there.
"""
from __future__ import annotations

import os as _os

__version__ = "0.2.0"

_here = _os.path.dirname(_os.path.abspath(__file__))
_root = _os.path.dirname(_here)
if not _os.path.isdir(_os.path.join(_here, "coupling")) and _os.path.isdir(_os.path.join(_root, "coupling")):
    __path__.append(_root)  # noqa: F821 (the package's own __path__)

# the API lives in fpd.frontends.api; its names are imported on first access
_API = ("run", "load_scene", "compare", "converge", "Result", "History", "StudyResult", "SceneError")
__all__ = ["__version__", *_API]


def __getattr__(name):
    if name in _API:
        from fpd.frontends import api
        value = getattr(api, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'fpd' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_API))
