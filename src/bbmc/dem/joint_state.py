"""Contact properties: each sub-contact's K_n, K_s, c and phi from its joint type's laws.

The one dispatch from a joint type's integer law codes (`bbmc.dem.layout`) to the scalar laws of
`bbmc.laws` (the same code the numpy ufuncs run): `update_joint_laws` re-evaluates the stress-dependent
laws at each sub-contact's own stresses every `update_interval` cycles (and sooner once
`stresses_moved`); `initial_joint_state` gives new sub-contacts their type's constants. A new law is a
scalar function in `bbmc.laws` and one branch here. SI units: Pa, Pa/m, m, rad.
"""

import math

import numba

from bbmc.dem.layout import (
    AFTER_SLIP,
    AFTER_SLIP_ZERO,
    BECAME_JOINT,
    BREAKS_INTO,
    COH,
    EDGE_A,
    EDGE_B,
    JOINT_TYPE,
    KN,
    KS,
    LAW_PATH,
    LAW_SN,
    LAW_TAU,
    NORMAL_BANDIS,
    NORMAL_CONSTANT,
    NORMAL_EQ8,
    NORMAL_LAW,
    P_A,
    P_B,
    P_COH,
    P_D,
    P_DAMAGE,
    P_JCS,
    P_JRC,
    P_K_J,
    P_K_NI,
    P_K_TANGENT,
    P_KN,
    P_KS,
    P_LG_E,
    P_N_J,
    P_PEAK_DISPLACEMENT,
    P_PHI,
    P_PHI_B,
    P_PHI_MAX,
    P_Q,
    P_SHEAR_FLOOR,
    P_SIGMA_REF,
    P_STRESS_FLOOR,
    P_TAU_P_INTERCEPT,
    P_TAU_P_SLOPE,
    P_TAU_ULT_INTERCEPT,
    P_TAU_ULT_SLOPE,
    P_TEN,
    P_V_M,
    PATH,
    SHEAR_BANDIS,
    SHEAR_CONSTANT,
    SHEAR_CORRECTED,
    SHEAR_LAW,
    SHEAR_SIMPLIFIED,
    SLIPPED,
    SLIPPED_IN_SHEAR,
    SN,
    STRENGTH_BARTON_BANDIS,
    STRENGTH_CONSTANT,
    STRENGTH_LAW,
    STRENGTH_MOBILIZED,
    TAN_DILATION,
    TANPHI,
    TAU,
    TEN,
)
from bbmc.laws.mobilized import (
    bandis_normal_stiffness,
    damage_coefficient,
    mobilized_dilation_angle,
    mobilized_friction_angle,
)
from bbmc.laws.stiffness import (
    bandis_shear_stiffness,
    corrected_shear_stiffness,
    hyperbolic_shear_stiffness,
    initial_shear_stiffness,
    linear_relation,
    normal_stiffness,
    simplified_shear_stiffness,
)
from bbmc.laws.strength import equivalent_cohesion, equivalent_friction_angle


@numba.njit(cache=True)
def _shear_stiffness(law, sigma, tau, p):
    """K_s [Pa/m] of one shear-stiffness law at (sigma, |tau|), floored at a fraction of K_si."""
    k_si = initial_shear_stiffness(sigma, p[P_K_J], p[P_N_J], p[P_SIGMA_REF])
    if law == SHEAR_SIMPLIFIED:
        k = simplified_shear_stiffness(sigma, p[P_K_J], p[P_N_J], p[P_SIGMA_REF], p[P_D])
    else:
        tau_p = linear_relation(sigma, p[P_TAU_P_SLOPE], p[P_TAU_P_INTERCEPT])
        tau_ult = linear_relation(tau_p, p[P_TAU_ULT_SLOPE], p[P_TAU_ULT_INTERCEPT])
        if law == SHEAR_BANDIS:
            k = bandis_shear_stiffness(tau, k_si, tau_p, tau_ult)
        elif law == SHEAR_CORRECTED:
            k = corrected_shear_stiffness(tau, k_si, tau_p, tau_ult, p[P_A], p[P_B])
        else:
            k = hyperbolic_shear_stiffness(tau, k_si, tau_ult)
    return max(k, p[P_SHEAR_FLOOR] * k_si)


@numba.njit(cache=True)
def _mobilize(subs, law_state, s, floored, p):
    """The mobilized Barton-Bandis law at the sub-contact's sigma_n and shear path (Barton 1982): the
    secant tan(phi_mob) (c = 0: the strength sigma_n tan(phi_mob) is exact at this sigma_n and path) and
    the dilation angle's tangent, both at max(sigma_n, stress floor) (an open joint carries no strength
    whatever its angle; it is the angle it will close with, and lg(JCS/sigma_n) has no limit at 0)."""
    path, jrc, jcs, phi_r, peak = subs[s, PATH], p[P_JRC], p[P_JCS], p[P_PHI_B], p[P_PEAK_DISPLACEMENT]
    subs[s, TANPHI] = math.tan(mobilized_friction_angle(path, floored, jrc, jcs, phi_r, peak, p[P_PHI_MAX]))
    subs[s, COH] = 0.0
    damage = p[P_DAMAGE] if p[P_DAMAGE] > 0.0 else damage_coefficient(floored, jrc, jcs)
    law_state[s, TAN_DILATION] = math.tan(
        mobilized_dilation_angle(path, floored, jrc, jcs, phi_r, peak, damage)
    )


@numba.njit(cache=True)
def update_joint_laws(contacts, subs, law_state, n_sub, laws, params, changed_only):
    """Re-evaluate K_n, K_s, c and phi of every sub-contact of a stress-dependent joint type.

    `changed_only`: skip a sub-contact whose sigma_n, tau and (mobilized law) shear path are those of
    its last evaluation (an open one stays at 0, 0) and that has not slipped or failed since: the laws
    would give the same values.

    Stiffness laws are evaluated at max(sigma_n, stress floor), so an open or barely closed joint keeps
    a usable stiffness (the laws give 0 at sigma_n = 0, and a joint with K_n = 0 could never close);
    the strength is evaluated at sigma_n itself (no strength when open). A slipped sub-contact of a
    joint type with ``after_slip = zero`` keeps c = 0. A broken share of intact rock follows the laws of
    the joint it broke into.
    """
    for c in range(contacts.shape[0]):
        own = contacts[c, JOINT_TYPE]
        breaks = laws[own, BREAKS_INTO]
        for s in range(c * n_sub, (c + 1) * n_sub):
            j = breaks if breaks >= 0 and subs[s, SLIPPED] != 0.0 else own
            sigma = subs[s, SN]
            if (
                changed_only
                and sigma == law_state[s, LAW_SN]
                and subs[s, TAU] == law_state[s, LAW_TAU]
                and (subs[s, PATH] == law_state[s, LAW_PATH] or laws[j, STRENGTH_LAW] != STRENGTH_MOBILIZED)
            ):
                continue
            law_state[s, LAW_SN] = sigma
            law_state[s, LAW_TAU] = subs[s, TAU]
            law_state[s, LAW_PATH] = subs[s, PATH]
            p = params[j]  # after the skip: an unchanged share costs no row view
            floored = max(sigma, p[P_STRESS_FLOOR])
            if laws[j, NORMAL_LAW] == NORMAL_EQ8:
                subs[s, KN] = normal_stiffness(floored, p[P_Q], p[P_LG_E])
            elif laws[j, NORMAL_LAW] == NORMAL_BANDIS:
                subs[s, KN] = bandis_normal_stiffness(floored, p[P_K_NI], p[P_V_M])
            if laws[j, SHEAR_LAW] != SHEAR_CONSTANT:
                subs[s, KS] = _shear_stiffness(laws[j, SHEAR_LAW], floored, abs(subs[s, TAU]), p)
            if laws[j, STRENGTH_LAW] == STRENGTH_MOBILIZED:
                _mobilize(subs, law_state, s, floored, p)
            elif laws[j, STRENGTH_LAW] == STRENGTH_BARTON_BANDIS:
                args = (sigma, p[P_JRC], p[P_JCS], p[P_PHI_B], p[P_PHI_MAX], p[P_K_TANGENT])
                subs[s, TANPHI] = math.tan(equivalent_friction_angle(*args))
                cohesion = equivalent_cohesion(*args)
                if subs[s, SLIPPED] != 0.0 and laws[j, AFTER_SLIP] == AFTER_SLIP_ZERO:
                    cohesion = 0.0
                subs[s, COH] = cohesion


@numba.njit(cache=True)
def stresses_moved(contacts, subs, law_state, n_sub, laws, params, change):
    """True once a sub-contact of a stress-dependent joint type has a sigma_n or tau that differs from
    the one its laws were last evaluated at by more than `change` times the larger of that value and
    the type's stress floor, or (mobilized law) a shear path longer by `change` x delta_peak (so an
    update is due before the interval is up)."""
    for c in range(contacts.shape[0]):
        j = contacts[c, JOINT_TYPE]
        if (
            laws[j, STRENGTH_LAW] == STRENGTH_CONSTANT
            and laws[j, NORMAL_LAW] == NORMAL_CONSTANT
            and laws[j, SHEAR_LAW] == SHEAR_CONSTANT
            and laws[j, BREAKS_INTO] < 0
        ):
            continue
        floor = params[j, P_STRESS_FLOOR]
        peak = params[j, P_PEAK_DISPLACEMENT]
        for s in range(c * n_sub, (c + 1) * n_sub):
            if peak > 0.0 and subs[s, PATH] - law_state[s, LAW_PATH] > change * peak:
                return True
            if abs(subs[s, SN] - law_state[s, LAW_SN]) > change * max(abs(law_state[s, LAW_SN]), floor):
                return True
            if abs(subs[s, TAU] - law_state[s, LAW_TAU]) > change * max(abs(law_state[s, LAW_TAU]), floor):
                return True
    return False


@numba.njit(cache=True)
def initial_joint_state(contacts, subs, law_state, n_sub, laws, params, first_new, intact):
    """Parameters of new sub-contacts (contacts first_new onwards) from their joint type.

    Contacts of the initial assembly (`intact`) get the type's cohesion and tensile strength; contacts
    that form during a run carry no tensile strength, and their cohesion follows ``after_slip``; one of
    intact rock that forms during a run is the joint it breaks into (rock that has moved apart is broken).
    """
    for c in range(first_new, contacts.shape[0]):
        j = contacts[c, JOINT_TYPE]
        for s in range(c * n_sub, (c + 1) * n_sub):
            subs[s, :] = 0.0
            law_state[s, :] = 0.0
            law_state[s, LAW_SN] = math.nan
            subs[s, KN] = params[j, P_KN]
            subs[s, KS] = params[j, P_KS]
            subs[s, TANPHI] = math.tan(params[j, P_PHI])
            if intact:
                subs[s, COH] = params[j, P_COH]
                subs[s, TEN] = params[j, P_TEN]
            else:
                subs[s, SLIPPED] = SLIPPED_IN_SHEAR
                joint = laws[j, BREAKS_INTO] if laws[j, BREAKS_INTO] >= 0 else j
                subs[s, KN] = params[joint, P_KN]
                subs[s, KS] = params[joint, P_KS]
                subs[s, TANPHI] = math.tan(params[joint, P_PHI])
                if laws[joint, AFTER_SLIP] != AFTER_SLIP_ZERO:
                    subs[s, COH] = params[joint, P_COH]


@numba.njit(cache=True)
def _become_joint(subs, law_state, s, joint, laws, params):
    """A share of intact rock (a rock bridge, a fictitious joint) that has slipped or failed in tension
    becomes a share of joint type `joint`, brittlely: that joint's stiffness, friction and cohesion (none
    where the joint loses it at slip), and no tensile strength. A stress-dependent joint gives its own
    K_n, K_s, c and phi at the next law update (the share keeps the intact friction, with no cohesion,
    until then)."""
    p = params[joint]
    subs[s, TEN] = 0.0
    subs[s, SLIPPED] += BECAME_JOINT
    law_state[s, LAW_SN] = math.nan
    if laws[joint, STRENGTH_LAW] == STRENGTH_CONSTANT:
        subs[s, TANPHI] = math.tan(p[P_PHI])
        subs[s, COH] = 0.0 if laws[joint, AFTER_SLIP] == AFTER_SLIP_ZERO else p[P_COH]
    else:
        subs[s, COH] = 0.0
    if laws[joint, NORMAL_LAW] == NORMAL_CONSTANT:
        subs[s, KN] = p[P_KN]
    if laws[joint, SHEAR_LAW] == SHEAR_CONSTANT:
        subs[s, KS] = p[P_KS]


@numba.njit(cache=True)
def break_bridges(contacts, subs, law_state, n_sub, laws, params, dry):
    """After the contact forces of a step: every share of intact rock (a joint type with BREAKS_INTO)
    that slipped or failed in tension in it becomes the joint it breaks into (`_become_joint`), from the
    next step; a contact of intact rock whose every share has broken lets joint water in (its two
    edges are no longer `dry`). Run only by scenes that have intact rock: the others pay nothing."""
    for c in range(contacts.shape[0]):
        joint = laws[contacts[c, JOINT_TYPE], BREAKS_INTO]
        if joint < 0:
            continue
        through = True
        for s in range(c * n_sub, (c + 1) * n_sub):
            state = subs[s, SLIPPED]
            if state != 0.0 and state < BECAME_JOINT + 0.5:
                _become_joint(subs, law_state, s, joint, laws, params)
            through = through and state != 0.0
        if through:
            dry[contacts[c, EDGE_A]] = False
            dry[contacts[c, EDGE_B]] = False
