"""The joint sets `bbmc kinematics` found, read back from its sets.csv for another analysis (the wedges
of every pair of sets, `bbmc wedge`'s `combinations.sets_file`).

sets.csv has a row per set: `set` (its name), `dip_deg`, `dip_direction_deg` (the Terzaghi-weighted mean
plane, degrees), `fisher_k` and the set's statistics (docs/reference/kinematics-command.md). A row named
`random` (the readings in no set) is not a set and is skipped. A file that is not such a table, a
missing column, a dip outside 0 to 90 or a dip direction outside 0 to 360, a name given twice: one
line naming the file, the row and the column (`ConfigError`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from bbmc.config import ConfigError

COLUMNS = ("set", "dip_deg", "dip_direction_deg")
RANDOM = "random"


@dataclass(frozen=True)
class SetPlane:
    """A set's mean plane: dip and dip direction [deg] and Fisher's K (NaN where the file has none)."""

    dip_deg: float
    dip_direction_deg: float
    fisher_k: float


def _number(path: Path, row: int, column: str, text: object, low: float, high: float) -> float:
    try:
        value = float(text)
    except (TypeError, ValueError):
        value = math.nan
    if not low <= value <= high:
        raise ConfigError(
            f"{path}: row {row}, column '{column}': {text!r} is not a number from {low:g} to {high:g}"
        )
    return value


def read_set_planes(path: Path) -> dict[str, SetPlane]:
    """The sets of a `bbmc kinematics` sets.csv by name, in the file's order (module docstring)."""
    try:
        table = pd.read_csv(path, dtype=str, keep_default_na=False)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as error:
        raise ConfigError(f"{path}: not a sets table: {error}") from None
    missing = [c for c in COLUMNS if c not in table.columns]
    if missing:
        raise ConfigError(
            f"{path}: missing column '{missing[0]}' (bbmc kinematics' sets.csv has {', '.join(COLUMNS)})"
        )
    planes: dict[str, SetPlane] = {}
    for index, row in table.iterrows():
        line = int(index) + 2  # the header is line 1
        name = row["set"].strip()
        if name == RANDOM:
            continue
        if not name or name in planes:
            raise ConfigError(f"{path}: row {line}, column 'set': {name!r} is empty or given twice")
        planes[name] = SetPlane(
            _number(path, line, "dip_deg", row["dip_deg"], 0.0, 90.0),
            _number(path, line, "dip_direction_deg", row["dip_direction_deg"], 0.0, 360.0),
            float(row["fisher_k"]) if row.get("fisher_k", "") not in ("", None) else math.nan,
        )
    if not planes:
        raise ConfigError(f"{path}: no set in the table (only '{RANDOM}' or no rows)")
    return planes
