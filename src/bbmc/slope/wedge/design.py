"""Bolt design for a wedge: the force (capacity) or count of bolts of a given direction that reaches a
target FS, by bisection on the vector solution, and the optimum bolt direction, its least force for a
target FS and its largest FS for a given force, in closed form.

The wedge's strength as a function of a bolt force T along a unit vector d. In a given sliding mode,
with Mohr-Coulomb planes in contact (N_i >= 0), the bolt adds T q_i to plane i's normal force and its
strength grows by T q_i tan phi_i; summed, by T d . g with the friction gradient
      g = tan phi_1 u_1 + tan phi_2 u_2,  u_1 = (-n_1 + r n_2) / (1 - r^2),  u_2 = (-n_2 + r n_1) / (1 - r^2)
on both planes (q_i = d . u_i is the 2x2 statics of `mechanics`, r = n_1 . n_2), and g = -tan phi_i n_i
on plane i alone. g is normal to the sliding direction s. With D_0 the driving force and R_0 the
resisting force without the bolt (`mechanics.WedgeSolution.driving`, `.resisting`):
      active:  FS = (R_0 + T d . g) / (D_0 + T d . s)       passive:  FS = (R_0 + T d . g - T d . s) / D_0
Written with the angle theta of d from the up-sliding direction -s towards g (d = -cos theta s +
sin theta g / |g|) and G = |g| these are the planar model's forms with tan phi replaced by G:
(R_0 + T G sin theta) / (D_0 - T cos theta) and (R_0 + T G sin theta + T cos theta) / D_0. Their
maxima over theta (d / d theta = 0; Hoek & Bray 1981 ch. 7 for the plane, G = tan phi):
      active:  tan theta = G / F (F the FS reached),      passive:  tan theta = G,
so the optimum bolt lies in the plane of s and g. One plane, or a symmetric wedge with one phi, gives
G = tan phi / sin(xi / 2) (xi the wedge's included angle): the issue's tan theta = tan phi / F and
theta = phi are the planar case. At the optimum, the least force for a target F and the largest F for a
force T are
      active:  T = (F D_0 - R_0) / sqrt(F^2 + G^2),
               F = (D_0 R_0 + T sqrt(G^2 (D_0^2 - T^2) + R_0^2)) / (D_0^2 - T^2)   (+inf for T >= D_0),
      passive: T = (F D_0 - R_0) / sqrt(1 + G^2),   F = (R_0 + T sqrt(1 + G^2)) / D_0.
These hold while the bolt keeps the mode (on both planes: q_i = d . u_i >= 0, or N_i + T q_i >= 0; it
fails where tan phi_1 < r tan phi_2 or the reverse, when the optimum lifts the wedge off one plane) and
for strength linear in N (Mohr-Coulomb; for Barton-Bandis the tangent c, phi at each plane's sigma_n
gives the first order, `strength.BartonBandis.equivalent_mohr_coulomb`). `required_bolt_force` needs
none of this: it bisects on the full vector solution.

FS against an active bolt's force (d fixed, both planes in contact): FS = (R_0 + a T) / (D_0 + b T),
a = d . g, b = d . s, is monotone in T with the sign of a D_0 - b R_0. A bolt with no component down
the sliding direction (b <= 0) that does not unload the planes (a >= 0: e.g. q_1, q_2 >= 0) makes FS
rise from FS_0 to +inf as T grows from 0 to T_0 = D_0 / |b|, where it stops the driving force; beyond
T_0 it pushes the wedge up the line (Swedge's "sliding up the line of intersection") and FS falls
from +inf towards a / |b|. A force with no down-line component that pulls the wedge off a plane
(a < 0) lowers FS from the start: "no down-dip component" alone does not make FS grow.

SI: forces N, angles rad; arrays broadcast over samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.geometry.orientation import wrapped_azimuth
from bbmc.slope.wedge.mechanics import PlaneStrength, SlidingMode, WedgeSolution, wedge_factor_of_safety
from bbmc.slope.wedge.support import SUPPORT_FORMS
from bbmc.slope.wedge.vectors import dot, norm


def _form(form: str) -> str:
    if form not in SUPPORT_FORMS:
        raise ValueError(f"bolt form must be one of {SUPPORT_FORMS}, not {form!r}")
    return form


def friction_gradient(
    mode: ArrayLike, normal_1: ArrayLike, normal_2: ArrayLike, tan_phi_1: ArrayLike, tan_phi_2: ArrayLike
) -> NDArray:
    """g (..., 3) [1] (module docstring): the growth of the planes' Mohr-Coulomb strength per unit
    force along d is d . g, in the sliding mode `mode` (`SlidingMode` values); NaN where contact is lost
    on both planes. Normals into the wedge (..., 3)."""
    n1, n2 = np.asarray(normal_1, dtype=float), np.asarray(normal_2, dtype=float)
    t1, t2 = (np.asarray(t, dtype=float)[..., None] for t in (tan_phi_1, tan_phi_2))
    r = dot(n1, n2)[..., None]
    both = (t1 * (-n1 + r * n2) + t2 * (-n2 + r * n1)) / (1.0 - r * r)
    mode = np.asarray(mode)[..., None]
    single = np.where(mode == SlidingMode.PLANE_1, -t1 * n1, -t2 * n2)
    return np.where(mode >= SlidingMode.BOTH, both, np.where(mode == SlidingMode.LIFTED, np.nan, single))


def optimum_bolt_angle(gradient_norm: ArrayLike, factor_of_safety: ArrayLike, form: str) -> NDArray:
    """theta [rad] from the up-sliding direction towards g: atan(G / F) active, atan(G) passive; F
    the FS the bolt reaches (the target), G = |g|."""
    g = np.asarray(gradient_norm, dtype=float)
    if _form(form) == "passive":
        return np.arctan(g)
    return np.arctan2(g, np.asarray(factor_of_safety, dtype=float))


def bolt_direction(angle: ArrayLike, sliding_direction: ArrayLike, gradient: ArrayLike) -> NDArray:
    """d = -cos theta s + sin theta g / |g| (..., 3): the bolt at theta [rad] from -s towards g."""
    g = np.asarray(gradient, dtype=float)
    size = norm(g)[..., None]
    across = np.divide(g, size, out=np.zeros_like(g), where=size > 0.0)
    theta = np.asarray(angle, dtype=float)[..., None]
    return -np.cos(theta) * np.asarray(sliding_direction, dtype=float) + np.sin(theta) * across


def bolt_trend_and_plunge(direction: ArrayLike) -> tuple[NDArray, NDArray]:
    """Trend [0, 2 pi) and plunge [rad] of a bolt's direction with its sense (a bolt that pulls the
    wedge upward has a negative plunge), for `support.Bolt`."""
    d = np.asarray(direction, dtype=float)
    d = d / norm(d)[..., None]
    return wrapped_azimuth(np.arctan2(d[..., 0], d[..., 1])), np.arcsin(np.clip(-d[..., 2], -1.0, 1.0))


def least_bolt_force(
    target: ArrayLike, driving: ArrayLike, resisting: ArrayLike, gradient_norm: ArrayLike, form: str
) -> NDArray:
    """T [N] of an optimally oriented bolt for FS = target (module docstring); 0 where the wedge
    already reaches it. D_0, R_0 [N] without the bolt, G = |g|."""
    f, d0, r0, g = (np.asarray(v, dtype=float) for v in (target, driving, resisting, gradient_norm))
    reach = np.sqrt(1.0 + g * g) if _form(form) == "passive" else np.sqrt(f * f + g * g)
    return np.maximum(f * d0 - r0, 0.0) / reach


def optimum_factor_of_safety(
    force: ArrayLike, driving: ArrayLike, resisting: ArrayLike, gradient_norm: ArrayLike, form: str
) -> NDArray:
    """The largest FS a bolt of force T [N] gives, optimally oriented (module docstring)."""
    t, d0, r0, g = (np.asarray(v, dtype=float) for v in (force, driving, resisting, gradient_norm))
    if _form(form) == "passive":
        return (r0 + t * np.sqrt(1.0 + g * g)) / d0
    short = t < d0
    square = np.where(short, d0 * d0 - t * t, 1.0)
    fs = (d0 * r0 + t * np.sqrt(g * g * square + r0 * r0)) / square
    return np.where(short, fs, np.inf)


@dataclass(frozen=True)
class OptimumBolt:
    """The optimum bolt of each sample: theta [rad] from the up-sliding direction, its unit direction
    (..., 3), trend and plunge [rad] (`bolt_trend_and_plunge`), force T [N] and the FS it gives."""

    angle: NDArray
    direction: NDArray
    trend: NDArray
    plunge: NDArray
    force: NDArray
    factor_of_safety: NDArray


def optimum_bolt(
    solution: WedgeSolution,
    normal_1: ArrayLike,
    normal_2: ArrayLike,
    tan_phi_1: ArrayLike,
    tan_phi_2: ArrayLike,
    form: str,
    *,
    target: ArrayLike | None = None,
    force: ArrayLike | None = None,
) -> OptimumBolt:
    """The optimum bolt on the wedges of `solution` (without the bolt), Mohr-Coulomb planes of friction
    tan phi_i: the least force for FS = `target`, or the largest FS for a bolt `force` [N] (give one)."""
    if (target is None) == (force is None):
        raise ValueError("give exactly one of target, force")
    g = friction_gradient(solution.mode, normal_1, normal_2, tan_phi_1, tan_phi_2)
    size = norm(g)
    if target is not None:
        fs = np.broadcast_to(np.asarray(target, dtype=float), size.shape)
        fs = np.maximum(fs, solution.factor_of_safety)
        t = least_bolt_force(fs, solution.driving, solution.resisting, size, form)
    else:
        t = np.broadcast_to(np.asarray(force, dtype=float), size.shape)
        fs = optimum_factor_of_safety(t, solution.driving, solution.resisting, size, form)
    angle = optimum_bolt_angle(size, fs, form)
    direction = bolt_direction(angle, solution.sliding_direction, g)
    trend, plunge = bolt_trend_and_plunge(direction)
    return OptimumBolt(angle, direction, trend, plunge, np.asarray(t, dtype=float), np.asarray(fs))


def required_bolt_force(
    target: ArrayLike,
    direction: ArrayLike,
    form: str,
    normal_1: ArrayLike,
    normal_2: ArrayLike,
    area_1: ArrayLike,
    area_2: ArrayLike,
    active: ArrayLike,
    strength_1: PlaneStrength,
    strength_2: PlaneStrength,
    maximum: ArrayLike,
    passive: ArrayLike = 0.0,
    tolerance: float = 1e-10,
) -> NDArray:
    """The least total force T [N] along the unit `direction` (..., 3), counted in `form`, that gives
    FS >= target, by bisection on `mechanics.wedge_factor_of_safety` (any strength, mode changes
    included) in [0, maximum], to `tolerance` of `maximum`; 0 where the wedge reaches the target
    without it, NaN where the bracket does not reach it. The bisection assumes FS rises with T on the
    bracket (module docstring: a bolt that does not unload the planes and has no component down the
    sliding direction). An active bolt on a wedge sliding on both planes has the bracket cut at T_0,
    where it stops the driving force (FS = +inf) before pushing the wedge up the line. A bolt count is
    ceil(T / capacity)."""
    d = np.asarray(direction, dtype=float)
    as_active = _form(form) == "active"

    def solve(t: ArrayLike) -> WedgeSolution:
        bolt = np.asarray(t, dtype=float)[..., None] * d
        pushed = np.asarray(active, dtype=float) + (bolt if as_active else 0.0)
        held = np.asarray(passive, dtype=float) + (0.0 if as_active else bolt)
        return wedge_factor_of_safety(
            normal_1, normal_2, area_1, area_2, pushed, strength_1, strength_2, held
        )

    start = solve(0.0)
    goal = np.asarray(target, dtype=float)
    shape = np.broadcast_shapes(start.factor_of_safety.shape, goal.shape, np.shape(maximum))
    high = np.broadcast_to(np.asarray(maximum, dtype=float), shape).copy()
    if as_active:
        up_line = -dot(d, start.sliding_direction)
        with np.errstate(invalid="ignore", divide="ignore"):
            stop = np.where(
                (start.mode == SlidingMode.BOTH) & (up_line > 0.0), start.driving / up_line, np.inf
            )
        high = np.minimum(high, stop)
    low = np.zeros(shape)
    done = start.factor_of_safety >= goal
    reachable = solve(high).factor_of_safety >= goal
    step = tolerance * np.max(np.asarray(maximum, dtype=float))
    while np.any(high - low > step):
        middle = 0.5 * (low + high)
        ok = solve(middle).factor_of_safety >= goal
        low, high = np.where(ok, low, middle), np.where(ok, middle, high)
    return np.where(done, 0.0, np.where(reachable, high, np.nan))
