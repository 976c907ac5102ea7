"""The lines of a joint set across the body, and the traces (joints) and gaps (rock bridges) along
each line, UDEC's way: every line crosses the whole body; a trace is the joint part of a line.

Lines. Along the set's mean trace normal, from the toe, one line lies at the offset (true, normal to
the joints: offset / factor in the section) and the others at spacings drawn from the spacing's
distribution on either side of it (true spacings S, S / factor apart in the section), until the body
is covered (with a margin of the body's size for a set whose lines scatter). Each line has its own
orientation (`bbmc.rockmass.sets`), turned about the point where the mean line crosses the body's
centroid's cross-line, so lines scatter least in the middle of the body.

Traces. Along each line, traces and gaps alternate, their lengths drawn from their distributions (a
persistence k with a trace length: gap = trace (1 - k) / k). The sequence starts a random fraction of
ten mean cycles before the line enters the body, so that where it enters is a random point of it
(stationary): the persistence measured along a line is E[trace] / (E[trace] + E[gap]) wherever it is.
A persistent set (no trace length, or k = 1) has one trace along the whole line.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bbmc.geometry.orientation import SectionTraces
from bbmc.rockmass import config as c
from bbmc.rockmass import distributions
from bbmc.rockmass.cut import Line
from bbmc.rockmass.sets import mean_trace, sample_traces

BURN_IN_CYCLES = 10.0


@dataclass(frozen=True)
class SetGeometry:
    """The lines of a set: their orientations, positions [m] (apparent, along the mean normal from the
    toe), the true spacings drawn, and the mean trace the positions are measured along."""

    traces: SectionTraces
    positions_m: np.ndarray
    spacings_m: np.ndarray
    mean: SectionTraces
    lines: list[Line]


def _positions(
    spacing: distributions.Sampler, start: float, end: float, factor: float, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Positions from `start` towards `end` (either side) at spacings drawn / factor, the last beyond
    `end`; and the true spacings drawn."""
    sense = 1.0 if end >= start else -1.0
    drawn: list[np.ndarray] = []
    position = start
    batch = max(8, int(abs(end - start) * factor / spacing.mean() * 1.2) + 4)
    while sense * (end - position) > 0:
        draws = spacing.rvs(size=batch, random_state=rng)
        drawn.append(draws)
        position = start + sense * float(np.sum(np.concatenate(drawn))) / factor
    spacings = np.concatenate(drawn) if drawn else np.empty(0)
    steps = start + sense * np.cumsum(spacings) / factor
    beyond = int(np.searchsorted(sense * steps, sense * end, side="right")) + 1
    return steps[:beyond], spacings[:beyond]


def set_lines(
    joint_set: c.JointSet,
    section_azimuth_deg: float | None,
    outline: np.ndarray,
    toe: np.ndarray,
    label: str,
    rng: np.random.Generator,
) -> SetGeometry:
    """The set's lines across the body (`outline`, counter-clockwise) as `Line`s labelled joint.<set>
    on their traces and bridge.<set> on their gaps (traces laid later by `lay_traces`)."""
    mean = mean_trace(joint_set, section_azimuth_deg)
    normal, factor = mean.normal[0], float(mean.factor[0])
    direction = np.array([normal[1], -normal[0]])
    reach = (outline - toe) @ normal
    scatters = joint_set.orientation is not None and joint_set.orientation.fisher_k is not None
    scatters = scatters or (isinstance(joint_set.dip_deg, c.DipScatter) and joint_set.dip_deg.std > 0)
    margin = float(np.ptp(outline, axis=0).max()) if scatters else 0.0
    low, high = reach.min() - margin, reach.max() + margin
    spacing = distributions.length(joint_set.spacing_m)
    first = joint_set.offset_m / factor
    ahead, spacings_ahead = _positions(spacing, first, high, factor, rng)
    behind, spacings_behind = _positions(spacing, first, low, factor, rng)
    positions = np.concatenate([behind[::-1], [first], ahead])
    traces = sample_traces(joint_set, section_azimuth_deg, len(positions), rng)
    centre = float((outline.mean(axis=0) - toe) @ direction)
    lines = []
    for position, line_normal in zip(positions, traces.normal, strict=True):
        pivot = toe + position * normal + centre * direction
        along = (line_normal[1], -line_normal[0])
        lines.append(Line((float(pivot[0]), float(pivot[1])), (float(along[0]), float(along[1])),
                          f"joint.{label}", f"bridge.{label}"))  # fmt: skip
    return SetGeometry(traces, positions, np.concatenate([spacings_behind, spacings_ahead]), mean, lines)


@dataclass(frozen=True)
class LineTraces:
    """The traces along one line: their (start, end) positions [m] overlapping the body, and the trace
    and gap lengths drawn that start inside it (each an independent draw)."""

    traces: np.ndarray  # (n, 2)
    trace_lengths_m: np.ndarray
    gap_lengths_m: np.ndarray


def lay_traces(joint_set: c.JointSet, entry: float, exit: float, rng: np.random.Generator) -> LineTraces:
    """Traces and gaps along a line inside the body between positions `entry` and `exit` [m]."""
    if joint_set.persistent:
        return LineTraces(np.array([[entry, exit]]), np.empty(0), np.empty(0))
    trace = distributions.length(joint_set.trace_length_m)
    gap = None if joint_set.gap_m is None else distributions.length(joint_set.gap_m)
    ratio = None if joint_set.persistence is None else (1.0 - joint_set.persistence) / joint_set.persistence
    cycle = trace.mean() * (1.0 + ratio) if gap is None else trace.mean() + gap.mean()
    start = entry - rng.uniform() * BURN_IN_CYCLES * cycle
    batch = int((exit - start) / cycle * 1.2) + 8
    traces, gaps = np.empty(0), np.empty(0)
    while start + traces.sum() + gaps.sum() <= exit:
        more = trace.rvs(size=batch, random_state=rng)
        traces = np.concatenate([traces, more])
        gaps = np.concatenate([gaps, more * ratio if gap is None else gap.rvs(size=batch, random_state=rng)])
    starts = start + np.concatenate([[0.0], np.cumsum(traces + gaps)[:-1]])
    ends = starts + traces
    inside = (ends > entry) & (starts < exit)
    return LineTraces(
        np.column_stack([starts[inside], ends[inside]]),
        traces[(starts >= entry) & (starts < exit)],
        gaps[(ends >= entry) & (ends < exit)],
    )
