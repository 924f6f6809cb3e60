"""simulate()'s compiled fast path for the bidirectional stepper.

Used when the run is staggered with one thermal step per step, the plates
are lumped / fe1d (on its kernel path) / none, the laws are
mechanics.friction's and numba is available (and already loaded, or a
plate needs it): coupling/_bidirectional_loop_jit.run_chunk runs the steps
between simulate()'s events (progress, VTK frames, hottest fields, buffer
full, every CHUNK steps for Ctrl-C). The stepper's own state arrays are the
compiled loop's (no copy); the plates are packed and unpacked as
coupling/fast_loop.py does, so the Python objects hold the state the Python
loop would have reached, and it can take over at any step.
"""
from __future__ import annotations

import os
import sys

import numpy as np

from .fast_loop import CHUNK, Outcome


def _plate_kind(plate):
    """'none', 'lumped', 'fe1d' (on the column kernel's path) or None (not compiled)
    (as fast_loop._plate_kind, with the modules' installed names fpd.thermal.*)."""
    if plate is None:
        return "none"
    name, mod = type(plate).__name__, type(plate).__module__
    if mod in ("fpd.thermal.lumped", "thermal.lumped") and name == "LumpedPlate":
        return "lumped"
    if mod in ("fpd.thermal.fe1d", "thermal.fe1d") and name == "FE1DPlate":
        integ = plate.integ
        if (integ._kern is not None and integ.scheme == "bdf2" and integ.rannacher
                and "step" not in vars(plate) and "step_surface" not in vars(integ)):
            return "fe1d"
    return None


def compiled_loop_2d(sim, every: int, n_rows: int, cols, inject_failure_at=None):
    """A BidirectionalCompiledLoop, or None (the Python loop runs it)."""
    mech = sim.mechanics
    if mech is None or sim.substeps != 1 or sim.scene["coupling"]["scheme"] != "staggered":
        return None
    if type(mech).__name__ != "BidirectionalStepper" or type(mech).__module__ != "fpd.mechanics.bidirectional":
        return None
    if any(k in vars(mech) for k in ("step", "values", "save", "restore")):
        return None
    kinds = [_plate_kind(p) for p in sim.plates]
    if None in kinds:
        return None
    if inject_failure_at is not None and inject_failure_at <= 1:
        return None
    if os.environ.get("FPD_NO_JIT"):
        return None
    if "fe1d" not in kinds and "numba" not in sys.modules:
        return None
    from fpd import kernels
    if not kernels.available():
        return None
    try:
        # the plate kernels and compiled laws are other modules' (being reworked
        # into the one-source style): if their names move, the Python loop runs
        from . import _bidirectional_loop_jit as lj
        from fpd.mechanics import _two_phase_jit as tp
        from fpd.thermal import _plate_jit as pj
        laws = [tp.pack_law(law) for law in sim.laws]
    except (ImportError, AttributeError):
        return None
    if any(x is None for x in laws):
        return None
    heat = any(k != "none" for k in kinds)
    if list(cols) != list(mech.columns) + (["mu1", "mu2", "T1_C", "T2_C", "E_stored_J", "E_air_J"]
                                           if heat else ["mu1", "mu2"]):
        return None
    mech.use_compiled()
    if not mech.compiled:
        return None
    return BidirectionalCompiledLoop(sim, lj, tp, pj, kinds, laws, every, n_rows, cols, inject_failure_at)


class BidirectionalCompiledLoop:
    """Runs steps 1.. of simulate()'s loop compiled (the interface of
    coupling/fast_loop.CompiledLoop.run)."""

    def __init__(self, sim, lj, tp, pj, kinds, laws, every, n_rows, cols, inject_failure_at):
        self.sim, self.lj, self.tp, self.pj = sim, lj, tp, pj
        self.kinds, self.cols = kinds, list(cols)
        mech = sim.mechanics
        self.MSAVE = np.zeros(lj.N_S)
        self.AX = np.asarray(mech._ax, dtype=float)
        self.AY = np.asarray(mech._ay, dtype=float)
        self.XG = np.ascontiguousarray(mech._xg, dtype=float)
        self.YG = (np.ascontiguousarray(mech._yg, dtype=float) if mech._yg is not None
                   else np.zeros(len(self.XG)))
        self.LW1, self.LW2 = laws
        N = sim.n_steps
        self.n_stop = N if inject_failure_at is None else min(N, inject_failure_at - 1)
        self.F = np.zeros(lj.N_F)
        self.F[lj.F_AREA] = sim.geometry.contact_area
        self.F[lj.F_ETA1] = sim.plate_params[0].heat_share
        self.F[lj.F_ETA2] = sim.plate_params[1].heat_share
        self.F[lj.F_DT] = sim.dt
        self.ctl = np.zeros(lj.N_CTL, dtype=np.int64)
        self.ctl[lj.C_NROWS], self.ctl[lj.C_EVERY], self.ctl[lj.C_N] = n_rows, every, N
        self.ctl[lj.C_HEAT] = any(k != "none" for k in kinds)
        self.row = np.zeros(len(cols))
        self.PP = np.zeros((2, pj.N_P))
        self.arrays = []
        dummy_f, dummy_i = np.zeros(1), np.zeros(1, dtype=np.int32)
        for i, (plate, kind) in enumerate(zip(sim.plates, kinds)):
            P = self.PP[i]
            P[pj.P_KIND] = {"none": pj.KIND_NONE, "lumped": pj.KIND_LUMPED, "fe1d": pj.KIND_FE1D}[kind]
            if kind == "fe1d":
                from fpd.thermal.stepping import START_STEPS
                integ = plate.integ
                n = len(integ.u)
                h = integ.dt
                X = np.zeros(3 * n)
                d, e = self._factor(integ, h / integ.start_substeps)
                X[:n], X[n:2 * n - 1] = d, e
                c23 = 2.0 * h / 3.0
                d, e = self._factor(integ, c23)
                integ._K[4 * n:5 * n], integ._K[5 * n:6 * n - 1] = d, e
                P[pj.P_C23V] = c23
                P[pj.P_JR], P[pj.P_H], P[pj.P_CB] = integ.jump_rtol, h, integ._cb
                P[pj.P_M], P[pj.P_E0] = integ.start_substeps, integ._e0
                P[pj.P_START] = START_STEPS["bdf2"]
                P[pj.P_TAIR] = plate._T_air
                P[pj.P_FIXED] = plate._fixed_point
                P[pj.P_R0], P[pj.P_AC] = plate.params.radius_m, plate.params.a_contact_m
                self.arrays.append((integ._K, integ._W, integ._I, X))
            else:
                if kind == "lumped":
                    P[pj.P_LH], P[pj.P_LT0], P[pj.P_DECAY] = plate.H, plate.T0, plate._decay
                    P[pj.P_LC], P[pj.P_LDT], P[pj.P_TAIR] = plate.C, plate.dt, plate.T_air
                self.arrays.append((dummy_f, dummy_f, dummy_i, dummy_f))
        self._call(np.zeros((1, len(cols))))      # load (or compile) now, not inside the timed loop

    @staticmethod
    def _factor(integ, gamma):
        integ.solver(gamma)
        return integ._factors[gamma]

    def _args(self, buf):
        mech = self.sim.mechanics
        (K1, W1, I1, X1), (K2, W2, I2, X2) = self.arrays
        return (mech.C, mech.S, self.MSAVE, self.AX, self.AY, self.XG, self.YG, self.LW1, self.LW2, self.F,
                self.PP, K1, W1, I1, X1, K2, W2, I2, X2, buf, self.row, self.ctl)

    def _call(self, buf):
        """run_chunk from ctl[C_NDONE] to ctl[C_NEND] (0 to 0: just the dispatch)."""
        return self.lj.run_chunk(*self._args(buf))

    def _pack(self):
        pj = self.pj
        for plate, kind, P in zip(self.sim.plates, self.kinds, self.PP):
            if kind == "fe1d":
                it = plate.integ
                P[pj.P_C23] = it._c23 if it._c23 is not None else 0.0
                P[pj.P_Q], P[pj.P_LS], P[pj.P_SL], P[pj.P_STEPS] = it._q, it.load_scale, it._start_left, it.steps
                P[pj.P_LP], P[pj.P_HIN], P[pj.P_HLOST] = it.loss_prev, it.heat_in, it.heat_lost
                P[pj.P_HALF], P[pj.P_SOK] = it.half_steps, it._stored_ok
            elif kind == "lumped":
                P[pj.P_RISE], P[pj.P_LIN], P[pj.P_LLOST] = plate.rise, plate._in, plate._lost

    def _unpack(self):
        pj = self.pj
        self.sim.mechanics.n = int(self.ctl[self.lj.C_NDONE])
        for plate, kind, P in zip(self.sim.plates, self.kinds, self.PP):
            v = P.tolist()
            if kind == "fe1d":
                it = plate.integ
                if v[pj.P_C23] != 0.0 and it._c23 is None:
                    it._bdf2_setup(it.dt)
                it._q, it.load_scale = v[pj.P_Q], v[pj.P_LS]
                it.b[0] = v[pj.P_Q]
                it._start_left, it.steps = int(v[pj.P_SL]), int(v[pj.P_STEPS])
                it.loss_prev, it.heat_in, it.heat_lost = v[pj.P_LP], v[pj.P_HIN], v[pj.P_HLOST]
                it.half_steps, it._stored_ok = int(v[pj.P_HALF]), bool(v[pj.P_SOK])
            elif kind == "lumped":
                plate.rise, plate._in, plate._lost = v[pj.P_RISE], v[pj.P_LIN], v[pj.P_LLOST]

    def run(self, buf, k, last_row, T1, T2, mu1, mu2, bar=None, hottest=None, hot_every=1,
            on_frame=None, frame_every=0, start=0, pending=False):
        lj = self.lj
        ctl, F = self.ctl, self.F
        ctl[lj.C_NDONE], ctl[lj.C_K], ctl[lj.C_LAST] = start, k, last_row
        ctl[lj.C_NROWS] = len(buf)
        F[lj.F_T1], F[lj.F_T2], F[lj.F_MU1], F[lj.F_MU2] = T1, T2, mu1, mu2
        self._pack()
        args = self._args(buf)
        events = (bar, hottest, hot_every, on_frame, frame_every)
        out = Outcome()
        n = start
        events_of = 0
        try:
            if pending:
                events_of = n
                self._events(n, *events)
                events_of = 0
            while n < self.n_stop:
                n_end = min(self.n_stop, (n // CHUNK + 1) * CHUNK)
                if hottest is not None:
                    n_end = min(n_end, (n // hot_every + 1) * hot_every)
                if on_frame is not None and frame_every:
                    n_end = min(n_end, (n // frame_every + 1) * frame_every)
                ctl[lj.C_NEND] = n_end
                status = lj.run_chunk(*args)
                n = int(ctl[lj.C_NDONE])
                if status == lj.REPLAY:
                    break
                if status == lj.ROW_FAILED:
                    n += 1
                    vals = self.row.tolist()
                    bad = [c for c, x in zip(self.cols, vals) if not np.isfinite(x)]
                    out.failure = (n, "non-finite " + ", ".join(bad))
                    break
                if status == lj.FULL:
                    out.full = True
                    break
                self.sim.mechanics.n = n
                events_of = n
                self._events(n, *events)
                events_of = 0
        except KeyboardInterrupt:
            out.interrupted = True
        finally:
            self._unpack()
        out.steps = int(ctl[lj.C_NDONE])
        out.k, out.last_row = int(ctl[lj.C_K]), int(ctl[lj.C_LAST])
        out.T1, out.T2, out.mu1, out.mu2 = (float(x) for x in F[lj.F_T1:lj.F_MU2 + 1])
        out.n = out.steps
        if out.failure:
            out.n = out.failure[0]
        elif out.interrupted and not events_of:
            out.n = min(out.steps + 1, self.sim.n_steps)
        return out

    def _events(self, n, bar, hottest, hot_every, on_frame, frame_every):
        if on_frame is not None and frame_every and n % frame_every == 0 and int(self.ctl[self.lj.C_LAST]) == n:
            vals = dict(zip(self.cols, self.row.tolist()))
            vals["phase"] = int(vals["phase"])
            self.sim.frame_values = vals
            on_frame(n, self.sim)
        if hottest is not None and n % hot_every == 0:
            hottest.update(self.sim.plates, n * self.sim.dt)
        if bar is not None and n % 2048 == 0:
            bar.update(n)
