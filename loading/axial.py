"""The test machine's axial-load programme (docs/test_machine.md, "Axial-load
programme"): the vertical load N(t) the machine's vertical actuator holds in
force control while the horizontal displacement is imposed.

``loading.vertical``:

- ``"constant"``: N = W = M g throughout;
- ``"sine"``: N = W + N_a sin(2 pi f_v t + phase), N_a given as
  ``vertical_amplitude_N`` or as ``vertical_amplitude_ratio`` x W, below W
  (the bearing stays in compression);
- ``"series"``: a text file of (t, N) rows (``vertical_file``: two columns,
  seconds and newtons; whitespace or commas; ``#`` comments), interpolated
  linearly onto the solver grid; it must cover the run and keep N > 0.

The programme is one function of time, ``AxialProgramme.at(t)``: the
stepper takes it on its grid (machines/seated.py SeatedTestMachine, the
kernel's GV = N / M per grid point) and the cycle meter over the recorded
rows' times (outputs/cycles.py, the mean axial load per cycle).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

PROGRAMMES = ("sine", "series")


class AxialError(ValueError):
    """A bad axial-load series file: ``str()`` is one line naming the file and what is wrong."""

    def __init__(self, path, message: str, line: int | None = None):
        where = f"{path}" + (f", line {line}" if line is not None else "")
        text = f"{where}: {message}"
        super().__init__("".join(c if c.isprintable() else repr(c)[1:-1] for c in text))


@dataclass
class AxialProgramme:
    """N(t) (N): kind "constant", "sine" (mean W, amplitude, frequency, phase)
    or "series" (the file's t, N, linear in between)."""

    kind: str
    W: float
    amplitude_N: float = 0.0
    frequency_Hz: float = 0.0
    phase_rad: float = 0.0
    t: np.ndarray | None = None
    N: np.ndarray | None = None

    def at(self, t) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if self.kind == "sine":
            return self.W + self.amplitude_N * np.sin(2.0 * math.pi * self.frequency_Hz * t + self.phase_rad)
        if self.kind == "series":
            return np.interp(t, self.t, self.N)
        return np.full(t.shape, self.W)

    @property
    def varying(self) -> bool:
        return self.kind in PROGRAMMES


def read_series(path) -> tuple[np.ndarray, np.ndarray]:
    """(t, N) of an axial-load file: two numbers per line (time in s, load in
    N), separated by whitespace or a comma; blank lines and ``#`` comments
    skipped; at least two rows, times strictly increasing, loads finite and > 0."""
    from fpd.loading.ground_motion import RecordError, _read_text
    try:
        text = _read_text(path)
    except RecordError as exc:
        raise AxialError(path, str(exc).split(": ", 1)[-1]) from None
    ts, ns = [], []
    for i, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].replace(",", " ").strip()
        if not line:
            continue
        parts = line.split()
        if len(parts) != 2:
            raise AxialError(path, f"found {len(parts)} column{'s' if len(parts) != 1 else ''}: an axial-load "
                             "file has two per line (time s, load N)", i)
        try:
            t, n = float(parts[0]), float(parts[1])
        except ValueError:
            raise AxialError(path, f"{line[:40]!r} is not two numbers (time s, load N)", i) from None
        if not (math.isfinite(t) and math.isfinite(n)):
            raise AxialError(path, "time and load must be finite numbers", i)
        if n <= 0.0:
            raise AxialError(path, f"load {n:g} N: must be > 0 (the bearing in compression; "
                             "lift-off is not modelled on the test machine)", i)
        if ts and t <= ts[-1]:
            raise AxialError(path, f"time {t:g} s: must increase (the previous row has {ts[-1]:g} s)", i)
        ts.append(t)
        ns.append(n)
    if len(ts) < 2:
        raise AxialError(path, f"has {len(ts)} row{'s' if len(ts) != 1 else ''}: an axial-load series needs "
                         "at least two (time s, load N)")
    return np.array(ts), np.array(ns)


def amplitude_of(ld: dict, W: float) -> float:
    """The sine's amplitude (N): vertical_amplitude_N, or the ratio times W."""
    if ld.get("vertical_amplitude_N") is not None:
        return float(ld["vertical_amplitude_N"])
    return float(ld["vertical_amplitude_ratio"]) * W


def programme_of(ld: dict, W: float) -> AxialProgramme:
    """The axial-load programme of a (validated) displacement loading; W = M g."""
    kind = ld.get("vertical", "constant")
    if kind == "sine":
        return AxialProgramme("sine", W, amplitude_of(ld, W), float(ld["vertical_frequency_Hz"]),
                              math.radians(ld.get("vertical_phase_deg") or 0.0))
    if kind == "series":
        t, N = read_series(ld["path_vertical"])
        return AxialProgramme("series", W, t=t, N=N)
    return AxialProgramme("constant", W)
