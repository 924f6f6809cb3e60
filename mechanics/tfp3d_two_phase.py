"""The paper's two-phase model of the TFP in both horizontal directions: the
stepper around mechanics/tfp3d_two_phase_kernel.py (docs/model.md 6.9).

The seated 3D TFP's stepper (mechanics/tfp3d.py) with the two-phase step:
phase 1 in the metric frozen at t_n, the re-seating of phases 2 and 3 a
projection whose loss is E_reseat_J, the phase-1 pivots in the plane of each
pair's slide. A ground motion (a record pair, a turned record) or the test
machine's orbit; a record with no y component is the planar two-phase TFP's run.
Under a vertical ground motion (az) the normal forces, caps, heat, the rocking
check and the re-seating see g + a_z, and when g + a_z < 0 the stack and the
superstructure lift off, fly and land as the seated 3D TFP's (docs/model.md 10).
"""
from __future__ import annotations

import numpy as np

from . import tfp3d_kernel as K3
from . import tfp3d_two_phase_kernel as K
from . import tfp_kernel as tk
from .tfp3d import COLUMNS as SEATED_COLUMNS, VERTICAL_COLUMNS, TFP3DFailure, TFP3DStepper

# the two-phase model's own columns, after the seated 3D TFP's: the re-seating
# loss, the phase-1 pivots and the re-seating rotations as tilt vectors along
# each pair's slide (the pad's beta, the slider plates' gamma), the phases
TWO_PHASE_COLUMNS = ("E_reseat_J", "beta1x_rad", "beta1y_rad", "beta2x_rad", "beta2y_rad",
                     "gamma1x_rad", "gamma1y_rad", "gamma2x_rad", "gamma2y_rad", "phases")
COLUMNS = SEATED_COLUMNS + TWO_PHASE_COLUMNS
assert len(COLUMNS) == K.N_ROW


class TFP3DTwoPhaseStepper(TFP3DStepper):
    """The two-phase TFP under a two-component ground motion or on the test
    machine along an orbit (gx, gy as TFP3DStepper's)."""

    columns = COLUMNS
    model = "two-phase"
    engine_device = "fpd.mechanics.dev_tfp3d_two_phase"

    def __init__(self, geom, gx, gy=None, kernel=None, az=None):
        super().__init__(geom, gx, gy, kernel=kernel if kernel is not None else K, az=az)
        self.par = geom.pack(two_phase=True)
        if az is not None:
            # the vertical columns after the two-phase model's (tfp3d_two_phase_kernel.vertical_row)
            self.par[tk.I_VERT] = 1.0
            self.columns = COLUMNS + VERTICAL_COLUMNS
        S = np.zeros(K.N_S)
        S[:K3.N_S] = self.S
        self.S = S
        self.N = self.S[K3.S_N:K3.S_N + 4]
        self.out = np.zeros(K.N_OUT)
        self._row = np.zeros(len(self.columns))

    RIM_MESSAGE = ('a surface reached its rim: the two-phase TFP in both directions has no rim impacts yet '
                   '(mechanics.model = "seated" takes them; docs/model.md 6.11)')

    @property
    def E_reseat(self) -> float:
        """Kinetic energy removed by the re-seating of phases 2 and 3."""
        return float(self.S[K.S_ERS])

    def ledger_residual(self) -> float:
        return self.E_in - (self.E_kin() + self.E_pot() + sum(self.W) + self.E_rim + self.E_reseat + self.E_land)

    def values(self) -> tuple:
        n = self.n
        K.row_values(self.par, self.S, self.t, self._xg[n], self._yg[n], self._row, self._sc)
        K.vertical_row(self.par, self.S, self._az[n - 1] if n > 0 else 0.0, self._row, self._sc)
        return tuple(self._row.tolist())

    def step(self, mu1: float, mu2: float, mu3: float, mu4: float) -> tuple:
        """TFP3DStepper.step with this kernel (whose advance has the same
        arguments and failures), and the rocking check from rest."""
        n = self.n
        dW = super().step(mu1, mu2, mu3, mu4)
        if self.S[K.S_NPH] < 0.0:
            self.n, self.t = n, n * self.dt          # the step is not taken (as the planar TFP's)
            ax, ay, gv = self._ax[n], self._ay[n], self.geom.g + self._az[n]
            part = "pad" if K.rocking_from_rest(self.par, self.S[0:4], ax, ay, gv) == 1 else "slider plates"
            raise TFP3DFailure(f"the {part} would start rocking on a corner (ground acceleration "
                               f"{float(np.hypot(ax, ay)) / gv:.3g} (g + a_z) beyond the restoring moment of "
                               "Eq. 7): rocking of the TFP's parts is not modelled (docs/model.md 6.6)")
        return dW

