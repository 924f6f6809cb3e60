"""The paper's lumped plate, Eq. (9)-(10), against its closed form."""
import math

import numpy as np
import pytest

from fpd.thermal.lumped import LumpedPlate
from fpd.thermal.params import PlateParams


def test_constant_power_matches_the_exponential():
    p = PlateParams(model="lumped", T0_C=20.0, T_air_C=20.0, h_conv=25.0)
    plate = LumpedPlate(p, dt=1e-2)
    P = 5.0e3
    C = p.c * p.mass
    H = p.h_conv * math.pi * p.plate_radius ** 2
    for n in range(1, 200001):
        T = plate.step(P, 0.0)
        if n % 20000 == 0:
            t = n * 1e-2
            exact = 20.0 + P / H * (1 - math.exp(-H * t / C))
            assert (T - 20.0) == pytest.approx(exact - 20.0, rel=1e-9)
    assert plate.heat_in() == pytest.approx(plate.stored_heat() + plate.heat_lost(), rel=1e-12)


def test_cooling_from_a_hot_start_and_piecewise_power():
    p = PlateParams(model="lumped", T0_C=80.0, T_air_C=15.0, h_conv=10.0, exchange_area_m2=0.3)
    dt = 0.05
    plate = LumpedPlate(p, dt)
    C, H = p.c * p.mass, 10.0 * 0.3
    T = 80.0
    rng = np.random.default_rng(1)
    for P in rng.uniform(0, 2e4, 500):
        Teq = 15.0 + P / H
        T = Teq + (T - Teq) * math.exp(-H * dt / C)
        assert plate.step(P, 0.0) == pytest.approx(T, rel=1e-12)
    assert plate.heat_in() == pytest.approx(plate.stored_heat() + plate.heat_lost(), rel=1e-12)


def test_adiabatic_plate_stores_everything():
    p = PlateParams(model="lumped", h_conv=0.0)
    plate = LumpedPlate(p, 1e-3)
    for _ in range(1000):
        plate.step(1e3, 0.0)
    assert plate.stored_heat() == pytest.approx(1e3, rel=1e-12)
    assert plate.surface_temperature() - 20.0 == pytest.approx(1e3 / (p.c * p.mass), rel=1e-12)


def test_save_restore_is_exact():
    plate = LumpedPlate(PlateParams(), 1e-3)
    plate.step(1e4, 0.0)
    snap = plate.save()
    a = plate.step(3e4, 0.0)
    plate.restore(snap)
    assert plate.step(3e4, 0.0) == a
