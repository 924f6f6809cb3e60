"""Test-only loading helpers until mechanics.ground_motion.read_record lands.

Ground motion from a piecewise-linear acceleration record, integrated exactly:
v by the trapezoid rule at the record points, d by the exact cubic; on the
solver grid the exact piecewise quadratic (v) and cubic (d).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from mechanics.geometry import G_ACC
from mechanics.ground_motion import GroundMotion

RECORDS = Path(__file__).resolve().parents[1] / "scenes" / "records"


def read_at2_legacy(path: Path) -> tuple[float, np.ndarray]:
    """Legacy PEER AT2: 4 header lines (the 4th holds NPTS and DT), values in g."""
    lines = Path(path).read_text().splitlines()
    head = lines[3].replace(",", " ").split()
    npts = int(head[head.index("NPTS=") + 1])
    dt = float(head[head.index("DT=") + 1])
    vals = np.array([float(x) for line in lines[4:] for x in line.split()])
    assert len(vals) == npts, (len(vals), npts)
    return dt, vals * G_ACC


def ground_from_samples(name: str, dt_rec: float, acc: np.ndarray, dt: float,
                        duration: float | None = None, t_start: float = 0.0) -> GroundMotion:
    """GroundMotion on the grid t = t_start + n dt of the piecewise-linear
    acceleration through (k dt_rec, acc[k]); the window is shifted to start at
    rest relative to its own start (d, v measured from t_start)."""
    acc = np.asarray(acc, float)
    n_rec = len(acc)
    t_end_rec = (n_rec - 1) * dt_rec
    # exact integrals at the record points
    da = np.diff(acc)
    v_rec = np.concatenate([[0.0], np.cumsum(dt_rec * (acc[:-1] + 0.5 * da))])
    d_inc = dt_rec * v_rec[:-1] + dt_rec ** 2 * (acc[:-1] / 2.0 + da / 6.0)
    d_rec = np.concatenate([[0.0], np.cumsum(d_inc)])
    if duration is None:
        duration = t_end_rec - t_start
    n_steps = int(math.floor(duration / dt + 1e-9))
    t = t_start + dt * np.arange(n_steps + 1)
    k = np.minimum((t / dt_rec).astype(int), n_rec - 2)
    tau = t - k * dt_rec
    slope = da[k] / dt_rec
    a = acc[k] + slope * tau
    v = v_rec[k] + acc[k] * tau + slope * tau ** 2 / 2.0
    d = d_rec[k] + v_rec[k] * tau + acc[k] * tau ** 2 / 2.0 + slope * tau ** 3 / 6.0
    v -= v[0]
    d -= d[0] + v[0] * 0.0
    d -= (t - t[0]) * 0.0
    a_step = np.diff(v) / dt
    return GroundMotion(name=name, dt=dt, t=t - t[0], d=d, v=v, a=a, a_step=a_step)


def elcentro(dt: float, scale: float = 1.0, duration: float | None = None,
             t_start: float = 0.0) -> GroundMotion:
    dt_rec, acc = read_at2_legacy(RECORDS / "IELC180.AT2")
    return ground_from_samples("elcentro-1940", dt_rec, scale * acc, dt, duration, t_start)


def harmonic(dt: float, amplitude_mps2: float, frequency_hz: float, cycles: float,
             ramp_cycles: float = 0.0) -> GroundMotion:
    """a_g = A sin(w t) (optionally ramped), integrated exactly per step."""
    w = 2.0 * math.pi * frequency_hz
    n_steps = int(round(cycles / frequency_hz / dt))
    t = dt * np.arange(n_steps + 1)
    if ramp_cycles:
        raise NotImplementedError
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
