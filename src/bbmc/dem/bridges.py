"""Which rock bridges broke, where and when: a record-step observer of a run (`bridges.csv`).

A bridge is a contact whose joint law breaks into another (`breaks_into`). At every record step the
log notes, for each bridge contact (known by its pair of edges), the first record at which one of its
shares was seen broken and the first at which all were, and how its shares broke: in shear (a first
slip) or in tension (the bond's tensile strength exceeded). The steps are record steps: a bridge
broken at step 1,234 of a run recorded every 500 steps is "broken by step 1,500".
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from bbmc.dem import layout as L
from bbmc.dem.model import Model
from bbmc.dem.state import State


def failure_mode(slipped: np.ndarray) -> np.ndarray:
    """0 intact, 1 slipped in shear, 2 failed in tension, from the SLIPPED column (whether or not the
    share has since become its joint: `layout.BECAME_JOINT`)."""
    return np.where(slipped == 0.0, 0, 1 + (slipped.astype(np.int64) + 1) % 2)


COLUMNS = [
    "block_a",
    "block_b",
    "law",
    "edge_label",
    "x_m",
    "y_m",
    "shares",
    "shares_broken",
    "in_shear",
    "in_tension",
    "first_broken_by_step",
    "first_broken_by_time_s",
    "broken_through_by_step",
    "broken_through_by_time_s",
]  # bridges.csv, in the order of a row's keys (`BridgeLog._new_row`)


class BridgeLog:
    """Called with the state at every record step (`simulate`'s on_record); `table()` at the end."""

    def __init__(self, model: Model) -> None:
        self.model = model
        self.rows: dict[tuple[int, int], dict] = {}

    def __call__(self, state: State) -> None:
        contacts, n_sub = state.contacts, state.n_sub
        bridge = self.model.laws[contacts[:, L.JOINT_TYPE], L.BREAKS_INTO] >= 0
        if not bridge.any():
            return
        slipped = state.subs[:, L.SLIPPED].reshape(-1, n_sub)
        centre = state.subs[:, [L.CX, L.CY]].reshape(-1, n_sub, 2).mean(axis=1)
        step, time = state.step, float(state.clock[L.TIME])
        for c in np.flatnonzero(bridge):
            key = (int(contacts[c, L.EDGE_A]), int(contacts[c, L.EDGE_B]))
            row = self.rows.get(key)
            if row is None:
                row = self.rows[key] = self._new_row(contacts[c], centre[c])
            broken = slipped[c] != 0.0
            row["shares_broken"] = max(row["shares_broken"], int(broken.sum()))
            mode = failure_mode(slipped[c])
            row["in_shear"] = max(row["in_shear"], int((mode == 1).sum()))
            row["in_tension"] = max(row["in_tension"], int((mode == 2).sum()))
            if broken.any() and row["first_broken_by_step"] < 0:
                row["first_broken_by_step"], row["first_broken_by_time_s"] = step, time
            if broken.all() and row["broken_through_by_step"] < 0:
                row["broken_through_by_step"], row["broken_through_by_time_s"] = step, time

    def _new_row(self, contact: np.ndarray, centre: np.ndarray) -> dict:
        model = self.model
        edge_a, edge_b = int(contact[L.EDGE_A]), int(contact[L.EDGE_B])
        label = model.label_names[model.edge_label[edge_a]] or model.label_names[model.edge_label[edge_b]]
        return {
            "block_a": model.block_names[contact[L.BLOCK_A]],
            "block_b": model.block_names[contact[L.BLOCK_B]],
            "law": model.law_names[contact[L.JOINT_TYPE]],
            "edge_label": label,
            "x_m": float(centre[0]),
            "y_m": float(centre[1]),
            "shares": self.model.scene.contacts.sub_contacts_per_edge,
            "shares_broken": 0,
            "in_shear": 0,
            "in_tension": 0,
            "first_broken_by_step": -1,
            "first_broken_by_time_s": float("nan"),
            "broken_through_by_step": -1,
            "broken_through_by_time_s": float("nan"),
        }

    def table(self) -> pd.DataFrame:
        """One row per bridge contact seen, in the order first seen: where it is, how many of its
        shares broke and how, and by which record step (-1: not broken)."""
        return pd.DataFrame(list(self.rows.values()), columns=COLUMNS)
