"""One wedge case from its inputs in SI: the slope (face, upper surface, height, crack), the loads and the
support held in a `WedgeSetting`, and two joint planes; geometry first (whether the wedge forms, the
length a Barton-Bandis plane is scaled to, the face traces shotcrete shears through), then on that one
geometry the loads (`analysis.wedge_loads`) and the limit equilibrium (`analysis.solved`),
the steps of `analysis.analyse_wedges`. And what drives a wedge: the driving force split by load.

    driving force   D = F . s,  F = W + U + E + A   (s the sliding direction, `mechanics`)
    its parts       -W s_z (weight), U . s (water on planes 1, 2 and the crack), E . s (seismic),
                    A . s (external forces and active support)

SI: N, m, Pa, N/m^3, rad.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from bbmc.slope.wedge.analysis import Seismic, WedgeAnalysis, solved, wedge_loads
from bbmc.slope.wedge.geometry import TensionCrack, WedgeGeometry, wedge_geometries
from bbmc.slope.wedge.loads import WATER_UNIT_WEIGHT
from bbmc.slope.wedge.mechanics import PlaneStrength
from bbmc.slope.wedge.size_limits import SizeLimits
from bbmc.slope.wedge.support import shotcrete_force
from bbmc.slope.wedge.water import DRY, WaterModel

LOADS = ("weight", "water", "seismic", "forces")


@dataclass(frozen=True)
class Plane:
    """A joint plane: dip and dip direction [rad] and its strength, given the wedge's line of
    intersection's length [m] (a Barton-Bandis plane may be scaled to it); optionally the largest trace
    length and persistence [m] the joint has (Swedge's Scale Wedge, `size_limits`)."""

    dip: float
    dip_direction: float
    strength: Callable[[float], PlaneStrength]
    trace_length: float | None = None
    persistence: float | None = None


@dataclass(frozen=True)
class WedgeSetting:
    """Everything of a wedge case but its two planes: the face and the upper surface (dip, dip direction
    [rad]), exactly one height [m], a crack, rock gamma [N/m^3], water with gamma_w [N/m^3], seismic,
    the external forces and active support summed (3,) [N], passive support (3,) [N], shotcrete
    (thickness [m], shear strength [Pa]) or None, and the optional size limits: bench width, slope
    length [m] and the largest volume [m^3] (`size_limits`; the planes carry their own)."""

    face: tuple[float, float]
    upper: tuple[float, float]
    unit_weight: float
    height_h1: float | None = None
    height_h: float | None = None
    overhanging_face: bool = False
    crack: TensionCrack | None = None
    water: WaterModel = DRY
    water_unit_weight: float = WATER_UNIT_WEIGHT
    seismic: Seismic | None = None
    forces: NDArray = field(default_factory=lambda: np.zeros(3))
    passive: NDArray = field(default_factory=lambda: np.zeros(3))
    shotcrete: tuple[float, float] | None = None
    bench_width: float | None = None
    slope_length: float | None = None
    max_volume: float | None = None


@dataclass(frozen=True)
class WedgeCase:
    """A case's geometry and, where the wedge forms, its analysis and the planes' strengths (None where
    it does not)."""

    geometry: WedgeGeometry
    analysis: WedgeAnalysis | None
    strengths: tuple[PlaneStrength, PlaneStrength] | None = None

    @property
    def reason(self) -> str:
        """Why the wedge does not form, or 'the wedge forms'."""
        return str(self.geometry.reason_texts())


def size_limits(setting: WedgeSetting, plane_1: Plane, plane_2: Plane) -> SizeLimits:
    """The limits on the size of the wedge of `plane_1` and `plane_2` in `setting`."""
    return SizeLimits(
        bench_width=setting.bench_width,
        slope_length=setting.slope_length,
        trace_length_plane_1=plane_1.trace_length,
        trace_length_plane_2=plane_2.trace_length,
        persistence_plane_1=plane_1.persistence,
        persistence_plane_2=plane_2.persistence,
        volume=setting.max_volume,
    )


def wedge_geometry_of(setting: WedgeSetting, plane_1: Plane, plane_2: Plane) -> WedgeGeometry:
    """The wedge's full geometry, scaled down to its size limits where they are given (NaN with its
    reason where it does not form: the arithmetic on the way to those NaN, e.g. an infinite scale
    times 0 for a line parallel to the upper surface, is not warned about)."""
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return wedge_geometries(
            plane_1.dip,
            plane_1.dip_direction,
            plane_2.dip,
            plane_2.dip_direction,
            *setting.face,
            *setting.upper,
            height_h1=setting.height_h1,
            height_h=setting.height_h,
            overhanging_face=setting.overhanging_face,
            crack=setting.crack,
            limits=size_limits(setting, plane_1, plane_2),
        )


def analyse_case(setting: WedgeSetting, plane_1: Plane, plane_2: Plane) -> WedgeCase:
    """The wedge of two planes in `setting`: geometry, and where it forms, loads, mode and FS."""
    geometry = wedge_geometry_of(setting, plane_1, plane_2)
    if not bool(geometry.formed):
        return WedgeCase(geometry, None)
    length = float(geometry.intersection_length)
    passive = setting.passive
    if setting.shotcrete is not None:
        traces = geometry.trace_face_1 + geometry.trace_face_2
        passive = passive + shotcrete_force(*setting.shotcrete, traces, geometry.normal_face)
    strengths = (plane_1.strength(length), plane_2.strength(length))
    loads = wedge_loads(
        geometry,
        setting.unit_weight,
        setting.water,
        setting.water_unit_weight,
        setting.seismic,
        setting.forces,
        passive,
    )
    analysis = solved(geometry, loads, *strengths)
    return WedgeCase(geometry, analysis, strengths)


def driving_parts(analysis: WedgeAnalysis) -> dict[str, float]:
    """The driving force's parts [N] along the sliding direction s, by load (module docstring); NaN
    where contact is lost on both planes (no sliding direction). They sum to D."""
    g, loads = analysis.geometry, analysis.loads
    s = analysis.solution.sliding_direction
    water = loads.water_1[..., None] * g.normal_1 + loads.water_2[..., None] * g.normal_2
    if g.has_crack:
        water = water + loads.water_crack[..., None] * g.normal_crack
    vectors = {
        "weight": loads.weight[..., None] * np.array([0.0, 0.0, -1.0]),
        "water": water,
        "seismic": loads.seismic,
        "forces": loads.forces,
    }
    return {name: float(np.sum(vector * s)) for name, vector in vectors.items()}


def driven_by(parts: dict[str, float]) -> str:
    """The loads that drive the wedge down its sliding direction (positive parts), largest first, as
    'weight 71 %, water 29 %'; 'nothing' where none does."""
    pushing = {name: value for name, value in parts.items() if value > 0.0}
    total = sum(pushing.values())
    if not total:
        return "nothing"
    order = sorted(pushing, key=pushing.get, reverse=True)
    return ", ".join(f"{name} {100.0 * pushing[name] / total:.0f} %" for name in order)
