"""Build only what a scene names (PyBaMM-style submodel selection).

FE plate models (scikit-fem) and the two-phase stepper are imported here,
lazily, so that a lumped or mechanics-only scene never imports scikit-fem,
meshio or pyvista.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from fpd.mechanics.friction import make_law
from fpd.mechanics.geometry import DeviceGeometry, G_ACC
from fpd.thermal.params import PlateParams

from .scene import Scene, SceneError


@dataclass
class Simulation:
    """Everything a run needs, built from a scene."""

    scene: Scene
    dt: float
    n_steps: int
    geometry: DeviceGeometry
    mechanics: object | None          # a Stepper, or None for thermal-only scenes
    laws: tuple                       # friction law per interface (lower, upper)
    plates: tuple                     # PlateModel or None per plate (lower, upper)
    plate_params: tuple
    heat_power: tuple = (0.0, 0.0)    # thermal-only scenes: power per plate (W)
    substeps: int = 1
    info: dict = field(default_factory=dict)


def geometry_of(scene: Scene) -> DeviceGeometry:
    dev = scene["device"]
    return DeviceGeometry(dev["kind"], dev["R1"], dev["R2"], dev["pad_height"], dev["pad_diameter"],
                          dev["pad_mass"], scene["superstructure"]["mass"])


def loading_of(scene: Scene, dt: float):
    """GroundMotion (record, harmonic) or DisplacementProgramme (test machine)."""
    from fpd.mechanics import ground_motion as gmod

    ld = scene["loading"]
    duration = scene["solver"].get("duration")
    if ld["kind"] == "record":
        try:
            rec = gmod.read_record(ld["path"], ld.get("units"))
        except gmod.RecordError as exc:
            raise SceneError(f"{exc} (loading.{'record' if 'record' in ld else 'file'})") from None
        if duration is not None and dt > duration:
            raise SceneError(f"{scene.path}: solver.dt = {dt:g}: must not exceed solver.duration")
        if dt > rec.t[-1]:
            raise SceneError(f"{scene.path}: solver.dt = {dt:g}: must not exceed the record's length {rec.t[-1]:g} s")
        from .scene import check_steps
        check_steps(scene.path, dt, duration or float(rec.t[-1]))
        gm = gmod.ground_motion_from_samples(
            ld.get("record", ld.get("file")), rec.t, rec.a_g * G_ACC * ld["scale"], dt, duration,
            baseline=ld["baseline"])
        gm.record = rec
        return gm
    if ld["kind"] == "harmonic":
        return gmod.harmonic_ground_motion(ld["amplitude_m"], ld["frequency_Hz"], ld["cycles"], dt, duration)
    if ld["kind"] == "displacement":
        return gmod.sine_programme(ld["amplitude_m"], ld["frequency_Hz"], ld["cycles"], dt, duration)
    if ld["kind"] == "pulse":
        from .scene import loading_length
        return gmod.pulse_ground_motion(ld["shape"], ld["velocity_mps"], ld["period_s"], ld["t0_s"],
                                        duration or loading_length(ld), dt)
    raise AssertionError(ld["kind"])


def plate_params(scene: Scene, side: str) -> PlateParams:
    t = scene.thermal(side)
    return PlateParams(**t, a_contact_m=0.5 * scene["device"]["pad_diameter"])


def make_plate(params: PlateParams, dt: float):
    """The plate model the scene names (None for 'none')."""
    if params.model == "none":
        return None
    if params.model == "lumped":
        from fpd.thermal.lumped import LumpedPlate
        return LumpedPlate(params, dt)
    if params.model == "fe1d":
        from fpd.thermal.fe1d import FE1DPlate
        try:
            return FE1DPlate(params, dt)
        except ValueError as exc:          # e.g. a grading that makes the first element vanish
            raise SceneError(f"{exc} (thermal.n_elements / thermal.grading)") from None
    if params.model == "axisym":
        from fpd.thermal.axisym import AxisymPlate
        try:
            return AxisymPlate(params, dt)
        except ValueError as exc:          # a user mesh without the named boundaries, a degenerate grading
            raise SceneError(f"{exc} (thermal.mesh_file / thermal.nz / thermal.grading)") from None
    raise AssertionError(params.model)


def build(scene: Scene) -> Simulation:
    dt = scene["solver"]["dt"]
    geom = geometry_of(scene)
    ld = scene["loading"]
    substeps = scene["coupling"]["substeps"]
    pp = (plate_params(scene, "lower"), plate_params(scene, "upper"))
    info = {}
    if ld["kind"] == "heat":
        from .scene import loading_length
        duration = scene["solver"].get("duration") or loading_length(ld)
        n_steps = max(1, int(round(duration / dt)))
        power = ld["flux_W_m2"] * geom.contact_area
        on = {"lower": (1, 0), "upper": (0, 1), "both": (1, 1)}[ld["plate"]]
        plates = tuple(make_plate(p, dt / substeps) if o else None for p, o in zip(pp, on))
        return Simulation(scene, dt, n_steps, geom, None, (None, None), plates, pp,
                          heat_power=(power * on[0], power * on[1]), substeps=substeps, info=info)
    loading = loading_of(scene, dt)
    model = scene["mechanics"]["model"]
    if ld["kind"] == "displacement":
        from fpd.mechanics.seated import SeatedTestMachine
        mech = SeatedTestMachine(geom, loading)
    elif model == "seated":
        from fpd.mechanics.seated import SeatedStepper
        mech = SeatedStepper(geom, loading)
    else:
        from fpd.mechanics.two_phase import TwoPhaseStepper
        mech = TwoPhaseStepper(geom, loading)
    if hasattr(loading, "record"):
        info["record"] = {"name": loading.name, "points": len(loading.record.t), "dt_s": loading.record.dt,
                          "pga_g": loading.record.pga_g, "scale": ld["scale"],
                          "baseline_b1_mps2": loading.baseline[0], "baseline_b2_mps3": loading.baseline[1]}
    laws = (make_law(scene.friction("lower")), make_law(scene.friction("upper")))
    plates = tuple(make_plate(p, dt / substeps) for p in pp)
    sim = Simulation(scene, dt, loading.n_steps, geom, mech, laws, plates, pp, substeps=substeps, info=info)
    from .fast_loop import warm
    warm(sim)           # load the compiled loop now, not after the run's folder is made (coupling/fast_loop.py)
    return sim
