"""simulate()'s compiled fast path for the bidirectional stepper.

Used when the run is staggered with one thermal step per step, the plates
are lumped / fe1d / none, the laws are mechanics.friction's and numba is
available (and already loaded, or a plate needs it): the kernel module
coupling/bidirectional_loop_kernel.py, compiled by fpd.kernels.compiled, runs
the steps between simulate()'s events. The driver is coupling/fast_loop.py's
CompiledLoop (its chunks, events, plate and law packing); only the stepper's
arrays differ: they are the stepper's own (no copy), so the Python objects
hold the state the Python loop would have reached, and it can take over at
any step.
"""
from __future__ import annotations

import numpy as np

from fpd import kernels

from . import fast_loop
from .fast_loop import CompiledLoop


def compiled_loop_2d(sim, every: int, n_rows: int, cols, inject_failure_at=None):
    """A BidirectionalCompiledLoop, or None (the Python loop runs it)."""
    mech = sim.mechanics
    if not fast_loop.enabled or mech is None or sim.substeps != 1 or sim.scene["coupling"]["scheme"] != "staggered":
        return None
    if type(mech).__name__ != "BidirectionalStepper" or type(mech).__module__ != "fpd.mechanics.bidirectional":
        return None
    if any(k in vars(mech) for k in ("step", "values", "save", "restore")):
        return None
    kinds = fast_loop.plate_kinds(sim)
    if kinds is None:
        return None
    if inject_failure_at is not None and inject_failure_at <= 1:
        return None
    heat = any(k != "none" for k in kinds)
    if list(cols) != list(mech.columns) + (["mu1", "mu2", "T1_C", "T2_C", "E_stored_J", "E_air_J"]
                                           if heat else ["mu1", "mu2"]):
        return None
    try:
        lj = kernels.compiled("fpd.coupling.bidirectional_loop_kernel")
    except ImportError:
        return None
    mech.use_compiled()
    if not mech.compiled:
        return None
    return BidirectionalCompiledLoop(sim, lj, kinds, every, n_rows, cols, inject_failure_at)


class BidirectionalCompiledLoop(CompiledLoop):
    """Runs steps 1.. of simulate()'s loop compiled (CompiledLoop.run)."""

    def __init__(self, sim, lj, kinds, every, n_rows, cols, inject_failure_at):
        self._setup(sim, lj.lk, kinds, every, n_rows, cols, inject_failure_at)
        self.run_chunk = lj.run_chunk
        mech = sim.mechanics
        self.MSAVE = np.zeros(len(mech.S))
        self.AX = np.asarray(mech._ax, dtype=float)
        self.AY = np.asarray(mech._ay, dtype=float)
        self.XG = np.ascontiguousarray(mech._xg, dtype=float)
        self.YG = (np.ascontiguousarray(mech._yg, dtype=float) if mech._yg is not None
                   else np.zeros(len(self.XG)))
        self._call(np.zeros((1, len(cols))))      # load (or compile) now, not inside the timed loop

    def _args(self, buf):
        mech = self.sim.mechanics
        (p1, _), (p2, _) = self.plates
        return (mech.C, mech.S, self.MSAVE, self.AX, self.AY, self.XG, self.YG, self.LW1, self.LW2, self.F,
                *p1, *p2, buf, self.row, self.ctl)

    # the stepper's state arrays are the kernel's: only its step count and the plates travel
    def _pack(self):
        fast_loop.pack_plates(self.sim.plates, self.plates)

    def _unpack(self):
        self.sim.mechanics.n = int(self.ctl[self.lj.C_NDONE])
        fast_loop.unpack_plates(self.sim.plates, self.plates)

    def _events(self, n, *events):
        self.sim.mechanics.n = n
        super()._events(n, *events)
