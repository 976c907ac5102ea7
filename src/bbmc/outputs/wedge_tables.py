"""The tables `bbmc wedge` writes, units in the column names (m, m^2, m^3, kN, kPa, deg):

* `wedge_table`: one row of every number of one wedge: its vertices (O the toe at the origin, C1, C2
  the crest points, T the top of the line of intersection; with a crack P, Q, R in its place), the
  areas of its faces, volume, weight, trace lengths, the line of intersection, H1 and H, the size
  limits' scale factor and the limit that governs, the extents they limit, Hoek & Bray's wedge factor
  K, the loads (water forces U1, U2, V; the seismic, external and support resultants as vectors), the
  normal reactions and mean normal stresses, each plane's c and phi at its stress
  (`strength.tangent_strength`), the driving and resisting forces, the
  sliding direction, the mode and FS, and the driving force's parts by load;
* `combinations_frame`: `combinations.Combination` rows;
* `design_frame`: `bolting.BoltDesign` rows.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import pandas as pd

from bbmc.slope.wedge.bolting import BoltDesign
from bbmc.slope.wedge.cases import WedgeCase, driven_by, driving_parts
from bbmc.slope.wedge.combinations import Combination
from bbmc.slope.wedge.size_limits import wedge_extents
from bbmc.slope.wedge.strength import normal_stresses, tangent_strength

KN = 1e3


def _vector(row: dict, name: str, vector, unit: str, scale: float = 1.0) -> None:
    for axis, value in zip("xyz", np.asarray(vector, dtype=float), strict=True):
        row[f"{name}_{axis}_{unit}"] = float(value) / scale


def _vertices(case: WedgeCase) -> list[tuple[str, np.ndarray]]:
    g = case.geometry
    named = [("O", g.toe), ("C1", g.crest_1), ("C2", g.crest_2)]
    if g.has_crack:
        return [*named, ("P", g.crack_1), ("Q", g.crack_2), ("R", g.crack_foot), ("T_uncut", g.top)]
    return [*named, ("T", g.top)]


def _geometry_columns(case: WedgeCase) -> dict:
    g = case.geometry
    row: dict = {}
    for name, point in _vertices(case):
        _vector(row, name, point, "m")
    for name in ("area_1", "area_2", "area_face", "area_upper", "area_crack"):
        row[f"{name}_m2"] = float(getattr(g, name))
    row["volume_m3"] = float(g.volume)
    _vector(row, "centroid", g.centroid, "m")
    for name in ("trace_face_1", "trace_face_2", "trace_upper_1", "trace_upper_2", "crest_length"):
        row[f"{name}_m"] = float(getattr(g, name))
    row["intersection_length_m"] = float(g.intersection_length)
    row["line_trend_deg"], row["line_plunge_deg"] = float(np.degrees(g.trend)), float(np.degrees(g.plunge))
    row["height_h1_m"], row["height_m"] = float(g.height_h1), float(g.height_h)
    row["size_scale"], row["size_limited_by"] = float(g.size_scale), str(g.size_limit_names())
    extents = wedge_extents(g.vertices, g.normal_face, g.normal_upper)
    row["extent_along_crest_m"] = float(extents.along_crest)
    row["extent_behind_crest_m"] = float(extents.behind_crest)
    for k in (1, 2):
        row[f"trace_length_{k}_m"] = float(getattr(extents, f"trace_length_plane_{k}"))
        row[f"persistence_{k}_m"] = float(getattr(extents, f"persistence_plane_{k}"))
    row["wedge_factor_k"] = float(g.short_solution.wedge_factor)
    return row


def wedge_table(case: WedgeCase) -> pd.DataFrame:
    """Every number of one formed wedge (module docstring), one row."""
    a = case.analysis
    g, loads, solution = a.geometry, a.loads, a.solution
    row = _geometry_columns(case)
    row["weight_kN"] = float(loads.weight) / KN
    for name in ("water_1", "water_2", "water_crack"):
        row[f"{name}_kN"] = float(getattr(loads, name)) / KN
    for name in ("seismic", "forces", "active", "passive"):
        _vector(row, name, getattr(loads, name), "kN", KN)
    row["normal_1_kN"], row["normal_2_kN"] = float(solution.normal_1) / KN, float(solution.normal_2) / KN
    sigma_1, sigma_2 = normal_stresses(solution.normal_1, solution.normal_2, g.area_1, g.area_2)
    row["sigma_n_1_kPa"], row["sigma_n_2_kPa"] = float(sigma_1) / KN, float(sigma_2) / KN
    for k, (strength, sigma) in enumerate(zip(case.strengths, (sigma_1, sigma_2), strict=True), start=1):
        tangent = tangent_strength(strength, sigma)
        row[f"cohesion_{k}_kPa"] = float(tangent.cohesion) / KN
        row[f"friction_{k}_deg"] = float(np.degrees(tangent.friction))
    row["driving_kN"], row["resisting_kN"] = float(solution.driving) / KN, float(solution.resisting) / KN
    _vector(row, "sliding_direction", solution.sliding_direction, "1")
    parts = driving_parts(a)
    for name, value in parts.items():
        row[f"driving_{name}_kN"] = value / KN
    row["driven_by"] = driven_by(parts)
    row["mode"] = str(solution.modes())
    row["factor_of_safety"] = float(solution.factor_of_safety)
    return pd.DataFrame([row])


def combinations_frame(rows: Iterable[Combination]) -> pd.DataFrame:
    """The combination table, one row per pair."""
    return pd.DataFrame([vars(row) for row in rows])


def design_frame(rows: Iterable[BoltDesign], names: tuple[str, str] = ("plane 1", "plane 2")) -> pd.DataFrame:
    """The bolt designs of the wedge of the planes called `names`, one row each, in degrees and kN."""
    out = []
    for d in rows:
        out.append(
            {
                "plane_1": names[0],
                "plane_2": names[1],
                "bolt": d.bolt,
                "form": d.form,
                "target_fs": d.target,
                "trend_deg": float(np.degrees(d.trend)),
                "plunge_deg": float(np.degrees(d.plunge)),
                "angle_from_up_sliding_deg": float(np.degrees(d.angle)),
                "total_force_kN": d.force / KN,
                "capacity_kN": d.capacity / KN,
                "count": d.count,
                "factor_of_safety": d.factor_of_safety,
                "closed_form_fs": d.closed_form,
            }
        )
    return pd.DataFrame(out)
