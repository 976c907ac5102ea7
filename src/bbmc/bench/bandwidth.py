"""The machine's memory bandwidth, the physical limit on the engine's rate per core
(results/bench/bandwidth.csv and bandwidth_limit.csv).

bandwidth.csv: a STREAM triad, a = b + s c, over three float64 arrays far larger than the caches (80 MB
each by default), in one numba kernel run on 1 thread and on every thread (`numba.set_num_threads`; the
kernel is `parallel`, its loop a `prange`), best of `repeats`. Bytes are counted as STREAM counts them:
3 x 8 per element (b and c read, a written). The write-allocate read of a (a cache line of a is read
before it is written, unless the stores bypass the cache) is not counted, so the traffic on the memory
bus is up to 4/3 of the figure: the figure is the one STREAM publishes and the issue quotes.

bandwidth_limit.csv: the bytes one sub-contact update moves (`bytes_per_update`, from the engine's
column layout, `bbmc.dem.layout`, and the scaling slope's sub-contacts, contacts and vertices per block),
and the most sub-contact updates per second that bandwidth carries (`updates_per_s_limit`);
`bandwidth_fraction` gives the fraction of the bandwidth a measured engine rate uses.
"""

from __future__ import annotations

import time
from pathlib import Path

import numba
import numpy as np
import pandas as pd

from bbmc.bench.scaling import scaled_slope
from bbmc.dem import layout as L
from bbmc.dem.model import build_model
from bbmc.dem.solver import prepare
from bbmc.scene.schema import Scene

FLOAT_BYTES = 8
TRIAD_BYTES_PER_ELEMENT = 3 * FLOAT_BYTES  # read b, read c, write a (STREAM's count; no write-allocate)
INT_BYTES = 8


@numba.njit(cache=True, parallel=True)
def _triad(a, b, c, s):
    for i in numba.prange(a.size):
        a[i] = b[i] + s * c[i]


def bandwidth_table(array_MB: float, repeats: int, thread_counts: list[int] | None = None) -> pd.DataFrame:
    """The triad's bandwidth [GB/s, 1e9 bytes/s] over three arrays of `array_MB` MB (1e6 bytes) each
    on each of `thread_counts` (default: 1 and every thread numba has), best of `repeats` after one
    untimed call each (compilation, page faults). The thread counts take turns in every repeat, so
    that a burst of other work on a shared machine slows one repeat of each, not every repeat of one."""
    counts = thread_counts or sorted({1, numba.config.NUMBA_NUM_THREADS})
    n = int(array_MB * 1e6) // FLOAT_BYTES
    a, b, c = np.zeros(n), np.ones(n), np.full(n, 2.0)
    best = dict.fromkeys(counts, np.inf)
    previous = numba.get_num_threads()
    try:
        for repeat in range(repeats + 1):
            for threads in counts:
                numba.set_num_threads(threads)
                start = time.perf_counter()
                _triad(a, b, c, 3.0)
                if repeat:
                    best[threads] = min(best[threads], time.perf_counter() - start)
    finally:
        numba.set_num_threads(previous)
    return pd.DataFrame(
        [
            {
                "threads": threads,
                "array_MB": array_MB,
                "GB_per_s": n * TRIAD_BYTES_PER_ELEMENT / seconds / 1e9,
                "repeats": repeats,
            }
            for threads, seconds in best.items()
        ]
    )


def bytes_per_update(
    sub_contacts_per_contact: int, sub_contacts_per_block: float, vertices_per_block: float
) -> float:
    """Bytes of memory traffic per sub-contact update in one step [bytes], when the arrays are far
    larger than the caches (100,000 blocks) and each is streamed once per step:

    * its sub-contact row, read and written back: 2 x `SUB_COLUMNS` x 8 (float64);
    * its share of its contact's row, read: `CONTACT_COLUMNS` x 8 (int64) / `sub_contacts_per_contact`;
    * its share of the block rows, read and written back by the motion update:
      2 x `BLOCK_COLUMNS` x 8 / `sub_contacts_per_block`;
    * its share of the vertices, local (x, y) read and world (x, y) written by the motion update:
      2 x 2 x 8 x `vertices_per_block` / `sub_contacts_per_block`.

    A lower bound: where a contact's reads of its two blocks' rows and its edges' vertices miss the
    cache, they add up to 2 x (`BLOCK_COLUMNS` + 2 x 2) x 8 / `sub_contacts_per_contact` (`gather_bytes`)."""
    sub_row = 2 * L.SUB_COLUMNS * FLOAT_BYTES
    contact_row = L.CONTACT_COLUMNS * INT_BYTES / sub_contacts_per_contact
    block_rows = 2 * L.BLOCK_COLUMNS * FLOAT_BYTES / sub_contacts_per_block
    vertices = 2 * 2 * FLOAT_BYTES * vertices_per_block / sub_contacts_per_block
    return sub_row + contact_row + block_rows + vertices


def gather_bytes(sub_contacts_per_contact: int) -> float:
    """The bytes per sub-contact update [bytes] a contact's reads of its two blocks' rows and of the two
    vertices of each of its edges add where they all miss the cache (`bytes_per_update` counts none)."""
    return 2 * (L.BLOCK_COLUMNS + 2 * 2) * FLOAT_BYTES / sub_contacts_per_contact


def bandwidth_fraction(updates_per_s: float, bytes_per_update: float, GB_per_s: float) -> float:
    """The fraction of a bandwidth `GB_per_s` [1e9 bytes/s] an engine running `updates_per_s`
    sub-contact updates a second, each moving `bytes_per_update` bytes, uses (1: at the limit)."""
    return updates_per_s * bytes_per_update / (GB_per_s * 1e9)


def slope_counts(blocks: int, slope_config: str) -> dict[str, float]:
    """Sub-contacts per contact and per block, and vertices per block, of the scaling section's slope
    (`bbmc.bench.scaling.scaled_slope`) of about `blocks` blocks after its first contact search."""
    model = build_model(
        Scene.model_validate(scaled_slope(blocks, slope_config), strict=False), Path(f"<slope of {blocks}>")
    )
    state = prepare(model)
    n = len(model.block_names)
    return {
        "blocks": n,
        "sub_contacts_per_contact": state.n_sub,
        "sub_contacts_per_block": len(state.subs) / n,
        "vertices_per_block": len(model.local) / n,
    }


def limit_table(bandwidth: pd.DataFrame, counts: dict[str, float]) -> pd.DataFrame:
    """For each row of `bandwidth_table`: the slope's `counts` (`slope_counts`), the bytes per
    sub-contact update (`bytes_per_update`, and with every gather missing the cache), and the most
    updates per second [1/s] the bandwidth carries at each."""
    per_contact, per_block = counts["sub_contacts_per_contact"], counts["sub_contacts_per_block"]
    streamed = bytes_per_update(per_contact, per_block, counts["vertices_per_block"])
    gathered = streamed + gather_bytes(per_contact)
    rate = bandwidth["GB_per_s"] * 1e9
    return pd.DataFrame(
        {
            "threads": bandwidth["threads"],
            "GB_per_s": bandwidth["GB_per_s"],
            **counts,
            "bytes_per_update": streamed,
            "bytes_per_update_gathers_missing": gathered,
            "updates_per_s_limit": rate / streamed,
            "updates_per_s_limit_gathers_missing": rate / gathered,
        }
    )
