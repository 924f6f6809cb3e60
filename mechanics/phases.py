"""Phase labels and failure types of the mechanics steppers (architecture.md:
the code is the index).

stick: the joints hold (no relative motion at the end of the step);
slip:  both interfaces slide under the capped friction (two-phase step);
tilt:  the pad rocks on a bottom corner (model.md section 3, Eq. 7).
"""
PHASES = ("stick", "slip", "tilt")
STICK, SLIP, TILT = 0, 1, 2
# the TFP (mechanics/tfp.py) appends its own: which surfaces slide (inner S2+S3, outer S1+S4, all four)
TFP_PHASES = PHASES + ("inner", "outer", "inner+outer")
INNER, OUTER, BOTH = 3, 4, 5

# the seated DFP / SFP model's columns in the plane (the planar test machine's; the stepper in both
# directions writes them for a planar run)
SEATED_COLUMNS = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad",
                  "s1_m", "s2_m", "N1_N", "N2_N", "W1_J", "W2_J", "phase",
                  "E_input_J", "E_kin_J", "E_pot_J")

# Loaded pad diagonal of the two-phase step: pivot A with top corner C for
# motion to +x, pivot B with top corner D on reversal (paper, Fig. 4e-h).
DIAGONALS = ("A-C", "B-D")
DIAGONAL_AC, DIAGONAL_BD = 0, 1


class MechanicsFailure(RuntimeError):
    """A state the mechanics model cannot continue from (e.g. an overturned
    pad): the run stops as a numerical failure, keeping its history."""


class PadOverturned(MechanicsFailure):
    """The rocking pad passed the angle where gravity stops restoring it."""
