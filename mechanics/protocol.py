"""What every stepper offers the coupled loop (docs/architecture.md, "Stepper
protocol"), for the steppers with two interfaces written with named slots
(N1, N2, slip_v1, slip_v2, s1, s2): the per-interface sequences the loop
reads, whatever the device.

    n_interfaces            1, 2 or 4
    drawing                 the device's VTK drawing (outputs/device_drawings.py), by name
    N, slip_v               per interface: normal force (N), sliding speed (m/s)
    footprints()            per interface: footprint centre on its plate (m; a pair (x, y) when two_d)
    step(*mu) -> dW         one step with mu_i held; friction work per interface (J)
"""
from __future__ import annotations


class TwoInterfaces:
    """N, slip_v and footprints() of a two-interface stepper: the lower plate
    (interface 1) at +s1, the upper (interface 2) at -s2 on a planar path."""

    n_interfaces = 2
    two_d = False             # footprint centres are pairs (x, y) (bidirectional steppers)
    engine_device = None      # the kernel module the compiled engine binds (coupling/engine_kernel.py)

    @property
    def drawing(self) -> str:
        """How the VTK series draws the device (a name of
        outputs/device_drawings.DRAWINGS): in the x-z plane, or in 3D when
        the motion has both directions."""
        return "spatial" if self.two_d else "planar"

    @property
    def N(self) -> tuple:
        return (self.N1, self.N2)

    @property
    def slip_v(self) -> tuple:
        return (self.slip_v1, self.slip_v2)

    def footprints(self) -> tuple:
        return (self.s1, -self.s2)
