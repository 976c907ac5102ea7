"""The bolts a wedge case needs for a target FS, as `bbmc wedge`'s design section asks, each answer
checked by the full vector solution with the bolts in place:

* a given bolt direction: the least total force T along it by bisection on the vector solution
  (`design.required_bolt_force`, bracket [0, 10 W]), the count n = ceil(T / capacity) of bolts of a
  given capacity (or for a given count the capacity T / n each), and the FS with them;
* the optimum direction: the closed form of `design.optimum_bolt` (active: tan theta = G / F, passive:
  tan theta = G, theta from the up-sliding direction), and along it the least force by the same
  bisection, the count and FS as above. The closed form takes Mohr-Coulomb planes; a Barton-Bandis plane
  enters with its tangent phi at its own unbolted normal stress
  (`strength.BartonBandis.equivalent_mohr_coulomb`), the first order of the curved envelope: its
  direction is then near, not at, the optimum, and its force (the `closed_form` FS reports what the
  closed form expects) is replaced by the bisection's, which reaches the target with the bolts in place.

SI: N, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from bbmc.geometry.orientation import line_vectors
from bbmc.slope.wedge.cases import Plane, WedgeCase, WedgeSetting, analyse_case
from bbmc.slope.wedge.design import bolt_trend_and_plunge, optimum_bolt, required_bolt_force
from bbmc.slope.wedge.mechanics import PlaneStrength
from bbmc.slope.wedge.strength import normal_stresses, tangent_strength

BRACKET_WEIGHTS = 10.0  # the bisection's bracket, in wedge weights
BoltSizing = tuple[float | None, int | None]  # (capacity [N], count): one given, the other designed


@dataclass(frozen=True)
class BoltDesign:
    """One design: the bolts' direction (trend, plunge [rad], into the rock), their angle from the
    up-sliding direction [rad] (optimum only, else NaN), the least total force T [N] (NaN where the
    bracket does not reach the target), the count of bolts of `capacity` [N], and the FS with them
    (the vector solution) and by the closed form (optimum only, else NaN)."""

    bolt: str
    form: str
    target: float
    trend: float
    plunge: float
    angle: float
    force: float
    capacity: float
    count: float
    factor_of_safety: float
    closed_form: float


def tangent_friction(strength: PlaneStrength, sigma_n: float) -> float:
    """tan phi of a plane: Mohr-Coulomb's, or a Barton-Bandis plane's tangent at sigma_n [Pa]."""
    return float(np.tan(tangent_strength(strength, sigma_n).friction))


def _with_bolts(setting: WedgeSetting, plane_1: Plane, plane_2: Plane, vector, form: str) -> float:
    """FS of the case with the bolts' force vector added to the active or the passive support."""
    if form == "active":
        bolted = replace(setting, forces=setting.forces + vector)
    else:
        bolted = replace(setting, passive=setting.passive + vector)
    return float(analyse_case(bolted, plane_1, plane_2).analysis.factor_of_safety)


def _finish(
    setting: WedgeSetting, planes: tuple[Plane, Plane], direction, bolts: BoltSizing, form: str, **fields
) -> BoltDesign:
    """The count of bolts of the given capacity for the force found (rounded up), or the capacity of each
    of the given count (the force shared), and the FS the vector solution gives with them."""
    force = fields["force"]
    capacity, count = bolts
    if count is None:
        count = float(math.ceil(force / capacity - 1e-9)) if np.isfinite(force) else math.nan
    else:
        capacity = force / count
    fs = math.nan
    if np.isfinite(count) and np.isfinite(capacity):
        fs = _with_bolts(setting, *planes, count * capacity * np.asarray(direction), form)
    return BoltDesign(form=form, capacity=capacity, count=float(count), factor_of_safety=fs, **fields)


def _least_force(case: WedgeCase, target: float, direction, form: str) -> float:
    """The least total bolt force [N] along the unit `direction` that brings `case` to FS `target`, by
    bisection on the vector solution (`design.required_bolt_force`); NaN where none in the bracket does."""
    g, loads = case.analysis.geometry, case.analysis.loads
    return float(
        required_bolt_force(
            target,
            direction,
            form,
            g.normal_1,
            g.normal_2,
            g.area_1,
            g.area_2,
            loads.active,
            *case.strengths,
            BRACKET_WEIGHTS * loads.weight,
            loads.passive,
        )
    )


def design_bolts(
    case: WedgeCase,
    setting: WedgeSetting,
    planes: tuple[Plane, Plane],
    target: float,
    bolts: BoltSizing,
    form: str,
    direction: tuple[float, float] | None = None,
) -> BoltDesign:
    """The bolts counted in `form` that bring the formed wedge `case` of `setting` and `planes` to FS
    `target`, `bolts` (capacity [N], count) with one of them None: the count of bolts of that capacity,
    or the capacity of each of that count; along `direction` (trend, plunge [rad]) if given, else along
    the closed form's optimum direction; in both, the least force by bisection on the vector solution (for
    Mohr-Coulomb planes it is the closed form's force; for Barton-Bandis planes the closed form's
    tangent friction is only its first order, and the bisection's force reaches the target)."""
    if direction is not None:
        d = line_vectors(*direction)
        fields = {"bolt": "given", "target": target, "trend": direction[0], "plunge": direction[1]}
        force = _least_force(case, target, d, form)
        return _finish(
            setting, planes, d, bolts, form, **fields, angle=math.nan, force=force, closed_form=math.nan
        )
    g, solution = case.analysis.geometry, case.analysis.solution
    strength_1, strength_2 = case.strengths
    sigma_1, sigma_2 = normal_stresses(solution.normal_1, solution.normal_2, g.area_1, g.area_2)
    tan_1, tan_2 = tangent_friction(strength_1, sigma_1), tangent_friction(strength_2, sigma_2)
    best = optimum_bolt(solution, g.normal_1, g.normal_2, tan_1, tan_2, form, target=target)
    trend, plunge = bolt_trend_and_plunge(best.direction)
    fields = {"bolt": "optimum", "target": target, "trend": float(trend), "plunge": float(plunge)}
    force = _least_force(case, target, best.direction, form)
    return _finish(
        setting,
        planes,
        best.direction,
        bolts,
        form,
        **fields,
        angle=float(best.angle),
        force=force,
        closed_form=float(best.factor_of_safety),
    )
