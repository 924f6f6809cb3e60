"""The three studies: ``fpd compare``, ``fpd converge``, ``fpd stability``.

One file per concept:

- coupling/study_runner.py: what the studies share (``Case``, ``run_case``,
  ``measure``, ``out_dir``, ``write_rows``, ``fmt``, ``md_table``, ...);
- coupling/compare.py: ``fpd compare``;
- coupling/converge.py: ``fpd converge``;
- coupling/stability.py: ``fpd stability``.

This module re-exports their names, so ``fpd.coupling.studies.cmd_compare``,
``cmd_converge``, ``cmd_stability`` (what coupling/cli.py dispatches to) and
the older imports keep working. Code that patches a name patches it in the
module that reads it (e.g. ``study_runner.run_case`` is read by compare.py and
converge.py under their own names).
"""
from __future__ import annotations

from .study_runner import (  # noqa: F401
    EXIT_FAILED, EXIT_OK, _WARM, Case, _cell, _json, _plt, _say, _scene_name, _tomlv, fmt, md_table, measure,
    min_heat_capacity, model_available, out_dir, run_case, thermal_set, write_rows)
from .compare import (  # noqa: F401
    COMPARE_MODELS, FAST_COMPARE, REFERENCES, _errors_vs_reference, _mu_at_peak, _reference, cmd_compare,
    compare_cases, compare_plots, compare_report, compare_rows, lumped_validity)
from .converge import (  # noqa: F401
    OUTPUTS, UNITS, Sweep, _duration, _mesh_label, closed_form, cmd_converge, converge_plan, converge_plots,
    converge_report, converge_tables, fe3d_sweeps, fit_order, richardson)


def cmd_stability(args) -> int:
    from .stability import cmd_stability as run
    return run(args)
