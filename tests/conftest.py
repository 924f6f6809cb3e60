import os
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
# The recorded histories (tests/data/*.npz) were computed with OpenBLAS's Haswell
# kernels. OpenBLAS picks its kernels by CPU, and another one rounds the fe1d
# column's band products and dot products differently (the SkylakeX / AVX-512
# kernels: 8.3e-11 relative on the default scene's history), which the suite's
# 1e-12 comparisons would read as a change of the code. So the suite pins the
# Haswell kernels, which every x86-64 CPU with AVX2 runs (numpy and scipy read
# this when their OpenBLAS loads: before any test imports them). A machine
# that sets OPENBLAS_CORETYPE itself keeps its own.
if "numpy" not in sys.modules:
    os.environ.setdefault("OPENBLAS_CORETYPE", "Haswell")
os.environ.setdefault("MPLBACKEND", "Agg")

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

# A suite started in the background of a non-interactive shell (`pytest ... &`)
# inherits SIGINT ignored, and so would every `fpd` it starts: the tests of what
# Ctrl-C does would then see a run that cannot be interrupted. Give the suite
# the interpreter's own Ctrl-C (its children then start with the default).
import signal  # noqa: E402

if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)
