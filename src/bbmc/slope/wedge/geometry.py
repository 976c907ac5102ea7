"""The geometry of a rock wedge: two joint planes, the slope face and the upper slope surface, computed
for one wedge or for arrays of wedges at once (numpy broadcasting over every input).

Axes x east, y north, z up; the wedge's toe O, where planes 1 and 2 meet the face, is the origin.
Angles in radians, lengths in metres (any one length unit works: outputs scale with the height).

The four planes and their vertices (Hoek & Bray, Rock Slope Engineering, 3rd ed. 1981, ch. 8;
Wyllie & Mah 2004, ch. 7 and Appendix III; Swedge's "Overview of Swedge input"):

* planes 1 and 2 (dip, dip direction, upward poles n1, n2) pass through O; the face (outward normal
  f: its upward pole, or for an overhanging face, by the explicit key `overhanging_face`, the pole
  of the face's plane turned to point down and out) passes through O; the upper surface (upward pole
  u) is the plane u . x = d, d > 0 set by the height;
* C1 = plane 1 ∩ face ∩ upper surface and C2 = plane 2 ∩ face ∩ upper surface are the crest points;
  T = plane 1 ∩ plane 2 ∩ upper surface is the top of the line of intersection. A point on planes p
  and q (through O) and on the upper surface is x = d (n_p x n_q) / (u . (n_p x n_q)).
* The wedge is the tetrahedron O C1 C2 T: the one bounded cell of the four planes. It lies in the
  rock, so forms, exactly when T lies behind the face (f . T < 0) and O below the upper surface.

Heights (two distinct keys, exactly one given):

* H1 (`height_h1`) — Swedge's "slope height referred to plane 1" and Hoek & Bray's H1: the vertical
  height above the toe O of C1, the point where plane 1's trace on the face meets the upper surface
  (the crest). The crest is horizontal only where the face and the upper surface share their dip
  direction, so in general C2 stands at another height than C1.
* H (`height_h`) — the wedge's total height: the vertical height above O of T, the top of the line
  of intersection (Hoek & Bray's H of the short solution and of its water model).

A tension crack (optional, `TensionCrack`): a plane of any dip and dip direction through the point of
the trace of plane 1 on the upper surface at the distance L from the crest point C1 (Swedge's and Hoek
& Bray's L, "measured along the trace of plane 1"). It must cut off the top T alone: O, C1 and C2 on
one side, T on the other, so that it crosses the line of intersection at R (the crack's foot), the
trace of plane 2 on the upper surface at Q and that of plane 1 at P. The wedge is then O C1 C2 P Q R,
the tetrahedron less T P Q R.

Size limits (optional, `SizeLimits`, module `size_limits`): Swedge's bench width, slope length and
Scale Wedge (each plane's trace length and persistence, the volume) scale the tetrahedron about O by
the factor s <= 1 that brings it within every limit: the height asked for times s (`size_scale`,
`size_limited_by` the limit that governs). Not with a tension crack (its distance L does not scale).

A wedge that cannot form is never a number: its fields are NaN and `reason` holds a `WedgeReason`
(for one wedge, `wedge_geometry` raises `WedgeNotFormedError` with the reason's text).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from enum import IntEnum

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.geometry.orientation import downward, pole_components, trend_and_plunge
from bbmc.slope.wedge.short_solution import ShortSolutionAngles, short_solution_angles
from bbmc.slope.wedge.size_limits import LIMIT_NAMES, SizeLimit, SizeLimits, size_scale
from bbmc.slope.wedge.vectors import (
    cross,
    dot,
    norm,
    spread,
    stacked,
    tetrahedron_volume,
    triangle_area,
    unit,
)

Array = NDArray[np.float64]
TOLERANCE = 1e-9  # sines and cosines of unit vectors closer to 0 than this count as 0 (parallel lines)


class WedgeReason(IntEnum):
    """Why a wedge forms or does not (0: it forms)."""

    FORMED = 0
    SLOPE_NOT_CONVEX = 1
    PARALLEL_PLANES = 2
    TRACE_MISSES_CREST = 3
    NOT_DAYLIGHTING = 4
    NOT_OUTCROPPING = 5
    HEIGHT_BELOW_TOE = 6
    CRACK_OUTSIDE = 7


REASON_TEXT = {
    WedgeReason.FORMED: "the wedge forms",
    WedgeReason.SLOPE_NOT_CONVEX: "the face is not steeper than the upper surface "
    "(the crest is not above the toe)",
    WedgeReason.PARALLEL_PLANES: "planes 1 and 2 are parallel: they have no line of intersection",
    WedgeReason.TRACE_MISSES_CREST: "a plane's trace on the face never meets the crest "
    "(the plane is parallel to the face, or strikes parallel to the crest)",
    WedgeReason.NOT_DAYLIGHTING: "the line of intersection does not daylight in the face "
    "(it plunges into the slope or more steeply than the face)",
    WedgeReason.NOT_OUTCROPPING: "the line of intersection does not outcrop in the upper surface "
    "(it plunges less steeply than the upper surface)",
    WedgeReason.HEIGHT_BELOW_TOE: "the point the height refers to is not above the toe",
    WedgeReason.CRACK_OUTSIDE: "the tension crack does not cut off the top of the wedge alone "
    "(it misses the wedge or cuts its face on the slope)",
}
_REASON_TEXTS = np.array([REASON_TEXT[r] for r in WedgeReason])
_VECTORS = {
    "crest_1",
    "crest_2",
    "top",
    "crack_1",
    "crack_2",
    "crack_foot",
    "line",
    "line_out",
    "centroid",
} | {
    "normal_1",
    "normal_2",
    "normal_face",
    "normal_upper",
    "normal_crack",
}


class WedgeNotFormedError(ValueError):
    """The wedge cannot form; `reason` says why."""

    def __init__(self, reason: WedgeReason) -> None:
        self.reason = WedgeReason(reason)
        super().__init__(f"no wedge: {REASON_TEXT[self.reason]}")


@dataclass(frozen=True)
class TensionCrack:
    """A tension crack: its dip and dip direction [rad] and its distance L [m] from the crest point C1
    along plane 1's trace on the upper surface (each a scalar or an array broadcast with the wedge)."""

    dip: ArrayLike
    dip_direction: ArrayLike
    distance: ArrayLike


@dataclass(frozen=True)
class WedgeGeometry:
    """Wedges' geometry, every field of the batch's shape (...) or (..., 3) for points and vectors.

    Points [m], toe O at the origin: `crest_1` C1, `crest_2` C2, `top` T; with a crack `crack_1` P (on
    plane 1), `crack_2` Q (on plane 2), `crack_foot` R (on the line of intersection), else NaN.
    Line of intersection: `line` its downward unit vector (bbmc's line convention), `trend` and
    `plunge` [rad]; `line_out` the unit vector along it from T towards the toe (out of the slope) and
    `plunge_out` its plunge (= `plunge` unless the line rises towards the face, then < 0).
    Normals (unit): `normal_1`, `normal_2`, `normal_crack` point into the wedge (the sense of the push
    of the rock or water behind each plane on the wedge); `normal_face`, `normal_upper` point out of
    the rock. Areas [m^2] of the wedge's faces on each plane; `volume` [m^3]; `centroid` [m].
    Trace lengths [m]: `trace_face_1` O C1, `trace_face_2` O C2, `trace_upper_1` C1 T (C1 P with a
    crack), `trace_upper_2` C2 T (C2 Q), `crest_length` C1 C2, `intersection_length` O T (O R).
    Heights [m]: `height_h1` = C1_z and `height_h` = T_z (of the whole tetrahedron, crack or not), of
    the wedge as built: the height asked for times `size_scale`, the factor the size limits set (1
    without them), `size_limited_by` the `SizeLimit` that governs (HEIGHT where none scales it down).
    `short_solution`: Hoek & Bray's angles and factors of the tetrahedron (no crack).
    """

    crest_1: Array
    crest_2: Array
    top: Array
    crack_1: Array
    crack_2: Array
    crack_foot: Array
    line: Array
    trend: Array
    plunge: Array
    line_out: Array
    plunge_out: Array
    normal_1: Array
    normal_2: Array
    normal_face: Array
    normal_upper: Array
    normal_crack: Array
    area_1: Array
    area_2: Array
    area_face: Array
    area_upper: Array
    area_crack: Array
    volume: Array
    centroid: Array
    trace_face_1: Array
    trace_face_2: Array
    trace_upper_1: Array
    trace_upper_2: Array
    crest_length: Array
    intersection_length: Array
    height_h1: Array
    height_h: Array
    size_scale: Array
    short_solution: ShortSolutionAngles
    reason: NDArray[np.int8]
    size_limited_by: NDArray[np.int8]
    has_crack: bool

    @property
    def formed(self) -> NDArray[np.bool_]:
        """True where the wedge forms."""
        return self.reason == WedgeReason.FORMED

    @property
    def toe(self) -> Array:
        """The toe O, the origin (..., 3)."""
        return np.zeros_like(self.crest_1)

    @property
    def vertices(self) -> Array:
        """The vertices (..., n, 3): O C1 C2 T, or O C1 C2 P Q R with a crack."""
        rest = (self.crack_1, self.crack_2, self.crack_foot) if self.has_crack else (self.top,)
        return np.stack((self.toe, self.crest_1, self.crest_2, *rest), axis=-2)

    def reason_texts(self) -> NDArray[np.str_]:
        """The reason of each wedge in words, of the batch's shape."""
        return _REASON_TEXTS[self.reason]

    def size_limit_names(self) -> NDArray[np.str_]:
        """What sets each wedge's size ('height', 'bench_width', ...), of the batch's shape."""
        return LIMIT_NAMES[self.size_limited_by]


def _refuse(bad: NDArray[np.bool_], key: str, what: str) -> None:
    if bad.any():
        raise ValueError(f"{key}: {what}")


def _plane_inputs(
    dips: dict[str, ArrayLike], directions: tuple[ArrayLike, ...], overhanging_face: ArrayLike
) -> tuple[Array, Array, Array, Array]:
    """Upward poles of planes 1, 2 and of the upper surface, and the face's outward normal."""
    dip = {key: np.asarray(value, dtype=float) for key, value in dips.items()}
    for key, value in dip.items():
        _refuse(~((value >= 0.0) & (value <= np.pi / 2.0)), key, "a dip must be 0 to 90 degrees")
    _refuse(~(dip["face_dip"] > 0.0), "face_dip", "the face must dip (> 0)")
    dip_1, dip_2, face, upper = dip.values()
    pole_1 = stacked(*pole_components(dip_1, directions[0]))
    pole_2 = stacked(*pole_components(dip_2, directions[1]))
    fx, fy, fz = pole_components(face, directions[2])
    face_normal = stacked(fx, fy, np.where(np.asarray(overhanging_face, dtype=bool), -fz, fz))
    return pole_1, pole_2, face_normal, stacked(*pole_components(upper, directions[3]))


def _point_on_upper(normal_p: Array, normal_q: Array, upper: Array) -> tuple[Array, Array]:
    """The point on planes p and q (through O) and on the upper surface u . x = 1, and |u . e| with e
    the unit direction of the line p ∩ q (0 where the line is parallel to the upper surface)."""
    direction = cross(normal_p, normal_q)
    along = dot(upper, direction)
    with np.errstate(invalid="ignore", divide="ignore"):
        return direction / along[..., None], np.abs(along) / norm(direction)


def _first_reasons(conditions: list[tuple[WedgeReason, NDArray[np.bool_]]]) -> NDArray[np.int8]:
    """The first failed condition's reason per wedge (conditions in order, True = failed)."""
    reason = np.zeros(np.broadcast_shapes(*(bad.shape for _, bad in conditions)), dtype=np.int8)
    for code, bad in reversed(conditions):
        reason = np.where(bad, np.int8(code), reason)
    return reason


def _unit_wedge(
    pole_1: Array, pole_2: Array, face: Array, upper: Array
) -> tuple[Array, Array, Array, Array, list[tuple[WedgeReason, NDArray[np.bool_]]]]:
    """C1, C2 and T for the upper surface u . x = 1, the line of intersection (downward unit vector) and
    the conditions of the wedge's forming."""
    crest_1, along_1 = _point_on_upper(pole_1, face, upper)
    crest_2, along_2 = _point_on_upper(pole_2, face, upper)
    top, along_line = _point_on_upper(pole_1, pole_2, upper)
    face_up = unit(np.array([0.0, 0.0, 1.0]) - face[..., 2:3] * face)
    convex = (norm(cross(face, upper)) > TOLERANCE) & (dot(upper, face_up) > TOLERANCE)
    across = cross(pole_1, pole_2)
    line = downward(unit(across))
    behind = dot(face, top) < -TOLERANCE * norm(top)
    daylights = dot(face, line) > TOLERANCE
    conditions = [
        (WedgeReason.SLOPE_NOT_CONVEX, ~convex),
        (WedgeReason.PARALLEL_PLANES, ~(norm(across) > TOLERANCE)),
        (WedgeReason.TRACE_MISSES_CREST, ~((along_1 > TOLERANCE) & (along_2 > TOLERANCE))),
        (WedgeReason.NOT_DAYLIGHTING, ~behind & ~daylights),
        (WedgeReason.NOT_OUTCROPPING, ~behind | ~(along_line > TOLERANCE)),
    ]
    return crest_1, crest_2, top, line, conditions


def _scale(
    crest_1: Array, top: Array, height_h1: ArrayLike | None, height_h: ArrayLike | None
) -> tuple[Array, NDArray[np.bool_]]:
    """The upper surface's offset d that gives the height asked for, and where its point is below O."""
    _refuse(np.array((height_h1 is None) == (height_h is None)), "height_h1, height_h", "give exactly one")
    key, height, point = (
        ("height_h1", height_h1, crest_1) if height_h1 is not None else ("height_h", height_h, top)
    )
    height = np.asarray(height, dtype=float)
    _refuse(~(height > 0.0), key, "a height must be > 0")
    below = ~(point[..., 2] > TOLERANCE * norm(point))
    with np.errstate(invalid="ignore", divide="ignore"):
        offset = height / point[..., 2]
    return offset, np.broadcast_to(below, offset.shape)


def _limited(
    limits: SizeLimits | None,
    crack: TensionCrack | None,
    offset: Array,
    points: tuple[Array, Array, Array],
    planes: tuple[Array, Array],
) -> tuple[Array, NDArray[np.int8]]:
    """The scale factor and the governing `SizeLimit` of the tetrahedra O C1 C2 T (`points`: the unit
    wedge's C1, C2, T; `planes`: the face's and upper surface's normals) at the height asked for (the
    offset d); 1 and HEIGHT without limits."""
    if limits is None or not limits.any():
        return np.ones_like(offset), np.full(offset.shape, SizeLimit.HEIGHT, dtype=np.int8)
    _refuse(np.array(crack is not None), "limits", "size limits scale the wedge; not with a tension crack")
    crest_1, crest_2, top = (offset[..., None] * point for point in points)
    vertices = np.stack(np.broadcast_arrays(np.zeros_like(top), crest_1, crest_2, top), axis=-2)
    volume = tetrahedron_volume(np.zeros_like(top), crest_1, crest_2, top)
    return size_scale(limits, vertices, volume, *planes)


def _inward(normal: Array, other_vertex: Array) -> Array:
    """`normal` turned to point towards `other_vertex` (a vertex of the wedge off the plane)."""
    return np.where(dot(normal, other_vertex)[..., None] < 0.0, -normal, normal)


def _crack_cut(
    crack: TensionCrack, crest_1: Array, crest_2: Array, top: Array
) -> tuple[Array, Array, Array, Array, NDArray[np.bool_]]:
    """P, Q, R, the crack's normal into the wedge, and where the crack fails to cut off T alone."""
    normal = stacked(*pole_components(np.asarray(crack.dip, float), np.asarray(crack.dip_direction, float)))
    point = crest_1 + np.asarray(crack.distance, dtype=float)[..., None] * unit(top - crest_1)
    side_toe = -dot(normal, point)
    side_1, side_2, side_top = (dot(normal, vertex - point) for vertex in (crest_1, crest_2, top))
    scale = TOLERANCE * norm(top)
    apart = [(side * side_top < 0.0) & (np.abs(side) > scale) for side in (side_toe, side_1, side_2)]
    outside = ~(apart[0] & apart[1] & apart[2] & (np.abs(side_top) > scale))
    with np.errstate(invalid="ignore", divide="ignore"):
        foot = (side_toe / (side_toe - side_top))[..., None] * top
        on_2 = crest_2 + (side_2 / (side_2 - side_top))[..., None] * (top - crest_2)
        on_1 = crest_1 + (side_1 / (side_1 - side_top))[..., None] * (top - crest_1)
    return on_1, on_2, foot, np.where((side_toe < 0.0)[..., None], -normal, normal), outside


def _measures(crest_1: Array, crest_2: Array, top: Array) -> dict[str, Array]:
    """Areas, volume, centroid and trace lengths of the tetrahedra O C1 C2 T."""
    origin = np.zeros_like(top)
    return {
        "area_1": triangle_area(origin, crest_1, top),
        "area_2": triangle_area(origin, crest_2, top),
        "area_face": triangle_area(origin, crest_1, crest_2),
        "area_upper": triangle_area(top, crest_1, crest_2),
        "volume": tetrahedron_volume(origin, crest_1, crest_2, top),
        "centroid": (crest_1 + crest_2 + top) / 4.0,
        "trace_face_1": norm(crest_1),
        "trace_face_2": norm(crest_2),
        "trace_upper_1": norm(top - crest_1),
        "trace_upper_2": norm(top - crest_2),
        "crest_length": norm(crest_2 - crest_1),
        "intersection_length": norm(top),
    }


def _truncated(
    measures: dict[str, Array],
    on_1: Array,
    on_2: Array,
    foot: Array,
    top: Array,
    crest_1: Array,
    crest_2: Array,
) -> dict[str, Array]:
    """The measures of the tetrahedron less T P Q R, the piece the crack cuts off."""
    cut = tetrahedron_volume(top, on_1, on_2, foot)
    volume = measures["volume"] - cut
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = (
            measures["volume"][..., None] * measures["centroid"]
            - cut[..., None] * (top + on_1 + on_2 + foot) / 4.0
        ) / volume[..., None]
    return measures | {
        "area_1": measures["area_1"] - triangle_area(top, on_1, foot),
        "area_2": measures["area_2"] - triangle_area(top, on_2, foot),
        "area_upper": measures["area_upper"] - triangle_area(top, on_1, on_2),
        "area_crack": triangle_area(on_1, on_2, foot),
        "volume": volume,
        "centroid": centroid,
        "trace_upper_1": norm(on_1 - crest_1),
        "trace_upper_2": norm(on_2 - crest_2),
        "intersection_length": norm(foot),
    }


def _masked(value: Array, shape: tuple[int, ...], formed: NDArray[np.bool_] | None) -> Array:
    """`value` broadcast to `shape`, with NaN where the wedge does not form (`formed`; None where every
    wedge forms: then no copy)."""
    value = spread(value, shape)
    if formed is None:
        return value
    value = np.array(value, dtype=float)
    value[~formed] = np.nan
    return value


def wedge_geometries(
    dip_1: ArrayLike,
    dip_direction_1: ArrayLike,
    dip_2: ArrayLike,
    dip_direction_2: ArrayLike,
    face_dip: ArrayLike,
    face_dip_direction: ArrayLike,
    upper_dip: ArrayLike,
    upper_dip_direction: ArrayLike,
    *,
    height_h1: ArrayLike | None = None,
    height_h: ArrayLike | None = None,
    overhanging_face: ArrayLike = False,
    crack: TensionCrack | None = None,
    limits: SizeLimits | None = None,
) -> WedgeGeometry:
    """The geometry of wedges [rad, m], every argument broadcast with the others (one wedge per element):
    planes 1 and 2, the face and the upper surface by dip and dip direction, and exactly one height,
    `height_h1` (H1: C1 above the toe) or `height_h` (H: T above the toe); `overhanging_face` True
    where the face overhangs (it faces its dip direction but leans out over the toe); an optional
    tension crack, or optional size limits (not both). Wedges that cannot form are NaN with their
    `reason` (module docstring). ValueError names the argument of a dip outside 0 to 90 degrees, a
    height <= 0 or a size limit <= 0."""
    dips = {"dip_1": dip_1, "dip_2": dip_2, "face_dip": face_dip, "upper_dip": upper_dip}
    directions = tuple(
        np.asarray(d, dtype=float)
        for d in (dip_direction_1, dip_direction_2, face_dip_direction, upper_dip_direction)
    )
    pole_1, pole_2, face, upper = _plane_inputs(dips, directions, overhanging_face)
    crest_1, crest_2, top, line, conditions = _unit_wedge(pole_1, pole_2, face, upper)
    offset, below = _scale(crest_1, top, height_h1, height_h)
    conditions.append((WedgeReason.HEIGHT_BELOW_TOE, below))
    factor, limited_by = _limited(limits, crack, offset, (crest_1, crest_2, top), (face, upper))
    offset = offset * factor
    crest_1, crest_2, top = (offset[..., None] * point for point in (crest_1, crest_2, top))
    normal_1, normal_2 = _inward(pole_1, crest_2), _inward(pole_2, crest_1)
    measures = _measures(crest_1, crest_2, top)
    nowhere = np.full_like(top, np.nan)
    crack_points = {"crack_1": nowhere, "crack_2": nowhere, "crack_foot": nowhere, "normal_crack": nowhere}
    if crack is None:
        measures["area_crack"] = np.zeros_like(measures["volume"])
    else:
        on_1, on_2, foot, normal_crack, outside = _crack_cut(crack, crest_1, crest_2, top)
        conditions.append((WedgeReason.CRACK_OUTSIDE, outside))
        measures = _truncated(measures, on_1, on_2, foot, top, crest_1, crest_2)
        crack_points = {"crack_1": on_1, "crack_2": on_2, "crack_foot": foot, "normal_crack": normal_crack}
    reason = _first_reasons(conditions)
    shape = np.broadcast_shapes(reason.shape, factor.shape)  # limits may be the only arrays
    reason = spread(reason, shape)
    trend, plunge = trend_and_plunge(line)
    line_out = unit(-top)
    plunge_out = np.arcsin(np.clip(-line_out[..., 2], -1.0, 1.0))
    angles = short_solution_angles(crest_1, crest_2, top, pole_1, pole_2, normal_1, normal_2, plunge_out)
    values = (
        measures
        | crack_points
        | {
            "crest_1": crest_1,
            "crest_2": crest_2,
            "top": top,
            "line": line,
            "trend": trend,
            "plunge": plunge,
            "line_out": line_out,
            "plunge_out": plunge_out,
            "normal_1": normal_1,
            "normal_2": normal_2,
            "normal_face": face,
            "normal_upper": upper,
            "height_h1": crest_1[..., 2],
            "height_h": top[..., 2],
            "size_scale": factor,
        }
    )
    formed = reason == WedgeReason.FORMED
    partly = None if formed.all() else formed
    out = {
        key: _masked(value, shape + value.shape[-1:] if key in _VECTORS else shape, partly)
        for key, value in values.items()
    }
    short = ShortSolutionAngles(
        **{f.name: _masked(getattr(angles, f.name), shape, partly) for f in fields(angles)}
    )
    limited_by = spread(limited_by, shape)
    return WedgeGeometry(
        **out, short_solution=short, reason=reason, size_limited_by=limited_by, has_crack=crack is not None
    )


def wedge_geometry(*args: float, **kwargs) -> WedgeGeometry:
    """One wedge (scalar arguments, as `wedge_geometries`); raises WedgeNotFormedError with the reason if
    it cannot form."""
    geometry = wedge_geometries(*args, **kwargs)
    _refuse(np.array(geometry.reason.shape != ()), "wedge_geometry", "one wedge: give scalars")
    if not geometry.formed:
        raise WedgeNotFormedError(WedgeReason(int(geometry.reason)))
    return geometry
