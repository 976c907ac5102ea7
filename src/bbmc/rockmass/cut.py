"""The body cut into convex blocks by straight lines, each edge labelled by what lies along it.

Three steps, on plain Python floats (the polygons are small; numpy's per-call cost would dominate):

1. `convex_parts`: the body (a simple polygon, possibly concave) is split by rays from its reflex
   vertices until every part is convex. At a reflex vertex the ray follows a line of `lines` through
   it where one fits (a joint then does the job); otherwise a new line labelled "cut" (a fictitious
   joint: intact rock) is made, straight down where that leaves both corners convex, else along the
   vertex's inner bisector. Forced rays (the tension crack) are made first.
2. `cut_by_sets`: every line of every set cuts every part it crosses, set after set. A piece is tested
   only against the lines that can pass through it (lines sorted by position, pieces behind the
   current line set aside), so the work grows with the number of blocks made, not with blocks x
   lines. A cut that would leave a piece smaller than `smallest_area` is not made in that piece: the
   piece stays whole there (as if the sliver were merged back into it) and the segment is reported
   as skipped.
3. `labelled`: each edge takes the label of its line at each point (`Line.label`), and is split where
   the label changes (a trace's end): such split vertices lie on a straight edge and are listed.
"""

from __future__ import annotations

import itertools
import math
from bisect import bisect_left, bisect_right
from dataclasses import dataclass, field

import numpy as np

Point = tuple[float, float]
Piece = tuple[list[Point], list[int]]  # counter-clockwise vertices; the line of each edge (-1: boundary)
BOUNDARY = -1
CUT = "cut"
STRAIGHT_DOWN_MARGIN = math.sin(math.radians(5.0))  # a ray straight down leaves both corners this convex


@dataclass
class Line:
    """A straight line through `anchor` along the unit `direction`; position along it t = direction .
    (x - anchor). Its label at t is `on_label` where an odd number of `breaks` (sorted) lie below t if
    it `starts_off`, an even number otherwise; `off_label` elsewhere."""

    anchor: Point
    direction: Point
    on_label: str
    off_label: str = ""
    breaks: list[float] = field(default_factory=list)
    starts_off: bool = False
    normal: Point = field(init=False)  # the direction turned a quarter counter-clockwise
    offset: float = field(init=False)  # the line is normal . x = offset

    def __post_init__(self) -> None:
        self.normal = (-self.direction[1], self.direction[0])
        self.offset = self.normal[0] * self.anchor[0] + self.normal[1] * self.anchor[1]

    def position(self, point: Point) -> float:
        (x, y), (ax, ay) = point, self.anchor
        return self.direction[0] * (x - ax) + self.direction[1] * (y - ay)

    def label(self, t: float) -> str:
        on = (bisect_right(self.breaks, t) % 2 == 1) == self.starts_off
        return self.on_label if on else self.off_label


def _cross(a: Point, b: Point) -> float:
    return a[0] * b[1] - a[1] * b[0]


def _unit(v: Point) -> Point:
    length = math.hypot(*v)
    return (v[0] / length, v[1] / length)


def area(points: list[Point]) -> float:
    """Signed area [m^2] of a polygon (shoelace), > 0 counter-clockwise."""
    total = 0.0
    x0, y0 = points[-1]
    for x1, y1 in points:
        total += x0 * y1 - x1 * y0
        x0, y0 = x1, y1
    return 0.5 * total


def _reflex(points: list[Point], tolerance: float) -> int | None:
    """The first vertex of a counter-clockwise polygon whose corner turns right (is reflex)."""
    n = len(points)
    for i in range(n):
        (ax, ay), (bx, by), (cx, cy) = points[i - 1], points[i], points[(i + 1) % n]
        incoming, outgoing = _unit((bx - ax, by - ay)), _unit((cx - bx, cy - by))
        if _cross(incoming, outgoing) < -tolerance:
            return i
    return None


def _split_by_ray(piece: Piece, i: int, ray: Point, line: int, tolerance: float) -> tuple[Piece, Piece]:
    """A simple polygon split by the ray from its vertex i along `ray` to the first edge it meets."""
    points, ids = piece
    n = len(points)
    px, py = points[i]
    best: tuple[float, int, float] | None = None
    for j in range(n):
        if j == i or (j + 1) % n == i:
            continue
        (ax, ay), (bx, by) = points[j], points[(j + 1) % n]
        edge = (bx - ax, by - ay)
        denominator = _cross(ray, edge)
        if abs(denominator) <= 1e-14 * math.hypot(*edge):
            continue
        w = (ax - px, ay - py)
        s, u = _cross(w, edge) / denominator, _cross(w, ray) / denominator
        if s > tolerance and -1e-12 <= u <= 1 + 1e-12 and (best is None or s < best[0]):
            best = (s, j, u)
    if best is None:
        raise ValueError("a ray from a reflex vertex left the body: the outline is not a simple polygon")
    s, j, u = best
    after = (j + 1) % n
    scale = math.hypot(points[after][0] - points[j][0], points[after][1] - points[j][1])
    order_a = [(i + k) % n for k in range((j - i) % n + 1)]  # i .. j
    order_b = [(j + 1 + k) % n for k in range((i - j - 1) % n + 1)]  # j + 1 .. i
    if u * scale <= tolerance:  # the ray ends at vertex j
        a = ([points[k] for k in order_a], [ids[k] for k in order_a[:-1]] + [line])
        b = ([points[j]] + [points[k] for k in order_b], [ids[j]] + [ids[k] for k in order_b[:-1]] + [line])
    elif (1 - u) * scale <= tolerance:  # at vertex j + 1
        a = ([points[k] for k in order_a] + [points[after]], [ids[k] for k in order_a] + [line])
        b = ([points[k] for k in order_b], [ids[k] for k in order_b[:-1]] + [line])
    else:
        x = (px + s * ray[0], py + s * ray[1])
        a = ([points[k] for k in order_a] + [x], [ids[k] for k in order_a] + [line])
        b = ([x] + [points[k] for k in order_b], [ids[j]] + [ids[k] for k in order_b[:-1]] + [line])
    return a, b


def _ray_at(points: list[Point], i: int, lines: list[Line], tolerance: float) -> tuple[Point, int | None]:
    """The ray from reflex vertex i: along a line through it that leaves both corners convex (and its
    index), else straight down or the inner bisector (and None: a new cut)."""
    n = len(points)
    (ax, ay), (bx, by), (cx, cy) = points[i - 1], points[i], points[(i + 1) % n]
    incoming, outgoing = _unit((bx - ax, by - ay)), _unit((cx - bx, cy - by))

    def convex_both(ray: Point, margin: float) -> bool:
        return _cross(incoming, ray) > margin and _cross(outgoing, ray) > margin

    for index, line in enumerate(lines):
        nx, ny = line.normal
        if abs(nx * bx + ny * by - line.offset) <= tolerance:
            for sense in (1.0, -1.0):
                ray = (sense * line.direction[0], sense * line.direction[1])
                if convex_both(ray, 1e-6):
                    return ray, index
    if convex_both((0.0, -1.0), STRAIGHT_DOWN_MARGIN):
        return (0.0, -1.0), None
    return _unit((-incoming[1] - outgoing[1], incoming[0] + outgoing[0])), None


def convex_parts(
    outline: np.ndarray, lines: list[Line], forced: list[tuple[int, Point, int]], tolerance: float
) -> list[Piece]:
    """The body (counter-clockwise outline, edges on the boundary) split into convex parts: first by
    the `forced` rays (vertex index, direction, line index), then at every reflex vertex (see the
    module's docstring); new cut lines are appended to `lines`."""
    pieces: list[Piece] = [([tuple(map(float, p)) for p in outline], [BOUNDARY] * len(outline))]
    for vertex, ray, line in forced:
        point = tuple(map(float, outline[vertex]))
        piece = next(p for p in pieces if point in p[0])
        pieces.remove(piece)
        pieces.extend(_split_by_ray(piece, piece[0].index(point), ray, line, tolerance))
    convex, pending = [], pieces
    while pending:
        piece = pending.pop()
        i = _reflex(piece[0], 1e-9)
        if i is None:
            convex.append(piece)
            continue
        ray, line = _ray_at(piece[0], i, lines, tolerance)
        if line is None:
            lines.append(Line(piece[0][i], ray, CUT))
            line = len(lines) - 1
        pending.extend(_split_by_ray(piece, i, ray, line, tolerance))
    return convex


def chord(piece: Piece, line: Line, tolerance: float) -> tuple[float, float] | None:
    """The interval of positions t along `line` inside a convex piece or on its boundary (a line along
    one of its edges has that edge), or None if it misses it or only touches a corner."""
    points = piece[0]
    nx, ny = line.normal
    c = line.offset
    d = [nx * x + ny * y - c for x, y in points]
    if max(d) < -tolerance or min(d) > tolerance:
        return None
    ts = [
        line.position(point) for point, distance in zip(points, d, strict=True) if abs(distance) <= tolerance
    ]
    n = len(points)
    for k in range(n):
        j = (k + 1) % n
        if min(d[k], d[j]) < -tolerance and max(d[k], d[j]) > tolerance:
            f = d[k] / (d[k] - d[j])
            (ax, ay), (bx, by) = points[k], points[j]
            ts.append(line.position((ax + f * (bx - ax), ay + f * (by - ay))))
    return (min(ts), max(ts)) if ts and max(ts) - min(ts) > tolerance else None


def body_intervals(parts: list[Piece], line: Line, tolerance: float) -> list[tuple[float, float]]:
    """The intervals of positions along `line` inside the body (the union of its convex parts)."""
    chords = sorted(filter(None, (chord(part, line, tolerance) for part in parts)))
    merged: list[list[float]] = []
    for low, high in chords:
        if merged and low <= merged[-1][1] + tolerance:
            merged[-1][1] = max(merged[-1][1], high)
        else:
            merged.append([low, high])
    return [(low, high) for low, high in merged]


def _split(
    piece: Piece, line: Line, index: int, tolerance: float
) -> tuple[Piece, Piece, Point, Point] | None:
    """A convex piece split by a line (the new edges are the line's `index`): the part below (n . x <= c)
    and above, and the two points where the line crosses the boundary; None if it does not cross it."""
    points, ids = piece
    nx, ny = line.normal
    c = line.offset
    d = [nx * x + ny * y - c for x, y in points]
    if max(d) <= tolerance or min(d) >= -tolerance:
        return None
    side = [0 if abs(v) <= tolerance else (1 if v > 0 else -1) for v in d]
    items: list[tuple[Point, int, int]] = []  # point, side, the line of the edge that leaves it
    n = len(points)
    for k in range(n):
        items.append((points[k], side[k], ids[k]))
        j = (k + 1) % n
        if side[k] * side[j] < 0:
            f = d[k] / (d[k] - d[j])
            (ax, ay), (bx, by) = points[k], points[j]
            items.append(((ax + f * (bx - ax), ay + f * (by - ay)), 0, ids[k]))
    m = len(items)
    halves = []
    for excluded in (1, -1):
        kept = [k for k in range(m) if items[k][1] != excluded]
        following = kept[1:] + kept[:1]
        halves.append(
            (
                [items[k][0] for k in kept],
                [
                    items[k][2] if (k + 1) % m == after else index
                    for k, after in zip(kept, following, strict=True)
                ],
            )
        )
    ends = [item[0] for item in items if item[1] == 0]
    return halves[0], halves[1], ends[0], ends[-1]


@dataclass(frozen=True)
class SetLines:
    """The lines of one set (indices into the line list) and the mean normal that orders them."""

    lines: list[int]
    normal: Point


class _Frame:
    """Coordinates along a set's mean normal (q) and mean direction (s) from a point `origin`. A line
    of the set is q = position + slope s; a piece spans [q_low, q_high] x [s_low, s_high]."""

    def __init__(self, normal: Point, origin: Point) -> None:
        self.normal, self.direction, self.origin = normal, (normal[1], -normal[0]), origin

    def box(self, points: list[Point]) -> tuple[float, float, float, float]:
        (nx, ny), (dx, dy), (ox, oy) = self.normal, self.direction, self.origin
        q = [nx * (x - ox) + ny * (y - oy) for x, y in points]
        s = [dx * (x - ox) + dy * (y - oy) for x, y in points]
        return min(q), max(q), min(s), max(s)

    def key(self, line: Line) -> tuple[float, float]:
        """The line's position (its q at s = 0) and slope dq/ds (steep lines are kept finite)."""
        along = self.direction[0] * line.direction[0] + self.direction[1] * line.direction[1]
        across = self.normal[0] * line.direction[0] + self.normal[1] * line.direction[1]
        slope = across / math.copysign(max(abs(along), 1e-6), along)
        q_low, _, s_low, _ = self.box([line.anchor])
        return q_low - slope * s_low, slope


def cut_by_sets(
    parts: list[Piece], lines: list[Line], sets: list[SetLines], smallest_area: float, tolerance: float
) -> tuple[list[Piece], list[tuple[int, Point, Point]]]:
    """The convex parts cut by every set's lines (see the module's docstring); also the segments not
    cut (line index, end points) because a piece smaller than `smallest_area` [m^2] would be left.

    A line q = p + m s meets a piece only if p + m s falls in the piece's q range somewhere in its s
    range: with |m| <= M (the set's steepest line) and |s| <= S, only lines with p within M S of the
    piece's q range are looked at (by bisection on the sorted positions), and a piece is set aside
    once the lines' positions have passed it by more than M S."""
    pieces, skipped = parts, []
    vertices = [point for part in parts for point in part[0]]
    origin = (sum(x for x, _ in vertices) / len(vertices), sum(y for _, y in vertices) / len(vertices))
    for group in sets:
        frame = _Frame(group.normal, origin)
        keyed = sorted(
            (*frame.key(lines[index]), index)
            for index in group.lines
            if body_intervals(parts, lines[index], tolerance)
        )
        positions = [position for position, _, _ in keyed]
        steepest = max((abs(slope) for _, slope, _ in keyed), default=0.0)
        cut = []
        for piece in pieces:
            q_low, q_high, s_low, s_high = frame.box(piece[0])
            span = steepest * max(abs(s_low), abs(s_high)) + tolerance
            first, last = bisect_left(positions, q_low - span), bisect_right(positions, q_high + span)
            active, done = [(piece, q_low, q_high, s_low, s_high)], []
            for position, slope, index in keyed[first:last]:
                still = []
                for current in active:
                    _, low, high, left, right = current
                    if high < position - steepest * max(abs(left), abs(right)) - tolerance:
                        done.append(current[0])  # no later line reaches it
                        continue
                    ends = (position + slope * left, position + slope * right)
                    halves = None
                    if min(ends) <= high + tolerance and max(ends) >= low - tolerance:
                        halves = _split(current[0], lines[index], index, tolerance)
                    if halves is None:
                        still.append(current)
                    elif min(area(halves[0][0]), area(halves[1][0])) < smallest_area:
                        skipped.append((index, halves[2], halves[3]))
                        still.append(current)
                    else:
                        still.extend((half, *frame.box(half[0])) for half in halves[:2])
                active = still
            cut.extend(done)
            cut.extend(current[0] for current in active)
        pieces = cut
    return pieces, skipped


def labelled(
    pieces: list[Piece], lines: list[Line], shortest_m: float
) -> tuple[list[np.ndarray], list[list[str]], list[list[int]]]:
    """Each piece's vertices, the label of each edge, and the vertices added where a label changes
    along an edge (no sub-edge shorter than `shortest_m` [m] is made)."""
    polygons, labels, splits = [], [], []
    for points, ids in pieces:
        vertices, edge_labels, added = [], [], []
        n = len(points)
        for k in range(n):
            p, q = points[k], points[(k + 1) % n]
            vertices.append(p)
            if ids[k] == BOUNDARY:
                edge_labels.append("")
                continue
            line = lines[ids[k]]
            ta, tb = line.position(p), line.position(q)
            low, high = min(ta, tb), max(ta, tb)
            inner = line.breaks[
                bisect_right(line.breaks, low + shortest_m) : bisect_left(line.breaks, high - shortest_m)
            ]
            stops = [ta, *(inner if ta < tb else inner[::-1]), tb]
            for start, end in itertools.pairwise(stops):
                label = line.label(0.5 * (start + end))
                if len(stops) > 2 and start != ta:
                    if label == edge_labels[-1]:
                        continue  # two breaks at one point (a gap of zero length): no change
                    f = (start - ta) / (tb - ta)
                    added.append(len(vertices))
                    vertices.append((p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])))
                edge_labels.append(label)
        polygons.append(np.array(vertices))
        labels.append(edge_labels)
        splits.append(added)
    return polygons, labels, splits
