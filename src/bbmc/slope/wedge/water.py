"""The water models of a wedge: the water's normal forces U1, U2 on joint planes 1 and 2 and V on the
tension crack [N], each acting along its plane's normal into the wedge.

* `Dry`: no water.
* `HoekBrayWater(filled)`: Hoek & Bray's water. Without a tension crack (Hoek & Bray 1981, ch. 8, the
  short solution; Wyllie & Mah 2004, section 7.2): the slope face and the upper surface drain, the
  pressure is zero along them and peaks at gamma_w H / 2 midway along the line of intersection (H the
  wedge's total height), falling linearly to the edges, so its mean on each plane is gamma_w H / 6:
      U_i = gamma_w H A_i / 6                                   (`loads.hoek_bray_water`)
  With a tension crack, the comprehensive solution (Hoek & Bray 1981, appendix 2; Wyllie & Mah 2004,
  appendix III; Swedge's theory manual, "water pressure" with a tension crack): the crack is full of
  water, the pressure peaks at the crack's lowest vertex R (its foot on the line of intersection) at
  gamma_w h_5, h_5 the vertical depth of R below the upper surface, and is zero on the free faces; the
  mean pressure on planes 1, 2 and the crack is taken as a third of the peak:
      u = gamma_w h_5 / 3,   U_1 = u A_1,   U_2 = u A_2,   V = u A_5
  (A_5 the crack's area within the wedge). `filled` (0 to 1, default 1) scales the head of either form
  (u -> filled u): a fissure system filled to that fraction of Hoek & Bray's head. This is bbmc's reading
  of "percent filled"; Swedge's "% filled fissures" instead places a water table between the toe and
  the wedge's top, which this model does not draw.
* `PlanePressures(plane_1, plane_2, crack)`: a given mean pressure per plane [Pa]:
  U_1 = p_1 A_1, U_2 = p_2 A_2, V = p_5 A_5 (Swedge's "custom pressure" as a mean per plane).

Sources: the no-crack form is the short solution's (checked against the issue's 1.2180). The crack form
is Swedge's "Filled Fissures" with a tension crack (Rocscience Swedge help, "Joint Water Pressure",
eqn. 2, citing Hoek & Bray 1981): u1 = u2 = u5 = gamma_w h_w / 3, h_w "the depth of the bottom vertex of
the tension crack below the upper ground surface"; it agrees with the comprehensive solution's
assumption (Hoek & Bray 1981, appendix 2; Wyllie & Mah 2004, appendix III). Those printed appendices
were not in the searchable corpus; the check against the comprehensive solution is the vector
solution's own (tests/test_wedge_mechanics.py).

SI: pressures Pa, forces N, lengths m, unit weights N/m^3; every value broadcasts over samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.wedge.loads import hoek_bray_water
from bbmc.slope.wedge.vectors import dot

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Dry:
    """No water on the wedge."""


@dataclass(frozen=True)
class HoekBrayWater:
    """Hoek & Bray's water (module docstring): without a crack gamma_w H / 6 on each plane, with one the
    comprehensive solution's gamma_w h_5 / 3 on planes 1, 2 and the crack; `filled` [1] scales the head."""

    filled: ArrayLike = 1.0


@dataclass(frozen=True)
class PlanePressures:
    """A given mean water pressure [Pa] on plane 1, plane 2 and the tension crack."""

    plane_1: ArrayLike
    plane_2: ArrayLike
    crack: ArrayLike = 0.0


WaterModel = Dry | HoekBrayWater | PlanePressures
DRY = Dry()


def crack_foot_depth(geometry) -> Array:
    """h_5 [m]: the vertical depth of the crack's foot R below the upper surface (which passes through
    the crest point C1): (u . C1 - u . R) / u_z, u the upper surface's upward unit pole."""
    upper = geometry.normal_upper
    return (dot(upper, geometry.crest_1) - dot(upper, geometry.crack_foot)) / upper[..., 2]


def _fraction(filled: ArrayLike) -> Array:
    fraction = np.asarray(filled, dtype=float)
    if np.any(~((fraction >= 0.0) & (fraction <= 1.0))):
        raise ValueError("filled: the water's filled fraction must be 0 to 1")
    return fraction


def water_forces(
    model: WaterModel, geometry, water_unit_weight: ArrayLike
) -> tuple[Array | float, Array | float, Array | float]:
    """U_1, U_2 and V [N] of `model` (module docstring) on wedges of `geometry` (a
    `geometry.WedgeGeometry`, or `essentials.WedgeEssentials` for the models that need no crack), with
    gamma_w [N/m^3]. ValueError names the key of a filled fraction outside 0 to 1, of an unknown model,
    and of a model that needs the crack's geometry where none was given."""
    has_crack = getattr(geometry, "has_crack", False)
    if isinstance(model, Dry):
        return 0.0, 0.0, 0.0
    if isinstance(model, HoekBrayWater):
        fraction = _fraction(model.filled)
        if not has_crack:
            u_1, u_2 = hoek_bray_water(geometry.height_h, geometry.area_1, geometry.area_2, water_unit_weight)
            return fraction * u_1, fraction * u_2, 0.0
        mean = fraction * np.asarray(water_unit_weight, dtype=float) * crack_foot_depth(geometry) / 3.0
        return mean * geometry.area_1, mean * geometry.area_2, mean * geometry.area_crack
    if isinstance(model, PlanePressures):
        crack = np.asarray(model.crack, dtype=float)
        if np.any(crack != 0.0) and not has_crack:
            raise ValueError("water.crack: a pressure on the tension crack needs a crack")
        on_crack = crack * geometry.area_crack if has_crack else 0.0
        return (
            np.asarray(model.plane_1, dtype=float) * geometry.area_1,
            np.asarray(model.plane_2, dtype=float) * geometry.area_2,
            on_crack,
        )
    raise ValueError(
        f"water: unknown water model {type(model).__name__}; use Dry, HoekBrayWater or PlanePressures"
    )
