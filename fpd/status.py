"""The exit statuses of the ``fpd`` command (docs/reference.md, "Exit status"),
one place for the command line and the studies that return them."""
EXIT_OK, EXIT_FAILED, EXIT_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130
EXIT_MEMBERS, EXIT_UNFINISHED = 3, 4     # fpd sweep: members not ok; members not run (studies/sweep.py)
