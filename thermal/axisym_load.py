"""The footprint load of the axisym plate (thermal/axisym.py): a disk of
radius a centred at distance c = |centre| from the axis, averaged around the
axis into a ring, f(r) = arccos((r^2 + c^2 - a^2)/(2 r c))/pi where the
circle of radius r is partly covered, 1 or 0 elsewhere. TopLoad turns it
into nodal loads on the top face: a precomputed quadrature operator for the
facets the footprint covers fully or not at all, the partly covered facets
split at the breakpoints and integrated in the angle around the footprint
centre (round-off accurate; docs/thermal.md)."""
from __future__ import annotations

import math

import numpy as np

NG_FACET = 8          # Gauss points per top facet in the fixed operator
NG_PIECE = 20         # Gauss points per piece of a partly covered facet
_GL_FACET = np.polynomial.legendre.leggauss(NG_FACET)
_GL_PIECE = np.polynomial.legendre.leggauss(NG_PIECE)


def covered_fraction(r, c: float, a: float):
    """Share of the circle of radius r covered by the disk (c, a)."""
    r = np.asarray(r, dtype=float)
    if c <= 1e-12 * a:
        return (r <= a).astype(float)
    x = (r * r + c * c - a * a) / (2.0 * np.maximum(r, 1e-300) * c)
    return np.arccos(np.clip(x, -1.0, 1.0)) / math.pi


class TopLoad:
    """Footprint load on the top face: whole facets where f is 0 or 1 from
    precomputed facet loads, the partly covered facets (the band) integrated
    apart. Nodes are local top-node indices."""

    def __init__(self, r_nodes: np.ndarray, facet_nodes: np.ndarray):
        ra, rb = r_nodes[facet_nodes[:, 0]], r_nodes[facet_nodes[:, 1]]
        swap = ra > rb
        facet_nodes = np.where(swap[:, None], facet_nodes[:, ::-1], facet_nodes)
        order = np.argsort(np.minimum(ra, rb))
        self.fn = facet_nodes[order]
        self.fn0, self.fn1 = self.fn[:, 0].copy(), self.fn[:, 1].copy()
        self.r0 = r_nodes[self.fn0]
        self.r1 = r_nodes[self.fn1]
        self.n_nodes = len(r_nodes)
        x, w = _GL_FACET
        xi = 0.5 * (x + 1.0)                       # on [0, 1]
        L = (self.r1 - self.r0)[:, None]
        r_qp = self.r0[:, None] + L * xi           # (n_facets, NG)
        wr = 2 * np.pi * r_qp * L * 0.5 * w        # 2 pi r dr weights
        # int phi_i 2 pi r dr over each whole facet, to its first and second node
        # (Gauss-Legendre, exact for this cubic): the load of a covered facet
        self.full0 = np.sum(wr * (1 - xi), axis=1)
        self.full1 = np.sum(wr * xi, axis=1)
        self.L = self.r1 - self.r0
        self.inv_L = 1.0 / self.L
        # facets in order along r without overlaps (any line mesh of the top face):
        # the covered facets are a prefix, the band a contiguous range
        self._sorted = bool(np.all(self.r1[:-1] <= self.r0[1:]))
        x, w = _GL_PIECE
        self._X = 0.5 * (x + 1.0)
        self._w_half = 0.5 * w
        self._cut_steps = 4.0 ** np.arange(40)

    def _range(self, lo: float, hi: float, strict_lo: bool) -> np.ndarray:
        """Facets with r1 > lo (r1 >= lo when not strict_lo... see callers) and r0 < hi."""
        if self._sorted:
            i0 = np.searchsorted(self.r1, lo, side="right" if strict_lo else "left")
            i1 = np.searchsorted(self.r0, hi, side="left")
            return np.arange(i0, max(i0, i1))
        sel = (self.r1 > lo) if strict_lo else (self.r1 >= lo)
        return np.flatnonzero(sel & (self.r0 < hi))

    def _band_loads(self, idx: np.ndarray, c: float, a: float, loads: np.ndarray) -> None:
        """Add the nodal loads of the facets idx that the footprint partly
        covers, each split at the breakpoints lo_b = |c - a|, hi_b = c + a.
        Below lo_b f is 1 (c < a, or the centred step r <= a) or 0, above
        hi_b it is 0: constant, Gauss-Legendre in r is exact there (and the
        zero pieces are left out). Inside the band the piece is integrated
        in the angle psi around the footprint centre,
        r^2 = c^2 + a^2 + 2 a c cos(psi): dr/dpsi vanishes at both
        breakpoints, which removes the square-root behaviour of f there, so
        Gauss-Legendre converges to round-off. All pieces in one batch."""
        r0, r1 = self.r0[idx], self.r1[idx]
        X, wh = self._X, self._w_half
        centred = c <= 1e-12 * a
        if centred:                 # f is the step r <= a
            lo_b = hi_b = a
        else:
            lo_b, hi_b = abs(c - a), c + a
        fis, rs, gs = [], [], []
        if centred or c < a:
            # the covered piece [r0, min(r1, lo_b)] (f = 1)
            p1 = np.minimum(r1, lo_b)
            keep = p1 > r0
            if keep.any():
                q0, q1 = r0[keep, None], p1[keep, None]
                r = q0 + (q1 - q0) * X
                fis.append(idx[keep])
                rs.append(r)
                gs.append(2 * np.pi * r * (q1 - q0) * wh)
        if hi_b > lo_b:
            q0 = np.maximum(r0, lo_b)
            q1 = np.minimum(r1, hi_b)
            # psi(r) = 2 atan(sqrt((hi_b^2 - r^2) / (r^2 - lo_b^2))), written without
            # the cancellation of arccos near the breakpoints (c ~ a puts lo_b ~ 0);
            # both ends of every piece in one call
            q = np.concatenate((q0, q1))
            psi = 2 * np.arctan2(np.sqrt(np.maximum((hi_b - q) * (hi_b + q), 0.0)),
                                 np.sqrt(np.maximum((q - lo_b) * (q + lo_b), 0.0)))
            m = len(idx)
            s0, s1 = psi[:m], psi[m:]              # s0 >= s1
            fi = idx
            if lo_b < a:
                # axis close to the footprint's rim (c ~ a): f has a feature of
                # width sqrt(lo_b / a) near psi = pi; split geometrically toward it
                s0, s1, fi = self._graded_split(s0, s1, idx, lo_b / a)
            else:
                s0, s1 = s0[:, None], s1[:, None]
            s = s1 + (s0 - s1) * X
            half_cos = np.cos(0.5 * s)
            hc2 = half_cos * half_cos
            sin_s = np.sin(s)
            r = np.sqrt((a - c) * (a - c) + (4 * a * c) * hc2)
            # f = (polar angle of the footprint's rim point seen from the axis) / pi,
            # and 2 pi r dr = 2 pi a c sin(psi) dpsi
            f_band = np.arctan2(a * sin_s, (c - a) + (2 * a) * hc2)
            fis.append(fi)
            rs.append(r)
            gs.append(f_band * ((2 * a * c) * sin_s * (s0 - s1) * wh))
        if not fis:
            return
        if len(fis) > 1:
            fi, r, g = np.concatenate(fis), np.concatenate(rs), np.concatenate(gs)
        else:
            fi, r, g = fis[0], rs[0], gs[0]
        gx = np.sum(g * (r - self.r0[fi][:, None]), axis=1) * self.inv_L[fi]
        n = self.n_nodes
        loads += np.bincount(self.fn0[fi], np.sum(g, axis=1) - gx, n)
        loads += np.bincount(self.fn1[fi], gx, n)

    def _graded_split(self, s0, s1, idx, ratio):
        """Cut the psi intervals [s1, s0] at pi - w 4^k, w = sqrt(ratio)
        (vectorised: every interval against the global partition)."""
        w = max(math.sqrt(ratio), 1e-8)
        cuts = w * self._cut_steps
        cuts = cuts[cuts < math.pi]
        part = np.concatenate(([0.0], math.pi - cuts[::-1], [math.pi]))
        lo = np.maximum(s1[:, None], part[None, :-1])
        hi = np.minimum(s0[:, None], part[None, 1:])
        keep = hi > lo
        fi = np.broadcast_to(idx[:, None], keep.shape)[keep]
        return hi[keep][:, None], lo[keep][:, None], fi

    def pattern(self, c: float, a: float) -> np.ndarray:
        """Nodal loads (W per unit flux, on top nodes) of the ring-averaged
        footprint: int f(r) phi_i 2 pi r dr. Facets fully covered add their
        precomputed loads (f = 1 there; uncovered ones nothing), the partly
        covered ones come from _band_loads."""
        loads = np.zeros(self.n_nodes)
        if c <= 1e-12 * a:
            full_below, band = a, self._range(a, a, strict_lo=True)    # r0 < a < r1
        else:
            lo_b, hi_b = abs(c - a), c + a
            full_below = lo_b if c < a else 0.0
            band = self._range(lo_b, hi_b, strict_lo=True)             # r1 > lo_b, r0 < hi_b
        if full_below > 0.0:
            full = np.flatnonzero(self.r1 <= full_below) if not self._sorted else \
                np.arange(np.searchsorted(self.r1, full_below, side="right"))
            if len(full):
                loads += np.bincount(self.fn0[full], self.full0[full], self.n_nodes)
                loads += np.bincount(self.fn1[full], self.full1[full], self.n_nodes)
        if len(band):
            self._band_loads(band, c, a, loads)
        return loads
