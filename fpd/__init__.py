"""fpd: thermo-mechanical simulator of multiple friction pendulum isolators.

The subpackages live at the top of the source repository (``mechanics/``,
``thermal/``, ``meshes/``, ``coupling/``, ``scenes/``) and are installed as
``fpd.mechanics``, ``fpd.thermal``, ... (pyproject's ``package-dir``). Run
from a source checkout without an install, the repository root is added to
this package's search path so that the same names resolve there.
"""
from __future__ import annotations

import os as _os

__version__ = "0.2.0"

_here = _os.path.dirname(_os.path.abspath(__file__))
_root = _os.path.dirname(_here)
if not _os.path.isdir(_os.path.join(_here, "coupling")) and _os.path.isdir(_os.path.join(_root, "coupling")):
    __path__.append(_root)  # noqa: F821 (the package's own __path__)
