"""Loadings of the two-phase tests: El Centro (windows too), an acceleration
harmonic and a half-sine pulse, each integrated exactly on the solver grid."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from fpd.mechanics.geometry import G_ACC
from fpd.loading.ground_motion import GroundMotion, ground_motion_from_samples, read_record

RECORDS = Path(__file__).resolve().parents[1] / "scenes" / "records"


def elcentro(dt: float, scale: float = 1.0, duration: float | None = None,
             t_start: float = 0.0) -> GroundMotion:
    """El Centro 1940 (IELC180) through the project's reader and integrator
    (loading.ground_motion: exact piecewise-linear integration, baseline
    correction); ``t_start`` cuts a window that starts at rest."""
    rec = read_record(RECORDS / "IELC180.AT2")
    k0 = int(round(t_start / rec.dt))
    t_rec = rec.t[k0:] - rec.t[k0]
    return ground_motion_from_samples("elcentro-1940", t_rec, rec.a_g[k0:] * G_ACC * scale,
                                      dt, duration)


def harmonic(dt: float, amplitude_mps2: float, frequency_hz: float, cycles: float) -> GroundMotion:
    """a_g = A sin(w t), integrated exactly per step."""
    w = 2.0 * math.pi * frequency_hz
    n_steps = int(round(cycles / frequency_hz / dt))
    t = dt * np.arange(n_steps + 1)
    a = amplitude_mps2 * np.sin(w * t)
    v = amplitude_mps2 / w * (1.0 - np.cos(w * t))
    d = amplitude_mps2 / w * (t - np.sin(w * t) / w)
    return GroundMotion(name="harmonic", dt=dt, t=t, d=d, v=v, a=a, a_step=np.diff(v) / dt)


def pulse(dt: float, amplitude_mps2: float, width_s: float, duration_s: float) -> GroundMotion:
    """One half-sine acceleration pulse of the given width, then rest."""
    n_steps = int(round(duration_s / dt))
    t = dt * np.arange(n_steps + 1)
    w = math.pi / width_s
    inside = t < width_s
    a = np.where(inside, amplitude_mps2 * np.sin(w * t), 0.0)
    v_end = 2.0 * amplitude_mps2 / w
    v = np.where(inside, amplitude_mps2 / w * (1.0 - np.cos(w * t)), v_end)
    d_end = amplitude_mps2 / w * width_s
    d = np.where(inside, amplitude_mps2 / w * (t - np.sin(w * t) / w), d_end + v_end * (t - width_s))
    return GroundMotion(name="pulse", dt=dt, t=t, d=d, v=v, a=a, a_step=np.diff(v) / dt)
