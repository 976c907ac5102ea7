"""Studies from Python (`bbmc.api.study`): the command's samples byte for byte, its files on demand,
progress through `bbmc.progress.Progress`; parameter studies (a grid with paired realizations) give FS
against the parameter, not P_f; on a dask LocalCluster the workers load the engine the study warmed
(nothing compiled by them) and the cluster shuts down without killing a worker."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner

from bbmc import api, kernel_cache
from bbmc.cli import main
from bbmc.progress import Progress
from bbmc.slope import fos_cases as fc

ROOT = Path(__file__).resolve().parents[1]
PLANAR = ROOT / "configs" / "sweeps" / "planar_block.yaml"


def _write(path: Path, data: dict) -> Path:
    path.write_text(yaml.safe_dump(data))
    return path


def _planar(samples: int = 400, batch: int = 100) -> dict:
    data = yaml.safe_load(PLANAR.read_text())
    data["sampling"]["samples"] = samples
    data["batch_size"] = batch
    return data


def _cli(study: Path, results: Path, *options: str) -> Path:
    outcome = CliRunner().invoke(main, ["sweep", str(study), "--results", str(results), *options])
    assert outcome.exit_code == 0, outcome.output
    return results / "sweep"


def _paired_grid(realizations: int = 4) -> dict:
    """The dry cohesionless planar block on its 35 deg plane at three face angles, tan phi drawn once
    per realization: FS = tan phi / tan 35 deg at every face angle (the face does not enter it), so
    each realization's FS is the same at every grid point when the draws are paired."""
    data = _planar()
    data["name"] = "face_chart"
    data["grid"] = [{"path": "face_deg", "values": [45.0, 60.0, 75.0]}]
    data["sampling"] = {"method": "grid", "realizations": realizations, "seed": 4}
    return data


def _saltelli() -> dict:
    data = _planar()
    data["sampling"] = {"method": "saltelli", "samples": 64, "seed": 2}
    return data


def _crossed() -> dict:
    """The plane's dip as the geometry (drawn once per realization), tan phi the other input."""
    data = _planar()
    data["variables"].append(
        {"path": "plane_deg", "distribution": "normal", "mean": 35, "std": 2, "geometry": True}
    )
    data["sampling"] = {"method": "latin_hypercube", "realizations": 8, "samples": 4, "seed": 2}
    return data


@pytest.mark.parametrize("make", [_planar, _saltelli, _crossed, _paired_grid], ids=lambda f: f.__name__)
def test_a_study_from_python_gives_the_commands_samples_and_files(tmp_path, make):
    """The same study file through `bbmc sweep` and `api.study` (from the file, from a dict), for a
    sampled, a Saltelli, a crossed and a grid study: `write` gives the same files, every table byte for
    byte; the result's samples are those of the file."""
    data = make()
    study = _write(tmp_path / "study.yaml", data)
    out = _cli(study, tmp_path / "cli") / data["name"]
    for k, source in enumerate((study, yaml.safe_load(study.read_text()))):
        result = api.study(source, workers=1)
        written = result.write(tmp_path / f"api{k}")
        assert sorted(p.name for p in written) == sorted(p.name for p in out.iterdir())
        for table in out.glob("*.csv"):
            assert (tmp_path / f"api{k}" / table.name).read_bytes() == table.read_bytes(), table.name
        numbers = [column for column in result.samples.columns if column not in ("error", "outcome")]
        samples = pd.read_csv(out / "samples.csv")
        pd.testing.assert_frame_equal(result.samples[numbers], samples[numbers], check_exact=True)


def test_a_study_reports_its_samples_through_the_progress_protocol(tmp_path):
    news: list[Progress] = []
    api.study(_planar(400, 100), workers=1, progress=news.append)
    counts = [n for n in news if n.text.endswith("s left")]
    assert [n.done for n in counts] == [100, 200, 300, 400]
    assert all(n.total == 400 and n.unit == "samples" for n in news)
    assert any(n.text.startswith("P_f = ") for n in news)


def test_a_grid_over_realizations_gives_fs_against_the_parameter_not_p_f(tmp_path):
    """The paired grid: every realization's FS equals tan phi_r / tan 35 deg at each face angle (1e-12),
    the same draws at every grid point; fs_against_parameter.csv's least, median and largest FS are
    those of the realizations; no P_f, sensitivity or tornado; the chart is drawn."""
    result = api.study(_paired_grid(4), workers=1)
    samples = result.samples
    assert len(samples) == 12 and list(samples["sample"]) == list(range(12))
    tan_phi = samples["strength.tan_friction"].to_numpy().reshape(3, 4)
    assert (tan_phi == tan_phi[0]).all() and len(set(tan_phi[0])) == 4  # paired: the same 4 draws
    fs = samples["factor_of_safety"].to_numpy().reshape(3, 4)
    np.testing.assert_allclose(fs, tan_phi / math.tan(math.radians(35.0)), rtol=1e-12)
    chart = result.tables["fs_against_parameter"]
    assert list(chart["face_deg"]) == [45.0, 60.0, 75.0]
    assert list(chart["runs"]) == [4, 4, 4] and list(chart["excluded"]) == [0, 0, 0]
    np.testing.assert_allclose(chart["fs_min"], fs.min(axis=1), rtol=0)
    np.testing.assert_allclose(chart["fs_median"], np.median(fs, axis=1), rtol=0)
    np.testing.assert_allclose(chart["fs_max"], fs.max(axis=1), rtol=0)
    assert list(chart["below_one"]) == list((fs < 1.0).sum(axis=1))
    assert "probability_of_failure" not in set(result.summary["quantity"])
    assert set(result.tables) == {"samples", "summary", "fs_against_parameter"}
    assert set(result.figures) == {"fs_against_parameter"}
    ax = result.figures["fs_against_parameter"].axes[0]
    assert ax.get_xlabel() == "face [deg]" and ax.get_ylabel() == "factor of safety FS [-]"


def test_a_grid_study_prints_fs_per_grid_point_and_no_p_f(tmp_path):
    study = _write(tmp_path / "study.yaml", _paired_grid(3))
    outcome = CliRunner().invoke(main, ["sweep", str(study), "--results", str(tmp_path / "out")])
    assert outcome.exit_code == 0, outcome.output
    assert "P_f" not in outcome.output and "tornado" not in outcome.output
    points = [line for line in outcome.output.splitlines() if line.startswith("bbmc sweep: face_deg ")]
    assert len(points) == 3 and all("over 3 runs" in line for line in points), outcome.output
    assert (tmp_path / "out" / "sweep" / "face_chart" / "fs_against_parameter.png").is_file()


@pytest.mark.parametrize(
    ("change", "fragment"),
    [
        ({"sampling": {"method": "grid"}}, "takes `variables` only with sampling.realizations"),
        ({"variables": [], "sampling": {"method": "grid", "realizations": 3}}, "give one"),
        ({"sampling": {"method": "grid", "realizations": 3, "samples": 5}}, "sampling.samples is not used"),
        ({"grid": []}, "needs `grid` axes"),
    ],
)
def test_a_grid_study_that_cannot_be_designed_is_refused_in_one_line(tmp_path, change, fragment):
    data = _paired_grid(3) | change
    outcome = CliRunner().invoke(main, ["sweep", str(_write(tmp_path / "s.yaml", data)), "--results", "o"])
    assert outcome.exit_code == 2, outcome.output
    (line,) = outcome.output.strip().splitlines()
    assert line.startswith(f"bbmc sweep: error: {tmp_path / 's.yaml'}") and fragment in line, line


def _block_study(tmp_path: Path) -> dict:
    """The DEM FS of the block on a 30 deg plane (`bbmc.slope.fos_cases`) on a grid of four friction
    angles: a grid runs no FS at the mean inputs first, so its batches are the study's first runs."""
    scene = _write(tmp_path / "scene.yaml", fc.block_on_plane(fc.MOHR_COULOMB, 0.8, 0.2))
    return {
        "name": "block_fos",
        "base": {"kind": "scene_fos", "scene": str(scene)},
        "grid": [{"path": "joint_laws.joint.friction_deg", "values": [31.0, 33.0, 35.0, 37.0]}],
        "sampling": {"method": "grid"},
        "batch_size": 1,
    }


class _Kills(logging.Handler):
    """The nanny's warnings that it killed a worker that did not exit in time."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.lines: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        if "still alive" in record.getMessage():
            self.lines.append(record.getMessage())


def _exits_quickly() -> bool:
    """On a worker: whether it is set to exit without the garbage collector's last sweeps."""
    from bbmc.sweep import runner

    return runner._freezing_at_exit


def _cluster_study(tmp_path: Path) -> tuple[list[Path], list[str], pd.DataFrame]:
    """The block study on a 2-worker LocalCluster (processes): the kernels written into the workers'
    cache after the study's warm-up (from its line announcing the batches to the end), the nanny's kill
    warnings at shutdown, and the samples."""
    distributed = pytest.importorskip("distributed")
    folder = kernel_cache.cache_root() / kernel_cache.source_key()  # the workers' (same source, same env)
    before: list[dict[Path, float]] = []  # the cache's kernel files when the batches were announced

    def progress(news: Progress) -> None:
        if "batches of up to" in news.text:
            before.append(kernel_cache.kernel_files(folder))

    kills = _Kills()
    logging.getLogger("distributed.nanny").addHandler(kills)
    try:
        with (
            distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster,
            distributed.Client(cluster) as client,
        ):
            result = api.study(_block_study(tmp_path), client=client, progress=progress)
            assert all(client.run(_exits_quickly).values())  # each worker set to skip the last sweeps
    finally:
        logging.getLogger("distributed.nanny").removeHandler(kills)
    assert len(before) == 1, "the study announced its batches once"
    return kernel_cache.written_since(before[0], folder), kills.lines, result.samples


@pytest.mark.slow  # 8-11 s: a local dask cluster; make test-slow runs it
def test_a_cluster_studys_workers_load_the_engine_and_shut_down_cleanly(tmp_path):
    """Not timed: the workers compile nothing (every kernel file in the cache is as it was when the
    batches started), the samples are those of one local process, each worker is set to exit quickly,
    and closing the cluster kills no worker (its nanny waits 4 s for each to exit; on a busy machine
    a worker tearing its objects down took longer)."""
    written, kills, samples = _cluster_study(tmp_path)
    assert written == [] and kills == []
    local = api.study(_block_study(tmp_path), workers=1).samples
    pd.testing.assert_frame_equal(samples, local, check_exact=True)


@pytest.mark.slow
def test_on_a_cold_cache_the_engine_is_compiled_once_before_the_workers_start(tmp_path, monkeypatch):
    """A fresh kernel cache for the cluster's workers: one of them compiles the engine before the
    batches start, and the batches compile nothing."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.delenv("NUMBA_DISABLE_JIT", raising=False)
    written, kills, _ = _cluster_study(tmp_path)
    assert kernel_cache.kernel_files(kernel_cache.cache_root() / kernel_cache.source_key())  # it warmed
    assert written == [] and kills == []
