"""Loadings on the solver's time grid: ground motion and the test machine."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

G_ACC = 9.80665  # m/s2, standard gravity (records given in g)


@dataclass
class GroundMotion:
    """Horizontal ground (lower plate) motion sampled on the solver grid.

    ``t``, ``d``, ``v``, ``a`` have n_steps + 1 entries (t_n = n dt);
    ``a_step[n] = (v[n+1] - v[n]) / dt`` is the exact mean acceleration over
    step n of the piecewise-linear acceleration history (what the steppers
    use, so that any dt sees the same ground velocity at the grid points).
    """

    name: str
    dt: float
    t: np.ndarray
    d: np.ndarray
    v: np.ndarray
    a: np.ndarray
    a_step: np.ndarray

    @property
    def n_steps(self) -> int:
        return len(self.t) - 1


class RecordError(ValueError):
    """A record file that cannot be read; ``str()`` is one line naming the
    file, the line and what is wrong."""

    def __init__(self, path, message: str, line: int | None = None):
        where = f"{path}" + (f", line {line}" if line is not None else "")
        text = f"{where}: {message}"     # one line: control characters (in names, values) escaped
        super().__init__("".join(c if c.isprintable() else repr(c)[1:-1] for c in text))


@dataclass
class Record:
    """A recorded accelerogram: times (s) and acceleration in g."""

    name: str
    t: np.ndarray
    a_g: np.ndarray
    source: str = ""

    @property
    def dt(self) -> float:
        return float(self.t[1] - self.t[0]) if len(self.t) > 1 else 0.0

    @property
    def pga_g(self) -> float:
        return float(np.max(np.abs(self.a_g)))


_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def _parse_npts_dt(line: str):
    """NPTS and DT from an AT2 header line, in any of the variants seen in
    PEER files: ``NPTS=  4000, DT= .01000 SEC``, ``NPTS = 5590, DT = .0050 SEC,``,
    values first ``4096 0.0100 NPTS, DT``, with or without ``SEC``."""
    import re

    up = line.upper()
    m_n = re.search(r"NPTS\s*[=:]\s*(" + _NUM + ")", up)
    m_d = re.search(r"\bDT\s*[=:]\s*(" + _NUM + ")", up)
    if m_n and m_d:
        return float(m_n.group(1)), float(m_d.group(1))
    nums = re.findall(_NUM, up.split("NPTS")[0])
    if len(nums) >= 2:
        return float(nums[0]), float(nums[1])
    return None


def _file_kind(mode: int) -> str | None:
    """What a file that is not a regular file is (None for a regular file)."""
    import stat
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISSOCK, "a socket"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device")):
        if test(mode):
            return name
    return None if stat.S_ISREG(mode) else "not a regular file"


def _read_text(path) -> str:
    import os
    try:
        kind = _file_kind(os.stat(path).st_mode)     # before opening: a FIFO would block the open forever
    except FileNotFoundError:
        raise RecordError(path, "file not found") from None
    except OSError as exc:
        raise RecordError(path, f"cannot be read ({exc.strerror})") from None
    if kind == "a directory":
        raise RecordError(path, "is a directory, not a record file")
    if kind is not None:
        raise RecordError(path, f"is {kind}, not a regular file: give a record file")
    try:
        raw = open(path, "rb").read()
    except FileNotFoundError:
        raise RecordError(path, "file not found") from None
    except IsADirectoryError:
        raise RecordError(path, "is a directory, not a record file") from None
    except OSError as exc:
        raise RecordError(path, f"cannot be read ({exc.strerror})") from None
    if raw.startswith(b"\xef\xbb\xbf"):       # a UTF-8 byte-order mark (Windows editors): not part of the text
        raw = raw[3:]
    for bom, name in ((b"\x00\x00\xfe\xff", "UTF-32 (big-endian)"), (b"\xff\xfe\x00\x00", "UTF-32 (little-endian)"),
                      (b"\xfe\xff", "UTF-16 (big-endian)"), (b"\xff\xfe", "UTF-16 (little-endian)")):
        if raw.startswith(bom):
            raise RecordError(path, f"{name} text (byte-order mark {bom.hex(' ').upper()} at byte 0); expected "
                              "an ASCII or UTF-8 text record (PEER .AT2 or two columns): save it as UTF-8")
    if not raw.strip():
        raise RecordError(path, "file is empty")
    if b"\x00" in raw:
        at = raw.find(b"\x00")
        raise RecordError(path, f"binary file (NUL byte at byte offset {at}; UTF-16 without a byte-order mark?); "
                          "expected a PEER .AT2 or two-column text record", raw.count(b"\n", 0, at) + 1)
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        # values are ASCII numbers; a non-UTF-8 byte can only be header text
        # (a station name, a degree sign in Latin-1): read as Latin-1, where
        # every byte is a character (a stray byte among the values is then
        # "not a number" at its line)
        return raw.decode("latin-1")


def _floats(tokens, path, lineno):
    out = []
    for tok in tokens:
        try:
            out.append(float(tok))
        except ValueError:
            raise RecordError(path, f"'{tok[:30]}' is not a number", lineno) from None
    return out


def parse_at2(text: str, path="<record>") -> Record:
    """PEER .AT2 (legacy pre-NGA and NGA-West2 headers): the NPTS/DT line is
    found among the first lines; values (in g) follow it, any number per line."""
    lines = text.splitlines()
    head = None
    for i, line in enumerate(lines[:12]):
        if "NPTS" in line.upper():
            head = i
            break
    if head is None:
        raise RecordError(path, "no NPTS/DT header line in the first 12 lines (not a PEER .AT2 file)")
    parsed = _parse_npts_dt(lines[head])
    if parsed is None:
        raise RecordError(path, f"cannot read NPTS and DT from '{lines[head].strip()[:60]}'", head + 1)
    npts, dt = parsed
    if not np.isfinite(npts) or npts != int(npts) or npts < 2:
        raise RecordError(path, f"NPTS = {npts:g} must be a whole number >= 2", head + 1)
    if not (np.isfinite(dt) and dt > 0):
        raise RecordError(path, f"DT = {dt:g} must be a finite number > 0", head + 1)
    vals = []
    for j, line in enumerate(lines[head + 1:], start=head + 2):
        toks = line.replace(",", " ").split()
        if toks:
            row = _floats(toks, path, j)
            for tok, x in zip(toks, row):
                if not np.isfinite(x):
                    raise RecordError(path, f"non-finite acceleration value '{tok[:30]}'", j)
            vals.extend(row)
    a = np.asarray(vals, dtype=float)
    if len(a) != int(npts):
        raise RecordError(path, f"header says NPTS = {int(npts)} but {len(a)} values follow")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise RecordError(path, f"non-finite acceleration value at point {bad[0] + 1}")
    title = " / ".join(s.strip() for s in lines[:head] if s.strip())
    return Record(name=str(path), t=np.arange(len(a)) * dt, a_g=a, source=title)


def parse_two_column(text: str, path="<record>", units: str = "g") -> Record:
    """Two-column text: time (s) and acceleration, whitespace-, tab- or
    comma-separated; leading header lines (non-numeric) are skipped. Times
    must increase strictly."""
    t, a = [], []
    header = []
    started = False
    for j, s, toks, row in _lines(text):
        if row is None:
            if started:
                raise RecordError(path, f"'{s[:40]}' is not two numbers (time, acceleration)", j)
            header.append(s)
            continue
        if len(row) != 2:
            raise RecordError(path, f"expected 2 columns (time, acceleration), found {len(row)}", j)
        if not all(np.isfinite(row)):
            raise RecordError(path, f"non-finite value '{s[:40]}'", j)
        if t and row[0] <= t[-1]:
            raise RecordError(path, f"time {row[0]:g} s does not increase (previous {t[-1]:g} s)", j)
        started = True
        t.append(row[0])
        a.append(row[1])
    if len(t) < 2:
        raise RecordError(path, "fewer than two (time, acceleration) rows")
    scale = {"g": 1.0, "m/s2": 1.0 / G_ACC}[units]
    with np.errstate(over="ignore"):
        tt, aa = np.asarray(t) - t[0], np.asarray(a) * scale
    if not (np.all(np.isfinite(tt)) and np.all(np.isfinite(aa)) and np.all(np.diff(tt) > 0)):
        raise RecordError(path, f"times from {t[0]:g} s to {t[-1]:g} s (or the accelerations) "
                          "are out of the range of floating-point numbers")
    return Record(name=str(path), t=tt, a_g=aa, source=" / ".join(header))


def guess_format(text: str) -> str:
    """'at2' when an NPTS header appears in the first lines, else 'two-column'."""
    for line in text.splitlines()[:12]:
        if "NPTS" in line.upper():
            return "at2"
    return "two-column"


def _first_data_line(text: str):
    """(line number, number of values) of the first all-numeric line after
    any leading header lines (comments '#' and blank lines skipped), or None."""
    for j, _s, toks, row in _lines(text):
        if row is not None:
            return j, len(toks)
    return None


def _lines(text: str):
    """(line number, stripped line, its tokens, their values or None when one
    is not a number) of each line that is neither blank nor a '#' comment;
    commas and semicolons separate values as spaces do."""
    for j, line in enumerate(text.splitlines(), start=1):
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        toks = s.replace(",", " ").replace(";", " ").split()
        try:
            row = [float(x) for x in toks]
        except ValueError:
            row = None
        yield j, s, toks, row


def parse_samples(text: str, path="<record>", dt: float = 0.0, units: str = "g") -> Record:
    """Acceleration samples without times, at a given interval dt (s): one
    value per line (the form OpenSees' ``Path -dt`` reads) or several per
    line (PEER-processed data without its header), read in order; leading
    header lines (non-numeric) and '#' comments are skipped. Times are
    k dt, k = 0, 1, ..."""
    a, header = [], []
    started = False
    for j, s, toks, row in _lines(text):
        if row is None:
            if started:
                bad = next(x for x in toks if not _is_float(x))
                raise RecordError(path, f"'{bad[:30]}' is not a number (acceleration samples, loading.dt "
                                  f"= {dt:g} s)", j)
            header.append(s)
            continue
        for tok, x in zip(toks, row):
            if not np.isfinite(x):
                raise RecordError(path, f"non-finite acceleration value '{tok[:30]}'", j)
        started = True
        a.extend(row)
    if len(a) < 2:
        raise RecordError(path, "fewer than two acceleration samples")
    scale = {"g": 1.0, "m/s2": 1.0 / G_ACC}[units]
    with np.errstate(over="ignore"):
        aa = np.asarray(a) * scale
    if not np.all(np.isfinite(aa)):
        raise RecordError(path, "accelerations out of the range of floating-point numbers")
    return Record(name=str(path), t=np.arange(len(aa)) * dt, a_g=aa, source=" / ".join(header))


# -- CESMD / CSMIP Volume 2: three channels in one file ---------------------------------

V2_UNITS = {"cm/sec2": 1.0 / (100.0 * G_ACC), "cm/s2": 1.0 / (100.0 * G_ACC), "g": 1.0}


def is_v2(text: str) -> bool:
    """A CESMD / CSMIP Volume 2 file: its first line names a corrected
    accelerogram and a block is headed "points of accel data"."""
    first = text.lstrip().split("\n", 1)[0].lower()
    return "accelerogram" in first and "points of accel data" in text


def v2_direction(label: str):
    """'h' (a horizontal channel, "<azimuth> Deg"), 'up' (vertical up: "Up",
    "Vert", "Vertical"), 'down' (vertical, positive down), or None."""
    import re
    low = label.strip().lower()
    if re.fullmatch(r"\d+(\.\d*)?\s*deg(rees?)?", low):
        return "h"
    if low in ("up", "vert", "vertical", "z"):
        return "up"
    if low == "down":
        return "down"
    return None


def parse_v2(text: str, path="<record>") -> list:
    """The channels of a CSMIP Volume 2 file, in file order: a list of
    (number, label, Record with acceleration in g, up positive for a vertical
    channel). Each channel block: a "Chan  k: <label>" line, then the block
    headed "N points of accel data equally spaced at DT sec, in cm/sec2."
    with N values in 8 fields of 10 characters per line (the velocity and
    displacement blocks that follow are not read)."""
    import re
    lines = text.splitlines()
    chans = []
    cur = None
    j = 0
    head = re.compile(r"^\s*(\d+)\s+points of accel data equally spaced at\s+(" + _NUM + r")\s+sec,\s*in\s+([^\s.(]+)",
                      re.IGNORECASE)
    while j < len(lines):
        line = lines[j]
        m = re.match(r"^\s*Chan\s+(\d+)\s*:\s*(.*?)\s*$", line)
        if m and cur is None:
            cur = (int(m.group(1)), m.group(2).strip())
        h = head.match(line)
        if h:
            if cur is None:
                raise RecordError(path, "an accel data block before any 'Chan  k: <name>' line", j + 1)
            npts, dt, units = int(h.group(1)), float(h.group(2)), h.group(3).lower().rstrip(".,")
            if units not in V2_UNITS:
                raise RecordError(path, f"channel {cur[0]} ({cur[1]}): units '{units}' (CSMIP V2 accelerations "
                                  "are read in cm/sec2 or g)", j + 1)
            if npts < 2 or not dt > 0.0:
                raise RecordError(path, f"channel {cur[0]}: {npts} points at {dt:g} s (need >= 2 points, DT > 0)",
                                  j + 1)
            vals = []
            k = j + 1
            while len(vals) < npts and k < len(lines):
                row = lines[k].rstrip()
                for i in range(0, len(row), 10):
                    tok = row[i:i + 10].strip()
                    if tok:
                        try:
                            x = float(tok)
                        except ValueError:
                            raise RecordError(path, f"channel {cur[0]}: '{tok}' is not a number", k + 1) from None
                        if not np.isfinite(x):
                            raise RecordError(path, f"channel {cur[0]}: non-finite value '{tok}'", k + 1)
                        vals.append(x)
                k += 1
            if len(vals) < npts:
                raise RecordError(path, f"channel {cur[0]}: header says {npts} points but {len(vals)} values follow",
                                  j + 1)
            a = np.asarray(vals[:npts]) * V2_UNITS[units]
            if v2_direction(cur[1]) == "down":
                a = -a
            chans.append((cur[0], cur[1], Record(name=f"{path} channel {cur[0]} ({cur[1]})",
                                                 t=np.arange(npts) * dt, a_g=a, source=lines[0].strip())))
            cur = None
            j = k
            continue
        j += 1
    return chans


def v2_roles(chans, path="<record>") -> tuple:
    """(horizontal channel numbers in file order, the vertical one) of a
    three-channel V2 file; RecordError naming what was found otherwise."""
    found = ", ".join(f"{n}: '{lab}'" for n, lab, _ in chans) or "none"
    unknown = [(n, lab) for n, lab, _ in chans if v2_direction(lab) is None]
    if unknown:
        raise RecordError(path, f"CSMIP V2 channel name{'s' if len(unknown) > 1 else ''} not known: "
                          + ", ".join(f"{n}: '{lab}'" for n, lab in unknown)
                          + " (a horizontal channel is '<azimuth> Deg', the vertical 'Up')")
    hor = [n for n, lab, _ in chans if v2_direction(lab) == "h"]
    ver = [n for n, lab, _ in chans if v2_direction(lab) in ("up", "down")]
    if len(chans) != 3 or len(hor) != 2 or len(ver) != 1:
        raise RecordError(path, f"a CSMIP V2 record must carry three channels (horizontal, horizontal, up); "
                          f"found {len(chans)}: {found}")
    return tuple(hor), ver[0]


def read_v2(path) -> list:
    """parse_v2 of a file, checked: exactly two horizontal channels and one vertical."""
    text = _read_text(path)
    if not is_v2(text):
        raise RecordError(path, "not a CSMIP Volume 2 file (no 'points of accel data' block)")
    chans = parse_v2(text, path)
    v2_roles(chans, path)
    return chans


def _is_float(x: str) -> bool:
    try:
        float(x)
        return True
    except ValueError:
        return False


def read_record(path, units: str | None = None, dt: float | None = None, channel: int | None = None) -> Record:
    """Read a record file, format guessed from its content (docs/reference.md,
    loading.file):
    a PEER .AT2 (its header gives DT); with ``dt`` (loading.dt), acceleration
    samples without times, any number per line; else two columns (time,
    acceleration); a CSMIP V2 file (three channels): channel ``channel``
    (None: its first horizontal one). The checks go in the order a reader
    would want them: the file's shape first (what it is, what it needs),
    then the units."""
    text = _read_text(path)
    if is_v2(text):
        if dt is not None:
            raise RecordError(path, "a CSMIP V2 file gives its own DT in each channel's header; remove loading.dt")
        chans = parse_v2(text, path)
        hor, ver = v2_roles(chans, path)
        pick = channel if channel is not None else hor[0]
        for n, _lab, rec in chans:
            if n == pick:
                return rec
        raise RecordError(path, f"no channel {pick} (channels " + ", ".join(str(n) for n, _l, _r in chans) + ")")
    if guess_format(text) == "at2":
        if dt is not None:
            raise RecordError(path, "a PEER .AT2 file gives its own DT in its header; remove loading.dt")
        return parse_at2(text, path)
    first = _first_data_line(text)
    if first is None:
        raise RecordError(path, "no line of numbers (expected time and acceleration columns, or "
                          "acceleration samples with loading.dt)")
    line, ncols = first
    if dt is None and ncols != 2:
        raise RecordError(path, f"found {ncols} value{'s' if ncols > 1 else ''} per line: without times, give the "
                          "sampling interval loading.dt (s) and loading.units; or give two columns "
                          "(time, acceleration)", line)
    if units is None:
        units = _units_from_header(text)
        if units is None:
            what = "acceleration samples" if dt is not None else "two-column record"
            raise RecordError(path, f"{what}: acceleration units not named "
                              "in its header; set loading.units = \"g\" or \"m/s2\"")
    if dt is not None:
        if ncols == 2:
            _refuse_time_column(text, path, dt)
        return parse_samples(text, path, dt, units)
    return parse_two_column(text, path, units)


def _refuse_time_column(text: str, path, dt: float) -> None:
    """loading.dt with a file of two values per line whose first column
    increases on every line, from about 0: a (time, acceleration) record.
    Read as samples it would interleave the times with the accelerations;
    refused (an accelerogram's samples never increase on every line)."""
    first = []
    for line in text.splitlines():
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        toks = s.replace(",", " ").replace(";", " ").split()
        try:
            row = [float(x) for x in toks]
        except ValueError:
            if first:
                return                  # parse_samples names the bad value
            continue
        if len(row) != 2:
            return
        first.append(row[0])
    if len(first) >= 3 and all(b > a for a, b in zip(first, first[1:])):
        raise RecordError(path, f"has two columns and the first increases on every line ({first[0]:g} to "
                          f"{first[-1]:g}): a time column, but loading.dt = {dt:g} s reads every value as an "
                          "acceleration sample; remove loading.dt (the times are read from the file)")


def _units_from_header(text: str):
    import re

    for line in text.splitlines()[:20]:
        low = line.lower()
        if re.search(r"[\[(]\s*g\s*[\])]", low) or "units of g" in low:
            return "g"
        if re.search(r"m/s(\^?2|\*\*2|²)", low):
            return "m/s2"
    return None


# -- integration to the solver grid -------------------------------------------

def _cumulative(t, a):
    """Exact velocity and displacement at the nodes of a piecewise-linear
    acceleration starting from rest."""
    h = np.diff(t)
    v = np.concatenate(([0.0], np.cumsum(0.5 * h * (a[:-1] + a[1:]))))
    d = np.concatenate(([0.0], np.cumsum(h * v[:-1] + h * h * (a[:-1] / 3.0 + a[1:] / 6.0))))
    return v, d


def baseline_fit(t, v):
    """Least-squares quadratic b1 t + b2 t^2 (zero at t = 0) fitted to the
    velocity: the drift removed by the baseline correction."""
    A = np.column_stack([t, t * t])
    (b1, b2), *_ = np.linalg.lstsq(A, v, rcond=None)
    return float(b1), float(b2)


CHUNK = 1 << 16        # grid points sampled at a time: the temporaries stay O(CHUNK), not O(steps)


def compact_zeros(n: int) -> np.ndarray:
    """n zeros as a numpy view of an array('d') (float_array hands the same
    memory to the steppers instead of a copy)."""
    from array import array
    return np.frombuffer(array("d", [0.0]) * n, dtype=np.float64)


def _sample(t_rec, a_rec, v_rec, d_rec, dt, n, want):
    """The piecewise-linear record (and its exact integrals) on t_n = n dt,
    n = 0..n, block by block; ``want``: the names among t, d, v, a, a_step
    to fill (a_step has n entries, the others n + 1). Element by element the
    same arithmetic as on the whole grid at once: the same numbers, bit for bit."""
    out = {k: compact_zeros(n if k == "a_step" else n + 1) for k in want}
    t_end = t_rec[-1]
    for i0 in range(0, n + 1, CHUNK):
        i1 = min(n + 1, i0 + CHUNK + 1)          # one point more: a_step of the block's last step
        t = np.arange(i0, i1) * dt
        k = np.clip(np.searchsorted(t_rec, t, side="right") - 1, 0, len(t_rec) - 2)
        h = t_rec[k + 1] - t_rec[k]
        tau = np.minimum(t - t_rec[k], h)
        slope = (a_rec[k + 1] - a_rec[k]) / h
        a = a_rec[k] + slope * tau
        v = v_rec[k] + a_rec[k] * tau + 0.5 * slope * tau ** 2
        d = d_rec[k] + v_rec[k] * tau + 0.5 * a_rec[k] * tau ** 2 + slope * tau ** 3 / 6.0
        after = t > t_end
        if after.any():
            extra = t[after] - t_end
            a[after] = 0.0
            v[after] = v_rec[-1]
            d[after] = d_rec[-1] + v_rec[-1] * extra
        m = min(CHUNK, n + 1 - i0)                # the block's own points
        for name, arr in (("t", t), ("d", d), ("v", v), ("a", a)):
            if name in out:
                out[name][i0:i0 + m] = arr[:m]
        if "a_step" in out and i0 < n:
            j1 = min(n, i0 + CHUNK)
            out["a_step"][i0:j1] = np.diff(v[:j1 - i0 + 1]) / dt
    return out


@dataclass
class _Lazy:
    """How a record's v and a are computed when first asked for."""
    args: tuple


class RecordGroundMotion(GroundMotion):
    """A record on the solver grid. t, d and a_step (what the steppers read)
    are kept; v and a are computed when first asked for (a long run does not
    hold them: 16 bytes per step)."""

    @property
    def v(self):
        if self._v is None:
            self._va()
        return self._v

    @v.setter
    def v(self, x):
        self._v = x

    @property
    def a(self):
        if self._a is None:
            self._va()
        return self._a

    @a.setter
    def a(self, x):
        self._a = x

    def _va(self):
        got = _sample(*self._lazy.args, want=("v", "a"))
        self._v, self._a = got["v"], got["a"]


def ground_motion_from_samples(name, t_rec, a_rec, dt, duration=None,
                               baseline: bool = True) -> GroundMotion:
    """Sample the piecewise-linear acceleration (m/s2) of a record on the grid
    t_n = n dt, integrating exactly; after the record ends the ground no longer
    accelerates.

    Baseline correction (docs/model.md): a quadratic b1 t + b2 t^2 fitted by
    least squares to the uncorrected velocity is removed, i.e. the linear
    acceleration b1 + 2 b2 t is subtracted. The corrected acceleration is still
    piecewise linear, so a, v and d stay exactly consistent.

    Memory: the grid is sampled block by block into compact arrays that the
    steppers use without a copy (float_array); v and a are computed only when
    asked for (RecordGroundMotion): a run holds 24 bytes per step of loading.
    """
    t_rec = np.asarray(t_rec, float)
    a_rec = np.asarray(a_rec, float)
    b1 = b2 = 0.0
    if baseline:
        v0, _ = _cumulative(t_rec, a_rec)
        b1, b2 = baseline_fit(t_rec, v0)
        a_rec = a_rec - (b1 + 2.0 * b2 * t_rec)
    v_rec, d_rec = _cumulative(t_rec, a_rec)
    if duration is None:
        duration = float(t_rec[-1])
    n = max(1, int(round(duration / dt)))
    args = (t_rec, a_rec, v_rec, d_rec, dt, n)
    got = _sample(*args, want=("t", "d", "a_step"))
    gm = RecordGroundMotion(name=name, dt=dt, t=got["t"], d=got["d"], v=None, a=None, a_step=got["a_step"])
    gm._lazy = _Lazy(args)
    gm.baseline = (b1, b2)
    return gm


def _sine_grid(frequency_Hz, cycles, dt, duration):
    """Grid of a sine lasting ``cycles`` cycles: (t, t clipped to the end, on, omega)."""
    w = 2.0 * np.pi * frequency_Hz
    t_end = cycles / frequency_Hz
    n = max(1, int(round((t_end if duration is None else duration) / dt)))
    t = np.arange(n + 1) * dt
    return t, np.minimum(t, t_end), t <= t_end + 1e-12, w


def harmonic_ground_motion(amplitude_m, frequency_Hz, cycles, dt, duration=None) -> GroundMotion:
    """x_g = A sin(2 pi f t) for the given number of cycles, then at rest."""
    t, tt, on, w = _sine_grid(frequency_Hz, cycles, dt, duration)
    d = amplitude_m * np.sin(w * tt)
    v = np.where(on, amplitude_m * w * np.cos(w * tt), 0.0)
    a = np.where(on, -amplitude_m * w * w * np.sin(w * tt), 0.0)
    # exact step means of the analytic acceleration; the velocity jump at the
    # start (and the stop) is a rigid-body impulse that the relative motion
    # does not feel, so steps see only the smooth part
    v_smooth = amplitude_m * w * np.cos(w * tt)
    a_step = np.diff(v_smooth) / dt
    return _compacted(GroundMotion(name=f"harmonic {amplitude_m:g} m {frequency_Hz:g} Hz", dt=dt,
                                   t=t, d=d, v=v, a=a, a_step=a_step))


@dataclass
class DisplacementProgramme:
    """Test machine: the relative displacement u(t) is imposed (the lower plate
    moves by -u, the superstructure is held horizontally and carries its
    weight). Arrays on the solver grid, n_steps + 1 entries."""

    name: str
    dt: float
    t: np.ndarray
    u: np.ndarray
    ud: np.ndarray
    udd: np.ndarray
    # the programme's smooth branch at the grid points: u' and u'' as if the
    # motion went on (equal to ud, udd while it runs); where they differ the
    # machine stopped the bearing between two grid points by an impulse
    ud_smooth: np.ndarray | None = None
    udd_smooth: np.ndarray | None = None

    @property
    def n_steps(self) -> int:
        return len(self.t) - 1


def sine_programme(amplitude_m, frequency_Hz, cycles, dt, duration=None) -> DisplacementProgramme:
    """Test machine: u = A sin(2 pi f t) for the given number of cycles."""
    t, tt, on, w = _sine_grid(frequency_Hz, cycles, dt, duration)
    return DisplacementProgramme(
        name=f"sine {amplitude_m:g} m {frequency_Hz:g} Hz x {cycles:g}", dt=dt, t=t,
        u=amplitude_m * np.sin(w * tt),
        ud=np.where(on, amplitude_m * w * np.cos(w * tt), 0.0),
        udd=np.where(on, -amplitude_m * w * w * np.sin(w * tt), 0.0),
        ud_smooth=amplitude_m * w * np.cos(w * tt),
        udd_smooth=-amplitude_m * w * w * np.sin(w * tt))


def triangle_programme(amplitude_m, frequency_Hz, cycles, dt, duration=None) -> DisplacementProgramme:
    """Test machine: a triangle wave of amplitude A (constant speed 4 A f,
    starting from 0 towards +A) for the given number of cycles, then at rest."""
    t, tt, on, w = _sine_grid(frequency_Hz, cycles, dt, duration)

    def wave(x):
        p = np.mod(x * frequency_Hz, 1.0)
        u = np.where(p < 0.25, 4.0 * p, np.where(p < 0.75, 2.0 - 4.0 * p, 4.0 * p - 4.0))
        ud = np.where((p < 0.25) | (p >= 0.75), 1.0, -1.0) * 4.0 * frequency_Hz
        return amplitude_m * u, amplitude_m * ud

    u, ud = wave(tt)
    _, ud_s = wave(t)
    zero = np.zeros_like(t)
    return DisplacementProgramme(
        name=f"triangle {amplitude_m:g} m {frequency_Hz:g} Hz x {cycles:g}", dt=dt, t=t,
        u=u, ud=np.where(on, ud, 0.0), udd=zero, ud_smooth=ud_s, udd_smooth=zero)


def held_programme(prog: DisplacementProgramme, hold_s: float) -> DisplacementProgramme:
    """The programme after a hold: the machine keeps the start position, at
    rest, for hold_s (rounded to whole steps; the bearing dwells under its
    load), then runs ``prog`` (built for the time left)."""
    nh = int(round(hold_s / prog.dt))
    if nh == 0:
        return prog
    z = np.zeros(nh)

    def pre(x, first):
        return np.concatenate([np.full(nh, first), np.asarray(x, dtype=float)])

    uds = prog.ud if prog.ud_smooth is None else prog.ud_smooth
    udds = prog.udd if prog.udd_smooth is None else prog.udd_smooth
    return DisplacementProgramme(
        name=f"hold {nh * prog.dt:g} s, {prog.name}", dt=prog.dt, t=np.arange(len(prog.t) + nh) * prog.dt,
        u=pre(prog.u, float(prog.u[0])), ud=np.concatenate([z, prog.ud]), udd=np.concatenate([z, prog.udd]),
        ud_smooth=np.concatenate([z, uds]), udd_smooth=np.concatenate([z, udds]))


def pulse_ground_motion(shape, velocity_mps, period_s, t0_s, duration, dt) -> GroundMotion:
    """Analytic ground velocity pulses (near-fault and impulsive loadings).

    ``step``: the ground velocity jumps from 0 to V at t0 and stays (an
    impulse V of the relative motion: the step containing t0 sees the mean
    acceleration V / dt, whatever dt is); ``cosine``: a one-sided fling,
    v = V/2 (1 - cos(2 pi (t - t0) / Tp)) for one period Tp (net ground
    displacement V Tp / 2); ``sine``: a forward-directivity cycle,
    v = V sin(2 pi (t - t0) / Tp) for one period (no net displacement).
    Ground at rest before t0 and after the pulse (except ``step``).
    a_step is the exact step mean diff(v) / dt.
    """
    n = max(1, int(round(duration / dt)))
    t = np.arange(n + 1) * dt
    tau = t - t0_s
    V = velocity_mps
    if shape == "step":
        on = tau >= -1e-12 * dt
        v = np.where(on, V, 0.0)
        d = np.where(on, V * np.maximum(tau, 0.0), 0.0)
        a = np.zeros_like(t)
    else:
        w = 2.0 * np.pi / period_s
        s = np.clip(tau, 0.0, period_s)
        on = (tau >= 0) & (tau <= period_s)
        if shape == "cosine":
            v = 0.5 * V * (1.0 - np.cos(w * s))
            d = 0.5 * V * (s - np.sin(w * s) / w)
            a = np.where(on, 0.5 * V * w * np.sin(w * s), 0.0)
        elif shape == "sine":
            v = V * np.sin(w * s)
            d = V * (1.0 - np.cos(w * s)) / w
            a = np.where(on, V * w * np.cos(w * s), 0.0)
        else:
            raise ValueError(f"unknown pulse shape {shape!r}")
    return _compacted(GroundMotion(name=f"{shape} pulse {V:g} m/s", dt=dt, t=t, d=d, v=v, a=a,
                                   a_step=np.diff(v) / dt))


def _compacted(gm: GroundMotion) -> GroundMotion:
    """The motion's arrays moved into compact arrays (compact_zeros), so that
    the steppers' float_array shares them instead of copying (the same values)."""
    for name in ("t", "d", "v", "a", "a_step"):
        x = getattr(gm, name)
        c = compact_zeros(len(x))
        c[:] = x
        setattr(gm, name, c)
    return gm


def float_array(x) -> "array":
    """The values of x as a compact array('d'): indexing gives plain Python
    floats (as fast as a list, 8 bytes per entry instead of ~32), so the
    steppers' per-step path keeps float arithmetic and a long run's loading
    costs 8 bytes per step and per series."""
    from array import array

    base = getattr(x, "base", None)
    if (isinstance(base, memoryview) and isinstance(base.obj, array) and base.obj.typecode == "d"
            and x.ndim == 1 and x.dtype == np.float64 and len(base.obj) == x.size
            and x.ctypes.data == base.obj.buffer_info()[0]):
        return base.obj           # a compact array (compact_zeros): the same memory, no copy
    a = array("d")
    a.frombytes(np.ascontiguousarray(x, dtype=np.float64).tobytes())
    return a


def as_float64(x) -> np.ndarray:
    """x as a float64 numpy array, without a copy where x already holds
    float64 values (an array('d') of float_array, a float64 ndarray): what
    the compiled engine reads, so a long run's loading is not held twice."""
    from array import array

    if isinstance(x, array) and x.typecode == "d":
        return np.frombuffer(x, dtype=np.float64)
    return np.ascontiguousarray(x, dtype=np.float64)
