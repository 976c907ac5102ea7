"""The kinematic tallies of many faces at once: every face dip direction around the compass at a
step (a pit wall's sectors), and every face dip for a chosen wall (the face-angle sweep).

Each face is classified by the very criteria of a single face (criteria.py, through the modes of
modes.py): `Face.many` gives the face fields the shape (F, 1), every test broadcasts to (F, N), and
the weighted critical counts of each group are the product of the (F, N) masks with the (N, G)
matrix of the items' weights per group. Faces are taken in blocks so that F x N stays near
`BLOCK_ELEMENTS`; the pairs of readings come chunk by chunk from the same `PairPlan` as the
single face's tallies, so the sweep at a face and the tally of that face are one computation.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from bbmc.kinematics.face import Face, KinematicLimits
from bbmc.kinematics.intersections import PairPlan, pair_plan
from bbmc.kinematics.modes import LINE_MODES, POLE_MODES, line_modes, pole_modes
from bbmc.kinematics.tallies import pair_groups, percentage, reading_groups, reading_pairs

BLOCK_ELEMENTS = 1 << 22

ModesOf = Callable[[np.ndarray, Face], dict[str, np.ndarray]]  # the critical masks of items at faces


@dataclass(frozen=True)
class FaceSweep:
    """Critical weight per face and group of every mode: `critical[mode]` (F, G) with the groups of
    its kind (`groups[kind]`, "all" last), the groups' weights (sum w, sum w^2), and the pair rule.
    Faces: `dip`, `dip_direction` (F,) [rad]."""

    dip: np.ndarray
    dip_direction: np.ndarray
    groups: dict[str, tuple[str, ...]]
    critical: dict[str, np.ndarray]
    weight: dict[str, np.ndarray]
    weight_sq: dict[str, np.ndarray]
    plan: PairPlan

    def percent(self, mode: str, group: str = "all") -> tuple[np.ndarray, np.ndarray]:
        """The percentage critical (F,) of `mode` in `group` at each face, and its standard error."""
        kind = "poles" if mode in POLE_MODES else "pairs"
        g = self.groups[kind].index(group)
        sampled = kind == "pairs" and not self.plan.exact
        return percentage(self.critical[mode][:, g], self.weight[kind][g], self.weight_sq[kind][g], sampled)

    def rows(self) -> list[dict[str, object]]:
        """The sweep as a long table: one row per face, mode and group, angles in degrees."""
        out = []
        for mode in POLE_MODES + LINE_MODES:
            kind = "poles" if mode in POLE_MODES else "pairs"
            for g, group in enumerate(self.groups[kind]):
                if not group or self.weight[kind][g] <= 0:
                    continue
                percent, error = self.percent(mode, group)
                for f in range(self.dip.size):
                    out.append(
                        {
                            "face_dip_deg": round(float(np.degrees(self.dip[f])), 9),
                            "face_dip_direction_deg": round(float(np.degrees(self.dip_direction[f])), 9),
                            "mode": mode,
                            "group": group,
                            "percent": float(percent[f]),
                            "standard_error_percent": float(error[f]),
                        }
                    )
        return out


def _group_matrix(code: np.ndarray, weight: np.ndarray, size: int) -> np.ndarray:
    """(N, size + 1): each item's weight in its group's column and in the last column ("all")."""
    matrix = np.zeros((code.size, size + 1))
    matrix[np.arange(code.size), code] = weight
    matrix[:, size] = weight
    return matrix


def _add_blocks(
    sums: dict[str, np.ndarray], faces: Face, items: np.ndarray, matrix: np.ndarray, modes_of: ModesOf
) -> None:
    """Add to `sums[mode]` (F, G) the weighted critical counts of `items`, faces block by block."""
    dips, directions = faces.dip.ravel(), faces.dip_direction.ravel()
    block = max(1, BLOCK_ELEMENTS // max(1, len(items)))
    for start in range(0, dips.size, block):
        stop = min(start + block, dips.size)
        masks = modes_of(items, Face(dips[start:stop, None], directions[start:stop, None]))
        for mode, mask in masks.items():
            sums[mode][start:stop] += np.broadcast_to(mask, (stop - start, len(items))).astype(float) @ matrix


def sweep_faces(
    poles: np.ndarray,
    faces: Face,
    friction: float | np.ndarray,
    limits: KinematicLimits | None = None,
    sets: np.ndarray | None = None,
    weights: np.ndarray | None = None,
    set_names: Sequence[str] | None = None,
    plan: PairPlan | None = None,
) -> FaceSweep:
    """Every mode's critical weight for each of `faces` (built with `Face.many`), readings and pairs
    as `tallies.kinematic_tally`."""
    limits = KinematicLimits() if limits is None else limits
    poles = np.asarray(poles, dtype=float)
    plan = pair_plan(len(poles)) if plan is None else plan
    weights = np.ones(len(poles)) if weights is None else np.asarray(weights, dtype=float)
    friction = np.broadcast_to(np.asarray(friction, dtype=float), (len(poles),))
    code, names = reading_groups(sets, len(poles), set_names)
    _, pair_names = pair_groups(code[:0], code[:0], names)
    count = faces.dip.size
    critical = {m: np.zeros((count, len(names) + 1)) for m in POLE_MODES}
    critical |= {m: np.zeros((count, len(names) ** 2 + 1)) for m in LINE_MODES}
    pole_matrix = _group_matrix(code, weights, len(names))
    _add_blocks(critical, faces, poles, pole_matrix, partial(pole_modes, friction=friction, limits=limits))
    pair_weight, pair_weight_sq = np.zeros(len(names) ** 2 + 1), np.zeros(len(names) ** 2 + 1)
    for chunk in reading_pairs(poles, plan, code, names, weights, friction):
        matrix = _group_matrix(chunk.code, chunk.weight, len(names) ** 2)
        pair_weight += matrix.sum(axis=0)
        pair_weight_sq += (matrix**2).sum(axis=0)
        modes_of = partial(line_modes, friction=chunk.friction, limits=limits)
        _add_blocks(critical, faces, chunk.lines, matrix, modes_of)
    pole_groups = (*names.values(), "all")
    pair_group_names = (*(pair_names.get(g, "") for g in range(len(names) ** 2)), "all")
    return FaceSweep(
        dip=faces.dip.ravel(),
        dip_direction=faces.dip_direction.ravel(),
        groups={"poles": pole_groups, "pairs": pair_group_names},
        critical=critical,
        weight={"poles": pole_matrix.sum(axis=0), "pairs": pair_weight},
        weight_sq={"poles": (pole_matrix**2).sum(axis=0), "pairs": pair_weight_sq},
        plan=plan,
    )


def compass_sweep(
    poles: np.ndarray,
    face_dip: float,
    friction: float | np.ndarray,
    step: float = np.radians(1.0),
    **options: Any,
) -> FaceSweep:
    """The tallies for faces of dip `face_dip` [rad] dipping towards every direction 0, step, ...
    below 2 pi [rad] (default 1 deg: 360 faces). `options` as `sweep_faces`."""
    directions = np.arange(0.0, 2.0 * np.pi - 1e-12, step)
    return sweep_faces(poles, Face.many(np.full(directions.size, face_dip), directions), friction, **options)


def face_angle_sweep(
    poles: np.ndarray,
    face_dip_direction: float,
    dips: np.ndarray,
    friction: float | np.ndarray,
    **options: Any,
) -> FaceSweep:
    """The tallies for a wall of dip direction `face_dip_direction` [rad] at each face dip of `dips`
    [rad]. `options` as `sweep_faces`."""
    dips = np.asarray(dips, dtype=float)
    return sweep_faces(poles, Face.many(dips, np.full(dips.size, face_dip_direction)), friction, **options)
