"""The store of a sweep's finished members (``DIR/.members``, studies/sweep.py).

One file per member, ``<key>.json``: the member's result (id, status,
message, summary, ...) plus

- ``key``: the member key it answers (the file's name; sweep.member_hash),
- ``code``: the fingerprint of the fpd source that computed it,
- ``files``: with ``keep = "timeseries"``, the SHA-256 of each file of the
  member's results folder, kept beside it in ``<key>.d/``,
- ``checksum``: the SHA-256 of all of the above.

A stored result is served only when its checksum, its key and every kept
file check out; anything else (edited, truncated, another key's file) is
reported and the member computed again. Every file is written to a
temporary name and renamed (whole or absent); the member folders of DIR
are copies of ``<key>.d``, never links (editing one cannot change the store).
"""
from __future__ import annotations

import hashlib
import json
import os
import shutil
from functools import lru_cache
from pathlib import Path

STORE = ".members"


@lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """SHA-256 (16 hex digits) of the installed fpd's Python source: every
    ``*.py`` of the package and its subpackages, by their path inside the
    package and their bytes. Any code change gives another fingerprint, so
    another member key (a version string alone does not change with every
    edit)."""
    import importlib

    import fpd

    h = hashlib.sha256()
    files = []
    top = Path(fpd.__file__).resolve().parent
    files += [("fpd/" + p.name, p) for p in top.glob("*.py")]
    for sub in ("loading", "mechanics", "thermal", "meshes", "schema", "coupling", "outputs", "studies", "frontends"):
        try:
            mod = importlib.import_module(f"fpd.{sub}")
        except ImportError:
            continue
        for base in mod.__path__:
            root = Path(base).resolve()
            files += [(f"fpd/{sub}/{p.relative_to(root).as_posix()}", p) for p in root.rglob("*.py")
                      if "__pycache__" not in p.parts]
    for name, p in sorted(set(files)):
        h.update(name.encode() + b"\0")
        h.update(p.read_bytes())
        h.update(b"\0")
    return h.hexdigest()[:16]


def _digest(record: dict) -> str:
    body = {k: v for k, v in record.items() if k != "checksum"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, allow_nan=True).encode()).hexdigest()


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _write_atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    with open(tmp, "wb") as fh:
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, path)


def write(store: Path, key: str, result: dict, files: dict | None = None) -> dict:
    """Store one member's result (and its results folder's files, relpath ->
    bytes); returns the sealed record. The record is written last: a member
    whose files are there without it is not done."""
    record = dict(result)
    record["key"] = key
    record["code"] = code_fingerprint()
    record["files"] = {}
    d = store / f"{key}.d"
    if d.exists():
        shutil.rmtree(d)
    for rel, data in sorted((files or {}).items()):
        p = d / rel
        if ".." in Path(rel).parts or Path(rel).is_absolute():
            raise ValueError(f"a member's file {rel!r} is not inside its folder")
        p.parent.mkdir(parents=True, exist_ok=True)
        _write_atomic(p, data)
        record["files"][rel] = sha256(data)
    record["checksum"] = _digest(record)
    _write_atomic(store / f"{key}.json", json.dumps(record).encode())
    return record


def check(store: Path, key: str) -> tuple[dict | None, str]:
    """(record, "") when ``<key>.json`` is a valid answer for key, else
    (None, why not); (None, "") when there is no such file."""
    f = store / f"{key}.json"
    try:
        text = f.read_text()
    except FileNotFoundError:
        return None, ""
    except (OSError, UnicodeDecodeError) as exc:
        return None, f"unreadable ({exc})"
    try:
        record = json.loads(text)
    except ValueError:
        return None, "not valid JSON"
    if not isinstance(record, dict) or "checksum" not in record:
        return None, "no checksum"
    if record["checksum"] != _digest(record):
        return None, "its checksum does not match its content (edited or damaged)"
    if record.get("key") != key:
        return None, f"it answers another member key ({record.get('key')})"
    if record.get("code") != code_fingerprint():
        return None, "computed by another fpd code"
    for rel, digest in record.get("files", {}).items():
        try:
            data = (store / f"{key}.d" / rel).read_bytes()
        except OSError:
            return None, f"its kept file {rel} is missing"
        if sha256(data) != digest:
            return None, f"its kept file {rel} does not match its checksum (edited or damaged)"
    return record, ""


def read(store: Path, keys) -> tuple[dict, dict]:
    """(key -> valid record, key -> why a file there was refused) for the keys
    asked; refused files are removed (their members are computed again)."""
    good, bad = {}, {}
    if not store.is_dir():
        return good, bad
    for key in dict.fromkeys(keys):
        record, why = check(store, key)
        if record is not None:
            good[key] = record
        elif why:
            bad[key] = why
            discard(store, key)
    return good, bad


def discard(store: Path, key: str) -> None:
    try:
        (store / f"{key}.json").unlink()
    except OSError:
        pass
    shutil.rmtree(store / f"{key}.d", ignore_errors=True)


def copy_member(store: Path, key: str, dest: Path) -> None:
    """A member's kept results folder, copied (not linked) to dest."""
    src = store / f"{key}.d"
    if src.is_dir():
        shutil.copytree(src, dest, dirs_exist_ok=True)
