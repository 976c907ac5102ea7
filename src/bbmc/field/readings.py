"""Reading a survey of orientation readings as recorded: one row per discontinuity, its plane in one of
four conventions, with the geometry it was sampled on, checked cell by cell (docs/reference/orientation-
data.md).

A CSV file (lines starting with # before the header are a comment) or an Excel workbook (.xlsx, its
first sheet). Columns, in degrees and metres:

    dip_deg, dip_direction_deg           convention `dip_direction`
    strike_deg, dip_deg                  convention `strike_rhr` (right-hand rule: it dips to the right)
    pole_trend_deg, pole_plunge_deg      convention `pole` (the lower-hemisphere pole)
    alpha_deg, beta_deg                  convention `core`, with hole_trend_deg, hole_plunge_deg (or the
                                         hole given once) and the reference line ("top" or "bottom")
    line_trend_deg, line_plunge_deg      the scanline or borehole the reading was sampled on, or
    face_dip_deg, face_dip_direction_deg the mapped face (or the sampling geometry given once)
    weight                               the reading's own weight (e.g. how many identical features), > 0
    type, location, set                  text: joint, bedding, fault...; where; a set named in the field
    trace_length_m, position_m           trace length > 0; distance along the scanline >= 0
    censored_ends                        how many ends of the trace are hidden: 0, 1 or 2

Every column is optional but those of a convention; other columns are left alone. A row's convention is
the one whose columns it fills (dip_direction_deg, strike_deg, pole_*, alpha_* / beta_*); the caller's
`convention` reads that convention's columns only. Azimuths may be written as quadrant bearings (N30E,
S45W), a column all in one form. Any fault is one `ConfigError` naming the file, the row's line and the
column.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc import units
from bbmc.config import ConfigError
from bbmc.geometry.conventions import (
    CORE_REFERENCES,
    core_poles,
    dip_direction_of_strike,
    plane_of_pole_trend_and_plunge,
    true_azimuth,
)
from bbmc.geometry.orientation import (
    DIPS_MAX_WEIGHT,
    face_weights,
    line_vectors,
    plane_of_pole,
    poles,
    terzaghi_weights,
)
from bbmc.io import NON_NEGATIVE, POSITIVE, Column, Records, checked_table, csv_records, sheet_records

CONVENTIONS = {
    "dip_direction": ("dip_deg", "dip_direction_deg"),
    "strike_rhr": ("strike_deg", "dip_deg"),
    "pole": ("pole_trend_deg", "pole_plunge_deg"),
    "core": ("alpha_deg", "beta_deg"),
}
# The cells that say a row is in a convention (dip_deg is shared by two).
MARKS = {
    "dip_direction": ("dip_direction_deg",),
    "strike_rhr": ("strike_deg",),
    "pole": CONVENTIONS["pole"],
    "core": CONVENTIONS["core"],
}
AZIMUTHS = (
    "dip_direction_deg",
    "strike_deg",
    "pole_trend_deg",
    "hole_trend_deg",
    "line_trend_deg",
    "face_dip_direction_deg",
)
QUARTER = Column(0.0, 90.0).or_blank()
NUMBERS = {
    **dict.fromkeys(AZIMUTHS, Column(0.0, 360.0).or_blank()),
    **dict.fromkeys(("dip_deg", "pole_plunge_deg", "alpha_deg", "line_plunge_deg", "face_dip_deg"), QUARTER),
    "beta_deg": Column(0.0, 360.0).or_blank(),
    "hole_plunge_deg": Column(-90.0, 90.0).or_blank(),
    "weight": POSITIVE.or_blank(),
    "trace_length_m": POSITIVE.or_blank(),
    "position_m": NON_NEGATIVE.or_blank(),
    "censored_ends": Column(0.0, 2.0).or_blank(),
}
TEXTS = ("type", "location", "set")
GEOMETRIES = {
    "line": ("line_trend_deg", "line_plunge_deg"),
    "face": ("face_dip_deg", "face_dip_direction_deg"),
}
HOLE = ("hole_trend_deg", "hole_plunge_deg")
QUADRANT = re.compile(r"^([NS])\s*(\d+(?:\.\d*)?)\s*°?\s*([EW])$", re.IGNORECASE)


@dataclass(frozen=True)
class SamplingLine:
    """A scanline or borehole every reading without its own geometry was sampled on (or the hole of
    core readings): `trend`, `plunge` [rad] (a hole's plunge < 0: drilled upward)."""

    trend: float
    plunge: float


@dataclass(frozen=True)
class SamplingFace:
    """A mapped face every reading without its own geometry was sampled on: `dip`, `dip_direction` [rad]."""

    dip: float
    dip_direction: float


Sampling = SamplingLine | SamplingFace


@dataclass(frozen=True)
class Readings:
    """A survey's readings in file order, in SI (rad, m). `weights` = the reading's own weight times its
    Terzaghi weight `terzaghi` (1 / |cos delta| on a line, 1 / sin theta on a face, capped at
    `max_weight`; 1 where no sampling geometry is known); text columns '' and numbers NaN where blank."""

    path: Path
    poles: np.ndarray  # (n, 3) upward unit normals
    dip: np.ndarray
    dip_direction: np.ndarray
    weights: np.ndarray
    terzaghi: np.ndarray
    max_weight: float
    convention: np.ndarray  # per reading, a key of CONVENTIONS
    kind: np.ndarray  # column `type`
    location: np.ndarray
    set_label: np.ndarray
    trace_length: np.ndarray  # [m]
    position: np.ndarray  # [m] along the scanline
    censored_ends: np.ndarray  # 0, 1 or 2 hidden ends of the trace (NaN: not recorded)
    lines: np.ndarray  # each reading's line (row) in the file

    @property
    def count(self) -> int:
        return int(self.lines.size)


def _azimuth_text(path: Path, records: Records, column: str) -> Records:
    """`records` with the quadrant bearings of `column` (N30E = 30, S30E = 150, S30W = 210, N30W = 330)
    written as azimuths; a column mixing bearings and azimuths is refused."""
    k = records.header.index(column)
    body, first = [], {}
    for line, row in records.body:
        raw = row[k].strip() if k < len(row) else ""
        match = QUADRANT.match(raw)
        form = "a quadrant bearing" if match else "an azimuth"
        if raw:
            first.setdefault(form, (line, raw))
            if len(first) == 2:
                (l1, r1), (l2, r2) = first["an azimuth"], first["a quadrant bearing"]
                raise ConfigError(
                    f"{path}: {records.word} {line}: column '{column}': mixed conventions in one column: "
                    f"{r1!r} ({records.word} {l1}) is an azimuth, {r2!r} ({records.word} {l2}) a quadrant "
                    "bearing: write the column in one form"
                )
        if match:
            start, angle, end = match.group(1).upper(), float(match.group(2)), match.group(3).upper()
            if angle > 90.0:
                raise ConfigError(
                    f"{path}: {records.word} {line}: column '{column}': the quadrant bearing {raw!r} must "
                    "turn 0 to 90 degrees from N or S"
                )
            base, sign = (0.0, 1.0) if start == "N" else (180.0, -1.0)
            raw = f"{(base + sign * angle * (1.0 if end == 'E' else -1.0)) % 360.0!r}"
            row = [*row[:k], raw, *row[k + 1 :]]
        body.append((line, row))
    return Records(records.header_line, records.header, body, records.word)


def _conventions(path: Path, header: list[str], convention: str | None) -> list[str]:
    """The conventions the file's columns hold (`convention` alone where given), each complete."""
    if convention is not None and convention not in CONVENTIONS:
        raise ConfigError(
            f"{path}: convention '{convention}' is unknown: use one of {', '.join(CONVENTIONS)}, or none "
            "to choose it from the columns"
        )
    found = [convention] if convention else [c for c in CONVENTIONS if set(MARKS[c]) & set(header)]
    if not found:
        pairs = "; ".join(" and ".join(columns) for columns in CONVENTIONS.values())
        raise ConfigError(f"{path}: no orientation columns: give {pairs}")
    for name in found:
        for column in CONVENTIONS[name]:
            if column not in header:
                raise ConfigError(f"{path}: missing column '{column}' (convention '{name}')")
    return found


def _row_conventions(path: Path, table: pd.DataFrame, found: list[str], word: str) -> np.ndarray:
    """Each row's convention: the one whose marking cells it fills, exactly one, its cells all given."""
    marked = np.array([table[list(MARKS[c])].notna().any(axis=1).to_numpy() for c in found])
    counts = marked.sum(axis=0)
    if (counts != 1).any():
        row = np.argmax(counts != 1)
        names = [found[k] for k in np.flatnonzero(marked[:, row])]
        marks = [c for name in names or found for c in MARKS[name]]
        problem = (
            f"mixed conventions in one row: {', '.join(marks)} all given (choose one with `convention`)"
            if names
            else f"no orientation in this row: fill {' or '.join(marks)}"
        )
        raise ConfigError(f"{path}: {word} {table.index[row]}: column '{marks[0]}': {problem}")
    convention = np.array(found, dtype=object)[np.argmax(marked, axis=0)]
    for name in found:
        for column in CONVENTIONS[name]:
            blank = (convention == name) & table[column].isna().to_numpy()
            if blank.any():
                line = table.index[np.argmax(blank)]
                raise ConfigError(f"{path}: {word} {line}: column '{column}': blank, a value is needed")
    return convention


def _pairs(path: Path, table: pd.DataFrame, columns: tuple[str, str], word: str) -> np.ndarray:
    """Rows filling both `columns` (True), neither (False); one alone is refused."""
    present = [c for c in columns if c in table.columns]
    if not present:
        return np.zeros(len(table), dtype=bool)
    filled = table[present].notna().to_numpy()
    for row in np.flatnonzero(filled.any(axis=1) & ~(filled.all(axis=1) & (len(present) == 2))):
        missing = next(c for c in columns if c not in table.columns or np.isnan(table[c].iloc[row]))
        raise ConfigError(
            f"{path}: {word} {table.index[row]}: column '{missing}': blank, while "
            f"'{(set(columns) - {missing}).pop()}' is given: give both or neither"
        )
    return filled.all(axis=1) & (len(present) == 2)


def _angles(table: pd.DataFrame, column: str, declination: float) -> np.ndarray:
    """A column's angles [rad] (NaN where blank or the column is absent), azimuths turned true."""
    if column not in table.columns:
        return np.full(len(table), np.nan)
    values = table[column].to_numpy(dtype=float) * units.deg
    return true_azimuth(values, declination) if column in AZIMUTHS else values


def _holes(
    path: Path,
    table: pd.DataFrame,
    core: np.ndarray,
    sampling: Sampling | None,
    declination: float,
    word: str,
) -> tuple[np.ndarray, np.ndarray]:
    """Each core row's hole, trend and plunge [rad] (NaN elsewhere): its own, else the caller's line."""
    own = _pairs(path, table, HOLE, word)
    trend, plunge = (_angles(table, c, declination) for c in HOLE)
    lacking = core & ~own
    if lacking.any() and not isinstance(sampling, SamplingLine):
        raise ConfigError(
            f"{path}: {word} {table.index[np.argmax(lacking)]}: column 'hole_trend_deg': blank, and no "
            "hole was given for the survey: give hole_trend_deg and hole_plunge_deg, or the hole once"
        )
    if lacking.any():
        trend[lacking], plunge[lacking] = true_azimuth(sampling.trend, declination), sampling.plunge
    return np.where(core, trend, np.nan), np.where(core, plunge, np.nan)


def _planes(
    table: pd.DataFrame,
    convention: np.ndarray,
    holes: tuple[np.ndarray, np.ndarray],
    reference: float,
    declination: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each row's pole (n, 3), dip and dip direction [rad] from the cells of its convention."""
    angle = {c: _angles(table, c, declination) for c in NUMBERS}
    dip, direction = angle["dip_deg"], np.full(len(table), np.nan)
    for name, rows in ((n, convention == n) for n in CONVENTIONS):
        if name == "dip_direction":
            direction[rows] = angle["dip_direction_deg"][rows]
        elif name == "strike_rhr":
            direction[rows] = dip_direction_of_strike(angle["strike_deg"][rows])
        elif name == "pole":
            dip[rows], direction[rows] = plane_of_pole_trend_and_plunge(
                angle["pole_trend_deg"][rows], angle["pole_plunge_deg"][rows]
            )
    normals = poles(dip, direction)
    core = convention == "core"
    if core.any():
        alpha, beta = angle["alpha_deg"][core], angle["beta_deg"][core]
        normals[core] = core_poles(alpha, beta, holes[0][core], holes[1][core], reference)
        dip[core], direction[core] = np.radians(plane_of_pole(normals[core]))
    return normals, dip, direction


def _sampling(
    path: Path,
    table: pd.DataFrame,
    holes: tuple[np.ndarray, np.ndarray],
    sampling: Sampling | None,
    declination: float,
    word: str,
) -> tuple[np.ndarray, np.ndarray]:
    """Each row's sampling geometry: its kind (0 none, 1 a line, 2 a face) and axis (n, 3): the line's
    direction or the face's pole; a core reading's line is its hole; the caller's where a row has none."""
    line, face = (_pairs(path, table, GEOMETRIES[k], word) for k in ("line", "face"))
    core = ~np.isnan(holes[0])
    for rows, problem in (
        (line & face, "two sampling geometries in one row, a line and a face"),
        ((line | face) & core, "a core reading is sampled on its hole: leave the line and face blank"),
    ):
        if rows.any():
            row = np.argmax(rows)
            column = "line_trend_deg" if line[row] else "face_dip_deg"
            raise ConfigError(f"{path}: {word} {table.index[row]}: column '{column}': {problem}")
    a = {c: _angles(table, c, declination) for c in (*GEOMETRIES["line"], *GEOMETRIES["face"])}
    axes = np.where(core[:, None], line_vectors(*holes), np.nan)
    axes[line] = line_vectors(a["line_trend_deg"][line], a["line_plunge_deg"][line])
    axes[face] = poles(a["face_dip_deg"][face], a["face_dip_direction_deg"][face])
    kind = np.where(line | core, 1, np.where(face, 2, 0))
    rest = kind == 0
    if isinstance(sampling, SamplingLine):
        axes[rest], kind[rest] = line_vectors(true_azimuth(sampling.trend, declination), sampling.plunge), 1
    elif isinstance(sampling, SamplingFace):
        axes[rest], kind[rest] = poles(sampling.dip, true_azimuth(sampling.dip_direction, declination)), 2
    return kind, axes


def _records(path: Path) -> Records:
    """A workbook's cells (.xlsx, .xlsm) or a CSV file's."""
    if path.suffix.lower() in (".xlsx", ".xlsm"):
        return sheet_records(path)
    return csv_records(path, comments=True)


def read_readings(
    path: Path,
    *,
    convention: str | None = None,
    declination: float = 0.0,
    sampling: Sampling | None = None,
    max_weight: float = DIPS_MAX_WEIGHT,
    core_reference: str = "bottom",
) -> Readings:
    """The readings of the survey at `path` (CSV, or .xlsx), checked row by row.

    `convention`: a key of `CONVENTIONS` every row is read in (its columns only), or None: each row in
    the one whose columns it fills. `declination` [rad, east positive]: added to every azimuth, the
    file's and `sampling`'s (give it when they were read on a magnetic compass). `sampling`: the line
    (or core's hole) or face of the readings without their own. `max_weight`: the cap on Terzaghi's
    weights (default Dips', 1 / sin 15 deg). `core_reference`: the line beta is measured from, "top" or
    "bottom" of core (`CORE_REFERENCES`)."""
    if core_reference not in CORE_REFERENCES:
        raise ConfigError(f"{path}: core reference '{core_reference}' is unknown: use 'top' or 'bottom'")
    records = _records(path)
    found = _conventions(path, records.header, convention)
    kept = {c for name in found for c in CONVENTIONS[name]}
    ignored = {c for columns in CONVENTIONS.values() for c in columns} - kept
    for column in AZIMUTHS:
        if column in records.header and column not in ignored:
            records = _azimuth_text(path, records, column)
    columns = {c: NUMBERS[c] for c in NUMBERS if c in records.header and c not in ignored}
    texts = {c: Column(text=True, blank=True) for c in TEXTS if c in records.header}
    table = checked_table(path, records, {**columns, **texts})
    word = records.word
    row_convention = _row_conventions(path, table, found, word)
    holes = _holes(path, table, row_convention == "core", sampling, declination, word)
    normals, dip, direction = _planes(
        table, row_convention, holes, CORE_REFERENCES[core_reference], declination
    )
    kind, axes = _sampling(path, table, holes, sampling, declination, word)
    terzaghi = np.ones(len(table))
    terzaghi[kind == 1] = terzaghi_weights(normals[kind == 1], axes[kind == 1], max_weight)
    terzaghi[kind == 2] = face_weights(normals[kind == 2], axes[kind == 2], max_weight)
    own = table["weight"].fillna(1.0).to_numpy() if "weight" in table.columns else np.ones(len(table))

    blanks = {"type": "", "location": "", "set": ""}
    blanks |= dict.fromkeys(("trace_length_m", "position_m", "censored_ends"), np.nan)
    blank = pd.DataFrame(blanks, index=table.index)
    table = table.combine_first(blank)
    hidden = table["censored_ends"]
    broken = hidden.notna() & (hidden % 1 != 0)
    if broken.any():
        raise ConfigError(
            f"{path}: {word} {broken.idxmax()}: column 'censored_ends': {hidden[broken].iloc[0]:g} is not "
            "0, 1 or 2 (the number of hidden ends of the trace)"
        )

    return Readings(
        path=path,
        poles=normals,
        dip=dip,
        dip_direction=direction,
        weights=own * terzaghi,
        terzaghi=terzaghi,
        max_weight=max_weight,
        convention=row_convention,
        kind=table["type"].to_numpy(object),
        location=table["location"].to_numpy(object),
        set_label=table["set"].to_numpy(object),
        trace_length=table["trace_length_m"].to_numpy(float) * units.m,
        position=table["position_m"].to_numpy(float) * units.m,
        censored_ends=table["censored_ends"].to_numpy(float),
        lines=table.index.to_numpy(dtype=int),
    )
