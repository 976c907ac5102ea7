"""Loads on the blocks of a toppling analysis besides their weight: support forces and joint water.

Support (as RocTopple applies bolts and line loads): a force T_n per metre run on block n at a point of
its surface, at θ_n from the base's up-dip direction, positive towards the base: T_s = T_n cos θ_n up
the base, T_⊥ = T_n sin θ_n onto it. The point is at height h_n above the base and offset x_n along
the base from the block's downhill face (x_n = 0 on that face, h_n = y_n on its top). About the pivot
(the downhill base corner) it resists toppling with the moment T_s h_n + T_⊥ x_n. A horizontal force
into the slope has θ = α; one plunging β below the horizontal has θ = α + β. ``face_support`` finds
the block and the point from a height on the slope face, as RocTopple places line loads.

Water (Wyllie & Mah 2004, section 9.4, eqs. 9.31-9.33; Hoek & Bray 1981, ch. 10): water stands in the
joint on block n's uphill side to y_w,n and on its downhill side to z_w,n above its base (measured along
the sides); the pressure is hydrostatic, γ_w cos α times the depth along the side, and varies linearly
along the base between the two sides:
    V_1 = ½ γ_w cos α y_w²            on the uphill side, at y_w/3, pushing the block downhill
    V_3 = ½ γ_w cos α z_w²            on the downhill side, at z_w/3, pushing it uphill
    V_2 = ½ γ_w cos α (y_w + z_w) Δx  uplift on the base, at Δx (2y_w + z_w) / (3 (y_w + z_w)) from
                                      the pivot
``phreatic_water`` takes the heights from a phreatic line (RocSlope2's phreatic surface: hydrostatic
forces on every block joint below it, the joints filled at most to their top, no water on the slope's
free face). Units: SI (m, rad, N/m, N/m³).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.toppling.geometry import BlockSystem

#: Unit weight of water [N/m³] unless a study gives its own.
WATER_UNIT_WEIGHT = 9.81e3


@dataclass(frozen=True)
class BlockSupport:
    """Support forces on the blocks of a system, one entry per block (index 0 = block 1, the toe):
    force T_n [N per metre run] (0: no support), angle θ_n [rad] from the base's up-dip direction towards
    the base, height h_n [m] above the base and offset x_n [m] along the base from the block's downhill
    face (module docstring)."""

    force: NDArray[np.float64]
    angle: NDArray[np.float64]
    height: NDArray[np.float64]
    offset: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        if self.offset is None:
            object.__setattr__(self, "offset", np.zeros_like(np.atleast_1d(np.asarray(self.force, float))))
        for name in ("force", "angle", "height", "offset"):
            object.__setattr__(self, name, np.atleast_1d(np.asarray(getattr(self, name), dtype=float)))
        shapes = {getattr(self, n).shape for n in ("force", "angle", "height", "offset")}
        if len(shapes) != 1 or self.force.ndim != 1:
            raise ValueError("support force, angle, height and offset need one entry per block")
        if np.any(~(self.force >= 0.0)):
            raise ValueError("support force must be >= 0 (a bolt pulls, it cannot push)")

    @classmethod
    def on_block(
        cls, blocks: BlockSystem, block: int, force: float, angle: float, height: float, offset: float = 0.0
    ) -> BlockSupport:
        """One support on block number `block` (1 = toe) of `blocks`, none on the others."""
        if not 1 <= block <= blocks.n_blocks:
            raise ValueError(f"block {block} is not one of the system's 1..{blocks.n_blocks}")
        values = np.zeros((4, blocks.n_blocks))
        values[:, block - 1] = force, angle, height, offset
        return cls(*values)

    def check(self, blocks: BlockSystem) -> None:
        if self.force.size != blocks.n_blocks:
            raise ValueError(f"support has {self.force.size} entries for {blocks.n_blocks} blocks")
        if np.any((self.height < 0.0) | (self.height > blocks.heights)):
            raise ValueError("support height must lie on the block's face, 0 <= h_n <= y_n")
        if np.any((self.offset < 0.0) | (self.offset > blocks.width)):
            raise ValueError("support offset must lie on the block, 0 <= x_n <= Δx")
        if np.any((self.offset > 0.0) & (self.height < blocks.heights)):
            raise ValueError(
                "a support off the downhill face (offset > 0) acts on the block's top, h_n = y_n"
            )


def _face_levels(blocks: BlockSystem) -> tuple[NDArray, NDArray]:
    """Vertical heights above the toe [m] of the foot and top of each block's exposed downhill face.

    The toe is block 1's downhill base corner; block n's downhill base corner lies (n − 1)Δx along the
    bases and (n − 1)b normal to them from it, and its face is exposed from max(L_n, 0) to y_n."""
    if not math.isfinite(blocks.b):
        raise ValueError("a point on the slope face needs a regular system (its step b)")
    n = np.arange(blocks.n_blocks)
    sa, ca = math.sin(blocks.base_dip), math.cos(blocks.base_dip)
    corner = n * blocks.width * sa + n * blocks.b * ca
    return corner + np.maximum(blocks.lower_arm, 0.0) * ca, corner + blocks.heights * ca


def face_support(blocks: BlockSystem, level: float, force: float, plunge: float) -> BlockSupport:
    """A support of `force` [N/m] placed on the slope face at `level` [m] above the toe (vertically, as
    RocTopple places line loads), plunging `plunge` [rad] below the horizontal into the slope.

    The face of a regular system is a staircase: each block's exposed downhill face, then its top. The
    point is on the face of the block whose exposed face spans `level` (h_n from the level), or on the
    top of the block below it (x_n from the level). θ = α + plunge."""
    foot, top = _face_levels(blocks)
    if not 0.0 <= level <= top[-1]:
        raise ValueError(f"level {level:.4g} m is not on the slope face (0 to {top[-1]:.4g} m)")
    sa, ca = math.sin(blocks.base_dip), math.cos(blocks.base_dip)
    angle = blocks.base_dip + plunge
    on_face = np.flatnonzero((foot <= level) & (level <= top))
    if on_face.size:
        k = int(on_face[0])
        height = max(blocks.lower_arm[k], 0.0) + (level - foot[k]) / ca
        return BlockSupport.on_block(blocks, k + 1, force, angle, min(height, blocks.heights[k]))
    k = int(np.flatnonzero(top < level)[-1])  # on the top of block k + 1
    offset = min((level - top[k]) / sa, blocks.width)
    return BlockSupport.on_block(blocks, k + 1, force, angle, blocks.heights[k], offset)


@dataclass(frozen=True)
class BlockWater:
    """Water in the joints, one entry per block (index 0 = toe): upper y_w,n and lower z_w,n [m], its
    height above the block's base on the uphill and downhill side (along the sides); unit_weight γ_w
    [N/m³]. The forces V_1, V_2, V_3 are in the module docstring."""

    upper: NDArray[np.float64]
    lower: NDArray[np.float64]
    unit_weight: float = WATER_UNIT_WEIGHT

    def __post_init__(self) -> None:
        for name in ("upper", "lower"):
            object.__setattr__(self, name, np.atleast_1d(np.asarray(getattr(self, name), dtype=float)))
        if self.upper.shape != self.lower.shape or self.upper.ndim != 1:
            raise ValueError("water heights need one upper and one lower entry per block")
        if np.any(~(self.upper >= 0.0)) or np.any(~(self.lower >= 0.0)) or not self.unit_weight >= 0.0:
            raise ValueError("water heights and the water's unit weight must be >= 0")

    def check(self, blocks: BlockSystem) -> None:
        if self.upper.size != blocks.n_blocks:
            raise ValueError(f"water has {self.upper.size} entries for {blocks.n_blocks} blocks")
        if np.any(self.upper > blocks.heights) or np.any(self.lower > blocks.heights):
            raise ValueError("water cannot stand above a block's top in its joints")

    def forces(self, base_dip: float, width: float) -> dict[str, NDArray[np.float64]]:
        """V_1, V_2, V_3 [N/m] and their moments about each block's pivot [N m/m] (toppling positive)."""
        k = 0.5 * self.unit_weight * math.cos(base_dip)
        yw, zw = self.upper, self.lower
        v1, v3, v2 = k * yw**2, k * zw**2, k * (yw + zw) * width
        moment = v1 * yw / 3.0 - v3 * zw / 3.0 + k * width**2 * (2.0 * yw + zw) / 3.0
        return {"upper": v1, "uplift": v2, "lower": v3, "moment": moment}


def phreatic_water(
    blocks: BlockSystem, surface_x: ArrayLike, surface_z: ArrayLike, unit_weight: float = WATER_UNIT_WEIGHT
) -> BlockWater:
    """The water in a regular system's joints below a phreatic line.

    surface_x, surface_z [m]: the line's vertices, x horizontal into the slope and z up from the toe (the
    toe block's downhill base corner), x increasing; level beyond its ends. The joint between blocks n
    and n+1 rises from block n's uphill base corner normal to the bases; the water stands in it where it
    meets the line, at most to the joint's top M_n (where block n+1's or n's top ends it); block n+1
    sees it b lower. The toe block's downhill face is the free slope face (dry), as is the top block's
    uphill side."""
    xs, zs = np.asarray(surface_x, dtype=float), np.asarray(surface_z, dtype=float)
    if xs.ndim != 1 or xs.shape != zs.shape or xs.size < 2 or np.any(np.diff(xs) <= 0.0):
        raise ValueError("the phreatic line needs two or more vertices with x increasing")
    if not math.isfinite(blocks.b):
        raise ValueError("water from a phreatic line needs a regular system (its step b)")
    sa, ca = math.sin(blocks.base_dip), math.cos(blocks.base_dip)
    n = np.arange(1, blocks.n_blocks + 1)
    along, normal = n * blocks.width, (n - 1) * blocks.b  # the foot of each joint, in the bases' frame
    top = np.maximum(blocks.upper_arm, 0.0)
    top[-1] = 0.0

    def above(s: NDArray) -> NDArray:
        """Height of the water line above the joint's point s [m] up from its foot."""
        x = along * ca - (normal + s) * sa
        z = along * sa + (normal + s) * ca
        return np.interp(x, xs, zs) - z

    low, high = np.zeros(blocks.n_blocks), top.copy()
    for _ in range(60):  # bisection on each joint at once: 2^-60 of the joint's length
        mid = 0.5 * (low + high)
        wet = above(mid) > 0.0
        low, high = np.where(wet, mid, low), np.where(wet, high, mid)
    level = np.where(above(np.zeros_like(top)) > 0.0, 0.5 * (low + high), 0.0)
    lower = np.concatenate([[0.0], np.clip(level[:-1] - blocks.b, 0.0, None)])
    lower = np.minimum(lower, np.maximum(blocks.lower_arm, 0.0))
    return BlockWater(level, lower, unit_weight)
