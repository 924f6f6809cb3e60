"""``python -m fpd``: the ``fpd`` command."""
from fpd.coupling.cli import entry

entry()
