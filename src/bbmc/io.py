"""Files in and out: validated input tables, and a stage's results written atomically with provenance."""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
import platform
import shutil
import signal
import subprocess
import tempfile
import threading
import warnings
import zipfile
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from importlib import metadata
from pathlib import Path

import pandas as pd
from matplotlib.figure import Figure
from pydantic import BaseModel

from bbmc import plausibility
from bbmc.config import ConfigError


@dataclass(frozen=True)
class Column:
    """What every cell of an input table's column must hold: a finite number from `low` to `high`
    (either end excluded where `*_open`), or any text (`text`); a blank cell only where `blank`.
    `quantity`: a key of `bbmc.plausibility.RANGES` whose quantity the column holds, `scale` times
    its number (or `scale` over it, where `reciprocal`) in the row's unit: a number far beyond that
    range (`plausibility.beyond`) is refused, as in a config."""

    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False
    blank: bool = False
    text: bool = False
    quantity: str | None = None
    scale: float = 1.0
    reciprocal: bool = False

    def holds(self, value: float) -> bool:
        above = value > self.low if self.low_open else value >= self.low
        below = value < self.high if self.high_open else value <= self.high
        return above and below

    @property
    def rule(self) -> str:
        """The range in words, e.g. 'must be > 0', 'must be >= 0 and <= 20'."""
        low = f"{'>' if self.low_open else '>='} {self.low:g}"
        high = f"{'<' if self.high_open else '<='} {self.high:g}"
        if math.isinf(self.high):
            return f"must be {low}"
        if math.isinf(self.low):
            return f"must be {high}"
        return f"must be {low} and {high}"

    def or_blank(self) -> Column:
        return replace(self, blank=True)

    def of(self, quantity: str, scale: float = 1.0, reciprocal: bool = False) -> Column:
        """This column holding `quantity` (see the class)."""
        return replace(self, quantity=quantity, scale=scale, reciprocal=reciprocal)

    def refusal(self, value: float) -> str | None:
        """Why a number within the column's range is still refused (far beyond its quantity's plausible
        range), or None."""
        if self.quantity is None:
            return None
        converted = self.scale / value if self.reciprocal else self.scale * value
        problem = plausibility.beyond(self.quantity, converted)
        if problem is None:
            return None
        unit = plausibility.unit_of(self.quantity)
        shown = "" if converted == value else f" ({plausibility.number(converted)} {unit} as {self.quantity})"
        return f"= {value:g}{shown} {problem}"


NUMBER = Column()
POSITIVE = Column(low=0.0, low_open=True)
NON_NEGATIVE = Column(low=0.0)
ANGLE_DEG = Column(0.0, 90.0, low_open=True, high_open=True)
TEXT = Column(text=True)


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


@dataclass(frozen=True)
class Records:
    """A table's cells as text, as read: the header's line and names, and each data row with its line
    (`word`: what a line is called in messages, 'line' in a CSV file, 'row' in a spreadsheet)."""

    header_line: int
    header: list[str]
    body: list[tuple[int, list[str]]]
    word: str = "line"


def csv_records(path: Path, comments: bool = False) -> Records:
    """The cells of a CSV file (UTF-8, a byte-order mark allowed), blank lines skipped, and lines before
    the header whose first cell starts with '#' where `comments`. `ConfigError` naming the file (and
    line) if it cannot be read as CSV text, is empty or names a column twice."""
    try:
        text = path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ConfigError(
            f"{path}: not UTF-8 text (byte {exc.start}): a binary file, or another encoding"
        ) from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read: {exc.strerror}") from None
    if "\0" in text:
        raise ConfigError(f"{path}: holds a NUL character: a binary file, not a CSV table")
    lines = csv.reader(io.StringIO(text, newline=""))
    try:
        records = [(lines.line_num, row) for row in lines if any(cell.strip() for cell in row)]
    except csv.Error as exc:
        raise ConfigError(f"{path}: line {lines.line_num}: not a CSV table: {exc}") from None
    while comments and records and records[0][1][0].lstrip().startswith("#"):
        records.pop(0)
    return _records(path, records, "line")


def sheet_records(path: Path) -> Records:
    """The cells of the first sheet of an Excel workbook (.xlsx, read by pandas with openpyxl) as text,
    each row numbered as the spreadsheet numbers it; blank rows and columns skipped."""
    try:
        sheet = pd.read_excel(path, sheet_name=0, header=None, dtype=str, keep_default_na=False)
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:
        raise ConfigError(f"{path}: cannot read as an Excel workbook: {str(exc).splitlines()[0]}") from None
    filled = sheet.apply(lambda column: column.str.strip() != "")
    sheet = sheet.loc[filled.any(axis=1), filled.any(axis=0)]
    records = [(int(index) + 1, list(row)) for index, row in zip(sheet.index, sheet.to_numpy(), strict=True)]
    return _records(path, records, "row")


def _records(path: Path, records: list[tuple[int, list[str]]], word: str) -> Records:
    if not records:
        raise ConfigError(f"{path}: the file is empty (a header {word} and data rows are expected)")
    header_line, header = records[0][0], [cell.strip() for cell in records[0][1]]
    for k, name in enumerate(header):
        if name in header[:k]:
            raise ConfigError(f"{path}: {word} {header_line}: column '{name}' is named twice")
    return Records(header_line, header, records[1:], word)


def read_table(path: Path, columns: Mapping[str, Column], rows: int | None = None) -> pd.DataFrame:
    """A CSV (UTF-8, a byte-order mark allowed) as a table of the named columns, each cell checked
    (`checked_table`)."""
    return checked_table(path, csv_records(path), columns, rows)


def checked_table(
    path: Path, records: Records, columns: Mapping[str, Column], rows: int | None = None
) -> pd.DataFrame:
    """The table of the named columns of `records` (read from `path`), each cell checked.

    The header names each column once; every named column is there; every data row has no more cells
    than the header (fewer: the missing ones are blank); a numeric cell is a finite number within its
    column's range, a blank cell only where the column allows it; there is at least one data row, and
    exactly `rows` if given. Any fault raises `ConfigError` naming the file, the line (counted in the
    file, the header's included) and the column. Returns the named columns only, numbers as floats,
    blank cells as NaN (text columns: ''), indexed by each row's line in the file (`line`).
    """
    header, body, word = records.header, records.body, records.word
    if not body:
        raise ConfigError(f"{path}: no data rows under the header")
    if rows is not None and len(body) != rows:
        raise ConfigError(f"{path}: {len(body)} data rows, where the table has {rows}")
    for line, row in body:
        if len(row) > len(header):
            raise ConfigError(f"{path}: {word} {line}: {len(row)} cells, the header names {len(header)}")
    table = {}
    for name, column in columns.items():
        if name not in header:
            raise ConfigError(f"{path}: missing column '{name}'")
        k = header.index(name)
        cells = [(line, row[k].strip() if k < len(row) else "") for line, row in body]
        table[name] = [_cell(path, f"{word} {line}", name, raw, column) for line, raw in cells]
    return pd.DataFrame(table, index=pd.Index([line for line, _ in body], name="line"))


def _cell(path: Path, line: str, name: str, raw: str, column: Column) -> float | str:
    """One cell's value, checked against its column (`line`: where it is, e.g. 'line 4')."""
    where = f"{path}: {line}: column '{name}'"
    if not raw:
        if not column.blank:
            raise ConfigError(f"{where}: blank, a value is needed")
        return "" if column.text else math.nan
    if column.text:
        return raw
    try:
        value = float(raw)
    except ValueError:
        raise ConfigError(f"{where}: not a number: {raw!r}") from None
    if not math.isfinite(value):
        raise ConfigError(f"{where}: not a finite number: {raw!r}")
    if not column.holds(value):
        raise ConfigError(f"{where} {column.rule}, got {value:g}")
    refusal = column.refusal(value)
    if refusal:
        raise ConfigError(f"{where} {refusal}")
    return value


def require_distinct(table: pd.DataFrame, path: Path, name: str, purpose: str, where: str = "") -> None:
    """ConfigError unless column `name` holds at least two different values (`purpose`: what needs
    them, e.g. 'a line is fitted through them'; `where`: which rows, e.g. ' at sigma_n_MPa = 0.05')."""
    found = table[name].nunique()
    if found < 2:
        raise ConfigError(
            f"{path}: column '{name}' needs at least 2 different values{where} ({purpose}), got {found}"
        )


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


class ResultsReplaced(UserWarning):
    """A results folder that another config file had written was replaced (the two share a name)."""


def _warn_if_another_file_wrote(out_dir: Path, record: Mapping[str, object]) -> None:
    """Warn when `out_dir` holds the results of another config file than the one of `record` (by its
    provenance.json): two scenes with the same name write to the same folder, and the second would
    replace the first's without a word."""
    try:
        before = json.loads((out_dir / "provenance.json").read_text()).get("config_file")
    except (OSError, ValueError, AttributeError):
        return
    now = record.get("config_file")
    if before and now and Path(str(before)).resolve() != Path(str(now)).resolve():
        warnings.warn(
            f"{out_dir}/ held the results of {before}, replaced by those of {now}: the two share a "
            "name; give one its own `name` to keep both",
            ResultsReplaced,
            stacklevel=3,
        )


def write_stage(out_dir: Path, result: StageResult, record: Mapping[str, object]) -> list[Path]:
    """Write tables (CSV), figures (PNG) and provenance.json into `out_dir`, all or nothing.

    Everything is written into a hidden sibling folder first, which then replaces `out_dir`; a failure
    or a Ctrl-C on the way leaves the previous results untouched and no partial folder behind. Results
    that another config file wrote there are replaced with a warning (`ResultsReplaced`).
    """
    _warn_if_another_file_wrote(out_dir, record)
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
