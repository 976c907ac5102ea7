"""A rock joint's behaviour from its Barton-Bandis parameters, as Barton draws it: the scale effects on
JRC, JCS and delta_peak, the peak and residual envelopes with their tangent Mohr-Coulomb phi and c, the
mobilized tau-delta and dilation curves, and the Bandis normal closure.

Everything is computed with the laws of `bbmc.laws` in SI (Pa, m, rad); the tables come out in the
units their column names carry (MPa, mm, deg, kPa, MPa/mm). Two scales are evaluated: the lab (L_0,
JRC_0, JCS_0) and the field (L_n, JRC_n, JCS_n from Barton & Bandis 1982). The closure keeps the lab
values at both scales: the Bandis fits were made on lab specimens (`bbmc.laws.mobilized`, note (a)).

No plotting here: `bbmc.joint.figures` draws from these tables.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from bbmc import laws, units
from bbmc.joint.derived import Closure, full_joint
from bbmc.laws.mobilized import MOBILIZATION_TABLE

LINEAR_POINTS = 401  # delta/delta_peak grid of a shear curve: evenly spaced from 0 ...
LOG_POINTS = 201  # ... and log-spaced from SMALLEST_RATIO, merged, with every table point added
SMALLEST_RATIO = 1.0e-3
ENVELOPE_POINTS = 400  # log-spaced normal stresses of the envelopes
CLOSURE_POINTS = 401  # evenly spaced normal stresses of the closure curve
CLOSURE_SPAN = 4.0  # the closure curve reaches at least 4 K_ni V_m, i.e. 80 % of V_m


@dataclass(frozen=True)
class Joint:
    """A joint's parameters in SI. damage None: Barton, Bandis & Bakhtar (1985)'s M(sigma_n)."""

    jrc0: float  # JRC_0 [1], at the lab length
    jcs0: float  # JCS_0 [Pa]
    phi_b: float  # basic friction angle [rad]
    phi_r: float  # residual friction angle [rad]
    lab_length: float  # L_0 [m]
    field_length: float  # L_n [m]
    closure: Closure  # the Bandis closure (lab values, `bbmc.joint.derived`)
    phi_max: float  # cap on the total friction angle [rad]
    damage: float | None  # M [1] of the dilation, or None for M = 0.7 + JRC/(12 lg(JCS/sigma_n))


@dataclass(frozen=True)
class Scale:
    """The joint at one size: name ("lab" or "field"), length [m], JRC [1], JCS [Pa], delta_peak [m]."""

    name: str
    length: float
    jrc: float
    jcs: float
    peak_displacement: float


def scale(joint: Joint, name: str, length: float) -> Scale:
    """The joint at `length` [m] (`bbmc.joint.derived`): JRC, JCS [Pa] and delta_peak [m] scaled from the
    lab length (Barton & Bandis 1982); at the lab length itself these are JRC_0, JCS_0."""
    at = full_joint(joint.jrc0, joint.jcs0, joint.lab_length, length)
    return Scale(name, length, at.jrc, at.jcs, at.peak_displacement)


def scales(joint: Joint) -> tuple[Scale, Scale]:
    """The lab and the field scale, in that order."""
    return scale(joint, "lab", joint.lab_length), scale(joint, "field", joint.field_length)


def scale_table(joint: Joint) -> pd.DataFrame:
    """One row per scale: L [m], JRC [1], JCS [MPa], delta_peak [mm], phi_r [deg] (phi_r has no scale
    effect: it is the same at both sizes)."""
    return pd.DataFrame(
        [
            {
                "scale": s.name,
                "length_m": s.length,
                "JRC": s.jrc,
                "JCS_MPa": s.jcs / units.MPa,
                "delta_peak_mm": s.peak_displacement / units.mm,
                "phi_r_deg": joint.phi_r / units.deg,
            }
            for s in scales(joint)
        ]
    )


def envelope_stresses(low: float, high: float, points: int = ENVELOPE_POINTS) -> np.ndarray:
    """Log-spaced normal stresses [Pa] from `low` to `high` [Pa] (0 < low < high)."""
    return np.geomspace(low, high, points)


def peak_strength(sigma_n: np.ndarray, scale: Scale, friction: float, phi_max: float) -> np.ndarray:
    """tau_p = sigma_n tan(friction + JRC lg(JCS/sigma_n)) [Pa], sigma_n [Pa], friction and phi_max [rad].

    friction = phi_b gives the criterion of bbmc mc (the paper's eq 9); phi_r gives Barton & Choubey
    (1977)'s form for weathered walls, which is the peak of the mobilized tau-delta curve.
    """
    return laws.peak_shear_strength(sigma_n, scale.jrc, scale.jcs, friction, phi_max)


def residual_strength(sigma_n: np.ndarray, phi_r: float) -> np.ndarray:
    """tau_r = sigma_n tan(phi_r) [Pa], sigma_n [Pa], phi_r [rad]."""
    return sigma_n * np.tan(phi_r)


def tangent_parameters(sigma_n: np.ndarray, scale: Scale, joint: Joint) -> tuple[np.ndarray, np.ndarray]:
    """The tangent to the peak envelope (phi_b) at each sigma_n [Pa]: friction angle [rad] and cohesion
    (its intercept) [Pa], with the exact factor k = pi JRC / (180 ln 10) of the scale's JRC."""
    k = float(laws.exact_tangent_coefficient(scale.jrc))
    args = (sigma_n, scale.jrc, scale.jcs, joint.phi_b, joint.phi_max, k)
    return laws.equivalent_friction_angle(*args), laws.equivalent_cohesion(*args)


def envelope_table(joint: Joint, sigma_n: np.ndarray) -> pd.DataFrame:
    """Peak (phi_b and phi_r forms) and residual strength [MPa] and the peak's tangent phi [deg] and
    c [kPa] at lab and field scale, at each sigma_n [Pa]."""
    table = {"sigma_n_MPa": sigma_n / units.MPa}
    for s in scales(joint):
        table[f"tau_peak_{s.name}_MPa"] = peak_strength(sigma_n, s, joint.phi_b, joint.phi_max) / units.MPa
    for s in scales(joint):
        table[f"tau_peak_phi_r_{s.name}_MPa"] = (
            peak_strength(sigma_n, s, joint.phi_r, joint.phi_max) / units.MPa
        )
    table["tau_residual_MPa"] = residual_strength(sigma_n, joint.phi_r) / units.MPa
    for s in scales(joint):
        phi, c = tangent_parameters(sigma_n, s, joint)
        table[f"phi_tangent_{s.name}_deg"] = phi / units.deg
        table[f"c_tangent_{s.name}_kPa"] = c / units.kPa
    return pd.DataFrame(table)


def displacement_ratios(max_ratio: float) -> np.ndarray:
    """delta/delta_peak [1] from 0 to `max_ratio`: an even grid merged with a log grid (for the log
    axes) and every point of Barton's table in range, so the peak sits exactly at 1."""
    table = [x for x, _ in MOBILIZATION_TABLE if x <= max_ratio]
    grid = np.concatenate(
        [
            np.linspace(0.0, max_ratio, LINEAR_POINTS),
            np.geomspace(SMALLEST_RATIO, max_ratio, LOG_POINTS),
            table,
        ]
    )
    return np.unique(grid)


def damage_coefficient(sigma_n: float, scale: Scale, joint: Joint) -> float:
    """M [1] of the dilation at sigma_n [Pa]: the given constant, or 0.7 + JRC/(12 lg(JCS/sigma_n))."""
    if joint.damage is not None:
        return joint.damage
    return float(laws.damage_coefficient(sigma_n, scale.jrc, scale.jcs))


def cumulative_dilation(delta: np.ndarray, dilation_angle: np.ndarray) -> np.ndarray:
    """Normal displacement [m] (opening positive) along delta [m]: the cumulative trapezoid of
    tan(dilation_angle [rad]), 0 at the first point."""
    slope = np.tan(dilation_angle)
    steps = 0.5 * (slope[1:] + slope[:-1]) * np.diff(delta)
    return np.concatenate([[0.0], np.cumsum(steps)])


def shear_curve(joint: Joint, scale: Scale, sigma_n: float, ratios: np.ndarray) -> pd.DataFrame:
    """The mobilized curve at constant sigma_n [Pa] over delta = ratios delta_peak: tau [MPa], phi_mob,
    the roughness ratio JRC_mob/JRC_peak, M, d_mob [deg] and the integrated dilation [mm]."""
    peak = scale.peak_displacement
    delta = ratios * peak
    args = (delta, sigma_n, scale.jrc, scale.jcs, joint.phi_r, peak)
    m = damage_coefficient(sigma_n, scale, joint)
    phi_mob = laws.mobilized_friction_angle(*args, joint.phi_max)
    tau = laws.mobilized_shear_strength(*args, joint.phi_max)
    dilation_angle = laws.mobilized_dilation_angle(*args, m)
    roughness = laws.roughness_angle(sigma_n, scale.jrc, scale.jcs)
    return pd.DataFrame(
        {
            "scale": scale.name,
            "sigma_n_MPa": sigma_n / units.MPa,
            "delta_mm": delta / units.mm,
            "delta_over_delta_peak": ratios,
            "tau_MPa": tau / units.MPa,
            "phi_mob_deg": phi_mob / units.deg,
            "JRC_mob_over_JRC_peak": laws.mobilized_roughness_ratio(ratios, joint.phi_r, roughness),
            "damage_M": m,
            "d_mob_deg": dilation_angle / units.deg,
            "dilation_mm": cumulative_dilation(delta, dilation_angle) / units.mm,
        }
    )


def shear_curves_table(joint: Joint, stresses: np.ndarray, max_ratio: float) -> pd.DataFrame:
    """The shear curves of `shear_curve` for each normal stress [Pa], lab scale first, then field."""
    ratios = displacement_ratios(max_ratio)
    frames = [shear_curve(joint, s, float(sigma), ratios) for s in scales(joint) for sigma in stresses]
    return pd.concat(frames, ignore_index=True)


def closure_stresses(closure: Closure, high: float, points: int = CLOSURE_POINTS) -> np.ndarray:
    """Normal stresses [Pa] from 0 to the larger of `high` [Pa] and CLOSURE_SPAN K_ni V_m, evenly
    spaced, with the half-closure stress K_ni V_m added."""
    half = closure.kni * closure.vm
    top = max(high, CLOSURE_SPAN * half)
    return np.unique(np.append(np.linspace(0.0, top, points), half))


def closure_table(closure: Closure, sigma_n: np.ndarray) -> pd.DataFrame:
    """Closure dV = sigma_n V_m/(K_ni V_m + sigma_n) [mm], dV/V_m [1] and the tangent
    K_n = K_ni (1 + sigma_n/(K_ni V_m))^2 [MPa/mm] at each sigma_n [Pa], beside K_ni, V_m and a_j."""
    dv = laws.bandis_closure(sigma_n, closure.kni, closure.vm)
    return pd.DataFrame(
        {
            "sigma_n_MPa": sigma_n / units.MPa,
            "closure_mm": dv / units.mm,
            "closure_over_V_m": dv / closure.vm,
            "K_n_MPa_per_mm": laws.bandis_normal_stiffness(sigma_n, closure.kni, closure.vm)
            / units.MPa_per_mm,
            "K_ni_MPa_per_mm": closure.kni / units.MPa_per_mm,
            "V_m_mm": closure.vm / units.mm,
            "a_j_mm": closure.aperture / units.mm,
        }
    )
