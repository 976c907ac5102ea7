"""The wedge's limit equilibrium, in vector form: normal reactions from statics, the sliding mode and the
factor of safety, vectorised over samples.

Sources: Hoek & Bray (1981), Rock Slope Engineering, 3rd ed., ch. 8 and appendix 2 (the comprehensive
solution); Wyllie & Mah (2004), Rock Slope Engineering, 4th ed., appendix III (the same solution);
Rocscience Swedge, theory manual ("Factor of Safety Calculations": active and passive force vectors,
sliding direction, normal forces, resisting forces, safety factor) and help page "Sliding Planes"
(the modes and their names). Written from the equations, in bbmc's own notation:

* n1, n2: unit normals of joint planes 1 and 2 pointing INTO the wedge, the sense in which each plane's
  reaction pushes it. For a wedge lying on both planes these are the upward poles
  (`bbmc.geometry.orientation.poles`); where one plane overlies the wedge (Hoek & Bray's "plane 2
  overlies plane 1", which their sign factors rho and mu handle) its normal into the wedge points down.
  r = n1 . n2; l = n1 x n2 / |n1 x n2| turned downward, the line of intersection.
* F: the active resultant [N]: the weight (0, 0, -W), the water's normal forces U1 n1 + U2 n2 (pressure
  pushes the wedge off each plane), seismic and external forces and active (pretensioned) support.
  P: the passive resultant [N] (passive, untensioned support mobilised by movement).
* Contact on both planes: F + N1 n1 + N2 n2 + S l = 0, dotted with n1 and n2 (l is normal to both):
      N1 = (-F.n1 + r F.n2) / (1 - r^2),   N2 = (-F.n2 + r F.n1) / (1 - r^2)
  the effective normal forces (water included in F gives Hoek & Bray's N1 = (...) - U1). The wedge
  slides along l, down the line where F.l > 0 (driving force D = F.l) and up it where F.l < 0 (the
  support or an external force pushes the wedge into the slope; D = |F.l|, the FS then measures the
  joints' resistance to being pushed up: Swedge's "Sliding UP Line of Intersection").
* Contact on plane 1 alone (N2 < 0: the wedge would pull off plane 2): N1' = -F.n1, sliding along the
  part of F in plane 1, t1 = F - (F.n1) n1, D = |t1|. N2 < 0 is exactly t1 . n2 > 0: sliding on plane 1
  moves the wedge off plane 2 (N2 (1 - r^2) = -t1 . n2). Likewise plane 2 alone where N1 < 0.
  Where the single-plane normal force is not positive too, contact is lost on both planes: this is
  exactly F.n1 >= 0 and F.n2 >= 0, F pointing away from both planes (the wedge "floats"; Swedge's
  "Contact Lost on Both Planes"). Its FS is 0 by Hoek & Bray's convention (appendix 2: contact lost
  on both planes, FS = 0), whatever the passive support. The four regions partition all F: at most
  one of "plane 1 alone" and "plane 2 alone" holds (both would need |r| > 1).
* The mode comes from the active forces alone (Swedge: passive forces resist, they do not drive). The
  passive resultant adds its normal parts to the planes in contact (the same 2x2 solution on both
  planes, -P.n1 on plane 1 alone) and its component against the sliding direction s to the resistance:
      FS = (sum over planes in contact of tau_i(N_i) + (-P.s)) / D,
      tau_i = c_i A_i + max(N_i, 0) tan phi_i   (Mohr-Coulomb; a plane's strength as a force [N])
  A plane's strength comes from its own normal force from statics, so no iteration is needed; a
  strength-reduction definition (FS the factor dividing tan phi and c until equilibrium) gives the same
  number for Mohr-Coulomb and for any strength linear in N, but differs for a curved envelope
  (Barton-Bandis), where it would need the normal forces at the reduced strength. Where D = 0 the
  wedge has no driving force and FS = +inf.

SI throughout: forces N, areas m^2, stresses Pa, angles rad. Vectors are arrays (..., 3) (x east,
y north, z up), scalars arrays (...); every input broadcasts over leading sample axes.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.geometry.orientation import intersection_lines
from bbmc.slope.wedge.vectors import spread

DOWN = np.array([0.0, 0.0, -1.0])


class SlidingMode(IntEnum):
    """How the wedge moves (Swedge's "Sliding Planes"); the values are stored per sample (int8)."""

    LIFTED = 0  # contact lost on both planes
    PLANE_1 = 1  # sliding on plane 1 alone, plane 2 lifted off
    PLANE_2 = 2  # sliding on plane 2 alone, plane 1 lifted off
    BOTH = 3  # sliding down the line of intersection on both planes
    BOTH_UP = 4  # pushed up the line of intersection on both planes

    @property
    def description(self) -> str:
        """The mode as a report names it."""
        return MODE_DESCRIPTIONS[self]


MODE_DESCRIPTIONS = {
    SlidingMode.LIFTED: "contact lost on both planes",
    SlidingMode.PLANE_1: "sliding on plane 1",
    SlidingMode.PLANE_2: "sliding on plane 2",
    SlidingMode.BOTH: "sliding along the line of intersection",
    SlidingMode.BOTH_UP: "sliding up the line of intersection",
}


class PlaneStrength(Protocol):
    """A joint plane's shear strength as a force [N] at its effective normal force N >= 0 [N] on its
    contact area A [m^2]."""

    def shear_force(self, normal: NDArray, area: NDArray) -> NDArray: ...


@dataclass(frozen=True)
class MohrCoulomb:
    """Mohr-Coulomb strength: cohesion c [Pa], friction angle phi [rad]; tau A = c A + N tan phi."""

    cohesion: ArrayLike
    friction: ArrayLike

    def shear_force(self, normal: NDArray, area: NDArray) -> NDArray:
        """c A + N tan phi [N]."""
        return np.asarray(self.cohesion) * area + normal * np.tan(self.friction)


@dataclass(frozen=True)
class WedgeSolution:
    """The limit equilibrium of wedges (module docstring), one entry per sample: the mode (`SlidingMode`
    values), the effective normal forces on planes 1 and 2 used for their strength [N] (0 on a plane
    lifted off; passive support included), the driving force along the sliding direction D >= 0 [N],
    the resisting force [N], the sliding direction s (..., 3) (NaN where contact is lost on both
    planes) and FS."""

    mode: NDArray[np.int8]
    normal_1: NDArray[np.float64]
    normal_2: NDArray[np.float64]
    driving: NDArray[np.float64]
    resisting: NDArray[np.float64]
    sliding_direction: NDArray[np.float64]
    factor_of_safety: NDArray[np.float64]

    def modes(self) -> NDArray[np.object_]:
        """The mode of each sample as its description."""
        names = np.array([MODE_DESCRIPTIONS[m] for m in SlidingMode], dtype=object)
        return np.asarray(names[self.mode], dtype=object)


def _dot(a: NDArray, b: NDArray) -> NDArray:
    return np.einsum("...i,...i->...", a, b)


def active_resultant(
    weight: ArrayLike,
    normal_1: ArrayLike,
    normal_2: ArrayLike,
    water_1: ArrayLike = 0.0,
    water_2: ArrayLike = 0.0,
    forces: ArrayLike = 0.0,
    gravity: ArrayLike = DOWN,
) -> NDArray:
    """F = W g + U1 n1 + U2 n2 + sum of `forces` (..., 3) [N]: the weight W [N] along the unit vector
    `gravity` (straight down unless given), the water's normal forces U1, U2 [N] along the normals into
    the wedge, and the other active forces already summed (seismic, external, active support)."""
    w = np.asarray(weight, dtype=float)[..., None] * np.asarray(gravity, dtype=float)
    u1 = np.asarray(water_1, dtype=float)[..., None] * np.asarray(normal_1, dtype=float)
    u2 = np.asarray(water_2, dtype=float)[..., None] * np.asarray(normal_2, dtype=float)
    return w + u1 + u2 + np.asarray(forces, dtype=float)


def _both_planes(f1: NDArray, f2: NDArray, r: NDArray) -> tuple[NDArray, NDArray]:
    """N1, N2 balancing a force of components f1 = F.n1, f2 = F.n2 with contact on both planes."""
    det = 1.0 - r * r
    return (-f1 + r * f2) / det, (-f2 + r * f1) / det


@dataclass(frozen=True)
class _Statics:
    """The active resultant's parts used by the modes: F.n1, F.n2, r, F.l, and N1, N2 on both planes."""

    mode: NDArray[np.int8]
    force_1: NDArray
    force_2: NDArray
    cosine: NDArray
    along: NDArray
    normal_1: NDArray
    normal_2: NDArray
    line: NDArray


def _statics(active: NDArray, normal_1: NDArray, normal_2: NDArray) -> _Statics:
    line, _ = intersection_lines(normal_1, normal_2)
    f1, f2, r = _dot(active, normal_1), _dot(active, normal_2), _dot(normal_1, normal_2)
    with np.errstate(invalid="ignore", divide="ignore"):
        n1, n2 = _both_planes(f1, f2, r)
    along = _dot(active, line)
    mode = np.full(np.shape(n1), SlidingMode.LIFTED, dtype=np.int8)
    mode[(n2 < 0.0) & (f1 < 0.0)] = SlidingMode.PLANE_1
    mode[(n1 < 0.0) & (f2 < 0.0)] = SlidingMode.PLANE_2
    both = (n1 >= 0.0) & (n2 >= 0.0)
    mode[both & (along >= 0.0)] = SlidingMode.BOTH
    mode[both & (along < 0.0)] = SlidingMode.BOTH_UP
    return _Statics(mode, f1, f2, r, along, n1, n2, line)


def _passive_parts(
    held: NDArray, n1_vec: NDArray, n2_vec: NDArray, force: NDArray, st: _Statics, driving: NDArray
) -> tuple[NDArray, NDArray, NDArray]:
    """The passive resultant P's normal forces on planes 1 and 2 in each mode and its component along
    the sliding direction, P.s: P.l sign(F.l) on both planes, (P.F - (P.n_i)(F.n_i)) / D on plane i."""
    p1, p2 = _dot(held, n1_vec), _dot(held, n2_vec)
    with np.errstate(invalid="ignore", divide="ignore"):
        q1, q2 = _both_planes(p1, p2, st.cosine)
        both = st.mode >= SlidingMode.BOTH
        on_1, on_2 = st.mode == SlidingMode.PLANE_1, st.mode == SlidingMode.PLANE_2
        extra_1 = np.where(both, q1, np.where(on_1, -p1, 0.0))
        extra_2 = np.where(both, q2, np.where(on_2, -p2, 0.0))
        across = _dot(held, force)
        single = np.where(on_1, across - p1 * st.force_1, across - p2 * st.force_2) / driving
        along = np.where(both, _dot(held, st.line) * np.sign(st.along), np.where(on_1 | on_2, single, 0.0))
    return extra_1, extra_2, np.nan_to_num(along)


def wedge_factor_of_safety(
    normal_1: ArrayLike,
    normal_2: ArrayLike,
    area_1: ArrayLike,
    area_2: ArrayLike,
    active: ArrayLike,
    strength_1: PlaneStrength,
    strength_2: PlaneStrength,
    passive: ArrayLike = 0.0,
) -> WedgeSolution:
    """The wedge's mode, normal forces and FS (module docstring) for planes of unit normals into the
    wedge `normal_1`, `normal_2` (..., 3), contact areas A1, A2 [m^2], the active resultant (..., 3)
    [N] (`active_resultant`), each plane's strength and the passive resultant (..., 3) [N]."""
    n1_vec, n2_vec = np.asarray(normal_1, dtype=float), np.asarray(normal_2, dtype=float)
    force = np.asarray(active, dtype=float)
    shape = np.broadcast_shapes(force.shape, n1_vec.shape, n2_vec.shape)
    force, n1_vec, n2_vec = (spread(v, shape) for v in (force, n1_vec, n2_vec))
    st = _statics(force, n1_vec, n2_vec)
    both = st.mode >= SlidingMode.BOTH
    on_1, on_2 = st.mode == SlidingMode.PLANE_1, st.mode == SlidingMode.PLANE_2
    square = _dot(force, force)
    driving = np.where(
        both,
        np.abs(st.along),
        np.sqrt(np.maximum(square - np.where(on_1, st.force_1, st.force_2) ** 2, 0.0)) * (on_1 | on_2),
    )
    normal_on_1 = np.where(both, st.normal_1, np.where(on_1, -st.force_1, 0.0))
    normal_on_2 = np.where(both, st.normal_2, np.where(on_2, -st.force_2, 0.0))
    moving = (
        (on_1 | on_2)[..., None] * force
        - np.where(on_1, st.force_1, 0.0)[..., None] * n1_vec
        - np.where(on_2, st.force_2, 0.0)[..., None] * n2_vec
        + np.where(both, st.along, 0.0)[..., None] * st.line
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        direction = moving / driving[..., None]
    held = np.asarray(passive, dtype=float)
    against = 0.0
    if np.any(held):
        held = spread(held, shape)
        extra_1, extra_2, with_sliding = _passive_parts(held, n1_vec, n2_vec, force, st, driving)
        normal_on_1, normal_on_2, against = normal_on_1 + extra_1, normal_on_2 + extra_2, -with_sliding
    area_1, area_2 = np.asarray(area_1, dtype=float), np.asarray(area_2, dtype=float)
    resisting_1 = strength_1.shear_force(np.maximum(normal_on_1, 0.0), area_1)
    resisting_2 = strength_2.shear_force(np.maximum(normal_on_2, 0.0), area_2)
    resisting = np.where(both | on_1, resisting_1, 0.0) + np.where(both | on_2, resisting_2, 0.0) + against
    with np.errstate(invalid="ignore", divide="ignore"):
        fs = np.where(driving > 0.0, resisting / np.where(driving > 0.0, driving, 1.0), np.inf)
    fs = np.where(st.mode == SlidingMode.LIFTED, 0.0, fs)
    fs = np.where(np.isnan(st.line[..., 0]), np.nan, fs)
    samples = fs.shape
    return WedgeSolution(
        np.array(spread(st.mode, samples)),
        np.array(spread(normal_on_1, samples)),
        np.array(spread(normal_on_2, samples)),
        np.array(spread(driving, samples)),
        np.array(spread(resisting, samples)),
        np.array(spread(direction, (*samples, 3))),
        fs,
    )
