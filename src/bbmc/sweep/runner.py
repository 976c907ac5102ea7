"""Run a sweep's samples in batches, on local processes or on a dask.distributed cluster, keeping every
finished batch on disk.

* The design (every sample's inputs) is made up front from the seed, so a sample's inputs never depend
  on which worker runs it or when; the models are deterministic; the result is the batches joined in
  sample order. So the results are the same, byte for byte, for any number of workers, a cluster, and
  any completion order.
* A batch is `batch_size` consecutive samples: one task. Each finished batch is written at once to
  `store/batch_<first sample>.csv` (to a temporary name, then renamed: never half a file). A run finds
  the batches already there and runs only the others: interrupting a study (Ctrl-C, a killed
  scheduler) loses at most the batches in flight.
* Locally: a pool of `workers` processes (default: every core). On a cluster (`scheduler` given):
  `distributed.Client(scheduler)`; a worker lost mid-task has its task rerun elsewhere by the
  scheduler, and each batch is written once, by this process, when its result arrives. Tasks are
  named by their store and first sample, so two studies on one scheduler never share a task's result.
"""

from __future__ import annotations

import hashlib
import os
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from pathlib import Path

import pandas as pd

Model = Callable[[pd.DataFrame], pd.DataFrame]


def batch_path(store: Path, first: int) -> Path:
    return store / f"batch_{first:09d}.csv"


def batches(design: pd.DataFrame, size: int) -> list[pd.DataFrame]:
    return [design.iloc[k : k + size] for k in range(0, len(design), size)]


def evaluate(model: Model, inputs: pd.DataFrame) -> pd.DataFrame:
    """One task: the batch's inputs beside the model's outputs, sample by sample."""
    return pd.concat([inputs, model(inputs)], axis=1)


def _write(store: Path, first: int, table: pd.DataFrame) -> None:
    path = batch_path(store, first)
    partial = path.with_suffix(".partial")
    table.to_csv(partial, index=True, float_format="%.17g", na_rep="nan")
    os.replace(partial, path)


def _pending(design: pd.DataFrame, size: int, store: Path) -> list[pd.DataFrame]:
    return [b for b in batches(design, size) if not batch_path(store, int(b.index[0])).exists()]


class Progress:
    """Samples done, and the time left at the rate of this run so far."""

    def __init__(self, total: int, done: int, say: Callable[[str], None]) -> None:
        self.total, self.done, self.start_done, self.say = total, done, done, say
        self.started = time.perf_counter()

    def add(self, n: int) -> None:
        self.done += n
        elapsed = time.perf_counter() - self.started
        rate = (self.done - self.start_done) / elapsed if elapsed > 0 else 0.0
        left = (self.total - self.done) / rate if rate > 0 else float("inf")
        self.say(f"{self.done}/{self.total} samples, {elapsed:.0f} s, about {left:.0f} s left")


def _local(model: Model, pending: list[pd.DataFrame], workers: int) -> Iterator[tuple[int, pd.DataFrame]]:
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures: dict[Future, int] = {pool.submit(evaluate, model, b): int(b.index[0]) for b in pending}
        while futures:
            done, _ = wait(futures, return_when=FIRST_COMPLETED)
            for future in done:
                yield futures.pop(future), future.result()


def _cluster(
    model: Model, pending: list[pd.DataFrame], scheduler: str, store: Path
) -> Iterator[tuple[int, pd.DataFrame]]:
    from distributed import Client, as_completed  # here: a local study needs no dask

    with Client(scheduler) as client:
        firsts = [int(b.index[0]) for b in pending]
        study = hashlib.sha256(str(store.resolve()).encode()).hexdigest()[:16]  # tasks named per store
        futures = client.map(
            evaluate, [model] * len(pending), pending, key=[f"bbmc-{study}-batch-{f}" for f in firsts]
        )
        first_of = dict(zip((f.key for f in futures), firsts, strict=True))
        for future in as_completed(futures):
            yield first_of[future.key], future.result()


def run_batches(
    model: Model,
    design: pd.DataFrame,
    store: Path,
    batch_size: int,
    scheduler: str | None = None,
    workers: int | None = None,
    say: Callable[[str], None] = lambda _: None,
) -> pd.DataFrame:
    """Run every sample not yet in `store`, then return all of them in sample order."""
    store.mkdir(parents=True, exist_ok=True)
    pending = _pending(design, batch_size, store)
    progress = Progress(len(design), len(design) - sum(len(b) for b in pending), say)
    if pending:
        say(
            f"{len(pending)} batches of up to {batch_size} samples to run "
            f"({progress.done} samples done before)"
        )
        results = (
            _cluster(model, pending, scheduler, store)
            if scheduler
            else _local(model, pending, workers or os.cpu_count() or 1)
        )
        for first, table in results:
            _write(store, first, table)
            progress.add(len(table))
    return collect(design, batch_size, store)


def collect(design: pd.DataFrame, batch_size: int, store: Path) -> pd.DataFrame:
    """Every batch of the design from `store`, in sample order (each sample exactly once)."""
    tables = [
        pd.read_csv(
            batch_path(store, int(b.index[0])), index_col="sample", keep_default_na=False, na_values=["nan"]
        )
        for b in batches(design, batch_size)
    ]
    table = pd.concat(tables)
    if not table.index.equals(design.index):
        raise RuntimeError(f"{store}: the stored batches do not match the design (a study changed mid-way?)")
    return table
