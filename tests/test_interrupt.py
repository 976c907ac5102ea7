"""Ctrl-C: every long command stops within 2 s with one line and exit status 130, writes nothing partial,
and a sweep keeps its finished batches; the kernel calls that make this possible change no number.

The commands run as real processes in a session of their own, and SIGINT goes to the whole process
group, as a terminal's Ctrl-C does (sweep workers included). Each waits for a line on stderr that shows
the run under way before the signal. The stop time is measured from the signal to the exit of the
process, the interpreter's shutdown included (about 0.4 s for bbmc's imports)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import pandas as pd
import pytest
import yaml

from bbmc.dem import pace, solver
from bbmc.fos.strength_reduction import factor_of_safety
from bbmc.io import StageResult, write_stage

ROOT = Path(__file__).resolve().parents[1]
STOP_S = 2.0  # the bound the feature promises
SHUTDOWN_S = 1.0  # allowance for the interpreter's shutdown after it, on a loaded machine
LONG = 1_000_000_000  # steps: hours of running, so that only Ctrl-C ends the run


def _resting_block(**changes: object) -> dict:
    """A block at rest on a fixed base: it runs as long as it is asked to."""
    rock = {"density_kg_m3": 2500}
    joint = {"law": "constant", "kn_MPa_per_mm": 10, "ks_MPa_per_mm": 10, "friction_deg": 30}
    scene = {
        "name": "rest",
        "materials": {"rock": rock},
        "blocks": [
            {
                "name": "base",
                "material": "rock",
                "fix": ["x", "y", "rotation"],
                "rectangle_m": {"x_m": -2.0, "y_m": -0.5, "width_m": 4.0, "height_m": 0.5},
            },
            {
                "name": "block",
                "material": "rock",
                "rectangle_m": {"x_m": -0.2, "y_m": 0.0, "width_m": 0.4, "height_m": 0.2},
            },
        ],
        "joint_laws": {"joint": joint},
        "contacts": {"default_law": "joint"},
        "solver": {"steps": LONG},
        "monitoring": {
            "every_steps": 20_000,
            "monitors": [{"name": "block", "block": "block", "quantity": "uy"}],
        },
    }
    scene.update(changes)
    return scene


def _write(path: Path, data: dict) -> Path:
    path.write_text(yaml.safe_dump(data))
    return path


@dataclass
class Stopped:
    status: int
    seconds: float  # from the signal to the process's exit
    stderr: list[str]
    group_left: bool  # a process of its group (a worker) still alive after it exited


def _interrupted(tmp_path: Path, args: list[str], ready: str, after_s: float = 0.3) -> Stopped:
    """`python -m bbmc ARGS` in tmp_path, in a session of its own; once `ready` is on its stderr (and
    `after_s` later), SIGINT to its whole process group."""
    env = os.environ | {"PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])}
    process = subprocess.Popen(
        [sys.executable, "-m", "bbmc", *args],
        cwd=tmp_path,
        env=env,
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    lines: list[str] = []
    seen = threading.Event()

    def read() -> None:
        for line in process.stderr:
            lines.append(line.rstrip("\n"))
            if ready in line:
                seen.set()

    reader = threading.Thread(target=read)
    reader.start()
    try:
        assert seen.wait(120), f"never saw {ready!r} on stderr: {lines}"
        time.sleep(after_s)
        os.killpg(process.pid, signal.SIGINT)
        sent = time.perf_counter()
        status = process.wait(60)
        seconds = time.perf_counter() - sent
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
        reader.join()
    try:
        os.killpg(process.pid, 0)
        group_left = True
        os.killpg(process.pid, signal.SIGKILL)
    except ProcessLookupError:
        group_left = False
    return Stopped(status, seconds, lines, group_left)


def _assert_stopped_cleanly(stopped: Stopped, command: str) -> str:
    """Exit 130 within the bound, no traceback, no process left; returns its one line."""
    assert stopped.status == 130, stopped.stderr
    assert stopped.seconds < STOP_S + SHUTDOWN_S, f"stopped {stopped.seconds:.2f} s after the signal"
    assert not any("Traceback" in line or "Error" in line for line in stopped.stderr), stopped.stderr
    assert not stopped.group_left
    last = stopped.stderr[-1]
    assert last.startswith(f"bbmc {command}: interrupted: "), stopped.stderr
    return last


def test_run_stops_at_once_and_writes_nothing(tmp_path):
    scene = _write(tmp_path / "rest.yaml", _resting_block())
    stopped = _interrupted(tmp_path, ["run", str(scene), "--results", "out"], ready="bbmc run rest.yaml")
    assert _assert_stopped_cleanly(stopped, "run") == "bbmc run: interrupted: nothing written"
    assert not (tmp_path / "out").exists()


def test_fos_stops_mid_search_and_writes_nothing(tmp_path):
    """Its equilibrium and each trial checked every 5 million steps (seconds): a search of minutes."""
    fos = {"check_every_steps": 5_000_000, "min_trial_steps": 100_000_000}
    scene = _write(tmp_path / "rest.yaml", _resting_block(fos=fos))
    stopped = _interrupted(tmp_path, ["fos", "--config", str(scene), "--results", "out"], ready="bbmc fos:")
    assert _assert_stopped_cleanly(stopped, "fos") == "bbmc fos: interrupted: nothing written"
    assert not (tmp_path / "out").exists()


def _long_study(tmp_path: Path) -> Path:
    """Four runs of the resting block, one per batch: the first 2000 steps, the others hours long."""
    scene = _write(tmp_path / "rest.yaml", _resting_block())
    study = {
        "name": "rest_study",
        "base": {"kind": "scene_run", "scene": str(scene), "monitor": "block_mm"},
        "grid": [{"path": "solver.steps", "values": [2000, LONG, LONG, LONG]}],
        "sampling": {"method": "grid"},
        "batch_size": 1,
    }
    return _write(tmp_path / "study.yaml", study)


def _assert_study_kept_its_first_batch(stopped: Stopped, results: Path) -> None:
    line = _assert_stopped_cleanly(stopped, "sweep")
    assert "1 of 4 samples done, kept in" in line and line.endswith("nothing else written"), line
    assert not (results / "sweep" / "rest_study").exists()
    (store,) = (results / "sweep" / "rest_study.progress").iterdir()
    assert sorted(p.name for p in store.iterdir()) == ["batch_000000000.csv"]
    kept = pd.read_csv(store / "batch_000000000.csv")
    assert list(kept["sample"]) == [0] and kept["error"].isna().all()


def test_a_local_sweep_ends_its_workers_and_keeps_its_finished_batch(tmp_path):
    """Two local workers, each on an hours-long batch when Ctrl-C comes: they ignore SIGINT and are
    ended by the parent; the first batch, done before, stays."""
    config = _long_study(tmp_path)
    args = ["sweep", "--config", str(config), "--results", "out", "--workers", "2"]
    stopped = _interrupted(tmp_path, args, ready="1/4 samples")
    _assert_study_kept_its_first_batch(stopped, tmp_path / "out")


@pytest.mark.slow  # 8-11 s: a local dask cluster; make test-slow runs it
def test_a_cluster_sweep_cancels_its_tasks_and_leaves_the_cluster_free(tmp_path):
    """A LocalCluster in this process (one worker, two threads, both on an hours-long batch when
    Ctrl-C comes): the client exits at once, its tasks leave the scheduler, and the worker's threads are
    free again within seconds (the batches stop at their next kernel call)."""
    distributed = pytest.importorskip("distributed")
    config = _long_study(tmp_path)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, protocol="tcp", dashboard_address=None
    ) as cluster:
        args = [
            "sweep",
            "--config",
            str(config),
            "--results",
            "out",
            "--scheduler",
            cluster.scheduler_address,
        ]
        stopped = _interrupted(tmp_path, args, ready="1/4 samples")
        _assert_study_kept_its_first_batch(stopped, tmp_path / "out")
        with distributed.Client(cluster) as client:
            freed = time.perf_counter()
            assert client.submit(sum, [1, 2], pure=False).result(timeout=10) == 3
            assert client.submit(sum, [3, 4], pure=False).result(timeout=10) == 7
            assert time.perf_counter() - freed < 10
            assert not client.run_on_scheduler(
                lambda dask_scheduler: [k for k in dask_scheduler.tasks if "bbmc" in str(k)]
            )


def test_a_kernel_chunk_of_minutes_hears_a_signal_at_once(tmp_path):
    """A record interval of 10^8 steps (about a minute in one kernel call before): a signal 0.5 s into
    it is acted on within 0.5 s, since the cycles run in calls of about `pace.CALL_SECONDS`."""
    scene = _write(tmp_path / "rest.yaml", _resting_block(monitoring={"every_steps": 100_000_000}))
    model = solver.load_scene(scene)
    solver.simulate(solver.load_scene(_write(tmp_path / "short.yaml", _resting_block(solver={"steps": 10}))))
    signalled = []

    def alarm(signum: int, frame: object) -> None:
        signalled.append(time.perf_counter())
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGALRM, alarm)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.5)
        with pytest.raises((KeyboardInterrupt, SystemError)) as raised:
            solver.simulate(model)
        heard = time.perf_counter()
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert isinstance(raised.value, KeyboardInterrupt) or isinstance(
        raised.value.__cause__.__cause__,
        KeyboardInterrupt,  # numba wraps one raised in its call-backs
    )
    assert heard - signalled[0] < 0.5


def _outputs(result: solver.RunResult) -> list[pd.DataFrame]:
    return [result.history, result.blocks, result.contacts, result.summary]


@pytest.mark.parametrize("name", ["incline", "example"])
def test_kernel_calls_cut_anywhere_give_the_same_numbers(name, monkeypatch):
    """A run whose cycles and contact search go one unit per kernel call, paced as usual, and one
    call per record interval (no pacing): every table equal to the last bit. incline slides through
    contact searches; example has loads ramped and laws updated every 50 steps."""
    scene = ROOT / "configs" / "scenes" / f"{name}.yaml"
    paced = _outputs(solver.simulate(solver.load_scene(scene)))
    monkeypatch.setattr(pace, "CALL_SECONDS", 0.0)
    one_by_one = _outputs(solver.simulate(solver.load_scene(scene)))
    monkeypatch.setattr(pace.Pace, "take", lambda self, left: left)
    whole = _outputs(solver.simulate(solver.load_scene(scene)))
    for a, b, c in zip(paced, one_by_one, whole, strict=True):
        pd.testing.assert_frame_equal(a, b, check_exact=True)
        pd.testing.assert_frame_equal(a, c, check_exact=True)


def test_the_factor_of_safety_is_the_same_however_its_calls_are_cut(monkeypatch):
    """planar_crack's strength-reduction search: every trial's F, verdict and steps, and the FS."""
    model = solver.load_scene(ROOT / "configs" / "scenes" / "planar_crack.yaml")
    paced = factor_of_safety(model)
    monkeypatch.setattr(pace, "CALL_SECONDS", 0.0)
    one_by_one = factor_of_safety(model)
    assert one_by_one.factor_of_safety == paced.factor_of_safety
    assert one_by_one.equilibrium_steps == paced.equilibrium_steps

    def numbers(t):
        return t.factor, t.verdict, t.reason, t.steps, t.largest_displacement_m, t.unbalanced_force_ratio

    assert [numbers(t) for t in one_by_one.trials] == [numbers(t) for t in paced.trials]
    assert (one_by_one.mechanism_world == paced.mechanism_world).all()


def test_a_stopped_thread_ends_its_run_between_kernel_calls(tmp_path):
    """`pace.stopped_when` (how a cancelled task on a dask worker ends): the run ends with
    RunStoppedError at the first call after the stop is asked for."""
    model = solver.load_scene(_write(tmp_path / "rest.yaml", _resting_block()))
    asked = []

    def stop() -> bool:
        asked.append(1)
        return len(asked) > 3

    with pace.stopped_when(stop), pytest.raises(pace.RunStoppedError):
        solver.simulate(model)
    assert len(asked) == 4
    solver.simulate(solver.load_scene(_write(tmp_path / "short.yaml", _resting_block(solver={"steps": 10}))))


def test_ctrl_c_while_results_replace_the_old_ones_waits_for_the_swap(tmp_path, monkeypatch):
    """A SIGINT between the two renames that put new results in place of old ones is held until both
    are done: the folder is the new results, whole, and the interrupt says so."""
    out = tmp_path / "out"
    write_stage(out, StageResult(tables={"old": pd.DataFrame({"a": [1]})}), {})
    real_rename = Path.rename

    def rename_then_signal(self: Path, target: Path) -> Path:
        moved = real_rename(self, target)
        if self == out:  # the old results just moved aside: a Ctrl-C now
            signal.raise_signal(signal.SIGINT)
        return moved

    monkeypatch.setattr(Path, "rename", rename_then_signal)
    with pytest.raises(KeyboardInterrupt, match="the results were complete"):
        write_stage(out, StageResult(tables={"new": pd.DataFrame({"b": [2]})}), {})
    assert sorted(p.name for p in out.iterdir()) == ["new.csv", "provenance.json"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
