"""The forces and modes of every block at one pair of friction angles, as [HB81] tabulates them."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from bbmc.slope.toppling.geometry import BlockSystem
from bbmc.slope.toppling.loads import BlockSupport, BlockWater
from bbmc.slope.toppling.march import MODE_NAMES, Loads, march


@dataclass(frozen=True)
class TopplingTable:
    """Result of ``toppling_forces``; every array has one entry per block, index 0 = block 1 (toe).

    block         block number n (1 = toe)
    height        y_n [m];  upper_arm M_n [m];  lower_arm L_n [m]
    weight        W_n = γ y_n Δx [N/m]
    force_above   P_n [N/m], from block n+1 (0 for the top block)
    p_topple      P_{n−1,t} [N/m], the lower-side force that holds block n against toppling (+∞: none
                  can, its lower force acting at or below the pivot)
    p_slide       P_{n−1,s} [N/m], the lower-side force that holds block n against sliding (−∞: locked)
    force_below   P_{n−1} [N/m], the force passed down, max(P_{n−1,t}, P_{n−1,s}, 0); +∞ from the first
                  block not held down to the toe
    mode          'stable', 'topples' or 'slides'
    held          whether a lower force can hold the block (``bbmc.slope.toppling.march``)
    normal_force  R_n [N/m] and shear_force S_n [N/m] on block n's base, dry and unsupported terms
                  included, with P_{n−1} = force_below (nan where not held)
    topples_alone y_n/Δx > cot α (the single-block toppling test)
    slides_alone  α > φ_p (the single-block sliding test)
    toe_force     P_0 [N/m], the toe block's governing lower-side force, not clipped at zero: the
                  support needed (> 0), the surplus (< 0), +∞ if some block cannot be held
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
    held: NDArray[np.bool_]
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
            "held",
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
    water: BlockWater | None = None,
) -> TopplingTable:
    """Goodman & Bray's block-by-block limit equilibrium, from the top block down
    (``bbmc.slope.toppling.march`` has the equations and rules).

    blocks: the block system; friction φ_p [rad] on the block bases; unit_weight γ [N/m³]; side_friction
    φ_d [rad] on the block sides (default: = friction, as in [HB81]'s example); support and water: loads
    on the blocks (``bbmc.slope.toppling.loads``), none by default.
    """
    phi_d = friction if side_friction is None else side_friction
    loads = Loads(blocks, unit_weight, support, water)
    tp, td = math.tan(friction), math.tan(phi_d)
    res = march(loads, tp, td, record=True)
    below = np.where(res["held"], res["force_below"], np.nan)
    dp = res["force_above"] - below
    y = blocks.heights
    return TopplingTable(
        block=blocks.numbers,
        height=y.copy(),
        upper_arm=blocks.upper_arm.copy(),
        lower_arm=blocks.lower_arm.copy(),
        weight=loads.weight,
        force_above=res["force_above"],
        p_topple=res["p_topple"],
        p_slide=res["p_slide"],
        force_below=res["force_below"],
        mode=np.asarray(MODE_NAMES)[res["mode"]],
        held=res["held"],
        normal_force=loads.normal + dp * td,
        shear_force=loads.along + dp,
        topples_alone=y / blocks.width > 1.0 / math.tan(blocks.base_dip),
        slides_alone=np.full(y.shape, blocks.base_dip > friction),
        toe_force=float(res["toe_force"]),
        friction_base=friction,
        friction_side=phi_d,
        blocks=blocks,
    )
