"""Goodman & Bray's march from the top block down: the force each block needs from the block below.

Equilibrium of block n (Wyllie & Mah 2004, section 9.4, eqs. 9.27-9.33; re-derived here; axes along and
normal to its base, moments about its downhill base corner, the pivot). P_n pushes it downhill at M_n
with the side shear Q_n = P_n tan φ_d pressing its uphill side down; P_{n−1} pushes it uphill at L_n,
its shear Q_{n−1} acting through the pivot; water V_1, V_2, V_3 and support T_s, T_⊥ as in
``bbmc.slope.toppling.loads``:
    R_n = W_n cos α + (P_n − P_{n−1}) tan φ_d − V_2 + T_⊥                 normal force on the base
    S_n = W_n sin α + (P_n − P_{n−1}) + V_1 − V_3 − T_s                    shear force on the base
    toppling:  P_{n−1,t} = [P_n (M_n − Δx tan φ_d) + (W_n/2)(y_n sin α − Δx cos α) + M_V − T_s h_n
                            − T_⊥ x_n] / L_n                              (M_V: the water's moment)
    sliding:   P_{n−1,s} = P_n + [W_n (sin α − tan φ_p cos α) + V_1 + V_2 tan φ_p − V_3 − T_s
                            − T_⊥ tan φ_p] / (1 − tan φ_p tan φ_d)
Dry and unsupported these are [HB81]'s equations.

The force block n passes down is the least P_{n−1} that holds it: P_{n−1} = max(P_{n−1,t}, P_{n−1,s}, 0)
(topples if P_{n−1,t} governs and is > 0, slides if P_{n−1,s} does, stable if neither is positive).
A block is **not held** and the system fails (P_0 = +∞) if its lower force acts at or below its pivot
(L_n ≤ 0; the toe block of a regular system, L_1 = −b) while the other loads topple it, as that force
cannot resist toppling (it is given no moment), or if its base carries no compression without the side
forces (W_n cos α − V_2 + T_⊥ ≤ 0: the water floats it). Hoek & Bray also ask R_n > 0 and
|S_n| < R_n tan φ_p of a toppling block; the march does not fail a block on them: where P_{n−1} = P_{n−1,t}
lifts block n or pushes it up its base, block n presses on block n+1, whose reaction P_n may grow beyond
the least force it passes down, and the system is not thereby failing. (Taking such a block as sliding
instead, with its smaller P_{n−1,s}, made P_0 jump and the factor of safety depend on where the search
looked.) Where 1 − tan φ_p tan φ_d ≤ 0, to within rounding (1e-12), side and base
friction lock sliding: P_{n−1,s} = −∞ ([WM04]'s sliding equation tends to −∞ as the factor tends to 0⁺
whenever the block would not slide without it; when it would, the compression bound above fails first).
The toe block's governing force P_0 = max(P_{0,t}, P_{0,s}) is not clipped at zero: the support the
slope needs (> 0) or its surplus (< 0; −∞ when sliding is locked and nothing topples it).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.toppling.geometry import BlockSystem
from bbmc.slope.toppling.loads import BlockSupport, BlockWater

#: Mode codes of the march and the strings the tables carry.
STABLE, TOPPLES, SLIDES = 0, 1, 2
MODE_NAMES = ("stable", "topples", "slides")
#: 1 − tan φ_p tan φ_d at or below this is taken as zero (tangents are exact to a few 1e-16).
LOCK_TOLERANCE = 1e-12


class Loads:
    """The loads of every block that do not depend on friction: weight, water, support [N/m, N m/m]."""

    def __init__(
        self,
        blocks: BlockSystem,
        unit_weight: float,
        support: BlockSupport | None = None,
        water: BlockWater | None = None,
    ) -> None:
        n = blocks.n_blocks
        self.blocks = blocks
        sa, ca = math.sin(blocks.base_dip), math.cos(blocks.base_dip)
        self.sa, self.ca = sa, ca
        self.weight = unit_weight * blocks.heights * blocks.width
        if support is None:
            support = BlockSupport(np.zeros(n), np.zeros(n), np.zeros(n))
        support.check(blocks)
        t_s, t_n = support.force * np.cos(support.angle), support.force * np.sin(support.angle)
        if water is None:
            wet = dict.fromkeys(("upper", "uplift", "lower", "moment"), np.zeros(n))
        else:
            water.check(blocks)
            wet = water.forces(blocks.base_dip, blocks.width)
        self.uplift = wet["uplift"]
        self.onto = t_n
        # moment about the pivot without the side forces (toppling positive)
        self.moment = (
            0.5 * self.weight * (blocks.heights * sa - blocks.width * ca)
            + wet["moment"]
            - t_s * support.height
            - t_n * support.offset
        )
        # the sums the sliding and up-slip conditions need (their friction terms are added in the march)
        self.along = self.weight * sa + wet["upper"] - wet["lower"] - t_s  # S_n with P_n = P_{n−1}
        self.normal = self.weight * ca - wet["uplift"] + t_n  # R_n with P_n = P_{n−1}


def march(loads: Loads, tan_base: ArrayLike, tan_side: ArrayLike, record: bool = False) -> dict[str, NDArray]:
    """The march over arrays of friction (tangents, broadcast together).

    Returns "toe_force" (P_0 [N/m], shape of the friction arrays) and, with record=True, per block
    (friction shape + (N,), index 0 = toe): force_above, p_topple, p_slide, force_below, mode, held.
    """
    blocks = loads.blocks
    tp, td = np.broadcast_arrays(np.asarray(tan_base, dtype=float), np.asarray(tan_side, dtype=float))
    lock = 1.0 - tp * td
    locked = lock <= LOCK_TOLERANCE
    safe_lock = np.where(locked, 1.0, lock)
    dx = blocks.width
    p_above = np.zeros(tp.shape)
    broken = np.zeros(tp.shape, dtype=bool)
    out: dict[str, NDArray] = {}
    if record:
        shape = (*tp.shape, blocks.n_blocks)
        for k in ("force_above", "p_topple", "p_slide", "force_below"):
            out[k] = np.empty(shape)
        out["mode"] = np.empty(shape, dtype=np.int8)
        out["held"] = np.empty(shape, dtype=bool)
    p_t = p_s = p_above
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for i in range(blocks.n_blocks - 1, -1, -1):
            l_arm = blocks.lower_arm[i]
            moment = p_above * (blocks.upper_arm[i] - dx * td) + loads.moment[i]
            if l_arm > 0.0:
                p_t = moment / l_arm
                holds_topple = np.ones(tp.shape, dtype=bool)
            else:  # the lower force cannot resist toppling: the block must not topple without it
                holds_topple = moment <= 0.0
                p_t = np.full(tp.shape, -np.inf)
            drive = loads.along[i] - tp * loads.normal[i]
            p_s = np.where(locked, -np.inf, p_above + drive / safe_lock)
            need = np.maximum(np.maximum(p_t, p_s), 0.0)
            held = holds_topple & (loads.normal[i] > 0.0)
            broken |= ~held
            p_below = np.where(broken, 0.0, need)
            if record:
                out["force_above"][..., i] = p_above
                out["p_topple"][..., i] = np.where(holds_topple, p_t, np.inf)
                out["p_slide"][..., i] = p_s
                out["force_below"][..., i] = np.where(broken, np.inf, need)
                mode = np.where(
                    ~holds_topple | ((p_t >= p_s) & (p_t > 0.0)), TOPPLES, np.where(p_s > 0.0, SLIDES, STABLE)
                )
                out["mode"][..., i] = mode
                out["held"][..., i] = held
            p_above = p_below
    out["toe_force"] = np.where(broken, np.inf, np.maximum(p_t, p_s))
    return out


def toe_force(
    blocks: BlockSystem,
    friction: ArrayLike,
    unit_weight: float,
    side_friction: ArrayLike | None = None,
    support: BlockSupport | None = None,
    water: BlockWater | None = None,
) -> NDArray[np.float64]:
    """P_0 [N/m], the force the toe block needs on its lower side, vectorised over friction [rad]
    (side_friction: default the same angles as friction): > 0 needed, < 0 surplus, +∞ if a block
    cannot be held (module docstring)."""
    phi_d = friction if side_friction is None else side_friction
    return march(Loads(blocks, unit_weight, support, water), np.tan(friction), np.tan(phi_d))["toe_force"]
