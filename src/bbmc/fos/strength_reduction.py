"""The factor of safety of a block scene by shear-strength reduction (UDEC's ``SOLVE FOS``, 3DEC's
``model factor-of-safety``), for Mohr-Coulomb and Barton-Bandis joints.

The scene is first brought to equilibrium with its strengths as given: the unreduced equilibrium,
computed once, in N_r steps. Each trial at a factor F starts from that state with every joint's
strength divided by F (`reduced_params`):

* Mohr-Coulomb: c / F, tan(phi) / F and the tensile strength T / F (as cohesion, T is a strength).
* Barton-Bandis, ``envelope`` (the default): the tangent c and tan(phi) are recomputed from the
  *unreduced* eq 9 envelope at every law update, at the sub-contact's current sigma_n, and then divided
  by F, so the strength is tau_p(sigma_n) / F; T / F.
* Barton-Bandis, ``phi_b_jrc``: tan(phi_b) / F and JRC / F, and the envelope recomputed from them (a
  reduction some authors use; phi_max and JCS kept; eq 15's coefficient recomputed if it is "exact").

A trial's verdict (`settle`): *stable* once the unbalanced-force ratio falls below the limit, read
every `check_every_steps`; *unstable* once any vertex of a block has moved `failure_displacement_m`
from the start state, or when the trial's budget, max(min_trial_steps, response_multiple x N_r)
steps, ends first (the ratio settled above the limit: "not settled"). The budget is Itasca's
characteristic response time: a stable system settles in a time of the order of the equilibrium run's.

The search (`factor_of_safety`): F = 1 holds by the equilibrium itself; F is doubled until a trial
fails, then the bracket [stable F, unstable F] is bisected until it is narrower than `tolerance`; the
factor of safety is its middle. A scene that finds no equilibrium with its own strengths (FS < 1)
starts instead from its equilibrium with every strength multiplied by 1e6 (elastic: no joint slips, as
FLAC takes its response time), and F = 1 is tried from there: if it holds (the unreduced run had only
not settled in its budget, or failed from the sudden switch-on of gravity) F is doubled as above, else
halved until a trial holds. A bracket not found within [1 / largest_factor, largest_factor] is
reported as that bound, not bracketed. In the `phi_b_jrc` mode the tensile strength of Barton-Bandis
joints is divided by F on the trial's sub-contacts, as the divisor does for the other joints. The
stiffness laws keep reading the unreduced strength (tau_p in the Bandis K_s): the path changes, not
the limit.

Support elements (`bbmc.dem.support`) are not reduced by default (``support_form: active``): at failure
the joints' reduced strength and the support's full force hold the block, RocPlane's *active* form,
whatever the bolt: (c A + (N + T sin theta) tan phi) / F + T cos theta = W sin psi for a planar block.
With ``support_form: passive`` the part of each element's force along the joint it crosses is divided
by F as well, RocPlane's *passive* form: (c A + (N + T sin theta) tan phi + T cos theta) / F = W sin
psi. A grouted bolt's force grows with the displacement across its joint, so its share at failure is
what it carries once a trial's blocks have moved `failure_displacement_m` (docs/how-to/support.md);
a trial's budget and trend windows are counted from the support's longest natural period where that is
longer than the equilibrium's steps. On such a soft support the reduction is spread over two of those
periods (`bbmc.fos.gradual`: no dynamic overshoot) and the trend judges where the block comes to rest.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from bbmc import laws
from bbmc.dem import joint_state
from bbmc.dem import layout as L
from bbmc.dem import monitors as mon
from bbmc.dem.model import Model
from bbmc.dem.solver import SimulationError, advance, prepare
from bbmc.dem.state import State
from bbmc.dem.verdict import STABLE, UNSTABLE
from bbmc.fos import gradual, search
from bbmc.fos.elastic_start import no_equilibrium
from bbmc.fos.result import FromRest, StrengthReductionResult, Trial
from bbmc.progress import Progress, ProgressCallback, ignore
from bbmc.scene.fos_settings import StrengthReduction

ELASTIC_DIVISOR = 1e-6  # strengths x 1e6: the start state of a scene not in equilibrium unreduced


def reduced_params(model: Model, factor: float, reduction: str) -> np.ndarray:
    """The joint types' parameters with their strength reduced by `factor` (module docstring)."""
    params = model.params.copy()
    params[:, L.P_STRENGTH_DIVISOR] = factor
    if reduction == "phi_b_jrc":
        bb = model.laws[:, L.STRENGTH_LAW] == L.STRENGTH_BARTON_BANDIS
        exact = np.isclose(
            params[bb, L.P_K_TANGENT], laws.exact_tangent_coefficient(params[bb, L.P_JRC]), rtol=1e-12
        )
        params[bb, L.P_STRENGTH_DIVISOR] = 1.0
        params[bb, L.P_JRC] /= factor
        params[bb, L.P_PHI_B] = np.arctan(np.tan(params[bb, L.P_PHI_B]) / factor)
        params[bb, L.P_K_TANGENT] = np.where(
            exact, laws.exact_tangent_coefficient(params[bb, L.P_JRC]), params[bb, L.P_K_TANGENT]
        )
    return params


def copy_state(state: State) -> State:
    return dataclasses.replace(
        state,
        clock=state.clock.copy(),
        blocks=state.blocks.copy(),
        world=state.world.copy(),
        contacts=state.contacts.copy(),
        subs=state.subs.copy(),
        law_state=state.law_state.copy(),
        support=state.support.copy(),
        dt_range=list(state.dt_range),
    )


def largest_displacement(state: State, start_world: np.ndarray, vertices: np.ndarray | None = None) -> float:
    """The largest distance any vertex (of `vertices`, a bool mask; default all) has moved from
    `start_world` [m]."""
    moved = np.hypot(*(state.world - start_world).T)
    return float(np.max(moved if vertices is None else moved[vertices], initial=0.0))


@dataclass(frozen=True)
class Judged:
    """The blocks whose motion decides a verdict (`fos.judge`; all by default), and their vertices."""

    blocks: np.ndarray  # bool per block
    vertices: np.ndarray  # bool per vertex

    @classmethod
    def of(cls, model: Model) -> Judged:
        """The scene's `fos.judge` as masks; a name that is no block or group, or a choice that leaves
        no block, is refused (bad input)."""
        judge = model.scene.fos.judge
        chosen = np.zeros(len(model.block_names), dtype=bool) if judge.blocks or judge.region_m else None
        for i, name in enumerate(judge.blocks):
            named = np.array([b == name for b in model.block_names])
            if name in model.group_names:
                named |= model.block_group == model.group_names.index(name)
            if not named.any():
                raise SimulationError(
                    f"key 'fos.judge.blocks.{i}': no block or group '{name}'{_closest(name, model)}",
                    bad_input=True,
                )
            chosen |= named
        if judge.region_m is not None:
            (x0, y0), (x1, y1) = judge.region_m
            x, y = model.blocks[:, L.X], model.blocks[:, L.Y]
            chosen |= (min(x0, x1) <= x) & (x <= max(x0, x1)) & (min(y0, y1) <= y) & (y <= max(y0, y1))
        blocks = np.ones(len(model.block_names), dtype=bool) if chosen is None else chosen
        blocks &= model.blocks[:, L.SIZE] >= judge.min_size_fraction * _median_size(model)
        if not (blocks & ~model.immobile).any():
            raise SimulationError("key 'fos.judge': it leaves no block free to move to judge", bad_input=True)
        return cls(blocks, blocks[model.vertex_block])

    def moved_most(self, model: Model, state: State, start_world: np.ndarray) -> tuple[str, float, float]:
        """The judged block with the vertex that moved farthest from `start_world`: (its name, how far
        [m], its size [m])."""
        moved = np.where(self.vertices, np.hypot(*(state.world - start_world).T), -1.0)
        block = int(model.vertex_block[int(np.argmax(moved))])
        return model.block_names[block], max(float(moved.max()), 0.0), float(model.blocks[block, L.SIZE])


def _closest(name: str, model: Model) -> str:
    close = difflib.get_close_matches(name, [*model.block_names, *model.group_names], n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


@dataclass
class _Run:
    """A 2D trial's run as `bbmc.fos.search.settle` reads it, on the `judged` blocks alone."""

    model: Model
    state: State
    reference: float
    judged: Judged

    @property
    def step(self) -> int:
        return self.state.step

    def advance(self, steps: int) -> None:
        advance(self.model, self.state, steps)

    def positions(self) -> np.ndarray:
        return self.state.world[self.judged.vertices]

    def unbalance(self) -> float:
        return mon.unbalanced_force_ratio(self.state, self.reference, self.judged.blocks)

    def loaded(self) -> bool:
        return self.state.step >= self.model.loads_applied_step


def settle(
    model: Model,
    state: State,
    settings: StrengthReduction,
    budget: int,
    failure_displacement: float,
    reference: float,
    judged: Judged,
    window: int | None = None,
    origin: np.ndarray | None = None,
    approach: bool = False,
) -> tuple[str, str]:
    """Run `state` until its verdict (module docstring; `bbmc.fos.search.settle`), read on the `judged`
    blocks alone: (verdict, reason), displacements counted from `origin` (all the vertices [m];
    default: as they are now); `window`, `approach` as `bbmc.fos.search.settle` takes them."""
    start = None if origin is None else origin[judged.vertices]
    run = _Run(model, state, reference, judged)
    return search.settle(run, settings, budget, failure_displacement, window, start, approach)


@contextmanager
def _stage(name: str) -> Iterator[None]:
    """Name the stage of the search (the equilibrium, a trial at F) in a run's fault."""
    try:
        yield
    except SimulationError as error:
        raise SimulationError(f"{name}: {error}", error.bad_input) from error


def _with_params(model: Model, params: np.ndarray, support_divisor: float = 1.0) -> Model:
    return dataclasses.replace(model, params=params, support_divisor=support_divisor)


STAGES = {
    "unreduced": "the equilibrium with the strengths as given",
    "elastic": "the equilibrium with every strength x 1e6 (the elastic start)",
}


def _equilibrium(
    model: Model, settings: StrengthReduction, failure: float, reference: float, judged: Judged
) -> tuple[str, State, int, float, FromRest]:
    """The start state of every trial: (unreduced | elastic, the state, its steps N_r, seconds, the run
    from rest)."""
    started = time.perf_counter()
    budget = model.scene.solver.steps
    from_rest = None
    for start, factor in (("unreduced", 1.0), ("elastic", ELASTIC_DIVISOR)):
        trial_model = _with_params(model, reduced_params(model, factor, "envelope"))
        with _stage(STAGES[start]):
            state = prepare(trial_model)
            start_world = state.world.copy()
            verdict, reason = settle(trial_model, state, settings, budget, failure, reference, judged)
        if from_rest is None:
            block, moved, _ = judged.moved_most(model, state, start_world)
            from_rest = FromRest(verdict, reason, state.step, block, moved)
        if verdict == STABLE:
            return start, state, state.step, time.perf_counter() - started, from_rest
    raise SimulationError(
        no_equilibrium(model, state, start_world, reason, settings.unbalanced_force_ratio, reference),
        bad_input=True,
    )


def _median_size(model: Model) -> float:
    """The median size of the blocks free to move (of all, if none is) [m]."""
    free = ~model.immobile
    return float(np.median(model.blocks[free if free.any() else slice(None), L.SIZE]))


def failure_displacement(model: Model) -> float:
    """The scene's `fos.failure_displacement_m`, or 5 % of the median size of the blocks free to move
    [m]; refused when larger than the whole model (every failing trial would run out its budget)."""
    given = model.scene.fos.failure_displacement_m
    extent = float(np.ptp(model.local, axis=0).max() + np.ptp(model.blocks[:, [L.X, L.Y]], axis=0).max())
    if given is not None and given > extent:
        raise SimulationError(
            f"key 'fos.failure_displacement_m': {given:g} m is larger than the whole model ({extent:.3g} m)",
            bad_input=True,
        )
    return given if given is not None else 0.05 * _median_size(model)


def _support_response_steps(model: Model, state: State) -> int:
    """The steps of the longest natural period of a block on its support (`SupportElements.
    longest_period`; 0 without support): a trial's budget and trend windows are counted from the larger
    of it and the equilibrium's steps, so that a soft support has the time to pick up its load."""
    period = model.support.longest_period(model.blocks, model.immobile)
    return math.ceil(period / state.clock[L.DT]) if period > 0 else 0


def factor_of_safety(model: Model, progress: ProgressCallback = ignore) -> StrengthReductionResult:
    """The scene's factor of safety by strength reduction (module docstring), with every trial.
    `progress` is called with a `bbmc.progress.Progress` in trials (total None: the search ends when
    the bracket is narrow enough) before the equilibrium, after it, and after every trial."""
    settings = model.scene.fos

    def report(text: str) -> None:
        progress(Progress(len(trials), None, "trials", text))

    trials: list[Trial] = []
    failure = failure_displacement(model)
    reference = mon.reference_force(model)
    report("equilibrium with the strengths as given")
    judged = Judged.of(model)
    start, equilibrium, n_r, eq_seconds, from_rest = _equilibrium(model, settings, failure, reference, judged)
    support_steps = _support_response_steps(model, equilibrium)
    response, soft = max(n_r, support_steps), support_steps > n_r
    ramp_steps = (
        gradual.RAMP_PERIODS * support_steps if soft and settings.barton_bandis_reduction == "envelope" else 0
    )
    budget = max(settings.min_trial_steps, math.ceil(settings.response_multiple * response))
    window = max(settings.check_every_steps, math.ceil(settings.trend_window_multiple * response))
    report(f"equilibrium ({start}) in {n_r} steps; each trial runs up to {budget} steps")
    mechanism, mechanism_blocks = None, None
    held, stable_blocks = equilibrium.support.copy(), equilibrium.blocks.copy()

    def reduced_to(factor: float) -> Model:
        return _with_params(
            model,
            reduced_params(model, factor, settings.barton_bandis_reduction),
            factor if settings.support_form == "passive" else 1.0,
        )

    def beyond(state: State) -> bool:
        return largest_displacement(state, equilibrium.world, judged.vertices) > failure

    def attempt(factor: float) -> bool:
        nonlocal mechanism, mechanism_blocks, held, stable_blocks
        state = copy_state(equilibrium)
        trial_model = reduced_to(factor)
        if settings.barton_bandis_reduction == "phi_b_jrc" and trial_model.variable_laws:
            state.law_state[:, L.LAW_SN] = math.nan  # the envelope changed: re-evaluate every sub-contact
            joint_state.update_joint_laws(
                state.contacts,
                state.subs,
                state.law_state,
                state.n_sub,
                trial_model.laws,
                trial_model.params,
                True,
            )
            # the divisor is 1 for these joints: their tensile strength is divided here instead
            law = trial_model.laws[state.contacts[:, L.JOINT_TYPE], L.STRENGTH_LAW]
            state.subs[np.repeat(law == L.STRENGTH_BARTON_BANDIS, state.n_sub), L.TEN] /= factor
        started, first = time.perf_counter(), state.step
        with _stage(f"the trial at F = {factor:.4g}"):
            every = settings.check_every_steps
            if ramp_steps and gradual.ramp(reduced_to, state, factor, ramp_steps, every, beyond):
                verdict, reason = UNSTABLE, "displacement"
            else:
                verdict, reason = settle(
                    trial_model,
                    state,
                    settings,
                    budget,
                    failure,
                    reference,
                    judged,
                    window,
                    equilibrium.world,
                    soft,
                )
        block, moved, size = judged.moved_most(model, state, equilibrium.world)
        trial = Trial(
            factor=factor,
            verdict=verdict,
            reason=reason,
            steps=state.step - first,
            largest_displacement_m=moved,
            unbalanced_force_ratio=mon.unbalanced_force_ratio(state, reference, judged.blocks),
            seconds=time.perf_counter() - started,
            block=block,
            block_size_m=size,
        )
        trials.append(trial)
        report(
            f"trial {len(trials)}: F = {factor:.4g} {verdict} ({reason}, {trial.steps} steps, "
            f"{trial.seconds:.1f} s)"
        )
        if verdict == UNSTABLE and all(t.factor >= factor for t in trials if t.verdict == UNSTABLE):
            mechanism, mechanism_blocks = state.world.copy(), state.blocks.copy()
        if verdict == STABLE and all(t.factor <= factor for t in trials if t.verdict == STABLE):
            held, stable_blocks = state.support.copy(), state.blocks.copy()
        return verdict == STABLE

    fs, (lo, hi), bracketed = search.bracket_factor(
        attempt, settings.largest_factor, settings.tolerance, start == "elastic"
    )
    return StrengthReductionResult(
        factor_of_safety=fs,
        bracket=(lo, hi),
        bracketed=bracketed,
        start=start,
        equilibrium_steps=n_r,
        equilibrium_seconds=eq_seconds,
        trials=trials,
        start_world=equilibrium.world.copy(),
        mechanism_world=mechanism,
        failure_displacement_m=failure,
        laws_losing_cohesion=model.laws_losing_cohesion,
        support_state=held,
        start_blocks=equilibrium.blocks.copy(),
        stable_blocks=stable_blocks,
        mechanism_blocks=mechanism_blocks,
        from_rest=from_rest,
        median_block_size_m=_median_size(model),
        model=model,
    )
