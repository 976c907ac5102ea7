"""What a sweep costs and how it scales (sweep_cost.csv), measured side by side in one run.

* `le_throughput`: planar limit-equilibrium samples per second on one core (`PlanarModel`, one
  vectorised call over the whole batch; best of N).
* `dem_throughput`: DEM factor-of-safety samples per minute on one core: the block on a 30 deg plane of
  `bbmc.slope.fos_cases` (a small scene) and the paper's B-B slope of `bbmc slope` (34 blocks).
* `speed_up`: the paper slope's DEM study on 1 and on 2 local processes, and on a 2-worker dask
  LocalCluster; wall time and the ratio to 1 process (the pool's start-up included: what a user waits
  for).
* `task_overhead`: per-task time of an empty batch (one planar sample) on the local pool and on the
  LocalCluster: what a task costs beyond its work.

The "LocalCluster" is a dask scheduler in this process and its worker processes (`dask worker`) in a
session of their own, so that a terminal's Ctrl-C reaches this process alone: the interrupted study
cancels its tasks (`bbmc.sweep.runner`) and the workers are ended with the cluster, whatever they were
doing (loading the kernels, which no Ctrl-C could stop). An interrupted study's batches go with its
temporary folder.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import pandas as pd

from bbmc.slope import fos_cases as fc
from bbmc.slope import safety
from bbmc.slope.config import load_paper_slope
from bbmc.sweep import design
from bbmc.sweep.models import PlanarModel, SceneModel
from bbmc.sweep.runner import StudyInterrupted, run_batches

SOURCE = Path(__file__).resolve().parents[2]  # src/: the package, whether installed or not
PLANAR = {
    "kind": "planar",
    "height_m": 20.0,
    "face_deg": 60.0,
    "plane_deg": 35.0,
    "crack_depth_m": 0.0,
    "water_fill": 0.0,
    "unit_weight_kN_m3": 26.0,
    "seismic_coefficient": 0.0,
    "strength": {"law": "mohr_coulomb", "cohesion_kPa": 0.0, "friction_deg": None, "tan_friction": 0.8},
}


def _planar_design(n: int) -> pd.DataFrame:
    return design.sample_table([("strength.tan_friction", design.marginal("normal", mean=0.8, std=0.15))], n,
                               "monte_carlo", 0)  # fmt: skip


def _dem_design(n: int) -> pd.DataFrame:
    friction = design.marginal("normal", mean=33.0, std=3.0)
    return design.sample_table([("joint_laws.joint.friction_deg", friction)], n, "latin_hypercube", 3)


def _timed(action: Callable[[], object]) -> float:
    start = time.perf_counter()
    action()
    return time.perf_counter() - start


def _study(model, table: pd.DataFrame, batch: int, **where) -> float:
    """Wall time of a whole study into a fresh store (thrown away, even when interrupted)."""
    with tempfile.TemporaryDirectory() as folder:
        try:
            return _timed(lambda: run_batches(model, table, Path(folder), batch, **where))
        except StudyInterrupted:
            raise KeyboardInterrupt from None  # no batch is kept: its folder goes


@contextmanager
def _cluster(workers: int) -> Iterator[str]:
    """A dask scheduler here and `workers` single-threaded worker processes in a session of their own
    (out of reach of a terminal's Ctrl-C), killed when the block ends; yields the scheduler's address."""
    from distributed import Client, LocalCluster  # here: only this part of the bench needs dask

    env = os.environ | {"PYTHONPATH": os.pathsep.join([str(SOURCE), os.environ.get("PYTHONPATH", "")])}
    with LocalCluster(n_workers=0, dashboard_address=None) as scheduler:
        address = scheduler.scheduler_address
        command = [sys.executable, "-m", "distributed.cli.dask_worker", address, "--nworkers", str(workers)]
        process = subprocess.Popen(
            [*command, "--nthreads", "1", "--no-dashboard"],
            env=env,
            start_new_session=True,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        try:
            with Client(address) as client:
                client.wait_for_workers(workers, timeout=300)
            yield address
        finally:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def _dem_row(what: str, model, table: pd.DataFrame) -> dict:
    model(table.iloc[:1])  # the kernels loaded
    seconds = _timed(lambda: model(table))
    return {"part": "dem_throughput", "what": what, "samples": len(table), "seconds": seconds,
            "per_minute": 60 * len(table) / seconds}  # fmt: skip


def sweep_cost_table(
    le_samples: int, dem_samples: int, repeats: int, slope_config: Path, progress: Callable[[str], None]
) -> pd.DataFrame:
    rows = []
    planar, inputs = PlanarModel(PLANAR), _planar_design(le_samples)
    progress("sweep cost: limit-equilibrium throughput")
    planar(inputs.iloc[:10])
    best = min(_timed(lambda: planar(inputs)) for _ in range(repeats))
    rows.append({"part": "le_throughput", "what": "planar FS, one core", "samples": le_samples,
                 "seconds": best, "per_second": le_samples / best})  # fmt: skip
    progress("sweep cost: DEM factor of safety, one core")
    block = SceneModel(fc.block_on_plane(fc.MOHR_COULOMB, 0.8, 0.2), "block_on_plane", "scene_fos")
    rows.append(_dem_row("block on a plane, FS by strength reduction", block, _dem_design(dem_samples)))
    scene = safety.reduction_scene(*load_paper_slope(slope_config), "barton_bandis")
    slope = SceneModel(scene, "paper slope", "scene_fos")
    slope_design = design.sample_table(
        [("joint_laws.joint.strength.phi_b_deg", design.marginal("normal", mean=33.4, std=2.0))],
        dem_samples,
        "latin_hypercube",
        3,
    )
    rows.append(_dem_row("the paper's B-B slope, FS by strength reduction", slope, slope_design))
    progress("sweep cost: speed-up on 2 local processes and on a 2-worker LocalCluster")
    one = _study(slope, slope_design, 1, workers=1)
    two = _study(slope, slope_design, 1, workers=2)
    empty = _planar_design(200)
    local_overhead = _study(planar, empty, 1, workers=2) / len(empty)
    with _cluster(2) as address:
        _study(slope, slope_design.iloc[:2], 1, scheduler=address)  # the workers load the kernels
        on_cluster = _study(slope, slope_design, 1, scheduler=address)
        cluster_overhead = _study(planar, empty, 1, scheduler=address) / len(empty)
    for what, seconds in (
        ("1 local process", one),
        ("2 local processes", two),
        ("2-worker LocalCluster", on_cluster),
    ):
        rows.append({"part": "speed_up", "what": what, "samples": dem_samples, "seconds": seconds,
                     "speed_up": one / seconds})  # fmt: skip
    for what, seconds in (("local pool", local_overhead), ("LocalCluster", cluster_overhead)):
        rows.append(
            {"part": "task_overhead", "what": what, "samples": len(empty), "seconds_per_task": seconds}
        )
    return pd.DataFrame(rows)
