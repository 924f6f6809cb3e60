"""Step labels shared by the mechanics steppers (architecture.md: the code is the index).

stick: the joints hold (no relative motion at the end of the step);
slip:  both interfaces slide under the capped friction (two-phase step);
tilt:  the pad rocks on a bottom corner (model.md section 3, Eq. 7).
PHASES itself is defined once, in mechanics.seated.
"""
from .seated import PHASES, SLIP, STICK, TILT, MechanicsFailure  # noqa: F401

# Loaded pad diagonal of the two-phase step: pivot A with top corner C for
# motion to +x, pivot B with top corner D on reversal (paper, Fig. 4e-h).
DIAGONALS = ("A-C", "B-D")
DIAGONAL_AC, DIAGONAL_BD = 0, 1
