"""Parameters of one plate's thermal model (the ``[thermal]`` scene table)."""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class PlateParams:
    """One steel plate and the thermal model chosen for it.

    Geometry: a disk of radius ``plate_radius`` and thickness
    ``plate_thickness`` (fe3d: the square of the same area, side
    sqrt(pi) R); the sliding face is the top face (z = 0 in the FE
    models, depth measured into the plate). The pad's contact footprint is a
    disk of radius ``a_contact_m`` (the pad radius, D / 2).
    """

    model: str = "lumped"            # none | lumped | fe1d | axisym | fe3d
    source: str = "follow-pad"       # follow-pad | fixed-point
    radius_m: float = 0.0            # fixed-point: radius r0 of the material point
    T0_C: float = 20.0
    T_air_C: float = 20.0
    heat_share: float = 1.0          # eta: share of the friction heat taken by this plate
    plate_thickness: float = 0.05    # m
    plate_radius: float = 0.40       # m
    k: float = 16.0                  # W/m/K
    rho: float = 7850.0              # kg/m3
    c: float = 500.0                 # J/kg/K
    h_conv: float = 10.0             # W/m2/K, sliding face (exposed part) and back face
    back: str = "convection"         # convection | adiabatic | fixed (back face at T_back_C)
    T_back_C: float = 20.0
    exchange_area_m2: float = 0.0    # lumped: area A_i of Eq. (10); 0 -> the plate's top face
    n_elements: int = 100            # fe1d: elements through the thickness
    grading: float = 1.05            # fe1d/axisym: geometric ratio of element sizes away from the sliding face
    nr: int = 0                      # axisym: elements in r; 0: automatic (per_radius over the swept band, graded beyond)
    per_radius: int = 20             # axisym (nr = 0) and fe3d: elements per footprint radius where the footprint goes
    step_multiple: int = 10          # fe3d: one thermal step every step_multiple mechanical steps
    nz: int = 60                     # axisym: elements in z (60 with grading 1.05: 0.06 K on the 1 MW/m2, 10 s check)
    scheme: str = "bdf2"             # bdf2 | cn | be
    mesh_file: str = ""              # axisym: a user's r-z mesh (any meshio format)
    a_contact_m: float = 0.125       # pad footprint radius (m), from [device]
    # not scene keys: set by coupling/build.py from the loading
    sweep_m: float = -1.0            # largest |centre| the footprint reaches (m); < 0: anywhere on the plate
    sweep_y_m: float = 0.0           # fe3d: largest |y| of the path (bidirectional runs); 0: a planar path

    @property
    def contact_area(self) -> float:
        """Pad footprint area A_c = pi a^2 (m2)."""
        return math.pi * self.a_contact_m ** 2

    @property
    def diffusivity(self) -> float:
        """kappa = k / (rho c) (m2/s)."""
        return self.k / (self.rho * self.c)

    @property
    def mass(self) -> float:
        """Plate mass M_i = rho pi R^2 t (kg), the paper's M_i."""
        return self.rho * math.pi * self.plate_radius ** 2 * self.plate_thickness
