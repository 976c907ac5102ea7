"""Planar failure of a rock slope with a tension crack: Hoek & Bray's limit equilibrium, vectorised.

The slope (Hoek & Bray 1981, ch. 7; Wyllie & Mah 2004, section 6.4): height H, face dipping at psi_f,
a horizontal upper surface, a failure plane dipping at psi_p < psi_f that daylights at the toe, and a
vertical tension crack whose foot, on the plane, lies z below the crest's level. The crack is in the
upper surface (behind the crest) when z / H <= 1 - cot(psi_f) tan(psi_p), else in the face. Water
fills the crack to z_w, enters the plane at the crack's foot and leaves at the toe: the pressure on
the plane falls linearly from gamma_w z_w to 0. A pseudo-static horizontal acceleration k_h g acts on
the block, out of the slope. Per metre of slope, with the block's weight W:

    A = (H - z) / sin psi_p                                  (length of the plane)
    W = 1/2 gamma H^2 [(1 - (z/H)^2) cot psi_p - cot psi_f]  (crack in the upper surface)
    W = 1/2 gamma H^2 (1 - z/H)^2 cot psi_p (cot psi_p tan psi_f - 1)   (crack in the face)
    U = 1/2 gamma_w z_w A,   V = 1/2 gamma_w z_w^2           (water on the plane, in the crack)
    N = W (cos psi_p - k_h sin psi_p) - U - V sin psi_p      (effective normal force on the plane)
    D = W (sin psi_p + k_h cos psi_p) + V cos psi_p          (driving force along the plane)
    FS = R / D,  R = c A + N tan phi (Mohr-Coulomb)  or  R = A tau_p(N / A) (Barton-Bandis, eq 9)

The Barton-Bandis strength is evaluated at the plane's mean effective normal stress N / A, as rock
engineers do for planar sliding. Rules at the edges: where the water lifts the block off its plane
(N <= 0) the friction term is 0 (the plane keeps its cohesion; Barton-Bandis gives no strength), never
negative. Geometry that forms no block (psi_p >= psi_f, psi_p <= 0, z >= H, z < 0, z_w below 0 or
above the crack's height: z in the upper surface, (H - z)(cot psi_p tan psi_f - 1) in the face) is
refused with ValueError naming the condition.

Support (a bolt, anchor or cable pattern; Hoek & Bray 1981 ch. 7; Wyllie & Mah 2004 eq 6.24): a force T
per metre run acting on the block at an angle theta to the plane, measured from the plane's up-dip
direction and positive towards the plane, i.e. into the rock: its components are T_s = T cos theta up
the plane and T_n = T sin theta pressing the block onto it. A bolt drilled from the face plunging psi_T
below the horizontal into the slope has theta = psi_p + psi_T; theta = 90 deg is a bolt normal to the
plane, theta = 0 a force pulling straight up-dip. RocPlane's two ways of counting T:

    active  (a pretensioned anchor, T acts before any movement; RocPlane's "active", equal to an
             external force): FS = (c A + (N + T_n) tan phi) / (D - T_s)
    passive (a grouted bolt mobilised by movement; its resisting part joins the resisting force):
             FS = (c A + (N + T_n) tan phi + T_s) / D

The Barton-Bandis forms put N + T_n in place of N. Where the active support alone holds the block
(D - T_s <= 0) FS = +inf. T >= 0 (a bolt pulls; it cannot push) is required.

The critical crack (Hoek & Bray, dry slope): depth z_c / H = 1 - sqrt(cot psi_f tan psi_p), behind
the crest by b_c / H = sqrt(cot psi_f cot psi_p) - cot psi_f.

SI throughout: lengths m, angles rad, unit weights N/m^3, stresses Pa, forces N per metre. Every
function broadcasts over numpy arrays of its arguments (for Monte Carlo: one call for all samples).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc import laws

WATER_UNIT_WEIGHT = 9810.0  # N/m^3


@dataclass(frozen=True)
class PlanarForces:
    """The forces of Hoek & Bray's planar analysis [N per metre] and the plane's length [m]."""

    plane_length: NDArray[np.float64]
    weight: NDArray[np.float64]
    uplift: NDArray[np.float64]
    crack_water: NDArray[np.float64]
    normal: NDArray[np.float64]
    driving: NDArray[np.float64]
    crack_in_face: NDArray[np.bool_]


def _refuse_where(bad: NDArray[np.bool_], what: str) -> None:
    if np.any(bad):
        raise ValueError(f"no planar block: {what}")


def crack_depth_behind_crest(height: ArrayLike, face: ArrayLike, plane: ArrayLike, distance: ArrayLike):
    """Depth z [m] of a vertical crack `distance` [m] behind the crest, down to the plane:
    z = H - (H cot psi_f + b) tan psi_p."""
    height, face, plane, distance = np.broadcast_arrays(*map(np.asarray, (height, face, plane, distance)))
    return height - (height / np.tan(face) + distance) * np.tan(plane)


def critical_crack(height: ArrayLike, face: ArrayLike, plane: ArrayLike) -> tuple[NDArray, NDArray]:
    """Hoek & Bray's critical tension crack of a dry slope: its depth z_c and its distance behind the
    crest b_c [m]: z_c / H = 1 - sqrt(cot psi_f tan psi_p),
    b_c / H = sqrt(cot psi_f cot psi_p) - cot psi_f."""
    height, face, plane = np.broadcast_arrays(*map(np.asarray, (height, face, plane)))
    cot_f = 1.0 / np.tan(face)
    return height * (1.0 - np.sqrt(cot_f * np.tan(plane))), height * (np.sqrt(cot_f / np.tan(plane)) - cot_f)


def planar_forces(
    height: ArrayLike,
    face: ArrayLike,
    plane: ArrayLike,
    crack_depth: ArrayLike,
    water_depth: ArrayLike,
    unit_weight: ArrayLike,
    seismic_coefficient: ArrayLike = 0.0,
    water_unit_weight: float = WATER_UNIT_WEIGHT,
) -> PlanarForces:
    """A, W, U, V, N and D of the module docstring; H, z, z_w [m], psi_f, psi_p [rad], gamma [N/m^3],
    k_h [1]."""
    h, face, plane, z, zw, gamma, kh = np.broadcast_arrays(
        *(
            np.asarray(v, dtype=float)
            for v in (height, face, plane, crack_depth, water_depth, unit_weight, seismic_coefficient)
        )
    )
    _refuse_where(~(plane > 0.0), "the plane must dip (psi_p > 0)")
    _refuse_where(~(plane < face), "the plane must daylight in the face (psi_p < psi_f)")
    _refuse_where(~((z >= 0.0) & (z < h)), "the crack depth must be 0 <= z < H")
    _refuse_where(~(h > 0.0) | ~(gamma > 0.0), "height and unit weight must be > 0")
    cot_p, tan_f = 1.0 / np.tan(plane), np.tan(face)
    ratio = z / h
    in_face = ratio > 1.0 - np.tan(plane) / tan_f
    crack_height = np.where(in_face, (h - z) * (cot_p * tan_f - 1.0), z)  # a face crack ends in the face
    _refuse_where(
        ~((zw >= 0.0) & (zw <= crack_height)), "the water in the crack must be 0 <= z_w <= its height"
    )
    upper = 0.5 * gamma * h**2 * ((1.0 - ratio**2) * cot_p - 1.0 / tan_f)
    lower = 0.5 * gamma * h**2 * (1.0 - ratio) ** 2 * cot_p * (cot_p * tan_f - 1.0)
    weight = np.where(in_face, lower, upper)
    length = (h - z) / np.sin(plane)
    uplift = 0.5 * water_unit_weight * zw * length
    crack = 0.5 * water_unit_weight * zw**2
    normal = weight * (np.cos(plane) - kh * np.sin(plane)) - uplift - crack * np.sin(plane)
    driving = weight * (np.sin(plane) + kh * np.cos(plane)) + crack * np.cos(plane)
    return PlanarForces(length, weight, uplift, crack, normal, driving, in_face)


SUPPORT_FORMS = ("active", "passive")


@dataclass(frozen=True)
class Support:
    """A support force T [N per metre run] at theta [rad] from the plane's up-dip direction, towards
    the plane (module docstring), counted in RocPlane's `form`, "active" or "passive"."""

    force: ArrayLike
    angle: ArrayLike
    form: str = "active"

    def __post_init__(self) -> None:
        if self.form not in SUPPORT_FORMS:
            raise ValueError(f"support form must be one of {SUPPORT_FORMS}, not {self.form!r}")
        if np.any(~(np.asarray(self.force, dtype=float) >= 0.0)):
            raise ValueError("support force must be >= 0 (a bolt pulls, it cannot push)")

    @property
    def along(self) -> NDArray:
        """T_s = T cos theta, up the plane [N/m]."""
        return np.asarray(self.force, dtype=float) * np.cos(self.angle)

    @property
    def onto(self) -> NDArray:
        """T_n = T sin theta, onto the plane [N/m]."""
        return np.asarray(self.force, dtype=float) * np.sin(self.angle)


def _factor_of_safety(
    forces: PlanarForces, resisting: Callable[[NDArray], NDArray], support: Support | None
) -> NDArray:
    """FS from the resisting force as a function of the effective normal force (clipped at 0)."""
    if support is None:
        return resisting(np.maximum(forces.normal, 0.0)) / forces.driving
    held = resisting(np.maximum(forces.normal + support.onto, 0.0))
    if support.form == "passive":
        return (held + support.along) / forces.driving
    driving = forces.driving - support.along
    with np.errstate(divide="ignore"):
        return np.where(driving > 0.0, held / np.where(driving > 0.0, driving, 1.0), np.inf)


def factor_of_safety_mohr_coulomb(
    forces: PlanarForces, cohesion: ArrayLike, friction: ArrayLike, support: Support | None = None
) -> NDArray:
    """FS = (c A + max(N, 0) tan phi) / D; c [Pa], phi [rad]; with a support, its active or passive
    form of the module docstring."""

    def resisting(normal: NDArray) -> NDArray:
        return np.asarray(cohesion) * forces.plane_length + normal * np.tan(friction)

    return _factor_of_safety(forces, resisting, support)


def factor_of_safety_barton_bandis(
    forces: PlanarForces,
    jrc: ArrayLike,
    jcs: ArrayLike,
    phi_b: ArrayLike,
    phi_max: ArrayLike,
    support: Support | None = None,
) -> NDArray:
    """FS = A tau_p(sigma_n) / D with sigma_n = N / A and tau_p from eq 9 (`bbmc.laws`): JRC [1],
    JCS [Pa], phi_b and phi_max [rad]. No strength where N <= 0. With a support, N + T_n in place of
    N and its active or passive form of the module docstring."""

    def resisting(normal: NDArray) -> NDArray:
        return forces.plane_length * laws.peak_shear_strength(
            normal / forces.plane_length, jrc, jcs, phi_b, phi_max
        )

    return _factor_of_safety(forces, resisting, support)
