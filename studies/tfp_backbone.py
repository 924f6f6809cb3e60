"""The rigid TFP's closed-form quasi-static backbone (docs/model.md 6.3) and
the series model's hexagon: the references the planar TFP's runs are
compared with (the branch forces from statics, the return mapping along a
displacement path, the small-angle backbone, the transition forces, and
the Fenz-Constantinou series model's loop for the comparison). Pure Python
over mechanics/tfp.py's geometry; no stepping."""
from __future__ import annotations

import math

from fpd.mechanics import tfp_kernel as K
from fpd.mechanics.tfp import TFPGeometry


def _statics(geom: TFPGeometry, phi: float, psi: float) -> tuple:
    """What the branch forces and the demands read: the weights W1..W4 the
    surfaces carry, the packed parameters (P1, P2), g, cos and sin of phi and psi."""
    return (*geom.static_weights(), geom.pack(), geom.g, math.cos(phi), math.sin(phi), math.cos(psi), math.sin(psi))


def branch_force(geom: TFPGeometry, mus, phi: float, psi: float, coord: str, s: float) -> float:
    """Quasi-static horizontal force of the rigid model on a branch where
    ``coord`` ('alpha': S2+S3, or 'phi': S1+S4) slides in the direction s,
    the other coordinate held; exact geometry, normal forces from statics
    (N_i = F sin(axis) + W_i cos(axis))."""
    mu1, mu2, mu3, mu4 = mus
    W1, W2, W3, W4, p, g, cf, sf, cp, sp = _statics(geom, phi, psi)
    if coord == "alpha":
        k = mu2 * geom.R2 + mu3 * geom.R3
        num = g * p[K.I_P2] * sp + s * (mu2 * geom.R2 * W2 + mu3 * geom.R3 * W3) * cp
        return num / (geom.Li * cp - s * k * sp)
    k = mu1 * geom.R1 + mu4 * geom.R4
    num = g * (p[K.I_P1] * sf + p[K.I_P2] * sp) + s * (mu1 * geom.R1 * W1 + mu4 * geom.R4 * W4) * cf
    return num / (geom.A * cf + geom.Li * cp - s * k * sf)


def demand(geom: TFPGeometry, mus, phi, psi, F, coord):
    """(generalised force the machine's F puts on ``coord`` minus gravity's, its friction cap)."""
    mu1, mu2, mu3, mu4 = mus
    W1, W2, W3, W4, p, g, cf, sf, cp, sp = _statics(geom, phi, psi)
    if coord == "alpha":
        d = F * geom.Li * cp - g * p[K.I_P2] * sp
        cap = mu2 * geom.R2 * (F * sp + W2 * cp) + mu3 * geom.R3 * (F * sp + W3 * cp)
        return d, cap
    d = F * (geom.A * cf + geom.Li * cp) - g * (p[K.I_P1] * sf + p[K.I_P2] * sp)
    cap = mu1 * geom.R1 * (F * sf + W1 * cf) + mu4 * geom.R4 * (F * sf + W4 * cf)
    return d, cap


def backbone_path(geom: TFPGeometry, mus, u_path, tol=1e-12):
    """The rigid model's quasi-static response along a displacement path
    (return mapping on the closed-form branch forces): returns lists
    (F, phi, alpha, regime) at each u of ``u_path`` (starting seated at rest).
    One coordinate slides at a time, the one whose threshold is reached;
    the branch force is ``branch_force``; the switch points are found by
    bisection on the other coordinate's threshold."""
    pm, am = geom.qmax
    phi = alpha = 0.0
    out_F, out_phi, out_al, out_reg = [], [], [], []
    u_prev = u_path[0]
    for u in u_path:
        du = u - u_prev
        u_prev = u
        s = 1.0 if du > 0 else -1.0
        # try the inner coordinate first: psi from u with phi held
        res = None
        for coord in ("alpha", "phi"):
            if coord == "alpha":
                x = (u - geom.A * math.sin(phi)) / geom.Li
                if abs(x) >= 1:
                    continue
                psi = math.asin(x)
                al = psi - phi
                if abs(al) > am * (1 + 1e-12):
                    continue
                F = branch_force(geom, mus, phi, psi, "alpha", s)
                d, cap = demand(geom, mus, phi, psi, F, "phi")
                if abs(d) <= cap * (1 + 1e-9) or abs(phi) >= pm * (1 - 1e-12) and d * phi > 0:
                    res = (F, phi, al, 5 if abs(phi) >= pm * (1 - 1e-12) else 1)
                    break
            else:
                # phi with alpha held: solve A sin phi + Li sin(phi + alpha) = u (Newton)
                ph = phi
                for _ in range(60):
                    f = geom.A * math.sin(ph) + geom.Li * math.sin(ph + alpha) - u
                    df = geom.A * math.cos(ph) + geom.Li * math.cos(ph + alpha)
                    step = f / df
                    ph -= step
                    if abs(step) < 1e-15:
                        break
                if abs(ph) > pm * (1 + 1e-12):
                    continue
                F = branch_force(geom, mus, ph, ph + alpha, "phi", s)
                res = (F, ph, alpha, 3)
                break
        if res is None:
            # both would pass their thresholds or a rim: take the inner with phi at its rim
            ph = math.copysign(pm, u)
            psi = math.asin(max(-1.0, min(1.0, (u - geom.A * math.sin(ph)) / geom.Li)))
            res = (branch_force(geom, mus, ph, psi, "alpha", s), ph, psi - ph, 5)
        F, phi, alpha, reg = res
        out_F.append(F)
        out_phi.append(phi)
        out_al.append(alpha)
        out_reg.append(reg)
    return out_F, out_phi, out_al, out_reg


def small_angle_backbone(geom: TFPGeometry, mus) -> dict:
    """Small-angle, light-parts closed forms of the rigid model (docs/model.md 6.3)
    and of the Fenz-Constantinou series model (R_eff,i = R_i - h_i), symmetric loop."""
    mu1, mu2, mu3, mu4 = mus
    W = geom.weight
    A, Li = geom.A, geom.Li
    Qi = W * (mu2 * geom.R2 + mu3 * geom.R3)
    Qo = W * (mu1 * geom.R1 + mu4 * geom.R4)
    hp, tl, tu = geom.pad_height, geom.slider_height_lower, geom.slider_height_upper
    Re1, Re4 = geom.R1 - (tl + 0.5 * hp), geom.R4 - (tu + 0.5 * hp)
    Re2, Re3 = geom.R2 - 0.5 * hp, geom.R3 - 0.5 * hp
    return {
        "rigid": {"k_I": W / Li, "k_III": W / (A + Li), "k_V": W / Li,
                  "F0_I": Qi / Li, "F0_III": Qo / (A + Li),
                  "F_I_III": (Qo - Qi) / A},
        "series": {"k_I": W / (Re2 + Re3), "k_III": W / (Re1 + Re4), "k_V": W / (Re2 + Re3),
                   "F0_I": W * (mu2 * Re2 + mu3 * Re3) / (Re2 + Re3),
                   "F_I_III": W * mu1},
    }


def transition_force(geom: TFPGeometry, mus, phi_held: float = 0.0, s: float = 1.0) -> tuple:
    """Force and displacement where the outer surfaces start (regime I -> III)
    on the inner branch with the stack held at ``phi_held``: the root in psi of
    the outer demand minus its cap on F = branch_force(alpha), by bisection."""
    def h(psi):
        F = branch_force(geom, mus, phi_held, psi, "alpha", s)
        d, cap = demand(geom, mus, phi_held, psi, F, "phi")
        return s * d - cap
    lo, hi = phi_held, phi_held + s * (geom.qmax[1])
    if h(lo) * h(hi) > 0:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if h(lo) * h(mid) <= 0:
            hi = mid
        else:
            lo = mid
    psi = 0.5 * (lo + hi)
    F = branch_force(geom, mus, phi_held, psi, "alpha", s)
    return F, geom.A * math.sin(phi_held) + geom.Li * math.sin(psi)


def hexagon_loop(k1: float, k3: float, F0_I: float, b3: float, U: float) -> tuple:
    """Small-angle steady loop of amplitude U reached on the outer branch (no
    rims): outer branches F = k3 u +- b3, inner branches of slope k1 after a
    rigid drop of 2 F0_I at each reversal. Returns (area, vertices)."""
    F_top = k3 * U + b3
    # from (U, F_top - 2 F0_I) along slope k1 down to the lower outer branch F = k3 u - b3
    F1 = F_top - 2.0 * F0_I
    u_x = (F1 - k1 * U + b3) / (k3 - k1)
    V = [(U, F_top), (U, F1), (u_x, k3 * u_x - b3), (-U, -F_top), (-U, -F1), (-u_x, -(k3 * u_x - b3))]
    area = 0.5 * abs(sum(V[i][0] * V[(i + 1) % 6][1] - V[(i + 1) % 6][0] * V[i][1] for i in range(6)))
    return area, V


def compare_with_series(geom: TFPGeometry, mus, U: float) -> dict:
    """Rigid model against Fenz-Constantinou (2008) for a symmetric TFP, small
    angles, amplitude U on the outer branch (docs/model.md 6.4)."""
    bb = small_angle_backbone(geom, mus)
    r, s = bb["rigid"], bb["series"]
    hp = geom.pad_height
    Re1 = geom.R1 - (geom.slider_height_lower + 0.5 * hp)
    Re2 = geom.R2 - 0.5 * hp
    u_star = 2.0 * Re2 * (mus[0] - mus[1])
    b3_series = geom.weight * mus[0] - geom.weight * u_star / (2.0 * Re1)
    a_r, _ = hexagon_loop(r["k_I"], r["k_III"], r["F0_I"], r["F0_III"], U)
    a_s, _ = hexagon_loop(s["k_I"], s["k_III"], s["F0_I"], b3_series, U)
    return {"rigid": dict(r, loop_area=a_r), "series": dict(s, F0_III=b3_series, loop_area=a_s, u_star=u_star)}
