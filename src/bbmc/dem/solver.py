"""The run loop around the kernels: contact search, time step, monitoring, fault detection.

The kernels run whole chunks of cycles; this module only acts between chunks: at record steps
(monitors, stop condition, interpenetration), after a block has moved far enough to need a new
contact search, and when a run goes wrong. Faults stop the run with a `SimulationError` whose message
is one line naming the step and the likely cause; nothing is written then. Each chunk runs in kernel
calls of about `pace.CALL_SECONDS` (`bbmc.dem.pace`), so that Ctrl-C stops a run at once, at any size.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc.config import load_config
from bbmc.dem import joint_state, kernels, motion, time_step
from bbmc.dem import layout as L
from bbmc.dem import monitors as mon
from bbmc.dem.bridges import BridgeLog
from bbmc.dem.contact_search import search_contacts
from bbmc.dem.detection import candidate_pairs, vertex_penetration
from bbmc.dem.model import Model, build_model
from bbmc.dem.state import State
from bbmc.dem.stopping import STOP_REASONS, Watch, far_from_balance, moved_beyond_stop, stop_reason, unsettled
from bbmc.dem.support_report import support_table
from bbmc.kernel_cache import announce_engine_compile
from bbmc.progress import Progress, ProgressCallback, ignore
from bbmc.scene.schema import Scene

TIME_STEP_MODES = {"auto": 0, "fixed": 1, "density_scaling": 2}
SLACK_SAFETY = 0.7  # a run with support warns above it: measured, an anchor that goes slack under a
# sudden load (two free blocks, undamped) peaks at 2.16 x its load at 0.7 and 5.5 x at 0.75
BOND_GAP = 1e-6  # of the smaller block's size: wider open at step 0, a share is not bonded
RUNAWAY_FRACTION = 0.1  # a block moving this fraction of its size in one step: the run is lost (an
# unstable time step grows without bound; a block this fast skips through contacts either way)


class SimulationError(Exception):
    """A run that cannot go on. `bad_input`: the scene itself is at fault (exit status 2)."""

    def __init__(self, message: str, bad_input: bool = False) -> None:
        super().__init__(message)
        self.bad_input = bad_input


@dataclass
class RunResult:
    """A scene's run (`simulate`, `bbmc.api.run`): the tables `bbmc run` writes, as DataFrames whose
    column names carry their units (every column in docs/scene-format.md#outputs).

    Attributes:
        history: history.csv: `step`, `time_s`, then one column `<name>_<unit>` per monitor of the
            scene, at step 0 and every record step.
        blocks: blocks.csv, every block at the end: `block`, `group`, `x0_m`, `y0_m` (its centroid at
            the start), `x_m`, `y_m`, `ux_mm`, `uy_mm`, `rotation_deg`, `vx_m_s`, `vy_m_s`.
        contacts: contacts.csv: every sub-contact at the end, its place, joint law, stresses [MPa],
            stiffnesses [MPa/mm], strength and displacements [mm] (inactive ones have length_m 0).
        summary: summary.csv: `quantity`, `value`, `unit` rows (steps, time, stop reason, time-step
            range, contact searches, interpenetration, warnings).
        warnings: the run's warnings, one line each (warnings.csv).
        bridges: bridges.csv: each rock bridge (a contact whose law breaks into a joint), where it is,
            how many of its shares broke and how, and by which record step (-1: not broken); no rows
            for a scene without bridges.
        support: support.csv: each support element at the end, its forces and capacities [kN per
            bolt] and its state; no rows for a scene without support.
        state: the engine's arrays at the end (`bbmc.dem.state.State`: SI units, the
            `bbmc.dem.layout` columns).
    """

    history: pd.DataFrame
    blocks: pd.DataFrame
    contacts: pd.DataFrame
    summary: pd.DataFrame
    warnings: list[str]
    bridges: pd.DataFrame
    support: pd.DataFrame
    state: State


def initial_state(model: Model) -> State:
    announce_engine_compile()
    n_sub = model.scene.contacts.sub_contacts_per_edge
    world = np.empty_like(model.local)
    blocks = model.blocks.copy()
    immobile = model.immobile
    motion.update_vertices(blocks, model.vertex_start, model.local, world, np.ones(len(blocks), dtype=bool))
    return State(
        clock=np.zeros(L.CLOCK_COLUMNS),
        blocks=blocks,
        dof=model.dof.copy(),
        world=world,
        contacts=np.zeros((0, L.CONTACT_COLUMNS), dtype=np.int64),
        subs=np.zeros((0, L.SUB_COLUMNS)),
        law_state=np.zeros((0, L.LAW_STATE_COLUMNS)),
        n_sub=n_sub,
        immobile=immobile,
        moving=~immobile if model.economy.skip_held_blocks else np.ones(len(blocks), dtype=bool),
        dry_edges=np.zeros(len(model.local), dtype=bool),
        support=model.support.support.copy(),
        largest_dt=largest_time_step(model),
        threads=kernels.thread_count(model.scene.solver.threads),
    )


def _set_time_step(model: Model, state: State) -> None:
    ts = model.scene.solver.time_step
    status = time_step.set_time_step(
        state.clock,
        *_stiffness(model, state),
        TIME_STEP_MODES[ts.mode],
        ts.safety_factor,
        state.largest_dt,
        model.scene.solver.damping,
    )
    if status == L.STEP_ABOVE_CRITICAL:
        _above_critical(model, state)
    if status == L.NO_BOUND and state.step == 0:
        raise SimulationError(
            "key 'solver.time_step.step_s': at step 0 nothing is in contact, so the automatic time step "
            "has no bound; give step_s as its upper limit",
            bad_input=True,
        )
    if status == L.NO_BOUND:
        now = _check_overlap(model, state, [])
        if now > 0.1:  # the search drops contacts deeper than a quarter of a block
            raise SimulationError(
                f"step {state.step}: every contact has been lost with blocks pushed through each other "
                f"(interpenetration {now:.3g} of a block's size); likely cause: joints too soft for the load"
            )
    _note_time_step(state)


def largest_time_step(model: Model) -> float:
    """The upper limit of the time step [s]: the scene's step_s (auto: its upper limit; fixed and
    density scaling: the step), and with support elements, safety x their own critical step
    (`SupportElements.critical_time_step`); a fixed step above that is refused. Computed once per
    state (`initial_state`), not per kernel call: a shear box's step is 0.3 µs."""
    ts = model.scene.solver.time_step
    if not len(model.support.names):
        return ts.step_s or math.inf
    support = model.support.critical_time_step(model.blocks, model.immobile)
    if ts.mode == "auto":
        return min(ts.step_s or math.inf, ts.safety_factor * support)
    if ts.step_s > support:
        raise SimulationError(
            f"key 'solver.time_step.step_s': the fixed time step {ts.step_s:.3g} s is above the critical "
            f"step of the blocks on their support springs ({support:.3g} s); lower it or use mode auto",
            bad_input=True,
        )
    return ts.step_s


def _note_time_step(state: State) -> None:
    """Keep the range of time steps used (law updates inside the kernel may change it)."""
    state.dt_range[0] = min(state.dt_range[0], state.clock[L.DT])
    state.dt_range[1] = max(state.dt_range[1], state.clock[L.DT])


def _stiffness(model: Model, state: State) -> tuple:
    """The arrays the kernels assemble the contact stiffness from (for the critical step)."""
    return (
        state.blocks,
        state.dof,
        state.world,
        model.vertex_next,
        state.contacts,
        state.subs,
        state.n_sub,
    )


def _critical(model: Model, state: State) -> float:
    """The critical step [s]: the contacts', or the support's where that is smaller."""
    return min(
        time_step.critical_time_step(*_stiffness(model, state), model.scene.solver.damping),
        model.support.critical_time_step(model.blocks, state.immobile),
    )


def _above_critical(model: Model, state: State) -> None:
    step_s, critical = model.scene.solver.time_step.step_s, _critical(model, state)
    if state.step == 0:
        raise SimulationError(
            f"key 'solver.time_step.step_s': the fixed time step {step_s:.3g} s is above this scene's "
            f"critical step {critical:.3g} s; lower it or use mode auto",
            bad_input=True,
        )
    raise SimulationError(
        f"step {state.step}: the fixed time step {step_s:.3g} s is now above the critical step "
        f"{critical:.3g} s (the joint stiffness grew); lower step_s or use time_step mode auto"
    )


def _has_loads(model: Model) -> bool:
    """Whether the scene has loads that `ramp_steps` ramps (gravity and water are not ramped)."""
    loads = model.scene.loads
    return bool(loads.edge_stresses or loads.block_forces)


def _check_health(model: Model, state: State) -> None:
    """Stop a run that has gone unstable: non-finite state, or a block running away in one step."""
    b, dt = state.blocks, state.clock[L.DT]
    if motion.first_runaway(b, dt, RUNAWAY_FRACTION) < 0:
        return
    finite = np.all(np.isfinite(b[:, [L.X, L.Y, L.TH, L.VX, L.VY, L.W]]), axis=1)
    travel = (np.hypot(b[:, L.VX], b[:, L.VY]) + np.abs(b[:, L.W]) * b[:, L.RADIUS]) * dt / b[:, L.SIZE]
    bad = ~finite | (travel > RUNAWAY_FRACTION)
    if not bad.any():
        return
    i = int(np.argmax(bad))
    what = (
        "a non-finite position or velocity"
        if not finite[i]
        else (f"moved {travel[i]:.2g} of its size in one step")
    )
    try:
        critical = _critical(model, state) if np.all(finite) else math.nan
    except ZeroDivisionError:  # a block thrown so far that its vertices merge in floating point
        critical = math.nan
    if math.isnan(critical):
        cause = (
            f"time step {dt:.3g} s above the critical step, or a load too large for the joints (the state "
            "left floating point before the critical step could be judged)"
        )
    elif not dt <= critical:
        cause = (
            f"time step {dt:.3g} s above the critical step ({critical:.3g} s now), e.g. a fixed step or a "
            f"joint stiffness that grew faster than the update interval "
            f"({model.scene.solver.update_interval_steps} steps)"
        )
    else:
        ramp = ", or ramp the loads up (their ramp_steps)" if _has_loads(model) else ""
        cause = (
            f"a load too large for the joints (time step {dt:.3g} s is below the critical {critical:.3g} s): "
            f"stiffer joints, or a smaller solver.time_step.safety_factor{ramp}"
        )
    raise SimulationError(
        f"step {state.step}: block '{model.block_names[i]}' has {what}: the run went unstable; "
        f"likely cause: {cause}"
    )


def _check_overlap(model: Model, state: State, warnings: list[str]) -> float:
    """The deepest interpenetration of any two blocks now (a vertex of one inside the other), as a
    fraction of the smaller block's size; kept as the largest seen, and warned of once when it passes
    the scene's limit."""
    pairs = candidate_pairs(state.world, model.vertex_start, state.immobile, 0.0)
    if not len(pairs):
        return 0.0
    depth = vertex_penetration(pairs, state.world, model.vertex_start, model.vertex_next)
    size = state.blocks[:, L.SIZE]
    relative = depth / np.minimum(size[pairs[:, 0]], size[pairs[:, 1]])
    k = int(np.argmax(relative))
    state.largest_overlap = max(state.largest_overlap, float(relative[k]))
    limit = model.scene.contacts.interpenetration_limit
    if relative[k] > limit and not any("interpenetrate" in w for w in warnings):
        a, b = pairs[k]
        warnings.append(
            f"step {state.step}: blocks '{model.block_names[a]}' and '{model.block_names[b]}' "
            f"interpenetrate by {100 * relative[k]:.3g} % of the smaller block's size (limit "
            f"{100 * limit:.3g} %): joints too soft for the load, or a block that moved through another "
            "between two contact searches"
        )
    return float(relative[k])


def prepare(model: Model) -> State:
    """The state at step 0: contacts found, joint laws evaluated, time step set."""
    state = initial_state(model)
    search_contacts(model, state)
    _bonds_only_where_touching(state)
    if model.variable_laws:
        joint_state.update_joint_laws(
            state.contacts,
            state.subs,
            state.law_state,
            state.n_sub,
            model.laws,
            model.params,
            model.economy.changed_laws_only,
        )
    _set_time_step(model, state)
    return state


def _bonds_only_where_touching(state: State) -> None:
    """A bond of the initial assembly (a share with a tensile strength: intact rock, a cemented joint)
    holds only where its two blocks touch: a share whose middle is open by more than BOND_GAP x the
    smaller block's size at step 0 (a corner within the search margin of a face, not on it) fails in
    tension there, as one does whose gap is more than its strength's stretch T / K_n; intact rock then
    becomes its joint at the first step (`joint_state.break_bridges`). Otherwise the bond's tension
    would be K_n x the gap, which a strong bond (a glued cut, or any bond in strength reduction's
    elastic start) holds, throwing the blocks apart."""
    subs, contacts = state.subs, state.contacts
    size = state.blocks[:, L.SIZE]
    smaller = np.minimum(size[contacts[:, L.BLOCK_A]], size[contacts[:, L.BLOCK_B]])
    gap = np.repeat(BOND_GAP * smaller, state.n_sub)
    apart = (subs[:, L.SLIPPED] == 0.0) & (subs[:, L.TEN] > 0.0) & (subs[:, L.UN] < -gap)
    subs[np.ix_(apart, [L.SN, L.TAU, L.CLOSED, L.TEN, L.COH])] = 0.0
    subs[apart, L.SLIPPED] = L.FAILED_IN_TENSION
    state.law_state[apart, L.LAW_SN] = math.nan


def advance(model: Model, state: State, n_steps: int) -> None:
    """Run n_steps cycles, searching contacts whenever blocks have moved enough, and stop the run
    with a `SimulationError` if it goes wrong."""
    end = state.step + n_steps
    while state.step < end:
        status = _cycles(model, state, end - state.step)
        _check_health(model, state)
        if status == L.STEP_ABOVE_CRITICAL:
            _above_critical(model, state)
        if status == L.SEARCH_NEEDED:
            search_contacts(model, state)
            _set_time_step(model, state)
            if moved_beyond_stop(model, state):
                break  # blocks move at most half the search margin between searches: so does the overshoot
        _note_time_step(state)


def _cycles(model: Model, state: State, n_steps: int) -> int:
    """`kernels.cycle` for up to n_steps cycles, in calls paced by `state.cycle_pace`, until they are
    done or a call returns another status; returns that status. A cut between calls changes nothing:
    the cycle's whole state is in its arrays."""
    solver, ts = model.scene.solver, model.scene.solver.time_step
    threaded = state.threads > 1 and len(state.contacts) >= kernels.THREADED_FROM_CONTACTS
    if threaded:
        kernels.set_threads(state.threads)
    left = n_steps
    while True:
        started = time.perf_counter()
        done, status = kernels.cycle(
            state.cycle_pace.take(left),
            state.clock,
            state.blocks,
            state.dof,
            model.vertex_start,
            model.vertex_block,
            model.vertex_next,
            model.local,
            state.world,
            state.contacts,
            state.subs,
            state.law_state,
            state.n_sub,
            model.laws,
            model.params,
            model.variable_laws,
            solver.update_interval_steps,
            solver.law_update_stress_change or math.inf,
            model.economy.changed_laws_only,
            state.moving,
            model.gravity,
            model.block_loads,
            model.load_block,
            model.edge_loads,
            model.load_edge,
            model.water_surface,
            model.water_unit_weight,
            state.dry_edges,
            model.has_bridges,
            model.support.blocks,
            state.support,
            model.support_divisor,
            solver.damping,
            model.search_margin,
            TIME_STEP_MODES[ts.mode],
            ts.safety_factor,
            state.largest_dt,
            threaded,
            state.per_contact,
            state.block_start,
            state.block_contacts,
        )
        state.cycle_pace.timed(done, time.perf_counter() - started)
        left -= done
        if status != L.DONE or left == 0:
            return status


def simulate(
    model: Model,
    progress: ProgressCallback = ignore,
    on_record: Callable[[State], None] | None = None,
) -> RunResult:
    """Run the scene: `solver.steps` cycles, or fewer if the stop condition is met.

    `progress` is called with a `bbmc.progress.Progress` in steps (of solver.steps) at every record
    step; `on_record(state)` at step 0 and at every record step, for callers that keep more than the
    monitors (it must not change the state).
    """
    solver, warnings = model.scene.solver, []
    if len(model.support.names) and solver.time_step.safety_factor > SLACK_SAFETY:
        warnings.append(
            f"key 'solver.time_step.safety_factor': {solver.time_step.safety_factor:g} with support: a "
            "tendon that goes slack and taut is a one-sided spring, which the explicit step keeps stable "
            f"only up to about {SLACK_SAFETY:g} of the critical step"
        )
    state = prepare(model)
    reference = mon.reference_force(model)
    joints = mon.JointMonitors.of(model)
    every = model.scene.monitoring.every_steps
    records = [_record(model, state, reference, joints)]
    bridges = BridgeLog(model)
    observe = [o for o in (on_record, bridges if model.has_bridges else None) if o is not None]
    for o in observe:
        o(state)
    stopped_by = ""
    trend = Watch.of(model, state)
    energy_before = math.nan
    while state.step < solver.steps and not stopped_by:
        before, chunk = state.step, min(every - state.step % every, solver.steps - state.step)
        if before + chunk == solver.steps:  # only the last chunk's energy is read (`unsettled`)
            energy_before = mon.kinetic_energy(state.blocks)
        advance(model, state, chunk)
        progress(Progress(state.step, solver.steps, "steps", f"step {state.step} of {solver.steps}"))
        _check_overlap(model, state, warnings)
        records.append(_record(model, state, reference, joints))
        for o in observe:
            o(state)
        stopped_by = stop_reason(model, state, reference) or (
            trend.verdict(model, state, reference) if trend else ""
        )
    if not stopped_by and far_from_balance(model, state, reference):
        warnings.append(unsettled(model, state, reference, energy_before))
    return RunResult(
        history=pd.DataFrame(records),
        blocks=mon.block_table(model, state.blocks),
        contacts=mon.contact_table(model, state.contacts, state.subs, state.n_sub),
        summary=_summary(model, state, stopped_by, warnings),
        warnings=warnings,
        bridges=bridges.table(),
        support=support_table(model.support, model.block_names, state.support),
        state=state,
    )


def _record(model: Model, state: State, reference: float, joints: mon.JointMonitors) -> dict[str, float]:
    row = {"step": state.step, "time_s": state.clock[L.TIME]}
    values = mon.monitor_values(model, state, reference, joints)
    row.update(zip((mon.column_name(spec) for spec in model.monitors), values, strict=True))
    return row


def _summary(model: Model, state: State, stopped_by: str, warnings: list[str]) -> pd.DataFrame:
    rows = [
        ("steps", state.step, "1"),
        ("time", state.clock[L.TIME], "s"),
        *((f"stopped_by_{reason}", int(stopped_by == reason), "1") for reason in STOP_REASONS),
        ("stopped_by_steps", int(not stopped_by), "1"),
        ("time_step_min", state.dt_range[0], "s"),
        ("time_step_max", state.dt_range[1], "s"),
        ("contact_searches", state.searches, "1"),
        ("contacts", len(state.contacts), "1"),
        ("active_sub_contacts", int(np.sum(state.subs[:, L.LENGTH] > 0)), "1"),
        ("largest_interpenetration", state.largest_overlap, "fraction of block size"),
        ("interpenetration_limit", model.scene.contacts.interpenetration_limit, "fraction of block size"),
        ("warnings", len(warnings), "1"),
        ("laws_losing_cohesion_at_slip", len(model.laws_losing_cohesion), "1"),
    ]
    return pd.DataFrame(rows, columns=["quantity", "value", "unit"])


def load_scene(path: Path) -> Model:
    """Read, validate and assemble a scene file (ConfigError on any fault)."""
    return build_model(load_config(path, Scene), path)
