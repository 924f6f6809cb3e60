"""The compiled fe3d kernel (numba): thermal/_fe3d_kernel.py loaded through
fpd.kernels.compiled (the same source, every function njit-ed)."""
from fpd.kernels import compiled

K = compiled("fpd.thermal._fe3d_kernel")


def warm_up():
    K.warm_up()
