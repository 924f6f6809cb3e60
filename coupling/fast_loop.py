"""simulate()'s compiled fast path (issue 7): when to use it, and the driver.

The common case (two-phase stepper, staggered coupling, one thermal step per
step, lumped / fe1d-kernel / no plates, a friction law of mechanics.friction)
runs in coupling/_loop_jit.run_chunk, a numba function over a range of
steps; this module packs the models into arrays, calls it in chunks that end
at simulate()'s events (progress bar, VTK frames, hottest-field tracker,
every 2048 steps so that Ctrl-C is seen within ~10 ms), and writes the state
back into the Python objects, which stay the reference: after the compiled
part they hold exactly the state the Python loop would have reached, so the
Python loop can take over at any step (an injected failure, a step the
kernel hands back because Python would raise there).

Used only with numba installed and FPD_NO_JIT unset. A scene with an fe1d
plate uses it always (numba is loaded for the column kernel anyway); a
lumped or mechanics-only scene only when numba is already loaded in the
process (a study, a process that ran an fe1d scene): loading numba, scipy
and the kernels costs ~0.7 s, which would take such a scene's start past
1 s (issue 7), while its Python loop costs ~10 us per step.
"""
from __future__ import annotations

import os
import sys

import numpy as np

from fpd.thermal.jit import OptionalKernels

CHUNK = 2048                 # steps per call at most (progress bar, Ctrl-C latency)

# (coupling._loop_jit, mechanics._two_phase_jit, thermal._plate_jit), or None
# (numba missing or FPD_NO_JIT set)
kernels = OptionalKernels("fpd.coupling._loop_jit", "fpd.mechanics._two_phase_jit", "fpd.thermal._plate_jit")


def _numba_loaded() -> bool:
    return "numba" in sys.modules


def _plate_kind(plate):
    """'none', 'lumped', 'fe1d' (on the column kernel's path) or None (not compiled)."""
    if plate is None:
        return "none"
    name = type(plate).__name__
    mod = type(plate).__module__
    if mod == "fpd.thermal.lumped" and name == "LumpedPlate":
        return "lumped"
    if mod == "fpd.thermal.fe1d" and name == "FE1DPlate":
        integ = plate.integ
        if (integ._kern is not None and integ.scheme == "bdf2" and integ.rannacher
                and "step" not in vars(plate) and "step_surface" not in vars(integ)):
            return "fe1d"
    return None


def compiled_loop(sim, every: int, n_rows: int, cols, inject_failure_at=None):
    """A CompiledLoop for this simulation, or None: the Python loop runs it."""
    mech = sim.mechanics
    if mech is None or sim.substeps != 1 or sim.scene["coupling"]["scheme"] != "staggered":
        return None
    if type(mech).__name__ != "TwoPhaseStepper" or type(mech).__module__ != "fpd.mechanics.two_phase":
        return None
    if any(k in vars(mech) for k in ("step", "values", "save", "restore")):
        return None                  # patched (tests): the Python loop calls the patch
    kinds = [_plate_kind(p) for p in sim.plates]
    if None in kinds:
        return None
    if inject_failure_at is not None and inject_failure_at <= 1:
        return None
    if "fe1d" not in kinds and not _numba_loaded():
        return None
    if os.environ.get("FPD_NO_JIT"):
        return None
    mods = kernels()
    if mods is None:
        return None
    _, tp, _ = mods
    laws = [tp.pack_law(law) for law in sim.laws]
    if any(x is None for x in laws):
        return None
    if list(cols) != list(mech.columns) + (["mu1", "mu2", "T1_C", "T2_C", "E_stored_J", "E_air_J"]
                                           if any(k != "none" for k in kinds) else ["mu1", "mu2"]):
        return None
    return CompiledLoop(sim, mods, kinds, laws, every, n_rows, cols, inject_failure_at)


class CompiledLoop:
    """Runs steps 1.. of simulate()'s loop compiled; see run()."""

    def __init__(self, sim, mods, kinds, laws, every, n_rows, cols, inject_failure_at):
        lj, tp, pj = mods
        self.sim, self.lj, self.tp, self.pj = sim, lj, tp, pj
        self.kinds, self.cols = kinds, list(cols)
        mech = sim.mechanics
        self.MC = tp.pack_constants(mech)
        self.MS = np.zeros(tp.N_STATE)
        self.MSAVE = np.zeros(tp.N_STATE)
        self.G = tp.ground_arrays(mech)
        self.LW1, self.LW2 = laws
        N = sim.n_steps
        # the Python loop takes over at an injected failure
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
        self._buf_warm = np.zeros((1, len(cols)))
        self._call(self._buf_warm)      # load (or compile) the kernel now, not inside the timed loop

    def _call(self, buf):
        """run_chunk from ctl[C_NDONE] to ctl[C_NEND] (0 to 0: just the dispatch)."""
        (K1, W1, I1, X1), (K2, W2, I2, X2) = self.arrays
        return self.lj.run_chunk(self.MC, self.MS, self.MSAVE, self.G, self.LW1, self.LW2, self.F, self.PP,
                                 K1, W1, I1, X1, K2, W2, I2, X2, buf, self.row, self.ctl)

    @staticmethod
    def _factor(integ, gamma):
        """The integrator's own factor of M + gamma A (computed as its Python
        path computes it, and kept in its cache as that path would)."""
        integ.solver(gamma)
        return integ._factors[gamma]

    # -- the Python objects <-> the arrays ---------------------------------------------
    def _pack(self):
        self.tp.pack_state(self.sim.mechanics, self.MS)
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
        self.tp.unpack_state(self.sim.mechanics, self.MS)
        pj = self.pj
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

    # -- the run -----------------------------------------------------------------------
    def run(self, buf, k, last_row, T1, T2, mu1, mu2, bar=None, hottest=None, hot_every=1,
            on_frame=None, frame_every=0, start=0, pending=False):
        """Steps start+1..n_stop (or until a step the Python loop must take),
        their rows into buf (loop column order) from row k, with simulate()'s
        floats T1, T2, mu1, mu2 and counters as they are after step start.
        Returns an Outcome; never raises for Ctrl-C or a failed row (the
        Outcome carries them, simulate() raises them once its own counters
        are set). Outcome.full: buf filled up at step Outcome.steps; the
        caller empties it and calls again with start=that step and
        pending=True (that step's frame, hottest and progress events are run
        then, after the flush, in simulate()'s order)."""
        lj = self.lj
        ctl, F = self.ctl, self.F
        ctl[lj.C_NDONE], ctl[lj.C_K], ctl[lj.C_LAST] = start, k, last_row
        ctl[lj.C_NROWS] = len(buf)
        F[lj.F_T1], F[lj.F_T2], F[lj.F_MU1], F[lj.F_MU2] = T1, T2, mu1, mu2
        self._pack()
        (K1, W1, I1, X1), (K2, W2, I2, X2) = self.arrays
        run_chunk = lj.run_chunk
        args = (self.MC, self.MS, self.MSAVE, self.G, self.LW1, self.LW2, F, self.PP,
                K1, W1, I1, X1, K2, W2, I2, X2, buf, self.row, ctl)
        events = (bar, hottest, hot_every, on_frame, frame_every)
        out = Outcome()
        n = start
        events_of = 0                # the step whose events are running (Ctrl-C there: that step)
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
                status = run_chunk(*args)
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
        # the step in progress (simulate()'s n) when it stopped early
        out.n = out.steps
        if out.failure:
            out.n = out.failure[0]
        elif out.interrupted and not events_of:
            out.n = min(out.steps + 1, self.sim.n_steps)
        return out

    def _events(self, n, bar, hottest, hot_every, on_frame, frame_every):
        """simulate()'s events at the end of step n, in its order."""
        if on_frame is not None and frame_every and n % frame_every == 0 and int(self.ctl[self.lj.C_LAST]) == n:
            self.tp.unpack_state(self.sim.mechanics, self.MS)
            self.sim.frame_values = self._frame_values(self.row)
            on_frame(n, self.sim)
        if hottest is not None and n % hot_every == 0:
            hottest.update(self.sim.plates, n * self.sim.dt)
        if bar is not None and n % 2048 == 0:
            bar.update(n)

    def _frame_values(self, r):
        vals = dict(zip(self.cols, r.tolist()))
        for c in ("phase", "diagonal"):
            if c in vals:
                vals[c] = int(vals[c])
        return vals


class Outcome:
    """How the compiled part ended: steps done, rows kept, the loop's floats."""

    steps = n = k = last_row = 0
    T1 = T2 = mu1 = mu2 = 0.0
    interrupted = False
    full = False             # the row buffer filled up (see CompiledLoop.run)
    failure = None           # (step, what) of a non-finite row
