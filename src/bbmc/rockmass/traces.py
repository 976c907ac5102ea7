"""The lines of a joint set across the body, and the traces (joints) and gaps (rock bridges) along
each line, UDEC's way: every line crosses the whole body; a trace is the joint part of a line.

Everything random belongs to a world-fixed object, so one seed gives the same joints whatever profile
cuts them (paired realizations, common random numbers: docs/rock-mass.md). Each draw of a line comes
from its own stream, `numpy.random.SeedSequence(seed, spawn_key=(set name, line number, draw))`: line
k's spacing, its orientation and its traces do not depend on how many lines the body needs, on where
the line enters the body, nor on the other sets.

Lines. Along the set's mean trace normal n, from the origin o (the config's `origin_m`, default the
toe), line 0 lies at the offset (true, normal to the joints: offset / factor in the section), lines
1, 2, ... ahead of it (+n) and -1, -2, ... behind it, line k a true spacing S_k from line k -+ 1 (drawn
from line k's stream; S_k / factor apart in the section), until the body is covered (with a margin, for
a set whose lines scatter, of the body's reach along the lines from o). Each line has its own
orientation (`bbmc.rockmass.sets`), turned about its pivot o + p_k n, where p_k is its position: lines
scatter least near the origin's cross-line.

Traces. Along each line, from its pivot (t = 0, t along the line), traces and gaps alternate in cycles
(a trace and the gap after it), their lengths drawn (a persistence k with a trace length:
gap = trace (1 - k) / k). The cycle that covers the pivot comes from a sequence started a random
fraction of ten mean cycles before it, so that the pivot is a random point of the sequence
(stationary): the persistence measured along a line is E[trace] / (E[trace] + E[gap]) wherever it is.
The cycles after it continue that sequence; the cycles before it are drawn going backwards from it,
from streams of their own. Lengths are drawn `CHUNK` at a time, so the j-th cycle is the same however
far the body reaches. A persistent set (no trace length, or k = 1) has one trace along the whole line.
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
CHUNK = 32  # lengths drawn at a time along a line
MAX_LINES = 10_000  # of a set on either side of line 0: a body that needs more is refused
SPACING, ORIENTATION, PHASE, AHEAD_TRACES, AHEAD_GAPS, BACK_TRACES, BACK_GAPS = range(7)


class TooManyLinesError(ValueError):
    """A body that would need more than `MAX_LINES` lines of a set on one side of its line 0."""


def stream(seed: int, set_name: str, line: int, draw: int) -> np.random.Generator:
    """The generator of one `draw` of line `line` (..., -1, 0, 1, ...) of the set `set_name`:
    `SeedSequence(seed, spawn_key=(len(name), *name's bytes, line's zigzag code, draw))` (zigzag:
    k >= 0 -> 2k, k < 0 -> -2k - 1; the name's length first so that no two keys coincide)."""
    name = set_name.encode()
    code = 2 * line if line >= 0 else -2 * line - 1
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(len(name), *name, code, draw)))


@dataclass(frozen=True)
class SetGeometry:
    """The lines of a set: their numbers (0 at the offset, > 0 ahead along the mean normal, < 0 behind),
    orientations, positions [m] (apparent, along the mean normal from the origin), the true spacings
    drawn (line k's from line k -+ 1), and the mean trace the positions are measured along."""

    numbers: np.ndarray
    traces: SectionTraces
    positions_m: np.ndarray
    spacings_m: np.ndarray
    mean: SectionTraces
    lines: list[Line]


def _walk(
    joint_set: c.JointSet, seed: int, first: float, end: float, factor: float
) -> tuple[list[int], list[float], list[float]]:
    """Line numbers, positions and true spacings from line 0 at `first` towards `end` (either side),
    up to the first line at or beyond `end`; line 0 not included."""
    spacing = distributions.length(joint_set.spacing_m)
    sense = 1 if end >= first else -1
    numbers, positions, spacings = [], [], []
    position = first
    while sense * (end - position) > 0:
        number = sense * (len(numbers) + 1)
        if len(numbers) == MAX_LINES:
            estimate = abs(end - first) * factor / spacing.mean()
            raise TooManyLinesError(
                f"the body reaches {abs(end - first):.4g} m from the set's line 0 (in the section): about "
                f"{estimate:,.0f} lines at this spacing, more than {MAX_LINES:,} on one side"
            )
        drawn = float(spacing.rvs(size=1, random_state=stream(seed, joint_set.name, number, SPACING))[0])
        position += sense * drawn / factor
        numbers.append(number)
        positions.append(position)
        spacings.append(drawn)
    return numbers, positions, spacings


def set_lines(
    joint_set: c.JointSet,
    section_azimuth_deg: float | None,
    outline: np.ndarray,
    origin: np.ndarray,
    seed: int,
) -> SetGeometry:
    """The set's lines that can cross the body (`outline`, counter-clockwise) as `Line`s labelled
    joint.<set> on their traces and bridge.<set> on their gaps (traces laid later by `lay_traces`),
    each anchored at its pivot. `TooManyLinesError` for a body that needs more than `MAX_LINES` a side."""
    mean = mean_trace(joint_set, section_azimuth_deg)
    normal, factor = mean.normal[0], float(mean.factor[0])
    direction = np.array([normal[1], -normal[0]])
    reach = (outline - origin) @ normal
    scatters = joint_set.orientation is not None and joint_set.orientation.fisher_k is not None
    scatters = scatters or (isinstance(joint_set.dip_deg, c.DipScatter) and joint_set.dip_deg.std > 0)
    margin = float(np.abs((outline - origin) @ direction).max()) if scatters else 0.0
    low, high = reach.min() - margin, reach.max() + margin
    first = joint_set.offset_m / factor
    ahead = _walk(joint_set, seed, first, high, factor)
    behind = _walk(joint_set, seed, first, low, factor)
    numbers = np.array([*behind[0][::-1], 0, *ahead[0]])
    positions = np.array([*behind[1][::-1], first, *ahead[1]])
    spacings = np.array([*behind[2][::-1], np.nan, *ahead[2]])
    keep = (positions >= low) & (positions <= high)
    numbers, positions, spacings = numbers[keep], positions[keep], spacings[keep]
    streams = [stream(seed, joint_set.name, int(number), ORIENTATION) for number in numbers]
    traces = sample_traces(joint_set, section_azimuth_deg, streams)
    lines = []
    for position, line_normal in zip(positions, traces.normal, strict=True):
        pivot = origin + position * normal
        along = (line_normal[1], -line_normal[0])
        lines.append(Line((float(pivot[0]), float(pivot[1])), (float(along[0]), float(along[1])),
                          f"joint.{joint_set.name}", f"bridge.{joint_set.name}"))  # fmt: skip
    return SetGeometry(numbers, traces, positions, spacings[~np.isnan(spacings)], mean, lines)


@dataclass(frozen=True)
class LineTraces:
    """The traces along one line: their (start, end) positions [m] from the line's pivot overlapping
    the body, and the trace and gap lengths of the cycles whose first end met walking out from the
    pivot lies in the body (each an independent draw: where a cycle is met depends on the cycles
    before it only; the cycle over the pivot, picked for covering it, is left out)."""

    traces: np.ndarray  # (n, 2)
    trace_lengths_m: np.ndarray
    gap_lengths_m: np.ndarray


def _cycles(
    trace: distributions.Sampler,
    gap: distributions.Sampler | None,
    ratio: float | None,
    traces_rng: np.random.Generator,
    gaps_rng: np.random.Generator,
    reach: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Trace and gap lengths of successive cycles, `CHUNK` at a time, until they are longer than
    `reach` [m] (none for a reach < 0)."""
    traces, gaps, total = [], [], 0.0
    while total <= reach:
        more = trace.rvs(size=CHUNK, random_state=traces_rng)
        traces.append(more)
        gaps.append(more * ratio if gap is None else gap.rvs(size=CHUNK, random_state=gaps_rng))
        total += float(np.sum(traces[-1] + gaps[-1]))
    return np.concatenate(traces or [np.empty(0)]), np.concatenate(gaps or [np.empty(0)])


def lay_traces(joint_set: c.JointSet, entry: float, exit: float, seed: int, number: int) -> LineTraces:
    """Traces and gaps along line `number` of the set inside the body between positions `entry` and
    `exit` [m] from the line's pivot."""
    if joint_set.persistent:
        return LineTraces(np.array([[entry, exit]]), np.empty(0), np.empty(0))
    trace = distributions.length(joint_set.trace_length_m)
    gap = None if joint_set.gap_m is None else distributions.length(joint_set.gap_m)
    ratio = None if joint_set.persistence is None else (1.0 - joint_set.persistence) / joint_set.persistence
    cycle = trace.mean() * (1.0 + ratio) if gap is None else trace.mean() + gap.mean()
    draw = lambda kind: stream(seed, joint_set.name, number, kind)  # noqa: E731
    start = -draw(PHASE).uniform() * BURN_IN_CYCLES * cycle
    lengths, gaps = _cycles(trace, gap, ratio, draw(AHEAD_TRACES), draw(AHEAD_GAPS), max(exit, 0.0) - start)
    ends = start + np.cumsum(lengths + gaps)
    covering = int(np.searchsorted(ends, 0.0, side="right"))
    lengths, gaps, ends = lengths[covering:], gaps[covering:], ends[covering:]
    pivot_cycle = ends[0] - lengths[0] - gaps[0]  # where the cycle over the pivot starts
    back_lengths, back_gaps = _cycles(
        trace, gap, ratio, draw(BACK_TRACES), draw(BACK_GAPS), pivot_cycle - entry
    )
    back_ends = pivot_cycle - np.cumsum(back_lengths + back_gaps) + back_lengths  # its trace's end
    starts = np.concatenate([(back_ends - back_lengths)[::-1], ends - lengths - gaps])
    lengths_all = np.concatenate([back_lengths[::-1], lengths])
    gaps_all = np.concatenate([back_gaps[::-1], gaps])
    met = np.concatenate([(back_ends + back_gaps)[::-1], starts[len(back_lengths) :]])
    counted = (met >= entry) & (met <= exit)  # the cycle's first end met from the pivot is in the body
    counted[len(back_lengths)] = False  # the cycle over the pivot, picked for covering it
    inside = (starts + lengths_all > entry) & (starts < exit)
    return LineTraces(
        np.column_stack([starts[inside], (starts + lengths_all)[inside]]),
        lengths_all[counted],
        gaps_all[counted],
    )
