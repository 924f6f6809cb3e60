"""fe3d plate model: Kronecker structure vs scikit-fem hexahedra, footprint
loads, closed forms (stationary and moving disk), the fe1d limit, ledgers,
orders, save/restore and the field's coordinates."""
import math

import numpy as np
import pytest

from fpd.meshes.box import hex_mesh, symmetric_nodes
from fpd.meshes.line import graded_nodes
from fpd.thermal import exact
from fpd.thermal.fe1d import FE1DPlate, assemble_column
from fpd.thermal.fe3d import FE3DPlate, footprint_loads, line_matrices
from fpd.thermal.params import PlateParams

A, K, RHO, C = 0.01, 16.0, 7850.0, 500.0
KAPPA = K / (RHO * C)
Q = 1.0e6


def halfspace_plate(per, nz, grading, band_x, L, depth, dt, **kw):
    """A box large against the heated region: uniform a/per over |x| <= band_x,
    |y| <= 1.5 a, graded beyond; adiabatic."""
    h = A / per
    x = symmetric_nodes(L, band_x, h)
    y = symmetric_nodes(L, 1.5 * A, h)
    z = graded_nodes(depth, nz, grading)
    args = dict(model="fe3d", plate_radius=1.0, plate_thickness=depth, a_contact_m=A, k=K, rho=RHO, c=C,
                h_conv=0.0, back="adiabatic", step_multiple=1)
    args.update(kw)
    return FE3DPlate(PlateParams(**args), dt, nodes=(x, y, z))


def test_kronecker_matrices_equal_scikit_fem_hexahedra():
    """M and A = K + C built from 1D factors equal scikit-fem's trilinear
    hexahedral assembly on the same grid (convection on every face)."""
    from skfem import Basis, BilinearForm, ElementHex1, FacetBasis, MeshHex
    from skfem.helpers import dot, grad

    x, y, z = np.array([0, 0.1, 0.25, 0.3]), np.array([-0.1, 0.0, 0.05]), np.array([0, 0.01, 0.03, 0.06])
    rc, k, h = 3.9e6, 16.0, 25.0
    mesh = MeshHex.init_tensor(x, y, z)
    basis = Basis(mesh, ElementHex1(), intorder=4)
    M = BilinearForm(lambda u, v, w: rc * u * v).assemble(basis)
    Kc = BilinearForm(lambda u, v, w: k * dot(grad(u), grad(v))).assemble(basis)
    Cb = BilinearForm(lambda u, v, w: h * u * v).assemble(FacetBasis(mesh, ElementHex1(), intorder=4))
    A_sk = (Kc + Cb).toarray()
    (Mx, Kx), (My, Ky), (Mz, Kz) = (line_matrices(v) for v in (x, y, z))
    Ax, Ay, Az = k * Kx, k * Ky, k * Kz
    for Ad in (Ax, Ay, Az):
        Ad[0, 0] += h
        Ad[-1, -1] += h
    Mk = rc * np.kron(np.kron(Mx, My), Mz)
    Ak = np.kron(np.kron(Ax, My), Mz) + np.kron(np.kron(Mx, Ay), Mz) + np.kron(np.kron(Mx, My), Az)
    # our order: node (i, j, k) at (i ny + j) nz + k; skfem's: match by coordinates
    pts, _ = hex_mesh(x, y, z)
    order = [int(np.argmin(np.sum((mesh.p.T - p) ** 2, axis=1))) for p in pts]
    Ms = M.toarray()[np.ix_(order, order)]
    As = A_sk[np.ix_(order, order)]
    assert abs(Ms - Mk).max() < 1e-12 * abs(Ms).max()
    assert abs(As - Ak).max() < 1e-12 * abs(As).max()


def test_footprint_loads_against_brute_force():
    """Loads sum to the covered area (pi a^2 inside, the covered part at an
    edge) and match a fine midpoint quadrature of chi phi_i phi_j."""
    rng = np.random.default_rng(3)
    xn = np.sort(np.concatenate(([-0.05, 0.05], rng.uniform(-0.05, 0.05, 18))))
    yn = np.linspace(-0.04, 0.04, 15)
    a = 0.021
    for cx, cy in ((0.0031, -0.0042), (0.0, 0.0), (0.04, 0.03), (xn[7], yn[3])):
        i0, j0, P = footprint_loads(xn, yn, cx, cy, a)
        n = 1500
        xs = np.linspace(xn[0], xn[-1], n + 1)
        ys = np.linspace(yn[0], yn[-1], n + 1)
        xm, ym = 0.5 * (xs[1:] + xs[:-1]), 0.5 * (ys[1:] + ys[:-1])
        hx = np.array([np.interp(xm, xn, np.eye(len(xn))[i]) for i in range(len(xn))])
        hy = np.array([np.interp(ym, yn, np.eye(len(yn))[j]) for j in range(len(yn))])
        chi = ((xm[:, None] - cx) ** 2 + (ym[None, :] - cy) ** 2 < a * a)
        B = hx @ chi @ hy.T * (xs[1] - xs[0]) * (ys[1] - ys[0])
        full = np.zeros_like(B)
        full[i0:i0 + P.shape[0], j0:j0 + P.shape[1]] = P
        assert abs(full - B).max() < 2e-3 * B.max()
        assert abs(full.sum() - B.sum()) < 2e-3 * B.sum()
        if abs(cx) + a < 0.05 and abs(cy) + a < 0.04:
            assert abs(P.sum() / (math.pi * a * a) - 1) < 1e-13


@pytest.mark.parametrize("t", [0.5, 5.0])
def test_stationary_disk_against_closed_forms(t):
    """Disk source on a thick plate: centre and footprint mean within 0.5 %
    of Carslaw & Jaeger (measured -0.22 % mean, +0.1 % centre at 20 per a)."""
    depth = 6 * math.sqrt(KAPPA * t) + 3 * A
    L = 1.5 * A + 6 * math.sqrt(KAPPA * t)
    plate = halfspace_plate(20, 30, 1.15, 1.5 * A, L, depth, t / 10, radius_m=0.0)
    for _ in range(10):
        T = plate.step(Q * math.pi * A * A, 0.0)
    mean = exact.disk_mean(t, Q, A, K, KAPPA)
    centre = float(exact.disk_centre(t, Q, A, K, KAPPA))
    assert abs((T - 20.0) / mean - 1) < 5e-3
    assert abs((plate.point_temperature() - 20.0) / centre - 1) < 5e-3


def _moving(Pe, per=20, steps=60, travel=3.0, mult=1, nz=30):
    V = 2 * KAPPA * Pe / A
    t = travel * A / V
    dl = math.sqrt(KAPPA * t)
    half = travel * A / 2 + 1.5 * A
    plate = halfspace_plate(per, nz, 1.15, half, half + 6 * dl, 6 * dl + 2 * A, t / steps, step_multiple=mult)
    x0, dt = -travel * A / 2, t / steps
    for i in range(steps):
        T = plate.step(Q * math.pi * A * A, x0 + V * (i + 1) * dt)
    return T - 20.0, t, V, plate


@pytest.mark.parametrize("Pe", [0.1, 1.0, 10.0])
def test_moving_disk_against_jaeger(Pe):
    """A disk switched on and moving at constant speed (Peclet V a / (2 kappa)):
    footprint mean within 1 % of the moving-source solution (Jaeger 1942's
    point source superposed in time; it is the quasi-steady solution once the
    disk has travelled far, test_exact). Measured -0.19 %, -0.15 %, -0.19 %.
    At Pe 10 the quasi-steady state is reached within the 3 radii travelled:
    within 1 % of Jaeger's quasi-steady disk mean too."""
    T, t, V, _ = _moving(Pe)
    ref = exact.moving_disk_transient(t, Q, A, K, KAPPA, V, mean=True)
    assert abs(T / ref - 1) < 1e-2
    if Pe >= 10:
        assert abs(T / exact.moving_disk_mean(Q, A, K, KAPPA, V) - 1) < 1e-2


def test_moving_disk_time_order():
    """Thermal step refined at Pe 10 (the footprint moves 5 % .. 1.25 % of a
    per step): self-convergence of the footprint mean, observed order >= 1.5
    (ETD2 with the footprint linear in time), coarsest error < 0.2 %."""
    vals = [_moving(10.0, per=10, steps=s, nz=20)[0] for s in (60, 120, 240, 960)]
    err = [abs(v - vals[-1]) / vals[-1] for v in vals[:-1]]
    order = math.log(err[0] / err[2]) / math.log(4)
    assert order > 1.5, (err, order)
    assert err[0] < 2e-3


def test_stationary_disk_space_order():
    """Footprint mean against the closed form, lateral element a/5 .. a/20
    (z fixed): the flux jump at the rim makes the field singular there and the
    mean converges at order ~1 (measured 1.0); errors bounded absolutely."""
    t = 0.5
    depth = 6 * math.sqrt(KAPPA * t) + 3 * A
    L = 1.5 * A + 6 * math.sqrt(KAPPA * t)
    mean = exact.disk_mean(t, Q, A, K, KAPPA)
    err = []
    for per in (5, 10, 20):
        plate = halfspace_plate(per, 30, 1.15, 1.5 * A, L, depth, t / 5)
        for _ in range(5):
            T = plate.step(Q * math.pi * A * A, 0.0)
        err.append(abs((T - 20) / mean - 1))
    order = math.log(err[0] / err[2]) / math.log(4)
    assert 0.7 < order < 2.5, (err, order)
    assert err[-1] < 3e-3


@pytest.mark.parametrize("back", ["adiabatic", "fixed"])
def test_uniform_flux_equals_fe1d(back):
    """A footprint covering the whole face, no convection: the 3D field is the
    fe1d column on the same z-mesh, exactly in time (each mode integrated
    exactly; the column's exact solution from its own eigenpairs), and within
    fe1d's BDF2 time error of its stepping."""
    R, H = 0.05, 0.02
    side = math.sqrt(math.pi) * R
    p = PlateParams(model="fe3d", plate_radius=R, plate_thickness=H, a_contact_m=0.8 * side, k=K, rho=RHO,
                    c=C, h_conv=0.0, back=back, T_back_C=20.0, nz=30, n_elements=30, grading=1.1, per_radius=10,
                    step_multiple=1)
    dt, n = 0.05, 40
    plate = FE3DPlate(p, dt)
    q = 2e5
    for _ in range(n):
        T3 = plate.step(q * side * side, 0.003)
    # the column, exactly in time: M u' + A u = q e0 (per unit area)
    (dM, eM), (dK, eK) = assemble_column(plate.z, RHO * C, K, 1.0)
    Mc = np.diag(dM) + np.diag(eM, 1) + np.diag(eM, -1)
    Kc = np.diag(dK) + np.diag(eK, 1) + np.diag(eK, -1)
    f = slice(0, len(dM) - (1 if back == "fixed" else 0))
    from scipy.linalg import eigh
    lam, W = eigh(Kc[f, f], Mc[f, f])
    b = np.zeros(len(lam))
    b[0] = q
    bh = W.T @ b
    t = n * dt
    y = np.where(lam > 1e-12, bh * -np.expm1(-lam * t) / np.where(lam > 1e-12, lam, 1), bh * t)
    u = W @ y
    field = plate.temperature() - 20.0
    assert abs(T3 - 20.0 - u[0]) < 1e-9 * u[0]
    assert np.abs(field[:, :, f] - u[None, None, :]).max() < 1e-9 * u[0]
    col = FE1DPlate(PlateParams(**{**p.__dict__, "model": "fe1d", "a_contact_m": 0.01}), dt / 10)
    for _ in range(10 * n):
        Tc = col.step(q * math.pi * 0.01 ** 2, 0.0)
    assert abs(Tc - T3) < 2e-3 * u[0]


def _ledger_plate(back, mult=3):
    p = PlateParams(model="fe3d", plate_radius=0.1, plate_thickness=0.02, a_contact_m=0.03, h_conv=500.0,
                    back=back, T_back_C=30.0, T0_C=25.0, nz=12, per_radius=10, step_multiple=mult)
    return FE3DPlate(p, 0.01)


@pytest.mark.parametrize("back", ["convection", "fixed", "adiabatic"])
def test_energy_ledger(back):
    """heat_in = stored + lost within 1e-9 (relative) at every step, with the
    footprint moving back and forth over the edge and partial thermal steps;
    for the adiabatic plate the stored heat also equals rho c int (T - T0)
    from the nodal field with scikit-fem's hexahedral mass."""
    plate = _ledger_plate(back)
    half = 0.5 * math.sqrt(math.pi) * 0.1
    for i in range(301):
        c = (half + 0.02) * math.sin(0.05 * i)
        plate.step(2e3 * (1 + math.sin(0.3 * i)) * (i % 50 < 35), (c, 0.3 * c))
        if i % 25 == 0 or i == 300:
            hin, st, lo = plate.heat_in(), plate.stored_heat(), plate.heat_lost()
            assert abs(hin - st - lo) <= 1e-9 * max(abs(hin), 1.0)
    assert plate.heat_in() > 0 and (back == "adiabatic" or abs(plate.heat_lost()) > 1e-3 * plate.heat_in())


def test_stored_heat_from_the_nodal_field():
    """No convection, adiabatic back: rho c int (T - T0) computed from the
    nodal field with scikit-fem's hexahedral mass (independent of the modal
    bookkeeping) equals the heat received, within 1e-9."""
    from skfem import Basis, BilinearForm, ElementHex1, MeshHex

    p = PlateParams(model="fe3d", plate_radius=0.05, plate_thickness=0.01, a_contact_m=0.015, h_conv=0.0,
                    back="adiabatic", T0_C=25.0, nz=6, per_radius=10, step_multiple=3, k=K, rho=RHO, c=C)
    plate = FE3DPlate(p, 0.01)
    for i in range(100):
        plate.step(2e3 * (1 + math.sin(0.3 * i)), (0.04 * math.sin(0.05 * i), 0.01))
    mesh = MeshHex.init_tensor(plate.x, plate.y, plate.z)
    M = BilinearForm(lambda u, v, w: RHO * C * u * v).assemble(Basis(mesh, ElementHex1()))
    T = np.empty(mesh.p.shape[1])
    idx = np.lexsort((mesh.p[2], mesh.p[1], mesh.p[0]))     # skfem nodes in our (x, y, z) order
    T[idx] = plate.temperature().ravel() - 25.0
    stored = float(np.ones(len(T)) @ (M @ T))
    pending = plate._acc[0]                                 # received in the thermal step under way
    assert pending > 0
    assert abs(stored + pending - plate.heat_in()) < 1e-9 * plate.heat_in()


def test_save_restore_exact():
    plate = _ledger_plate("convection", mult=4)
    for i in range(10):
        plate.step(1e3, 0.001 * i)
    snap = plate.save()
    a = [plate.step(1e3 * (1 + 0.1 * i), 0.002 * i) for i in range(13)]
    ea = (plate.heat_in(), plate.stored_heat(), plate.heat_lost())
    plate.restore(snap)
    b = [plate.step(1e3 * (1 + 0.1 * i), 0.002 * i) for i in range(13)]
    assert a == b
    assert ea == (plate.heat_in(), plate.stored_heat(), plate.heat_lost())


def test_field_coordinates_and_hot_track():
    """field(): plate-local coordinates (z = depth >= 0, the sliding face at
    z = 0), VTK hexahedra of positive volume, the hottest node on the face
    under the footprint's last position; a pair centre (x, y) is accepted."""
    plate = _ledger_plate("convection", mult=1)
    for i in range(40):
        plate.step(4e3, (0.01, 0.02))
    pts, cells, T = plate.field()
    (kind, conn), = cells
    assert kind == "hexahedron" and conn.shape[1] == 8 and len(T) == len(pts)
    assert pts[:, 2].min() == 0.0 and pts[:, 2].max() == pytest.approx(0.02)
    e = pts[conn]
    vol = np.einsum("ij,ij->i", e[:, 1] - e[:, 0], np.cross(e[:, 3] - e[:, 0], e[:, 4] - e[:, 0]))
    assert np.all(vol > 0)
    hot = pts[np.argmax(T)]
    assert hot[2] == 0.0 and math.hypot(hot[0] - 0.01, hot[1] - 0.02) < 0.03
    assert plate.peak_temperature() == pytest.approx(T.max(), rel=1e-12)


def test_fe3d_scene_runs_and_is_validated(tmp_path):
    """`fpd run` with fe3d plates: the run closes its ledgers, the hottest-field
    plot is drawn from the sliding face; bad fe3d keys are one line at load."""
    import subprocess
    import sys
    from pathlib import Path

    from fpd.schema import scene as scn

    root = Path(__file__).resolve().parent.parent
    out = tmp_path / "run"
    cmd = [sys.executable, "-m", "fpd", "run", "default", "--out", str(out), "--quiet",
           "--set", 'thermal.model="fe3d"', "--set", "solver.duration=2", "--set", "thermal.per_radius=10",
           "--set", "thermal.nz=8", "--set", "thermal.grading=1.4"]
    env = {**__import__("os").environ, "PYTHONPATH": str(root)}
    assert subprocess.run(cmd, env=env, cwd=tmp_path).returncode == 0
    import json
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "ok" and s["heat_residual_rel"] < 1e-9
    pt = s["heat"]["plates"]["lower"]                       # the fixed material point (radius_m = 0)
    assert pt["point_radius_m"] == 0.0 and 20.0 < pt["point_T_peak_C"] < 200.0
    assert pt["point_T_end_C"] <= pt["point_T_peak_C"]
    assert (out / "plots" / "lower_plate_hottest.png").is_file()
    for key, val in (("thermal.step_multiple", "0"), ("thermal.per_radius", "9"), ("thermal.model", '"fe4d"')):
        with pytest.raises(scn.SceneError, match=key.replace(".", r"\.")):
            scn.load("default", [f"{key}={val}"])


@pytest.mark.parametrize("Pe,travel,steps", [(1.0, 10.0, 200),
                                             pytest.param(0.1, 20.0, 400, marks=pytest.mark.slow)])
def test_moving_disk_reaches_jaeger_quasi_steady(Pe, travel, steps):
    """Travelled far enough for the quasi-steady state (10 radii at Pe 1, 20 at
    Pe 0.1, where the moving-source solution is within 2e-4 / 3e-3 of it): the
    footprint mean within 1 % of Jaeger's quasi-steady disk mean (measured
    -0.19 % and -0.75 %)."""
    T, t, V, _ = _moving(Pe, travel=travel, steps=steps)
    assert abs(T / exact.moving_disk_mean(Q, A, K, KAPPA, V) - 1) < 1e-2


def test_compiled_kernel_matches_numpy():
    """The kernel module runs as numpy (FPD_NO_JIT) and compiled by numba: the
    same source, the same numbers to round-off."""
    pytest.importorskip("numba")
    pa, pb = _ledger_plate("fixed", mult=2), None
    pb = FE3DPlate(pa.params, pa.dt, jit=False)
    assert pb._K.__name__.endswith("_fe3d_kernel")
    for i in range(60):
        c = 0.05 * math.sin(0.07 * i)
        ta, tb = pa.step(3e3, (c, 0.01)), pb.step(3e3, (c, 0.01))
        assert abs(ta - tb) <= 1e-12 * abs(ta)
    assert abs(pa.heat_lost() - pb.heat_lost()) <= 1e-12 * abs(pa.heat_lost())
