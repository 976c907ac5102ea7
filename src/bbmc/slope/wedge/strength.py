"""A wedge plane's Barton-Bandis strength as a force, for `mechanics.wedge_factor_of_safety`: the peak
envelope at the plane's own effective normal stress from statics, its scale correction to the plane's
size, the paper's equivalent Mohr-Coulomb and a waviness angle.

* Barton-Bandis peak strength (the paper's eq 9, `bbmc.laws.peak_shear_strength`, the one law in bbmc):
      tau_p = sigma_n tan(min(phi_b + JRC_n lg(JCS_n / sigma_n), phi_max) + i),   sigma_n = N / A,
  N [N] the plane's effective normal force from statics (mechanics), A [m^2] its contact area: the
  mean stress over the plane, as `bbmc.slope.planar.factor_of_safety_barton_bandis` takes it. The
  plane's shear strength as a force is A tau_p [N]; an open plane (N <= 0) has none.
* Scale (Barton & Bandis 1982, `bbmc.laws.scaled_jrc`, `scaled_jcs`): JRC_n = JRC_0 (L_n/L_0)^(-0.02
  JRC_0), JCS_n = JCS_0 (L_n/L_0)^(-0.03 JRC_0), L_0 the lab specimen's length and L_n the joint's
  length in the direction of shear: for a wedge sliding on both planes, the length of its line of
  intersection (`geometry.WedgeGeometry.intersection_length`), the edge both planes slide along. A
  length <= 0 (the default) applies no scale.
* Waviness (Barton 1973; Hoek & Bray 1981, ch. 4; Swedge's "Waviness"): a large-scale undulation of
  amplitude angle i [rad] that shearing must ride over; it adds to the total friction angle, on top of
  the small-scale B-B angle and its cap: tan(min(phi_b + JRC lg(JCS/sigma_n), phi_max) + i). It is
  the law's angle arguments shifted by i, phi_b + i and phi_max + i, so the law is never copied.
  phi_max + i must stay below 90 degrees.
* Equivalent Mohr-Coulomb (the paper's eqs 11-14, `bbmc.laws.equivalent_friction_angle`,
  `equivalent_cohesion`, as `bbmc mc` reports them): the tangent of the envelope at sigma_n,
      tan phi_t = tan(theta) - k (tan^2 theta + 1),   c_t = tau_p - sigma_n tan phi_t,
  theta the total angle (waviness included; d(theta)/d(sigma_n) does not depend on i) and the exact
  k = pi JRC_n / (180 ln 10). On a plane at its own sigma_n, c_t A + N tan phi_t = A tau_p exactly.

The factor of safety and strength reduction. The vector solution's FS is the ratio of the planes'
strength at the normal forces from statics to the driving force. Statics gives those normal forces
without the strength (the wedge slides along one direction, and equilibrium normal to it fixes them),
so no iteration is needed, and dividing each plane's B-B shear strength by F until limit equilibrium
(tau_p / F, i.e. tan of the total angle divided by F) gives the same FS: the normal stresses do not
move as the strength is reduced. What a strength-reduction definition changes for B-B is where the
reduction is applied: reducing the parameters (tan phi_b / F and JRC / F, as some codes reduce B-B)
bends the envelope, so the F at limit equilibrium solves sum_i A_i tau_p(sigma_n,i; F) = D by
iteration on F (at the same sigma_n,i) and differs from the ratio FS; it equals the ratio FS only where
the envelope is linear in N (Mohr-Coulomb, JRC = 0). On 3DEC's wedge (planes 40/130 and 60/220, W = 20 MN,
A = 120 and 90 m^2, JRC_0 8, JCS_0 60 MPa, phi_b 30 deg, L_n 10 m) the ratio FS is 1.2273 and the
parameter reduction's 1.2530. In a deformable model (`bbmc fos`'s engine)
the normal stresses also redistribute as the strength falls.

SI throughout: forces N, areas m^2, stresses Pa, lengths m, angles rad; arrays broadcast over samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc import laws
from bbmc.slope.wedge.mechanics import MohrCoulomb, PlaneStrength

PHI_MAX = 70.0 * math.pi / 180.0  # the cap on the B-B angle, as `bbmc.laws.strength` takes it


@dataclass(frozen=True)
class BartonBandis:
    """A plane's Barton-Bandis strength (module docstring): JRC_0 [1] and JCS_0 [Pa] at the lab length
    L_0 [m], scaled to the field length L_n [m] (no scale where either is <= 0), the basic (or
    residual) friction angle phi_b and the cap phi_max [rad], and the waviness angle i [rad]."""

    jrc: ArrayLike
    jcs: ArrayLike
    basic_friction: ArrayLike
    max_friction: ArrayLike = PHI_MAX
    lab_length: ArrayLike = 0.0
    field_length: ArrayLike = 0.0
    waviness: ArrayLike = 0.0

    def __post_init__(self) -> None:
        if np.any(~(np.asarray(self.max_friction) + np.asarray(self.waviness) < 0.5 * math.pi)):
            raise ValueError("max_friction + waviness must be below 90 degrees")
        if np.any(~(np.asarray(self.waviness) >= 0.0)):
            raise ValueError("waviness must be >= 0")

    def scaled(self) -> tuple[NDArray, NDArray]:
        """JRC_n [1] and JCS_n [Pa] at the field length (Barton & Bandis 1982)."""
        jrc_n = laws.scaled_jrc(self.jrc, self.lab_length, self.field_length)
        return jrc_n, laws.scaled_jcs(self.jcs, self.jrc, self.lab_length, self.field_length)

    def _arguments(self) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """The law's (JRC_n, JCS_n, phi_b + i, phi_max + i)."""
        jrc_n, jcs_n = self.scaled()
        i = np.asarray(self.waviness, dtype=float)
        return jrc_n, jcs_n, np.asarray(self.basic_friction) + i, np.asarray(self.max_friction) + i

    def shear_stress(self, sigma_n: ArrayLike) -> NDArray:
        """tau_p [Pa] at the effective normal stress sigma_n [Pa] (0 where sigma_n <= 0)."""
        return laws.peak_shear_strength(sigma_n, *self._arguments())

    def shear_force(self, normal: NDArray, area: NDArray) -> NDArray:
        """A tau_p(N / A) [N] for the effective normal force N [N] on the contact area A [m^2]."""
        area = np.asarray(area, dtype=float)
        with np.errstate(invalid="ignore", divide="ignore"):
            sigma_n = np.where(area > 0.0, np.asarray(normal, dtype=float) / area, 0.0)
        return area * self.shear_stress(sigma_n)

    def equivalent_mohr_coulomb(self, sigma_n: ArrayLike) -> MohrCoulomb:
        """The tangent Mohr-Coulomb strength at sigma_n [Pa] (module docstring): c_t [Pa], phi_t [rad]."""
        jrc_n, jcs_n, phi_b, phi_max = self._arguments()
        k = laws.exact_tangent_coefficient(jrc_n)
        return MohrCoulomb(
            laws.equivalent_cohesion(sigma_n, jrc_n, jcs_n, phi_b, phi_max, k),
            laws.equivalent_friction_angle(sigma_n, jrc_n, jcs_n, phi_b, phi_max, k),
        )


def normal_stresses(normal_1: ArrayLike, normal_2: ArrayLike, area_1: ArrayLike, area_2: ArrayLike):
    """sigma_n on planes 1 and 2 [Pa] from their effective normal forces [N] (`WedgeSolution.normal_1`,
    `normal_2`) and contact areas [m^2]: N_i / A_i, 0 on a plane lifted off or without area."""
    out = []
    for n, a in ((normal_1, area_1), (normal_2, area_2)):
        n, a = np.asarray(n, dtype=float), np.asarray(a, dtype=float)
        with np.errstate(invalid="ignore", divide="ignore"):
            out.append(np.where(a > 0.0, np.maximum(n, 0.0) / np.where(a > 0.0, a, 1.0), 0.0))
    return out[0], out[1]


def tangent_strength(strength: PlaneStrength, sigma_n: ArrayLike) -> MohrCoulomb:
    """A plane's Mohr-Coulomb c [Pa] and phi [rad] at sigma_n [Pa]: a Mohr-Coulomb plane's own, a
    Barton-Bandis plane's tangent there (`BartonBandis.equivalent_mohr_coulomb`)."""
    tangent = getattr(strength, "equivalent_mohr_coulomb", None)
    return tangent(sigma_n) if tangent is not None else strength
