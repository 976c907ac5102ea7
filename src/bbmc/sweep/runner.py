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
* Locally: a pool of `workers` processes (default: every core), each running its scenes on one
  thread (`bbmc.dem.kernels.limit_threads`; so do a cluster's workers). On a cluster (`scheduler` given):
  `distributed.Client(scheduler)`; a worker lost mid-task has its task rerun elsewhere by the
  scheduler, and each batch is written once, by this process, when its result arrives.
* The warnings a batch raises (numpy's overflow from an extreme sample, say) come back with its result,
  each once, and are raised again in this process, where the command shows them one line each: a
  worker has no terminal of its own to show them on, and a forked one inherits the command's way of
  showing them, which keeps them in the worker.
* Ctrl-C (or SIGINT to this process alone) stops the study at once with `StudyInterrupted`, which says
  how many samples are done and kept. Locally, the workers ignore SIGINT (a terminal sends it to the
  whole process group: a worker acting on it would print its own traceback), and this process ends
  them (SIGTERM), running batches and all. On a cluster, this process cancels its tasks and
  disconnects; the scheduler and its workers stay up for the next study, and a batch running on a
  worker ends at its next kernel call (`bbmc.dem.pace.stopped_when`), freeing the worker. A task's
  key holds the study's digest (the store's name), so that one study's task is never taken for
  another's.
* Compiled once per machine (`warm_engine`): with a cold kernel cache, each worker would compile the
  engine for itself, all at once (two dask workers each took 71 s). So a study of scenes warms the
  cache (`bbmc.warmup.warm_if_cold`) before its batches start: locally in this process before the
  workers are made, on a cluster as one task on one worker of each host whose cache is cold; then
  every worker loads the engine from the cache. The check is per copy of the source
  (`bbmc.kernel_cache.engine_is_cold`): a worker importing bbmc from another folder than the one
  warmed by `make` (a second checkout, an uploaded copy) has a cold cache of its own.
* A worker process exits without the garbage collector's last sweeps (`gc.freeze` at exit,
  `_exit_quickly`): a dask worker that had run a study took 3-4 s to tear down its ~160,000 Python
  objects on 2 busy cores, past the 4 s its nanny waits before "Worker process still alive after 4.0
  seconds, killing"; frozen, it exits in a few tenths of a second. The operating system frees the
  memory either way.
"""

from __future__ import annotations

import atexit
import gc
import hashlib
import multiprocessing
import os
import signal
import time
import warnings
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from contextlib import closing, contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd

from bbmc import kernel_cache, warmup
from bbmc.dem.kernels import limit_threads
from bbmc.dem.pace import stopped_when
from bbmc.progress import Progress, ProgressCallback, ignore

if TYPE_CHECKING:
    from distributed import Client

Model = Callable[[pd.DataFrame], pd.DataFrame]
Caught = list[tuple[type[Warning], str]]  # (category, message) of each warning a batch raised, once


def batch_path(store: Path, first: int) -> Path:
    return store / f"batch_{first:09d}.csv"


def batches(design: pd.DataFrame, size: int) -> list[pd.DataFrame]:
    return [design.iloc[k : k + size] for k in range(0, len(design), size)]


def evaluate(model: Model, inputs: pd.DataFrame) -> tuple[pd.DataFrame, Caught]:
    """One task: the batch's inputs beside the model's outputs, sample by sample, and the warnings its
    run raised, each once (for the process that runs the study to raise again)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        table = pd.concat([inputs, model(inputs)], axis=1)
    return table, list(dict.fromkeys((w.category, str(w.message)) for w in caught))


class StudyInterrupted(KeyboardInterrupt):
    """Ctrl-C during a study; its message says how many samples are done and where they are kept."""


def _write(store: Path, first: int, table: pd.DataFrame) -> None:
    path = batch_path(store, first)
    partial = path.with_suffix(".partial")
    try:
        table.to_csv(partial, index=True, float_format="%.17g", na_rep="nan")
    except BaseException:
        partial.unlink(missing_ok=True)
        raise
    os.replace(partial, path)


def _pending(design: pd.DataFrame, size: int, store: Path) -> list[pd.DataFrame]:
    return [b for b in batches(design, size) if not batch_path(store, int(b.index[0])).exists()]


class _Counter:
    """Samples done, and the time left at the rate of this run so far, reported as `Progress`."""

    def __init__(self, total: int, done: int, progress: ProgressCallback) -> None:
        self.total, self.done, self.start_done, self.progress = total, done, done, progress
        self.started = time.perf_counter()

    def say(self, text: str) -> None:
        self.progress(Progress(self.done, self.total, "samples", text))

    def add(self, n: int) -> None:
        self.done += n
        elapsed = time.perf_counter() - self.started
        rate = (self.done - self.start_done) / elapsed if elapsed > 0 else 0.0
        left = (self.total - self.done) / rate if rate > 0 else float("inf")
        self.say(f"{self.done}/{self.total} samples, {elapsed:.0f} s, about {left:.0f} s left")


_freezing_at_exit = False


def _exit_quickly() -> None:
    """From now on this process ends without the garbage collector's sweeps at its exit (`gc.freeze`
    as the first exit handler; registered once): module docstring."""
    global _freezing_at_exit
    if not _freezing_at_exit:
        atexit.register(gc.freeze)
        _freezing_at_exit = True


def _start_worker() -> None:
    """Each local worker's start: SIGINT ignored (the parent ends the workers), one thread for its
    runs (the sweep runs one process per core), a quick exit."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    limit_threads(1)
    _exit_quickly()


class _KeptProcesses:
    """The default multiprocessing context, keeping each process it makes: `concurrent.futures` cancels
    only the tasks not yet started, so an interrupted study ends its running workers itself."""

    def __init__(self) -> None:
        self.context = multiprocessing.get_context()
        self.made: list[multiprocessing.process.BaseProcess] = []

    def Process(self, *args: object, **kwargs: object) -> multiprocessing.process.BaseProcess:
        process = self.context.Process(*args, **kwargs)
        self.made.append(process)
        return process

    def __getattr__(self, name: str) -> object:
        return getattr(self.context, name)

    def end(self) -> None:
        """Terminate (SIGTERM) every process still alive and wait for it."""
        for process in self.made:
            if process.is_alive():
                process.terminate()
        for process in self.made:
            process.join()


def _local(
    model: Model, pending: list[pd.DataFrame], workers: int
) -> Iterator[tuple[int, tuple[pd.DataFrame, Caught]]]:
    processes = _KeptProcesses()
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=processes, initializer=_start_worker)
    try:
        futures: dict[Future, int] = {pool.submit(evaluate, model, b): int(b.index[0]) for b in pending}
        while futures:
            done, _ = wait(futures, return_when=FIRST_COMPLETED)
            for future in done:
                yield futures.pop(future), future.result()
    except BaseException:  # Ctrl-C, a failed batch, or the caller stopped early
        pool.shutdown(wait=False, cancel_futures=True)
        processes.end()
        raise
    pool.shutdown()


def _evaluate_on_worker(model: Model, inputs: pd.DataFrame) -> tuple[pd.DataFrame, Caught]:
    """One task on a dask worker: `evaluate`, ended at its next kernel call once the task is cancelled
    (its client interrupted: the worker marks the task cancelled, or forgets it)."""
    from distributed import get_worker

    limit_threads(1)  # the cluster's workers are its processes: each runs on one thread
    _exit_quickly()
    worker = get_worker()
    key = worker.get_current_task()

    def cancelled() -> bool:
        task = worker.state.tasks.get(key)
        return task is None or task.state == "cancelled"

    with stopped_when(cancelled):
        return evaluate(model, inputs)


def _cold_on_worker() -> bool:
    """Whether this worker's host has a cold kernel cache (`warmup.warm_if_cold` would compile). The
    worker exits quickly from now on."""
    _exit_quickly()
    return not kernel_cache.jit_disabled() and kernel_cache.engine_is_cold(kernel_cache.current_folder())


@contextmanager
def _connected(scheduler: str | Client) -> Iterator[Client]:
    """A client of the scheduler at an address (closed at the end), or the caller's own client (left
    open)."""
    from distributed import Client  # here: a local study needs no dask

    if not isinstance(scheduler, str):
        yield scheduler
        return
    with Client(scheduler) as client:
        yield client


def _on_each(client: Client, function: Callable[[], object], workers: dict[str, str]) -> list:
    """`function` run as a task on each of `workers` (host: worker address), its results in order."""
    futures = [
        client.submit(function, workers=[address], allow_other_workers=False, pure=False)
        for address in workers.values()
    ]
    return client.gather(futures)


def warm_engine(scheduler: str | Client | None, say: Callable[[str], None] = lambda _: None) -> None:
    """Before a study of scenes: the block engine compiled once on each machine whose kernel cache is
    cold (module docstring), here (`scheduler` None: the local workers are made from this process
    later) or on one worker of each host of the cluster; `say` is told of a compile before it starts."""
    if scheduler is None:
        warmup.warm_if_cold(say)
        return
    with _connected(scheduler) as client:
        _warm_hosts(client, say)


def _warm_hosts(client: Client, say: Callable[[str], None]) -> None:
    """The engine compiled on one worker of each host whose cache is cold, waited for."""
    from distributed.comm import get_address_host

    hosts: dict[str, str] = {}
    for address in client.ncores():  # every worker
        hosts.setdefault(get_address_host(address), address)
    found = _on_each(client, _cold_on_worker, hosts)
    cold = {host: address for (host, address), is_cold in zip(hosts.items(), found, strict=True) if is_cold}
    if cold:
        say(
            f"compiling the block engine on {len(cold)} host(s), once each, before the batches start "
            "(a cold cache: 20-90 s)"
        )
        _on_each(client, warmup.warm_if_cold, cold)


def _cluster(
    model: Model, pending: list[pd.DataFrame], client: Client, study: str
) -> Iterator[tuple[int, tuple[pd.DataFrame, Caught]]]:
    from distributed import as_completed

    firsts = [int(b.index[0]) for b in pending]
    futures = client.map(
        _evaluate_on_worker,
        [model] * len(pending),
        pending,
        key=[f"bbmc-batch-{study}-{f}" for f in firsts],
    )
    first_of = dict(zip((f.key for f in futures), firsts, strict=True))
    try:
        for future in as_completed(futures):
            yield first_of[future.key], future.result()
    except BaseException:  # the tasks not done leave the cluster with this client
        client.cancel(futures)
        raise


def _keep(results: Iterator[tuple[int, tuple[pd.DataFrame, Caught]]], store: Path, counter: _Counter) -> None:
    """Each batch written to `store` as it comes, its warnings raised here; Ctrl-C: `StudyInterrupted`."""
    try:
        with closing(results):  # an interrupt while writing a batch still ends the workers at once
            for first, (table, caught) in results:
                _write(store, first, table)
                for category, message in caught:
                    warnings.warn(message, category, stacklevel=3)
                counter.add(len(table))
    except KeyboardInterrupt:
        raise StudyInterrupted(
            f"{counter.done} of {counter.total} samples done, kept in {store}/ "
            "(the same command runs only the rest)"
        ) from None


def run_batches(
    model: Model,
    design: pd.DataFrame,
    store: Path,
    batch_size: int,
    scheduler: str | Client | None = None,
    workers: int | None = None,
    progress: ProgressCallback = ignore,
) -> pd.DataFrame:
    """Run every sample not yet in `store`, then return all of them in sample order. `scheduler`: a
    dask scheduler's address or a `distributed.Client` (None: `workers` local processes, default every
    core); `progress` is told each batch done (unit "samples")."""
    store.mkdir(parents=True, exist_ok=True)
    pending = _pending(design, batch_size, store)
    counter = _Counter(len(design), len(design) - sum(len(b) for b in pending), progress)
    if not pending:
        return collect(design, batch_size, store)
    announce = (
        f"{len(pending)} batches of up to {batch_size} samples to run ({counter.done} samples done before)"
    )
    counter.say(announce)
    if scheduler is None:
        _keep(_local(model, pending, workers or os.cpu_count() or 1), store, counter)
    else:
        with _connected(scheduler) as client:
            study = hashlib.sha256(str(store.resolve()).encode()).hexdigest()[:16]  # tasks named per store
            _keep(_cluster(model, pending, client, study), store, counter)
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
