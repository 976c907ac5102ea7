"""Forces on a wedge other than the joints' reactions, as vectors for `mechanics.active_resultant`: the
water on the joint planes, a pseudo-static seismic force, and a force of given trend, plunge and
magnitude (an external load, a bolt or an anchor).

* Water without a tension crack (Hoek & Bray 1981, ch. 8, "the influence of water pressure" and the
  short solution; Wyllie & Mah 2004, section 7.2 and appendix III): the wedge's free faces (the slope
  face and the upper surface) drain, so the pressure is zero along them, and it peaks at gamma_w H / 2
  midway along the line of intersection, H the wedge's total height (toe to the top of the line of
  intersection). The pressure falls linearly to the edges, so over each plane (a triangle whose apex
  carries the peak) its mean is a third of the peak, gamma_w H / 6, and the normal force on plane i is
      U_i = gamma_w H A_i / 6   [N],
  acting along the plane's normal into the wedge (the `water_1`, `water_2` of `active_resultant`).
* Pseudo-static seismic force (Hoek & Bray 1981, ch. 8; Swedge's "Seismic Force"): k W along a unit
  direction: the line of intersection (down it), the horizontal along its trend, or a given one.
* A force of magnitude T [N] along the line of trend t and plunge p (downward positive):
  T (cos p sin t, cos p cos t, -sin p). A bolt (`support.Bolt`) is given by the trend and plunge of
  its hole, drilled from the face into the rock: it pulls the wedge along that direction, towards its
  anchor.

SI: forces N, lengths m, unit weights N/m^3, angles rad; arrays broadcast over samples.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.geometry.orientation import line_vectors

WATER_UNIT_WEIGHT = 9810.0  # N/m^3


def hoek_bray_water(
    total_height: ArrayLike,
    area_1: ArrayLike,
    area_2: ArrayLike,
    water_unit_weight: ArrayLike = WATER_UNIT_WEIGHT,
) -> tuple[NDArray, NDArray]:
    """U_i = gamma_w H A_i / 6 [N] on planes 1 and 2 of a wedge without a tension crack (Hoek & Bray
    1981, ch. 8): zero pressure on the free faces, peak gamma_w H / 2 midway along the line of
    intersection. H the wedge's total height [m], A_i [m^2], gamma_w [N/m^3]."""
    mean_pressure = np.asarray(water_unit_weight, dtype=float) * np.asarray(total_height, dtype=float) / 6.0
    return mean_pressure * np.asarray(area_1, dtype=float), mean_pressure * np.asarray(area_2, dtype=float)


def horizontal_along(line: ArrayLike) -> NDArray:
    """The horizontal unit vector (..., 3) along the trend of `line` (..., 3) (not vertical)."""
    line = np.asarray(line, dtype=float)
    flat = line * np.array([1.0, 1.0, 0.0])
    return flat / np.linalg.norm(flat, axis=-1, keepdims=True)


def seismic_force(weight: ArrayLike, coefficient: ArrayLike, direction: ArrayLike) -> NDArray:
    """k W d (..., 3) [N]: the pseudo-static force on a wedge of weight W [N], coefficient k [1], along
    the unit vector `direction` (..., 3)."""
    scale = np.asarray(weight, dtype=float) * np.asarray(coefficient, dtype=float)
    return scale[..., None] * np.asarray(direction, dtype=float)


def force_vector(magnitude: ArrayLike, trend: ArrayLike, plunge: ArrayLike) -> NDArray:
    """T (cos p sin t, cos p cos t, -sin p) (..., 3) [N]: a force of magnitude T [N] along the line of
    trend t and plunge p [rad] (downward positive; a negative plunge points up)."""
    return np.asarray(magnitude, dtype=float)[..., None] * line_vectors(trend, plunge)
