"""The factor of safety of a toppling block system: the least factor on friction at which it fails.

Definition. Goodman & Bray (1976) and Hoek & Bray (1981, ch. 10) define the factor of safety of block
toppling by the friction: FS is the factor by which tan φ must be divided to bring the system to
limiting equilibrium, FS = tan φ / tan φ_limit with one friction angle. With the base friction φ_p and
the side friction φ_d both reduced (RocTopple's "Factor of Safety" likewise reduces the joint strengths
of the bases and the sides), the system *fails at F* when the march (``bbmc.slope.toppling.march``) with
tan φ_p / F and tan φ_d / F needs a positive force at the toe beyond the support applied (P_0 > 0), or
cannot be completed (a block that no force from below holds, P_0 = +∞). Then

    FS = the least F at which the system fails, above the factors at which it holds.

"Above the factors at which it holds": the search starts from much friction (F = 1e-4) and takes the
first failure as friction is reduced, so that a failure at high friction (none is known with the march's
rules; the property tests find the failure condition monotone) could not be taken for the FS.
FS is found on the yes/no condition, never on a root of P_0, which jumps (a
mode change) and diverges (1 − tan φ_p tan φ_d → 0): all samples at once, on a grid of 33 factors from
1e-4 to 1e4, then bisected in log F between the last factor that holds and the first that fails, to a
relative 1e-13. A system that holds at no factor gets FS = 0 (a toe block that topples under its own
weight, say); one that never fails again gets FS = +∞ (its support holds it without friction). With one
friction angle for bases and sides this is the tangent ratio, FS = tan φ / tan φ_limit (Hoek & Bray's
example: φ_limit 38.15°, FS 1.0682 at 40°). Supports and water are not reduced.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.toppling.geometry import BlockSystem
from bbmc.slope.toppling.loads import BlockSupport, BlockWater
from bbmc.slope.toppling.march import LOCK_TOLERANCE, Loads, march
from bbmc.slope.toppling.table import toppling_forces

#: The bracket of the factor of safety, and the relative tolerance of its bisection.
FS_RANGE = (1e-4, 1e4)
FS_TOLERANCE = 1e-13
FS_GRID = 33  # factors 1e-4 to 1e4, 1.78 apart


def _loads(
    blocks: BlockSystem,
    support: BlockSupport | None,
    water: BlockWater | None,
    unit_weight: float | None,
) -> Loads:
    """The loads at the given unit weight; without support and water every force scales with γ, so γ = 1."""
    if support is None and water is None:
        return Loads(blocks, 1.0)
    if unit_weight is None or not unit_weight > 0.0:
        raise ValueError(
            "a supported or wet system needs its unit weight (> 0): the forces no longer scale with it"
        )
    return Loads(blocks, unit_weight, support, water)


def fails(loads: Loads, tan_base: ArrayLike, tan_side: ArrayLike) -> NDArray[np.bool_]:
    """Whether the system fails with these friction tangents: P_0 > 0 (support needed) or not held."""
    return march(loads, tan_base, tan_side)["toe_force"] > 0.0


def _least_failing_factor(loads: Loads, tan_base: NDArray, tan_side: NDArray) -> NDArray[np.float64]:
    """Per sample, the least F at which the system fails above the first F (from FS_RANGE's low end,
    the most friction) at which it holds: found on a grid of FS_GRID factors, then bisected in log F
    between the grid's last holding and first failing factor."""
    grid = np.geomspace(*FS_RANGE, FS_GRID)
    failing = fails(loads, tan_base[..., None] / grid, tan_side[..., None] / grid)
    holding = ~failing
    first_hold = np.argmax(holding, axis=-1)
    after = failing & (np.arange(FS_GRID) > first_hold[..., None])
    first_fail = np.argmax(after, axis=-1)
    none_hold, none_fail = ~holding.any(axis=-1), ~after.any(axis=-1)
    k = np.clip(first_fail, 1, FS_GRID - 1)
    low, high = np.log(grid[k - 1]), np.log(grid[k])
    steps = math.ceil(math.log2(math.log(grid[1] / grid[0]) / FS_TOLERANCE))
    for _ in range(steps):
        mid = 0.5 * (low + high)
        factor = np.exp(mid)
        failed = fails(loads, tan_base / factor, tan_side / factor)
        high, low = np.where(failed, mid, high), np.where(failed, low, mid)
    return np.where(none_hold, 0.0, np.where(none_fail, np.inf, np.exp(0.5 * (low + high))))


def limiting_friction(
    blocks: BlockSystem,
    bracket: tuple[float, float] | None = None,
    xtol: float = 1e-13,
    support: BlockSupport | None = None,
    unit_weight: float | None = None,
    water: BlockWater | None = None,
) -> float:
    """φ_limit [rad], one friction angle on bases and sides: the least angle at which the system holds
    (it fails just below), bisected on ``fails`` to `xtol` [rad].

    Independent of the unit weight without support or water (every force scales with γ); with them,
    unit_weight γ [N/m³] is needed. bracket: (low, high) [rad], failing at low and holding at high;
    default: the first holding angle on a 0.1° grid from 0.1° to 89.9° and the angle below it.
    """
    loads = _loads(blocks, support, water, unit_weight)
    if bracket is None:
        grid = np.radians(np.arange(0.1, 89.95, 0.1))
        held = ~fails(loads, np.tan(grid), np.tan(grid))
        if not held.any():
            raise ValueError("the system fails at every friction angle from 0.1° to 89.9°")
        k = int(np.argmax(held))
        if k == 0:
            raise ValueError("the system holds at 0.1°: it needs no friction")
        low, high = float(grid[k - 1]), float(grid[k])
    else:
        low, high = bracket

    def failing(phi: float) -> bool:
        return bool(fails(loads, math.tan(phi), math.tan(phi)))

    if not failing(low):
        raise ValueError(f"the system holds at the bracket's low end, {math.degrees(low):.4g}°")
    if failing(high):
        raise ValueError(f"the system fails at the bracket's high end, {math.degrees(high):.4g}°")
    while high - low > xtol:
        mid = 0.5 * (low + high)
        if mid in (low, high):
            break
        low, high = (mid, high) if failing(mid) else (low, mid)
    return 0.5 * (low + high)


def factor_of_safety(
    blocks: BlockSystem,
    friction: ArrayLike,
    side_friction: ArrayLike | None = None,
    support: BlockSupport | None = None,
    unit_weight: float | None = None,
    water: BlockWater | None = None,
) -> NDArray[np.float64]:
    """FS [1], the least factor on tan φ_p and tan φ_d at which the system fails (module docstring),
    broadcast over arrays of friction angles [rad] (a Monte Carlo calls it once for all samples).

    side_friction None, or equal to friction, is one friction angle: FS = tan φ / tan φ_limit. A support
    or water (not reduced) needs the unit weight γ [N/m³].
    """
    friction = np.asarray(friction, dtype=float)
    if side_friction is None or np.array_equal(np.broadcast_to(side_friction, friction.shape), friction):
        try:
            limit = limiting_friction(blocks, support=support, unit_weight=unit_weight, water=water)
            return np.tan(friction) / math.tan(limit)
        except ValueError:  # support holds it without friction (FS +inf) or nothing holds it (0)
            side_friction = friction
    tan_base, tan_side = np.broadcast_arrays(np.tan(friction), np.tan(np.asarray(side_friction, dtype=float)))
    loads = _loads(blocks, support, water, unit_weight)
    return _least_failing_factor(loads, np.array(tan_base, dtype=float), np.array(tan_side, dtype=float))


def horizontal_toe_support(
    blocks: BlockSystem,
    friction: float,
    unit_weight: float,
    side_friction: float | None = None,
    height: float | None = None,
    plunge: float = 0.0,
    water: BlockWater | None = None,
) -> float:
    """The least force T [N/m] on the toe block's downhill face, `height` [m] above its base (default:
    half its height) and plunging `plunge` [rad] below the horizontal (θ = α + plunge), that holds the
    system at these friction angles [rad]; ≤ 0 where none is needed (the surplus, in the sliding form).

    Only the toe block's equations change with T (derived here from the march's):
      toppling  T cos θ h ≥ M_1                  (M_1: its toppling moment about the pivot without T)
      sliding   T (cos θ + tan φ_p sin θ) ≥ (1 − tan φ_p tan φ_d) P_{0,s}   (none if sliding is locked)
    T is the larger of the two; +∞ if a block above the toe cannot be held, or the toe block floats.
    A toe block that slides gives [HB81]'s horizontal toe force.
    """
    phi_d = friction if side_friction is None else side_friction
    h = 0.5 * blocks.heights[0] if height is None else height
    theta = blocks.base_dip + plunge
    loads = Loads(blocks, unit_weight, None, water)
    table = toppling_forces(blocks, friction, unit_weight, phi_d, water=water)
    if not np.all(table.held[1:]):
        return math.inf
    tp, td = math.tan(friction), math.tan(phi_d)
    p1 = float(table.force_above[0])
    moment = p1 * (blocks.upper_arm[0] - blocks.width * td) + loads.moment[0]
    along = math.cos(theta) * h
    need_topple = moment / along if moment > 0.0 else -math.inf
    if moment > 0.0 and along <= 0.0:
        return math.inf
    lock = 1.0 - tp * td
    sliding = (lock * p1 + loads.along[0] - tp * loads.normal[0]) if lock > LOCK_TOLERANCE else -math.inf
    need_slide = sliding / (math.cos(theta) + tp * math.sin(theta))
    force = max(need_topple, need_slide)
    floats = loads.normal[0] + max(force, 0.0) * math.sin(theta) <= 0.0  # water lifts the toe block
    return math.inf if floats else force
