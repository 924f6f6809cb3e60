"""Build only what a scene names (PyBaMM-style submodel selection).

FE plate models (scikit-fem) and the two-phase stepper are imported here,
lazily, so that a lumped or mechanics-only scene never imports scikit-fem,
meshio or pyvista.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from fpd.tribology.friction import dwell_law, make_law, static_mu
from fpd.mechanics.geometry import DeviceGeometry, G_ACC
from fpd.thermal.params import PlateParams

from fpd.schema.scene import TFP_PARTS, TFP_SURFACES, Scene, SceneError


@dataclass
class Simulation:
    """Everything a run needs, built from a scene."""

    scene: Scene
    dt: float
    n_steps: int
    geometry: DeviceGeometry
    mechanics: object | None          # a Stepper, or None for thermal-only scenes
    laws: tuple                       # friction law per interface (DFP: lower, upper; TFP: S1..S4)
    plates: tuple                     # PlateModel or None per interface's plate
    plate_params: tuple
    heat_power: tuple = (0.0, 0.0)    # thermal-only scenes: power per plate (W)
    substeps: int = 1
    info: dict = field(default_factory=dict)

    # per interface the Archard wear coefficient's law (tribology.friction.wear_laws), or None: no wear
    wear: tuple | None = None

    def __post_init__(self):
        if self.mechanics is not None and self.wear is None:
            from fpd.tribology.friction import wear_laws
            sides = TFP_SURFACES if len(self.laws) == 4 else ("lower", "upper")
            self.wear = wear_laws([self.scene.friction(s) for s in sides])

    @property
    def areas(self) -> tuple:
        """Contact area (m^2) per interface: p_i = N_i / area_i in the friction laws."""
        areas = getattr(self.geometry, "areas", None)
        if areas is not None:
            return tuple(areas)
        return (self.geometry.contact_area,) * len(self.plates)


def geometry_of(scene: Scene) -> DeviceGeometry:
    dev = scene["device"]
    return DeviceGeometry(dev["kind"], dev["R1"], dev["R2"], dev["pad_height"], dev["pad_diameter"],
                          dev["pad_mass"], scene["superstructure"]["mass"])


def loading_of(scene: Scene, dt: float):
    """GroundMotion (record, harmonic) or DisplacementProgramme (test machine)."""
    from fpd.loading import ground_motion as gmod

    ld = scene["loading"]
    duration = scene["solver"].get("duration")
    if ld["kind"] == "record":
        try:
            rec = _read_record(ld)
        except gmod.RecordError as exc:
            raise SceneError(f"{exc} (loading.{'record' if 'record' in ld else 'file'})") from None
        factor = ld["scale"] * _target_factor(ld, rec)
        if duration is not None and dt > duration:
            raise SceneError(f"{scene.path}: solver.dt = {dt:g}: must not exceed solver.duration")
        if dt > rec.t[-1]:
            raise SceneError(f"{scene.path}: solver.dt = {dt:g}: must not exceed the record's length {rec.t[-1]:g} s")
        from fpd.schema.scene import check_steps
        check_steps(scene.path, dt, duration or float(rec.t[-1]))
        gm = gmod.ground_motion_from_samples(
            _name(ld, 0) or rec.name, rec.t, rec.a_g * G_ACC * factor, dt, duration,
            baseline=ld["baseline"])
        gm.record = rec
        return gm
    if ld["kind"] == "harmonic":
        return gmod.harmonic_ground_motion(ld["amplitude_m"], ld["frequency_Hz"], ld["cycles"], dt, duration)
    if ld["kind"] == "displacement":
        hold = ld.get("hold_s", 0.0)
        if duration is not None and hold:
            duration = max(dt, duration - round(hold / dt) * dt)
        make = gmod.triangle_programme if ld["waveform"] == "triangle" else gmod.sine_programme
        prog = make(ld["amplitude_m"], ld["frequency_Hz"], ld["cycles"], dt, duration)
        return gmod.held_programme(prog, hold) if hold else prog
    if ld["kind"] == "pulse":
        from fpd.schema.scene import loading_length
        return gmod.pulse_ground_motion(ld["shape"], ld["velocity_mps"], ld["period_s"], ld["t0_s"],
                                        duration or loading_length(ld), dt)
    raise AssertionError(ld["kind"])


def _read_record(ld: dict):
    """The record a [loading] names: a file (packaged or given) or a member of a P695 set."""
    from fpd.loading import ground_motion as gmod
    if "record_set" in ld:
        from fpd.loading import p695
        comp = "a" if ld["component"] == "pair" else ld["component"]      # a pair: a on x
        return p695.read(ld["record_set"], ld["record_id"], comp, ld["normalize"])
    return gmod.read_record(ld["path"], ld.get("units"), ld.get("dt"), _channel(ld, 0))


def _name(ld: dict, i: int, key: str = "file"):
    """The name a component is reported by: the packaged record's or the file's,
    with its channel for a three-channel record."""
    base = ld.get("record", ld.get(key))
    ch = _channel(ld, i)
    return f"{base} channel {ch}" if (base and ch) else base


def _channel(ld: dict, i: int):
    """Channel i (0 x, 1 y, 2 z) of a three-channel record (loading.channels), or None."""
    ch = ld.get("channels")
    return int(ch[i]) if ch and ch[i] else None


def _read_record_y(ld: dict):
    """The y component of a bidirectional record: a file, a packaged pair's
    second file, or component b of a P695 set record (component = "pair")."""
    from fpd.loading import ground_motion as gmod
    if "record_set" in ld:
        from fpd.loading import p695
        return p695.read(ld["record_set"], ld["record_id"], "b", ld["normalize"])
    return gmod.read_record(ld["path_y"], ld.get("units"), ld.get("dt"), _channel(ld, 1))


def _read_record_z(ld: dict):
    """The vertical component: the V2 record's vertical channel, or loading.file_z
    (any format the reader takes; a V2 file: its vertical channel)."""
    from fpd.loading import ground_motion as gmod
    if ld.get("file_z") is None:
        return gmod.read_record(ld["path_z"], ld.get("units"), ld.get("dt"), _channel(ld, 2))
    text = gmod._read_text(ld["path_z"])
    if gmod.is_v2(text):
        chans = gmod.parse_v2(text, ld["path_z"])
        _hor, ver = gmod.v2_roles(chans, ld["path_z"])
        return gmod.read_record(ld["path_z"], channel=ver)
    return gmod.read_record(ld["path_z"], ld.get("units"), ld.get("dt"))


def vertical_loading_of(scene: Scene, dt: float, gx):
    """The vertical ground motion (up) on the solver grid, or None (model.md 10).
    Treated as the y component of a pair is: read on its own sampling, scaled by
    loading.scale (and the x record's target_pga_g factor), baseline-corrected
    and integrated exactly onto the solver grid; the x record (or
    solver.duration) sets the length, after a shorter vertical record ends the
    ground stops accelerating vertically."""
    from fpd.loading import ground_motion as gmod

    ld = scene["loading"]
    if ld["kind"] == "record" and ld.get("vertical_scale") is not None:
        return scaled_vertical(gx, ld["vertical_scale"])
    if ld["kind"] != "record" or not ld.get("path_z"):
        return None
    key = "file_z" if ld.get("file_z") is not None else ("record" if "record" in ld else "file")
    try:
        rec = _read_record_z(ld)
    except gmod.RecordError as exc:
        raise SceneError(f"{exc} (loading.{key})") from None
    duration = scene["solver"].get("duration")
    length = duration if duration is not None else float(gx.t[-1])
    factor = ld["scale"] * (_target_factor(ld, gx.record) if hasattr(gx, "record") else 1.0)
    gz = gmod.ground_motion_from_samples(ld.get("file_z", _name(ld, 2)), rec.t, rec.a_g * G_ACC * factor, dt, length,
                                         baseline=ld["baseline"])
    gz.record = rec
    return gz


def scaled_vertical(gx, k: float):
    """The vertical ground motion as k times the horizontal x one, on its grid
    (loading.vertical_scale: given by name only, never a default)."""
    import dataclasses

    import numpy as np
    gz = dataclasses.replace(gx, name=f"{k:g} x {gx.name}", d=k * np.asarray(gx.d, dtype=float),
                             v=k * np.asarray(gx.v, dtype=float), a=k * np.asarray(gx.a, dtype=float),
                             a_step=k * np.asarray(gx.a_step, dtype=float))
    gz.vertical_scale = k
    return gz


def vertical_info(gz, ld, gx) -> dict:
    """summary.json's record_z: the vertical record's, or the scale of the horizontal one it copies."""
    if hasattr(gz, "vertical_scale"):
        return {"name": gz.name, "vertical_scale": gz.vertical_scale, "of": gx.name}
    return _record_info(gz, ld, gx)


def _record_info(g, ld, gx) -> dict:
    return {"name": g.name, "points": len(g.record.t), "dt_s": g.record.dt, "pga_g": g.record.pga_g,
            "scale": ld["scale"], "scaled_pga_g": g.record.pga_g * ld["scale"] * _target_factor(ld, gx.record),
            "baseline_b1_mps2": g.baseline[0], "baseline_b2_mps3": g.baseline[1]}


def _target_factor(ld: dict, rec) -> float:
    """loading.target_pga_g: a set member is scaled by the factor that brings
    the set's median PGA to the target (one factor for the whole set, as P695
    scales a set; the records keep their spread); a single record by the one
    that brings its own PGA there."""
    target = ld.get("target_pga_g")
    if not target:
        return 1.0
    if "record_set" in ld:
        from fpd.loading import p695
        return target / p695.median_pga_g(ld["record_set"], ld["normalize"])
    if rec.pga_g <= 0:
        raise SceneError(f"{rec.name}: PGA is 0, cannot scale to loading.target_pga_g = {target:g}")
    return target / rec.pga_g


def record_info(scene: Scene, loading) -> dict:
    """summary.json's ``record`` of a loading read from a record (the TFP's and the flat bearing's)."""
    ld = scene["loading"]
    return {"name": loading.name, "points": len(loading.record.t), "dt_s": loading.record.dt,
            "pga_g": loading.record.pga_g, "scale": ld["scale"],
            "baseline_b1_mps2": loading.baseline[0], "baseline_b2_mps3": loading.baseline[1]}


def rim_of(scene: Scene) -> tuple:
    """(d1, d2, restitution, stiffness, damping ratio) of a DFP / SFP / flat
    bearing (d2 None for the SFP; stiffness None: the rigid rim)."""
    dev = scene["device"]
    return (dev["d1"], dev.get("d2"), dev["rim_restitution"], dev.get("rim_stiffness_N_per_m"),
            dev["rim_damping_ratio"])


def plate_params(scene: Scene, side: str) -> PlateParams:
    t = scene.thermal(side)
    # a heat-only scene keeps the footprint at the plate centre: the meshes
    # resolve it there and grade away (sweep_m); otherwise it may go anywhere
    sweep = 0.0 if scene["loading"]["kind"] == "heat" else -1.0
    return PlateParams(**t, a_contact_m=0.5 * scene["device"]["pad_diameter"], sweep_m=sweep)


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
    if params.model == "fe3d":
        from fpd.thermal.fe3d import FE3DPlate
        try:
            return FE3DPlate(params, dt)
        except ValueError as exc:
            raise SceneError(f"{exc} (thermal.per_radius / thermal.nz / thermal.grading)") from None
    raise AssertionError(params.model)


def build(scene: Scene) -> Simulation:
    if scene["device"]["kind"] == "TFP":          # four surfaces, five parts (build_tfp)
        return build_tfp(scene)
    if scene["device"]["kind"] == "flat":         # the flat double bearing (paper Fig. 2)
        return build_flat(scene)
    dt = scene["solver"]["dt"]
    geom = geometry_of(scene)
    ld = scene["loading"]
    substeps = scene["coupling"]["substeps"]
    pp = (plate_params(scene, "lower"), plate_params(scene, "upper"))
    info = {}
    if ld["kind"] == "heat":
        from fpd.schema.scene import loading_length
        duration = scene["solver"].get("duration") or loading_length(ld)
        n_steps = max(1, int(round(duration / dt)))
        power = ld["flux_W_m2"] * geom.contact_area
        on = {"lower": (1, 0), "upper": (0, 1), "both": (1, 1)}[ld["plate"]]
        plates = tuple(make_plate(p, dt / substeps) if o else None for p, o in zip(pp, on))
        return Simulation(scene, dt, n_steps, geom, None, (None, None), plates, pp,
                          heat_power=(power * on[0], power * on[1]), substeps=substeps, info=info)
    from fpd.schema.scene import is_bidirectional
    if is_bidirectional(scene.data):
        return _build_bidirectional(scene, dt, geom, pp, substeps, info)
    loading = loading_of(scene, dt)
    model = scene["mechanics"]["model"]
    if ld["kind"] == "displacement":
        from fpd.machines.seated import SeatedTestMachine
        from fpd.loading.axial import AxialError, programme_of
        try:
            axial = programme_of(ld, geom.mass * geom.g)
        except AxialError as exc:
            raise SceneError(f"{exc} (loading.vertical_file)") from None
        mech = SeatedTestMachine(geom, loading, ld["vertical"], axial if axial.varying else None)
        if ld.get("link_stiffness_N_per_m"):
            mech.set_link(ld["link_stiffness_N_per_m"], ld["link_mass_kg"])
    else:
        # one DFP/SFP stepper: a planar ground motion is the 3D stepper's with the
        # y component absent (signed planar columns), both models, both schemes
        from fpd.mechanics.bidirectional import BidirectionalStepper
        gz = vertical_loading_of(scene, dt, loading)
        mech = BidirectionalStepper(geom, loading, None, normal_force=scene["mechanics"]["normal_force"],
                                    model=model, planar=True, rim=rim_of(scene), gz=gz)
        if gz is not None:
            info["record_z"] = vertical_info(gz, ld, loading)
    if hasattr(loading, "record"):
        info["record"] = {"name": loading.name, "points": len(loading.record.t), "dt_s": loading.record.dt,
                          "pga_g": loading.record.pga_g, "scale": ld["scale"],
                          "scaled_pga_g": loading.record.pga_g * ld["scale"] * _target_factor(ld, loading.record),
                          "baseline_b1_mps2": loading.baseline[0], "baseline_b2_mps3": loading.baseline[1]}
    laws = (make_law(scene.friction("lower")), make_law(scene.friction("upper")))
    _set_static(scene, mech)
    plates = tuple(make_plate(p, dt / substeps) for p in pp)
    sim = Simulation(scene, dt, loading.n_steps, geom, mech, laws, plates, pp, substeps=substeps, info=info)
    from .fast_loop import warm
    warm(sim)           # load the compiled loop now, not after the run's folder is made (coupling/fast_loop.py)
    return sim


def _set_static(scene: Scene, mech) -> None:
    """The surfaces' static (breakaway) coefficients into a DFP/SFP stepper (when any is given)."""
    (m1, r1), (m2, r2) = (static_mu(scene.friction(side)) for side in ("lower", "upper"))
    if m1 > 0.0 or m2 > 0.0 or r1 > 0.0 or r2 > 0.0:
        mech.set_static(m1, m2, r1, r2)
    dwell = tuple(dwell_law(scene.friction(side)) for side in ("lower", "upper"))
    if any(d[1] > 0.0 for d in dwell):
        mech.set_dwell(*dwell)          # the planar test machine's (schema/scene.py refuses it elsewhere)


# -- bidirectional runs (model.md 8) ----------------------------------------------------

def bidirectional_loading_of(scene: Scene, dt: float):
    """(gx, gy) ground motions on the solver grid, or an OrbitProgramme (test machine).

    Records: each component read, scaled, baseline-corrected and integrated
    onto the solver grid as a planar record is (each on its own sampling),
    then the pair turned by loading.angle_deg (x towards y). The x record
    (or solver.duration) sets the length; after a shorter y record ends the
    ground stops accelerating in y."""
    from fpd.loading import ground_motion as gmod

    ld = scene["loading"]
    duration = scene["solver"].get("duration")
    if ld["kind"] == "displacement":
        from fpd.loading.orbits import held_orbit, orbit_programme
        hold = ld.get("hold_s", 0.0)
        if duration is not None and hold:
            duration = max(dt, duration - round(hold / dt) * dt)
        prog = orbit_programme(ld["waveform"], ld["amplitude_m"], ld["frequency_Hz"], ld["cycles"], dt,
                               duration, ld["direction_deg"])
        return held_orbit(prog, hold) if hold else prog
    if ld["kind"] != "record":
        gx = loading_of(scene, dt)
        return gx, None
    gx = loading_of(scene, dt)
    if ld.get("path_y"):
        # the file that failed: file_y when given (beside a packaged record or a file), else the pair's
        key = "file_y" if ld.get("file_y") is not None else ("record" if "record" in ld else "file")
        try:
            rec = _read_record_y(ld)
        except gmod.RecordError as exc:
            raise SceneError(f"{exc} (loading.{key})") from None
        length = duration if duration is not None else float(gx.t[-1])
        # the pair scaled as one: target_pga_g's factor is the x record's (the pair keeps its proportions)
        factor = ld["scale"] * (_target_factor(ld, gx.record) if hasattr(gx, "record") else 1.0)
        gy = gmod.ground_motion_from_samples(_name(ld, 1, "file_y") or rec.name, rec.t, rec.a_g * G_ACC * factor,
                                             dt, length, baseline=ld["baseline"])
        gy.record = rec
    else:
        gy = None
    ang = math.radians(ld["angle_deg"])
    if ang != 0.0:
        gx, gy = _turned(gx, gy, ang)
    return gx, gy


def _turned(gx, gy, ang):
    """The pair (gx, gy) turned by ang in the plane (x towards y)."""
    from fpd.loading.ground_motion import GroundMotion
    import numpy as np
    c, s = math.cos(ang), math.sin(ang)
    fields = ("d", "v", "a", "a_step")
    y = {f: getattr(gy, f) if gy is not None else np.zeros_like(getattr(gx, f)) for f in fields}
    X = {f: c * getattr(gx, f) - s * y[f] for f in fields}
    Y = {f: s * getattr(gx, f) + c * y[f] for f in fields}
    out = []
    for name, V, src in ((gx.name, X, gx), (gy.name if gy is not None else gx.name, Y, gy or gx)):
        g = GroundMotion(name, gx.dt, gx.t, V["d"], V["v"], V["a"], V["a_step"])
        for extra in ("record", "baseline"):
            if hasattr(src, extra):
                setattr(g, extra, getattr(src, extra))
        out.append(g)
    return out[0], out[1]


def _build_bidirectional(scene: Scene, dt: float, geom, pp, substeps, info) -> Simulation:
    from fpd.machines.orbit import BidirectionalTestMachine
    from fpd.mechanics.bidirectional import BidirectionalStepper

    ld = scene["loading"]
    loading = bidirectional_loading_of(scene, dt)
    if ld["kind"] == "displacement":
        axial = None
        if ld["vertical"] != "riding-mass":
            from fpd.loading.axial import AxialError, programme_of
            try:
                axial = programme_of(ld, geom.mass * geom.g)
            except AxialError as exc:
                raise SceneError(f"{exc} (loading.vertical_file)") from None
        mech = BidirectionalTestMachine(geom, loading, axial=axial)
        if ld.get("link_stiffness_N_per_m"):
            mech.set_link(ld["link_stiffness_N_per_m"], ld["link_mass_kg"])
        n_steps = loading.n_steps
    else:
        gx, gy = loading
        model = "seated" if scene["mechanics"]["model"] == "seated" else "two-phase"
        gz = vertical_loading_of(scene, dt, gx)
        mech = BidirectionalStepper(geom, gx, gy, normal_force=scene["mechanics"]["normal_force"], model=model,
                                    rim=rim_of(scene), gz=gz)
        n_steps = gx.n_steps
        if gz is not None and hasattr(gz, "vertical_scale"):
            info["record_z"] = vertical_info(gz, ld, gx)
        for comp, g in (("record", gx), ("record_y", gy), ("record_z", gz)):
            if g is not None and hasattr(g, "record") and not hasattr(g, "vertical_scale"):
                info[comp] = {"name": g.name, "points": len(g.record.t), "dt_s": g.record.dt,
                              "pga_g": g.record.pga_g, "scale": ld["scale"],
                              "scaled_pga_g": g.record.pga_g * ld["scale"] * _target_factor(ld, gx.record),
                              "baseline_b1_mps2": g.baseline[0], "baseline_b2_mps3": g.baseline[1]}
        if ld["kind"] == "record":
            info["record"]["angle_deg"] = ld["angle_deg"]
    info["bidirectional"] = {"normal_force": mech.normal_force}
    laws = (make_law(scene.friction("lower")), make_law(scene.friction("upper")))
    _set_static(scene, mech)
    plates = tuple(make_plate(p, dt / substeps) for p in pp)
    sim = Simulation(scene, dt, n_steps, geom, mech, laws, plates, pp, substeps=substeps, info=info)
    from .fast_loop import warm
    warm(sim)           # load the compiled engine now, not after the run's folder is made
    return sim


# -- the triple friction pendulum (model.md 6) and the flat bearing (model.md 7) ---------

def build_tfp(scene: Scene) -> Simulation:
    from fpd.mechanics.tfp import TFPStepper
    from fpd.schema.scene import tfp_geometry

    dt = scene["solver"]["dt"]
    geom = tfp_geometry(scene.data)
    from fpd.schema.scene import is_bidirectional
    if is_bidirectional(scene.data):
        return _build_tfp3d(scene, dt, geom)
    loading = loading_of(scene, dt)
    gz = vertical_loading_of(scene, dt, loading)
    axial = None
    if scene["loading"]["kind"] == "displacement":
        from fpd.loading.axial import AxialError, programme_of
        try:
            axial = programme_of(scene["loading"], geom.weight)
        except AxialError as exc:
            raise SceneError(f"{exc} (loading.vertical_file)") from None
    mech = TFPStepper(geom, loading, model=scene["mechanics"]["model"], gz=gz, axial=axial)
    _tfp_statics(scene, mech)
    dev = scene["device"]
    feet = (dev["slider_diameter"] / 2, dev["pad_diameter"] / 2, dev["pad_diameter"] / 2, dev["slider_diameter"] / 2)
    pp = tuple(PlateParams(**scene.thermal(part), a_contact_m=a) for part, a in zip(TFP_PARTS, feet))
    sub = scene["coupling"]["substeps"]
    plates = tuple(make_plate(p, dt / sub) for p in pp)
    laws = tuple(make_law(scene.friction(s)) for s in TFP_SURFACES)
    info = {"device": "TFP", "capacity_m": geom.capacity}
    if hasattr(loading, "record"):
        info["record"] = record_info(scene, loading)
    if gz is not None:
        info["record_z"] = vertical_info(gz, scene["loading"], loading)
    sim = Simulation(scene, dt, loading.n_steps, geom, mech, laws, plates, pp, substeps=sub, info=info)
    from .fast_loop import warm
    warm(sim)           # load the compiled engine now, not after the run's folder is made
    return sim


def _tfp_parts(scene: Scene, dt: float):
    dev = scene["device"]
    feet = (dev["slider_diameter"] / 2, dev["pad_diameter"] / 2, dev["pad_diameter"] / 2, dev["slider_diameter"] / 2)
    pp = tuple(PlateParams(**scene.thermal(part), a_contact_m=a) for part, a in zip(TFP_PARTS, feet))
    sub = scene["coupling"]["substeps"]
    plates = tuple(make_plate(p, dt / sub) for p in pp)
    laws = tuple(make_law(scene.friction(s)) for s in TFP_SURFACES)
    return pp, plates, laws, sub


def _tfp_statics(scene: Scene, mech) -> None:
    """The breakaway of S1..S4 (friction.mu_static, static_ratio, a liner's) on a TFP stepper."""
    statics = [static_mu(scene.friction(s)) for s in TFP_SURFACES]
    if any(m > 0.0 or r > 0.0 for m, r in statics):
        mech.set_static([m for m, _ in statics], [r for _, r in statics])


def _build_tfp3d(scene: Scene, dt: float, geom) -> Simulation:
    """The TFP in both horizontal directions (mechanics/tfp3d.py): a record pair or a turned record."""
    from fpd.mechanics.tfp3d import TFP3DStepper

    ld = scene["loading"]
    loading = bidirectional_loading_of(scene, dt)
    # an orbit (or a turned sine) on the test machine, or a ground-motion pair
    gx, gy = (loading, None) if ld["kind"] == "displacement" else loading
    # the vertical component (a record, a V2 file's vertical channel or a scaled copy of x as run): not turned
    gz = vertical_loading_of(scene, dt, gx)
    if scene["mechanics"]["model"] == "two-phase":
        from fpd.mechanics.tfp3d_two_phase import TFP3DTwoPhaseStepper
        mech = TFP3DTwoPhaseStepper(geom, gx, gy, kernel=_tfp3d_kernel(gx.n_steps, "tfp3d_two_phase_kernel"),
                                    az=None if gz is None else gz.a_step)
    else:
        mech = TFP3DStepper(geom, gx, gy, kernel=_tfp3d_kernel(gx.n_steps), az=None if gz is None else gz.a_step)
    _tfp_statics(scene, mech)
    pp, plates, laws, sub = _tfp_parts(scene, dt)
    info = {"device": "TFP", "capacity_m": geom.capacity}
    for comp, g in (("record", gx), ("record_y", gy)):
        if g is not None and hasattr(g, "record"):
            info[comp] = _record_info(g, ld, gx)
    if "record" in info:
        info["record"]["angle_deg"] = ld["angle_deg"]
    if gz is not None:
        info["record_z"] = vertical_info(gz, ld, gx)
    return Simulation(scene, dt, gx.n_steps, geom, mech, laws, plates, pp, substeps=sub, info=info)


def _tfp3d_kernel(n_steps: int, name: str = "tfp3d_kernel"):
    """The compiled step of the TFP in both directions (the kernel module
    mechanics/<name>) past a few hundred steps (its Python step costs ~6 ms),
    when numba is there; else the pure one."""
    from fpd import kernels
    if n_steps >= 500 and kernels.available():
        return kernels.compiled("fpd.mechanics." + name)
    return None


def build_flat(scene: Scene) -> Simulation:
    """The flat double bearing (mechanics/flat.py): two interfaces."""
    from fpd.mechanics.flat import FlatGeometry, FlatStepper

    dt = scene["solver"]["dt"]
    dev = scene["device"]
    geom = FlatGeometry(dev["pad_height"], dev["pad_diameter"], dev["pad_mass"], scene["superstructure"]["mass"])
    loading = loading_of(scene, dt)
    gz = vertical_loading_of(scene, dt, loading)
    axial = None
    if scene["loading"]["kind"] == "displacement":
        from fpd.loading.axial import AxialError, programme_of
        try:
            axial = programme_of(scene["loading"], geom.weight)
        except AxialError as exc:
            raise SceneError(f"{exc} (loading.vertical_file)") from None
    mech = FlatStepper(geom, loading, gz=gz, rim=rim_of(scene), axial=axial)
    _set_static(scene, mech)
    sub = scene["coupling"]["substeps"]
    pp = (plate_params(scene, "lower"), plate_params(scene, "upper"))
    plates = tuple(make_plate(p, dt / sub) for p in pp)
    laws = (make_law(scene.friction("lower")), make_law(scene.friction("upper")))
    info = {"device": "flat", "mu_tip_closed_form": geom.mu_tip()}
    if hasattr(loading, "record"):
        info["record"] = record_info(scene, loading)
    if gz is not None:
        info["record_z"] = vertical_info(gz, scene["loading"], loading)
    sim = Simulation(scene, dt, loading.n_steps, geom, mech, laws, plates, pp, substeps=sub, info=info)
    from .fast_loop import warm
    warm(sim)           # load the compiled engine now, not after the run's folder is made
    return sim
