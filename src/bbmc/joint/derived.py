"""The full Barton-Bandis joint's derived inputs, computed in one place for every user: the engine's law
parameters of both Barton-Bandis laws, the full joint's and the peak envelope's (`bbmc.dem.joint_types`),
the 3D engine's (`bbmc.dem3d.scene_laws`), the slope's joints (`bbmc.slope.safety`) and `bbmc joint`'s
curves.

From a joint measured on a lab specimen (JRC_0, JCS_0 at length L_0) to the joint at its field length
L_n, in SI (Pa, m, rad), with the laws of `bbmc.laws.mobilized` (as ufuncs, `bbmc.laws`):

* JRC_n = JRC_0 (L_n/L_0)^(-0.02 JRC_0), JCS_n = JCS_0 (L_n/L_0)^(-0.03 JRC_0) (Barton & Bandis 1982);
* delta_peak = (L_n/500) (JRC_n/L_n)^0.33, L_n in m (Barton & Bandis 1982);
* phi_r as given, or phi_r = (phi_b - 20 deg) + 20 deg r/R (Barton & Choubey 1977);
* the Bandis closure from the lab values JRC_0, JCS_0 (where the fits were made, `bbmc.laws.mobilized`
  note (a)): a_j as given or a_j = (JRC_0/5)(0.2 sigma_c/JCS_0 - 0.1) [mm] (Barton, Bandis & Bakhtar
  1985), K_ni = -7.15 + 1.75 JRC_0 + 0.02 JCS_0/a_j [MPa/mm] and V_m = A + B JRC_0 + C (JCS_0/a_j)^D
  [mm] (Bandis, Lumsden & Barton 1983, first loading cycle).
"""

from __future__ import annotations

from dataclasses import dataclass

from bbmc import laws, units
from bbmc.joint.inputs import ResidualAndScale


@dataclass(frozen=True)
class Closure:
    """The Bandis closure's parameters (lab values): aperture a_j [m], K_ni [Pa/m], V_m [m]."""

    aperture: float
    kni: float
    vm: float


@dataclass(frozen=True)
class FullJoint:
    """The joint at one length: L [m], JRC [1], JCS [Pa], delta_peak [m], phi_r [rad] (None: not asked
    for, a peak-only joint) and its Bandis closure (None: no aperture source given)."""

    length: float
    jrc: float
    jcs: float
    peak_displacement: float
    phi_r: float | None
    closure: Closure | None


def full_joint(
    jrc0: float,
    jcs0: float,
    lab_length: float,
    field_length: float,
    *,
    phi_b: float | None = None,
    phi_r: float | None = None,
    rebound_ratio: float | None = None,
    aperture: float | None = None,
    sigma_c: float | None = None,
) -> FullJoint:
    """The derived inputs of the joint with JRC_0 `jrc0` [1] and JCS_0 `jcs0` [Pa] measured at
    `lab_length` L_0 [m], taken to `field_length` L_n [m] (the module docstring's equations).

    phi_r [rad]: `phi_r` as given, else from `phi_b` [rad] and `rebound_ratio` r/R [1] when both are
    given, else None. The closure: from `aperture` a_j [m] if given, else from the rock's uniaxial
    strength `sigma_c` [Pa], else None. The inputs are taken as checked (`bbmc.joint.inputs`).
    """
    jrc = float(laws.scaled_jrc(jrc0, lab_length, field_length))
    jcs = float(laws.scaled_jcs(jcs0, jrc0, lab_length, field_length))
    if phi_r is None and phi_b is not None and rebound_ratio is not None:
        phi_r = float(laws.residual_friction_angle(phi_b, rebound_ratio))
    if aperture is None and sigma_c is not None:
        aperture = float(laws.initial_aperture(jrc0, jcs0, sigma_c))
    closure = None
    if aperture is not None:
        closure = Closure(
            aperture,
            float(laws.bandis_initial_normal_stiffness(jrc0, jcs0, aperture)),
            float(laws.bandis_maximum_closure(jrc0, jcs0, aperture)),
        )
    peak = float(laws.peak_shear_displacement(field_length, jrc))
    return FullJoint(field_length, jrc, jcs, peak, phi_r, closure)


def joint_at_field_length(
    keys: ResidualAndScale,
    jrc: float,
    jcs_MPa: float,
    aperture: float | None = None,
    sigma_c: float | None = None,
) -> FullJoint:
    """A scene's Barton-Bandis law's joint (either law: the keys they share, `bbmc.joint.inputs`, with
    its phi_b_deg) at its field length, in SI (`full_joint`): JRC [1] and JCS [MPa] as given at the lab
    length, phi_r given or from the rebound ratio (None where neither is), and the closure from
    `aperture` [m] or `sigma_c` [Pa] where given."""
    return full_joint(
        jrc,
        jcs_MPa * units.MPa,
        keys.lab_length_m,
        keys.field_length_m or keys.lab_length_m,
        phi_b=keys.phi_b_deg * units.deg,
        phi_r=None if keys.phi_r_deg is None else keys.phi_r_deg * units.deg,
        rebound_ratio=keys.rebound_ratio,
        aperture=aperture,
        sigma_c=sigma_c,
    )
