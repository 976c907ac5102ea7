"""What the support carries: its table (support.csv), its lines at the blocks' positions (for the
figures and ParaView), and the largest load per tendon (monitors, summaries). Forces are per bolt [kN]:
the engine's force per metre run times the bolt's spacing."""

from __future__ import annotations

import numpy as np
import pandas as pd

from bbmc.dem import layout as L
from bbmc.dem.support_elements import SupportElements
from bbmc.geometry.polygons import carried_points

STATES = ("elastic", "yielded", "ruptured")


def per_bolt_kN(elements: SupportElements, column: np.ndarray) -> np.ndarray:
    """A force per metre run [N/m] of each element as the force per bolt [kN]."""
    return column * elements.spacing / 1e3


def element_state(support: np.ndarray) -> np.ndarray:
    """Each element's state: elastic, yielded (it has reached its capacity) or ruptured."""
    names = np.array(STATES, dtype=object)
    return names[np.where(support[:, L.BROKEN] > 0, 2, np.where(support[:, L.YIELDED] > 0, 1, 0))]


def support_table(elements: SupportElements, block_names: list[str], support: np.ndarray) -> pd.DataFrame:
    """support.csv: per element (an anchor, or a grouted bolt's crossing of one joint) its blocks, its
    point at the start, its axial and shear force and capacities per bolt, and its state."""
    names = np.array(block_names, dtype=object)
    return pd.DataFrame(
        {
            "support": elements.names,
            "crossing": elements.crossing,
            "kind": np.where(support[:, L.KIND] == L.ANCHOR, "anchor", "grouted_bolt"),
            "block_a": names[elements.blocks[:, 0]],
            "block_b": names[elements.blocks[:, 1]],
            "x_m": elements.points[:, 0],
            "y_m": elements.points[:, 1],
            "axial_kN": per_bolt_kN(elements, support[:, L.AXIAL]),
            "shear_kN": per_bolt_kN(elements, support[:, L.SHEAR]),
            "capacity_kN": per_bolt_kN(elements, support[:, L.CAP_AXIAL]),
            "shear_capacity_kN": per_bolt_kN(elements, support[:, L.CAP_SHEAR]),
            "state": element_state(support),
        }
    )


def largest_loads(elements: SupportElements, support: np.ndarray) -> dict[str, float]:
    """Each tendon's largest axial force over its elements [kN per bolt], in scene order."""
    axial = per_bolt_kN(elements, support[:, L.AXIAL])
    loads: dict[str, float] = {}
    for name, value in zip(elements.names, axial, strict=True):
        loads[name] = max(loads.get(name, -np.inf), float(value))
    return loads


def _moved(blocks: np.ndarray, block: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Points fixed in their blocks, from their start positions to now [m]."""
    rows = blocks[block]
    return carried_points(start, rows[:, [L.X0, L.Y0]], rows[:, [L.X, L.Y]], rows[:, L.TH])


def support_lines(
    elements: SupportElements, blocks: np.ndarray, support: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Each element as a line at the blocks' positions now, (n, 2, 2) [m], and its axial force [kN per
    bolt]: an anchor from its head to its end; a grouted bolt's crossing as the bolt's stretch from
    halfway to the crossing before it (or the head) to halfway to the one after it (or the end)."""
    a, b = elements.blocks[:, 0], elements.blocks[:, 1]
    heads = _moved(blocks, a, elements.ends[:, 0])
    ends = _moved(blocks, b, elements.ends[:, 1])
    a_side, b_side = _moved(blocks, a, elements.points), _moved(blocks, b, elements.points)
    lines = np.stack([heads, ends], axis=1)
    names = elements.names
    for e in np.flatnonzero(support[:, L.KIND] == L.GROUTED):
        if e > 0 and names[e - 1] == names[e]:
            lines[e, 0] = 0.5 * (b_side[e - 1] + a_side[e])
        if e + 1 < len(names) and names[e + 1] == names[e]:
            lines[e, 1] = 0.5 * (b_side[e] + a_side[e + 1])
    return lines, per_bolt_kN(elements, support[:, L.AXIAL])
