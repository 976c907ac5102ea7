"""The one progress protocol of bbmc's long computations (a run, a factor of safety, a study).

A function that takes `progress=` calls it with a `Progress` each time it has news: how much of its
work is done, of how much, in what unit, and a line a person can read. A caller that only prints
uses `.text`; a progress bar uses `done` and `total`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class Progress:
    """One report of progress.

    Attributes:
        done: units of work done so far (steps, trials, samples), counted from the start of the call.
        total: units expected in all, or None where the end is not known in advance (the trials of
            a strength reduction stop when the bracket is narrow enough).
        unit: what is counted: "steps", "trials" or "samples".
        text: one line a person can read, e.g. "trial 4 at F = 1.12: holds".
    """

    done: int
    total: int | None
    unit: str
    text: str


ProgressCallback = Callable[[Progress], None]


def ignore(_: Progress) -> None:
    """The default callback: progress is not reported."""
