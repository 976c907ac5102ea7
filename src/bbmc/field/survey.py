"""Reading a scanline survey: one row per discontinuity the line crosses, checked cell by cell.

Columns (a header row; lines starting with # before it are a comment):

    set                 the set the discontinuity was assigned to in the field (text)
    position_m          distance along the scanline from its start [m], 0 to its length
    dip_deg             dip [deg], 0 to 90
    dip_direction_deg   dip direction [deg], 0 to 360 (optional: the column, or a set's cells, blank)
    trace_length_m      visible trace length [m], > 0
    censored_ends       how many ends of the trace are hidden (beyond the exposure): 0, 1 or 2

Any fault is one `ConfigError` naming the file, its line (the header's line counts) and the column.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc import units
from bbmc.config import ConfigError
from bbmc.io import read_csv

NUMBERS = {
    "position_m": (0.0, np.inf, "a distance along the scanline, >= 0"),
    "dip_deg": (0.0, 90.0, "a dip, 0 to 90"),
    "dip_direction_deg": (0.0, 360.0, "a dip direction, 0 to 360"),
    "trace_length_m": (0.0, np.inf, "a trace length, > 0"),
    "censored_ends": (0.0, 2.0, "the number of hidden ends: 0, 1 or 2"),
}
REQUIRED = ("set", "position_m", "dip_deg", "trace_length_m", "censored_ends")


@dataclass(frozen=True)
class SetSurvey:
    """One set's discontinuities in order along the line, in SI (m, rad); `lines` are their lines in the
    file. `dip_direction` is None for a set mapped without dip directions."""

    name: str
    position: np.ndarray
    dip: np.ndarray
    dip_direction: np.ndarray | None
    trace_length: np.ndarray
    censored_ends: np.ndarray
    lines: np.ndarray
    resolution: float  # [m] the reading of the positions: two joints closer than it share a position


def _comment_lines(path: Path) -> int:
    count = 0
    try:
        with path.open("rb") as handle:
            for text in handle:
                if not text.startswith(b"#"):
                    break
                count += 1
    except OSError as error:
        raise ConfigError(f"{path}: cannot read: {error.strerror}") from None
    return count


def read_rows(path: Path) -> tuple[pd.DataFrame, int]:
    """The survey's rows as text, and the file line of its first row."""
    skipped = _comment_lines(path)
    table = read_csv(path, skiprows=skipped, dtype=str, keep_default_na=False, skipinitialspace=True)
    for column in REQUIRED:
        if column not in table.columns:
            raise ConfigError(
                f"{path}: missing column '{column}' (columns: {', '.join(REQUIRED)}; "
                "dip_direction_deg optional)"
            )
    if table.empty:
        raise ConfigError(f"{path}: no rows below the header")
    return table, skipped + 2


def set_names(path: Path) -> dict[str, int]:
    """The sets named in the survey, each with the file line of its first row."""
    table, first = read_rows(path)
    names: dict[str, int] = {}
    for row, name in enumerate(table["set"].str.strip()):
        if not name:
            raise ConfigError(f"{path}: line {first + row}: column 'set': empty")
        names.setdefault(name, first + row)
    return names


def _numbers(path: Path, table: pd.DataFrame, first: int, column: str) -> np.ndarray:
    low, high, meaning = NUMBERS[column]
    text = table[column].str.strip()
    values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=float)
    for row, (raw, value) in enumerate(zip(text, values, strict=True)):
        where = f"{path}: line {first + row}: column '{column}'"
        if not raw:
            if column == "dip_direction_deg":
                continue
            raise ConfigError(f"{where}: empty")
        if not np.isfinite(value):
            raise ConfigError(f"{where}: not a number: {raw!r}")
        positive = column == "trace_length_m"
        if value < low or value > high or (positive and value <= 0):
            raise ConfigError(f"{where}: must be {meaning}, got {value:g}")
        if column == "censored_ends" and value != round(value):
            raise ConfigError(f"{where}: must be {meaning}, got {value:g}")
    return values


def _resolution(positions: pd.Series) -> float:
    """The reading of the positions [m]: 10^-d for the most decimals d written in the column."""
    decimals = positions.str.strip().str.partition(".")[2].str.len()
    return 10.0 ** -int(decimals.max())


def read_survey(path: Path, length_m: float, known_sets: Collection[str]) -> dict[str, SetSurvey]:
    """The survey's sets (those of `known_sets`, in that order), checked row by row: positions within
    the scanline's `length_m`, a set's dip directions all given or all blank."""
    table, first = read_rows(path)
    names = table["set"].str.strip()
    for row, name in enumerate(names):
        if name not in known_sets:
            given = ", ".join(known_sets)
            raise ConfigError(
                f"{path}: line {first + row}: column 'set': set '{name}' is not among the config's sets "
                f"({given})"
            )
    columns = {c: _numbers(path, table, first, c) for c in NUMBERS if c in table.columns}
    beyond = np.flatnonzero(columns["position_m"] > length_m)
    if beyond.size:
        row = beyond[0]
        raise ConfigError(
            f"{path}: line {first + row}: column 'position_m': {columns['position_m'][row]:g} m is beyond "
            f"the scanline's length of {length_m:g} m (scanline.length_m)"
        )
    lines = np.arange(len(table)) + first
    resolution = _resolution(table["position_m"])
    sets = {}
    for name in known_sets:
        rows = np.flatnonzero(names.to_numpy() == name)
        rows = rows[np.argsort(columns["position_m"][rows], kind="stable")]
        position = columns["position_m"][rows]
        directions = columns.get("dip_direction_deg")
        direction = None if directions is None else directions[rows]
        if direction is not None and np.isnan(direction).all():
            direction = None
        elif direction is not None and np.isnan(direction).any():
            row = rows[np.flatnonzero(np.isnan(direction))[0]]
            raise ConfigError(
                f"{path}: line {lines[row]}: column 'dip_direction_deg': empty while other rows of set "
                f"'{name}' give one: give every dip direction of a set, or none"
            )
        sets[name] = SetSurvey(
            name=name,
            position=position * units.m,
            dip=columns["dip_deg"][rows] * units.deg,
            dip_direction=None if direction is None else direction * units.deg,
            trace_length=columns["trace_length_m"][rows] * units.m,
            censored_ends=columns["censored_ends"][rows].astype(int),
            lines=lines[rows],
            resolution=resolution,
        )
    return sets
