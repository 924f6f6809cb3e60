"""``python -m fpd``: the ``fpd`` command."""
from fpd.frontends.cli import entry

entry()
