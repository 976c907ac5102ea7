"""Joint stiffness laws of the paper: Bandis hyperbola (eqs 1-4), the correction (eq 16), the simplified
law (eqs 17-18) and the normal stiffness (eqs 5-8).

Scalar laws in SI (Pa, m, Pa/m), compiled with numba; `bbmc.laws` exposes them as numpy ufuncs.

Rules at the edges (documented choices, never a NaN, never a negative stiffness):

* An open joint (sigma_n <= 0) has no stiffness: K_si = K_n = 0.
* The bracket [1 - g] of eqs 2, 3 and 16 is clamped to [0, 1], and that is the only limit. Past the
  peak (the paper states eqs 3 and 16 for tau <= tau_p) the formula goes on: g keeps growing, so the
  stiffness keeps falling until the bracket reaches 0, and stays 0 after: never negative, never rising
  again (the paper itself evaluates eq 4 at tau above its fitted tau_p in Table 3). The upper clamp keeps
  K_st <= K_si: for eq 16 it stops f(tau/tau_p) < 0 (tau < 0.1 tau_p with the paper's a, b) from
  stiffening the joint beyond its initial stiffness. With a >= 0 every law is non-increasing in tau.
* tau -> 0 in eq 16: f R_f = (a ln(tau/tau_p) + b) tau/tau_ult -> 0, so K_st -> K_si; tau <= 0 returns
  K_si exactly instead of evaluating 0 * ln(0).
"""

import math

import numba


@numba.njit(cache=True)
def linear_relation(x: float, slope: float, intercept: float) -> float:
    """y = slope x + intercept: the Table 1 fits tau_p(sigma_n) (fit d) and tau_ult(tau_p) (fit c) [Pa]."""
    return slope * x + intercept


@numba.njit(cache=True)
def initial_shear_stiffness(sigma_n: float, k_j: float, n_j: float, sigma_ref: float) -> float:
    """K_si = K_j (sigma_n / sigma_ref)^n_j [Pa/m], the factor K_j sigma_n^n_j of eqs 2-4 and 16-18.

    k_j [Pa/m] is the stiffness at sigma_n = sigma_ref [Pa] (the paper's sigma_n is in MPa, so
    sigma_ref = 1 MPa); n_j [1]. Open joint (sigma_n <= 0): 0.
    """
    if sigma_n <= 0.0:
        return 0.0
    return k_j * (sigma_n / sigma_ref) ** n_j


@numba.njit(cache=True)
def _reduction(g: float) -> float:
    """[1 - g]^2 with the bracket clamped to [0, 1] [1]."""
    bracket = min(max(1.0 - g, 0.0), 1.0)
    return bracket * bracket


@numba.njit(cache=True)
def hyperbolic_shear_stiffness(tau: float, k_si: float, tau_ult: float) -> float:
    """Tangent stiffness of the hyperbola of eq 1, K_st = K_si (1 - tau/tau_ult)^2 [Pa/m] (eq 2).

    tau, tau_ult [Pa]; k_si [Pa/m]. Zero for tau >= tau_ult.
    """
    return k_si * _reduction(max(tau, 0.0) / tau_ult)


@numba.njit(cache=True)
def bandis_shear_stiffness(tau: float, k_si: float, tau_p: float, tau_ult: float) -> float:
    """Eq 3 as the paper writes it: K_st = K_si [1 - (tau/tau_p) R_f]^2, R_f = tau/tau_ult [Pa/m].

    With K_si from `initial_shear_stiffness`, tau_p and tau_ult from the Table 1 fits this is eq 4.
    tau, tau_p, tau_ult [Pa]; k_si [Pa/m]. Zero from tau = sqrt(tau_p tau_ult) on.
    """
    t = max(tau, 0.0)
    return k_si * _reduction((t / tau_p) * (t / tau_ult))


@numba.njit(cache=True)
def correction_function(tau: float, tau_p: float, a: float, b: float) -> float:
    """f(tau/tau_p) = a ln(tau/tau_p) + b [1], the paper's correction (eq 16); tau > 0 [Pa]."""
    return a * math.log(tau / tau_p) + b


@numba.njit(cache=True)
def corrected_shear_stiffness(
    tau: float, k_si: float, tau_p: float, tau_ult: float, a: float, b: float
) -> float:
    """Eq 16: K_st = K_si [1 - f(tau/tau_p) R_f]^2, R_f = tau/tau_ult [Pa/m].

    tau, tau_p, tau_ult [Pa]; k_si [Pa/m]; a, b [1] (the paper: 0.312, 0.7188). tau <= 0, or a tau so
    small that tau/tau_p underflows to 0, gives K_si (the limit of f R_f -> 0 as tau -> 0).
    """
    if tau / tau_p <= 0.0:
        return k_si
    return k_si * _reduction(correction_function(tau, tau_p, a, b) * (tau / tau_ult))


@numba.njit(cache=True)
def peak_reduction_factor(tau_p: float, tau_ult: float, b: float) -> float:
    """D of eq 17 taken from eq 16 at tau = tau_p, where f(1) = b: D = [1 - b tau_p/tau_ult]^2 [1]."""
    return _reduction(b * tau_p / tau_ult)


@numba.njit(cache=True)
def simplified_shear_stiffness(sigma_n: float, k_j: float, n_j: float, sigma_ref: float, d: float) -> float:
    """Eq 17: K_st = D K_j (sigma_n/sigma_ref)^n_j [Pa/m]; eq 18 is this with D K_j = 0.1164 MPa/mm."""
    return d * initial_shear_stiffness(sigma_n, k_j, n_j, sigma_ref)


@numba.njit(cache=True)
def hyperbolic_shear_displacement(tau: float, m: float, n: float) -> float:
    """Shear displacement on the hyperbola of eq 1, 1/tau = m/d_h + n, solved: d_h = m tau/(1 - n tau) [m].

    m [m/Pa] (= 1/K_si), n [1/Pa] (= 1/tau_ult). For n > 0 the asymptote tau_ult = 1/n is never
    reached: tau >= 1/n returns +inf. tau <= 0 returns 0.
    """
    if tau <= 0.0:
        return 0.0
    denominator = 1.0 - n * tau
    if denominator <= 0.0:
        return math.inf
    return m * tau / denominator


@numba.njit(cache=True)
def normal_stiffness(sigma_n: float, q: float, log10_e: float) -> float:
    """K_n = d sigma_n / d dV_j = q sigma_n / lg e [Pa/m] (eqs 5, 6, 8).

    q [1/m] is the slope of lg sigma_n = p + q dV_j (eq 5); log10_e is lg e = 0.4343 (exact); eq 6
    prints 0.3434, pass that to reproduce the paper's eq 8. Open joint (sigma_n <= 0): 0.
    """
    if sigma_n <= 0.0:
        return 0.0
    return q * sigma_n / log10_e
