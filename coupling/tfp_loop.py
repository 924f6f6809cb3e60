"""The triple friction pendulum's build and staggered loop (model.md section 5
with four interfaces).

Per step: mu_i(T_i^n, p_i, v_i) for S1..S4 -> the rigid TFP step
(mechanics/tfp.py) -> friction work of each surface and its footprint ->
a thermal step of each part (S1 -> lower plate, S2 -> lower slider plate,
S3 -> upper slider plate, S4 -> upper plate) -> T_i^{n+1}. The plates and the
friction laws are the project's own (thermal/, mechanics/friction.py); only the
bookkeeping of four interfaces lives here, so coupling/run.py's two-interface
loop is untouched. ``iterated`` and ``substeps`` behave as in run.py.
"""
from __future__ import annotations

import time

import numpy as np

from fpd.mechanics.friction import make_law
from fpd.thermal.params import PlateParams

from .build import Simulation, loading_of, make_plate
from .history import MemoryHistory, signals_held
from .scene import TFP_PARTS, TFP_SURFACES, Scene

ORDER = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad", "s1_m", "s2_m", "s3_m", "s4_m",
         "N1_N", "N2_N", "N3_N", "N4_N", "mu1", "mu2", "mu3", "mu4", "T1_C", "T2_C", "T3_C", "T4_C",
         "W1_J", "W2_J", "W3_J", "W4_J", "phase", "E_input_J", "E_kin_J", "E_pot_J", "E_rim_J",
         "E_reseat_J", "E_stored_J", "E_air_J")


def build_tfp(scene: Scene) -> Simulation:
    from fpd.mechanics.tfp import TFPStepper
    from .tfp_scene import tfp_geometry

    dt = scene["solver"]["dt"]
    geom = tfp_geometry(scene.data)
    loading = loading_of(scene, dt)
    mech = TFPStepper(geom, loading, model=scene["mechanics"]["model"])
    dev = scene["device"]
    feet = (dev["slider_diameter"] / 2, dev["pad_diameter"] / 2, dev["pad_diameter"] / 2, dev["slider_diameter"] / 2)
    pp = tuple(PlateParams(**scene.thermal(part), a_contact_m=a) for part, a in zip(TFP_PARTS, feet))
    sub = scene["coupling"]["substeps"]
    plates = tuple(make_plate(p, dt / sub) for p in pp)
    laws = tuple(make_law(scene.friction(s)) for s in TFP_SURFACES)
    info = {"device": "TFP", "capacity_m": geom.capacity}
    if hasattr(loading, "record"):
        ld = scene["loading"]
        info["record"] = {"name": loading.name, "points": len(loading.record.t), "dt_s": loading.record.dt,
                          "pga_g": loading.record.pga_g, "scale": ld["scale"],
                          "baseline_b1_mps2": loading.baseline[0], "baseline_b2_mps3": loading.baseline[1]}
    return Simulation(scene, dt, loading.n_steps, geom, mech, laws, plates, pp, substeps=sub, info=info)


def columns_of(sim: Simulation):
    heat = any(p is not None for p in sim.plates)
    cols = list(sim.mechanics.columns) + ["mu1", "mu2", "mu3", "mu4"]
    if heat:
        cols += ["T1_C", "T2_C", "T3_C", "T4_C", "E_stored_J", "E_air_J"]
    order = [c for c in ORDER if c in cols] + [c for c in cols if c not in ORDER]
    return cols, order


def simulate_tfp(sim: Simulation, progress: bool = False, every: int = 1, inject_failure_at=None,
                 history=None, on_loop_end=None, on_frame=None, frame_every: int = 0, hottest=None):
    """simulate() for the TFP (same Result, statuses and history contract;
    ``on_frame(n, sim)`` every ``frame_every`` steps, after the row, with
    ``sim.frame_values`` the row as a dict: the VTK series, coupling/tfp_vtk.py;
    ``hottest``: a coupling/hottest.HottestFields (TFP_SIDES) offered the four
    parts' fields every ``hot_every`` steps, as simulate() offers the DFP's)."""
    from .run import LOOP_STOPS, NumericalFailure, Result, _Progress, check_row, stop_status

    mech = sim.mechanics
    plates, laws, pp = sim.plates, sim.laws, sim.plate_params
    dt, N, sub = sim.dt, sim.n_steps, sim.substeps
    cpl = sim.scene["coupling"]
    iterated = cpl["scheme"] == "iterated"
    tol, max_iter = cpl["tol_K"], cpl["max_iter"]
    eta = [p.heat_share for p in pp]
    areas = sim.geometry.areas
    heat = any(p is not None for p in plates)
    cols, order = columns_of(sim)
    n_rows = N // every + 1 + (1 if N % every else 0)
    hist = history if history is not None else MemoryHistory()
    cap = hist.start(cols, order, n_rows)
    buf = np.full((cap, len(cols)), np.nan)
    store_s = 0.0
    T = [p.surface_temperature() if p is not None else q.T0_C for p, q in zip(plates, pp)]
    mu = [law(Ti, mech.N[i] / areas[i], 0.0) for i, (law, Ti) in enumerate(zip(laws, T))]

    def row():
        r = mech.values() + tuple(mu)
        if heat:
            st = sum(p.stored_heat() for p in plates if p is not None)
            lo = sum(p.heat_lost() for p in plates if p is not None)
            r += tuple(T) + (st, lo)
        return r

    def flush():
        nonlocal k, store_s
        t0 = time.perf_counter()
        ready = hist.prepare(buf[:k])
        with signals_held():
            hist.commit(ready)
            k = 0
        store_s += time.perf_counter() - t0

    buf[0] = row()
    k = 1
    if k == cap:
        flush()
    status, message = "ok", ""
    total_iter = worst_iter = 0
    bar = _Progress(N, dt, progress)
    old = mech.footprints()
    from .hottest import look_every
    hot_every = look_every(N)              # the plates' fields, ~2000 times a run
    # the common case compiled (coupling/tfp_fast.py); the loop below takes over where it stops
    from .tfp_fast import CHUNK, FULL, REPLAY, ROW_FAILED, compiled_tfp
    fast = None if (on_frame is not None and frame_every) else compiled_tfp(sim, every, len(cols), inject_failure_at)
    t_start = time.perf_counter()
    n = last_row = n0 = 0
    try:
        if fast is not None:
            T_arr, mu_arr = np.array(T, dtype=float), np.array(mu, dtype=float)
            fast.pack()
            try:
                while n0 < N:
                    n_end = min(N, n0 + CHUNK)
                    if hottest is not None:       # chunks end where the fields are looked at
                        n_end = min(n_end, (n0 // hot_every + 1) * hot_every)
                    n_done, k, code = fast._call(buf, k, n0, n_end, T_arr, mu_arr)
                    total_iter += n_done - n0
                    worst_iter = 1
                    n0 = n = n_done
                    last_row = n - n % every if n != N else N
                    if hottest is not None and code != ROW_FAILED and n % hot_every == 0:
                        fast.unpack(n)            # the plates' rows back in their objects: field() reads them
                        hottest.update(plates, n * dt)
                    if code == FULL:
                        flush()
                    elif code == REPLAY:
                        break
                    elif code == ROW_FAILED:
                        check_row(fast.row.tolist(), cols, n, dt)
                    bar.update(n)
            finally:
                fast.unpack(n0)
                T, mu = T_arr.tolist(), mu_arr.tolist()
                old = mech.footprints()
        for n in range(n0 + 1, N + 1):
            snaps = (mech.save(), [p.save() if p else None for p in plates]) if iterated else None
            Tg = list(T)
            it = 0
            while True:
                it += 1
                mu = [law(Tg[i], mech.N[i] / areas[i], mech.slip_v[i]) for i, law in enumerate(laws)]
                dW = mech.step(*mu)
                new = mech.footprints()
                Tn = list(T)
                if heat:
                    for i, p in enumerate(plates):
                        if p is None:
                            continue
                        P = eta[i] * dW[i] / dt
                        if sub == 1:
                            Tn[i] = p.step(P, new[i])
                        else:
                            for j in range(1, sub + 1):
                                Tn[i] = p.step(P, old[i] + j / sub * (new[i] - old[i]))
                if not iterated or max(abs(a - b) for a, b in zip(Tn, Tg)) <= tol:
                    break
                if it >= max_iter:
                    raise NumericalFailure(n, n * dt, f"iterated coupling did not converge in {max_iter} iterations "
                                           f"(|dT| = {max(abs(a - b) for a, b in zip(Tn, Tg)):.3g} K > tol_K = {tol:g})")
                mech.restore(snaps[0])
                for p, s in zip(plates, snaps[1]):
                    if p is not None:
                        p.restore(s)
                Tg = Tn
            total_iter += it
            worst_iter = max(worst_iter, it)
            T = Tn
            old = new
            if inject_failure_at is not None and n == inject_failure_at:
                mech.st[:] = float("nan")
            if n % every == 0 or n == N or n == inject_failure_at:
                r = row()
                check_row(r, cols, n, dt)
                buf[k] = r
                k += 1
                last_row = n
                if k == cap:
                    flush()
                if on_frame is not None and frame_every and n % frame_every == 0:
                    sim.frame_values = dict(zip(cols, r))
                    on_frame(n, sim)
            if hottest is not None and n % hot_every == 0:
                hottest.update(plates, n * dt)
            if n % 2048 == 0:
                bar.update(n)
    except LOOP_STOPS as exc:
        status, message = stop_status(exc, n, dt)
    runtime = time.perf_counter() - t_start - store_s
    if on_loop_end is not None:
        on_loop_end()
    bar.close()
    flush()
    with signals_held():
        hist.finish()
    res = Result(order, None if hist.streamed else hist.data, status, message, runtime, total_iter, worst_iter,
                 plates, dict(sim.info), history=hist)
    res.steps = n if status == "ok" or last_row == n else n - 1
    return res


def build_flat(scene: Scene) -> Simulation:
    """The flat double bearing (mechanics/flat.py): two interfaces, so
    coupling/run.py's own loop drives it."""
    from fpd.mechanics.flat import FlatGeometry, FlatStepper
    from .build import plate_params

    dt = scene["solver"]["dt"]
    dev = scene["device"]
    geom = FlatGeometry(dev["pad_height"], dev["pad_diameter"], dev["pad_mass"], scene["superstructure"]["mass"])
    loading = loading_of(scene, dt)
    mech = FlatStepper(geom, loading)
    sub = scene["coupling"]["substeps"]
    pp = (plate_params(scene, "lower"), plate_params(scene, "upper"))
    plates = tuple(make_plate(p, dt / sub) for p in pp)
    laws = (make_law(scene.friction("lower")), make_law(scene.friction("upper")))
    info = {"device": "flat", "mu_tip_closed_form": geom.mu_tip()}
    if hasattr(loading, "record"):
        ld = scene["loading"]
        info["record"] = {"name": loading.name, "points": len(loading.record.t), "dt_s": loading.record.dt,
                          "pga_g": loading.record.pga_g, "scale": ld["scale"],
                          "baseline_b1_mps2": loading.baseline[0], "baseline_b2_mps3": loading.baseline[1]}
    return Simulation(scene, dt, loading.n_steps, geom, mech, laws, plates, pp, substeps=sub, info=info)
