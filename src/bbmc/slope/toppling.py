"""Goodman & Bray's (1976) limit-equilibrium analysis of block toppling on a stepped base.

The method as it is taught in Hoek & Bray, *Rock Slope Engineering* (3rd ed. 1981, ch. 10) and
Wyllie & Mah, *Rock Slope Engineering: Civil and Mining* (4th ed. 2004, ch. 9, section 9.4): a slope
is cut into N rectangular blocks of width Δx standing on a stepped base. Each block's base dips at
α (Wyllie & Mah's ψ_p; the base is normal to the toppling joints, so α = 90° − their dip); the line
through the steps, the overall base, dips at ψ_b ≥ α. Blocks are numbered from the toe (block 1)
upwards. Going from the top block down, each block n receives the force P_n from the block above and
passes P_{n−1} to the block below; the force left on the toe block's lower side, P_0, is the support
the slope needs (negative: a surplus, the slope stands). Units: SI inside and out (m, rad, γ in N/m³,
forces in N per metre of slope).

Equilibrium of block n (Wyllie & Mah 2004, section 9.4; re-derived here, see ``toppling_forces``):
    R_n = W_n cos α + (P_n − P_{n−1}) tan φ_d                 normal force on the base
    S_n = W_n sin α + (P_n − P_{n−1})                         shear force on the base
    toppling about its downhill base corner:
    P_{n−1,t} = [P_n (M_n − Δx tan φ_d) + (W_n/2)(y_n sin α − Δx cos α)] / L_n
    sliding (S_n = R_n tan φ_p):
    P_{n−1,s} = P_n − W_n (tan φ_p cos α − sin α) / (1 − tan φ_p tan φ_d)
  with W_n = γ y_n Δx. [HB81]'s worked example uses φ_p = φ_d = φ; then 1 − tan φ_p tan φ_d = 1 − tan² φ.

Support on chosen blocks (as RocTopple applies bolts; derived here from the same three equations):
  a force T_n per metre run on block n's downhill face at h_n above its base, at θ_n from the base's
  up-dip direction, positive towards the base (into the rock below): T_s = T_n cos θ_n up the base,
  T_⊥ = T_n sin θ_n onto it. Acting on the face through the pivot's line, T_⊥ has no moment; T_s
  resists toppling with the arm h_n:
    R_n = W_n cos α + (P_n − P_{n−1}) tan φ_d + T_⊥
    S_n = W_n sin α + (P_n − P_{n−1}) − T_s
    P_{n−1,t} = [P_n (M_n − Δx tan φ_d) + (W_n/2)(y_n sin α − Δx cos α) − T_s h_n] / L_n
    P_{n−1,s} = P_n − [W_n (tan φ_p cos α − sin α) + T_s + T_⊥ tan φ_p] / (1 − tan φ_p tan φ_d)
  With T = 0 these are the equations above. A support makes the forces no longer proportional to γ,
  so the limiting friction and FS then depend on the unit weight.

Limiting equilibrium and factor of safety ([HB81], [WM04]): the friction angle at which P_0 = 0, found
here with Brent's method; the factor of safety is the factor by which tan φ must be divided to reach
it, FS = tan φ / tan φ_limit when the bases and sides share one friction angle.

The sources ([GB76], [HB81], [WM04], [IIT], [RS]) and where each formula was checked, the regular
system's heights and arms, the crest block, the marching procedure with its three stated choices, and
the cross-checks: docs/reference/toppling-method.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from bbmc.geometry.polygons import MAX_BLOCKS

#: Mode codes of the internal march and the strings the tables carry.
STABLE, TOPPLES, SLIDES = 0, 1, 2
MODE_NAMES = ("stable", "topples", "slides")


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


@dataclass(frozen=True)
class BlockSupport:
    """Support forces on the blocks of a system, one entry per block (index 0 = block 1, the toe):
    force T_n [N per metre run] (0: no support), angle θ_n [rad] from the base's up-dip direction towards
    the base, height h_n [m] above the base on the block's downhill face (module docstring)."""

    force: NDArray[np.float64]
    angle: NDArray[np.float64]
    height: NDArray[np.float64]

    def __post_init__(self) -> None:
        for name in ("force", "angle", "height"):
            object.__setattr__(self, name, np.atleast_1d(np.asarray(getattr(self, name), dtype=float)))
        if not (self.force.shape == self.angle.shape == self.height.shape) or self.force.ndim != 1:
            raise ValueError("support force, angle and height need one entry per block")
        if np.any(~(self.force >= 0.0)):
            raise ValueError("support force must be >= 0 (a bolt pulls, it cannot push)")

    @classmethod
    def on_block(
        cls, blocks: BlockSystem, block: int, force: float, angle: float, height: float
    ) -> BlockSupport:
        """One support on block number `block` (1 = toe) of `blocks`, none on the others."""
        if not 1 <= block <= blocks.n_blocks:
            raise ValueError(f"block {block} is not one of the system's 1..{blocks.n_blocks}")
        values = np.zeros((3, blocks.n_blocks))
        values[:, block - 1] = force, angle, height
        return cls(*values)

    def check(self, blocks: BlockSystem) -> None:
        if self.force.size != blocks.n_blocks:
            raise ValueError(f"support has {self.force.size} entries for {blocks.n_blocks} blocks")
        if np.any((self.height < 0.0) | (self.height > blocks.heights)):
            raise ValueError("support height must lie on the block's face, 0 <= h_n <= y_n")


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


# --- the march from the top block down ------------------------------------------------------------
def _march(
    blocks: BlockSystem,
    tan_base: ArrayLike,
    tan_side: ArrayLike,
    unit_weight: float,
    support: BlockSupport | None = None,
) -> dict[str, NDArray]:
    """Forces of every block, vectorised over the friction arrays (broadcast together).

    Returns arrays of shape friction_shape + (N,), index 0 = toe block, and "toe_force" of shape
    friction_shape.
    """
    tp, td = np.broadcast_arrays(np.asarray(tan_base, dtype=float), np.asarray(tan_side, dtype=float))
    shape = (*tp.shape, blocks.n_blocks)
    out = {
        k: np.empty(shape)
        for k in ("force_above", "p_topple", "p_slide", "force_below", "normal_force", "shear_force")
    }
    out["mode"] = np.empty(shape, dtype=np.int8)
    dx, alpha = blocks.width, blocks.base_dip
    sa, ca = math.sin(alpha), math.cos(alpha)
    lock = 1.0 - tp * td
    if support is None:
        support = BlockSupport(*np.zeros((3, blocks.n_blocks)))
    support.check(blocks)
    along, onto = support.force * np.cos(support.angle), support.force * np.sin(support.angle)
    p_above = np.zeros(tp.shape)
    raw = np.zeros(tp.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        for i in range(blocks.n_blocks - 1, -1, -1):
            y, m_arm, l_arm = blocks.heights[i], blocks.upper_arm[i], blocks.lower_arm[i]
            w = unit_weight * y * dx
            t_s, t_n = along[i], onto[i]
            moment = p_above * (m_arm - dx * td) + 0.5 * w * (y * sa - dx * ca) - t_s * support.height[i]
            # if L_n <= 0 the lower force acts at or below the pivot and cannot hold the block
            p_t = moment / l_arm if l_arm > 0.0 else np.where(moment > 0.0, np.inf, -np.inf)
            p_s = np.where(lock > 0.0, p_above - (w * (tp * ca - sa) + t_s + t_n * tp) / lock, -np.inf)
            r_t = w * ca + (p_above - p_t) * td + t_n
            s_t = w * sa + (p_above - p_t) - t_s
            admissible = np.isfinite(p_t) & (r_t > 0.0) & (np.abs(s_t) < r_t * tp)
            admissible |= p_t == np.inf  # cannot be held at all: it topples
            topples = admissible & (p_t > p_s) & (p_t > 0.0)
            slides = ~topples & (p_s > 0.0)
            mode = np.where(topples, TOPPLES, np.where(slides, SLIDES, STABLE))
            raw = np.where(admissible, np.maximum(p_t, p_s), p_s)
            p_below = np.where(topples, p_t, np.where(slides, p_s, 0.0))
            out["force_above"][..., i] = p_above
            out["p_topple"][..., i] = p_t
            out["p_slide"][..., i] = p_s
            out["force_below"][..., i] = p_below
            out["normal_force"][..., i] = w * ca + (p_above - p_below) * td + t_n
            out["shear_force"][..., i] = w * sa + (p_above - p_below) - t_s
            out["mode"][..., i] = mode
            p_above = p_below
    out["toe_force"] = raw
    return out


@dataclass(frozen=True)
class TopplingTable:
    """Result of ``toppling_forces``; every array has one entry per block, index 0 = block 1 (toe).

    block         block number n (1 = toe)
    height        y_n [m];  upper_arm M_n [m];  lower_arm L_n [m]
    weight        W_n = γ y_n Δx [N/m]
    force_above   P_n [N/m], from block n+1 (0 for the top block)
    p_topple      P_{n−1,t} [N/m], the lower-side force that holds block n against toppling
    p_slide       P_{n−1,s} [N/m], the lower-side force that holds block n against sliding
    force_below   P_{n−1} [N/m], the force passed down, max(P_{n−1,t} if admissible, P_{n−1,s}, 0)
    mode          'stable', 'topples' or 'slides'
    normal_force  R_n [N/m] and shear_force S_n [N/m] on block n's base, with P_{n−1} = force_below
    topples_alone y_n/Δx > cot α (the single-block toppling test)
    slides_alone  α > φ_p (the single-block sliding test)
    toe_force     P_0 [N/m], the toe block's governing lower-side force, not clipped at zero: the
                  support needed (> 0) or the surplus (< 0)
    """

    block: NDArray[np.int64]
    height: NDArray[np.float64]
    upper_arm: NDArray[np.float64]
    lower_arm: NDArray[np.float64]
    weight: NDArray[np.float64]
    force_above: NDArray[np.float64]
    p_topple: NDArray[np.float64]
    p_slide: NDArray[np.float64]
    force_below: NDArray[np.float64]
    mode: NDArray[np.str_]
    normal_force: NDArray[np.float64]
    shear_force: NDArray[np.float64]
    topples_alone: NDArray[np.bool_]
    slides_alone: NDArray[np.bool_]
    toe_force: float
    friction_base: float
    friction_side: float
    blocks: BlockSystem = field(repr=False)

    def to_frame(self) -> pd.DataFrame:
        """The table as a DataFrame indexed by block number, top block first as [HB81] prints it."""
        cols = [
            "height",
            "upper_arm",
            "lower_arm",
            "weight",
            "force_above",
            "p_topple",
            "p_slide",
            "force_below",
            "mode",
            "normal_force",
            "shear_force",
            "topples_alone",
            "slides_alone",
        ]
        frame = pd.DataFrame({c: getattr(self, c) for c in cols}, index=pd.Index(self.block, name="block"))
        return frame.iloc[::-1]


def toppling_forces(
    blocks: BlockSystem,
    friction: float,
    unit_weight: float,
    side_friction: float | None = None,
    support: BlockSupport | None = None,
) -> TopplingTable:
    """Goodman & Bray's block-by-block limit equilibrium, from the top block down.

    blocks: the block system (``regular_block_heights`` or a ``BlockSystem`` of measured heights);
    friction φ_p [rad] on the block bases; unit_weight γ [N/m³]; side_friction φ_d [rad] on the block
    sides (default: = friction, as in [HB81]'s example); support: forces on chosen blocks (module
    docstring), none by default.

    Equilibrium of block n (axes along and normal to its base; moments about its downhill base corner;
    P_n pushes it downhill at M_n with the side shear Q_n = P_n tan φ_d pressing its uphill side down;
    P_{n−1} pushes it uphill at L_n, its shear Q_{n−1} acting through the pivot):
      normal:  R_n = W_n cos α + (P_n − P_{n−1}) tan φ_d
      along:   S_n = W_n sin α + (P_n − P_{n−1})
      moment:  P_{n−1} L_n = P_n (M_n − Δx tan φ_d) + (W_n/2)(y_n sin α − Δx cos α)   → P_{n−1,t}
      sliding: S_n = R_n tan φ_p                                                     → P_{n−1,s}
    The mode rules and the support's terms are in the module docstring.
    """
    phi_d = friction if side_friction is None else side_friction
    res = _march(blocks, math.tan(friction), math.tan(phi_d), unit_weight, support)
    y = blocks.heights
    return TopplingTable(
        block=blocks.numbers,
        height=y.copy(),
        upper_arm=blocks.upper_arm.copy(),
        lower_arm=blocks.lower_arm.copy(),
        weight=unit_weight * y * blocks.width,
        force_above=res["force_above"],
        p_topple=res["p_topple"],
        p_slide=res["p_slide"],
        force_below=res["force_below"],
        mode=np.asarray(MODE_NAMES)[res["mode"]],
        normal_force=res["normal_force"],
        shear_force=res["shear_force"],
        topples_alone=y / blocks.width > 1.0 / math.tan(blocks.base_dip),
        slides_alone=np.full(y.shape, blocks.base_dip > friction),
        toe_force=float(res["toe_force"]),
        friction_base=friction,
        friction_side=phi_d,
        blocks=blocks,
    )


def toe_force(
    blocks: BlockSystem,
    friction: ArrayLike,
    unit_weight: float,
    side_friction: ArrayLike | None = None,
    support: BlockSupport | None = None,
) -> NDArray[np.float64]:
    """P_0 [N/m], the force the toe block needs on its lower side, vectorised over friction [rad]."""
    phi_d = friction if side_friction is None else side_friction
    return _march(blocks, np.tan(friction), np.tan(phi_d), unit_weight, support)["toe_force"]


def _weight_scale(
    blocks: BlockSystem, support: BlockSupport | None, unit_weight: float | None
) -> tuple[float, float]:
    """The unit weight the march needs (1 without support: every force then scales with γ) and the
    blocks' total weight, the scale of P_0 in the root searches."""
    if support is None:
        return 1.0, blocks.width * float(blocks.heights.sum())
    if unit_weight is None or not unit_weight > 0.0:
        raise ValueError("a supported system needs its unit weight (> 0): the forces no longer scale with it")
    return unit_weight, unit_weight * blocks.width * float(blocks.heights.sum())


def horizontal_toe_support(
    blocks: BlockSystem, friction: float, unit_weight: float, side_friction: float | None = None
) -> float:
    """The horizontal force [N/m] on the toe block's face that holds a sliding toe block.

    With a horizontal force H (no friction of its own) in place of P_0, the toe block's equilibrium
    along and normal to its base with S_1 = R_1 tan φ_p gives (derived here)
        H (cos α + tan φ_p sin α) = (1 − tan φ_p tan φ_d) P_{0,s}.
    Negative: the toe has a surplus. Raises if the toe block topples (then H depends on where it acts).
    """
    table = toppling_forces(blocks, friction, unit_weight, side_friction)
    if table.mode[0] == "topples":
        raise ValueError("the toe block topples: a horizontal support needs its point of application")
    tp, td = math.tan(table.friction_base), math.tan(table.friction_side)
    alpha = blocks.base_dip
    p0_slide = float(table.p_slide[0])
    return (1.0 - tp * td) * p0_slide / (math.cos(alpha) + tp * math.sin(alpha))


def limiting_friction(
    blocks: BlockSystem,
    bracket: tuple[float, float] | None = None,
    xtol: float = 1e-13,
    support: BlockSupport | None = None,
    unit_weight: float | None = None,
) -> float:
    """The friction angle φ_limit [rad] (bases and sides alike) at which P_0 = 0 (Brent's method).

    Independent of the unit weight without support (every force scales with γ); with a support, its
    unit_weight γ [N/m³] is needed. bracket: (low, high) [rad] with P_0(low) > 0 > P_0(high); default
    (1e-6, π/4 − 1e-9), as the sliding equation needs tan² φ < 1.
    """
    low, high = bracket if bracket is not None else (1e-6, math.pi / 4 - 1e-9)
    gamma, scale = _weight_scale(blocks, support, unit_weight)

    def p0(phi: float) -> float:
        # arctan keeps the sign and the root but maps P_0 = ±inf (a block its lower neighbour
        # cannot hold, or sliding locked by side friction) to ±π/2 so that Brent's method can work
        return math.atan(float(toe_force(blocks, phi, gamma, support=support)) / scale)

    f_low, f_high = p0(low), p0(high)
    if not (f_low > 0.0 > f_high):
        raise ValueError(
            f"P_0 does not change sign over the bracket {math.degrees(low):.4g}°-{math.degrees(high):.4g}°"
        )
    return float(brentq(p0, low, high, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=500))


def factor_of_safety(
    blocks: BlockSystem,
    friction: ArrayLike,
    side_friction: ArrayLike | None = None,
    support: BlockSupport | None = None,
    unit_weight: float | None = None,
) -> NDArray[np.float64]:
    """FS [1]: the factor by which tan φ_p and tan φ_d must both be divided for P_0 = 0; broadcast over
    arrays of friction angles [rad] (a Monte Carlo calls it once for all samples).

    With one friction angle on bases and sides this is [HB81]'s FS = tan φ / tan φ_limit. A support
    (not reduced) needs the unit weight γ [N/m³].
    """
    if side_friction is None:
        limit = limiting_friction(blocks, support=support, unit_weight=unit_weight)
        return np.tan(friction) / math.tan(limit)
    return np.vectorize(
        lambda p, d: _factor_of_safety_two_angles(blocks, p, d, support, unit_weight), otypes=[float]
    )(friction, side_friction)


def _factor_of_safety_two_angles(
    blocks: BlockSystem,
    friction: float,
    side_friction: float,
    support: BlockSupport | None,
    unit_weight: float | None,
) -> float:
    tp, td = math.tan(friction), math.tan(side_friction)
    gamma, scale = _weight_scale(blocks, support, unit_weight)

    def p0(fs: float) -> float:
        reduced = toe_force(blocks, math.atan(tp / fs), gamma, math.atan(td / fs), support)
        return math.atan(float(reduced) / scale)

    low, high = 1e-3, 1e3
    # keep tan φ_p tan φ_d / FS² < 1 so the sliding equation stays defined
    low = max(low, math.sqrt(tp * td) * (1.0 + 1e-9))
    f_low, f_high = p0(low), p0(high)
    if not (f_low < 0.0 < f_high):
        raise ValueError(f"P_0 does not change sign between FS = {low:.4g} and {high:.4g}")
    return float(brentq(p0, low, high, xtol=1e-13, rtol=4 * np.finfo(float).eps, maxiter=500))
