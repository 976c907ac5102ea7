"""Studies from Python: any study `bbmc sweep` runs (sampled, crossed, Sobol, a grid with or without
realizations), locally or on the caller's dask cluster, its tables as DataFrames and its files on demand.

    from bbmc import api
    result = api.study("configs/sweeps/planar_block.yaml")          # or a dict, or a validated study
    result.samples, result.summary                                  # pandas DataFrames
    result.write("results/sweep/planar_block")                     # the files `bbmc sweep` writes

The work is `bbmc.sweep.study`'s, the same as the command's: the same study gives the same samples
byte for byte. Without a `client`, the samples run on `workers` local processes (default every core);
with a `distributed.Client`, on its cluster, the engine compiled once per machine before the batches
start, the cluster left running for the caller to close.
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd
import yaml
from matplotlib.figure import Figure

from bbmc.config import load_config, validate
from bbmc.io import StageResult, provenance, write_stage
from bbmc.progress import ProgressCallback, ignore
from bbmc.sweep import study as studies
from bbmc.sweep.config import Config

if TYPE_CHECKING:
    from distributed import Client

DICT_SOURCE = "<study dict>"


@dataclass
class StudyResult:
    """A study's results, as `bbmc sweep` writes them.

    Attributes:
        config: the validated study.
        source: the study file it was read from, or "<study dict>".
        tables: every table by its file name without ".csv": samples (each sample's inputs, FS or the
            monitor, error, outcome), summary (quantity, value, unit), and as the study has them
            convergence, sensitivity, geometry_share, fs_against_parameter (a grid study).
        figures: every figure by its file name without ".png" (matplotlib figures).
    """

    config: Config
    source: str
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)
    figures: dict[str, Figure] = field(default_factory=dict)

    @property
    def samples(self) -> pd.DataFrame:
        """Each sample's inputs (by dotted path, in the key's unit), its FS [-] (or the monitor of a
        scene_run study), error and outcome (valid, invalid, failed_run, impossible_input)."""
        return self.tables["samples"]

    @property
    def summary(self) -> pd.DataFrame:
        """summary.csv: quantity, value, unit (the counts; a sampled study's P_f, its interval,
        reliability indices and FS statistics; the truncations)."""
        return self.tables["summary"]

    def write(self, folder: str | Path) -> list[Path]:
        """Write the tables (CSV), figures (PNG) and provenance.json into `folder`, as `bbmc sweep` does
        into results/sweep/<name>/ (all or nothing); return the files written."""
        record = _record(self.config, self.source)
        return write_stage(Path(folder), StageResult(self.tables, self.figures), record)


def _record(config: Config, source: str) -> dict[str, object]:
    """provenance.json's record: of the study file, or for a study given as a dict or a validated
    config, of its YAML dump (config_sha256 is then that text's)."""
    if source != DICT_SOURCE:
        return provenance("sweep", Path(source), config)
    with tempfile.TemporaryDirectory() as folder:
        dump = Path(folder) / "study.yaml"
        dump.write_text(yaml.safe_dump(config.model_dump(mode="json"), sort_keys=True))
        return provenance("sweep", dump, config) | {"config_file": DICT_SOURCE}


def load_study(source: Config | str | Path | Mapping) -> tuple[Config, str]:
    """A validated study and where it came from: a study file (its paths relative to it), a dict in the
    same form (paths relative to the working folder) or a validated `Config`; `ConfigError`, one line,
    on any fault."""
    if isinstance(source, Config):
        return source, DICT_SOURCE
    if isinstance(source, Mapping):
        return validate(dict(source), Config, DICT_SOURCE), DICT_SOURCE
    return load_config(source, Config), str(source)


def study(
    config: Config | str | Path | Mapping,
    client: Client | None = None,
    workers: int | None = None,
    progress: ProgressCallback = ignore,
    keep: str | Path | None = None,
) -> StudyResult:
    """Run a study as `bbmc sweep` does and return its tables and figures (nothing written but the
    finished batches, and those only with `keep`).

    Args:
        config: a study file (docs/reference/study-format.md), a dict in its form, or a `Config`.
        client: a `distributed.Client` whose cluster runs the batches (one dask task each); the
            engine is compiled once per machine before they start, and the cluster stays up.
        workers: without a client, the local processes [default: every core].
        progress: told each batch done and each line `bbmc sweep` prints (`bbmc.progress.Progress`,
            unit "samples").
        keep: a folder for the finished batches (under <keep>/<name>.progress/), so that the same call
            after an interruption runs only the rest; default a temporary folder, removed at the end.

    Raises `ConfigError` (bad input, before any sample runs), `NoValidSampleError` (no sample gave a
    result), `StudyInterrupted` (Ctrl-C: how many samples are kept, with `keep`).
    """
    settings, source = load_study(config)
    path = Path(source)
    if keep is not None:
        result = studies.run(settings, path, Path(keep), client, workers, progress)
    else:
        with tempfile.TemporaryDirectory(prefix="bbmc-study-") as folder:
            result = studies.run(settings, path, Path(folder), client, workers, progress)
    return StudyResult(settings, source, result.tables, result.figures)
