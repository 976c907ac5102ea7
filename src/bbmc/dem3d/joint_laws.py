"""Contact properties of the 3D engine: its joint types as flat tables, and each sub-contact's
Mohr-Coulomb strength from them, by the scalar laws of `bbmc.laws` (the same code as the 2D engine's).

A joint type is one row of `law_codes` (int64, LAW_COLUMNS) and one of `law_params` (float64,
PARAMETERS), SI: stiffnesses in Pa/m, stresses in Pa, angles in rad. Laws so far:

* `MohrCoulomb`: constant K_n, K_s, cohesion c and friction phi; ``after_slip`` ``keep`` (the cohesion
  stays, as limit equilibrium counts it) or ``zero`` (Itasca's Coulomb slip: c = 0 from the first slip).
* `BartonBandis`: constant K_n, K_s and the paper's equivalent Mohr-Coulomb strength, the tangent to the
  Barton-Bandis peak envelope at the sub-contact's own sigma_n (`bbmc.laws.strength`, paper eqs 9-15):
  tan(phi) = d tau_p / d sigma_n, c = tau_p - sigma_n tan(phi); ``after_slip = zero`` drops c.
* `MobilizedBartonBandis`, the full joint (Barton 1982; Barton, Bandis & Bakhtar 1985; `bbmc.laws.mobilized`,
  the 2D engine's `barton_bandis_mobilized`): constant K_n, K_s; strength sigma_n tan(phi_mob), c = 0,
  phi_mob = phi_r + (JRC_mob / JRC) JRC lg(JCS / sigma_n) mobilized along the sub-contact's shear path
  (the length of its path in the plane, whatever its direction: the law is isotropic in the plane), and
  the dilation angle d_mob = JRC_mob lg(JCS / sigma_n) / M, both at max(sigma_n, stress floor). The
  dilation opens the joint along its normal: the share's closure is the geometric one plus
  DILATION = sum of tan(d_mob) (|u_s + d u_s| - |u_s|), never below 0 (the asperities ride up as the
  share moves away from where it started, down as it comes back), from the next step, as in 2D.
  JRC, JCS are the field values (`bbmc.joint.derived.full_joint` scales them, and gives delta_peak).

Stress-dependent stiffnesses (the paper's K_n of eqs 5-8, Bandis's closure hyperbola, the shear
stiffness laws) are not in the 3D engine yet: its normal stress is integrated exactly over each share
as a linear spring bed, which a K_n(sigma_n) is not (`bbmc.dem3d.scene_laws` refuses them in one line).

Every law takes a given uniform joint water `pressure` p [Pa] (default 0) on its contacts' closed
parts; a phreatic plane is the model's, not a joint type's (`bbmc.dem3d.water`).

A new law is a dataclass here, a code and one branch in `strength`. Strength reduction divides the shear
strength c + sigma_n tan(phi) by P_STRENGTH_DIVISOR (1 otherwise), as the 2D engine does; not the water.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numba
import numpy as np

from bbmc.laws.mobilized import damage_coefficient, mobilized_dilation_angle, mobilized_friction_angle
from bbmc.laws.strength import equivalent_cohesion, equivalent_friction_angle, exact_tangent_coefficient

# --- law_codes: int64 (n_types, LAW_COLUMNS) --------------------------------------------------------
STRENGTH_LAW, AFTER_SLIP = 0, 1
LAW_COLUMNS = 2
STRENGTH_CONSTANT, STRENGTH_BARTON_BANDIS, STRENGTH_MOBILIZED = 0, 1, 2
AFTER_SLIP_KEEP, AFTER_SLIP_ZERO = 0, 1

# --- law_params: float64 (n_types, PARAMETERS) ------------------------------------------------------
P_KN, P_KS = 0, 1  # normal and shear stiffness [Pa/m]
P_COH, P_PHI = 2, 3  # Mohr-Coulomb cohesion [Pa] and friction angle [rad]
P_JRC, P_JCS, P_PHI_B, P_PHI_MAX, P_K_TANGENT = 4, 5, 6, 7, 8  # Barton-Bandis: [1], [Pa], [rad], [rad], [1]
P_STRENGTH_DIVISOR = 9  # strength reduction's factor F [1]
P_PRESSURE = 10  # the joint type's given uniform water pressure [Pa]
P_PEAK_DISPLACEMENT, P_DAMAGE, P_STRESS_FLOOR = (
    11,
    12,
    13,
)  # mobilized: delta_peak [m], M [1] (0: M(sigma_n)), [Pa]
PARAMETERS = 14


@dataclass(frozen=True)
class MohrCoulomb:
    """Constant stiffnesses kn, ks [Pa/m], friction angle [rad], cohesion [Pa], after_slip keep|zero, a
    given uniform water pressure [Pa]."""

    kn: float
    ks: float
    friction: float
    cohesion: float = 0.0
    after_slip: str = "keep"
    pressure: float = 0.0


@dataclass(frozen=True)
class BartonBandis:
    """Constant stiffnesses kn, ks [Pa/m]; JRC [1], JCS [Pa], basic (or residual) friction angle phi_b
    and the cap phi_max [rad]; the tangent's k: None for the exact pi JRC / (180 ln 10), or the paper's
    0.016; after_slip keep|zero; a given uniform water pressure [Pa]."""

    kn: float
    ks: float
    jrc: float
    jcs: float
    phi_b: float
    phi_max: float = math.radians(70.0)
    tangent_coefficient: float | None = None
    after_slip: str = "keep"
    pressure: float = 0.0


@dataclass(frozen=True)
class MobilizedBartonBandis:
    """The full joint (module docstring): constant stiffnesses kn, ks [Pa/m]; JRC_n [1], JCS_n [Pa] at
    the field length, the residual friction angle phi_r [rad], the peak shear displacement delta_peak
    [m], the cap phi_max [rad], the dilation's damage coefficient M [1] (0: Barton, Bandis & Bakhtar's
    M(sigma_n)), the stress floor [Pa] the law is evaluated at least at, a given water pressure [Pa]."""

    kn: float
    ks: float
    jrc: float
    jcs: float
    phi_r: float
    peak_displacement: float
    phi_max: float = math.radians(70.0)
    damage: float = 0.0
    stress_floor: float = 0.01e6
    pressure: float = 0.0
    after_slip: str = "keep"  # c = 0 already: kept for the table's checks


JointLaw = MohrCoulomb | BartonBandis | MobilizedBartonBandis


def _row(law: JointLaw, name: str) -> tuple[list[int], np.ndarray]:
    if law.after_slip not in ("keep", "zero"):
        raise ValueError(f"{name}: after_slip must be keep or zero, got {law.after_slip!r}")
    if not (law.kn > 0.0 and law.ks > 0.0):
        raise ValueError(f"{name}: kn and ks must be > 0 Pa/m, got {law.kn}, {law.ks}")
    if not (law.pressure >= 0.0 and math.isfinite(law.pressure)):
        raise ValueError(f"{name}: pressure must be >= 0 Pa, got {law.pressure}")
    p = np.zeros(PARAMETERS)
    p[P_KN], p[P_KS], p[P_STRENGTH_DIVISOR], p[P_PRESSURE] = law.kn, law.ks, 1.0, law.pressure
    after = AFTER_SLIP_ZERO if law.after_slip == "zero" else AFTER_SLIP_KEEP
    if isinstance(law, MohrCoulomb):
        p[P_COH], p[P_PHI] = law.cohesion, law.friction
        return [STRENGTH_CONSTANT, after], p
    if isinstance(law, MobilizedBartonBandis):
        p[P_JRC], p[P_JCS], p[P_PHI_B], p[P_PHI_MAX] = law.jrc, law.jcs, law.phi_r, law.phi_max
        p[P_PEAK_DISPLACEMENT], p[P_DAMAGE], p[P_STRESS_FLOOR] = (
            law.peak_displacement,
            law.damage,
            law.stress_floor,
        )
        return [STRENGTH_MOBILIZED, after], p
    p[P_JRC], p[P_JCS], p[P_PHI_B], p[P_PHI_MAX] = law.jrc, law.jcs, law.phi_b, law.phi_max
    k = law.tangent_coefficient
    p[P_K_TANGENT] = exact_tangent_coefficient(law.jrc) if k is None else k
    return [STRENGTH_BARTON_BANDIS, after], p


def joint_tables(laws: Sequence[JointLaw]) -> tuple[np.ndarray, np.ndarray]:
    """The joint types' tables (law_codes int64 (n, LAW_COLUMNS), law_params float64 (n, PARAMETERS))
    from the laws in order; a bad law is refused in one line naming it (joint type i)."""
    rows = [_row(law, f"joint type {i}") for i, law in enumerate(laws)]
    params = np.array([r[1] for r in rows]).reshape(len(rows), PARAMETERS)
    return np.array([r[0] for r in rows], dtype=np.int64).reshape(len(rows), LAW_COLUMNS), params


@numba.njit(cache=True)
def strength(law_codes, law_params, j, sigma_n, slipped, path):
    """Mohr-Coulomb parameters (c [Pa], tan phi [1]) of a sub-contact of joint type j at effective normal
    stress sigma_n [Pa] (compression positive), `slipped` whether it has slipped before (``after_slip =
    zero`` then takes c = 0), both already divided by the strength reduction's F; and its dilation's
    tan(d_mob) [1] (0 but for the mobilized law, which reads the shear path `path` [m])."""
    p = law_params[j]
    tan_dilation = 0.0
    code = law_codes[j, STRENGTH_LAW]
    if code == STRENGTH_BARTON_BANDIS:
        args = (sigma_n, p[P_JRC], p[P_JCS], p[P_PHI_B], p[P_PHI_MAX], p[P_K_TANGENT])
        cohesion, tan_phi = equivalent_cohesion(*args), math.tan(equivalent_friction_angle(*args))
    elif code == STRENGTH_MOBILIZED:
        floored = max(sigma_n, p[P_STRESS_FLOOR])
        jrc, jcs, phi_r, peak = p[P_JRC], p[P_JCS], p[P_PHI_B], p[P_PEAK_DISPLACEMENT]
        cohesion = 0.0
        tan_phi = math.tan(mobilized_friction_angle(path, floored, jrc, jcs, phi_r, peak, p[P_PHI_MAX]))
        damage = p[P_DAMAGE] if p[P_DAMAGE] > 0.0 else damage_coefficient(floored, jrc, jcs)
        tan_dilation = math.tan(mobilized_dilation_angle(path, floored, jrc, jcs, phi_r, peak, damage))
    else:
        cohesion, tan_phi = p[P_COH], math.tan(p[P_PHI])
    if slipped and law_codes[j, AFTER_SLIP] == AFTER_SLIP_ZERO:
        cohesion = 0.0
    divisor = p[P_STRENGTH_DIVISOR]
    return cohesion / divisor, tan_phi / divisor, tan_dilation
