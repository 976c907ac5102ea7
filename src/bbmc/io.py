"""Files in and out: validated input tables, and a stage's results written atomically with provenance."""

from __future__ import annotations

import hashlib
import json
import platform
import shutil
import signal
import subprocess
import tempfile
import threading
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from pydantic import BaseModel

from bbmc.config import ConfigError

RowCheck = tuple[Callable[[float], bool], str]
POSITIVE: RowCheck = (lambda v: v > 0, "must be > 0")
ANY: RowCheck = (lambda v: True, "")


def read_csv(path: Path, **options: object) -> pd.DataFrame:
    """`pandas.read_csv(path, **options)`; a file that cannot be read as CSV text raises `ConfigError`
    naming it."""
    try:
        return pd.read_csv(path, **options)
    except UnicodeDecodeError as exc:
        raise ConfigError(
            f"{path}: not UTF-8 text (byte {exc.start}): a binary file, or another encoding"
        ) from None
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise ConfigError(f"{path}: cannot read CSV: {str(exc).splitlines()[0]}") from None


def read_table(path: Path, columns: Mapping[str, RowCheck]) -> pd.DataFrame:
    """Read a CSV and check each named column, cell by cell; blank cells are allowed (NaN).

    A missing column, a non-numeric cell or a cell failing its check raises `ConfigError` naming the
    file, the line (header = line 1) and the column.
    """
    table = read_csv(path)
    for name, (check, rule) in columns.items():
        if name not in table.columns:
            raise ConfigError(f"{path}: missing column '{name}'")
        values = pd.to_numeric(table[name], errors="coerce")
        for row, (raw, value) in enumerate(zip(table[name], values, strict=True)):
            line = row + 2
            if pd.isna(raw):
                continue
            if pd.isna(value) or not np.isfinite(value):
                raise ConfigError(f"{path}: line {line}: column '{name}': not a number: {raw!r}")
            if not check(float(value)):
                raise ConfigError(f"{path}: line {line}: column '{name}' {rule}, got {value:g}")
        table[name] = values
    return table


@dataclass
class StageResult:
    """What a stage produces: CSV tables and figures by file name without extension, and other files
    (e.g. the scenes a stage ran) by relative path with extension."""

    tables: dict[str, pd.DataFrame] = field(default_factory=dict)
    figures: dict[str, Figure] = field(default_factory=dict)
    files: dict[str, str | bytes] = field(default_factory=dict)


def _versions() -> dict[str, str]:
    names = [
        "bbmc",
        "numpy",
        "scipy",
        "pandas",
        "numba",
        "matplotlib",
        "pydantic",
        "click",
        "pyyaml",
    ]
    found = {"python": platform.python_version()}
    for name in names:
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            found[name] = "not installed"
    return found


def _git_commit() -> str:
    try:
        run = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
            cwd=Path(__file__).parent,
        )
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return run.stdout.strip()


def provenance(stage: str, config_path: Path, config: BaseModel) -> dict[str, object]:
    """The record written beside a stage's results: what ran, on what config, with which versions."""
    return {
        "stage": stage,
        "config_file": str(config_path),
        "config_sha256": hashlib.sha256(config_path.read_bytes()).hexdigest(),
        "config": config.model_dump(mode="json"),
        "git_commit": _git_commit(),
        "platform": platform.platform(),
        "versions": _versions(),
    }


def write_stage(out_dir: Path, result: StageResult, record: Mapping[str, object]) -> list[Path]:
    """Write tables (CSV), figures (PNG) and provenance.json into `out_dir`, all or nothing.

    Everything is written into a hidden sibling folder first, which then replaces `out_dir`; a failure
    or a Ctrl-C on the way leaves the previous results untouched and no partial folder behind.
    """
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.", dir=out_dir.parent))
    try:
        for name, table in result.tables.items():
            table.to_csv(staging / f"{name}.csv", index=False)
        for name, figure in result.figures.items():
            figure.savefig(staging / f"{name}.png", dpi=figure.dpi, metadata={"Software": None})
        for name, content in result.files.items():
            target = staging / name
            target.parent.mkdir(parents=True, exist_ok=True)
            if isinstance(content, bytes):
                target.write_bytes(content)
            else:
                target.write_text(content)
        (staging / "provenance.json").write_text(json.dumps(record, indent=2) + "\n")
        written = sorted(str(p.relative_to(staging)) for p in staging.rglob("*") if p.is_file())
        with _interrupt_held() as held:
            if out_dir.exists():
                retired = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.old.", dir=out_dir.parent))
                out_dir.rename(retired / out_dir.name)
                staging.rename(out_dir)
                shutil.rmtree(retired)
            else:
                staging.rename(out_dir)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    if held:
        raise KeyboardInterrupt(f"the results were complete when it came, in {out_dir}/")
    return [out_dir / name for name in written]


@contextmanager
def _interrupt_held() -> Iterator[list[int]]:
    """Hold a Ctrl-C (SIGINT) back while the block runs: the renames that put a new results folder in
    place of the old one must not stop between them. Yields the list of signals held, for the caller
    to act on. Handlers can be set only in the main thread: elsewhere the block runs as it is."""
    held: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield held
        return
    previous = signal.signal(signal.SIGINT, lambda signum, _frame: held.append(signum))
    try:
        yield held
    finally:
        signal.signal(signal.SIGINT, previous)
