"""A wedge from its inputs to its FS: geometry, loads, sliding mode and factor of safety in one call,
vectorised over batches of wedges (every input broadcasts with the others).

    geometry  `geometry.wedge_geometries` (full: vertices, areas, traces, angles, a tension crack), or
              with `essentials_only=True` and no crack, `essentials.wedge_essentials` (only what the
              mechanics needs, one compiled pass, equal to the full path to rounding)
    weight    W = gamma V                                    [N]
    water     U_1, U_2 on planes 1 and 2, V on the crack     (`water`: Dry, HoekBrayWater, PlanePressures)
    seismic   k W along the line of intersection (down it), horizontal along its trend, or a given
              unit vector (Hoek & Bray 1981, ch. 8; `loads.seismic_force`)
    forces    other active forces (external loads, active support) summed, (..., 3) [N]; `passive`
              the passive resultant (untensioned support), (..., 3) [N] (`mechanics` docstring)
    F         W (0, 0, -1) + U_1 n_1 + U_2 n_2 + V n_5 + seismic + forces   (`mechanics.active_resultant`)
    FS, mode  `mechanics.wedge_factor_of_safety`

Wedges that cannot form carry their `WedgeReason` and NaN loads, mode LIFTED and FS NaN, never a number.
SI: N, m, Pa, N/m^3, rad.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.wedge.essentials import WedgeEssentials, wedge_essentials
from bbmc.slope.wedge.geometry import TensionCrack, WedgeGeometry, wedge_geometries
from bbmc.slope.wedge.loads import WATER_UNIT_WEIGHT, horizontal_along, seismic_force
from bbmc.slope.wedge.mechanics import PlaneStrength, WedgeSolution, active_resultant, wedge_factor_of_safety
from bbmc.slope.wedge.vectors import spread
from bbmc.slope.wedge.water import DRY, WaterModel, water_forces

Array = NDArray[np.float64]


@dataclass(frozen=True)
class WedgeOrientations:
    """Dips and dip directions [rad] of joint planes 1 and 2, the slope face and the upper surface."""

    dip_1: ArrayLike
    dip_direction_1: ArrayLike
    dip_2: ArrayLike
    dip_direction_2: ArrayLike
    face_dip: ArrayLike
    face_dip_direction: ArrayLike
    upper_dip: ArrayLike
    upper_dip_direction: ArrayLike

    def angles(self) -> tuple[ArrayLike, ...]:
        """The eight angles in the order `wedge_geometries` takes them."""
        return (
            self.dip_1,
            self.dip_direction_1,
            self.dip_2,
            self.dip_direction_2,
            self.face_dip,
            self.face_dip_direction,
            self.upper_dip,
            self.upper_dip_direction,
        )


@dataclass(frozen=True)
class Seismic:
    """A pseudo-static seismic force k W: `coefficient` k [1] and its direction, "line" (down the line of
    intersection), "horizontal" (horizontal along the line's trend, out of the slope) or a unit vector
    (..., 3)."""

    coefficient: ArrayLike
    direction: Literal["line", "horizontal"] | ArrayLike = "line"


@dataclass(frozen=True)
class WedgeLoads:
    """The loads on wedges: the weight W [N], the water's normal forces U_1, U_2, V [N] (on planes 1, 2
    and the crack), the seismic force (..., 3) [N], the other active forces (..., 3) [N], the active
    resultant F (..., 3) [N] and the passive resultant (..., 3) [N]."""

    weight: Array
    water_1: Array
    water_2: Array
    water_crack: Array
    seismic: Array
    forces: Array
    active: Array
    passive: Array


@dataclass(frozen=True)
class WedgeAnalysis:
    """A wedge analysis: its geometry (full, or the essentials), loads and limit equilibrium."""

    geometry: WedgeGeometry | WedgeEssentials
    loads: WedgeLoads
    solution: WedgeSolution

    @property
    def factor_of_safety(self) -> Array:
        """FS per wedge (NaN where the wedge does not form)."""
        return self.solution.factor_of_safety


def _seismic_direction(seismic: Seismic, line: Array) -> Array:
    if isinstance(seismic.direction, str):
        if seismic.direction == "line":
            return line
        if seismic.direction == "horizontal":
            return horizontal_along(line)
        raise ValueError(f"seismic.direction: {seismic.direction!r} is not 'line', 'horizontal' or a vector")
    return np.asarray(seismic.direction, dtype=float)


def wedge_loads(
    geometry: WedgeGeometry | WedgeEssentials,
    unit_weight: ArrayLike,
    water: WaterModel = DRY,
    water_unit_weight: ArrayLike = WATER_UNIT_WEIGHT,
    seismic: Seismic | None = None,
    forces: ArrayLike = 0.0,
    passive: ArrayLike = 0.0,
) -> WedgeLoads:
    """The loads on wedges of `geometry` (module docstring): rock unit weight gamma [N/m^3], a water
    model with gamma_w [N/m^3], an optional seismic force, other active `forces` and the `passive`
    resultant (..., 3) [N]."""
    weight = np.asarray(unit_weight, dtype=float) * geometry.volume
    water_1, water_2, water_crack = water_forces(water, geometry, water_unit_weight)
    shape = np.broadcast_shapes(*(np.shape(v) for v in (weight, water_1, water_2, water_crack)))
    weight = spread(weight, shape)
    zero = np.zeros((*shape, 3))
    shaking = (
        zero
        if seismic is None
        else seismic_force(weight, seismic.coefficient, _seismic_direction(seismic, geometry.line))
    )
    other = zero + np.asarray(forces, dtype=float)
    crack_push = 0.0
    if np.any(water_crack):
        crack_push = np.asarray(water_crack)[..., None] * geometry.normal_crack
    active = active_resultant(
        weight, geometry.normal_1, geometry.normal_2, water_1, water_2, shaking + other + crack_push
    )
    return WedgeLoads(
        weight=weight,
        water_1=spread(water_1, shape) + 0.0,
        water_2=spread(water_2, shape) + 0.0,
        water_crack=spread(water_crack, shape) + 0.0,
        seismic=shaking,
        forces=other,
        active=active,
        passive=zero + np.asarray(passive, dtype=float),
    )


def analyse_wedges(
    orientations: WedgeOrientations,
    strength_1: PlaneStrength,
    strength_2: PlaneStrength,
    *,
    unit_weight: ArrayLike,
    height_h1: ArrayLike | None = None,
    height_h: ArrayLike | None = None,
    crack: TensionCrack | None = None,
    overhanging_face: ArrayLike = False,
    water: WaterModel = DRY,
    water_unit_weight: ArrayLike = WATER_UNIT_WEIGHT,
    seismic: Seismic | None = None,
    forces: ArrayLike = 0.0,
    passive: ArrayLike = 0.0,
    essentials_only: bool = False,
) -> WedgeAnalysis:
    """Geometry, loads, mode and FS of wedges (module docstring). `orientations` and the heights, crack
    and face key as `geometry.wedge_geometries`; each plane's strength (e.g. `mechanics.MohrCoulomb`);
    rock unit weight gamma [N/m^3]; the loads as `wedge_loads`. `essentials_only=True` (no crack) takes
    the fast path of the geometry: the result's geometry then holds only the mechanics' fields."""
    heights = {"height_h1": height_h1, "height_h": height_h, "overhanging_face": overhanging_face}
    if essentials_only and crack is not None:
        raise ValueError("essentials_only: the fast path has no tension crack; use the full geometry")
    if essentials_only:
        geometry = wedge_essentials(*orientations.angles(), **heights)
    else:
        geometry = wedge_geometries(*orientations.angles(), crack=crack, **heights)
    loads = wedge_loads(geometry, unit_weight, water, water_unit_weight, seismic, forces, passive)
    return solved(geometry, loads, strength_1, strength_2)


def solved(
    geometry: WedgeGeometry | WedgeEssentials,
    loads: WedgeLoads,
    strength_1: PlaneStrength,
    strength_2: PlaneStrength,
) -> WedgeAnalysis:
    """The limit equilibrium (`mechanics.wedge_factor_of_safety`) of wedges of `geometry` under `loads`,
    with the planes' strengths."""
    solution = wedge_factor_of_safety(
        geometry.normal_1,
        geometry.normal_2,
        geometry.area_1,
        geometry.area_2,
        loads.active,
        strength_1,
        strength_2,
        loads.passive,
    )
    return WedgeAnalysis(geometry, loads, solution)
