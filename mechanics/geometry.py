"""Planar geometry of the double (DFP) and single (SFP) friction pendulum.

Conventions (model.md section 1): x horizontal, z up, angles counter-clockwise.
RB1 lower plate: concave surface of radius R1, centre C1 = (x_g, R1), lowest
point at (x_g, 0). RB3+4 upper plate with the superstructure: concave surface
of radius R2 centred at C2 = (x_s, z_s - R2), (x_s, z_s) its apex. The pad
(RB2) has a bottom arc of radius R1 and a top arc of radius R2; in its body
frame (origin at the bottom apex O, axis eta along the pad) the bottom arc is
centred at (0, R1), the top arc at (0, h - R2), and the corners sit at
xi = +-a on each arc.

Seated (geometrically compatible): the arc centres coincide with C1 and C2,
|C1 C2| = L, and one angle theta describes the whole device:
u = L sin(theta), uplift = L (1 - cos(theta)), the pad axis is rotated by
+theta, arc slid on the lower surface R1 theta, on the upper R2 theta.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from fpd.loading.ground_motion import G_ACC  # noqa: F401 (m/s2, standard gravity; the unit of records in g)


@dataclass(frozen=True)
class DeviceGeometry:
    """Device and superstructure as one seated one-DOF system.

    kind: "DFP" (rigid pad between two concave plates) or "SFP" (articulated
    slider on one concave surface of radius R1, pivot ``pad_height`` above
    the surface, so L = R_eff = R1 - h; the articulation carries no friction).
    """

    kind: str
    R1: float
    R2: float
    pad_height: float
    pad_diameter: float
    pad_mass: float
    mass: float  # superstructure M (kg)
    g: float = G_ACC

    # -- sizes ---------------------------------------------------------
    @property
    def a(self) -> float:
        """Pad half-width a = D / 2 (m)."""
        return 0.5 * self.pad_diameter

    @property
    def h(self) -> float:
        return self.pad_height

    @property
    def L(self) -> float:
        """Distance between the centres of curvature when seated (m)."""
        if self.kind == "SFP":
            return self.R1 - self.pad_height
        return self.R1 + self.R2 - self.pad_height

    @property
    def friction_radius2(self) -> float:
        """Lever arm of the upper friction about C2: R2 (DFP), 0 (SFP)."""
        return 0.0 if self.kind == "SFP" else self.R2

    @property
    def pad_centroid_height(self) -> float:
        """Height of the pad centroid above its bottom apex, along its axis."""
        return 0.5 * self.pad_height

    @property
    def rho(self) -> float:
        """Distance from C1 to the pad centroid, along the pad axis (m)."""
        return self.R1 - self.pad_centroid_height

    @property
    def pad_inertia(self) -> float:
        """Centroidal moment of inertia J of the pad about the y axis (kg m2):
        a solid cylinder of radius a and height h, m (3 a^2 + h^2) / 12."""
        return self.pad_mass * (3.0 * self.a ** 2 + self.pad_height ** 2) / 12.0

    @property
    def I(self) -> float:
        """Generalised inertia of the seated system, M L^2 + m rho^2 + J."""
        return self.mass * self.L ** 2 + self.pad_mass * self.rho ** 2 + self.pad_inertia

    @property
    def S(self) -> float:
        """First moment M L + m rho: gravity and ground-acceleration coupling."""
        return self.mass * self.L + self.pad_mass * self.rho

    @property
    def weight(self) -> float:
        """W = M g (N)."""
        return self.mass * self.g

    @property
    def contact_area(self) -> float:
        """Pad footprint area pi a^2 (m2)."""
        return math.pi * self.a ** 2

    # -- seated configuration -------------------------------------------
    def seated_angle(self, u: float) -> float:
        """theta for a relative displacement u = L sin(theta)."""
        return math.asin(u / self.L)

    def seated(self, theta: float, xg: float = 0.0) -> dict:
        """Positions of the seated device at angle theta, ground at xg.

        Returns a dict of numpy 2-vectors: C1, C2, apex (superstructure
        apex of the upper surface), O (pad bottom apex), axis (unit pad axis),
        G (pad centroid), and the pad rotation angle ``pad_angle`` (= theta).
        """
        s, c = math.sin(theta), math.cos(theta)
        C1 = np.array([xg, self.R1])
        axis = np.array([-s, c])
        C2 = C1 - self.L * axis
        R2 = 0.0 if self.kind == "SFP" else self.R2
        apex = C2 + np.array([0.0, R2]) if self.kind == "DFP" else C2.copy()
        O = C1 - self.R1 * axis
        G = O + self.pad_centroid_height * axis
        return {"C1": C1, "C2": C2, "apex": apex, "O": O, "axis": axis,
                "G": G, "pad_angle": theta}

    def pad_corners_body(self) -> dict:
        """Corner coordinates (xi, eta) in the pad body frame.

        A, B on the bottom arc at xi = -a, +a; C, D on the top arc at
        xi = +a, -a. Diagonals are A-C and B-D.
        """
        a, h = self.a, self.pad_height
        eb = self.R1 - math.sqrt(self.R1 ** 2 - a ** 2)
        R2 = self.R2 if self.kind == "DFP" else self.R1
        et = h - R2 + math.sqrt(R2 ** 2 - a ** 2)
        return {"A": (-a, eb), "B": (a, eb), "C": (a, et), "D": (-a, et)}

    def to_world(self, O: np.ndarray, angle: float, xi: float, eta: float) -> np.ndarray:
        """World position of the body-frame point (xi, eta) of a pad whose
        bottom apex is at O and whose axis is rotated by ``angle``."""
        s, c = math.sin(angle), math.cos(angle)
        return np.array([O[0] + c * xi - s * eta, O[1] + s * xi + c * eta])


def geometry_errors(g: DeviceGeometry) -> list[tuple[str, float, str]]:
    """Reasons the pad does not fit, as (key, value, what is allowed)."""
    out = []
    if g.kind == "SFP":
        if g.pad_height >= g.R1:
            out.append(("device.pad_height", g.pad_height, f"< R1 = {g.R1}"))
        if g.a >= g.R1:
            out.append(("device.pad_diameter", g.pad_diameter, f"< 2 R1 = {2 * g.R1}"))
        return out
    if g.a >= min(g.R1, g.R2):
        out.append(("device.pad_diameter", g.pad_diameter,
                    f"< 2 min(R1, R2) = {2 * min(g.R1, g.R2)}"))
        return out
    if g.pad_height >= g.R1 + g.R2:
        out.append(("device.pad_height", g.pad_height, f"< R1 + R2 = {g.R1 + g.R2}"))
        return out
    c = g.pad_corners_body()
    # corners clear: the top corners must lie above the bottom corners
    if c["C"][1] <= c["B"][1]:
        out.append(("device.pad_height", g.pad_height,
                    "tall enough that the top corners clear the bottom corners "
                    f"(> {c['B'][1] - (c['C'][1] - g.pad_height):.4g} m for this diameter)"))
    return out
