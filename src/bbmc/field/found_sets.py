"""Sets found in orientation readings, written for a rock mass: each set's 3D orientation (mean
plane and Fisher's K), and its spacing and trace length where its readings were mapped along a
scanline with their positions, trace lengths and hidden ends (fitted as `bbmc joints` fits them,
`bbmc.field.analysis.fit_set`); where they were not, the set is written without them and says that its
spacing must be given.

A set's scanline fit uses the readings of one survey sheet (one scanline of known length): the sheet
that holds most of the set's readings with positions. It needs at least `MIN_TRACES` readings there,
`MIN_WHOLE` of them seen whole.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bbmc.field import distributions as dist
from bbmc.field.analysis import MIN_TRACES, MIN_WHOLE, SCENE_FAMILIES, SetFit, fit_set
from bbmc.field.block import BlockEntry
from bbmc.field.readings import Readings
from bbmc.field.survey import SetSurvey
from bbmc.geometry.fisher import FisherStatistics


@dataclass(frozen=True)
class Scanline:
    """A sheet's readings mapped along a scanline of unit vector `line` and `length` [m]."""

    readings: Readings
    line: np.ndarray
    length: float


def position_resolution(positions: np.ndarray) -> float:
    """The reading of positions [m]: 10^-d for the fewest decimals d that write them all (to 1e-9)."""
    for decimals in range(7):
        scaled = positions * 10.0**decimals
        if np.all(np.abs(scaled - np.round(scaled)) < 1e-9 * np.maximum(1.0, np.abs(scaled))):
            return 10.0**-decimals
    return 1e-6


def _survey(name: str, sheet: Scanline, rows: np.ndarray) -> SetSurvey:
    r = sheet.readings
    order = rows[np.argsort(r.position[rows], kind="stable")]
    return SetSurvey(
        name=name,
        position=r.position[order],
        dip=r.dip[order],
        dip_direction=r.dip_direction[order],
        trace_length=r.trace_length[order],
        censored_ends=r.censored_ends[order].astype(int),
        lines=r.lines[order],
        resolution=position_resolution(r.position[order]),
    )


def scanline_fit(
    name: str, labels: list[np.ndarray], label: int, sheets: list[Scanline | None], max_weight: float
) -> tuple[SetFit | None, str]:
    """The set `label`'s spacing and trace-length fit from the sheet holding most of its readings with
    positions (`labels[k]`: the set of each reading of sheet k; `sheets[k]` None where sheet k is no
    scanline), or None and the reason."""
    best, best_rows = None, np.array([], dtype=int)
    for sheet, sheet_labels in zip(sheets, labels, strict=True):
        if sheet is None:
            continue
        r = sheet.readings
        measured = np.isfinite(r.position) & np.isfinite(r.trace_length) & np.isfinite(r.censored_ends)
        rows = np.flatnonzero((sheet_labels == label) & measured)
        if rows.size > best_rows.size:
            best, best_rows = sheet, rows
    if best is None or best_rows.size == 0:
        return None, "no reading of the set was mapped along a scanline with its position and trace"
    if best_rows.size < MIN_TRACES:
        return None, (
            f"{best_rows.size} readings along the scanline of {best.readings.path.name}: fitting a spacing "
            f"needs at least {MIN_TRACES}"
        )
    whole = int(np.sum(best.readings.censored_ends[best_rows] == 0))
    if whole < MIN_WHOLE:
        return None, (
            f"{whole} traces seen whole along the scanline of {best.readings.path.name}: fitting a trace "
            f"length needs at least {MIN_WHOLE}"
        )
    return fit_set(_survey(name, best, best_rows), best.line, best.length, max_weight, None), ""


def block_entry(
    name: str, statistics: FisherStatistics, fit: SetFit | None, reason: str, persistence: float
) -> BlockEntry:
    """The set as the rock mass's block writes it: the found set's orientation, and the spacing and
    trace-length laws a scene reads (exponential or lognormal, least AIC) where it was fitted."""
    if fit is None:
        return BlockEntry(name, statistics.orientation, None, None, persistence, reason)
    spacing = dist.best(fit.spacing, SCENE_FAMILIES)
    trace = dist.best(fit.trace_length, SCENE_FAMILIES)
    return BlockEntry(name, statistics.orientation, spacing, trace, persistence)
