"""docs/api.md, the Python API reference, generated from the docstrings and
signatures of ``fpd.frontends.api``: ``python3 -m fpd.frontends.apidoc > docs/api.md``
(tests/test_api_docs.py checks that the file is current and that every public
function is typed and documented)."""
from __future__ import annotations

import inspect
import textwrap

HEAD = """# The Python API

Generated from the docstrings by `python3 -m fpd.frontends.apidoc > docs/api.md`;
do not edit by hand. Every scene key, output column and summary field is in
[reference.md](reference.md); a first run from a datasheet is in
[tutorial.md](tutorial.md).

"""


def public_names() -> list[str]:
    """The names ``import fpd`` gives (``fpd.run``, ``fpd.Result``, ...), in their order."""
    from . import api
    return list(api.__all__)


def members(cls) -> list[tuple[str, object]]:
    """A class's public methods and properties, in source order."""
    out = []
    for name, obj in cls.__dict__.items():
        if name.startswith("_"):
            continue
        if isinstance(obj, property) or inspect.isfunction(obj):
            out.append((name, obj))
    return out


def _ann(a) -> str:
    """An annotation as written in the source (they are strings: postponed evaluation)."""
    return (a if isinstance(a, str) else inspect.formatannotation(a)).strip("'\"")


def _signature(name: str, fn) -> str:
    """``name(a: T = default, *, b: U, **kw: V) -> R`` as written in the source."""
    sig = inspect.signature(fn)
    out, star = [], False
    for p in sig.parameters.values():
        if p.name == "self":
            continue
        text = p.name
        if p.kind is p.VAR_KEYWORD:
            text = "**" + text
        elif p.kind is p.VAR_POSITIONAL:
            text, star = "*" + text, True
        elif p.kind is p.KEYWORD_ONLY and not star:
            out.append("*")
            star = True
        if p.annotation is not p.empty:
            text += f": {_ann(p.annotation)}"
        if p.default is not p.empty:
            text += f" = {p.default!r}"
        out.append(text)
    ret = "" if sig.return_annotation is sig.empty else f" -> {_ann(sig.return_annotation)}"
    return f"{name}({', '.join(out)}){ret}"


def _doc(obj) -> str:
    return textwrap.dedent(inspect.getdoc(obj) or "").strip()


def render() -> str:
    from . import api
    parts = [HEAD, _doc(api), "\n"]
    functions = [n for n in public_names() if inspect.isfunction(getattr(api, n))]
    classes = [n for n in public_names() if inspect.isclass(getattr(api, n))]
    parts.append("\n## Functions\n")
    for n in functions:
        fn = getattr(api, n)
        parts.append(f"\n### `fpd.{_signature(n, fn)}`\n\n{_doc(fn)}\n")
    parts.append("\n## Classes\n")
    for n in classes:
        cls = getattr(api, n)
        parts.append(f"\n### `fpd.{n}`\n\n{_doc(cls)}\n")
        for m, obj in members(cls):
            if isinstance(obj, property):
                ret = _ann(inspect.signature(obj.fget).return_annotation)
                parts.append(f"\n#### `{n}.{m}` (property) -> `{ret}`\n\n{_doc(obj.fget)}\n")
            else:
                parts.append(f"\n#### `{n}.{_signature(m, obj)}`\n\n{_doc(obj)}\n")
    return "".join(parts).rstrip() + "\n"


if __name__ == "__main__":
    print(render(), end="")
