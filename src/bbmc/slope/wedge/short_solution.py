"""The angles and geometric factors of Hoek & Bray's short solution of the wedge, from its vertices.

Hoek & Bray (Rock Slope Engineering, 3rd ed. 1981, ch. 8; Wyllie & Mah 2004, section 7.2) number the
lines of a wedge: 1 = plane A's trace on the face, 2 = plane B's trace on the face, 3 = plane A's
trace on the upper surface, 4 = plane B's trace on the upper surface, 5 = the line of intersection.
Here plane A is plane 1 and plane B is plane 2 (Hoek & Bray call the flatter plane A; the formulas
hold for either labelling). With the toe O, the crest points C1 (plane 1) and C2 (plane 2) and the top
of the line of intersection T:

* theta_na.nb: the angle between the planes' upward poles;
* theta_ij: the angle between lines i and j as read on the stereonet, i.e. between the lines as axes
  (0 to 90 degrees): theta_13 and theta_35 are the angles of the face on plane 1 (triangle O C1 T) at
  C1 and at T, or their supplements; theta_24 and theta_45 those of the face on plane 2 (O C2 T);
  only their sines enter the factors, which a supplement leaves unchanged;
* theta_2.na: the angle between line 2 and plane 1's pole (as axes); theta_1.nb: line 1 and plane 2's;
* psi_5 = psi_i: the plunge of the line of intersection (out of the slope, downward positive).

The factors (Hoek & Bray 1981, eqs. for the short solution; H the wedge's total height):

    X = sin theta_24 / (sin theta_45 cos theta_2.na)      (cohesion and water on plane 1)
    Y = sin theta_13 / (sin theta_35 cos theta_1.nb)      (cohesion and water on plane 2)
    A = (cos psi_a - cos psi_b cos theta_na.nb) / (sin psi_5 sin^2 theta_na.nb)
    B = (cos psi_b - cos psi_a cos theta_na.nb) / (sin psi_5 sin^2 theta_na.nb)
    FS = 3 / (gamma H) (c_A X + c_B Y) + (A - gamma_w X / (2 gamma)) tan phi_A
         + (B - gamma_w Y / (2 gamma)) tan phi_B                (`short_solution_factor_of_safety`)

gamma the rock's and gamma_w the water's unit weight; gamma_w = 0 is the dry wedge, gamma_w > 0 Hoek &
Bray's water without a tension crack (mean pressure gamma_w H / 6 on each plane, `loads.hoek_bray_water`).
The solution holds where the wedge slides on both planes (both bracketed terms of the normal forces
>= 0) under gravity and water alone; elsewhere it is not the wedge's FS (`mechanics` gives the mode).

By the sine rule in triangle O C2 T, X = A_1 H / (3 V sin psi_5) (A_1 the area on plane 1, V the
volume), and likewise Y = A_2 H / (3 V sin psi_5); A and B are the normal reactions on planes 1 and 2
per unit W sin psi_5 under gravity alone, valid while both are >= 0 (contact on both planes).

The wedge factor (Hoek & Bray 1981, ch. 8, friction only, one phi): FS = K tan phi / tan psi_i with
K = sin beta / sin(xi / 2), xi the wedge's included angle (its interior dihedral angle at the line of
intersection, measured normal to that line) and beta the angle of xi's bisector from the horizontal in
the plane normal to the line: with n1, n2 the planes' unit normals pointing into the wedge,
xi = pi - angle(n1, n2), the bisector is along n1 + n2 and sin beta = b_z / cos psi_i.
Angles in radians.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.wedge.vectors import Vectors, angle_between, unit

Array = NDArray[np.float64]


@dataclass(frozen=True)
class ShortSolutionAngles:
    """Hoek & Bray's short-solution angles [rad] and factors [1] of wedges (module docstring)."""

    plunge: Array  # psi_5 = psi_i
    included_angle: Array  # xi
    bisector_angle: Array  # beta
    wedge_factor: Array  # K = sin beta / sin(xi / 2)
    theta_na_nb: Array
    theta_13: Array
    theta_35: Array
    theta_1_nb: Array
    theta_24: Array
    theta_45: Array
    theta_2_na: Array
    x: Array
    y: Array
    a: Array
    b: Array


def _acute(a: Vectors, b: Vectors) -> Array:
    """The angle between axes along `a` and `b` [rad], 0 to pi/2."""
    angle = angle_between(a, b)
    return np.minimum(angle, np.pi - angle)


def short_solution_angles(
    crest_1: Vectors,
    crest_2: Vectors,
    top: Vectors,
    pole_1: Vectors,
    pole_2: Vectors,
    normal_1: Vectors,
    normal_2: Vectors,
    plunge: Array,
) -> ShortSolutionAngles:
    """The short solution's angles and factors of wedges whose toe is at the origin: `crest_1`, `crest_2`,
    `top` the vertices (..., 3) [m], `pole_1`, `pole_2` the planes' upward unit poles, `normal_1`,
    `normal_2` their unit normals into the wedge, `plunge` psi_i [rad] of the line out of the slope."""
    theta_na_nb = angle_between(pole_1, pole_2)
    theta_13, theta_35 = _acute(crest_1, top - crest_1), _acute(top - crest_1, top)
    theta_24, theta_45 = _acute(crest_2, top - crest_2), _acute(top - crest_2, top)
    theta_2_na, theta_1_nb = _acute(crest_2, pole_1), _acute(crest_1, pole_2)
    included = np.pi - angle_between(normal_1, normal_2)
    bisector = unit(normal_1 + normal_2)
    with np.errstate(invalid="ignore", divide="ignore"):
        sin_beta = bisector[..., 2] / np.cos(plunge)
        beta = np.arctan2(sin_beta, np.sqrt(np.clip(1.0 - sin_beta**2, 0.0, None)))
        cos_ab, sin2_ab, sin_5 = np.cos(theta_na_nb), np.sin(theta_na_nb) ** 2, np.sin(plunge)
        cos_a, cos_b = pole_1[..., 2], pole_2[..., 2]
        return ShortSolutionAngles(
            plunge=plunge,
            included_angle=included,
            bisector_angle=beta,
            wedge_factor=sin_beta / np.sin(included / 2.0),
            theta_na_nb=theta_na_nb,
            theta_13=theta_13,
            theta_35=theta_35,
            theta_1_nb=theta_1_nb,
            theta_24=theta_24,
            theta_45=theta_45,
            theta_2_na=theta_2_na,
            x=np.sin(theta_24) / (np.sin(theta_45) * np.cos(theta_2_na)),
            y=np.sin(theta_13) / (np.sin(theta_35) * np.cos(theta_1_nb)),
            a=(cos_a - cos_b * cos_ab) / (sin_5 * sin2_ab),
            b=(cos_b - cos_a * cos_ab) / (sin_5 * sin2_ab),
        )


def short_solution_factor_of_safety(
    angles: ShortSolutionAngles,
    total_height: ArrayLike,
    unit_weight: ArrayLike,
    cohesion_a: ArrayLike,
    cohesion_b: ArrayLike,
    friction_a: ArrayLike,
    friction_b: ArrayLike,
    water_unit_weight: ArrayLike = 0.0,
) -> Array:
    """Hoek & Bray's short-solution FS (module docstring) of wedges of short-solution `angles`, total
    height H [m], rock unit weight gamma [N/m^3], cohesions c_A, c_B [Pa] and friction angles phi_A,
    phi_B [rad] of planes 1 (A) and 2 (B), and gamma_w [N/m^3] (0: dry)."""
    gamma = np.asarray(unit_weight, dtype=float)
    ratio = np.asarray(water_unit_weight, dtype=float) / (2.0 * gamma)
    cohesion = (
        3.0
        / (gamma * np.asarray(total_height, dtype=float))
        * (np.asarray(cohesion_a, dtype=float) * angles.x + np.asarray(cohesion_b, dtype=float) * angles.y)
    )
    return (
        cohesion
        + (angles.a - ratio * angles.x) * np.tan(friction_a)
        + (angles.b - ratio * angles.y) * np.tan(friction_b)
    )
