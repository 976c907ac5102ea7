"""The paper's two scenes as the benchmark runs them, with the solver's knobs exposed.

* shear: the stress-controlled direct shear tests of Table 3 with eq 16's corrected K_s, exactly as
  `bbmc shear` builds them from configs/shear.yaml; what users read is d_h of each test.
* slope: the section 5 slope of configs/slope.yaml with one joint model; what users read is the
  displacement of blocks 1-4 at the end of the run (interpolated to `run.duration_s`, so that runs with
  different time steps are compared at the same physical time).

The knobs (`Knobs`): the B-B update interval, the time-step safety factor, sub-contacts per edge,
local damping, and density scaling as the fixed time step in multiples of the automatic step at
step 0 (masses raised so it stays `safety_factor` x critical).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Protocol

import numpy as np

from bbmc import units
from bbmc.config import load_config
from bbmc.dem import layout as L
from bbmc.dem.model import EVERY_ECONOMY, Economy, Model, build_model
from bbmc.dem.solver import SimulationError, prepare, simulate
from bbmc.scene.schema import Scene, Solver, TimeStep
from bbmc.shear import box
from bbmc.shear import config as shear_config
from bbmc.shear.bench import Bench
from bbmc.slope import config as slope_config
from bbmc.slope import model as sm


@dataclass(frozen=True)
class Knobs:
    update_interval_steps: int
    safety_factor: float
    sub_contacts_per_edge: int
    damping: float
    density_scaling: float | None = None  # the fixed step over the automatic step at step 0 (None: off)
    law_update_stress_change: float | None = None  # laws also updated once stresses move this much


class PaperScene(Protocol):
    """What the trade and the economies need of a scene."""

    name: str
    what: str  # what users read off it
    labels: tuple[str, ...]  # one per value read
    stress_dependent: bool  # whether its joint laws depend on the stresses (the update interval matters)

    def defaults(self) -> Knobs: ...

    def read(self, knobs: Knobs, economy: Economy = EVERY_ECONOMY) -> Reading: ...


@dataclass(frozen=True)
class Reading:
    """What users read off one run of a scene, and what it cost."""

    values: np.ndarray  # d_h per test [m] (inf where a test does not hold) | displacement per block [m]
    statuses: tuple[str, ...]
    seconds: float
    steps: int


def _density_scaling(scene: dict, knobs: Knobs) -> None:
    """Density scaling with a fixed step `knobs.density_scaling` times the scene's automatic step at
    step 0, in place."""
    step = knobs.density_scaling * _automatic_step(scene)
    scene["solver"]["time_step"] = {
        "mode": "density_scaling",
        "safety_factor": knobs.safety_factor,
        "step_s": step,
    }


def _automatic_step(scene: dict) -> float:
    """The automatic time step at step 0 with the scene's own settings [s]."""
    model = build_model(Scene.model_validate(scene, strict=False), Path(f"<{scene['name']}>"))
    return float(prepare(model).clock[L.DT])


class ShearScene:
    """The stress-controlled tests of Table 3 with eq 16's K_s (configs/shear.yaml)."""

    name = "shear"
    what = "d_h of each Table 3 test"
    stress_dependent = True

    def __init__(self, config_path: Path) -> None:
        self.config = load_config(config_path, shear_config.Config)
        inputs = shear_config.load_inputs(self.config)
        self.bench = Bench(self.config, inputs)
        table3 = inputs["table3"]
        self.loads = list(zip(table3["sigma_n_MPa"] * units.MPa, table3["tau_MPa"] * units.MPa, strict=True))
        self.labels = tuple(
            f"sigma_n {s / units.MPa:g} MPa, tau {t / units.MPa:g} MPa" for s, t in self.loads
        )

    def defaults(self) -> Knobs:
        """The config's schedule and specimen; the box leaves the time step and damping to the engine."""
        c = self.config
        return Knobs(
            c.stress_controlled.update_interval_steps,
            TimeStep().safety_factor,
            c.specimen.sub_contacts_per_edge,
            Solver.model_fields["damping"].default,
        )

    def _scene(self, knobs: Knobs, sigma_n: float, tau: float) -> dict:
        c = self.config
        specimen = c.specimen.model_copy(update={"sub_contacts_per_edge": knobs.sub_contacts_per_edge})
        run = c.stress_controlled.model_copy(update={"update_interval_steps": knobs.update_interval_steps})
        law = self.bench.paper_law("corrected", sigma_n)
        scene = box.stress_controlled_scene(
            "bench_shear", specimen, run, self.bench.density, law, sigma_n, tau
        )
        scene["solver"]["damping"] = knobs.damping
        scene["solver"]["law_update_stress_change"] = knobs.law_update_stress_change
        scene["solver"]["time_step"] = {"mode": "auto", "safety_factor": knobs.safety_factor}
        if knobs.density_scaling is not None:
            _density_scaling(scene, knobs)
        return scene

    def read(self, knobs: Knobs, economy: Economy = EVERY_ECONOMY) -> Reading:
        scenes = [self._scene(knobs, s, t) for s, t in self.loads]
        start = time.perf_counter()
        outcomes = [_stress_test(scene, economy) for scene in scenes]
        seconds = time.perf_counter() - start
        return Reading(
            values=np.array([o.d_h for o in outcomes]),
            statuses=tuple(o.status for o in outcomes),
            seconds=seconds,
            steps=sum(o.steps for o in outcomes),
        )


def _stress_test(scene: dict, economy: Economy) -> box.Outcome:
    try:
        return box.run_stress_controlled(scene, economy)
    except SimulationError as error:
        return box.Outcome(d_h=math.inf, status=f"failed: {error}", steps=0, final_ks=math.nan)


class SlopeScene:
    """The section 5 slope with one joint model (configs/slope.yaml); blocks 1-4 as `bbmc slope`."""

    what = "displacement of blocks 1-4 at the end of the run"

    def __init__(self, config_path: Path, kind: sm.JointModel) -> None:
        self.config, self.table4 = slope_config.load_paper_slope(config_path)
        self.kind, self.name = kind, f"slope_{kind}"
        self.stress_dependent = kind != "constant"
        probe = self._model(self.defaults())
        self.numbering = sm.paper_numbering(sm.sliding_layer(probe, self.config.slope))
        self.labels = tuple(f"block {n}" for n in sm.PAPER_NUMBERS)

    def defaults(self) -> Knobs:
        r = self.config.run
        return Knobs(r.update_interval_steps, r.safety_factor, r.sub_contacts_per_edge, r.damping)

    def _scene(self, knobs: Knobs) -> dict:
        run = self.config.run.model_copy(
            update={
                "update_interval_steps": knobs.update_interval_steps,
                "safety_factor": knobs.safety_factor,
                "sub_contacts_per_edge": knobs.sub_contacts_per_edge,
                "damping": knobs.damping,
            }
        )
        law = sm.joint_law(self.kind, self.table4, self.config.constant, self.config.barton_bandis)
        scene = sm.slope_scene(self.name, self.config.slope, self.table4.density_kg_m3, law, run, [])
        scene["solver"]["law_update_stress_change"] = knobs.law_update_stress_change
        if knobs.density_scaling is not None:
            _density_scaling(scene, knobs)
        return scene

    def _model(self, knobs: Knobs) -> Model:
        scene = self._scene(knobs)
        return build_model(Scene.model_validate(scene, strict=False), Path(f"<{self.name}>"))

    def read(self, knobs: Knobs, economy: Economy = EVERY_ECONOMY) -> Reading:
        model = replace(self._model(knobs), economy=economy)
        watched = [self.numbering[n] for n in sm.PAPER_NUMBERS]
        times, positions = [], []

        def keep(state) -> None:
            times.append(state.clock[L.TIME])
            positions.append(state.blocks[watched][:, [L.X, L.Y]].copy())

        start = time.perf_counter()
        try:
            result = simulate(model, on_record=keep)
        except SimulationError as error:
            failed = (f"failed: {error}",) * len(watched)
            return Reading(np.full(len(watched), math.inf), failed, time.perf_counter() - start, 0)
        seconds = time.perf_counter() - start
        moved = np.hypot(*(np.array(positions) - positions[0]).transpose(2, 0, 1))
        end = self.config.run.duration_s
        values = np.array([np.interp(end, times, moved[:, k]) for k in range(len(watched))])
        stopped = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
        status = "ran its time" if stopped["stopped_by_time"] else "stopped at max_steps"
        return Reading(
            values=values, statuses=(status,) * len(watched), seconds=seconds, steps=result.state.step
        )


def relative_error(reading: Reading, reference: Reading) -> float:
    """Largest difference from the reference over what users read, relative to the largest reference
    value (a block or test that hardly moves does not blow it up); inf where a test's outcome differs
    (e.g. it slides instead of holding)."""
    if reading.statuses != reference.statuses:
        return math.inf
    finite = np.isfinite(reference.values)
    if not finite.any():
        return 0.0
    scale = float(np.max(np.abs(reference.values[finite])))
    return float(np.max(np.abs(reading.values[finite] - reference.values[finite]))) / scale
