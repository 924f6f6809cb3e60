"""The two-coordinate rigid-rim impact law written once (tribology/rim_law.py
``stop2``: the flat bearing's rims and the planar TFP's), against the
conditions that define it: Newton's impact law as a linear complementarity
problem in the impulses."""
import numpy as np
import pytest

from fpd.tribology import rim_law as rl


def _kinetic(M, v):
    return 0.5 * v @ M @ v


def _lcp(M, v, o, e):
    """The same law solved in the impulses (an independent formulation): with
    W = M^-1, find lambda >= 0 on the coordinates on a rim with the outward
    rate after, o_k (v + W P)_k, P = -o lambda, at most b_k = -e max(o_k v_k,
    0) and equal to it where lambda_k > 0, by trying every active set."""
    W = np.linalg.inv(M)
    on = [k for k in range(2) if o[k] != 0.0]
    b = -e * np.maximum(o * v, 0.0)
    for size in range(len(on) + 1):
        for active in ([()] if size == 0 else [(k,) for k in on] if size == 1 else [tuple(on)]):
            lam = np.zeros(2)
            if active:
                idx = list(active)
                A = np.array([[o[j] * W[j, k] * o[k] for k in idx] for j in idx])
                lam[idx] = np.linalg.solve(A, [o[j] * v[j] - b[j] for j in idx])
            w = v - W @ (o * lam)
            if np.all(lam >= -1e-12) and all(o[k] * w[k] <= b[k] + 1e-12 for k in on):
                return w
    raise AssertionError("no active set solves the problem")


@pytest.mark.parametrize("e", [0.0, 0.4, 1.0])
def test_stop2_solves_newtons_impact_law(e):
    """Random positive definite metrics, rates and rim sides: after the
    impact every coordinate on a rim leaves it at least at e times its rate
    into it (and not into it when it was not moving into it); impulses (M
    dv) act only on coordinates on a rim, push away from it (>= 0) and are
    zero where the coordinate leaves faster than that (complementarity);
    a free coordinate keeps its momentum; the rates equal those of the same
    law solved in the impulses (``_lcp``) to 1e-9; the returned loss is the
    kinetic energy's change (>= 0 inelastic, 0 at e = 1 for a single rim),
    to 1e-12."""
    rng = np.random.default_rng(7)
    cases = 0
    for _ in range(4000):
        A = rng.normal(size=(2, 2))
        M = A @ A.T + 0.05 * np.eye(2)
        v = rng.normal(size=2)
        o = rng.choice([-1.0, 0.0, 1.0], size=2)
        w = np.zeros(2)
        loss = rl.stop2(M[0, 0], M[0, 1], M[1, 1], v[0], v[1], o[0], o[1], e, w)
        dv = w - v
        P = M @ dv                                   # the impulses, generalised
        scale = np.abs(M).max() * (np.abs(v).max() + 1e-300)
        target = -e * np.maximum(o * v, 0.0)         # the outward rate allowed after, at most
        for k in range(2):
            if o[k] == 0.0:
                assert abs(P[k]) <= 1e-12 * scale    # no impulse off the rims
                continue
            lam = -o[k] * P[k]
            assert lam >= -1e-12 * scale             # pushes away from its rim
            assert o[k] * w[k] <= target[k] + 1e-12 * np.abs(v).max()
            if lam > 1e-10 * scale:                  # an active contact: the law holds with equality
                assert o[k] * w[k] == pytest.approx(target[k], abs=1e-11 * np.abs(v).max())
                cases += 1
        np.testing.assert_allclose(w, _lcp(M, v, o, e), rtol=0, atol=1e-9 * np.abs(v).max())
        K0, K1 = _kinetic(M, v), _kinetic(M, w)
        assert loss == pytest.approx(K0 - K1, abs=1e-12 * max(K0, 1e-300))
        if e == 0.0:
            # (with e > 0 and both rims struck, Newton's law may hand energy back: the
            # known limit of kinematic restitution at simultaneous impacts)
            assert loss >= -1e-12 * K0
            assert loss == pytest.approx(0.5 * dv @ M @ dv, abs=1e-12 * max(K0, 1e-300))
        if e == 1.0 and np.count_nonzero(P * o) <= 1:
            assert abs(loss) <= 1e-12 * K0           # a single elastic stop keeps the energy
    assert cases > 1000


def test_stop2_stops_exactly_and_matches_the_single_rim_closed_form():
    """One coordinate into its rim, the other free: it leaves at exactly -e
    times its rate (0.0 inelastic, no round-off residue), the other keeps its
    momentum, and the loss is (1 - e^2) times the kinetic energy of the rate
    normal to the rim, (1/2) v1^2 / (M^-1)_11."""
    M = np.array([[3.0, 1.2], [1.2, 2.0]])
    v = np.array([0.7, -0.3])
    for e in (0.0, 0.5):
        w = np.zeros(2)
        loss = rl.stop2(M[0, 0], M[0, 1], M[1, 1], v[0], v[1], 1.0, 0.0, e, w)
        assert w[0] == -e * v[0]
        assert M[1] @ w == pytest.approx(M[1] @ v, rel=1e-15)
        normal = 0.5 * v[0] ** 2 / np.linalg.inv(M)[0, 0]
        assert loss == pytest.approx((1.0 - e * e) * normal, rel=1e-13)
