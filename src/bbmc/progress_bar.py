"""A progress bar on stderr for the command line's long runs, shown only once a run has lasted."""

from __future__ import annotations

import sys
import time

import click

from bbmc.progress import Progress


class ProgressBar:
    """A progress bar on stderr for runs that last: it appears once a run has taken `after` seconds.
    Called with a `bbmc.progress.Progress` (its `done` of `total`, counted from the start)."""

    def __init__(self, total: int, label: str, after: float = 2.0) -> None:
        self.total, self.label, self.after = total, label, after
        self.start, self.done, self.bar = time.perf_counter(), 0, None

    def __call__(self, report: Progress) -> None:
        new, self.done = report.done - self.done, report.done
        if self.bar is None and time.perf_counter() - self.start > self.after:
            self.bar = click.progressbar(length=self.total, label=self.label, file=sys.stderr)
            self.bar.__enter__()
            self.bar.update(self.done)
        elif self.bar is not None:
            self.bar.update(new)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.__exit__(None, None, None)
