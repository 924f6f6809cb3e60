"""Microseconds per step of the two-phase stepper (run from the repository root).

    python benchmarks/two_phase_step.py [dt_s] [scale]

El Centro 1940 on the default device (DFP R1 = R2 = 2.2 m, pad 0.10 m x
0.25 m, 30 kg; superstructure 1e5 kg; mu = 0.05). Reports step() alone,
step() + values(), and the seated reference for scale.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fpd.mechanics.geometry import DeviceGeometry  # noqa: E402
from fpd.mechanics.two_phase import TwoPhaseStepper  # noqa: E402
from tests.records_helper import elcentro  # noqa: E402

DEVICE = DeviceGeometry("DFP", R1=2.2, R2=2.2, pad_height=0.10, pad_diameter=0.25,
                        pad_mass=30.0, mass=1.0e5)


def per_step_us(make, with_values: bool, repeats: int = 3) -> float:
    best = float("inf")
    for _ in range(repeats):
        st = make()
        step, values = st.step, st.values
        t0 = time.perf_counter()
        if with_values:
            for _ in range(st.n_steps):
                step(0.05, 0.05)
                values()
        else:
            for _ in range(st.n_steps):
                step(0.05, 0.05)
        best = min(best, (time.perf_counter() - t0) / st.n_steps * 1e6)
    return best


def numba_kernel_us(make, repeats: int = 3):
    """The same steps through the compiled mechanics/two_phase_kernel.run_steps (None without numba)."""
    from fpd import kernels
    if not kernels.available():
        return None
    import numpy as np
    K = kernels.compiled("fpd.mechanics.two_phase_kernel")
    best = float("inf")
    for _ in range(repeats + 1):              # the first loads (or compiles) the kernel
        st = make()
        C, S = np.array(st.C), np.array(st.S, dtype=float)
        A, T, D = (np.asarray(x, dtype=float) for x in (st._a_step, st._t, st._d))
        rows = np.zeros((st.n_steps, K.N_VALUES))
        t0 = time.perf_counter()
        K.run_steps(C, S, A, T, D, 0.05, 0.05, st.n_steps, rows)
        best = min(best, (time.perf_counter() - t0) / st.n_steps * 1e6)
    return best


def main() -> None:
    dt = float(sys.argv[1]) if len(sys.argv) > 1 else 1e-3
    scale = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
    ground = elcentro(dt, scale)
    make = lambda: TwoPhaseStepper(DEVICE, ground)  # noqa: E731
    st = make()
    counts = [0, 0, 0]
    for _ in range(st.n_steps):
        st.step(0.05, 0.05)
        counts[st.mode] += 1
    print(f"El Centro x{scale}, dt = {dt:g} s, {st.n_steps} steps "
          f"(stick {counts[0]}, slip {counts[1]}, tilt {counts[2]})")
    print(f"two-phase step():            {per_step_us(make, False):6.2f} us/step")
    print(f"two-phase step() + values(): {per_step_us(make, True):6.2f} us/step")
    kernel_us = numba_kernel_us(make)
    if kernel_us is not None:
        print(f"numba kernel step + values:  {kernel_us:6.2f} us/step (mechanics/two_phase_kernel.py, compiled)")
    try:
        from fpd.machines.seated import SeatedStepper
    except ImportError:
        return
    seated = lambda: SeatedStepper(DEVICE, ground)  # noqa: E731
    print(f"seated step():               {per_step_us(seated, False):6.2f} us/step")


if __name__ == "__main__":
    main()
