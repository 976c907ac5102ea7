"""From a scene's `support:` section to the engine's support elements (`bbmc.dem.support`), in SI.

Each anchor is one element from its head's block to its end's block. Each grouted bolt becomes one
element per joint it crosses: walking from the head to the end, the bolt passes through a sequence of
blocks (convex, so each holds one stretch of it); where it leaves one block and enters the next it
crosses their joint, and an element joins the two at that point. A crossing between two blocks that
are both held still is left out (it can carry nothing). Faults are one line naming the key.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bbmc.dem import layout as L
from bbmc.scene.schema import scene_error
from bbmc.support.capacity import anchor_capacity, grouted_bolt_capacity
from bbmc.support.config import Anchor, GroutedBolt

DEBONDED_DIAMETERS = 10.0  # a grouted crossing's default debonded length, in bolt diameters
INSIDE = 1e-9  # relative tolerance of "inside a block" and of a stretch's ends
OPEN_GAP = 1e-3  # a gap between two blocks along a bolt wider than this fraction of its length is refused


@dataclass(frozen=True)
class SupportElements:
    """The engine's support arrays (`blocks`, `support`: `layout`'s support columns) and what each row
    is: its tendon's name, its crossing (0 for an anchor), its spacing [m] (per-metre forces times it
    are forces per bolt), its point at the start (an anchor's head, a crossing's point) [m], and its
    tendon's head and end at the start, (n, 2, 2) [m]."""

    names: list[str]
    crossing: np.ndarray
    spacing: np.ndarray
    blocks: np.ndarray
    support: np.ndarray
    points: np.ndarray
    ends: np.ndarray

    @classmethod
    def none(cls) -> SupportElements:
        return cls(
            [],
            np.zeros(0, np.int64),
            np.zeros(0),
            np.zeros((0, 2), np.int64),
            np.zeros((0, L.SUPPORT_COLUMNS)),
            np.zeros((0, 2)),
            np.zeros((0, 2, 2)),
        )

    def _row_sums(self, blocks: np.ndarray, held: np.ndarray, rotation: bool) -> np.ndarray:
        """Per block, an upper bound of the squared natural frequency of the blocks on their support
        springs alone [1/s^2] (Gershgorin's row sums): the sum over the elements on the block of
        k (1/m_a + 1/m_b) and, with `rotation`, + k (r_a^2/I_a + r_b^2/I_b), with k the axial plus
        shear stiffness, r the element's arm from each centroid, and the terms of a held block left
        out (it does not move)."""
        k = self.support[:, L.K_AXIAL] + self.support[:, L.K_SHEAR]
        per_element = np.zeros(len(k))
        for side, columns in ((0, [L.AX, L.AY]), (1, [L.BX, L.BY])):
            b = self.blocks[:, side]
            free = ~held[b]
            term = 1.0 / blocks[b, L.MASS]
            if rotation:
                term = term + np.hypot(*self.support[:, columns].T) ** 2 / blocks[b, L.INERTIA]
            per_element += np.where(free, term, 0.0)
        sums = np.zeros(len(blocks))
        for side in (0, 1):
            np.add.at(sums, self.blocks[:, side], k * per_element)
        sums[held] = 0.0
        return sums

    def critical_time_step(self, blocks: np.ndarray, held: np.ndarray) -> float:
        """A lower bound of the critical step of the blocks on their support springs alone [s]:
        2 / sqrt(the largest row sum of `_row_sums`, translation and rotation; inf without support).
        Contacts and support act on the same blocks; the engine takes the smaller of this and the
        contacts' own critical step, which can overrate the combined one by up to sqrt 2 where the two
        are alike (the default safety factor 0.5 covers it; support is far softer than contacts in
        practice)."""
        largest = float(self._row_sums(blocks, held, rotation=True).max(initial=0.0))
        return 2.0 / np.sqrt(largest) if largest > 0 else np.inf

    def longest_period(self, blocks: np.ndarray, held: np.ndarray) -> float:
        """The longest period of a free block translating on its support springs [s]: 2 pi / sqrt of
        the least non-zero translational row sum (0 without support). A soft support takes about this
        long to pick up its load: a strength-reduction trial's budget allows for it. (Rotation is left
        out: the contacts that a block rests on hold its rotation, so an element near its centroid
        would give a period no trial needs.)"""
        sums = self._row_sums(blocks, held, rotation=False)
        loaded = sums[sums > 0]
        return float(2.0 * np.pi / np.sqrt(loaded.min())) if len(loaded) else 0.0


def _stretch(shape: np.ndarray, head: np.ndarray, end: np.ndarray) -> tuple[float, float, np.ndarray]:
    """(t_in, t_out, tangent of the exit edge) of the segment head + t (end - head), 0 <= t <= 1,
    inside a convex counter-clockwise polygon (Cyrus-Beck); t_in > t_out where it misses. ValueError
    where the segment runs along one of the polygon's edges."""
    direction = end - head
    edges = np.roll(shape, -1, axis=0) - shape
    outward = np.column_stack([edges[:, 1], -edges[:, 0]])
    tolerance = INSIDE * float(np.max(np.hypot(*edges.T))) * float(np.hypot(*direction))
    t_in, t_out, exit_edge, along_edge = 0.0, 1.0, _unit(direction), False
    for k in range(len(shape)):
        rate = float(outward[k] @ direction)
        gap = float(outward[k] @ (head - shape[k]))  # > 0: the head is outside edge k
        if abs(rate) <= tolerance:
            if gap > tolerance:
                return 1.0, 0.0, exit_edge
            along_edge = along_edge or gap > -tolerance
            continue
        t = -gap / rate
        if rate < 0:
            t_in = max(t_in, t)
        elif t < t_out:
            t_out, exit_edge = t, _unit(edges[k])
    if along_edge and t_out - t_in > INSIDE:
        raise ValueError("the bolt runs along a joint (in line with a block's edge), crossing none")
    return t_in, t_out, exit_edge


def _path(
    shapes: list[np.ndarray], head: np.ndarray, end: np.ndarray
) -> list[tuple[int, float, float, np.ndarray]]:
    """The blocks the bolt passes through, in order from its head: (block, t_in, t_out, the tangent
    of the edge where it leaves the block)."""
    low, high = np.minimum(head, end), np.maximum(head, end)
    found = []
    for b, shape in enumerate(shapes):
        if np.any(shape.max(axis=0) < low) or np.any(shape.min(axis=0) > high):
            continue
        t_in, t_out, tangent = _stretch(shape, head, end)
        if t_out - t_in > INSIDE:
            found.append((b, t_in, t_out, tangent))
    return sorted(found, key=lambda item: item[1])


def _holding(on_path: list, t: float) -> tuple[int, float, float, np.ndarray] | None:
    """The stretch that holds the bolt's point at t (0: its head, 1: its end), or None."""
    for item in on_path:
        if item[1] - INSIDE <= t <= item[2] + INSIDE:
            return item
    return None


def _unit(vector: np.ndarray) -> np.ndarray:
    return vector / float(np.hypot(*vector))


def support_elements(
    tendons: list[Anchor | GroutedBolt],
    shapes: list[np.ndarray],
    centroids: np.ndarray,
    immobile: np.ndarray,
    block_names: list[str],
    path: Path,
) -> SupportElements:
    """The elements of every tendon (module docstring); shapes are the blocks' world vertices at the
    start [m], counter-clockwise, `block_names` their names; faults name the key `support.<k>.<field>`."""
    if not tendons:
        return SupportElements.none()
    extent = float(np.hypot(*np.ptp(np.concatenate(shapes), axis=0)))
    names, crossing, spacing, pairs, rows, points, ends = [], [], [], [], [], [], []
    seen = set()
    for k, tendon in enumerate(tendons):
        key = f"support.{k}"
        if tendon.name in seen:
            raise scene_error(path, f"{key}.name", f"two support elements are named '{tendon.name}'")
        seen.add(tendon.name)
        if tendon.length_m > extent:
            raise scene_error(
                path,
                f"{key}.end_m",
                f"the bolt is {tendon.length_m:.4g} m long, longer than the model ({extent:.4g} m across)",
            )
        head, end = np.array(tendon.head_m, dtype=float), np.array(tendon.end_m, dtype=float)
        try:
            on_path = _path(shapes, head, end)
        except ValueError as error:
            raise scene_error(path, f"{key}.end_m", str(error)) from None
        for which, t, point in (("head_m", 0.0, head), ("end_m", 1.0, end)):
            if _holding(on_path, t) is None:
                raise scene_error(path, f"{key}.{which}", f"the point {point.tolist()} lies in no block")
        made = (
            [_anchor_row(tendon, on_path, head, end, centroids, immobile, path, key)]
            if isinstance(tendon, Anchor)
            else _crossing_rows(tendon, on_path, head, end, centroids, immobile, block_names, path, key)
        )
        for n, (pair, row, point) in enumerate(made):
            names.append(tendon.name)
            crossing.append(n)
            spacing.append(tendon.spacing_m)
            pairs.append(pair)
            rows.append(row)
            points.append(point)
            ends.append([head, end])
    return SupportElements(
        names,
        np.array(crossing, dtype=np.int64),
        np.array(spacing),
        np.array(pairs, dtype=np.int64).reshape(-1, 2),
        np.array(rows).reshape(-1, L.SUPPORT_COLUMNS),
        np.array(points).reshape(-1, 2),
        np.array(ends).reshape(-1, 2, 2),
    )


def anchor_capacity_kN(anchor: Anchor) -> float:
    """The anchor's capacity per bolt [kN]: the weakest of its steel, plate and bond (`capacity`)."""
    bond = anchor.bond_strength_kN_per_m
    return float(
        anchor_capacity(anchor.steel_capacity_kN, anchor.plate_capacity_kN, bond, anchor.bond_length_m or 0.0)
    )


def _anchor_row(
    anchor: Anchor,
    on_path: list,
    head: np.ndarray,
    end: np.ndarray,
    centroids: np.ndarray,
    immobile: np.ndarray,
    path: Path,
    key: str,
) -> tuple[tuple[int, int], np.ndarray, np.ndarray]:
    """One anchor: its head's block A to its end's block B; the joint it crosses is where it leaves A."""
    a, _, _, plane = _holding(on_path, 0.0)
    b = _holding(on_path, 1.0)[0]
    if a == b:
        raise scene_error(
            path, f"{key}.end_m", "the anchor's head and end lie in one block: it holds nothing"
        )
    if immobile[a] and immobile[b]:
        raise scene_error(path, f"{key}.end_m", "the anchor joins two blocks held still: it holds nothing")
    length = anchor.length_m
    if (anchor.bond_length_m or 0.0) > length:
        raise scene_error(
            path,
            f"{key}.bond_length_m",
            f"{anchor.bond_length_m:g} m is longer than the anchor ({length:.4g} m)",
        )
    capacity = anchor_capacity_kN(anchor) * 1e3
    if anchor.pretension_kN * 1e3 > capacity:
        raise scene_error(
            path,
            f"{key}.pretension_kN",
            f"{anchor.pretension_kN:g} kN is above the anchor's capacity "
            f"({capacity / 1e3:.4g} kN, the weakest of steel, plate and bond)",
        )
    row = np.zeros(L.SUPPORT_COLUMNS)
    row[L.KIND] = L.ANCHOR
    row[[L.AX, L.AY]] = head - centroids[a]
    row[[L.BX, L.BY]] = end - centroids[b]
    row[[L.DIR_X, L.DIR_Y]] = _unit(end - head)
    row[[L.PLANE_X, L.PLANE_Y]] = plane
    row[L.K_AXIAL] = anchor.steel_modulus_GPa * 1e9 * anchor.area_m2 / length / anchor.spacing_m
    row[L.PRETENSION] = anchor.pretension_kN * 1e3 / anchor.spacing_m
    row[L.CAP_AXIAL] = capacity / anchor.spacing_m
    row[L.FREE_LENGTH] = length
    row[L.RUPTURE] = anchor.rupture_strain
    row[L.AXIAL] = row[L.PRETENSION]
    return (a, b), row, head


def _crossing_rows(
    bolt: GroutedBolt,
    on_path: list,
    head: np.ndarray,
    end: np.ndarray,
    centroids: np.ndarray,
    immobile: np.ndarray,
    block_names: list[str],
    path: Path,
    key: str,
) -> list[tuple[tuple[int, int], np.ndarray, np.ndarray]]:
    """One element per joint the bolt crosses: between consecutive blocks on its path, at the middle
    of the two stretches' ends (they meet on a closed joint; a wider opening between them than
    `OPEN_GAP` of the bolt's length is refused: a grouted bolt is not held across open space)."""
    for (a, _, t_out, _), (b, t_in, _, _) in itertools.pairwise(on_path):
        if t_in - t_out > OPEN_GAP:
            raise scene_error(
                path,
                f"{key}.end_m",
                f"the bolt crosses an opening {(t_in - t_out) * bolt.length_m:.3g} m wide between blocks "
                f"'{block_names[a]}' and '{block_names[b]}': a grouted bolt is not held across open space",
            )
    length, axis = bolt.length_m, _unit(end - head)
    debonded = bolt.debonded_length_m or DEBONDED_DIAMETERS * bolt.diameter_m
    stiffness = bolt.steel_modulus_GPa * 1e9 * bolt.area_m2 / debonded / bolt.spacing_m
    made = []
    for (a, _, t_out, plane), (b, t_in, _, _) in itertools.pairwise(on_path):
        t = 0.5 * (t_out + t_in)
        if immobile[a] and immobile[b]:
            continue
        point = head + t * (end - head)
        capacity = grouted_bolt_capacity(
            bolt.steel_capacity_kN * 1e3,
            bolt.bond_strength_kN_per_m * 1e3,
            t * length,
            (1.0 - t) * length,
            None if bolt.plate_capacity_kN is None else bolt.plate_capacity_kN * 1e3,
        )
        row = np.zeros(L.SUPPORT_COLUMNS)
        row[L.KIND] = L.GROUTED
        row[[L.AX, L.AY]] = point - centroids[a]
        row[[L.BX, L.BY]] = point - centroids[b]
        row[[L.DIR_X, L.DIR_Y]] = axis
        row[[L.PLANE_X, L.PLANE_Y]] = plane
        row[L.K_AXIAL] = stiffness
        row[L.K_SHEAR] = (
            stiffness
            if bolt.shear_stiffness_MN_per_m is None
            else bolt.shear_stiffness_MN_per_m * 1e6 / bolt.spacing_m
        )
        row[L.CAP_AXIAL] = float(capacity) / bolt.spacing_m
        row[L.CAP_SHEAR] = (
            0.0 if bolt.shear_capacity_kN is None else bolt.shear_capacity_kN * 1e3 / bolt.spacing_m
        )
        row[L.FREE_LENGTH] = debonded
        row[L.RUPTURE] = bolt.rupture_strain
        made.append(((a, b), row, point))
    if len(on_path) < 2:
        raise scene_error(path, f"{key}.end_m", "the grouted bolt crosses no joint (it lies in one block)")
    if not made:
        raise scene_error(path, f"{key}.end_m", "every joint the bolt crosses lies between blocks held still")
    return made
