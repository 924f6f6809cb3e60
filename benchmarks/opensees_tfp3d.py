"""The seated TFP in both horizontal directions against OpenSees'
TripleFrictionPendulum (the Fenz-Constantinou series model) under a packaged
two-component record pair, and the difference taken apart (docs/model.md 6.10).

    python benchmarks/opensees_tfp3d.py [--opensees-python PATH] [--write]

One bearing: the tfp-elcentro device (inner capacities d2 = d3 = 0.08 m, so
that no surface reaches its rim: the TFP in both directions does not model rim
impacts yet), 40 t on it, constant friction mu1 = mu4 = 0.10, mu2 = mu3 = 0.02,
seated, dt = 1 ms. The OpenSees model: a TripleFrictionPendulum element
between a fixed node and the mass node (rotations fixed, no vertical mass, the
weight a constant nodal load, a stiff elastic vertical material, so the axial
force is W every step), L1 = R_eff2 = R_eff3, L2 = R_eff1, L3 = R_eff4
(R_eff,i = R_i - h_i, docs/model.md 6.4), the displacement limits d_i R_eff,i /
R_i, Coulomb friction, uy = 0.25 mm, Newmark (average acceleration) at the
same dt and the same ground acceleration samples.

Records: the packaged Imperial Valley 1979 pair (x 1) and Ferndale 2022 at
Fortuna (180 / 90 deg, x 2, its first 60 s: later, in the coda, the
element's Newton stalls). Runs, each under the pair (xy) and under each
component alone (x, y):

- rigid: our model (mechanics/tfp3d.py), the device's mu;
- rigid@Reff: our model with each mu_i scaled by R_eff,i / R_i (the friction
  moment about each centre mu_i N R_eff,i, as in the series model);
- series: OpenSees with the device's mu;
- series@Ri: OpenSees with mu_i R_i / R_eff,i (friction acting at the surface);
- series=rigid: OpenSees with the rigid model's small-angle backbone:
  mu_inner = Qi / (W L_i), mu_outer = (Qo - Qi) / (W A): its hexagon is the
  rigid one's exactly (docs/model.md 6.10).

Then quasi-static test-machine cycles, a circle and a line of 0.12 m (rigid,
series, series=rigid), to isolate how each model couples the two directions.

OpenSees runs only when openseespy imports, in this interpreter or in the one
``--opensees-python`` (or FPD_OPENSEES_PYTHON) names; it is not a dependency:

    python3 -m venv /tmp/osvenv && /tmp/osvenv/bin/pip install openseespy
    python benchmarks/opensees_tfp3d.py --opensees-python /tmp/osvenv/bin/python

``--write`` stores the table in benchmarks/opensees_tfp3d.json (the numbers
docs/model.md quotes; tests/test_opensees_tfp3d.py checks them against it).
The OpenSees worker (``--worker in.json out.json``) needs only openseespy.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULT = Path(__file__).resolve().with_suffix(".json")

MUS = (0.10, 0.02, 0.02, 0.10)
RECORDS = {
    "impvall": ("Imperial Valley 1979, El Centro Array #11 (140 on x, 230 on y), x 1",
                ["loading.record=impvall-1979-e11", "loading.scale=1.0"]),
    "ferndale": ("Ferndale 2022, Fortuna (180 on x, 90 on y), x 2, the first 60 s",
                 ["loading.record=ferndale-2022", "loading.channels=[1, 2]", "loading.scale=2.0",
                  "solver.duration=60"]),
}
DEVICE = ["mechanics.model=seated", "device.d2=0.08", "device.d3=0.08"]
DT = 1.0e-3
UY = 2.5e-4                 # OpenSees' yield displacement of its elastic-plastic friction (m); doubled
                            # for a run whose Newton iterations do not converge at it (the table says)
INSTALL = ("openseespy is not importable: OpenSees is not run. It is not a dependency; to compare, "
           "python3 -m venv /tmp/osvenv && /tmp/osvenv/bin/pip install openseespy, then "
           "python benchmarks/opensees_tfp3d.py --opensees-python /tmp/osvenv/bin/python")


# -- the OpenSees worker: openseespy and the standard library only --------------------------
def opensees_element(ops, p: dict, mass: bool) -> float:
    """The model both analyses build: the fixed node and the upper one (free in
    x, y, z), the TripleFrictionPendulum element between them with p's
    friction, radii and capacities, the weight W a constant load on the upper
    node; with mass, the superstructure's mass on x and y. Returns W."""
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, 0.0)
    ops.node(2, 0.0, 0.0, p["H"])
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 0, 0, 0, 1, 1, 1)
    if mass:
        m = p["mass"]
        ops.mass(2, m, m, 0.0, 0.0, 0.0, 0.0)     # no vertical mass: the axial force is W every step
    for i, mu in enumerate(p["mu"]):              # inner pair (L1), lower outer (L2), upper outer (L3)
        ops.frictionModel("Coulomb", i + 1, mu)
    ops.uniaxialMaterial("Elastic", 1, p["kv"])
    ops.uniaxialMaterial("Elastic", 2, 1.0e6)
    L1, L2, L3 = p["L"]
    d1, d2, d3 = p["ubar"]
    W = p["W"]
    ops.element("TripleFrictionPendulum", 1, 1, 2, 1, 2, 3, 1, 2, 2, 2, L1, L2, L3, d1, d2, d3, W,
                p["uy"], 1.0, 0.1, 1.0e-10)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, 0.0, -W, 0.0, 0.0, 0.0)
    return W


def opensees_run(p: dict) -> dict:
    import openseespy.opensees as ops

    W = opensees_element(ops, p, mass=True)
    dt = p["dt"]
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *p["ax"])
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    if p["ay"] is not None:
        ops.timeSeries("Path", 3, "-dt", dt, "-values", *p["ay"])
        ops.pattern("UniformExcitation", 3, 2, "-accel", 3)
    tol = p["tol"]
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", tol, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    ux, uy, fx, fy, fz = [0.0], [0.0], [0.0], [0.0], [-W]
    retried = 0
    relaxed = 0
    t0 = time.time()
    for k in range(len(p["ax"]) - 1):
        ok = ops.analyze(1, dt)
        if ok != 0:                   # a stick-slip switch Newton missed: other algorithms, sub-steps
            retried += 1
            for alg, sub, tl in (("KrylovNewton", 1, tol), ("Newton", 10, tol), ("KrylovNewton", 10, 10 * tol),
                                 ("Newton", 10, 1e2 * tol), ("Newton", 10, 1e4 * tol)):
                ops.algorithm(alg)
                ops.test("NormDispIncr", tl, 100)
                ok = ops.analyze(sub, dt / sub)
                if ok == 0:
                    relaxed += tl > tol
                    break
            ops.algorithm("Newton")
            ops.test("NormDispIncr", tol, 50)
            if ok != 0:
                raise SystemExit(f"OpenSees did not converge at t = {(k + 1) * dt:.3f} s")
        if os.environ.get("FPD_OS_PROGRESS") and k % 1000 == 0:
            print(k, retried, time.time() - t0, file=sys.stderr, flush=True)
        ux.append(ops.nodeDisp(2, 1))
        uy.append(ops.nodeDisp(2, 2))
        f = ops.eleResponse(1, "force")
        fx.append(f[6])
        fy.append(f[7])
        fz.append(f[8])
    return {"ux": ux, "uy": uy, "Fx": fx, "Fy": fy, "Fz": fz, "retried_steps": retried, "relaxed_steps": relaxed,
            "runtime_s": time.time() - t0}


def opensees_orbit(p: dict) -> dict:
    """The element driven quasi-statically along a displacement path (static
    analysis, the path imposed on the mass node's x and y, the weight a
    constant load): the forces along it."""
    import openseespy.opensees as ops

    opensees_element(ops, p, mass=False)
    for dof, key in ((1, "path_x"), (2, "path_y")):
        ops.timeSeries("Path", 1 + dof, "-dt", 1.0, "-values", *p[key])
        ops.pattern("Plain", 1 + dof, 1 + dof)
        ops.sp(2, dof, 1.0)
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", p["tol"], 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    fx, fy = [0.0], [0.0]
    for k in range(len(p["path_x"]) - 1):
        if ops.analyze(1) != 0:
            ops.algorithm("KrylovNewton")
            ok = ops.analyze(1)
            ops.algorithm("Newton")
            if ok != 0:
                raise SystemExit(f"OpenSees did not converge at orbit point {k + 1}")
        f = ops.eleResponse(1, "force")
        fx.append(f[6])
        fy.append(f[7])
    return {"Fx": fx, "Fy": fy}


def worker(argv) -> None:
    with open(argv[0]) as f:
        p = json.load(f)
    out = opensees_orbit(p) if p.get("orbit") else opensees_run(p)
    with open(argv[1], "w") as f:
        json.dump(out, f)


# -- the comparison ------------------------------------------------------------------------
def opensees_python(arg):
    """The interpreter that imports openseespy: this one, the named one, or None."""
    try:
        import openseespy.opensees  # noqa: F401
        return sys.executable
    except Exception:
        pass
    cand = arg or os.environ.get("FPD_OPENSEES_PYTHON")
    if cand:
        r = subprocess.run([cand, "-c", "import openseespy.opensees"], capture_output=True)
        if r.returncode == 0:
            return cand
    return None


def series_parameters(g) -> dict:
    """R_eff,i (docs/model.md 6.4) and the three sets of the series model's mu."""
    hp, tl, tu = g.pad_height, g.slider_height_lower, g.slider_height_upper
    Re = (g.R1 - tl - 0.5 * hp, g.R2 - 0.5 * hp, g.R3 - 0.5 * hp, g.R4 - tu - 0.5 * hp)
    R = (g.R1, g.R2, g.R3, g.R4)
    mu1, mu2, mu3, mu4 = MUS
    Qi = mu2 * g.R2 + mu3 * g.R3          # per unit weight
    Qo = mu1 * g.R1 + mu4 * g.R4
    return {
        "Reff": Re,
        "series": (mu2, mu1, mu4),
        "series@Ri": (mu2 * R[1] / Re[1], mu1 * R[0] / Re[0], mu4 * R[3] / Re[3]),
        "series=rigid": (Qi / g.Li, (Qo - Qi) / g.A, (Qo - Qi) / g.A),
        "rigid": MUS,
        "rigid@Reff": tuple(m * re / r for m, re, r in zip(MUS, Re, R)),
    }


def load(rec):
    from fpd.schema import scene as scn
    from fpd.schema.scene import tfp_geometry
    from fpd.coupling.build import bidirectional_loading_of

    s = scn.load("tfp-elcentro", DEVICE + RECORDS[rec][1])
    g = tfp_geometry(s.data)
    gx, gy = bidirectional_loading_of(s, DT)
    return g, gx, gy


def ours(g, gx, gy, mus):
    import numpy as np
    from fpd import kernels
    from fpd.mechanics.tfp3d import TFP3DStepper

    k = kernels.compiled("fpd.mechanics.tfp3d_kernel") if kernels.available() else None
    st = TFP3DStepper(g, gx, gy, kernel=k)
    ix = [st.columns.index(c) for c in ("ux_m", "uy_m", "Fx_N", "Fy_N")]
    rows = [st.values()]
    for _ in range(gx.n_steps):
        st.step(*mus)
        rows.append(st.values())
    d = np.array(rows)[:, ix]
    return {"ux": d[:, 0], "uy": d[:, 1], "Fx": d[:, 2], "Fy": d[:, 3], "W_friction": sum(st.W),
            "step_force": True}


def theirs(py, g, gx, gy, mus):
    import numpy as np
    sp = series_parameters(g)
    Re = sp["Reff"]
    caps = (g.d2 * Re[1] / g.R2, g.d1 * Re[0] / g.R1, g.d4 * Re[3] / g.R4)
    p = {"H": g.H, "mass": g.mass, "mu": list(mus), "kv": 1.0e10, "L": [Re[1], Re[0], Re[3]],
         "ubar": list(caps), "W": g.weight, "uy": UY, "tol": 1.0e-10, "dt": DT,
         "ax": [float(a) for a in gx.a], "ay": None if gy is None else [float(a) for a in gy.a]}
    with tempfile.TemporaryDirectory() as tmp:
        fi, fo = Path(tmp) / "in.json", Path(tmp) / "out.json"
        for _ in range(3):
            fi.write_text(json.dumps(p))
            try:
                r = subprocess.run([py, str(Path(__file__).resolve()), "--worker", str(fi), str(fo)],
                                   capture_output=True, text=True, timeout=300)
            except subprocess.TimeoutExpired:       # Newton stuck retrying a chattering stretch
                r = subprocess.CompletedProcess([], 1, "", "timed out")
            if r.returncode == 0:
                break
            p["uy"] *= 2.0
        else:
            raise SystemExit(f"the OpenSees run failed: {r.stderr.strip().splitlines()[-1:]}")
        out = json.loads(fo.read_text())
    if max(abs(f + g.weight) for f in out["Fz"]) > 1e-6 * g.weight:
        raise SystemExit("OpenSees' axial force left W")
    return {k: np.asarray(out[k]) for k in ("ux", "uy", "Fx", "Fy")} | {
        "retried_steps": out["retried_steps"], "relaxed_steps": out["relaxed_steps"], "uy_m": p["uy"],
        "step_force": False}


WINDOW = 3000               # steps of the stored check tests/test_opensees_tfp3d.py reruns


def window_peak_force(g, gx, gy, n=WINDOW) -> float:
    """Our model's peak resultant force over the record pair's first n steps."""
    import numpy as np
    from fpd.loading.ground_motion import GroundMotion
    cut = [GroundMotion(m.name, m.dt, m.t[:n + 1], m.d[:n + 1], m.v[:n + 1], m.a[:n + 1], m.a_step[:n])
           for m in (gx, gy)]
    r = ours(g, cut[0], cut[1], MUS)
    return float(np.max(np.hypot(r["Fx"], r["Fy"])))


ORBIT_A, ORBIT_F, ORBIT_CYCLES, ORBIT_DT, ORBIT_POINTS = 0.12, 0.02, 3, 5.0e-3, 2000


def orbit_runs(py, g) -> dict:
    """Quasi-static test-machine cycles, the last of three measured: a circle
    of radius 0.12 m (the directions coupled) and a line of amplitude 0.12 m
    (x only), both engaging all four surfaces. Ours: the test machine at
    0.02 Hz, dt = 5 ms (the circle the TFP in both directions, the line the
    planar TFP, which a zero y component reproduces); OpenSees: the element
    driven along the same path (2000 points a cycle, static; the circle
    reached by a radial ramp). Dissipation per cycle int F . du and peak
    resultant force of the last cycle."""
    import numpy as np
    from fpd import kernels
    from fpd.loading.ground_motion import sine_programme
    from fpd.loading.orbits import orbit_programme
    from fpd.mechanics.tfp import TFPStepper
    from fpd.mechanics.tfp3d import TFP3DStepper

    sp = series_parameters(g)
    Re = sp["Reff"]
    A, cyc = ORBIT_A, ORBIT_CYCLES
    out = {}
    for wf in ("circle", "line"):
        if wf == "circle":
            prog = orbit_programme("circle", A, ORBIT_F, cyc, ORBIT_DT)
            k = kernels.compiled("fpd.mechanics.tfp3d_kernel") if kernels.available() else None
            st = TFP3DStepper(g, prog, None, kernel=k)
            cols = ("ux_m", "uy_m", "Fx_N", "Fy_N")
        else:
            prog = sine_programme(A, ORBIT_F, cyc, ORBIT_DT)
            st = TFPStepper(g, prog, model="seated")
            cols = ("u_m", "u_m", "F_N", "F_N")
        ix = [st.columns.index(c) for c in cols]
        rows = [st.values()]
        for _ in range(prog.n_steps):
            st.step(*MUS)
            rows.append(st.values())
        d = np.array(rows)[prog.n_steps - prog.n_steps // cyc:, ix]
        ux, uy, Fx, Fy = d.T
        if wf == "line":
            uy, Fy = 0.0 * uy, 0.0 * Fy
        out[f"{wf}/rigid"] = {"E_J": float(np.sum(Fx[1:] * np.diff(ux) + Fy[1:] * np.diff(uy))),
                              "F_peak_W": float(np.max(np.hypot(Fx, Fy)) / g.weight)}
        if py is None:
            continue
        m = ORBIT_POINTS
        th = np.linspace(0.0, 2.0 * math.pi * cyc, m * cyc + 1)
        if wf == "circle":
            ramp = np.linspace(0.0, A, 201)
            px = np.concatenate([ramp, A * np.cos(th[1:])])
            py_ = np.concatenate([0.0 * ramp, A * np.sin(th[1:])])
        else:
            px, py_ = A * np.sin(th), 0.0 * th
        for name in ("series", "series=rigid"):
            p = {"orbit": True, "H": g.H, "mu": list(sp[name]), "kv": 1.0e10, "L": [Re[1], Re[0], Re[3]],
                 "ubar": [g.d2 * Re[1] / g.R2, g.d1 * Re[0] / g.R1, g.d4 * Re[3] / g.R4], "W": g.weight,
                 "uy": UY, "tol": 1.0e-10, "path_x": px.tolist(), "path_y": py_.tolist()}
            with tempfile.TemporaryDirectory() as tmp:
                fi, fo = Path(tmp) / "in.json", Path(tmp) / "out.json"
                fi.write_text(json.dumps(p))
                r = subprocess.run([py, str(Path(__file__).resolve()), "--worker", str(fi), str(fo)],
                                   capture_output=True, text=True, timeout=600)
                if r.returncode != 0:
                    raise SystemExit(f"the OpenSees orbit failed: {r.stderr.strip().splitlines()[-1:]}")
                o = json.loads(fo.read_text())
            s0 = len(px) - m - 1
            Fx, Fy = np.asarray(o["Fx"])[s0:], np.asarray(o["Fy"])[s0:]
            ux, uy = px[s0:], py_[s0:]
            E = np.sum(0.5 * (Fx[1:] + Fx[:-1]) * np.diff(ux) + 0.5 * (Fy[1:] + Fy[:-1]) * np.diff(uy))
            out[f"{wf}/{name}"] = {"E_J": float(E), "F_peak_W": float(np.max(np.hypot(Fx, Fy)) / g.weight)}
    return out


def metrics(r, W) -> dict:
    """Peak resultant displacement and force (the largest force held over two
    consecutive rows: our force is the step's impulse / dt, and a step in
    which a sliding block stops while the ground demands more than friction
    holds reads one row of M a_g, docs/model.md 6.2, 0.182 W once in the
    Ferndale runs against 0.137 W around it; the largest row is kept as
    F_max_row_N), dissipated energy (the work of
    the bearing's force on the relative displacement, int F . du), residual
    displacement, and the orbit's shape: the principal axes of the
    displacement's second moment (minor / major, the major's azimuth)."""
    import numpy as np
    ux, uy, Fx, Fy = r["ux"], r["uy"], r["Fx"], r["Fy"]
    dux, duy = np.diff(ux), np.diff(uy)
    if r["step_force"]:           # our force is the step's (impulse / dt): step n -> n + 1 is row n + 1's
        E = float(np.sum(Fx[1:] * dux + Fy[1:] * duy))
    else:                         # OpenSees' nodal forces at the grid points: trapezoid
        E = float(np.sum(0.5 * (Fx[1:] + Fx[:-1]) * dux + 0.5 * (Fy[1:] + Fy[:-1]) * duy))
    F = np.hypot(Fx, Fy)
    F2 = float(np.max(np.minimum(F[1:], F[:-1])))     # held over two rows: not a one-step spike
    C = np.cov(np.vstack([ux, uy]))
    lam, vec = np.linalg.eigh(C)
    az = math.degrees(math.atan2(vec[1, 1], vec[0, 1])) % 180.0
    out = {"u_peak_m": float(np.max(np.hypot(ux, uy))), "F_peak_N": F2, "F_peak_W": F2 / W,
           "F_max_row_N": float(np.max(F)), "E_J": E,
           "u_res_m": float(math.hypot(ux[-1], uy[-1])),
           "orbit_axes": float(math.sqrt(max(lam[0], 0.0) / lam[1])) if lam[1] > 0 else 0.0,
           "orbit_azimuth_deg": float(az)}
    if "W_friction" in r:
        out["W_friction_J"] = float(r["W_friction"])
    for k in ("retried_steps", "relaxed_steps", "uy_m"):
        if k in r:
            out[k] = r[k]
    return out


def hexagon_table(g) -> dict:
    """The small-angle loops of docs/model.md 6.3-6.4 at U = 0.25 m: rigid,
    series, series with friction at R_i, series with the rigid backbone."""
    from fpd.studies.tfp_backbone import hexagon_loop
    sp = series_parameters(g)
    W, Li, L = g.weight, g.Li, g.A + g.Li
    out = {}
    for name in ("series", "series@Ri", "series=rigid"):
        mi, m1, m4 = sp[name]
        mo = 0.5 * (m1 + m4)
        # series, symmetric: inner branch W u / Li + mi W; outer W u / L + (mo A + mi Li) W / L
        out[name] = hexagon_loop(W / Li, W / L, mi * W, (mo * g.A + mi * Li) * W / L, 0.25)[0]
    Qi = W * (MUS[1] * g.R2 + MUS[2] * g.R3)
    Qo = W * (MUS[0] * g.R1 + MUS[3] * g.R4)
    out["rigid"] = hexagon_loop(W / Li, W / L, Qi / Li, Qo / L, 0.25)[0]
    return out


NAMES = ("rigid", "rigid@Reff", "series", "series@Ri", "series=rigid")
COMPS = {"xy": "both", "x": "x alone", "y": "y alone"}


def markdown(table) -> list:
    """The rows docs/model.md 6.10 quotes (tests/test_opensees_tfp3d.py finds
    each of them there): the pair's runs, then the gap and its parts."""
    rows = []
    recs = sorted({k.split("/")[0] for k in table["runs"]}, key=list(RECORDS).index)
    for rec in recs:
        for name in NAMES:
            m = table["runs"][f"{rec}/xy/{name}"]
            rows.append(f"| {rec} | {name} | {m['u_peak_m']:.4f} | {m['F_peak_W']:.4f} | {m['E_J'] / 1e3:.2f} | "
                        f"{1e3 * m['u_res_m']:.1f} | {m['orbit_axes']:.3f} | {m['orbit_azimuth_deg']:.1f} |")
    for rec in recs:
        for comp in COMPS:
            R = {n: table["runs"][f"{rec}/{comp}/{n}"] for n in NAMES}

            def rel(a, b, q):
                return f"{100 * (R[a][q] / R[b][q] - 1):+.1f} %"

            gap = R["rigid"]["F_peak_N"] - R["series"]["F_peak_N"]
            ob = table["outer_branch"]
            pred = ((ob["k_per_m"] * R["rigid"]["u_peak_m"] + ob["b_rigid"])
                    / (ob["k_per_m"] * R["series"]["u_peak_m"] + ob["b_series"]) - 1)
            rows.append(f"| {rec} | {COMPS[comp]} | {rel('rigid', 'series', 'F_peak_N')} | {100 * pred:+.1f} % | "
                        f"{100 * (R['series@Ri']['F_peak_N'] - R['series']['F_peak_N']) / gap:.0f} % | "
                        f"{100 * (R['series=rigid']['F_peak_N'] - R['series']['F_peak_N']) / gap:.0f} % | "
                        f"{rel('rigid@Reff', 'series', 'F_peak_N')} | {rel('series=rigid', 'rigid', 'F_peak_N')} | "
                        f"{rel('rigid', 'series', 'u_peak_m')} | {rel('series=rigid', 'rigid', 'u_peak_m')} | "
                        f"{rel('rigid', 'series', 'E_J')} | {rel('series=rigid', 'rigid', 'E_J')} |")
    if "orbits" in table:
        o = table["orbits"]
        for wf in ("circle", "line"):
            for name in ("rigid", "series", "series=rigid"):
                m = o[f"{wf}/{name}"]
                rows.append(f"| {wf} | {name} | {m['E_J'] / 1e3:.2f} | {m['F_peak_W']:.4f} | "
                            f"{100 * (m['E_J'] / o[f'{wf}/rigid']['E_J'] - 1):+.1f} % | "
                            f"{100 * (m['F_peak_W'] / o[f'{wf}/rigid']['F_peak_W'] - 1):+.1f} % |")
    return rows


def outer_branches(g) -> dict:
    """Small-angle outer branches F / W = u / (A + L_i) + b of the two models
    (docs/model.md 6.3-6.4): b = Qo / (W (A + L_i)) rigid, (A mu1 + L_i mu2) /
    (A + L_i) series (symmetric)."""
    L = g.A + g.Li
    return {"k_per_m": 1.0 / L, "b_rigid": (MUS[0] * g.R1 + MUS[3] * g.R4) / L,
            "b_series": (g.A * MUS[0] + g.Li * MUS[1]) / L}


def main(argv) -> int:
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--opensees-python", default=None)
    ap.add_argument("--write", action="store_true", help=f"store the table in {RESULT.name}")
    ap.add_argument("--records", default="impvall,ferndale", help="comma-separated; 'none' for the orbits only")
    ap.add_argument("--no-orbits", action="store_true", help="skip the quasi-static circle and line")
    a = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    py = opensees_python(a.opensees_python)
    if py is None:
        print(INSTALL)
    table = {"dt_s": DT, "uy_m": UY, "mu": MUS, "runs": {}}
    for rec in [r for r in a.records.split(",") if r != "none"]:
        g, gx, gy = load(rec)
        sp = series_parameters(g)
        table["weight_N"] = g.weight
        table["series_mu"] = {k: list(sp[k]) for k in ("series", "series@Ri", "series=rigid")}
        table["rigid_mu"] = {k: list(sp[k]) for k in ("rigid", "rigid@Reff")}
        table["hexagon_area_J"] = hexagon_table(g)
        table["outer_branch"] = outer_branches(g)
        if rec == "impvall":
            table["window_rigid_F_peak_N"] = window_peak_force(g, gx, gy)
        print(f"\n{RECORDS[rec][0]}, {gx.n_steps} steps at dt = {DT * 1e3:g} ms")
        print(f"{'run':<14} {'comp':<4} {'u_peak m':>9} {'F_peak/W':>9} {'E kJ':>8} {'u_res mm':>9} "
              f"{'minor/major':>11} {'azimuth':>8}")
        for comp in ("xy", "x", "y"):
            ax = gx
            ay = gy if comp == "xy" else None
            if comp == "y":
                ax, ay = gy, None
            for name in ("rigid", "rigid@Reff", "series", "series@Ri", "series=rigid"):
                if name.startswith("series") and py is None:
                    continue
                t0 = time.perf_counter()
                r = ours(g, ax, ay, sp[name]) if name.startswith("rigid") else theirs(py, g, ax, ay, sp[name])
                if comp == "y":                # the y record ran along x: put it back on y
                    r["ux"], r["uy"], r["Fx"], r["Fy"] = 0 * r["ux"], r["ux"], 0 * r["Fx"], r["Fx"]
                m = metrics(r, g.weight)
                m["runtime_s"] = time.perf_counter() - t0
                table["runs"][f"{rec}/{comp}/{name}"] = m
                print(f"{name:<14} {comp:<4} {m['u_peak_m']:9.4f} {m['F_peak_W']:9.4f} {m['E_J'] / 1e3:8.3f} "
                      f"{1e3 * m['u_res_m']:9.2f} {m['orbit_axes']:11.3f} {m['orbit_azimuth_deg']:8.1f}")
    if not a.no_orbits:
        g, _, _ = load("impvall")
        table["orbits"] = orbit_runs(py, g)
        print(f"\nquasi-static cycles of {ORBIT_A} m, the last of {ORBIT_CYCLES}: E per cycle (J), peak F / W")
        for k, v in table["orbits"].items():
            print(f"  {k:<20} {v['E_J']:10.1f} {v['F_peak_W']:8.4f}")
    if py is not None:
        print("\nrows of docs/model.md 6.10:")
        print("\n".join(markdown(table)))
    if a.write:
        if py is None:
            print(f"not written: {RESULT.name} holds the OpenSees runs too")
            return 1
        if RESULT.exists():           # the runs of other records are kept
            old = json.loads(RESULT.read_text())
            old["runs"].update(table["runs"])
            table = old | {k: v for k, v in table.items() if k != "runs"} | {"runs": old["runs"]}
        RESULT.write_text(json.dumps(table, indent=1, sort_keys=True) + "\n")
        print(f"written {RESULT}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--worker":
        worker(sys.argv[2:])
    else:
        sys.exit(main(sys.argv[1:]))
