"""The three studies of issue 6: ``fpd compare``, ``fpd converge``, ``fpd stability``.

One concept per file: coupling/study_runner.py (running and measuring one
case, the folder helpers), coupling/compare.py, coupling/converge.py and
coupling/stability.py. This module keeps their names importable from
``fpd.coupling.studies`` (the command line and other callers use them).
"""
from __future__ import annotations

from .compare import (COMPARE_MODELS, FAST_COMPARE, compare_cases, _reference, lumped_validity, cmd_compare,
                      compare_rows, compare_plots, compare_report)  # noqa: F401
from .converge import (OUTPUTS, _duration, closed_form, richardson, fit_order, Sweep, converge_plan,
                       cmd_converge, converge_tables, _mesh_label, UNITS, converge_plots, converge_report)  # noqa: F401
from .stability import cmd_stability  # noqa: F401
from .study_runner import (EXIT_OK, EXIT_FAILED, Case, model_available, thermal_set, _tomlv,
                           min_heat_capacity, run_case, measure, out_dir, write_rows, _cell, fmt, md_table,
                           _plt, _say, _scene_name, _json)  # noqa: F401
