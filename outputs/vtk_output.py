"""The run's VTK series (docs/reference.md, outputs: ``vtk/``), whatever the
device.

What differs between devices is the device's drawing
(outputs/device_drawings.py, named by the stepper's ``drawing``): the
device's own series (``device.pvd`` drawn in the x-z plane, or
``device3d.pvd`` in 3D) with the bodies of each frame, and per interface
whether and where its plate field goes. The rest is this one class:

- the device's series: per frame the drawing's bodies, with cell data
  ``T_C`` and ``mu`` of each heated body (the values of timeseries.csv at
  the frame's step);
- ``<part>_plate.pvd``: the temperature field of each interface whose
  plate model has one (``PlateModel.field()``: points, meshio-style cells,
  nodal T_C) placed by the drawing in the device's coordinates, so it
  overlays the device, with point data ``depth_m`` (below the sliding face:
  the heated layer); an fe3d plate on the grid of ``output.vtk_fe3d``
  (outputs/vtk_budget.py), in float32; no series for plates without a field
  (lumped, none), nor for a drawing that places none.

Every frame is written when ``simulate`` calls ``VTKSeries.frame`` (every
``output.vtk_every`` steps); frame 0 is the initial state (row 0 as the run
records it: mu_i at the initial temperatures, N_i / area_i and zero sliding
speed). Frame 0 is built first in memory and the whole series bounded from
it: over ``output.vtk_max_GB`` the run is refused before any file exists.
The files are written by meshes/vtk.py (zlib-compressed VTU, no meshio);
matplotlib is imported only by ``hottest_pictures``.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .device_drawings import drawing_of
from .hottest import HottestFields
from .vtk_budget import FieldView, check_budget, depth_of, put


class VTKSeries:
    """Writes the device and plate series of one run into ``folder``.

    ``frame(n, sim)`` is ``simulate``'s on_frame hook; it reads the values of
    the step's CSV row from ``sim.frame_values`` (set by ``simulate`` just
    before the call) and falls back to the models' current state.
    """

    def __init__(self, folder, sim):
        from fpd.meshes.vtk import PVDWriter

        self.folder = Path(folder)
        self.sim = sim
        self.geom = sim.geometry
        self.drawing = drawing_of(sim)
        self.hottest = HottestFields.of(sim)   # side -> (Tmax, time, points, cells, T)
        mode = sim.scene["output"]["vtk_fe3d"]
        self.plates = []              # (interface, its part's name, plate, its output grid)
        if self.drawing.place is not None:
            for i, (part, plate, pp) in enumerate(zip(self.drawing.parts, sim.plates, sim.plate_params)):
                if plate is None or not callable(getattr(plate, "field", None)) or plate.field() is None:
                    continue
                self.plates.append((i, part, plate, FieldView(plate, pp.model, mode)))
        # frame 0 built in memory and the whole series bounded before any file exists
        vals = self._initial_values()
        t, entries, fields = self._entries(0, vals)
        single = {f"{part}_plate": view.single for _, part, _, view in self.plates}
        self.estimate_bytes = check_budget(sim, entries, single,
                                           any(v.mode != "slice" and v.single for *_, v in self.plates))
        series = self.drawing.series
        self.writers = {series: PVDWriter(self.folder, series)}
        for _, part, _, view in self.plates:
            self.writers[f"{part}_plate"] = PVDWriter(self.folder, f"{part}_plate", single=view.single)
        self.device = self.writers[series]
        self._put(t, entries, fields, vals)

    # values of the CSV row ----------------------------------------------------
    def _initial_values(self) -> dict:
        """Row 0 as ``simulate`` records it: mechanics values, the plates'
        surface temperatures, mu_i at those temperatures with zero sliding speed."""
        sim = self.sim
        mech = sim.mechanics
        vals = dict(zip(mech.columns, mech.values())) if mech is not None else {"t_s": 0.0}
        T = [p.surface_temperature() if p is not None else pp.T0_C for p, pp in zip(sim.plates, sim.plate_params)]
        for i, Ti in enumerate(T, start=1):
            vals[f"T{i}_C"] = Ti
        if mech is not None:
            for i, (law, N, area) in enumerate(zip(sim.laws, mech.N, sim.areas), start=1):
                vals[f"mu{i}"] = law(T[i - 1], N / area, 0.0)
        return vals

    def _current_values(self, n: int) -> dict:
        sim = self.sim
        vals = getattr(sim, "frame_values", None)
        if vals is not None:
            return dict(vals)
        mech = sim.mechanics
        vals = dict(zip(mech.columns, mech.values())) if mech is not None else {"t_s": n * sim.dt}
        for i, (p, pp) in enumerate(zip(sim.plates, sim.plate_params), start=1):
            vals.setdefault(f"T{i}_C", p.surface_temperature() if p is not None else pp.T0_C)
        return vals

    # hooks ------------------------------------------------------------------
    def frame(self, n: int, sim=None) -> None:
        vals = self._current_values(n)
        self._put(*self._entries(n, vals), vals)

    def _put(self, t, entries, fields, vals) -> None:
        put(self.writers, t, entries)
        if self.drawing.place is None:
            return
        # the hottest field of each plate (plots/): a plate whose field is dear to
        # build (fe3d) offers its temperature and state only (outputs/hottest.py),
        # the others their field as written (``fields``)
        self.hottest.update([p if hasattr(p, "field_state") else None for p in self.sim.plates], t)
        for i, part, fld in fields:
            self.hottest.consider(part, t, *fld, surface=vals.get(f"T{i + 1}_C"), params=self.sim.plate_params[i])

    def _entries(self, n: int, vals: dict):
        """(time, the frame's files as outputs/vtk_budget entries, [(interface,
        part, the plate's own field)] for the hottest-field pictures)."""
        t = float(vals.get("t_s", n * self.sim.dt))
        entries, fields = [(self.drawing.series, self.drawing.bodies(vals))], []
        for i, part, plate, view in self.plates:
            fld = view.field(plate)
            if fld is None:
                continue
            p, c, Tf = fld
            p, Tf = np.asarray(p, dtype=float), np.asarray(Tf, dtype=float)
            # placed in the device's coordinates, so it overlays the device
            pw, cw, Tw = self.drawing.place(i, (p, c, Tf), vals)
            depth = depth_of(p, len(pw))            # below the sliding face: the heated layer in ParaView, fpd render
            if len(Tw) == len(pw):
                entries.append((f"{part}_plate", [(None, pw, cw, {"T_C": Tw, "depth_m": depth}, None)]))
            else:
                entries.append((f"{part}_plate", [(None, pw, cw, {"depth_m": depth}, {"T_C": [Tw]})]))
            if not hasattr(plate, "field_state"):
                fields.append((i, part, (p, c, Tf)))
        return t, entries, fields

    def close(self) -> None:
        for w in self.writers.values():
            w.close()

    # pictures -----------------------------------------------------------------
    def hottest_pictures(self, plots_dir) -> list[Path]:
        """One PNG per plate with a field: its temperature field at the frame
        with the highest maximum temperature (matplotlib, no OpenGL)."""
        return self.hottest.pictures(plots_dir)
