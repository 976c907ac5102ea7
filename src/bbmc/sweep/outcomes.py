"""What became of each sample of a study: valid (an FS, counted in P_f), invalid (its own scene at
fault), a failed run, or impossible inputs (not run); their counts and their first errors, for
summary.csv and the command's lines (`bbmc.stages.sweep`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from bbmc.sweep.models import FAILED_RUN, INVALID, OUTCOME

FIRST_ERRORS = 3  # distinct errors shown when no sample gave a result
COUNTS = ("samples", "valid_samples", "invalid_samples", "failed_runs", "impossible_samples")  # first rows
IMPOSSIBLE = "impossible_input"  # the outcome of a sample not run (`bbmc.sweep.models` has the others)


@dataclass(frozen=True)
class Outcomes:
    """Each sample's outcome, as masks over the samples: invalid (its own scene at fault), failed run,
    impossible inputs (not run); a sample in none of them is valid."""

    invalid: np.ndarray
    failed: np.ndarray
    impossible: np.ndarray

    @classmethod
    def of(cls, samples: pd.DataFrame) -> Outcomes:
        outcome = samples[OUTCOME].to_numpy()
        return cls(outcome == INVALID, outcome == FAILED_RUN, outcome == IMPOSSIBLE)

    @property
    def excluded(self) -> np.ndarray:
        """The samples without an FS: not counted in P_f."""
        return self.invalid | self.failed | self.impossible

    def counts(self) -> dict[str, int]:
        """summary.csv's first rows (`COUNTS`)."""
        masks = (~self.excluded, self.invalid, self.failed, self.impossible)
        return dict(zip(COUNTS, [len(self.invalid), *(int(mask.sum()) for mask in masks)], strict=True))

    def text(self) -> str:
        """The samples without an FS, by outcome ("10 invalid, 0 failed runs, 0 impossible inputs")."""
        return (
            f"{int(self.invalid.sum())} invalid, {int(self.failed.sum())} failed runs, "
            f"{int(self.impossible.sum())} impossible inputs"
        )


def one_line(text: str, width: int = 200) -> str:
    line = " ".join(str(text).split())
    return line if len(line) <= width else line[: width - 3] + "..."


def first_errors(messages: pd.Series, count: int = FIRST_ERRORS) -> list[str]:
    """The first `count` distinct errors in sample order, each with its first sample and how many
    samples share it."""
    shown = messages[messages != ""].map(one_line)
    counts = shown.value_counts(sort=False)
    return [
        f"sample {shown.index[shown == text][0]} (and {counts[text] - 1} more): {text}"
        for text in list(dict.fromkeys(shown))[:count]
    ]
