"""Test-machine orbits in the plane (bidirectional bearing tests): the
prescribed relative displacement u(t) = (ux, uy) with its exact rates.

- ``sine``: u = A sin(w t) (cos d, sin d), d = direction_deg;
- ``circle``: u = A (cos(w t), sin(w t)), a circular orbit of radius A at
  constant speed, starting at (A, 0) (the machine places the bearing there
  and launches it: that energy is input at t = 0);
- ``figure-eight``: u = A (sin(w t), sin(2 w t) / 2), through the centre.
- ``triangle``: a triangle wave of amplitude A along (cos d, sin d)
  (constant speed 4 A f, from 0 towards +A): a straight orbit.

After ``cycles`` cycles the machine holds the last position (u' = u'' = 0).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

WAVEFORMS = ("sine", "circle", "figure-eight", "triangle")


@dataclass
class OrbitProgramme:
    name: str
    dt: float
    t: np.ndarray
    u: np.ndarray       # (n+1, 2)
    ud: np.ndarray
    udd: np.ndarray

    @property
    def n_steps(self) -> int:
        return len(self.t) - 1


def orbit_programme(waveform: str, amplitude_m: float, frequency_Hz: float, cycles: float, dt: float,
                    duration: float | None = None, direction_deg: float = 0.0) -> OrbitProgramme:
    if waveform not in WAVEFORMS:
        raise ValueError(f"waveform {waveform!r}: one of {WAVEFORMS}")
    w = 2.0 * math.pi * frequency_Hz
    t_end = cycles / frequency_Hz
    n = max(1, int(round((t_end if duration is None else duration) / dt)))
    t = np.arange(n + 1) * dt
    tt = np.minimum(t, t_end)
    on = (t <= t_end + 1e-12).astype(float)
    A = amplitude_m
    s, c = np.sin(w * tt), np.cos(w * tt)
    if waveform == "sine":
        d = math.radians(direction_deg)
        e = np.array([math.cos(d), math.sin(d)])
        u = np.outer(A * s, e)
        ud = np.outer(on * A * w * c, e)
        udd = np.outer(-on * A * w * w * s, e)
    elif waveform == "triangle":
        d = math.radians(direction_deg)
        e = np.array([math.cos(d), math.sin(d)])
        p = np.mod(tt * frequency_Hz, 1.0)
        tri = np.where(p < 0.25, 4.0 * p, np.where(p < 0.75, 2.0 - 4.0 * p, 4.0 * p - 4.0))
        slope = np.where((p < 0.25) | (p >= 0.75), 1.0, -1.0) * 4.0 * frequency_Hz
        u = np.outer(A * tri, e)
        ud = np.outer(on * A * slope, e)
        udd = np.zeros_like(u)
    elif waveform == "circle":
        u = A * np.column_stack([c, s])
        ud = on[:, None] * A * w * np.column_stack([-s, c])
        udd = on[:, None] * -A * w * w * np.column_stack([c, s])
    else:
        s2, c2 = np.sin(2 * w * tt), np.cos(2 * w * tt)
        u = A * np.column_stack([s, 0.5 * s2])
        ud = on[:, None] * A * w * np.column_stack([c, c2])
        udd = on[:, None] * -A * w * w * np.column_stack([s, 2.0 * s2])
    name = f"{waveform} {A:g} m {frequency_Hz:g} Hz x {cycles:g}"
    return OrbitProgramme(name, dt, t, np.ascontiguousarray(u), np.ascontiguousarray(ud),
                          np.ascontiguousarray(udd))


def held_orbit(prog: OrbitProgramme, hold_s: float) -> OrbitProgramme:
    """The orbit after a hold: the machine keeps the start position, at rest,
    for hold_s (rounded to whole steps; the bearing dwells under its load),
    then runs ``prog`` (built for the time left) and launches the bearing."""
    nh = int(round(hold_s / prog.dt))
    if nh == 0:
        return prog
    z = np.zeros((nh, 2))
    u = np.concatenate([np.repeat(prog.u[:1], nh, axis=0), prog.u])
    return OrbitProgramme(f"hold {nh * prog.dt:g} s, {prog.name}", prog.dt, np.arange(len(prog.t) + nh) * prog.dt,
                          np.ascontiguousarray(u), np.ascontiguousarray(np.concatenate([z, prog.ud])),
                          np.ascontiguousarray(np.concatenate([z, prog.udd])))
