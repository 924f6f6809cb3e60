"""Units and meanings of every scene key, output column and summary.json field.

The one place to describe a name: docs/reference.md is generated from this
module and the schema in coupling/scene.py (``fpd reference``, or
``python -m fpd.coupling.reference``), and tests/test_reference.py fails when
a schema key, a column or a summary field has no entry here, when an entry
names something that no longer exists, or when the committed reference is
out of date. Adding a scene key, a column or a summary field therefore means:
declare it (scene.py / the stepper / output.py), describe it here, regenerate
the reference.

Each entry is ``(unit, meaning)``; unit ``""`` for dimensionless, text or
flags. Scene keys are dotted as in ``--set``; a key whose meaning depends on
the table's ``law`` / ``kind`` may be described per variant as
``"friction.<law>.<key>"`` / ``"loading.<kind>.<key>"``, which takes
precedence over ``"friction.<key>"`` / ``"loading.<key>"``. Summary fields are
dotted paths into summary.json, ``*`` standing for a plate (``lower`` /
``upper``).
"""
from __future__ import annotations

# -- exit status of the fpd command ---------------------------------------------------------
EXIT: dict[int, str] = {
    0: "Success.",
    1: "Numerical failure (non-finite state, coupling not converged, the pad overturned), with the step and "
       "time on stderr; the results folder holds the history up to it (status \"failed\"). Studies: a case failed.",
    2: "Bad input (scene, file, option, results folder): one line on stderr naming the file, the key, the "
       "value and what is allowed; no results folder is written.",
    130: "Interrupted (Ctrl-C, SIGTERM); the results folder holds the history up to then (status "
         "\"interrupted\").",
}

# -- scene keys ----------------------------------------------------------------------------
KEYS: dict[str, tuple[str, str]] = {
    "name": ("", "Scene name; names the results folder (`results/<name>/`). Default: the file's stem."),
    "description": ("", "One line shown by `fpd scenes`."),

    # [device]
    "device.kind": ("", '"DFP": planar double friction pendulum (two concave plates, one rigid pad); '
                        '"SFP": single friction pendulum (seated model only; R1 is its concave radius, '
                        'pad_height its pivot height).'),
    "device.R1": ("m", "Radius of the lower concave sliding surface."),
    "device.R2": ("m", "Radius of the upper concave sliding surface (required for a DFP; an SFP takes R1)."),
    "device.pad_height": ("m", "Pad height h, apex to apex along the pad axis."),
    "device.pad_diameter": ("m", "Pad diameter D = 2a; the contact footprint is a disk of radius a on each plate."),
    "device.pad_mass": ("kg", "Pad mass; default: a solid steel cylinder of the pad's size (7850 kg/m3)."),
    "superstructure.mass": ("kg", "Mass carried by the bearing (its weight is the vertical load)."),

    # [friction] (both interfaces; [friction.lower] / [friction.upper] override per interface)
    "friction.law": ("", 'The friction law mu(T, p, v) of the interface; each law has its own keys below. '
                         'Default "constant".'),
    "friction.constant.mu": ("", "Friction coefficient."),
    "friction.linear.mu0": ("", "mu at T0_C."),
    "friction.linear.T0_C": ("degC", "Reference temperature of the linear law."),
    "friction.linear.slope_per_C": ("1/degC", "d mu / dT: mu = mu0 + slope_per_C (T - T0_C)."),
    "friction.linear.mu_min": ("", "Lower bound of mu."),
    "friction.kumar2015.mu_ref": ("", "mu at the reference pressure, 20 degC and high velocity "
                                      "(Kumar, Whittaker and Constantinou 2015: mu = mu_ref k_p k_T k_v)."),
    "friction.kumar2015.p_ref_MPa": ("MPa", "Reference contact pressure of k_p = 0.70^((p - p_ref) / 50 MPa)."),
    "friction.kumar2015.a_s_per_m": ("s/m", "Rate parameter of k_v = 1 - 0.5 exp(-a v)."),
    "friction.kumar2015.use_pressure": ("", "Apply the pressure factor k_p (else 1)."),
    "friction.kumar2015.use_temperature": ("", "Apply the temperature factor k_T = 0.79 (0.70^(T / 50 C) + 0.40) "
                                               "(else 1): 1.00 at 20 C, 0.70 at 100 C."),
    "friction.kumar2015.use_velocity": ("", "Apply the velocity factor k_v (else 1)."),
    "friction.table.T_C": ("degC", "Temperatures of the table, strictly increasing."),
    "friction.table.mu": ("", "mu at each T_C (piecewise linear between, constant beyond the ends)."),

    # [loading]
    "loading.kind": ("", '"record": ground acceleration record; "harmonic": sinusoidal ground motion; '
                         '"displacement": bearing-test machine imposing the relative displacement; '
                         '"pulse": analytic ground-velocity pulse; "heat": thermal only, a prescribed flux.'),
    "loading.record.record": ("", "A packaged record by name (give record or file)."),
    "loading.record.file": ("", "A record file (path relative to the scene file): PEER .AT2 (old and NGA-West2 "
                                "headers) or two-column time-acceleration text; format guessed from content."),
    "loading.record.scale": ("", "Factor on the record's accelerations (non-zero; negative flips it)."),
    "loading.record.units": ("", "Acceleration units of a two-column text record (.AT2 files say g)."),
    "loading.record.baseline": ("", "Quadratic-velocity baseline correction of the integrated record "
                                    "(docs/model.md, Loading)."),
    "loading.amplitude_m": ("m", "Amplitude of the sine."),
    "loading.harmonic.amplitude_m": ("m", "Amplitude of the ground displacement."),
    "loading.displacement.amplitude_m": ("m", "Amplitude of the imposed relative displacement (< L, the pad's "
                                              "reach)."),
    "loading.frequency_Hz": ("Hz", "Frequency of the sine."),
    "loading.cycles": ("", "Number of cycles; the loading lasts cycles / frequency_Hz."),
    "loading.displacement.waveform": ("", "Shape of the imposed relative displacement."),
    "loading.pulse.shape": ("", '"step": the ground velocity jumps to velocity_mps at t0_s and stays; "cosine": '
                                'one-sided fling V/2 (1 - cos(2 pi tau / Tp)) for one period; "sine": '
                                'forward-directivity cycle V sin(2 pi tau / Tp).'),
    "loading.pulse.velocity_mps": ("m/s", "Pulse velocity V (either sign)."),
    "loading.pulse.period_s": ("s", "Pulse period Tp (cosine and sine)."),
    "loading.pulse.t0_s": ("s", "Start of the pulse."),
    "loading.pulse.duration_s": ("s", "Length of the loading; default t0_s + period_s + 10."),
    "loading.heat.flux_W_m2": ("W/m2", "Heat flux into the footprint of the heated plate(s)."),
    "loading.heat.duration_s": ("s", "Length of the thermal-only run."),
    "loading.heat.plate": ("", "Which plate receives the flux."),
    "loading.heat.reference": ("", "Closed form that summary.json compares T1_C with (`reference` field): "
                                   "semi-infinite solid, adiabatic-backed slab, disk source on a half-space."),

    # [mechanics]
    "mechanics.model": ("", '"two-phase": the paper\'s rigid-body stepper (stick/slip/tilt, pad rocking); '
                            '"seated": the classical seated model (the pad never tilts). A displacement loading '
                            'always uses the seated test machine.'),

    # [thermal] (both plates; [thermal.lower] / [thermal.upper] override per plate)
    "thermal.model": ("", '"none": no heat; "lumped": the paper\'s lumped plate (Eq. 9-10); "fe1d": conduction '
                          'through the thickness under the pad (scikit-fem); "axisym": r-z conduction in the '
                          'whole plate.'),
    "thermal.source": ("", '"follow-pad": the heated column/footprint moves with the pad; "fixed-point": the '
                           'material point at radius_m, heated only while the footprint covers it (fe1d).'),
    "thermal.radius_m": ("m", "fixed-point source: radius r0 of the material point (<= plate_radius)."),
    "thermal.T0_C": ("degC", "Initial plate temperature."),
    "thermal.T_air_C": ("degC", "Ambient air temperature (convection)."),
    "thermal.heat_share": ("", "Share eta of the interface's friction heat that enters this plate."),
    "thermal.plate_thickness": ("m", "Plate thickness."),
    "thermal.plate_radius": ("m", "Plate radius (>= the pad radius)."),
    "thermal.k": ("W/m/K", "Thermal conductivity of the steel."),
    "thermal.rho": ("kg/m3", "Density."),
    "thermal.c": ("J/kg/K", "Specific heat."),
    "thermal.h_conv": ("W/m2/K", "Convection coefficient of the exposed sliding face and the back face."),
    "thermal.back": ("", "Back face: convection to air, adiabatic, or held at T_back_C."),
    "thermal.T_back_C": ("degC", "Back-face temperature when back = \"fixed\"."),
    "thermal.exchange_area_m2": ("m2", "lumped: exchange area A_i of Eq. (10); 0 means the plate's top face."),
    "thermal.n_elements": ("", "fe1d: elements through the thickness."),
    "thermal.grading": ("", "fe1d/axisym: geometric ratio of element sizes away from the sliding face (1 = uniform)."),
    "thermal.nr": ("", "axisym: elements in r."),
    "thermal.nz": ("", "axisym: elements in z."),
    "thermal.scheme": ("", "FE time scheme: BDF2 (Rannacher-started), Crank-Nicolson, backward Euler."),
    "thermal.mesh_file": ("", "axisym: a user r-z mesh (any meshio format; path relative to the scene); "
                              "empty: the generated mesh."),

    # [coupling]
    "coupling.scheme": ("", '"staggered": mu from the temperatures at the start of the step; "iterated": the '
                            'step repeated with mu at the new temperatures until they change by less than tol_K.'),
    "coupling.tol_K": ("K", "iterated: temperature change that ends the iteration."),
    "coupling.max_iter": ("", "iterated: iterations before the run fails (exit 1)."),
    "coupling.substeps": ("", "Thermal steps per mechanical step (footprint interpolated across them)."),

    # [solver]
    "solver.dt": ("s", "Time step."),
    "solver.duration": ("s", "Length of the run; default: the loading's length."),

    # [output]
    "output.vtk_every": ("", "Steps between VTK frames (vtk/); 0 writes none."),
    "output.plots": ("", "Write plots/ (PNG)."),
    "output.csv_every": ("", "Steps between rows of timeseries.csv (the last step is always written)."),
}

# -- timeseries.csv columns (1 = lower interface / plate, 2 = upper) ------------------------
COLUMNS: dict[str, tuple[str, str]] = {
    "t_s": ("s", "Time."),
    "xg_m": ("m", "Ground displacement (test machine: the fixed base, 0)."),
    "u_m": ("m", "Displacement of the superstructure relative to the ground."),
    "v_mps": ("m/s", "Velocity of the superstructure relative to the ground."),
    "F_N": ("N", "Horizontal force the bearing exerts against the relative displacement (the F-u loop runs "
                 "clockwise; its area is the dissipated energy)."),
    "z_m": ("m", "Uplift of the superstructure."),
    "theta_rad": ("rad", "Seated angle of the line joining the centres of the two surfaces."),
    "beta_rad": ("rad", "Pad rotation about its pivot (rocking), = beta1_rad."),
    "s1_m": ("m", "Footprint centre on the lower plate (arc from the plate centre)."),
    "s2_m": ("m", "Footprint centre on the upper plate (arc from the plate centre)."),
    "N1_N": ("N", "Normal force on the lower interface."),
    "N2_N": ("N", "Normal force on the upper interface."),
    "mu1": ("", "Friction coefficient of the lower interface in the step."),
    "mu2": ("", "Friction coefficient of the upper interface in the step."),
    "T1_C": ("degC", "Sliding-surface temperature of the lower plate (under the pad)."),
    "T2_C": ("degC", "Sliding-surface temperature of the upper plate (under the pad)."),
    "W1_J": ("J", "Cumulative friction work on the lower interface."),
    "W2_J": ("J", "Cumulative friction work on the upper interface."),
    "phase": ("", "State at the end of the step: stick, slip or tilt (the pad rocks or lands)."),
    "E_input_J": ("J", "Cumulative work of the ground (or machine) on the device: "
                       "E_input_J = E_kin_J + E_pot_J + W1_J + W2_J [+ E_reseat_J]."),
    "E_kin_J": ("J", "Kinetic energy of the moving parts relative to the ground."),
    "E_pot_J": ("J", "Potential energy (uplift of the superstructure and pad)."),
    "E_reseat_J": ("J", "Cumulative kinetic energy lost when a rocking pad re-seats (two-phase)."),
    "E_stored_J": ("J", "Heat stored in the plates (above the initial temperature)."),
    "E_air_J": ("J", "Cumulative heat lost to the air (and through the back face)."),
    # two-phase diagnostics (docs/two_phase.md, section 5)
    "beta1_rad": ("rad", "Phase-1 rotation of the pad about its pivot."),
    "beta2_rad": ("rad", "Phase-2 counter-rotation of the pad."),
    "pad_tilt_rad": ("rad", "Pad axis minus the line C1C2 at the end of phase 1."),
    "diagonal": ("", "Diagonal the pad rests on: 0 = A-C, 1 = B-D."),
    "ds1_m": ("m", "Slip increment of the lower interface in the step (signed)."),
    "ds2_m": ("m", "Slip increment of the upper interface in the step (signed)."),
    "Ff1_N": ("N", "Mobilised friction force of the lower interface, referred to the superstructure."),
    "Ff2_N": ("N", "Mobilised friction force of the upper interface, referred to the superstructure."),
    "theta_dot_radps": ("rad/s", "Rate of the seated angle theta."),
    "slip1_m": ("m", "Cumulative sliding path on the lower interface."),
    "slip2_m": ("m", "Cumulative sliding path on the upper interface."),
    "tip_ratio": ("", "Forward-tipping ratio |F_t| h' / (N2 2a) of the step (> 1 is outside the model)."),
}

# -- summary.json fields (dotted paths; * = lower | upper) ------------------------------------
SUMMARY: dict[str, tuple[str, str]] = {
    "status": ("", '"ok", "failed" (numerical failure; the history up to it is kept) or "interrupted".'),
    "message": ("", "Why the run failed or stopped (empty when ok)."),
    "scene": ("", "Scene name."),
    "models.mechanics": ("", 'Mechanics model that ran ("two-phase", "seated", "none" for thermal-only).'),
    "models.thermal_lower": ("", "Thermal model of the lower plate."),
    "models.thermal_upper": ("", "Thermal model of the upper plate."),
    "models.friction_lower": ("", "Friction law of the lower interface."),
    "models.friction_upper": ("", "Friction law of the upper interface."),
    "models.coupling": ("", "Coupling scheme."),
    "steps": ("", "Time steps computed."),
    "dt_s": ("s", "Time step."),
    "runtime_s": ("s", "Time spent stepping (not writing)."),
    "version": ("", "fpd version that wrote the results."),
    "peak_u_m": ("m", "Peak |u_m|."),
    "residual_u_m": ("m", "u_m at the end of the run."),
    "peak_F_N": ("N", "Peak |F_N|."),
    "friction_work_J.lower": ("J", "Friction work on the lower interface (final W1_J)."),
    "friction_work_J.upper": ("J", "Friction work on the upper interface (final W2_J)."),
    "reseat_loss_J": ("J", "Re-seating loss (final E_reseat_J; two-phase)."),
    "input_work_J": ("J", "Work of the ground or machine (final E_input_J)."),
    "energy_residual_rel": ("", "Mechanical ledger |input - (kinetic + potential + friction + re-seating)| / input."),
    "peak_T1_C": ("degC", "Peak T1_C."),
    "peak_T2_C": ("degC", "Peak T2_C."),
    "min_mu1": ("", "Lowest mu1."),
    "min_mu2": ("", "Lowest mu2."),
    "heat.plates.*.heat_in_J": ("J", "Heat delivered to the plate."),
    "heat.plates.*.stored_J": ("J", "Heat stored in the plate at the end."),
    "heat.plates.*.lost_J": ("J", "Heat lost to air and through the back face."),
    "heat.plates.*.residual_rel": ("", "Thermal ledger |in - stored - lost| / in."),
    "heat.plates.*.friction_heat_J": ("J", "Friction work x heat_share of the interface."),
    "heat.plates.*.work_vs_heat_rel": ("", "|friction heat - heat delivered| / friction heat."),
    "heat.plates.*.work_vs_heat": ("", "Why friction heat and heat delivered are not compared (fixed-point source)."),
    "heat.residual_rel": ("", "Worst of the plates' ledger residuals."),
    "heat_residual_rel": ("", "Thermal ledger residual (= heat.residual_rel)."),
    "reference.closed_form": ("", "Closed form of a heat scene's check (loading.reference)."),
    "reference.quantity": ("", "What is compared."),
    "reference.T_end_C": ("degC", "Computed temperature at the end."),
    "reference.T_exact_end_C": ("degC", "Closed-form temperature at the end."),
    "reference.error_end_K": ("K", "Computed minus closed form at the end."),
    "reference.max_abs_error_K": ("K", "Largest |error| over the sampled times."),
    "reference.samples": ("", "Times sampled (up to 50)."),
    "coupling_iterations.total": ("", "iterated coupling: iterations over the run."),
    "coupling_iterations.max_per_step": ("", "iterated coupling: most iterations in one step."),
    "record.name": ("", "Record name (packaged name or file)."),
    "record.points": ("", "Samples in the record."),
    "record.dt_s": ("s", "Record sampling interval."),
    "record.pga_g": ("g", "Peak ground acceleration of the record (unscaled)."),
    "record.scale": ("", "loading.scale applied."),
    "record.baseline_b1_mps2": ("m/s2", "Baseline correction: b1 of the velocity drift b1 t + b2 t^2 removed "
                                        "(the acceleration b1 + 2 b2 t is subtracted)."),
    "record.baseline_b2_mps3": ("m/s3", "Baseline correction: b2 of the velocity drift b1 t + b2 t^2 removed."),
    "plots": ("", "PNG files written in plots/ (fpd run only)."),
}
