"""A 3D scene's run, as `bbmc run` gives it (`bbmc.scene.schema3d.Solver3D`, `Monitoring3D`): the time
step from the contacts (`bbmc.dem3d.solver.time_step`, x the scene's safety factor), the steps in
chunks of the record interval, the monitors read at every record (history), and the stop: once the
unbalanced-force ratio (`bbmc.dem3d.monitors`) is below the scene's limit, once a vertex of a block free
to move has moved `displacement_m` from where it started, or once `time_s` of physical time has run;
checked at record steps, whichever comes first.

Monitors (at the record step): a block's centroid displacement ux, uy, uz and its length
`displacement` [m], its velocity vx, vy, vz and `speed` [m/s], its `rotation` since the start [deg]
(the angle of q q0^-1); the system's kinetic energy (1/2 m v.v + 1/2 w.(J w), true masses) [J] and
the unbalanced-force ratio [1]. history.csv names a monitor's column <name>_<unit> and gives it in
that unit (`UNITS`, as the 2D history: mm, m_s, deg, J, 1). Units: SI inside.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from bbmc.config import ConfigKeyError
from bbmc.dem3d import monitors
from bbmc.dem3d.layout import I1, MASS, QW, VX, X
from bbmc.dem3d.model import Model
from bbmc.dem3d.motion import body_angular_velocity
from bbmc.dem3d.scene_model import SceneModel
from bbmc.dem3d.solver import run, thread_count, time_step
from bbmc.progress import Progress, ProgressCallback, ignore
from bbmc.scene.schema3d import Monitor3D, Scene3D

UNITS = {
    **dict.fromkeys(("ux", "uy", "uz", "displacement"), ("mm", 1e3)),
    **dict.fromkeys(("vx", "vy", "vz", "speed"), ("m_s", 1.0)),
    "rotation": ("deg", 1.0),
    "kinetic_energy": ("J", 1.0),
    "unbalanced_force_ratio": ("1", 1.0),
}  # the quantity's unit in history.csv and its factor from the reading's (m, m/s, deg, J, 1)


@dataclass(frozen=True)
class RunOutcome3D:
    """What a 3D run gave: the `history` (step, time_s, one column per monitor), the steps run, the
    time step `dt` [s], the physical time [s], why it stopped (`stopped_by`: steps, ratio,
    displacement, time), the unbalanced-force ratio and the largest vertex displacement of a free
    block [m] at the end."""

    history: pd.DataFrame
    steps: int
    dt: float
    time_s: float
    stopped_by: str
    unbalanced_force_ratio: float
    largest_displacement_m: float
    warnings: tuple[str, ...] = ()

    def summary(self) -> pd.DataFrame:
        """summary.csv's rows (quantity, value, unit)."""
        rows = [
            ("steps", self.steps, "1"),
            ("time_step", self.dt, "s"),
            ("time", self.time_s, "s"),
            ("stopped_by_" + self.stopped_by, 1, "1"),
            ("unbalanced_force_ratio", self.unbalanced_force_ratio, "1"),
            ("largest_displacement", self.largest_displacement_m * 1e3, "mm"),
        ]
        return pd.DataFrame(rows, columns=["quantity", "value", "unit"])


def _rotation_deg(model: Model, start: np.ndarray, i: int) -> float:
    """The angle [deg] block i has turned since the start: 2 acos |q . q0|."""
    dot = abs(float(model.blocks[i, QW : QW + 4] @ start[i, QW : QW + 4]))
    return math.degrees(2.0 * math.acos(min(dot, 1.0)))


def kinetic_energy(model: Model) -> float:
    """1/2 m v.v + 1/2 w_b.(I w_b) over every block, true masses and moments [J]."""
    b = model.blocks
    w = body_angular_velocity(b)
    linear = 0.5 * b[:, MASS] * np.sum(b[:, VX : VX + 3] ** 2, axis=1)
    return float(np.sum(linear + 0.5 * np.sum(b[:, I1 : I1 + 3] * w * w, axis=1)))


def _reading(monitor: Monitor3D, sm: SceneModel, i: int | None, reference: float) -> float:
    model, q = sm.model, monitor.quantity
    if q == "kinetic_energy":
        return kinetic_energy(model)
    if q == "unbalanced_force_ratio":
        return monitors.unbalanced_force_ratio(model, reference)
    if q == "rotation":
        return _rotation_deg(model, sm.start, i)
    moved = model.blocks[i, X : X + 3] - sm.start[i, X : X + 3]
    velocity = model.blocks[i, VX : VX + 3]
    if q in ("displacement", "speed"):
        return float(np.linalg.norm(moved if q == "displacement" else velocity))
    return float((moved if q[0] == "u" else velocity)["xyz".index(q[1])])


def _targets(scene: Scene3D, sm: SceneModel) -> list[int | None]:
    """Each monitor's block index (None for a system quantity); an unknown block names its key."""
    return [
        None if m.block is None else sm.index(m.block, f"monitoring.monitors.{k}.block")
        for k, m in enumerate(scene.monitoring.monitors)
    ]


def _free_vertices(model: Model) -> np.ndarray:
    return np.repeat(monitors.free_blocks(model), np.diff(model.vertex_start))


def run_scene(
    sm: SceneModel,
    scene: Scene3D,
    progress: ProgressCallback = ignore,
    on_record: Callable[[Model, float], None] | None = None,
) -> RunOutcome3D:
    """Run the scene's model `sm` in place for `scene.solver` (module docstring), reporting `progress`
    in steps at every record and calling `on_record(model, time [s])` there (a ParaView series). A
    scene with no contact to take a time step from is refused."""
    model, solver = sm.model, scene.solver
    targets = _targets(scene, sm)
    dt = time_step(model, solver.safety_factor, solver.damping)
    if not math.isfinite(dt):
        raise ConfigKeyError(
            "blocks",
            "no two blocks within the search margin at the start: no contact to take a time step from",
        )
    threads = thread_count(solver.threads)
    reference = monitors.reference_force(model)
    moving = _free_vertices(model)
    origin = model.vertices[moving].copy()
    every, stop = scene.monitoring.every_steps, solver.stop
    rows, first, stopped_by = [], model.step, "steps"

    def record() -> None:
        readings = [
            _reading(m, sm, i, reference) * UNITS[m.quantity][1]
            for m, i in zip(scene.monitoring.monitors, targets, strict=True)
        ]
        rows.append([model.step - first, (model.step - first) * dt, *readings])
        if on_record is not None:
            on_record(model, (model.step - first) * dt)

    def largest() -> float:
        return float(np.max(np.linalg.norm(model.vertices[moving] - origin, axis=1), initial=0.0))

    record()
    while model.step - first < solver.steps:
        run(model, min(every, solver.steps - (model.step - first)), dt, solver.damping, threads)
        record()
        done = model.step - first
        progress(Progress(done, solver.steps, "steps", f"step {done} of {solver.steps}"))
        if stop is None:
            continue
        if stop.unbalanced_force_ratio is not None and (
            monitors.unbalanced_force_ratio(model, reference) < stop.unbalanced_force_ratio
        ):
            stopped_by = "ratio"
        elif stop.displacement_m is not None and largest() > stop.displacement_m:
            stopped_by = "displacement"
        elif stop.time_s is not None and done * dt >= stop.time_s:
            stopped_by = "time"
        if stopped_by != "steps":
            break
    columns = ["step", "time_s", *(f"{m.name}_{UNITS[m.quantity][0]}" for m in scene.monitoring.monitors)]
    steps = model.step - first
    ratio = monitors.unbalanced_force_ratio(model, reference)
    return RunOutcome3D(
        pd.DataFrame(rows, columns=columns), steps, dt, steps * dt, stopped_by, ratio, largest()
    )
