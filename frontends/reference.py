"""docs/reference.md, generated from the code so that it cannot drift.

    fpd reference > docs/reference.md
    python -m fpd.frontends.reference > docs/reference.md     (the same)

Sources: the command line's parser (frontends/cli.py), the scene schema
(schema/scene.py: kinds, defaults, checks), the units and meanings in
frontends/descriptions.py, the packaged default scene. tests/test_reference.py
fails when the committed file differs from what this prints, and when a key,
column or summary field has no description.
"""
from __future__ import annotations

import contextlib
import os
import sys

from . import descriptions as D
from fpd.schema import scene as scn

COLUMNS = D.COLUMNS
REGENERATE = "python3 -m fpd.frontends.reference > docs/reference.md"

_PROBES_FLOAT = (-1e300, -1.0, 0.0, 0.5, 1.0, 1e300)
_PROBES_INT = (-10**9, -1, 0, 1, 10**9)
_KIND = {"float": "number", "int": "whole number", "bool": "true / false", "str": "string",
         "floats": "list of numbers"}


# -- what the schema declares ------------------------------------------------------------------
def scene_keys() -> list[tuple[str, str, tuple]]:
    """Every declared scene key: (dotted key, description key, schema spec).

    The description key names the variant for law- and kind-specific keys
    (``friction.kumar2015.mu_ref``); the dotted key is what a scene or --set
    writes (``friction.mu_ref``)."""
    out = [(k, k, (kind, None, None)) for k, kind in scn.TOP_KEYS.items()]
    for table, schema in scn.TABLES.items():
        out += [(f"{table}.{k}", f"{table}.{k}", spec) for k, spec in schema.items()]
    out.append(("friction.law", "friction.law", (tuple(scn.FRICTION_KEYS), "constant", None)))
    for law, schema in scn.FRICTION_KEYS.items():
        out += [(f"friction.{k}", f"friction.{law}.{k}", spec) for k, spec in schema.items()]
    out.append(("friction.liner", "friction.liner", (tuple(scn.liner_names()), None, None)))
    out += [(f"friction.{k}", f"friction.{k}", spec) for k, spec in scn.SURFACE_KEYS.items()]
    out.append(("loading.kind", "loading.kind", (tuple(scn.LOADING_KEYS), scn.REQUIRED, None)))
    for kind, schema in scn.LOADING_KEYS.items():
        out += [(f"loading.{k}", f"loading.{kind}.{k}", spec) for k, spec in schema.items()]
    out += [(f"thermal.{k}", f"thermal.{k}", spec) for k, spec in scn.THERMAL_KEYS.items()]
    return out


def describe_key(desc_key: str) -> tuple[str, str] | None:
    """(unit, meaning) of a key: its variant's entry, else the table's."""
    if desc_key in D.KEYS:
        return D.KEYS[desc_key]
    parts = desc_key.split(".")
    if len(parts) == 3:
        return D.KEYS.get(f"{parts[0]}.{parts[2]}")
    return None


def missing_descriptions() -> list[str]:
    """Scene keys and columns the code declares without a description (the test's list)."""
    miss = [d for _, d, _ in scene_keys() if describe_key(d) is None]
    miss += [f"column {c}" for c in declared_columns() if c not in D.COLUMNS]
    return miss


def stale_descriptions() -> list[str]:
    """Descriptions of scene keys that the schema no longer declares."""
    declared = {d for _, d, _ in scene_keys()}
    tables = {d.split(".")[0] for d in declared}
    stale = []
    for k in D.KEYS:
        parts = k.split(".")
        if k in declared:
            continue
        if len(parts) == 2 and parts[0] in tables and any(
                d.startswith(parts[0] + ".") and d.endswith("." + parts[1]) for d in declared):
            continue            # a table-wide meaning used by some variant
        stale.append(k)
    return stale


# where the columns a run can write are declared ("module:attribute", a sequence of
# names): a new stepper or loop with its own columns adds a line here
COLUMN_SOURCES = (
    "fpd.coupling.run:CANONICAL",
    "fpd.machines.seated:SEATED_COLUMNS",
    "fpd.mechanics.two_phase:COLUMNS",
    "fpd.mechanics.bidirectional:COLUMNS",
    "fpd.mechanics.bidirectional:VERTICAL_COLUMNS",
    "fpd.mechanics.tfp:COLUMNS",
    "fpd.mechanics.tfp:TWO_PHASE_COLUMNS",
    "fpd.mechanics.tfp:VERTICAL_COLUMNS",
    "fpd.mechanics.tfp3d:COLUMNS",
    "fpd.mechanics.tfp3d:VERTICAL_COLUMNS",
    "fpd.mechanics.tfp3d_two_phase:TWO_PHASE_COLUMNS",
    "fpd.mechanics.flat:COLUMNS",
    "fpd.coupling.fast_loop:WEAR_COLUMNS",
)


def declared_columns() -> list[str]:
    """Every column a run can write, canonical order first (COLUMN_SOURCES)."""
    import importlib
    cols = []
    for source in COLUMN_SOURCES:
        mod, attr = source.split(":")
        for c in getattr(importlib.import_module(mod), attr):
            if c not in cols:
                cols.append(c)
    return cols


# -- formatting ----------------------------------------------------------------------------
def _value(v) -> str:
    if v is scn.REQUIRED:
        return "required"
    if v is None:
        return "-"
    if isinstance(v, bool):
        return "`true`" if v else "`false`"
    if isinstance(v, str):
        return f'`"{v}"`' if v else '`""`'
    if isinstance(v, float):
        return f"`{v:g}`"
    return f"`{v!r}`"


def allowed(spec) -> str:
    """What a value must be, from the schema (its kind and its check, probed)."""
    kind, _default, check = spec
    if isinstance(kind, tuple):
        return " \\| ".join(f'`"{k}"`' for k in kind)
    if check is None:
        return "any"
    probes = _PROBES_INT if kind == "int" else _PROBES_FLOAT
    msgs = []
    for x in probes:
        try:
            m = check(x)
        except Exception:           # a check for another kind of value
            m = None
        if m and m not in msgs:
            msgs.append(m)
    conds = "; ".join(m.removeprefix("must be ").replace("|", "\\|") for m in msgs)
    return conds or "any"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _unit(u: str) -> str:
    return u if u else "-"


def key_table(rows) -> list[str]:
    lines = ["| key | type | unit | default | allowed | meaning |", "|---|---|---|---|---|---|"]
    for dotted, desc_key, spec in rows:
        unit, meaning = describe_key(desc_key) or ("?", "(undescribed)")
        kind = spec[0]
        typ = "choice" if isinstance(kind, tuple) else _KIND[kind]
        lines.append(f"| `{dotted.split('.', 1)[-1]}` | {typ} | {_unit(unit)} | {_value(spec[1])} | "
                     f"{allowed(spec)} | {_cell(meaning)} |")
    return lines


@contextlib.contextmanager
def _columns_env(width: int):
    """argparse wraps help to the terminal's width: a fixed width for a stable file."""
    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(width)
    try:
        yield
    finally:
        if old is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = old


def command_help() -> list[tuple[str, str]]:
    """(command, its --help text) for fpd and each subcommand, in parser order."""
    import argparse

    from .cli import _parser
    with _columns_env(100):
        p = _parser()
        out = [("fpd", p.format_help())]
        for action in p._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    out.append((f"fpd {name}", sub.format_help()))
    return out


# -- the document ------------------------------------------------------------------------------
_INTRO = """\
# fpd reference

<!-- Generated from the code by `{regen}` (or `fpd reference`): do not edit
by hand. Units and meanings live in frontends/descriptions.py, kinds, defaults
and allowed values in the schema of schema/scene.py, the command help in
frontends/cli.py; tests/test_reference.py fails when this file is out of date. -->

Everything here is a contract: scripts use these names, so keys, commands and
columns are added, never renamed or dropped. Everything is SI; names carry
their unit where one applies (`u_m`, `F_N`, `T1_C`, `flux_W_m2`). Index 1 is
the lower interface / plate, 2 the upper.

The Python API (`import fpd`: `fpd.run`, `fpd.load_scene`, `fpd.compare`,
`fpd.converge`) takes the same scenes and keys and returns the same summary
fields and columns; see `help(fpd)` and `examples/`.
"""

_CLI_RULES = """\
## Command line

- SCENE is a path to a TOML file or the name of a packaged scene (`fpd scenes`
  lists them, e.g. `default`, `lab-sine`, `stability/tall-pad`); without it,
  `fpd run` runs the packaged `default`.
- `--set KEY=VALUE` overrides one dotted key before validation
  (`--set solver.dt=5e-4 --set thermal.model=lumped`); the value is a TOML
  value (numbers, `true`/`false`, `"strings"` or bare words, `[lists]`); it may
  be repeated. `--set thermal.lower.k=20` sets one plate only.
- DIR (`--out`) defaults to `results/<scene name>/` (studies:
  `results/compare-<name>/`, ...). An existing non-empty DIR is refused unless
  `--force`. Results are written into a temporary folder beside DIR and moved
  into place at the end: a failed or interrupted run never leaves a
  half-written DIR, and a run refused for bad input leaves none.
- A failed (exit 1) or interrupted (exit 130) run still leaves a complete DIR
  with the history up to that point, `status` in summary.json saying
  `failed` or `interrupted` and `message` why.
- On a terminal, long runs show a progress bar on stderr (not with `--quiet`,
  not when stderr is not a terminal); the first run after an install compiles
  the numba kernels once (a one-line notice, about 15 s) before the bar starts.
"""

_OUTPUTS = """\
## Outputs (`fpd run`, in DIR)

- `timeseries.csv`: one row per step (or per `output.csv_every` steps, the
  last step always), the columns below in this order; a scene writes only the
  columns it computes (a thermal-only scene: `t_s` and the thermal columns;
  no heat: no `T1_C` ...). `phase` is written as its name. With
  `output.history = "parquet"`: `timeseries.parquet` instead, the same columns.
- `summary.json`: the fields below (those a scene does not compute are left
  out; numbers that are not finite are `null`).
- `scene.toml`: the fully resolved scene (every default filled in), so the
  run can be repeated: `fpd run DIR/scene.toml`.
- `plots/`: `hysteresis.png` (F against u), `response.png`, `temperature.png`,
  `friction.png`; `lower_plate_hottest.png` / `upper_plate_hottest.png` for FE
  plates (each plate's field at its hottest moment; a TFP: one per FE part,
  `lower`, `slider_lower`, `slider_upper`, `upper_plate_hottest.png`);
  `cycles.png` for a test-machine run.
- `cycles.csv` (a test-machine run with at least one complete cycle): one row
  per cycle, the fields of `test_machine.cycles[]` below
  (docs/test_machine.md).
- `vtk/` when `output.vtk_every > 0`: `device.pvd` (the plates, the pad and the
  superstructure as moving polygons in the x-z plane, with `T_C`, `mu`, `body`
  as cell data) and `lower_plate.pvd` / `upper_plate.pvd` (FE temperature
  fields, with `depth_m` below the sliding face; an fe3d plate on the grid
  of `output.vtk_fe3d`, in float32), series of zlib-compressed `.vtu`
  frames with their times (ParaView, pyvista, meshio); a TFP: its five
  bodies and the superstructure (`body` 0..5) and `<part>_plate.pvd` per FE
  part (`lower`, `slider_lower`, `slider_upper`, `upper`); a bidirectional
  run: `device3d.pvd`, the device in 3D. The run estimates the series' size
  before writing and refuses one over `output.vtk_max_GB`. `fpd render DIR`
  turns them into PNG frames and a GIF, each plate field's heated layer in a
  section of its own beside the device (not the flat bearing, which writes
  no VTK).
"""


LINER_BEGIN = "<!-- liner presets: generated from tribology/friction.py LINERS (fpd.frontends.reference) -->"
LINER_END = "<!-- end of the generated liner presets -->"


def liner_markdown() -> list[str]:
    """The liner presets (tribology.friction.LINERS) as markdown: their values,
    per value its source and what the source states (or the basis used where
    none states the number), and the references in full. docs/reference.md
    and docs/liners.md carry it (tests/test_tribology.py checks the latter)."""
    from fpd.tribology.friction import LINER_SOURCES, LINERS

    keys = []
    for preset in LINERS.values():
        keys += [k for k in preset["values"] if k not in keys]
    out = ["| preset | " + " | ".join(keys) + " |", "|---|" + "---|" * len(keys)]
    for name, preset in LINERS.items():
        cells = []
        for k in keys:
            if k not in preset["values"]:
                cells.append("(none)")
                continue
            src = preset["sources"][k]
            mark = "" if src["stated"] else "*"
            cells.append(f"{_value(preset['values'][k]).strip('`')}{mark} [{src['ref'] or 'no source'}]")
        out.append(f"| `{name}` | " + " | ".join(cells) + " |")
    out.append("")
    out.append("`*`: a number no source states as such: a pick inside what the source reports, or the basis "
               "given below where no published value was found. Per value:\n")
    out.append("| preset | key | value | source | stated there | what the source says; the basis used |")
    out.append("|---|---|---|---|---|---|")
    for name, preset in LINERS.items():
        for k, v in preset["values"].items():
            src = preset["sources"][k]
            out.append(f"| `{name}` | `{k}` | {_value(v)} | {src['ref'] or 'none'} | "
                       f"{'yes' if src['stated'] else 'no'} | {_cell(src['note'])} |")
    out.append("")
    out.append("References:\n")
    out += [f"- [{k}] {_cell(text)}" for k, text in LINER_SOURCES.items()]
    return out


def generate() -> str:
    out = [_INTRO.format(regen=REGENERATE), _CLI_RULES]
    for name, text in command_help():
        out.append(f"### `{name}`\n\n```text\n{text.rstrip()}\n```\n")
    out.append("## Exit status\n")
    out.append("| status | meaning |\n|---|---|")
    out += [f"| {code} | {_cell(text)} |" for code, text in D.EXIT.items()]
    out.append("")

    keys = scene_keys()
    out.append("## Scene files (TOML)\n")
    out.append("A scene is a TOML file of the tables below; a key left out takes its default, "
               "\"required\" keys must be given, an unknown key is refused with the nearest valid "
               "one named. `fpd check SCENE` prints a scene with every default filled in. "
               "The packaged default scene:\n")
    default = (scn.SCENES_DIR / "default.toml").read_text().rstrip()
    out.append(f"```toml\n{default}\n```\n")
    out.append("### Top level\n")
    out += key_table([k for k in keys if "." not in k[0]])
    out.append("")
    for table in scn.TABLES:
        out.append(f"### `[{table}]`\n")
        out += key_table([k for k in keys if k[0].startswith(table + ".")])
        out.append("")
    out.append("### `[friction]`\n")
    out.append("Applies to both interfaces; `[friction.lower]` / `[friction.upper]` override it per "
               "interface (a different law included). `law` picks the keys:\n")
    out += key_table([k for k in keys if k[1] == "friction.law"])
    out.append("")
    for law in scn.FRICTION_KEYS:
        out.append(f'#### `law = "{law}"`\n')
        out += key_table([k for k in keys if k[1].startswith(f"friction.{law}.")])
        out.append("")
    out.append("#### Every law: breakaway, wear, liner presets\n")
    out.append("Per surface beside the law's keys (docs/liners.md has the presets and their sources):\n")
    out += key_table([k for k in keys if k[1] == "friction.liner" or k[1][len("friction."):] in scn.SURFACE_KEYS])
    out.append("")
    out.append("#### Liner presets and their sources\n")
    out += liner_markdown()
    out.append("")
    out.append("### `[loading]`\n")
    out.append("`kind` picks the keys. Packaged records (`record = ...`): "
               + ", ".join(f"`\"{r}\"` ({f})" for r, f in scn.RECORDS.items())
               + "; the pairs " + ", ".join(f"`\"{r}\"` ({f[0]}, {f[1]})" for r, f in scn.RECORD_PAIRS.items())
               + "; three channels (CSMIP V2, `channels`) "
               + ", ".join(f"`\"{r}\"` ({f})" for r, f in scn.RECORDS_3C.items())
               + "; their provenance is in scenes/records/README.md.\n")
    out += key_table([k for k in keys if k[1] == "loading.kind"])
    out.append("")
    for kind in scn.LOADING_KEYS:
        out.append(f'#### `kind = "{kind}"`\n')
        out += key_table([k for k in keys if k[1].startswith(f"loading.{kind}.")])
        out.append("")
    out.append("### `[thermal]`\n")
    out.append("Applies to both plates; `[thermal.lower]` / `[thermal.upper]` override it per plate. "
               "Defaults are those of `thermal/params.py` (PlateParams).\n")
    out += key_table([k for k in keys if k[0].startswith("thermal.")])
    out.append("")

    out.append(_OUTPUTS)
    out.append("### `timeseries.csv` columns\n")
    out.append("| column | unit | meaning |\n|---|---|---|")
    for c in declared_columns():
        unit, meaning = D.COLUMNS.get(c, ("?", "(undescribed)"))
        out.append(f"| `{c}` | {_unit(unit)} | {_cell(meaning)} |")
    extra = [c for c in D.COLUMNS if c not in declared_columns()]
    for c in extra:
        unit, meaning = D.COLUMNS[c]
        out.append(f"| `{c}` | {_unit(unit)} | {_cell(meaning)} |")
    out.append("")
    out.append("### `summary.json` fields\n")
    out.append("Dotted paths into the JSON object; `*` is `lower` or `upper`, `[]` each entry of a "
               "list.\n")
    out.append("| field | unit | meaning |\n|---|---|---|")
    for f, (unit, meaning) in D.SUMMARY.items():
        out.append(f"| `{f}` | {_unit(unit)} | {_cell(meaning)} |")
    out.append("")
    text = "\n".join(out)
    return text.rstrip() + "\n"


def main(argv=None) -> int:
    sys.stdout.write(generate())
    return 0


def cmd_reference(args) -> int:
    """``fpd reference``: print docs/reference.md."""
    return main()


if __name__ == "__main__":
    sys.exit(main())
