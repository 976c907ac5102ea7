"""Barton-Bandis peak strength and its equivalent Mohr-Coulomb parameters (paper eqs 9-15).

Scalar laws in SI (Pa, rad), compiled with numba so kernels call them directly; `bbmc.laws` exposes the
same functions as numpy ufuncs. Compression positive.

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
