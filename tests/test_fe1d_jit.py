"""The fe1d column kernel (thermal/column_kernel.py) compiled gives the pure
run's numbers bit for bit (the one source; its two primitive backends call
the same BLAS/LAPACK routines), through start-ups, load jumps,
save/restore, every scheme and back face, and numpy's products beyond
the rows numpy's whole-array band product once started at (350 here)."""
import dataclasses

import numpy as np
import pytest

from fpd import kernels
from fpd.thermal import fe1d
from fpd.thermal.params import PlateParams

pytestmark = pytest.mark.skipif(not kernels.available(), reason="numba not installed (or FPD_NO_JIT)")


def loads(n=3000):
    t = np.arange(n) * 1e-3
    q = 2e3 * np.abs(np.sin(2 * np.pi * 0.7 * t)) * (np.sin(2 * np.pi * 0.13 * t) > -0.3)
    q[1000:1010] = 0.0                       # a stick: two jumps
    return q


@pytest.mark.parametrize("back,scheme,n_el", [("convection", "bdf2", 100), ("adiabatic", "bdf2", 40),
                                             ("fixed", "bdf2", 100), ("convection", "cn", 100),
                                             ("convection", "bdf2", 350), ("fixed", "be", 30),
                                             ("fixed", "cn", 320)])
def test_jit_matches_pure_bit_for_bit(back, scheme, n_el):
    p = dataclasses.replace(PlateParams(model="fe1d"), back=back, scheme=scheme, n_elements=n_el,
                            h_conv=50.0, plate_thickness=0.05, grading=1.05 if n_el < 300 else 1.01)
    a, b = fe1d.FE1DPlate(p, 1e-3, jit=False), fe1d.FE1DPlate(p, 1e-3, jit=True)
    snap = None
    for i, q in enumerate(loads()):
        if i == 2000:
            snap = (a.save(), b.save())
        Ta, Tb = a.step(q, 0.0), b.step(q, 0.0)
        assert Ta == Tb, i
        assert a.stored_heat() == b.stored_heat() and a.heat_lost() == b.heat_lost(), i
    a.restore(snap[0])
    b.restore(snap[1])
    assert a.stored_heat() == b.stored_heat()
    for q in loads()[:500]:
        assert a.step(q, 0.0) == b.step(q, 0.0)
    np.testing.assert_array_equal(a.temperature(), b.temperature())
    assert a.heat_in() == b.heat_in()


def test_kernel_used_on_the_default_column():
    p = PlateParams(model="fe1d")
    assert fe1d.FE1DPlate(p, 1e-3).integ.compiled
    assert not fe1d.FE1DPlate(p, 1e-3, jit=False).integ.compiled


def test_pure_path_reproduces_the_fingerprints(monkeypatch):
    from tests.test_speed_equivalence import DATA, assert_same
    from tests.speed_cases import fingerprint, run_case
    monkeypatch.setenv("FPD_NO_JIT", "1")
    ref = np.load(DATA)
    data, _, _ = fingerprint(run_case("default"))
    assert_same(data, ref["default/data"])


def test_a_plate_survives_pickling():
    """The column holds its kernel module (not picklable): it is found again
    on unpickling, and the copy steps on exactly as the original."""
    import pickle
    for jit in (False, True):
        a = fe1d.FE1DPlate(PlateParams(model="fe1d"), 1e-3, jit=jit)
        for q in loads(300):
            a.step(q, 0.0)
        b = pickle.loads(pickle.dumps(a))
        assert b.integ.compiled == jit and b.integ.u is b.integ.V[0]
        for q in loads(600)[300:]:
            assert a.step(q, 0.0) == b.step(q, 0.0)
        assert a.stored_heat() == b.stored_heat() and a.heat_lost() == b.heat_lost()
