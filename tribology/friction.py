"""Friction laws mu(T, p, v) per interface (paper Eq. 8: F_mu = mu(T) N).

Each law is a small callable ``law(T_C, p_Pa, v_mps) -> mu`` evaluated once
per step at the surface temperature the thermal model returns. The
evaluation itself is written once, in tribology/friction_kernel.py (a kernel
module: the compiled loop runs the same source); the classes here hold the
parameters, their defaults and the law's row ``P`` that the kernel reads.
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from functools import partial

from . import friction_kernel as _k


class _Law:
    """A law's parameters and their kernel row (set once, after __init__)."""

    kind = -1

    def __post_init__(self):
        object.__setattr__(self, "P", self.row())
        # the evaluation bound to this law's row: what the Python loop calls
        # (one Python frame less than __call__)
        object.__setattr__(self, "evaluate", partial(_k.law_mu, self.P))

    def row(self) -> list:
        return [float(self.kind)] + [float(getattr(self, f.name)) for f in fields(self)]

    def __call__(self, T_C: float, p_Pa: float = 0.0, v_mps: float = 0.0) -> float:
        return _k.law_mu(self.P, T_C, p_Pa, v_mps)


@dataclass(frozen=True)
class Constant(_Law):
    mu: float
    kind = _k.LAW_CONSTANT


@dataclass(frozen=True)
class Linear(_Law):
    """mu = mu0 + slope (T - T0), never below mu_min."""

    mu0: float
    T0_C: float = 20.0
    slope_per_C: float = 0.0
    mu_min: float = 0.0
    kind = _k.LAW_LINEAR


@dataclass(frozen=True)
class Kumar2015(_Law):
    """Kumar, Whittaker and Constantinou (2015), mu = mu_ref k_p k_T k_v with
    k_p = 0.70^((p - p_ref) / 50 MPa), k_T = 0.79 (0.70^(T / 50 C) + 0.40),
    k_v = 1 - 0.5 exp(-a v). Each factor can be switched off (then 1).
    k_T is 1.00 at 20 C and falls to 0.70 at 100 C, 0.45 at 250 C
    (constants: tribology/friction_kernel.py)."""

    mu_ref: float
    p_ref_MPa: float = 50.0
    a_s_per_m: float = 100.0
    use_pressure: bool = False
    use_temperature: bool = True
    use_velocity: bool = False
    kind = _k.LAW_KUMAR


@dataclass(frozen=True)
class Constantinou1990(_Law):
    """Constantinou, Mokha and Reinhorn (1990): mu = mu_fast - (mu_fast -
    mu_slow) exp(-a |v|): mu_slow at rest, mu_fast at high sliding speed."""

    mu_slow: float
    mu_fast: float
    a_s_per_m: float = 100.0
    kind = _k.LAW_CONSTANTINOU


@dataclass(frozen=True)
class Table(_Law):
    """Piecewise linear in T through (T_C[i], mu[i]), constant beyond the ends."""

    T_C: tuple
    mu: tuple
    kind = _k.LAW_TABLE

    def row(self) -> list:
        n = len(self.T_C)
        if n < 1 or len(self.mu) != n:
            raise ValueError(f"friction table: T_C and mu need the same length >= 1, got {n} and {len(self.mu)}")
        head = [float(self.kind), float(n)] + [0.0] * (_k.N_HEAD - 2)
        return head + [float(x) for x in self.T_C] + [float(x) for x in self.mu]

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "evaluate", self.__call__)      # (raises for a NaN temperature)

    def __call__(self, T_C: float, p_Pa: float = 0.0, v_mps: float = 0.0) -> float:
        mu = _k.law_mu(self.P, T_C, p_Pa, v_mps)
        if mu != mu:
            raise ValueError(f"friction table asked at T = {T_C} degC")
        return mu


LAWS = {"constant": Constant, "linear": Linear, "kumar2015": Kumar2015, "table": Table,
        "constantinou": Constantinou1990}


# keys of a surface beside its law's (schema.scene.SURFACE_KEYS): read by surface_of
SURFACE_KEYS = ("mu_static", "static_ratio", "mu_static_inf", "dwell_time_s", "dwell_exponent",
                "wear_k_mm3_per_Nm", "wear_T_C", "wear_k_T_mm3_per_Nm", "liner")

# liner presets: name -> {"values": the [friction] keys it sets, "sources": per key, where the
# value comes from}. Each source entry: "ref" (a key of LINER_SOURCES, or None), "stated"
# (True: the reference states this number; False: a pick or a basis of ours, which "note"
# gives) and "note" (what the reference says and how the value relates to it). docs/liners.md
# renders this (frontends.reference.liner_markdown); starting points for comparisons, not
# design values: a product's own qualification tests replace them.
LINER_SOURCES = {
    "mokha1990": 'Mokha, A., Constantinou, M. C., Reinhorn, A. M. (1990). "Teflon bearings in base isolation. '
                 'I: Testing." Journal of Structural Engineering (ASCE) 116(2), 438-454.',
    "constantinou1990": 'Constantinou, M. C., Mokha, A., Reinhorn, A. M. (1990). "Teflon bearings in base '
                        'isolation. II: Modeling." Journal of Structural Engineering (ASCE) 116(2), 455-474.',
    "dolce2005": 'Dolce, M., Cardone, D., Croatto, F. (2005). "Frictional behavior of steel-PTFE interfaces for '
                 'seismic isolation." Bulletin of Earthquake Engineering 3(1), 75-99.',
    "en1337-2": 'CEN (2004). EN 1337-2:2004, "Structural bearings - Part 2: Sliding elements." European '
                'Committee for Standardization, Brussels. Table 11 and Annex B, Eq. (B.1).',
    "trrl-lr491": 'Transport and Road Research Laboratory, Crowthorne. Laboratory Report LR 491: the friction '
                  'and deformation of PTFE-based materials for the sliding bearings of bridges and viaducts '
                  '(https://trl.co.uk/reports/LR491). Conclusions (summary).',
    "constantinou2007": 'Constantinou, M. C., Whittaker, A. S., Kalpakidis, Y., Fenz, D. M., Warn, G. P. (2007). '
                        '"Performance of seismic isolation hardware under service and seismic loading." '
                        'Technical Report MCEER-07-0012, MCEER, University at Buffalo. Section 4.',
    "kumar2015": 'Kumar, M., Whittaker, A. S., Constantinou, M. C. (2015). "Characterizing friction in sliding '
                 'isolation bearings." Earthquake Engineering and Structural Dynamics 44(9), 1409-1425. The '
                 'velocity factor k_v = 1 - 0.5 exp(-a v).',
    "blanchet1992": 'Blanchet, T. A., Kennedy, F. E. (1992). "Sliding wear mechanism of polytetrafluoroethylene '
                    '(PTFE) and PTFE composites." Wear 153(1), 229-243.',
}


def _src(ref, stated, note):
    return {"ref": ref, "stated": stated, "note": note}


_VEL_LAW = _src("constantinou1990", True, "the velocity law fitted there to PTFE on polished stainless steel")
_PTFE_RATE = _src("constantinou1990", False, "of the order of the rates fitted there (mu covers 1 - 1/e of its way "
                  "from mu_slow to mu_fast at 10 mm/s); the kumar2015 law's default")
LINERS: dict = {
    "ptfe": {
        "values": {"law": "constantinou", "mu_slow": 0.04, "mu_fast": 0.10, "a_s_per_m": 100.0,
                   "mu_static": 0.10, "wear_k_mm3_per_Nm": 3e-4},
        "sources": {
            "law": _VEL_LAW,
            "mu_slow": _src("mokha1990", False, "a pick inside the low-speed values of a few hundredths the tests "
                            "report (falling with pressure), at the packaged scenes' ~20 MPa"),
            "mu_fast": _src("mokha1990", False, "a pick inside the high-speed values of the order of 0.1 the tests "
                            "report (falling with pressure), at ~20 MPa"),
            "a_s_per_m": _PTFE_RATE,
            "mu_static": _src("mokha1990", False, "a pick (equal to mu_fast): the tests report breakaway above the "
                              "low-speed sliding value, growing with dwell and falling with pressure, but no single "
                              "value; the least certain number of the preset"),
            "wear_k_mm3_per_Nm": _src("blanchet1992", False, "unfilled PTFE wears at specific rates of the order "
                                      "of 1e-4 to 1e-3 mm3/(N m); a pick inside that range"),
        },
    },
    "ptfe-lubricated": {
        "values": {"law": "constantinou", "mu_slow": 0.01, "mu_fast": 0.03, "a_s_per_m": 100.0,
                   "mu_static": 0.03},
        "sources": {
            "law": _src("dolce2005", True, "the Constantinou form, extended there and fitted to lubricated "
                        "steel-PTFE interfaces"),
            "mu_slow": _src("dolce2005", False, "lubrication lowers the coefficient to roughly a third or less of "
                            "the dry one with the same rise with speed; a pick at that fraction of ptfe's"),
            "mu_fast": _src("en1337-2", True, "0.03: the maximum design coefficient of lubricated (dimpled) PTFE "
                            "on austenitic steel at contact pressures >= 30 MPa (Table 11; Eq. (B.1), mu_max = "
                            "1.2 / (10 + sigma_p), sigma_p in MPa)"),
            "a_s_per_m": _PTFE_RATE,
            "mu_static": _src("en1337-2", True, "0.03: the same design maximum at >= 30 MPa, taken for the "
                              "breakaway too (an upper bound, not a measured breakaway)"),
        },
    },
    "ptfe-composite": {
        "values": {"law": "constantinou", "mu_slow": 0.03, "mu_fast": 0.07, "a_s_per_m": 100.0,
                   "mu_static": 0.07, "wear_k_mm3_per_Nm": 1e-6},
        "sources": {
            "law": _src("constantinou2007", True, "composites containing PTFE are described as PTFE on stainless "
                        "steel is (Section 4), by the velocity law of constantinou1990"),
            "mu_slow": _src("trrl-lr491", True, "0.03: the lower end of the range 0.03 to 0.07 in which the "
                            "coefficient of PTFE-based bearing materials lies for most practical applications "
                            "(dry running in the long term); taken at low speed"),
            "mu_fast": _src("trrl-lr491", True, "0.07: the upper end of that range; taken at high speed"),
            "a_s_per_m": _src("kumar2015", True, "a = 100 s/m, the rate parameter of the velocity factor for the "
                              "PTFE-type composite liners of friction pendulum bearings"),
            "mu_static": _src("trrl-lr491", False, "no published breakaway value for a composite liner: set to the "
                              "upper end of the stated range (equal to mu_fast), so the breakaway is not below any "
                              "sliding value the source states"),
            "wear_k_mm3_per_Nm": _src("blanchet1992", False, "fillers lower unfilled PTFE's wear rate (1e-4 to "
                                      "1e-3 mm3/(N m)) by two orders of magnitude or more; 1e-6 is a pick at that "
                                      "reduction (a proprietary liner's own coefficient is not published)"),
        },
    },
}


# liners asked for by name that have no preset, and why (the scene loader says so in one line)
NOT_PACKAGED: dict = {
    "uhmwpe": "no preset: no published friction of UHMWPE isolator liners was found (it is given in proprietary "
              "European Technical Assessments); give its law and coefficients from the product's tests "
              "(docs/liners.md)",
}


def make_law(spec: dict):
    """A law from a validated ``[friction]`` table (keys already checked)."""
    kw = {k: v for k, v in spec.items() if k != "law" and k not in SURFACE_KEYS}
    if spec["law"] == "table":
        kw = {"T_C": tuple(kw["T_C"]), "mu": tuple(kw["mu"])}
    return LAWS[spec["law"]](**kw)


def static_mu(spec: dict) -> tuple:
    """The surface's static (breakaway) coefficient and its ratio to the
    sliding mu at rest; 0.0 each when not given (friction_kernel.holding_mu:
    the sliding mu holds a stuck surface)."""
    return float(spec.get("mu_static", 0.0)), float(spec.get("static_ratio", 0.0))


def dwell_law(spec: dict) -> tuple:
    """The surface's dwell law of the static coefficient (friction_kernel.dwell_mu):
    (mu_s after a long dwell, the time constant in s, the exponent); zeros when
    not given (no growth with the time stuck)."""
    if spec.get("dwell_time_s") is None:
        return 0.0, 0.0, 0.0
    return float(spec["mu_static_inf"]), float(spec["dwell_time_s"]), float(spec.get("dwell_exponent", 1.0))


MM3_PER_NM = 1e-9          # 1 mm^3 / (N m) in m^2 / N


def wear_law(spec: dict):
    """The surface's Archard wear coefficient k_w(T) in m^2/N as a law (its row
    P is what friction_kernel.wear_step reads): the table (wear_T_C,
    wear_k_T_mm3_per_Nm) if given, else the constant wear_k_mm3_per_Nm, else
    None (no wear given)."""
    if spec.get("wear_T_C") is not None:
        return Table(tuple(spec["wear_T_C"]), tuple(k * MM3_PER_NM for k in spec["wear_k_T_mm3_per_Nm"]))
    if spec.get("wear_k_mm3_per_Nm") is not None:
        return Constant(spec["wear_k_mm3_per_Nm"] * MM3_PER_NM)
    return None


def wear_laws(specs) -> tuple | None:
    """Per surface the wear law, or None when no surface gives wear (then no
    wear columns); a surface without: k_w = 0 (its path is still counted)."""
    laws = [wear_law(s) for s in specs]
    if all(w is None for w in laws):
        return None
    return tuple(w if w is not None else Constant(0.0) for w in laws)
