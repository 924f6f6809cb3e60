"""The fpd command, the Python API (fpd.run, ...), the reference generator and
the descriptions it reads. May import every layer."""
