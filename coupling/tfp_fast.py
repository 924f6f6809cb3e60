"""The TFP's staggered loop compiled: the common case of
coupling/tfp_loop.py (staggered, one thermal step per step, plates none /
lumped / fe1d, friction laws of mechanics/friction.py).

Nothing is translated by hand: the chunk is the kernel module
coupling/tfp_loop_kernel.py compiled by fpd.kernels.compiled; it calls
mechanics/tfp_kernel.py (advance, row_values: the same source the Python
loop runs), friction_kernel.law_mu and coupling/loop_kernel.py's plate steps
and row bookkeeping. This module only packs the Python objects into arrays
(the laws and plates with coupling/fast_loop.py's helpers), calls the chunk
and writes the state back, so the Python objects hold exactly what the
Python loop would have reached (tests/test_tfp.py checks the histories bit
for bit).

Used when numba is installed and FPD_NO_JIT is unset and a plate is fe1d (a
lumped or mechanics-only scene compiles only when numba is loaded already, as
fast_loop does); anything unavailable returns None and the Python loop runs.
"""
from __future__ import annotations

import numpy as np

from fpd import kernels

from . import fast_loop

CHUNK = 4096
WORTH_LOADING_STEPS = 5000
# the chunk's statuses: coupling/loop_kernel.py's DONE, REPLAY, ROW_FAILED, FULL (tfp_loop.py
# compares with these; not imported from there: loop_kernel loads scipy, which a lumped or
# mechanics-only run must not; tests/test_tfp.py checks they agree)
OK, REPLAY, ROW_FAILED, FULL = 1, 2, 3, 4


class TFPCompiled:
    """Packs a TFP simulation for the compiled chunk and runs it."""

    def __init__(self, sim, kinds, every, n_cols):
        from fpd.mechanics import tfp_kernel as tk

        lj = kernels.compiled("fpd.coupling.tfp_loop_kernel")
        lk = lj.lk
        mech = sim.mechanics
        self.sim, self.kinds, self.lj, self.lk = sim, kinds, lj, lk
        self.LW = fast_loop.law_rows(sim.laws)
        N = sim.n_steps
        self.A = np.asarray(mech._a, dtype=float)
        if mech.machine:
            self.U = np.asarray(mech._u, dtype=float)
            self.UD = np.asarray(mech._ud, dtype=float)
            self.XG = -self.U
            self.machine = 1
        else:
            self.U = np.zeros(N + 1)
            self.UD = np.zeros(N + 1)
            self.XG = np.asarray(mech._xg, dtype=float)
            self.machine = 0
        self.areas = np.array(sim.geometry.areas, dtype=float)
        self.eta = np.array([p.heat_share for p in sim.plate_params])
        self.dd = np.array([sim.geometry.d1, sim.geometry.d2, sim.geometry.d3, sim.geometry.d4])
        self.plates, codes = fast_loop.plate_arrays(sim.plates, kinds, lk)
        self.kind_codes = np.array(codes, dtype=np.int64)
        # per part: (Mb, Ab, FAC, V, I, P) -> six tuples over the parts
        self.plate_args = tuple(tuple(arr[j] for arr, _ in self.plates) for j in range(6))
        self.row = np.zeros(n_cols)
        self.out = np.zeros(tk.N_OUT)
        self.M, self.w, self.tmp = np.zeros(3), np.zeros(2), np.zeros(2)
        self.sc = np.zeros(4 + 2 * tk.N_OUT)
        self.S0 = np.zeros(tk.N_S)
        self.ctl = np.zeros(lk.N_CTL, dtype=np.int64)
        self.ctl[lk.C_EVERY], self.ctl[lk.C_N] = every, N
        self.ctl[lk.C_HEAT] = any(k != "none" for k in kinds)
        # compile (or load) now, not inside the timed loop: a call that does no step
        self._call(np.zeros((1, n_cols)), 0, 0, 0, np.zeros(4), np.zeros(4))

    def _call(self, buf, k, n0, n_end, T, mu):
        """Steps n0 + 1 .. n_end, rows into buf from row k -> (steps done, k,
        status): OK, FULL (buf full after the last step done), REPLAY (the
        next step is the Python loop's) or ROW_FAILED (the last step's row,
        in self.row, is not finite)."""
        lk, ctl = self.lk, self.ctl
        ctl[lk.C_NDONE], ctl[lk.C_NEND], ctl[lk.C_K], ctl[lk.C_NROWS] = n0, n_end, k, len(buf)
        m = self.sim.mechanics
        status = self.lj.run_chunk(m.par, m.S, self.S0, self.A, self.U, self.UD, self.XG, self.machine,
                                   self.sim.dt, self.LW, self.areas, self.eta, self.dd, self.kind_codes,
                                   *self.plate_args, T, mu, buf, self.row, ctl,
                                   self.out, self.M, self.w, self.tmp, self.sc)
        n = int(ctl[lk.C_NDONE]) + (1 if status == ROW_FAILED else 0)
        return n, int(ctl[lk.C_K]), status

    def pack(self):
        fast_loop.pack_plates(self.sim.plates, self.plates)

    def unpack(self, n):
        m = self.sim.mechanics
        m.n, m.t = n, n * self.sim.dt
        fast_loop.unpack_plates(self.sim.plates, self.plates)


def compiled_tfp(sim, every, n_cols, inject_failure_at=None):
    """A TFPCompiled for this simulation, or None (the Python loop runs it)."""
    if not fast_loop.enabled or inject_failure_at is not None:
        return None
    if sim.substeps != 1 or sim.scene["coupling"]["scheme"] != "staggered":
        return None
    # the TFP's Python step costs ~85 us: past ~5000 steps loading numba (and the
    # cached kernels) pays for itself even without an fe1d part (benchmarks/tfp_speed.py)
    kinds = fast_loop.plate_kinds(sim, worth_loading=sim.n_steps >= WORTH_LOADING_STEPS)
    if kinds is None:
        return None
    try:
        return TFPCompiled(sim, kinds, every, n_cols)
    except ImportError:         # numba missing after all: the Python loop runs
        return None
