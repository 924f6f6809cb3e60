"""The paper's two-phase model of the TFP in both horizontal directions: the
stepper around mechanics/tfp3d_two_phase_kernel.py (docs/model.md 6.9).

The seated 3D TFP's stepper (mechanics/tfp3d.py) with the two-phase step:
phase 1 in the metric frozen at t_n, the re-seating of phases 2 and 3 a
projection whose loss is E_reseat_J, the phase-1 pivots in the plane of each
pair's slide. A ground motion (a record pair, a turned record) or the test
machine's orbit; a record with no y component is the planar two-phase TFP's run.
"""
from __future__ import annotations

import numpy as np

from . import tfp3d_kernel as K3
from . import tfp3d_two_phase_kernel as K
from . import tfp_kernel as TK
from .tfp3d import COLUMNS as SEATED_COLUMNS, TFP3DFailure, TFP3DStepper

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
        S = np.zeros(K.N_S)
        S[:K3.N_S] = self.S
        self.S = S
        self.N = self.S[K3.S_N:K3.S_N + 4]
        self.out = np.zeros(K.N_OUT)
        self._row = np.zeros(K.N_ROW)

    @property
    def E_reseat(self) -> float:
        """Kinetic energy removed by the re-seating of phases 2 and 3."""
        return float(self.S[K.S_ERS])

    def ledger_residual(self) -> float:
        return self.E_in - (self.E_kin() + self.E_pot() + sum(self.W) + self.E_reseat)

    def values(self) -> tuple:
        n = self.n
        K.row_values(self.par, self.S, self.t, self._xg[n], self._yg[n], self._row, self._sc)
        return tuple(self._row.tolist())

    def step(self, mu1: float, mu2: float, mu3: float, mu4: float) -> tuple:
        n = self.n
        fail = self.k.advance(self.par, self.S, self.dt, self._ax[n], self._ay[n], self._az[n],
                              mu1, mu2, mu3, mu4, 1 if self.machine else 0, self._ux[n + 1], self._uy[n + 1],
                              self._udx[n + 1], self._udy[n + 1], self.out, self._sc)
        if fail == K3.FAIL_CAPACITY:
            raise TFP3DFailure("the test machine's force did not make the bearing follow the orbit "
                               "(Newton on the machine's force did not converge; lower solver.dt)")
        if fail == K.FAIL_ROCKING:
            q = self.S[0:4]
            ax, ay = self._ax[n], self._ay[n]
            gv = self.geom.g + self._az[n]
            part = "pad" if K.rocking_from_rest(self.par, q, ax, ay, gv) == 1 else "slider plates"
            raise TFP3DFailure(f"the {part} would start rocking on a corner (ground acceleration "
                               f"{float(np.hypot(ax, ay)) / gv:.3g} (g + a_z) beyond the restoring moment of "
                               "Eq. 7): rocking of the TFP's parts is not modelled (docs/model.md 6.6)")
        if fail == K3.FAIL_RIM:
            raise TFP3DFailure("a surface reached its rim: rim impacts of the TFP in both directions are not "
                               "modelled yet (the planar TFP has them)")
        if fail == K3.FAIL_FIXED_POINT:
            raise TFP3DFailure(f"the step's fixed point on q(t_n+1) did not converge in {K3.FIXED_POINT_ITERS} "
                               "iterations (lower solver.dt)")
        self.n = n + 1
        self.t = self.n * self.dt
        return tuple(float(x) for x in self.S[K3.S_DW:K3.S_DW + 4])


assert TK.FAIL_ROCKING == K.FAIL_ROCKING
