"""A scene's joint law (`bbmc.scene.schema.JointLaw`, the 2D scene format's `joint_laws` entries) as a
joint type of the 3D engine (`bbmc.dem3d.joint_laws`), from the same keys and the same derived joint
(`bbmc.joint.derived.joint_at_field_length`) as the 2D engine's `bbmc.dem.joint_types`, SI inside:

* `constant` -> `MohrCoulomb` (kn, ks from MPa/mm, c from MPa, phi from degrees, after_slip);
* `barton_bandis` with constant stiffnesses -> `BartonBandis`: JRC, JCS at the field length, phi_r in
  place of phi_b where given (or from the rebound ratio), phi_max, the tangent's k, after_slip;
* `barton_bandis_mobilized` with a constant normal stiffness -> `MobilizedBartonBandis`: JRC_n, JCS_n,
  phi_r, delta_peak, phi_max, M (0 for barton_1985), the stress floor.

Refused in one line naming the key (what the 3D engine does not have yet): a tensile strength (bonds),
`breaks_into` (rock bridges), and the stress-dependent stiffness laws: `eq8` normal stiffness and the
shear stiffness laws of `barton_bandis`, and the `bandis` closure of the mobilized law (its normal
stress is integrated exactly over each share as a linear spring bed, `bbmc.dem3d.contact_forces`).
"""

from __future__ import annotations

from bbmc import laws, units
from bbmc.dem3d.joint_laws import BartonBandis, JointLaw, MobilizedBartonBandis, MohrCoulomb
from bbmc.joint.derived import joint_at_field_length
from bbmc.scene.schema import BartonBandisLaw, ConstantLaw, MobilizedLaw

NOT_YET = "not in the 3D engine yet"


def _refuse_stiffness(name: str, law: BartonBandisLaw | MobilizedLaw) -> None:
    for key in ("normal_stiffness", "shear_stiffness"):
        given = getattr(law, key).law
        if given != "constant":
            raise ValueError(f"joint_laws.{name}.{key}: the law '{given}' is {NOT_YET} (give 'constant')")


def law_from_scene(name: str, law: ConstantLaw | BartonBandisLaw | MobilizedLaw) -> JointLaw:
    """The 3D joint type of the scene's joint law `name` (module docstring); ValueError in one line
    naming `joint_laws.<name>.<key>` for what the 3D engine does not have."""
    tensile = getattr(law, "tensile_strength_MPa", 0.0)
    if tensile > 0.0:
        raise ValueError(f"joint_laws.{name}.tensile_strength_MPa: a tensile strength is {NOT_YET}")
    if getattr(law, "breaks_into", None) is not None:
        raise ValueError(f"joint_laws.{name}.breaks_into: rock bridges are {NOT_YET}")
    if isinstance(law, ConstantLaw):
        return MohrCoulomb(
            law.kn_MPa_per_mm * units.MPa_per_mm,
            law.ks_MPa_per_mm * units.MPa_per_mm,
            law.friction_deg * units.deg,
            law.cohesion_MPa * units.MPa,
            law.after_slip,
        )
    _refuse_stiffness(name, law)
    kn = law.normal_stiffness.kn_MPa_per_mm * units.MPa_per_mm
    ks = law.shear_stiffness.ks_MPa_per_mm * units.MPa_per_mm
    if isinstance(law, MobilizedLaw):
        joint = joint_at_field_length(law, law.jrc0, law.jcs0_MPa)
        return MobilizedBartonBandis(
            kn,
            ks,
            joint.jrc,
            joint.jcs,
            joint.phi_r,
            joint.peak_displacement,
            phi_max=law.phi_max_deg * units.deg,
            damage=0.0 if law.damage == "barton_1985" else law.damage,
            stress_floor=law.stress_floor_MPa * units.MPa,
        )
    s = law.strength
    joint = joint_at_field_length(s, s.jrc, s.jcs_MPa)
    exact = float(laws.exact_tangent_coefficient(joint.jrc))
    return BartonBandis(
        kn,
        ks,
        joint.jrc,
        joint.jcs,
        s.phi_b_deg * units.deg if joint.phi_r is None else joint.phi_r,
        phi_max=s.phi_max_deg * units.deg,
        tangent_coefficient=exact if s.tangent_coefficient == "exact" else s.tangent_coefficient,
        after_slip=law.after_slip,
    )
