"""`generate`: a rock mass realization from its config and a seed (docs/rock-mass.md).

The body (`bbmc.rockmass.profile`) is split into convex parts at the tension crack and at its reflex
corners, then cut by every line of every set (`bbmc.rockmass.cut`); each edge is labelled joint.<set>
(on a trace), bridge.<set> (intact rock between traces of the set's line), cut (a fictitious joint
making a concave profile convex: intact rock), joint.tension_crack, or "" (the model's boundary).

Cuts that would leave a block smaller than `min_block_fraction` x the median block are not made: the
median is that of the same realization cut without this rule (a first pass), and the piece is left
whole where the cut would have made the sliver. Blocks are never dropped, so the blocks tile the body.
Held blocks: those with an edge on a fixed side, and the slivers near one: a block smaller than
`held_sliver_fraction` x the median block (of this realization) with a vertex within the median
block's size (the square root of its area) of a fixed side. Such a sliver, cut off against a held side
by a joint, would otherwise be a block that nothing holds in place.
Every draw belongs to a world-fixed object (a line of a set, numbered from the origin): the same seed
gives the same lines, dips and traces whatever profile cuts them, and a set's lines do not change when
another set is added, removed or changed (`bbmc.rockmass.traces`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc.config import ConfigError, load_config
from bbmc.geometry.orientation import SectionTraces
from bbmc.rockmass import cut, profile
from bbmc.rockmass.config import CRACK, JointSet, RockMassConfig
from bbmc.rockmass.traces import SetGeometry, TooManyLinesError, lay_traces, set_lines

TOLERANCE = 1e-9  # of the body's size: a vertex this close to a line lies on it
SHORTEST_EDGE = 1e-6  # of the body's size: no edge is split closer than this to its ends


class GeometryError(ValueError):
    """A rock mass that cannot be made from its (valid) config: `key` names the config key at fault."""

    def __init__(self, key: str, reason: str) -> None:
        super().__init__(f"key '{key}': {reason}")
        self.key, self.reason = key, reason


@dataclass(frozen=True)
class SetSample:
    """What one realization drew for a set: each line's orientation (true dip and dip direction
    relative to the face [deg], apparent dip in the section [deg], spacing factor), the true spacings,
    and the trace and gap lengths that start inside the body [m] (each an independent draw)."""

    dip_deg: np.ndarray
    dip_direction_to_face_deg: np.ndarray
    apparent_dip_deg: np.ndarray
    factor: np.ndarray
    spacing_m: np.ndarray
    trace_length_m: np.ndarray
    gap_length_m: np.ndarray
    mean_apparent_dip_deg: float
    mean_factor: float


@dataclass(frozen=True)
class RockMass:
    """A realization: convex counter-clockwise polygons [m] and their edge labels (edge k from vertex k
    to k + 1); `split_vertices` lists, per polygon, the vertices that split a straight edge where its
    label changes (a trace's end); `held` the blocks with an edge on a fixed boundary and the slivers
    near one (the module's docstring)."""

    polygons: list[np.ndarray]
    edge_labels: list[list[str]]
    split_vertices: list[list[int]]
    held: list[bool]
    traces: pd.DataFrame  # set, line, x0_m, y0_m, x1_m, y1_m, length_m, censored
    lines: pd.DataFrame  # set, line, apparent_dip_deg, position_m, length_m (inside the body)
    sets: dict[str, SetSample]
    skipped: pd.DataFrame  # set, line, x0_m, y0_m, x1_m, y1_m: segments of lines not cut (see the module)
    # `line` is the line's number in its set (0 at the offset, > 0 ahead along the set's mean normal,
    # < 0 behind): the same line of the same seed has the same number in every profile
    outline: np.ndarray  # the body, counter-clockwise
    seed: int


def possible_labels(config: RockMassConfig) -> list[str]:
    """The labels the edges of a realization of `config` can carry (a realization may lack any of them):
    joint.<set> and bridge.<set> for each set, cut, and joint.tension_crack with a tension crack."""
    sets = [f"{kind}.{s.name}" for s in config.joint_sets for kind in ("joint", "bridge")]
    crack = [f"joint.{CRACK}"] if config.profile.tension_crack is not None else []
    return [*sets, cut.CUT, *crack]


def _with_crack(outline: np.ndarray, crest: np.ndarray, distance: float) -> tuple[np.ndarray, int]:
    """The outline with the crack's point on the ground behind the crest, and its index."""
    point = crest + np.array([distance, 0.0])
    for k in range(len(outline)):
        a, b = outline[k], outline[(k + 1) % len(outline)]
        if a[1] == b[1] == crest[1] and min(a[0], b[0]) < point[0] < max(a[0], b[0]):
            return np.insert(outline, k + 1, point, axis=0), k + 1
    raise AssertionError("the crack's point is on the ground behind the crest (the config checks it)")


def _sample(traces: SectionTraces, mean: SectionTraces, spacings: np.ndarray, laid: list) -> SetSample:
    return SetSample(
        traces.dip_deg, traces.dip_direction_to_face_deg, traces.apparent_dip_deg, traces.factor, spacings,
        np.concatenate([t.trace_lengths_m for t in laid] or [np.empty(0)]),
        np.concatenate([t.gap_lengths_m for t in laid] or [np.empty(0)]),
        float(mean.apparent_dip_deg[0]), float(mean.factor[0]),
    )  # fmt: skip


def _trace_rows(name: str, number: int, line: cut.Line, laid, intervals, tolerance: float) -> list[dict]:
    rows = []
    for start, end in laid.traces:
        for low, high in intervals:
            a, b = max(start, low), min(end, high)
            if b - a > tolerance:
                (x0, y0), (x1, y1) = (np.array(line.anchor) + t * np.array(line.direction) for t in (a, b))
                censored = start < low - tolerance or end > high + tolerance
                rows.append({"set": name, "line": number, "x0_m": x0, "y0_m": y0, "x1_m": x1, "y1_m": y1,
                             "length_m": b - a, "censored": bool(censored)})  # fmt: skip
    return rows


def _lay(
    joint_set: JointSet,
    geometry: SetGeometry,
    group: cut.SetLines,
    lines: list[cut.Line],
    parts: list[cut.Piece],
    seed: int,
    tolerance: float,
    trace_rows: list[dict],
    line_rows: list[dict],
) -> SetSample:
    """Traces and gaps along each of the set's lines that crosses the body (given to the line, for its
    labels); their rows added to `trace_rows` and `line_rows`; what the set drew."""
    laid = []
    for k, index in enumerate(group.lines):
        line, number = lines[index], int(geometry.numbers[k])
        intervals = cut.body_intervals(parts, line, tolerance)
        if not intervals:
            continue
        traces = lay_traces(joint_set, intervals[0][0], intervals[-1][1], seed, number)
        laid.append(traces)
        if not joint_set.persistent:
            line.breaks, line.starts_off = list(traces.traces.ravel()), True
        trace_rows += _trace_rows(joint_set.name, number, line, traces, intervals, tolerance)
        line_rows.append({"set": joint_set.name, "line": number,
                          "apparent_dip_deg": float(geometry.traces.apparent_dip_deg[k]),
                          "position_m": float(geometry.positions_m[k]),
                          "length_m": sum(high - low for low, high in intervals)})  # fmt: skip
    return _sample(geometry.traces, geometry.mean, geometry.spacings_m, laid)


def _held(
    polygons: list[np.ndarray], outline: np.ndarray, sides: list[str], tolerance: float, sliver: float
) -> list[bool]:
    """Blocks with an edge (two vertices) on one of the fixed sides of the model's box, and blocks
    smaller than `sliver` x the median block with a vertex within the median block's size of one."""
    (left, bottom), (right, _) = outline.min(axis=0), outline.max(axis=0)
    distance = {
        "left": lambda v: v[:, 0] - left,
        "right": lambda v: right - v[:, 0],
        "bottom": lambda v: v[:, 1] - bottom,
    }
    areas = np.array([cut.area([tuple(point) for point in p]) for p in polygons])
    median = float(np.median(areas))
    reach = np.sqrt(median)
    held = []
    for polygon, block_area in zip(polygons, areas, strict=True):
        gaps = [distance[side](polygon) for side in sides]
        on_side = any(np.count_nonzero(gap <= tolerance) >= 2 for gap in gaps)
        near = block_area < sliver * median and any(gap.min() <= reach for gap in gaps)
        held.append(on_side or near)
    return held


def generate(config: RockMassConfig, seed: int | None = None) -> RockMass:
    """A realization of the rock mass; `seed` [default: the config's] makes it reproducible."""
    seed = config.seed if seed is None else seed
    p = config.profile
    surface = p.surface()
    outline = profile.body_outline(surface, p.toe_extent_m, p.crest_extent_m, p.depth_m)
    size = float(np.ptp(outline, axis=0).max())
    tolerance = TOLERANCE * size
    lines: list[cut.Line] = []
    forced = []
    if p.tension_crack is not None:
        outline, vertex = _with_crack(outline, surface[-1], p.tension_crack.distance_behind_crest_m)
        top = (float(outline[vertex, 0]), float(outline[vertex, 1]))
        lines.append(cut.Line(top, (0.0, -1.0), f"joint.{CRACK}", cut.CUT, [p.tension_crack.depth_m]))
        forced.append((vertex, (0.0, -1.0), 0))
    origin = surface[0] if config.origin_m is None else np.array(config.origin_m, dtype=float)
    geometries = []
    for number, joint_set in enumerate(config.joint_sets):
        try:
            geometries.append(set_lines(joint_set, config.section_azimuth_deg, outline, origin, seed))
        except TooManyLinesError as error:
            raise GeometryError(f"joint_sets.{number}.spacing_m", str(error)) from None
    groups, numbers = [], [None] * len(lines)
    for geometry in geometries:
        groups.append(cut.SetLines(list(range(len(lines), len(lines) + len(geometry.lines))),
                                   tuple(geometry.mean.normal[0])))  # fmt: skip
        lines.extend(geometry.lines)
        numbers.extend(int(number) for number in geometry.numbers)
    parts = cut.convex_parts(outline, lines, forced, tolerance)
    samples, trace_rows, line_rows = {}, [], []
    for joint_set, geometry, group in zip(config.joint_sets, geometries, groups, strict=True):
        samples[joint_set.name] = _lay(
            joint_set, geometry, group, lines, parts, seed, tolerance, trace_rows, line_rows
        )
    if not line_rows:
        raise GeometryError("joint_sets", "the sets make no block: none of their lines crosses the body "
                            "(spacings larger than the body, or an offset beyond it)")  # fmt: skip
    smallest = 1e-12 * size * size
    if config.min_block_fraction > 0:
        first, _ = cut.cut_by_sets(parts, lines, groups, smallest, tolerance)
        smallest = max(
            smallest, config.min_block_fraction * float(np.median([cut.area(q[0]) for q in first]))
        )
    pieces, skipped = cut.cut_by_sets(parts, lines, groups, smallest, tolerance)
    if len(pieces) == len(parts):
        raise GeometryError("joint_sets", "the sets make no block: no line of theirs cuts the body")
    polygons, labels, splits = cut.labelled(pieces, lines, SHORTEST_EDGE * size)
    skipped_rows = [{"set": lines[i].on_label.split(".", 1)[1], "line": numbers[i], "x0_m": a[0],
                     "y0_m": a[1], "x1_m": b[0], "y1_m": b[1]} for i, a, b in skipped]  # fmt: skip
    trace_columns = ["set", "line", "x0_m", "y0_m", "x1_m", "y1_m", "length_m", "censored"]
    return RockMass(
        polygons=polygons,
        edge_labels=labels,
        split_vertices=splits,
        held=_held(
            polygons, outline, list(config.fixed_boundaries), 1e-6 * size, config.held_sliver_fraction
        ),
        traces=pd.DataFrame(trace_rows, columns=trace_columns),
        lines=pd.DataFrame(line_rows),
        sets=samples,
        skipped=pd.DataFrame(skipped_rows, columns=["set", "line", "x0_m", "y0_m", "x1_m", "y1_m"]),
        outline=outline,
        seed=seed,
    )


def from_file(path: str | Path, seed: int | None = None) -> RockMass:
    """A realization of the rock mass in a YAML file (the `rock_mass:` section alone); any fault is one
    `ConfigError` line naming the file and the key."""
    config = load_config(path, RockMassConfig)
    try:
        return generate(config, seed)
    except GeometryError as error:
        raise ConfigError(f"{path}: {error}") from None
