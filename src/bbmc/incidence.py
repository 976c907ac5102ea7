"""Which contacts each block takes part in, as the engines' fixed-order force sums need them (2D
`bbmc.dem.kernels`, 3D `bbmc.dem3d.contact_forces`): one list per block in contact order, so a block's
sum is the same whatever thread computed each contact."""

from __future__ import annotations

import numpy as np


def block_contacts(block_a: np.ndarray, block_b: np.ndarray, n_blocks: int) -> tuple[np.ndarray, np.ndarray]:
    """Each block's contacts in contact order, as CSR: (start, entries), int64 (n_blocks + 1,) and
    (2 n_contacts,), for contact c between blocks `block_a[c]` and `block_b[c]`; block i's entries are
    entries[start[i]:start[i + 1]], c >= 0 for contact c with the block as B, -1 - c with it as A."""
    index = np.arange(len(block_a), dtype=np.int64)
    block = np.concatenate([block_a, block_b]).astype(np.int64)
    order = np.lexsort((np.concatenate([index, index]), block))
    start = np.zeros(n_blocks + 1, dtype=np.int64)
    np.cumsum(np.bincount(block, minlength=n_blocks), out=start[1:])
    return start, np.concatenate([-1 - index, index])[order]
