"""The audit's inputs and its log: each check judges one printed number against ours
(`bbmc.comparison.judge`) and records the row, with the reasoning and the numbers that support it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from bbmc.comparison import TOLERANCES, judge
from bbmc.joint import model as jm


@dataclass(frozen=True)
class AuditInputs:
    """Everything the audit reads: the paper's tables and our stages' in-memory results."""

    table1: pd.DataFrame
    paper_fits: pd.DataFrame
    legends: pd.DataFrame
    table2: pd.DataFrame
    table3: pd.DataFrame
    table4_constant: pd.DataFrame
    table4_nonlinear: pd.DataFrame
    table4_rock: pd.DataFrame
    printed: dict[str, float]
    our_fits: pd.DataFrame
    strength: jm.StrengthParameters
    stiffness: jm.StiffnessParameters
    k_j_unrounded: float
    n_j_unrounded: float


class AuditLog:
    """Rows of the audit, in the order they are checked."""

    def __init__(self) -> None:
        self.rows: list[dict[str, object]] = []

    def check(
        self,
        source: str,
        item: str,
        quantity: str,
        tolerance: str,
        paper: float,
        ours: float,
        reasoning: str,
        rounding: tuple[tuple[str, float], ...] = (),
        explanations: tuple[tuple[str, float], ...] = (),
        corrected: float | None = None,
    ) -> None:
        """Judge one printed number and record it."""
        tol = TOLERANCES[tolerance]
        j = judge(paper, ours, tol.value, rounding, explanations, corrected)
        if j.via:
            reasoning += f" Printed value reproduced by {j.via}: {j.via_value:.6g}."
        self._add(source, item, quantity, tol.unit, paper, ours, tol.value, j.verdict, j.reproduction)
        self.rows[-1].update(corrected=np.nan if corrected is None else corrected, reasoning=reasoning)

    def not_derivable(
        self, source: str, item: str, quantity: str, unit: str, paper: float, ours: float, reasoning: str
    ) -> None:
        """Record a printed number whose inputs are not published; `ours` is the nearest we can do."""
        self._add(source, item, quantity, unit, paper, ours, np.nan, "not derivable", "not derivable")
        self.rows[-1].update(corrected=np.nan, reasoning=reasoning)

    def _add(self, source, item, quantity, unit, paper, ours, tol, verdict, reproduction) -> None:
        difference = ours - paper
        self.rows.append(
            {
                "source": source,
                "item": item,
                "quantity": quantity,
                "unit": unit,
                "paper": paper,
                "ours": ours,
                "difference": difference,
                "relative_difference": difference / paper if paper != 0 else np.nan,
                "tolerance": tol,
                "reproduction": reproduction,
                "verdict": verdict,
            }
        )

    def table(self) -> pd.DataFrame:
        return pd.DataFrame(self.rows)
