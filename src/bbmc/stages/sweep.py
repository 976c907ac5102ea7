"""`bbmc sweep`: a study (`bbmc.sweep.study`) of a limit-equilibrium model or a block scene, its
finished batches kept under <results>/sweep/<name>.progress/, on local processes or a dask.distributed
cluster. What is checked, run and written is in `bbmc.sweep.study`; `bbmc.api.study` runs the same from
Python."""

from __future__ import annotations

from pathlib import Path

from bbmc.io import StageResult
from bbmc.progress import ProgressCallback, ignore
from bbmc.sweep import study
from bbmc.sweep.config import Config
from bbmc.sweep.study import NoValidSampleError

NAME = "sweep"
__all__ = ["NAME", "Config", "NoValidSampleError", "run"]


def run(
    config: Config,
    config_path: Path,
    progress_root: Path,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: ProgressCallback = ignore,
) -> StageResult:
    """The study of `config` (read from `config_path`), resuming from the batches under
    `progress_root`, on the scheduler at that address or on `workers` local processes."""
    return study.run(config, config_path, progress_root, scheduler, workers, progress)
