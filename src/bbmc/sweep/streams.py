"""Uniform draws that belong to a sample, not to the batch it runs in: the u of (seed, sample, stream)
is the value at position 4 x sample + stream of SplitMix64's sequence from `seed` (Steele, Lea & Flood
2014, "Fast splittable pseudorandom number generators"), turned into a double on (0, 1) from its top 53
bits. A sample's draws are then the same whatever the batch size, the workers or the order the batches
run in, and each is computed for a whole batch at once (numpy, no loop per sample)."""

from __future__ import annotations

import numpy as np

STREAMS = 4  # independent uniforms per sample
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX_1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX_2 = np.uint64(0x94D049BB133111EB)


def sample_uniforms(seed: int, samples: np.ndarray, stream: int) -> np.ndarray:
    """Uniforms on (0, 1), one per entry of `samples` (sample numbers >= 0), for stream 0 to 3."""
    if not 0 <= stream < STREAMS:
        raise ValueError(f"stream must be 0 to {STREAMS - 1}, got {stream}")
    position = np.asarray(samples, dtype=np.uint64) * np.uint64(STREAMS) + np.uint64(stream + 1)
    with np.errstate(over="ignore"):
        z = np.uint64(seed) + position * _GOLDEN
        z = (z ^ (z >> np.uint64(30))) * _MIX_1
        z = (z ^ (z >> np.uint64(27))) * _MIX_2
        z = z ^ (z >> np.uint64(31))
    return ((z >> np.uint64(11)).astype(np.float64) + 0.5) / 2.0**53
