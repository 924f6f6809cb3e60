"""The TFP's staggered loop compiled (numba): the common case of
coupling/tfp_loop.py (staggered, one thermal step per step, plates none /
lumped / fe1d on the column kernel, friction laws of mechanics/friction.py).

Nothing is translated by hand: the mechanics is mechanics/tfp_kernel.py
compiled by fpd.kernels.compiled (advance, row_values: the same source the
Python loop runs), the plates are thermal/_plate_jit.py's steps and the laws
mechanics/_two_phase_jit.law_mu, as in coupling/fast_loop.py. This module only
packs the Python objects into arrays, calls the compiled chunk and writes the
state back, so the Python objects hold exactly what the Python loop would
have reached (tests/test_tfp.py checks the histories bit for bit).

Used when numba is installed and FPD_NO_JIT is unset and a plate is fe1d (a
lumped or mechanics-only scene compiles only when numba is loaded already, as
fast_loop does); anything unavailable returns None and the Python loop runs.
"""
from __future__ import annotations

import os
import sys

import numpy as np

CHUNK = 4096
OK, FULL, REPLAY, ROW_FAILED = 0, 1, 2, 3
_runner = None


def _plate_kind(plate):
    if plate is None:
        return "none"
    name, mod = type(plate).__name__, type(plate).__module__
    if name == "LumpedPlate" and mod.endswith("thermal.lumped"):
        return "lumped"
    if name == "FE1DPlate" and mod.endswith("thermal.fe1d"):
        integ = plate.integ
        if (integ._kern is not None and integ.scheme == "bdf2" and integ.rannacher
                and "step" not in vars(plate) and "step_surface" not in vars(integ)):
            return "fe1d"
    return None


def _make_runner():
    """The compiled chunk (coupling/_tfp_loop_jit.py: numba, cached on disk)."""
    from . import _tfp_loop_jit
    return _tfp_loop_jit.run


class TFPCompiled:
    """Packs a TFP simulation for the compiled chunk and runs it."""

    def __init__(self, sim, kinds, every, n_cols):
        global _runner
        from fpd.mechanics._two_phase_jit import pack_law
        from fpd.thermal import _plate_jit as pj
        from fpd.thermal.stepping import START_STEPS

        mech = sim.mechanics
        self.sim, self.kinds, self.pj = sim, kinds, pj
        self.every = every
        laws = [pack_law(law) for law in sim.laws]
        if any(x is None for x in laws):
            raise LookupError("a friction law without a compiled form")
        width = max(len(x) for x in laws)
        self.LW = np.zeros((4, width))
        for i, x in enumerate(laws):
            self.LW[i, :len(x)] = x
        N = sim.n_steps
        if mech.machine:
            self.A = np.asarray(mech._a, dtype=float)
            self.U = np.asarray(mech._u, dtype=float)
            self.UD = np.asarray(mech._ud, dtype=float)
            self.XG = -self.U
            self.machine = 1
        else:
            self.A = np.asarray(mech._a, dtype=float)
            self.U = np.zeros(N + 1)
            self.UD = np.zeros(N + 1)
            self.XG = np.asarray(mech._xg, dtype=float)
            self.machine = 0
        self.areas = np.array(sim.geometry.areas, dtype=float)
        self.eta = np.array([p.heat_share for p in sim.plate_params])
        self.dd = np.array([sim.geometry.d1, sim.geometry.d2, sim.geometry.d3, sim.geometry.d4])
        self.kind_codes = np.array([{"none": pj.KIND_NONE, "lumped": pj.KIND_LUMPED, "fe1d": pj.KIND_FE1D}[k]
                                    for k in kinds], dtype=np.int64)
        self.PP = np.zeros((4, pj.N_P))
        Ks, Ws, Is, Xs = [], [], [], []
        for i, (plate, kind) in enumerate(zip(sim.plates, kinds)):
            P = self.PP[i]
            P[pj.P_KIND] = self.kind_codes[i]
            if kind == "fe1d":
                integ = plate.integ
                n = len(integ.u)
                h = integ.dt
                X = np.zeros(3 * n + len(integ._W))
                integ.solver(h / integ.start_substeps)
                d, e = integ._factors[h / integ.start_substeps]
                X[:n], X[n:2 * n - 1] = d, e
                c23 = 2.0 * h / 3.0
                integ.solver(c23)
                d, e = integ._factors[c23]
                integ._K[4 * n:5 * n], integ._K[5 * n:6 * n - 1] = d, e
                P[pj.P_C23V] = c23
                P[pj.P_JR], P[pj.P_H], P[pj.P_CB] = integ.jump_rtol, h, integ._cb
                P[pj.P_M], P[pj.P_E0] = integ.start_substeps, integ._e0
                P[pj.P_START] = START_STEPS["bdf2"]
                P[pj.P_TAIR] = plate._T_air
                P[pj.P_FIXED] = plate._fixed_point
                P[pj.P_R0], P[pj.P_AC] = plate.params.radius_m, plate.params.a_contact_m
                Ks.append(integ._K)
                Ws.append(integ._W)
                Is.append(integ._I)
                Xs.append(X)
            else:
                if kind == "lumped":
                    P[pj.P_LH], P[pj.P_LT0], P[pj.P_DECAY] = plate.H, plate.T0, plate._decay
                    P[pj.P_LC], P[pj.P_LDT], P[pj.P_TAIR] = plate.C, plate.dt, plate.T_air
                Ks.append(np.zeros(1))
                Ws.append(np.zeros(1))
                Is.append(np.zeros(1, dtype=np.int32))
                Xs.append(np.zeros(1))
        self.Ks, self.Ws, self.Is, self.Xs = tuple(Ks), tuple(Ws), tuple(Is), tuple(Xs)
        self.row = np.zeros(n_cols)
        from fpd.mechanics import tfp_kernel as tk
        self.out = np.zeros(tk.N_OUT)
        self.M, self.w, self.tmp = np.zeros(3), np.zeros(2), np.zeros(2)
        self.sc = np.zeros(4 + 2 * tk.N_OUT)
        self.S0 = np.zeros(tk.N_S)
        if _runner is None:
            _runner = _make_runner()
        self.run_chunk = _runner
        self.heat = any(k != "none" for k in kinds)
        # compile (or load) now, not inside the timed loop: a call that does no step
        self._call(np.zeros((1, n_cols)), 0, 0, 0, np.zeros(4), np.zeros(4))

    def _call(self, buf, k, n0, n_end, T, mu):
        m = self.sim.mechanics
        return self.run_chunk(m.par, m.S, self.A, self.U, self.UD, self.XG, self.machine, self.sim.dt, self.LW,
                              self.areas, self.eta, self.kind_codes, self.PP, self.Ks, self.Ws, self.Is, self.Xs,
                              T, mu, self.dd, buf, k, n0, n_end, self.every, self.sim.n_steps, self.heat,
                              self.row, self.out, self.M, self.w, self.tmp, self.sc, self.S0)

    def pack(self):
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

    def unpack(self, n):
        pj = self.pj
        m = self.sim.mechanics
        m.n, m.t = n, n * self.sim.dt
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


def compiled_tfp(sim, every, n_cols, inject_failure_at=None):
    """A TFPCompiled for this simulation, or None (the Python loop runs it)."""
    if os.environ.get("FPD_NO_JIT") or inject_failure_at is not None:
        return None
    if sim.substeps != 1 or sim.scene["coupling"]["scheme"] != "staggered":
        return None
    kinds = [_plate_kind(p) for p in sim.plates]
    if None in kinds:
        return None
    if "fe1d" not in kinds and "numba" not in sys.modules:
        return None
    try:
        return TFPCompiled(sim, kinds, every, n_cols)
    except Exception:       # noqa: BLE001 - any kernel missing or not compiling (e.g. renamed
        return None         # plate or law kernels): the Python loop runs; tests/test_tfp.py notices
