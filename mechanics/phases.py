"""Step labels shared by the mechanics steppers (architecture.md: the code is the index).

stick: the joints hold over the step (no relative motion at its end);
slip:  both interfaces slide under the capped friction (two-phase step);
tilt:  the pad rocks on a bottom corner (model.md section 3, Eq. 7).
"""
PHASES = ("stick", "slip", "tilt")
STICK, SLIP, TILT = 0, 1, 2

# Loaded pad diagonal of the two-phase step: pivot A with top corner C for
# motion to +x, pivot B with top corner D on reversal (paper, Fig. 4e-h).
DIAGONALS = ("A-C", "B-D")
DIAGONAL_AC, DIAGONAL_BD = 0, 1
