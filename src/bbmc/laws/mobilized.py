"""Displacement-dependent Barton-Bandis joint laws: scale effects, mobilized friction and dilation, and the
Bandis hyperbolic normal closure.

Scalar laws in SI (Pa, m, Pa/m, rad), compiled with numba so kernels call them directly; `bbmc.laws`
exposes the same functions as numpy ufuncs. Compression positive; a closure is positive.

Sources (the scale corrections of JRC and JCS and the residual friction angle phi_r, which the peak
envelope takes too, are `bbmc.laws.strength`'s):

* Barton & Bandis (1982), 23rd US Symp. Rock Mech., 739-760: the peak shear displacement delta_peak.
* Barton (1982), ONWI-308 (in situ block tests): the table of JRC_mob/JRC_peak against delta/delta_peak.
* Barton, Bandis & Bakhtar (1985), IJRMMS 22(3), 121-140: the damage coefficient M of the dilation, the
  initial aperture a_j, and the closure fits quoted with lab-scale JRC_0, JCS_0.
* Bandis, Lumsden & Barton (1983), IJRMMS 20(6), 249-268: the hyperbola sigma_n = K_ni dV/(1 - dV/V_m)
  and the fits of K_ni and V_m to JRC, JCS and a_j (they give V_m's constants for three loading
  cycles; bbmc uses the first, a fresh joint loaded once; some codes use the third, -0.1032, -0.0074,
  1.1350, -0.2510, for a joint already closed by its history).

Where the sources disagree, bbmc chose:

(a) Closure at lab scale. The K_ni and V_m fits were made on lab specimens (Bandis et al. 1983) and
    Barton et al. (1985) write them with the lab values JRC_0, JCS_0, as do the functions here. Field
    use calls for the scaled JRC_n, JCS_n (`strength.scaled_jrc`, `strength.scaled_jcs`) in the shear
    laws (delta_peak, the mobilized angles), while the closure keeps the lab values: closure is set by
    the small-scale asperity contacts that the lab specimen holds, and the fits are not valid for other
    values.
(b) Shear stiffness. Barton (1982) estimates K_s = (100/L) tau_p (L in m) from block tests, while the
    mobilized law here reaches tau_p at delta_peak, i.e. at the secant K_s = tau_p/delta_peak. The two
    agree near lab scale (L = 0.1 m, JRC = 10: 1000 tau_p vs 1094 tau_p per metre) and drift apart with
    size (L = 1 m: 100 vs 234; L = 10 m: 10 vs 50). bbmc does not derive K_s from either: the user gives
    it (or the stiffness laws of `bbmc.laws.stiffness`); the secant tau_p/delta_peak is the formula this
    module quotes, being the one consistent with the mobilized curve.

Rules at the edges (documented choices, never a NaN); each function's docstring states its own too:

* Open joint (sigma_n <= 0): no strength (tau = 0), the friction angle is phi_max (the limit, as in
  `strength.peak_friction_angle`), no dilation, no closure, K_n = K_ni.
* The roughness term uses `strength.roughness_angle`: 0 for sigma_n >= JCS or JRC = 0.
* The mobilized friction angle is capped at phi_max; the dilation angle at pi/2 - phi_r (Patton).

The closure laws are written without branches (max/min clamps): numba's vectorized ufunc loop evaluates
both sides of a branch across SIMD lanes, which raised spurious numpy divide/invalid warnings.
"""

import math

import numba
import numpy as np

from bbmc.laws.strength import roughness_angle

MPA = 1.0e6
MM = 1.0e-3
MPA_PER_MM = MPA / MM

# Barton (1982), ONWI-308: delta/delta_peak -> JRC_mob/JRC_peak, as published, from 0.3 on (the point
# at 0 is -phi_r/i and depends on the stress; `mobilized_roughness_ratio`). The laws interpolate it
# (linear up to the peak at 1, linear in lg(delta/delta_peak) after); `bbmc joint` draws it over them.
MOBILIZATION_TABLE: tuple[tuple[float, float], ...] = (
    (0.3, 0.0),
    (0.6, 0.75),
    (1.0, 1.0),
    (2.0, 0.85),
    (4.0, 0.70),
    (10.0, 0.50),
    (100.0, 0.0),
)
ZERO_ROUGHNESS_RATIO = MOBILIZATION_TABLE[0][0]  # delta/delta_peak where JRC_mob = 0
PEAK_RATIO = 1.0  # delta/delta_peak at the peak: the table is interpolated linearly up to it, in lg after
# The table as the kernels read it (numba freezes global arrays into the compiled code): x, lg x, y.
_TABLE_X = np.array([x for x, _ in MOBILIZATION_TABLE])
_TABLE_LG_X = np.log10(_TABLE_X)
_TABLE_Y = np.array([y for _, y in MOBILIZATION_TABLE])

# Bandis, Lumsden & Barton (1983): V_m = A + B JRC + C (JCS/a_j)^D [mm], first loading cycle.
VM_A = -0.2960
VM_B = -0.0056
VM_C = 2.2410
VM_D = -0.2450
MIN_APERTURE = 1.0e-6  # [m] floor of a_j and V_m: 1 micrometre
MIN_NORMAL_STIFFNESS = 0.01 * MPA_PER_MM  # [Pa/m] floor of the K_ni fit
CLOSURE_GAP = 2.0**-52  # smallest 1 - dV/V_m used by bandis_closure_stress
MAX_STRESS = 1.0e300  # [Pa] bandis_closure clamps sigma_n here (inf -> V_m)


@numba.njit(cache=True)
def peak_shear_displacement(length: float, jrc: float) -> float:
    """delta_peak = (L/500) (JRC/L)^0.33 [m], L in metres (Barton & Bandis 1982).

    length L [m] (the block or joint length, L_n in the field); jrc [1] (JRC_n). L <= 0 or JRC <= 0 give
    0, the limit of the formula (a joint with delta_peak = 0 is at residual for any displacement).
    Evaluated as L^0.67 JRC^0.33 / 500: JRC/L overflowed for L = 1e-308 m (delta_peak infinite).
    """
    if length <= 0.0 or jrc <= 0.0:
        return 0.0
    return length**0.67 * jrc**0.33 / 500.0


@numba.njit(cache=True)
def _lerp(x: float, x0: float, y0: float, x1: float, y1: float) -> float:
    """The straight line through (x0, y0) and (x1, y1) at x."""
    return y0 + (y1 - y0) * (x - x0) / (x1 - x0)


@numba.njit(cache=True)
def _table_segment(x: float, k: int) -> float:
    """JRC_mob/JRC_peak at x on the table's segment from point k - 1 to point k: linear in x up to the
    peak, linear in lg x after it [1]."""
    if _TABLE_X[k] <= PEAK_RATIO:
        return _lerp(x, _TABLE_X[k - 1], _TABLE_Y[k - 1], _TABLE_X[k], _TABLE_Y[k])
    return _lerp(math.log10(x), _TABLE_LG_X[k - 1], _TABLE_Y[k - 1], _TABLE_LG_X[k], _TABLE_Y[k])


@numba.njit(cache=True)
def _table_ratio(x: float) -> float:
    """JRC_mob/JRC_peak at x = delta/delta_peak >= 0.3 from `MOBILIZATION_TABLE`, which from there on
    does not depend on phi_r or i: linear in x up to 1, linear in lg x from 1 to 100, 0 beyond [1]."""
    last = _TABLE_X.size - 1
    if x >= _TABLE_X[last]:
        return _TABLE_Y[last]
    for k in range(1, last):
        if x <= _TABLE_X[k]:
            return _table_segment(x, k)
    return _table_segment(x, last)


@numba.njit(cache=True)
def mobilized_roughness_ratio(displacement_ratio: float, phi_r: float, peak_roughness_angle: float) -> float:
    """JRC_mob/JRC_peak [1] against x = |delta/delta_peak| (Barton 1982).

    Table points: x = 0 -> -phi_r/i, then `MOBILIZATION_TABLE` (0.3 -> 0, 0.6 -> 0.75, 1 -> 1,
    2 -> 0.85, 4 -> 0.70, 10 -> 0.50, 100 -> 0), and 0 beyond 100. i = peak_roughness_angle =
    JRC_peak lg(JCS/sigma_n) [rad], phi_r [rad]: the value at 0 makes the mobilized angle
    phi_r + i (JRC_mob/JRC_peak) zero at delta = 0.

    Interpolation: linear in x on [0, 1] and linear in lg x on [1, 100]. Barton draws the post-peak curve
    on a log displacement axis, where the points 1, 2, 4, 10, 100 lie on straight segments; the pre-peak
    part must reach x = 0, which a log axis cannot hold, so it is linear in x, which also makes the
    mobilized angle rise linearly from 0 to phi_r over [0, 0.3]. The result is continuous, passes through
    every table point, rises to 1 at the peak (monotone for phi_r >= 0) and falls monotonically after.

    i <= 0 (smooth joint, or sigma_n >= JCS): the point at x = 0 is undefined; the ratio is 0 on
    [0, 0.3) (no roughness to mobilize) and the table after. Where phi_r/i overflows (i < ~1e-308 rad)
    the value below 0.3 is -inf.
    """
    x = abs(displacement_ratio)
    if x >= ZERO_ROUGHNESS_RATIO:
        return _table_ratio(x)
    if peak_roughness_angle <= 0.0:
        return 0.0
    return -phi_r / peak_roughness_angle * (1.0 - x / ZERO_ROUGHNESS_RATIO)


@numba.njit(cache=True)
def _displacement_ratio(shear_displacement: float, peak_displacement: float) -> float:
    """x = |delta|/delta_peak [1]; 0 at delta = 0, +inf for delta != 0 when delta_peak <= 0."""
    d = abs(shear_displacement)
    if d == 0.0:
        return 0.0
    if peak_displacement <= 0.0:
        return math.inf
    return d / peak_displacement


@numba.njit(cache=True)
def mobilized_friction_angle(
    shear_displacement: float,
    sigma_n: float,
    jrc: float,
    jcs: float,
    phi_r: float,
    peak_displacement: float,
    phi_max: float,
) -> float:
    """phi_mob = JRC_mob lg(JCS/sigma_n) + phi_r, JRC_mob = JRC (JRC_mob/JRC_peak), capped at phi_max [rad].

    shear_displacement delta, peak_displacement delta_peak [m] (its sign is ignored); sigma_n, jcs [Pa];
    jrc [1] (JRC_n); phi_r, phi_max [rad]. The roughness term is `strength.roughness_angle` (0 for
    sigma_n >= JCS or JRC = 0). At delta = delta_peak this is the peak angle JRC lg(JCS/sigma_n) + phi_r.
    Rules: sigma_n <= 0 returns phi_max (the limit). For delta < 0.3 delta_peak the table gives
    phi_mob = phi_r delta/(0.3 delta_peak) whatever i is; bbmc keeps that also for i = 0 (the limit
    i -> 0+), so the angle is continuous in JRC and across sigma_n = JCS. delta_peak <= 0: at residual
    for any delta != 0.
    """
    if sigma_n <= 0.0:
        return phi_max
    x = _displacement_ratio(shear_displacement, peak_displacement)
    if x < ZERO_ROUGHNESS_RATIO:
        return min(phi_r * x / ZERO_ROUGHNESS_RATIO, phi_max)
    ratio = _table_ratio(x)
    if ratio == 0.0:  # also keeps 0 * inf (JCS/sigma_n overflowing) out
        return min(phi_r, phi_max)
    return min(phi_r + ratio * roughness_angle(sigma_n, jrc, jcs), phi_max)


@numba.njit(cache=True)
def mobilized_shear_strength(
    shear_displacement: float,
    sigma_n: float,
    jrc: float,
    jcs: float,
    phi_r: float,
    peak_displacement: float,
    phi_max: float,
) -> float:
    """tau_mob = sigma_n tan(phi_mob) [Pa], phi_mob from `mobilized_friction_angle` (same arguments).

    An open joint (sigma_n <= 0) has no strength; never negative (a negative phi_r gives 0).
    """
    if sigma_n <= 0.0:
        return 0.0
    phi = mobilized_friction_angle(shear_displacement, sigma_n, jrc, jcs, phi_r, peak_displacement, phi_max)
    return max(sigma_n * math.tan(phi), 0.0)


@numba.njit(cache=True)
def damage_coefficient(sigma_n: float, jrc: float, jcs: float) -> float:
    """M = 0.7 + JRC / (12 lg(JCS/sigma_n)) [1] (Barton, Bandis & Bakhtar 1985).

    sigma_n, jcs [Pa]; jrc [1]. Rules: JRC = 0 gives 0.7; sigma_n <= 0 gives 0.7, the limit as
    lg(JCS/sigma_n) -> inf; sigma_n >= JCS (lg <= 0, no roughness left) gives +inf, the limit as
    sigma_n -> JCS-, which makes the dilation JRC_mob lg(JCS/sigma_n)/M vanish continuously.
    """
    if jrc == 0.0 or sigma_n <= 0.0:
        return 0.7
    if sigma_n >= jcs:
        return math.inf
    return 0.7 + jrc / (12.0 * math.log10(jcs / sigma_n))


@numba.njit(cache=True)
def mobilized_dilation_angle(
    shear_displacement: float,
    sigma_n: float,
    jrc: float,
    jcs: float,
    phi_r: float,
    peak_displacement: float,
    damage: float,
) -> float:
    """d_mob = (1/M) JRC_mob lg(JCS/sigma_n) [rad] (Barton 1982; Barton, Bandis & Bakhtar 1985).

    Arguments as `mobilized_friction_angle`; damage M [1] > 0 (`damage_coefficient`, or the older M = 2).
    Rules: 0 for an open joint (sigma_n <= 0), for sigma_n >= JCS or JRC = 0, and beyond 100 delta_peak.
    For delta < 0.3 delta_peak the table's JRC_mob < 0 would give a negative angle (contraction, up to
    -phi_r/M at delta = 0); bbmc clamps it to 0: that negative JRC_mob is a device to start the friction
    angle at 0, not a measured contraction, and closure under sigma_n is the Bandis hyperbola's part.
    The angle is capped at pi/2 - max(phi_r, 0), Patton's limit where the apparent friction phi_r + d
    reaches 90 degrees and asperities shear through instead of being ridden over (reached only at very
    low sigma_n, where lg(JCS/sigma_n) grows without bound); tan of the result stays finite.
    """
    if sigma_n <= 0.0:
        return 0.0
    x = _displacement_ratio(shear_displacement, peak_displacement)
    if x < ZERO_ROUGHNESS_RATIO:
        return 0.0
    ratio = _table_ratio(x)
    i = roughness_angle(sigma_n, jrc, jcs)
    if ratio == 0.0 or i == 0.0:
        return 0.0
    return min(ratio * i / damage, math.pi / 2.0 - max(phi_r, 0.0))


@numba.njit(cache=True)
def initial_aperture(jrc0: float, jcs0: float, sigma_c: float) -> float:
    """a_j = (JRC_0/5)(0.2 sigma_c/JCS_0 - 0.1), in mm in Barton's form, returned in m.

    Barton, Bandis & Bakhtar (1985). jcs0, sigma_c [Pa]; jrc0 [1]. Floored at 1 micrometre (where the
    formula is <= 0: sigma_c <= JCS_0/2, JRC_0 = 0 or JCS_0 <= 0) so the closure fits, which divide by
    a_j, stay finite.
    """
    if jcs0 <= 0.0:
        return MIN_APERTURE
    return max(jrc0 / 5.0 * (0.2 * sigma_c / jcs0 - 0.1) * MM, MIN_APERTURE)


@numba.njit(cache=True)
def bandis_initial_normal_stiffness(jrc0: float, jcs0: float, aperture: float) -> float:
    """K_ni = -7.15 + 1.75 JRC_0 + 0.02 JCS_0/a_j [MPa/mm, JCS in MPa, a_j in mm], returned in Pa/m.

    Bandis, Lumsden & Barton (1983). jcs0 [Pa]; aperture a_j [m], floored at 1 micrometre. Where the fit
    falls below 0.01 MPa/mm (1e7 Pa/m: smooth, weak, wide-open joints) it is floored there.
    """
    a_mm = max(aperture, MIN_APERTURE) / MM
    kni = -7.15 + 1.75 * jrc0 + 0.02 * (jcs0 / MPA) / a_mm
    return max(kni * MPA_PER_MM, MIN_NORMAL_STIFFNESS)


@numba.njit(cache=True)
def bandis_maximum_closure(jrc0: float, jcs0: float, aperture: float) -> float:
    """V_m = A + B JRC_0 + C (JCS_0/a_j)^D [mm, JCS in MPa, a_j in mm], returned in m.

    Bandis, Lumsden & Barton (1983), first loading cycle: A = -0.2960, B = -0.0056, C = 2.2410,
    D = -0.2450. jcs0 [Pa]; aperture a_j [m], floored at 1 micrometre. The result is kept in
    [1 micrometre, a_j]: the fit goes <= 0 for large JCS/a_j (it is floored), and a joint cannot close by
    more than its aperture (capped; JCS_0 <= 0 sends the power term to +inf and so gives a_j).
    """
    a = max(aperture, MIN_APERTURE)
    ratio = (jcs0 / MPA) / (a / MM)
    if ratio <= 0.0:
        return a
    vm = (VM_A + VM_B * jrc0 + VM_C * ratio**VM_D) * MM
    return min(max(vm, MIN_APERTURE), a)


@numba.njit(cache=True)
def bandis_closure(sigma_n: float, kni: float, vm: float) -> float:
    """Closure dV = sigma_n V_m / (K_ni V_m + sigma_n) [m], the Bandis hyperbola solved for dV.

    sigma_n [Pa]; kni K_ni [Pa/m] > 0; vm V_m [m] > 0. 0 for sigma_n <= 0; tends to V_m as sigma_n -> inf
    (sigma_n is clamped at 1e300 Pa, so sigma_n = inf gives V_m, not inf/inf).
    """
    s = min(max(sigma_n, 0.0), MAX_STRESS)
    return vm * (s / (kni * vm + s))


@numba.njit(cache=True)
def bandis_closure_stress(closure: float, kni: float, vm: float) -> float:
    """sigma_n = K_ni dV / (1 - dV/V_m) [Pa] (Bandis, Lumsden & Barton 1983), for 0 <= dV < V_m.

    closure dV, vm V_m [m] > 0; kni K_ni [Pa/m]. dV <= 0 gives 0. dV/V_m is clamped just below 1, at
    1 - 2^-52, so dV >= V_m returns the finite stress K_ni V_m (2^52 - 1) (about 4.5e15 K_ni V_m)
    instead of +inf or a negative stress.
    """
    r = min(max(closure, 0.0) / vm, 1.0 - CLOSURE_GAP)
    return kni * vm * r / (1.0 - r)


@numba.njit(cache=True)
def bandis_normal_stiffness(sigma_n: float, kni: float, vm: float) -> float:
    """Tangent K_n = d sigma_n / d dV = K_ni (1 + sigma_n/(K_ni V_m))^2 [Pa/m].

    sigma_n [Pa]; kni K_ni [Pa/m] > 0; vm V_m [m] > 0. K_ni for sigma_n <= 0 (the tangent at dV = 0).
    """
    g = 1.0 + max(sigma_n, 0.0) / (kni * vm)
    return kni * g * g
