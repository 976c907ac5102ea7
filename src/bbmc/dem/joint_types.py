"""The engine's joint types from a scene's joint laws: the integer law codes and the SI parameters of
each (`bbmc.dem.layout`), and which law an intact rock breaks into."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from bbmc import laws, units
from bbmc.dem import layout as L
from bbmc.joint.derived import joint_at_field_length
from bbmc.joint.model import SIGMA_REF
from bbmc.scene.schema import (
    BartonBandisLaw,
    ConstantLaw,
    MobilizedLaw,
    Scene,
    scene_error,
)

SHEAR_CODES = {
    "constant": L.SHEAR_CONSTANT,
    "bandis": L.SHEAR_BANDIS,
    "corrected": L.SHEAR_CORRECTED,
    "simplified": L.SHEAR_SIMPLIFIED,
    "hyperbolic": L.SHEAR_HYPERBOLIC,
}


def _mobilized_law_row(law: MobilizedLaw, p: np.ndarray) -> tuple[list[int], np.ndarray]:
    """The mobilized law's parameters: JRC_n, JCS_n at the field length, phi_r, delta_peak, M, and the
    Bandis closure's K_ni, V_m (`bbmc.joint.derived`)."""
    normal = law.normal_stiffness
    bandis = normal.law == "bandis"
    joint = joint_at_field_length(
        law,
        law.jrc0,
        law.jcs0_MPa,
        aperture=normal.aperture_mm * units.mm if bandis and normal.aperture_mm is not None else None,
        sigma_c=normal.sigma_c_MPa * units.MPa if bandis and normal.sigma_c_MPa is not None else None,
    )
    p[L.P_JRC], p[L.P_JCS], p[L.P_PHI_B] = joint.jrc, joint.jcs, joint.phi_r
    p[L.P_PHI_MAX] = law.phi_max_deg * units.deg
    p[L.P_PEAK_DISPLACEMENT] = joint.peak_displacement
    p[L.P_DAMAGE] = 0.0 if law.damage == "barton_1985" else law.damage
    p[L.P_STRESS_FLOOR] = law.stress_floor_MPa * units.MPa
    p[L.P_KS] = law.shear_stiffness.ks_MPa_per_mm * units.MPa_per_mm
    if joint.closure is None:
        p[L.P_KN] = normal.kn_MPa_per_mm * units.MPa_per_mm
        normal_code = L.NORMAL_CONSTANT
    else:
        p[L.P_K_NI] = p[L.P_KN] = joint.closure.kni
        p[L.P_V_M] = joint.closure.vm
        normal_code = L.NORMAL_BANDIS
    return [L.STRENGTH_MOBILIZED, normal_code, L.SHEAR_CONSTANT, L.AFTER_SLIP_KEEP], p


def _joint_law_row(law: ConstantLaw | BartonBandisLaw | MobilizedLaw) -> tuple[list[int], np.ndarray]:
    p = np.zeros(L.PARAMETERS)
    p[L.P_STRENGTH_DIVISOR] = 1.0
    if isinstance(law, MobilizedLaw):
        return _mobilized_law_row(law, p)
    after = L.AFTER_SLIP_ZERO if law.after_slip == "zero" else L.AFTER_SLIP_KEEP
    p[L.P_TEN] = law.tensile_strength_MPa * units.MPa
    if isinstance(law, ConstantLaw):
        p[L.P_KN] = law.kn_MPa_per_mm * units.MPa_per_mm
        p[L.P_KS] = law.ks_MPa_per_mm * units.MPa_per_mm
        p[L.P_COH] = law.cohesion_MPa * units.MPa
        p[L.P_PHI] = law.friction_deg * units.deg
        return [L.STRENGTH_CONSTANT, L.NORMAL_CONSTANT, L.SHEAR_CONSTANT, after], p
    s = law.strength
    joint = joint_at_field_length(s, s.jrc, s.jcs_MPa)
    p[L.P_JRC], p[L.P_JCS] = joint.jrc, joint.jcs
    p[L.P_PHI_B] = s.phi_b_deg * units.deg if joint.phi_r is None else joint.phi_r
    p[L.P_PHI_MAX] = s.phi_max_deg * units.deg
    exact = float(laws.exact_tangent_coefficient(joint.jrc))
    p[L.P_K_TANGENT] = exact if s.tangent_coefficient == "exact" else s.tangent_coefficient
    p[L.P_STRESS_FLOOR] = law.stress_floor_MPa * units.MPa
    p[L.P_SHEAR_FLOOR] = law.shear_stiffness_floor
    p[L.P_SIGMA_REF] = SIGMA_REF
    normal, shear = law.normal_stiffness, law.shear_stiffness
    if normal.law == "constant":
        p[L.P_KN] = normal.kn_MPa_per_mm * units.MPa_per_mm
    else:
        p[L.P_Q], p[L.P_LG_E] = normal.q_per_mm * units.per_mm, normal.lg_e
    if shear.law == "constant":
        p[L.P_KS] = shear.ks_MPa_per_mm * units.MPa_per_mm
    else:
        p[L.P_K_J], p[L.P_N_J] = shear.kj_MPa_per_mm * units.MPa_per_mm, shear.nj
    if shear.law == "simplified":
        p[L.P_D] = shear.d
    elif shear.law != "constant":
        p[L.P_TAU_P_SLOPE] = shear.peak_strength.slope
        p[L.P_TAU_P_INTERCEPT] = shear.peak_strength.intercept_MPa * units.MPa
        p[L.P_TAU_ULT_SLOPE] = shear.ultimate_strength.slope
        p[L.P_TAU_ULT_INTERCEPT] = shear.ultimate_strength.intercept_MPa * units.MPa
        p[L.P_A], p[L.P_B] = shear.a, shear.b
    normal_code = L.NORMAL_CONSTANT if normal.law == "constant" else L.NORMAL_EQ8
    return [L.STRENGTH_BARTON_BANDIS, normal_code, SHEAR_CODES[shear.law], after], p


def joint_types(scene: Scene, path: Path) -> tuple[list[str], np.ndarray, np.ndarray]:
    """The scene's joint laws as the engine's joint types: their names, the integer law codes (LAW_COLUMNS
    each, BREAKS_INTO resolved: the type an intact rock becomes where it breaks, -1 for none) and the
    SI parameters (PARAMETERS each); a `breaks_into` that names no law, a law that breaks itself, or a
    bridge with no strength is refused in one line."""
    law_names = list(scene.joint_laws)
    rows = [_joint_law_row(law) for law in scene.joint_laws.values()]
    law_codes = np.array([r[0] + [-1] for r in rows], dtype=np.int64)
    for j, (name, law) in enumerate(scene.joint_laws.items()):
        target = getattr(law, "breaks_into", None)
        if target is None:
            continue
        key = f"joint_laws.{name}.breaks_into"
        if target not in law_names:
            raise scene_error(path, key, f"no joint law '{target}' in joint_laws")
        if law.cohesion_MPa == 0.0 and law.tensile_strength_MPa == 0.0:
            raise scene_error(
                path, key, "a bridge with no strength: give it cohesion_MPa or tensile_strength_MPa"
            )
        if getattr(scene.joint_laws[target], "breaks_into", None) is not None:
            raise scene_error(path, key, f"'{target}' breaks into a law itself: a bridge breaks into a joint")
        if target == name:
            raise scene_error(path, key, "a law cannot break into itself")
        law_codes[j, L.BREAKS_INTO] = law_names.index(target)
    params = np.array([r[1] for r in rows])
    return law_names, law_codes, params
