"""The paper's joint model assembled from its parts: parameter sets in SI and their evaluation.

`StrengthParameters` feed eqs 9-15, `StiffnessParameters` eqs 2-8 and 16-18. Both are built from a
config (joint inputs, errata switches) and from coefficients that come either as printed in the paper
(`data/paper/equation_constants.csv`) or from our own regressions of Table 1. Evaluation is vectorised
through the ufuncs of `bbmc.laws`; kernels use the scalar laws with the same parameters.

Errata (each a config switch; `paper` reproduces the paper, `corrected` applies the audit's fix, see
docs/paper-audit.md):

* ``lg_e``: eq 6 prints lg e = 0.3434; lg e = 0.43429.
* ``tangent_coefficient``: eq 15 uses 0.016; exactly pi JRC / (180 ln 10).
* ``shear_stiffness_form``: eq 3 takes R_f = tau/tau_ult, which counts tau twice; Bandis et al. (1983)
  take R_f = tau_p/tau_ult, so eq 3 becomes eq 2, the hyperbola's own tangent K_si (1 - tau/tau_ult)^2.
  Eq 16 keeps its own R_f: its a, b were calibrated with it.
* ``eq18_coefficient``: eq 18's 0.1164 is D alone (K_j dropped); corrected, eq 17 is evaluated as
  D K_si with D from eq 16 at tau = tau_p at each normal stress.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator
from scipy import integrate

from bbmc import laws, units
from bbmc.config import Section
from bbmc.fitting import linear_fit, power_law_fit

Choice = Literal["paper", "corrected"]
SIGMA_REF = 1.0 * units.MPa  # the paper's sigma_n is in MPa: K_j is the stiffness at 1 MPa


class BartonBandisJoint(Section):
    """The joint's eq 9 inputs as a config gives them: JRC [1], JCS [MPa], phi_b and phi_max [deg]."""

    jrc: float = Field(ge=0, le=20)
    jcs_MPa: float = Field(gt=0)
    phi_b_deg: float = Field(gt=0, lt=90)
    phi_max_deg: float = Field(gt=0, lt=90)

    @model_validator(mode="after")
    def _cap_above_basic(self) -> BartonBandisJoint:
        if self.phi_max_deg <= self.phi_b_deg:
            raise ValueError(f"phi_max_deg ({self.phi_max_deg}) must exceed phi_b_deg ({self.phi_b_deg})")
        return self


@dataclass(frozen=True)
class StrengthParameters:
    """Barton-Bandis strength (eq 9) in SI: JCS [Pa], angles [rad]; k is eq 13's factor [1]."""

    jrc: float
    jcs: float
    phi_b: float
    phi_max: float
    k: float


@dataclass(frozen=True)
class StiffnessParameters:
    """Bandis stiffness laws in SI (stiffness Pa/m, stress Pa, q 1/m)."""

    k_j: float
    n_j: float
    tau_p_slope: float
    tau_p_intercept: float
    tau_ult_slope: float
    tau_ult_intercept: float
    correction_a: float
    correction_b: float
    eq18_k_j: float
    eq18_n_j: float
    q: float
    log10_e: float
    form: Choice
    simplified: Choice


def strength_parameters(
    jrc: float, jcs_MPa: float, phi_b_deg: float, phi_max_deg: float, k: Choice, printed: float
) -> StrengthParameters:
    """SI strength parameters; k = `printed` (eq 15's 0.016) for ``paper``, the exact factor else."""
    exact = laws.exact_tangent_coefficient(jrc)
    return StrengthParameters(
        jrc=jrc,
        jcs=jcs_MPa * units.MPa,
        phi_b=phi_b_deg * units.deg,
        phi_max=phi_max_deg * units.deg,
        k=printed if k == "paper" else float(exact),
    )


def fitted_coefficients(table1: pd.DataFrame) -> dict[str, float]:
    """Eq 4's coefficients from our own regressions of Table 1 (log-log power law, OLS lines)."""
    s, tp = table1["sigma_n_MPa"].to_numpy(), table1["tau_p_MPa"].to_numpy()
    k_si, tu = table1["K_si_GPa_per_m"].to_numpy(), table1["tau_ult_MPa"].to_numpy()
    power, peak, ultimate = power_law_fit(s, k_si, "log-log"), linear_fit(s, tp), linear_fit(tp, tu)
    return {
        "eq4.K_j": power.a,
        "eq4.n_j": power.b,
        "eq4.tau_p_slope": peak.a,
        "eq4.tau_p_intercept": peak.b,
        "eq4.tau_ult_slope": ultimate.a,
        "eq4.tau_ult_intercept": ultimate.b,
    }


def stiffness_parameters(
    constants: dict[str, float], lg_e: Choice, form: Choice, simplified: Choice
) -> StiffnessParameters:
    """SI stiffness parameters from coefficients named as in `paper_tables.CONSTANTS` (boundary units)."""
    return StiffnessParameters(
        k_j=constants["eq4.K_j"] * units.GPa_per_m,
        n_j=constants["eq4.n_j"],
        tau_p_slope=constants["eq4.tau_p_slope"],
        tau_p_intercept=constants["eq4.tau_p_intercept"] * units.MPa,
        tau_ult_slope=constants["eq4.tau_ult_slope"],
        tau_ult_intercept=constants["eq4.tau_ult_intercept"] * units.MPa,
        correction_a=constants["eq16.correction_a"],
        correction_b=constants["eq16.correction_b"],
        eq18_k_j=constants["eq18.K_st_coefficient"] * units.MPa_per_mm,
        eq18_n_j=constants["eq18.K_st_exponent"],
        q=constants["eq7.q"] * units.per_mm,
        log10_e=constants["eq6.lg_e"] if lg_e == "paper" else math.log10(math.e),
        form=form,
        simplified=simplified,
    )


def fitted_strengths(sigma_n: np.ndarray, p: StiffnessParameters) -> tuple[np.ndarray, np.ndarray]:
    """tau_p = a sigma_n + b (Table 1 fit d) and tau_ult = a tau_p + b (fit c) [Pa], as in eq 4."""
    tau_p = laws.linear_relation(sigma_n, p.tau_p_slope, p.tau_p_intercept)
    return tau_p, laws.linear_relation(tau_p, p.tau_ult_slope, p.tau_ult_intercept)


def stiffness_state(sigma_n: np.ndarray, tau: np.ndarray, p: StiffnessParameters) -> dict[str, np.ndarray]:
    """Every stiffness of the paper at (sigma_n, tau) [Pa/m], with the strengths it used [Pa]."""
    sigma_n, tau = (
        np.array(a) for a in np.broadcast_arrays(np.asarray(sigma_n, float), np.asarray(tau, float))
    )
    tau_p, tau_ult = fitted_strengths(sigma_n, p)
    k_si = laws.initial_shear_stiffness(sigma_n, p.k_j, p.n_j, SIGMA_REF)
    if p.form == "paper":
        uncorrected = laws.bandis_shear_stiffness(tau, k_si, tau_p, tau_ult)
    else:
        uncorrected = laws.hyperbolic_shear_stiffness(tau, k_si, tau_ult)
    if p.simplified == "paper":
        simplified = laws.simplified_shear_stiffness(sigma_n, p.eq18_k_j, p.eq18_n_j, SIGMA_REF, 1.0)
    else:
        simplified = laws.peak_reduction_factor(tau_p, tau_ult, p.correction_b) * k_si
    return {
        "tau_p_fit": tau_p,
        "tau_ult_fit": tau_ult,
        "K_si": k_si,
        "K_st_uncorrected": uncorrected,
        "K_st_corrected": laws.corrected_shear_stiffness(
            tau, k_si, tau_p, tau_ult, p.correction_a, p.correction_b
        ),
        "K_st_simplified": simplified,
        "K_n": laws.normal_stiffness(sigma_n, p.q, p.log10_e),
    }


def strength_state(sigma_n: np.ndarray, p: StrengthParameters) -> dict[str, np.ndarray]:
    """B-B peak strength [Pa], total angle [rad] and the equivalent M-C phi [rad], c [Pa] (eqs 9-15)."""
    args = (p.jrc, p.jcs, p.phi_b, p.phi_max)
    return {
        "tau_p_bb": laws.peak_shear_strength(sigma_n, *args),
        "total_friction_angle": laws.peak_friction_angle(sigma_n, *args),
        "phi": laws.equivalent_friction_angle(sigma_n, *args, p.k),
        "c": laws.equivalent_cohesion(sigma_n, *args, p.k),
    }


def tangent_displacement(
    sigma_n: float, tau: float, p: StiffnessParameters, law: str, floor: float = 0.0
) -> float:
    """d_h [m] of a joint loaded by shear stress to `tau` [Pa] at constant `sigma_n` [Pa] without slip:
    the integral of d tau / K_st from 0 to tau, K_st the `law` of `stiffness_state` (e.g.
    ``K_st_corrected``) floored at `floor` x K_si as the engine does; inf where K_st reaches 0."""

    def stiffness(t: float) -> float:
        state = stiffness_state(np.array(sigma_n), np.array(t), p)
        return max(float(state[law]), floor * float(state["K_si"]))

    if stiffness(tau) == 0.0:
        return math.inf
    value, _ = integrate.quad(lambda t: 1.0 / stiffness(t), 0.0, tau, limit=400, epsabs=0.0, epsrel=1e-10)
    return value
