"""Swedge's combination analysis: the wedge of every pair of joint sets (and of every set with a basal
plane, where one is given) against one slope face, each analysed as `cases.analyse_case` with the same
slope, loads and support, in a table sorted by FS with the critical wedges named.

A pair (i, j) takes the set listed first as plane 1 (H1, where given, refers to it; with a crest that is
horizontal, face and upper surface of one dip direction, H1 is the slope height whichever set is plane 1;
each set's trace length and persistence, where given, limit the size of every wedge it bounds);
a set with the basal plane takes the set as plane 1 and the basal plane as plane 2. A pair whose wedge
cannot form is a row with its reason and no FS, never a number. Critical: a wedge that forms with FS
below the critical FS; the lowest FS of the table is named first.

SI inside; the table's columns carry their units.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from bbmc.slope.wedge.cases import Plane, WedgeSetting, analyse_case, driven_by, driving_parts

N_PER_KN = 1e3


@dataclass(frozen=True)
class Combination:
    """One row of the table: the planes' names, whether and why the wedge forms, its line of
    intersection [deg], H1, H [m], volume [m^3], weight [kN], mode, FS, the driving force [kN] and what
    drives it, the size limits' scale factor and the limit that governs (`size_limits`; 'height' where
    none scales the wedge down), and whether it is critical."""

    plane_1: str
    plane_2: str
    forms: bool
    reason: str
    trend_deg: float
    plunge_deg: float
    height_h1_m: float
    height_m: float
    volume_m3: float
    weight_kN: float
    mode: str
    factor_of_safety: float
    driving_kN: float
    driven_by: str
    size_scale: float = float("nan")
    size_limited_by: str = ""
    critical: bool = False


def plane_pairs(names: list[str], basal: str | None) -> list[tuple[str, str]]:
    """Every pair of the sets in the order given, then every set with the basal plane."""
    pairs = list(itertools.combinations(names, 2))
    return pairs + ([(name, basal) for name in names] if basal is not None else [])


def _row(setting: WedgeSetting, name_1: str, name_2: str, plane_1: Plane, plane_2: Plane) -> Combination:
    case = analyse_case(setting, plane_1, plane_2)
    g, nan = case.geometry, float("nan")
    if case.analysis is None:
        return Combination(name_1, name_2, False, case.reason, *[nan] * 6, "", nan, nan, "")
    solution, loads = case.analysis.solution, case.analysis.loads
    return Combination(
        name_1,
        name_2,
        True,
        case.reason,
        float(np.degrees(g.trend)),
        float(np.degrees(g.plunge)),
        float(g.height_h1),
        float(g.height_h),
        float(g.volume),
        float(loads.weight) / N_PER_KN,
        str(solution.modes()),
        float(solution.factor_of_safety),
        float(solution.driving) / N_PER_KN,
        driven_by(driving_parts(case.analysis)),
        float(g.size_scale),
        str(g.size_limit_names()),
    )


def combination_table(
    setting: WedgeSetting, sets: Mapping[str, Plane], basal: Plane | None = None, critical_fs: float = 1.0
) -> list[Combination]:
    """The wedge of every pair of `sets` (and of each with `basal`, named 'basal') in `setting`, sorted
    by FS (wedges that do not form last, in the order of the pairs), critical ones marked (FS below
    `critical_fs`)."""
    planes = dict(sets) | ({"basal": basal} if basal is not None else {})
    pairs = plane_pairs(list(sets), "basal" if basal is not None else None)
    rows = [_row(setting, a, b, planes[a], planes[b]) for a, b in pairs]
    rows.sort(key=lambda r: (not r.forms, r.factor_of_safety if r.forms else 0.0))
    return [
        Combination(**{**vars(r), "critical": r.forms and r.factor_of_safety < critical_fs}) for r in rows
    ]
