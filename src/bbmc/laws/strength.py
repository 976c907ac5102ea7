"""Barton-Bandis peak strength and its equivalent Mohr-Coulomb parameters (paper eqs 9-15), and the
joint's values at field scale that both Barton-Bandis laws (this peak envelope and the mobilized one,
`bbmc.laws.mobilized`) take.

Scalar laws in SI (Pa, m, rad), compiled with numba so kernels call them directly; `bbmc.laws` exposes
the same functions as numpy ufuncs. Compression positive.

The values at field scale (the last three laws):

* Barton & Bandis (1982), 23rd US Symp. Rock Mech., 739-760 (from Bandis, Lumsden & Barton 1981): JRC
  and JCS measured at the lab length L_0, taken to the field length L_n:
  JRC_n = JRC_0 (L_n/L_0)^(-0.02 JRC_0), JCS_n = JCS_0 (L_n/L_0)^(-0.03 JRC_0).
* Barton & Choubey (1977), Rock Mechanics 10, 1-54: the residual friction angle
  phi_r = (phi_b - 20 deg) + 20 deg r/R, and the envelope tau = sigma_n tan(JRC lg(JCS/sigma_n) + phi_r)
  of a weathered joint, eq 9 with phi_r in place of phi_b: the functions here take whichever angle the
  joint's envelope uses as `phi_b`.

Rules at the edges of the criterion's range (each is a documented choice, never a NaN):

* sigma_n <= 0, an open joint: no strength (tau_p = 0, c = 0). The friction angle returned there is the
  limit from above, phi_max, so the functions stay continuous.
* sigma_n -> 0+: lg(JCS/sigma_n) grows without bound and the total angle phi_b + JRC lg(JCS/sigma_n)
  would pass 90 degrees, where tan changes sign. The total angle is capped at phi_max (70 degrees by
  default: the upper limit Barton & Choubey (1977) give for the peak friction angle arctan(tau/sigma_n)
  at low normal stress). Where the cap acts the envelope is the line tau = sigma_n tan(phi_max): its
  tangent is phi_max and its intercept c is 0.
* sigma_n >= JCS: the criterion is not defined for negative roughness; the roughness term is clamped at
  0, so tau = sigma_n tan(phi_b), the tangent is phi_b and c = 0.
"""

import math

import numba

LN10 = math.log(10.0)
DEG = math.pi / 180.0


@numba.njit(cache=True)
def roughness_angle(sigma_n: float, jrc: float, jcs: float) -> float:
    """Roughness angle i = JRC lg(JCS/sigma_n) [rad], the second term of eq 9, clamped at >= 0.

    sigma_n, jcs [Pa]; jrc [1]. JRC multiplies a decade count and gives degrees, as in Barton's form.
    sigma_n <= 0 is not asked here (callers treat the open joint first); it returns +inf. A smooth joint
    (JRC = 0) has no roughness at any stress, also where JCS/sigma_n overflows to infinity.
    """
    if sigma_n <= 0.0:
        return math.inf
    if sigma_n >= jcs or jrc == 0.0:
        return 0.0
    return math.radians(jrc * math.log10(jcs / sigma_n))


@numba.njit(cache=True)
def peak_friction_angle(sigma_n: float, jrc: float, jcs: float, phi_b: float, phi_max: float) -> float:
    """Total peak friction angle phi_b + JRC lg(JCS/sigma_n), capped at phi_max [rad] (eq 9).

    sigma_n, jcs [Pa]; jrc [1]; phi_b, phi_max [rad]. Returns phi_max for sigma_n <= 0 (the limit).
    """
    if sigma_n <= 0.0:
        return phi_max
    return min(phi_b + roughness_angle(sigma_n, jrc, jcs), phi_max)


@numba.njit(cache=True)
def peak_shear_strength(sigma_n: float, jrc: float, jcs: float, phi_b: float, phi_max: float) -> float:
    """Barton-Bandis peak shear strength tau_p = sigma_n tan(phi_b + JRC lg(JCS/sigma_n)) [Pa] (eq 9).

    sigma_n, jcs [Pa]; jrc [1]; phi_b, phi_max [rad]. An open joint (sigma_n <= 0) has no strength.
    """
    if sigma_n <= 0.0:
        return 0.0
    return sigma_n * math.tan(peak_friction_angle(sigma_n, jrc, jcs, phi_b, phi_max))


@numba.njit(cache=True)
def exact_tangent_coefficient(jrc: float) -> float:
    """k = pi JRC / (180 ln 10) [1], the factor of eq 13; eq 15 rounds it to 0.016 for JRC = 2.13."""
    return math.pi * jrc / (180.0 * LN10)


@numba.njit(cache=True)
def _tangent_drop(sigma_n: float, jrc: float, jcs: float, phi_b: float, phi_max: float, k: float) -> float:
    """k (tan^2 theta + 1) [1], what eq 13 subtracts from tan theta; 0 where the roughness is clamped."""
    if sigma_n <= 0.0 or sigma_n >= jcs:
        return 0.0
    theta = phi_b + roughness_angle(sigma_n, jrc, jcs)
    if theta >= phi_max:
        return 0.0
    f = math.tan(theta)
    return k * (f * f + 1.0)


@numba.njit(cache=True)
def envelope_slope(sigma_n: float, jrc: float, jcs: float, phi_b: float, phi_max: float, k: float) -> float:
    """d tau_p / d sigma_n [1] (eq 13): tan(theta) - k (tan^2 theta + 1), theta the total angle.

    k is exact_tangent_coefficient(jrc) for the exact derivative, or the paper's rounded 0.016 (eq 15).
    """
    theta = peak_friction_angle(sigma_n, jrc, jcs, phi_b, phi_max)
    return math.tan(theta) - _tangent_drop(sigma_n, jrc, jcs, phi_b, phi_max, k)


@numba.njit(cache=True)
def equivalent_friction_angle(
    sigma_n: float, jrc: float, jcs: float, phi_b: float, phi_max: float, k: float
) -> float:
    """Equivalent Mohr-Coulomb friction angle phi = arctan(d tau_p / d sigma_n) [rad] (eqs 11, 14, 15).

    sigma_n, jcs [Pa]; jrc, k [1]; phi_b, phi_max [rad]. The tangent of the B-B envelope at sigma_n.
    """
    return math.atan(envelope_slope(sigma_n, jrc, jcs, phi_b, phi_max, k))


@numba.njit(cache=True)
def equivalent_cohesion(
    sigma_n: float, jrc: float, jcs: float, phi_b: float, phi_max: float, k: float
) -> float:
    """Equivalent Mohr-Coulomb cohesion c = tau_p - sigma_n tan(phi) = k sigma_n (f^2 + 1) [Pa].

    Eqs 12, 14, 15: the intercept of the tangent at sigma_n. Written in the product form, which has no
    cancellation and is >= 0 by construction; 0 for an open joint and where the roughness is clamped.
    """
    if sigma_n <= 0.0:
        return 0.0
    return sigma_n * _tangent_drop(sigma_n, jrc, jcs, phi_b, phi_max, k)


@numba.njit(cache=True)
def scaled_jrc(jrc0: float, lab_length: float, field_length: float) -> float:
    """JRC_n = JRC_0 (L_n/L_0)^(-0.02 JRC_0) [1] (Barton & Bandis 1982).

    lab_length L_0, field_length L_n [m]. A non-positive length carries no scale: JRC_0 is returned.
    """
    if lab_length <= 0.0 or field_length <= 0.0:
        return jrc0
    return jrc0 * (field_length / lab_length) ** (-0.02 * jrc0)


@numba.njit(cache=True)
def scaled_jcs(jcs0: float, jrc0: float, lab_length: float, field_length: float) -> float:
    """JCS_n = JCS_0 (L_n/L_0)^(-0.03 JRC_0) [Pa] (Barton & Bandis 1982).

    jcs0 [Pa]; jrc0 [1]; lengths [m]. A non-positive length carries no scale: JCS_0 is returned.
    """
    if lab_length <= 0.0 or field_length <= 0.0:
        return jcs0
    return jcs0 * (field_length / lab_length) ** (-0.03 * jrc0)


@numba.njit(cache=True)
def residual_friction_angle(phi_b: float, rebound_ratio: float) -> float:
    """phi_r = (phi_b - 20 deg) + 20 deg r/R [rad] (Barton & Choubey 1977).

    phi_b [rad]; rebound_ratio r/R [1], Schmidt rebound on the weathered wet wall over the fresh dry one,
    clamped to [0, 1] (so phi_b - 20 deg <= phi_r <= phi_b); the result is floored at 0 (no negative
    friction). Evaluated as phi_b - 20 deg (1 - r/R), which is phi_b exactly at r/R = 1.
    """
    r = min(max(rebound_ratio, 0.0), 1.0)
    return max(phi_b - 20.0 * DEG * (1.0 - r), 0.0)
