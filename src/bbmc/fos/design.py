"""The support that reaches a target factor of safety: a scene's `design:` section (`bbmc fos`).

One support element's steel capacity (the smallest that reaches the target) or its out-of-plane
spacing (the largest) is searched in its range, in two stages:

1. Limit equilibrium, where the scene allows it: one block free to move, resting on blocks held still
   along one straight plane (`planar_limit_equilibrium`). Its loads (gravity, seismic, water, block
   loads) are the engine's own at step 0, its plane's length, cohesion and friction those of the
   contacts found at step 0, and the support's force its capacity per metre along its axis, in
   RocPlane's active form: FS = (c A + (N + T_n) tan phi) / (D - T_s). FS grows with the capacity and
   falls with the spacing, so the target is found by bisection (to 1e-4 of the value).
2. The engine: strength reduction (`bbmc.fos.strength_reduction`) at the limit-equilibrium value, then,
   while it falls short of the target, at values stepped towards the safe end of the range by
   bisection between the last short and the safe end, to `tolerance` of the value. Without a
   limit-equilibrium stage the engine bisects the whole range.

The engine's FS is found to `fos.tolerance` (the bisection's bracket) and is not monotone in the
support to better than its scatter (a rock mass's blocks take other paths at another support force),
so the design is the value nearest the unsafe end whose engine FS reached the target and beyond which
every value tried reached it too (`confirmed_value`): confirmed by the engine, never inferred. The
largest drop of FS towards the safe end between two trials is reported (`fs_scatter`), and so is an
answer at an end of the range, or why there is none (the block that fails first at the safe end, and
whether the support holds it). One `design.support` may name several elements: one value for all.

Every trial is a row of the design table: stage, value, FS, seconds.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc.dem import layout as L
from bbmc.dem.model import Model, build_model
from bbmc.dem.motion import apply_loads
from bbmc.dem.solver import initial_state, prepare
from bbmc.dem.support_elements import anchor_capacity_kN
from bbmc.dem.water import add_water_loads
from bbmc.fos.strength_reduction import StrengthReductionResult, factor_of_safety
from bbmc.progress import Progress, ProgressCallback, ignore
from bbmc.support.config import Anchor, Design, Tendon

PARALLEL = math.radians(1.0)  # contacts of one plane: their edges within this angle of each other
LIMIT_EQUILIBRIUM_TOLERANCE = 1e-4  # of the value: limit equilibrium is cheap, the engine is not
LOADED_STEP = 1e18  # a step after every ramp: the loads in full


@dataclass(frozen=True)
class PlanarLimitEquilibrium:
    """A free block on one plane: c A [N/m], N [N/m] onto the plane, D [N/m] down it, tan phi, the
    down-plane unit vector and the unit normal into the plane, and the block's index."""

    cohesion_force: float
    normal: float
    driving: float
    tan_phi: float
    down: np.ndarray
    into: np.ndarray
    block: int

    def factor_of_safety(self, support_force: np.ndarray, form: str = "active") -> float:
        """FS with a support force vector on the block [N/m], in RocPlane's `form`: active,
        (c A + (N + T_n) tan phi) / (D - T_s) (inf where nothing drives), or passive,
        (c A + (N + T_n) tan phi + T_s) / D."""
        along = -float(support_force @ self.down)
        onto = float(support_force @ self.into)
        held = self.cohesion_force + max(self.normal + onto, 0.0) * self.tan_phi
        if form == "passive":
            return (held + along) / self.driving
        driving = self.driving - along
        return held / driving if driving > 0 else math.inf


def _loads(model: Model) -> np.ndarray:
    """The engine's loads on every block at step 0 with every ramp done: (n, 3) [N/m, N/m, N m/m]."""
    state = initial_state(model)
    blocks = state.blocks
    apply_loads(
        blocks,
        state.world,
        model.vertex_next,
        model.vertex_block,
        model.gravity,
        model.block_loads,
        model.load_block,
        model.edge_loads,
        model.load_edge,
        LOADED_STEP,
    )
    everyone = np.ones(len(blocks), dtype=bool)
    add_water_loads(
        blocks,
        state.world,
        model.vertex_start,
        model.vertex_next,
        everyone,
        model.water_surface,
        model.water_unit_weight,
        state.dry_edges,
    )
    return blocks[:, [L.FX, L.FY, L.FM]].copy()


def planar_limit_equilibrium(model: Model) -> PlanarLimitEquilibrium | str:
    """The scene as a planar limit-equilibrium problem (module docstring), or why it is not one."""
    free = np.flatnonzero(~model.immobile)
    if len(free) != 1:
        return f"{len(free)} blocks are free to move (limit equilibrium here takes one)"
    block = int(free[0])
    state = prepare(model)
    touching = (state.contacts[:, L.BLOCK_A] == block) | (state.contacts[:, L.BLOCK_B] == block)
    subs = state.subs.reshape(len(state.contacts), state.n_sub, L.SUB_COLUMNS)[touching]
    lengths = subs[:, :, L.LENGTH]
    if not np.any(lengths > 0):
        return "the free block touches nothing at step 0"
    contacts = state.contacts[touching]
    own = np.where(contacts[:, L.BLOCK_A] == block, contacts[:, L.EDGE_A], contacts[:, L.EDGE_B])
    carrying = lengths.sum(axis=1) > 0
    tangents = state.world[model.vertex_next[own[carrying]]] - state.world[own[carrying]]
    angles = np.arctan2(tangents[:, 1], tangents[:, 0])
    if np.ptp(np.angle(np.exp(1j * (angles - angles[0])))) > PARALLEL:
        return "the free block rests on more than one plane"
    tangent = tangents[0] / np.hypot(*tangents[0])
    outward = np.array([tangent[1], -tangent[0]])
    load = _loads(model)[block, :2]
    along = float(load @ tangent)
    down = tangent if along >= 0 else -tangent
    area = float(lengths.sum())
    weights = lengths.ravel() / area
    return PlanarLimitEquilibrium(
        cohesion_force=float(weights @ subs[:, :, L.COH].ravel()) * area,
        normal=float(load @ outward),
        driving=abs(along),
        tan_phi=float(weights @ subs[:, :, L.TANPHI].ravel()),
        down=down,
        into=outward,
        block=block,
    )


def support_force_on(model: Model, problem: PlanarLimitEquilibrium, names: list[str]) -> np.ndarray:
    """The force per metre [N/m] that the tendons `names` put on the free block as it slides down the
    plane, at their capacity: each of their elements on the block pulls along its axis u against the
    slide, -T sign(down . u) u, where the slide stretches it (a grouted crossing: always, in tension
    or compression; an anchor: when the block moves away from its other end, else it is slack)."""
    support = model.support
    force = np.zeros(2)
    for e, element in enumerate(support.names):
        a, b = support.blocks[e]
        if element not in names or problem.block not in (a, b):
            continue
        axis = support.support[e, [L.DIR_X, L.DIR_Y]]
        slide = float(problem.down @ axis)
        stretched = slide < 0 if a == problem.block else slide > 0
        if support.support[e, L.KIND] == L.ANCHOR and not stretched:
            continue
        force -= np.sign(slide) * support.support[e, L.CAP_AXIAL] * axis
    return force


def varied_model(model: Model, design: Design, value: float, path: Path) -> Model:
    """The model with the design element's capacity or spacing set to `value` (an anchor's
    pretension kept at the same fraction of its steel capacity, and at most its capacity)."""

    def changed(tendon: Tendon) -> Tendon:
        if design.vary == "spacing":
            return tendon.model_copy(update={"spacing_m": value})
        update = {"steel_capacity_kN": value}
        if isinstance(tendon, Anchor):
            varied = tendon.model_copy(update=update)
            update["pretension_kN"] = min(
                tendon.pretension_kN * value / tendon.steel_capacity_kN, anchor_capacity_kN(varied)
            )
        return tendon.model_copy(update=update)

    support = [changed(t) if t.name in design.elements else t for t in model.scene.support]
    scene = model.scene.model_copy(update={"support": support, "design": None})
    return dataclasses.replace(build_model(scene, path), economy=model.economy)


@dataclass
class DesignResult:
    value: float | None  # the design's capacity [kN] or spacing [m]; None: the range does not reach it
    trials: pd.DataFrame  # stage, value, factor_of_safety, seconds
    limit_equilibrium_note: str  # why the scene has no limit-equilibrium stage ("" when it has one)
    seconds: float
    note: str = ""  # the answer at an end of its range, or why there is none
    scatter: float = 0.0  # the largest drop of the engine's FS towards the safe end between trials


def _safer(design: Design, a: float, b: float) -> bool:
    """Whether value a is on the safe side of value b (a larger capacity, a smaller spacing)."""
    return a > b if design.vary == "capacity" else a < b


def confirmed_value(design: Design, engine: pd.DataFrame) -> float | None:
    """The value nearest the unsafe end whose engine FS reached the target and beyond which, towards
    the safe end, every value tried reached it too: the engine's FS is not monotone in the support
    to better than its scatter, so a value that passed once beside a safer one that failed is no
    design."""
    passed = engine[engine.factor_of_safety >= design.target_fs].value
    failed = engine[engine.factor_of_safety < design.target_fs].value
    good = [v for v in passed if not any(_safer(design, f, v) for f in failed)]
    if not good:
        return None
    return min(good) if design.vary == "capacity" else max(good)


def fs_scatter(design: Design, engine: pd.DataFrame) -> float:
    """The largest drop of the engine's FS from one value tried to a safer one [1] (0: monotone)."""
    rows = list(zip(engine.value, engine.factor_of_safety, strict=True))
    drops = [fa - fb for va, fa in rows for vb, fb in rows if _safer(design, vb, va)]
    return max([0.0, *drops])


def _search(
    passes: Callable[[float], bool], unsafe_end: float, safe_end: float, tolerance: float
) -> float | None:
    """The value nearest `unsafe_end` that passes, to `tolerance` of it, by bisection: `unsafe_end`
    itself if it passes, None if `safe_end` does not (each end tried once)."""
    if passes(unsafe_end):
        return unsafe_end
    if unsafe_end == safe_end or not passes(safe_end):
        return None
    short, ok = unsafe_end, safe_end
    while abs(ok - short) > tolerance * abs(ok):
        middle = 0.5 * (short + ok)
        short, ok = (short, middle) if passes(middle) else (middle, ok)
    return ok


def design_support(model: Model, path: Path, progress: ProgressCallback = ignore) -> DesignResult:
    """The design of the scene's `design:` section (module docstring); `progress` gets a
    `bbmc.progress.Progress` in trials (limit equilibrium's and the engine's) after each."""
    design = model.scene.design
    started = time.perf_counter()
    low, high = design.range
    unsafe_end, safe_end = (low, high) if design.vary == "capacity" else (high, low)
    rows: list[tuple[str, float, float, float]] = []

    def trial(stage: str, value: float, fs_of: Callable[[Model], float]) -> float:
        begun = time.perf_counter()
        fs = fs_of(varied_model(model, design, value, path))
        rows.append((stage, value, fs, time.perf_counter() - begun))
        text = f"design: {stage.replace('_', ' ')}, {design.vary} {value:.4g}: FS {fs:.3f}"
        progress(Progress(len(rows), None, "trials", text))
        return fs

    problem = planar_limit_equilibrium(model)
    note = problem if isinstance(problem, str) else ""
    start = unsafe_end
    if note:
        text = f"design: no limit-equilibrium stage ({note}): the engine alone searches"
        progress(Progress(0, None, "trials", text))
    else:
        le = _search(
            lambda v: (
                trial(
                    "limit_equilibrium",
                    v,
                    lambda m: problem.factor_of_safety(
                        support_force_on(m, problem, design.elements), model.scene.fos.support_form
                    ),
                )
                >= design.target_fs
            ),
            unsafe_end,
            safe_end,
            LIMIT_EQUILIBRIUM_TOLERANCE,
        )
        start = safe_end if le is None else le
    results: dict[float, StrengthReductionResult] = {}

    def engine_fs(m: Model, value: float) -> float:
        results[value] = factor_of_safety(m)
        return results[value].factor_of_safety

    _search(
        lambda v: trial("engine", v, lambda m: engine_fs(m, v)) >= design.target_fs,
        start,
        safe_end,
        design.tolerance,
    )
    trials = pd.DataFrame(rows, columns=["stage", "value", "factor_of_safety", "seconds"])
    engine = trials[trials.stage == "engine"]
    best = confirmed_value(design, engine)
    why = _why(model, design, best, engine, results, unsafe_end, safe_end)
    return DesignResult(best, trials, note, time.perf_counter() - started, why, fs_scatter(design, engine))


def _why(
    model: Model,
    design: Design,
    best: float | None,
    engine: pd.DataFrame,
    results: dict[float, StrengthReductionResult],
    unsafe_end: float,
    safe_end: float,
) -> str:
    """The answer at an end of its range, or why there is none: the block that fails first at the
    safe end, and whether the elements hold it."""
    if best == unsafe_end:
        return f"at the end of the range: {design.vary} {unsafe_end:g} already gives FS {design.target_fs:g}"
    if best is not None:
        return ""
    if safe_end not in results:
        return "the engine's FS is not monotone in the support here (design.csv): no value is confirmed"
    at_safe = results[safe_end]
    failing = at_safe.failing_trial
    fs = f"at {design.vary} {safe_end:g} the FS is {at_safe.factor_of_safety:.4g}"
    if failing is None or not failing.block:
        return fs
    held = {
        model.block_names[int(b)]
        for name, blocks in zip(model.support.names, model.support.blocks, strict=True)
        if name in design.elements
        for b in blocks
    }
    if failing.block in held:
        return f"{fs}; block '{failing.block}', which the support holds, still fails first"
    return (
        f"{fs}; the block that fails first, '{failing.block}', is not one the support holds "
        f"({', '.join(sorted(held))}): support it too, or judge the FS on the blocks that matter (fos.judge)"
    )
