"""The geometry of a toppling analysis: the blocks of Goodman & Bray's regular system on a stepped base.

A slope is cut into N rectangular blocks of width Δx standing on a stepped base (Goodman & Bray 1976;
Hoek & Bray 1981, ch. 10; Wyllie & Mah 2004, section 9.4). Each block's base dips at α, normal to the
toppling joints (α = 90° − their dip); the line through the steps, the overall base, dips at ψ_b ≥ α.
Blocks are numbered from the toe (block 1) upwards. ``slope_blocks`` builds the system from RocTopple's
inputs (slope height and angle, upper slope angle, toppling joint dip and spacing, overall base
inclination); ``regular_system`` from the constants a1, a2, b; ``BlockSystem`` takes measured heights.
The regular system's heights, arms and crest block are derived in docs/reference/toppling-method.md.
Units: SI (m, rad).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from bbmc.geometry.polygons import MAX_BLOCKS


# --- geometry of the regular system ---------------------------------------------------------------
@dataclass(frozen=True)
class BlockSystem:
    """The blocks of a toppling analysis, numbered from the toe (index 0 = block 1).

    heights    y_n [m], the block heights normal to the base
    upper_arm  M_n [m], height above block n's base at which P_n (from block n+1) acts
    lower_arm  L_n [m], height above block n's base at which P_{n−1} (from block n−1) acts
    width      Δx [m], block width along the base
    base_dip   α [rad], dip of each block's base
    crest_block  n_c (1-based), the block containing the crest; 0 if not a regular system
    a1, a2, b  [m], the regular system's constants (nan if not a regular system)
    """

    heights: NDArray[np.float64]
    upper_arm: NDArray[np.float64]
    lower_arm: NDArray[np.float64]
    width: float
    base_dip: float
    crest_block: int = 0
    a1: float = math.nan
    a2: float = math.nan
    b: float = math.nan

    def __post_init__(self) -> None:
        for name in ("heights", "upper_arm", "lower_arm"):
            arr = np.asarray(getattr(self, name), dtype=float)
            if arr.ndim != 1:
                raise ValueError(f"{name} must be one-dimensional")
            object.__setattr__(self, name, arr)
        if not (self.heights.shape == self.upper_arm.shape == self.lower_arm.shape):
            raise ValueError("heights, upper_arm and lower_arm must have the same length")
        if self.heights.size == 0 or np.any(self.heights <= 0.0):
            raise ValueError("block heights must be positive (and there must be at least one block)")
        if not self.width > 0.0:
            raise ValueError("block width must be positive")

    @property
    def n_blocks(self) -> int:
        return int(self.heights.size)

    @property
    def numbers(self) -> NDArray[np.int64]:
        """Block numbers 1..N (1 = toe block)."""
        return np.arange(1, self.n_blocks + 1)


def regular_constants(
    width: float, base_dip: float, base_line_dip: float, face_angle: float, upper_slope_angle: float
) -> tuple[float, float, float]:
    """The constants (a1, a2, b) [m] of a regular system.

    a1 = Δx tan(ψ_f − α), a2 = Δx tan(α − ψ_s), b = Δx tan(ψ_b − α)   ([GB76], [WM04] 9.4)

    width Δx [m]; base_dip α, base_line_dip ψ_b, face_angle ψ_f, upper_slope_angle ψ_s [rad].
    """
    if base_line_dip < base_dip:
        raise ValueError("the overall base dip ψ_b cannot be less than the block base dip α ([RS])")
    a1 = width * math.tan(face_angle - base_dip)
    a2 = width * math.tan(base_dip - upper_slope_angle)
    b = width * math.tan(base_line_dip - base_dip)
    return a1, a2, b


def crest_block_number(slope_height: float, width: float, base_dip: float, face_angle: float) -> int:
    """The number n_c (1 = toe) of the block whose top holds the crest [1].

    The uphill top corner of block n lies on the face line at height z_n = n Δx sin ψ_f / cos(ψ_f − α)
    above the toe; n_c is the first n with z_n ≥ H: n_c = ceil(H cos(ψ_f − α) / (Δx sin ψ_f)).
    slope_height H [m], width Δx [m], base_dip α and face_angle ψ_f [rad]. (Derived here.)
    """
    n = slope_height * math.cos(face_angle - base_dip) / (width * math.sin(face_angle))
    return max(1, math.ceil(n - 1e-9))


def regular_system(
    width: float,
    base_dip: float,
    crest_block: int,
    a1: float,
    a2: float,
    b: float,
    n_blocks: int | None = None,
) -> BlockSystem:
    """Heights and moment arms of a regular system from its constants a1, a2, b [m].

    y_n = n (a1 − b) for n ≤ n_c, y_n = y_{n−1} − a2 − b above the crest; M_n, L_n as in the module
    docstring. n_blocks=None takes every block of positive height.
    """
    if crest_block < 1:
        raise ValueError("crest_block is 1-based and at least 1")
    if not a1 - b > 0.0:
        raise ValueError("a1 − b ≤ 0: block heights do not grow towards the crest")
    y_crest = crest_block * (a1 - b)
    if n_blocks is None:
        above = y_crest / (a2 + b) - 1e-12 if a2 + b > 0 else 0.0
        n_blocks = crest_block + max(math.floor(above), 0) if above < MAX_BLOCKS else MAX_BLOCKS + 1
    if n_blocks > MAX_BLOCKS:
        raise ValueError(f"the system would have more than {MAX_BLOCKS:,} blocks")
    n = np.arange(1, n_blocks + 1)
    heights = np.where(n <= crest_block, n * (a1 - b), y_crest - (n - crest_block) * (a2 + b))
    upper = np.where(n < crest_block, heights, heights - a2)
    lower = np.where(n <= crest_block, heights - a1, heights)
    return BlockSystem(heights, upper, lower, width, base_dip, crest_block, a1, a2, b)


def regular_block_heights(
    n_blocks: int | None,
    width: float,
    base_dip: float,
    base_line_dip: float,
    face_angle: float,
    upper_slope_angle: float,
    crest_block: int,
) -> BlockSystem:
    """The regular block system of [GB76]/[HB81]: heights y_n and moment arms M_n, L_n.

    n_blocks: number of blocks (None: all blocks of positive height); width Δx [m]; base_dip α,
    base_line_dip ψ_b, face_angle ψ_f, upper_slope_angle ψ_s [rad]; crest_block n_c, 1-based from the
    toe (see ``crest_block_number`` for how to find it from the slope height).
    """
    a1, a2, b = regular_constants(width, base_dip, base_line_dip, face_angle, upper_slope_angle)
    return regular_system(width, base_dip, crest_block, a1, a2, b, n_blocks)


def slope_blocks(
    slope_height: float,
    slope_angle: float,
    upper_slope_angle: float,
    joint_dip: float,
    joint_spacing: float,
    base_inclination: float,
    n_blocks: int | None = None,
) -> BlockSystem:
    """The regular block system of a slope from RocTopple's geometry inputs.

    slope_height H [m] (vertical, toe to crest); slope_angle ψ_f, upper_slope_angle ψ_s [rad] (0: a
    horizontal upper slope); joint_dip [rad], the dip of the toppling joints into the slope; joint_spacing
    Δx [m], their spacing normal to the joints (the block width); base_inclination ψ_b [rad], the overall
    base from the toe to the exit on the upper slope. The block bases are normal to the joints,
    α = 90° − joint_dip, and ψ_b ≥ α (RocTopple's "Slope Geometry" and "Overall Base Inclination" help
    pages). The blocks are generated as Goodman & Bray did (RocTopple's "Goodman and Bray" block
    generation, not its default "Equal Area"): a1 = Δx tan(ψ_f − α), a2 = Δx tan(α − ψ_s),
    b = Δx tan(ψ_b − α), the crest on block ``crest_block_number(H, Δx, α, ψ_f)``; n_blocks=None keeps
    every block of positive height.
    """
    base_dip = 0.5 * math.pi - joint_dip
    if not 0.0 < base_dip < slope_angle:
        raise ValueError("the toppling joints must dip into the slope more steeply than 90° − slope angle")
    if base_dip - 1e-12 <= base_inclination < base_dip:  # equal but for the rounding of 90° − dip
        base_inclination = base_dip
    crest = crest_block_number(slope_height, joint_spacing, base_dip, slope_angle)
    return regular_block_heights(
        n_blocks, joint_spacing, base_dip, base_inclination, slope_angle, upper_slope_angle, crest
    )
