"""Optional numba kernels of the axisym plate on a tensor mesh (issue 7).

Imported only by thermal/axisym.py, and only when numba is installed and
the environment variable FPD_NO_JIT is not set (thermal.fe1d.jit_kernels
decides for both). Each kernel is the pure numpy path of thermal/axisym.py
written as one loop, with the same scalar arithmetic in the same order:

- ``pattern``: TopLoad.pattern on a top face whose facets are sorted along r
  (searchsorted ranges, the covered prefix, the band pieces with the graded
  split, numpy's pairwise sum over each piece's Gauss points, bincount's
  accumulation order);
- ``modal_bdf2``, ``modal_be``: the elementwise updates of
  ModalIntegrator._bdf2 and _be/_cn (the dot products of the ledger stay in
  numpy, whose BLAS the kernels would not share).

The numbers are bit-for-bit those of the pure path (tests/test_axisym.py);
what the kernels save is numpy's per-call overhead on arrays of a few
hundred (the footprint band) to ~10^4 (the section) values.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def _pairwise(a, n):
    """numpy's pairwise summation (loops_utils.h) of a[0:n], n <= 128: the
    order of np.sum over a contiguous row."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[i]
        return res
    r0, r1, r2, r3 = a[0], a[1], a[2], a[3]
    r4, r5, r6, r7 = a[4], a[5], a[6], a[7]
    i = 8
    while i < n - (n % 8):
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[i]
        i += 1
    return res


@njit(cache=True, nogil=True)
def _psi(q, lo_b, hi_b):
    return 2 * math.atan2(math.sqrt(max((hi_b - q) * (hi_b + q), 0.0)),
                          math.sqrt(max((q - lo_b) * (q + lo_b), 0.0)))


@njit(cache=True, nogil=True)
def pattern(c, a, r0, r1, fn0, fn1, full0, full1, inv_L, X, wh, cut_steps, loads):
    """TopLoad.pattern(c, a) into loads (len n_nodes), facets sorted along r."""
    n = loads.shape[0]
    ng = X.shape[0]
    two_pi = 2 * np.pi
    for i in range(n):
        loads[i] = 0.0
    centred = c <= 1e-12 * a
    if centred:
        lo_b = a
        hi_b = a
        full_below = a
    else:
        lo_b = abs(c - a)
        hi_b = c + a
        full_below = lo_b if c < a else 0.0
    i0 = np.searchsorted(r1, lo_b, side="right")
    i1 = max(i0, np.searchsorted(r0, hi_b, side="left"))
    if full_below > 0.0:
        nfull = np.searchsorted(r1, full_below, side="right")
        if nfull > 0:
            t0 = np.zeros(n)
            t1 = np.zeros(n)
            for k in range(nfull):
                t0[fn0[k]] += full0[k]
            for k in range(nfull):
                t1[fn1[k]] += full1[k]
            for i in range(n):
                loads[i] = (loads[i] + t0[i]) + t1[i]
    m = i1 - i0
    if m == 0:
        return
    # pieces: (facet, s0 or q1, s1 or q0, kind) with kind 0 = covered in r, 1 = band in psi
    cuts_n = 0
    part = np.empty(cut_steps.shape[0] + 2)
    split = hi_b > lo_b and lo_b < a
    if split:
        w = max(math.sqrt(lo_b / a), 1e-8)
        for k in range(cut_steps.shape[0]):
            if w * cut_steps[k] < math.pi:
                cuts_n += 1
        part[0] = 0.0
        for k in range(cuts_n):
            part[1 + k] = math.pi - w * cut_steps[cuts_n - 1 - k]
        part[cuts_n + 1] = math.pi
    n_part = cuts_n + 1
    cap = m * (n_part + 1)
    pf = np.empty(cap, dtype=np.int64)
    p_hi = np.empty(cap)
    p_lo = np.empty(cap)
    p_kind = np.empty(cap, dtype=np.int64)
    npc = 0
    if centred or c < a:
        for e in range(i0, i1):
            p1 = min(r1[e], lo_b)
            if p1 > r0[e]:
                pf[npc] = e
                p_hi[npc] = p1
                p_lo[npc] = r0[e]
                p_kind[npc] = 0
                npc += 1
    if hi_b > lo_b:
        for e in range(i0, i1):
            s0 = _psi(max(r0[e], lo_b), lo_b, hi_b)
            s1 = _psi(min(r1[e], hi_b), lo_b, hi_b)
            if split:
                for p in range(n_part):
                    lo = max(s1, part[p])
                    hi = min(s0, part[p + 1])
                    if hi > lo:
                        pf[npc] = e
                        p_hi[npc] = hi
                        p_lo[npc] = lo
                        p_kind[npc] = 1
                        npc += 1
            else:
                pf[npc] = e
                p_hi[npc] = s0
                p_lo[npc] = s1
                p_kind[npc] = 1
                npc += 1
    if npc == 0:
        return
    g = np.empty(ng)
    gr = np.empty(ng)
    gs = np.empty(npc)
    gx = np.empty(npc)
    k_ac = 4 * a * c
    k_2a = 2 * a
    k_2ac = 2 * a * c
    amc2 = (a - c) * (a - c)
    cma = c - a
    for k in range(npc):
        e = pf[k]
        hi = p_hi[k]
        lo = p_lo[k]
        d = hi - lo
        if p_kind[k] == 0:
            for j in range(ng):
                r = lo + d * X[j]
                g[j] = two_pi * r * d * wh[j]
                gr[j] = g[j] * (r - r0[e])
        else:
            for j in range(ng):
                s = lo + d * X[j]
                half_cos = math.cos(0.5 * s)
                hc2 = half_cos * half_cos
                sin_s = math.sin(s)
                r = math.sqrt(amc2 + k_ac * hc2)
                f_band = math.atan2(a * sin_s, cma + k_2a * hc2)
                g[j] = f_band * (k_2ac * sin_s * d * wh[j])
                gr[j] = g[j] * (r - r0[e])
        gx[k] = _pairwise(gr, ng) * inv_L[e]
        gs[k] = _pairwise(g, ng) - gx[k]
    t0 = np.zeros(n)
    t1 = np.zeros(n)
    for k in range(npc):
        t0[fn0[pf[k]]] += gs[k]
    for k in range(npc):
        t1[fn1[pf[k]]] += gx[k]
    for i in range(n):
        loads[i] += t0[i]
    for i in range(n):
        loads[i] += t1[i]


@njit(cache=True, nogil=True)
def modal_bdf2(lam, fD, b, bprev, inv, y, dprev, c23h, rc3):
    """ModalIntegrator._bdf2's update of the free dofs, in place: y += du,
    dprev = du, du = (rc3 dprev + c23h (G - lam y - fD)) inv,
    G = 1.5 b - 0.5 bprev (fD empty: no Dirichlet dofs)."""
    has_fd = fD.shape[0] > 0
    for k in range(y.shape[0]):
        au = lam[k] * y[k]
        if has_fd:
            au = au + fD[k]
        g = 1.5 * b[k]
        g = g - 0.5 * bprev[k]
        g = g - au
        g = g * c23h
        d = dprev[k] * rc3
        d = d + g
        d = d * inv[k]
        y[k] = y[k] + d
        dprev[k] = d


@njit(cache=True, nogil=True)
def modal_be(lam, fD, b, inv, y, du, h):
    """ModalIntegrator._be / _cn's update of the free dofs, in place:
    du = h (b - lam y - fD) inv, y += du (inv for gamma = h or h/2)."""
    has_fd = fD.shape[0] > 0
    for k in range(y.shape[0]):
        au = lam[k] * y[k]
        if has_fd:
            au = au + fD[k]
        d = b[k] - au
        d = d * h
        d = d * inv[k]
        y[k] = y[k] + d
        du[k] = d


def warm_up() -> None:
    """Load (or compile) the kernels now, at build time, not in the loop."""
    r = np.linspace(0.0, 1.0, 5)
    fn0 = np.arange(4)
    loads = np.zeros(5)
    X = np.array([0.25, 0.75])
    one = np.ones(4)
    pattern(0.3, 0.4, r[:-1].copy(), r[1:].copy(), fn0, fn0 + 1, one, one, one, X, X,
            4.0 ** np.arange(3), loads)
    v = np.ones(3)
    modal_bdf2(v, np.zeros(0), v, v, v, v.copy(), v.copy(), 1.0, 1.0)
    modal_be(v, np.zeros(0), v, v, v.copy(), v.copy(), 1.0)
