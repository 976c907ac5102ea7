"""A progress bar on stderr for the command line's long runs, shown only once a run has lasted."""

from __future__ import annotations

import sys
import time

import click


class ProgressBar:
    """A progress bar on stderr for runs that last: it appears once a run has taken `after` seconds."""

    def __init__(self, total: int, label: str, after: float = 2.0) -> None:
        self.total, self.label, self.after = total, label, after
        self.start, self.done, self.bar = time.perf_counter(), 0, None

    def __call__(self, steps: int) -> None:
        self.done += steps
        if self.bar is None and time.perf_counter() - self.start > self.after:
            self.bar = click.progressbar(length=self.total, label=self.label, file=sys.stderr)
            self.bar.__enter__()
            self.bar.update(self.done)
        elif self.bar is not None:
            self.bar.update(steps)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.__exit__(None, None, None)
