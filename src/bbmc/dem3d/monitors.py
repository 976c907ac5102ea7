"""What a 3D run is watched by: the unbalanced-force ratio, as the 2D engine's (`bbmc.dem.monitors`).

The ratio is the largest out-of-balance force or moment on a block's free degrees of freedom over a
reference force, the largest weight of a block free to move: a moment M counts as the force M / R that
makes it at the block's radius R (its farthest vertex from the centroid). The out-of-balance force is
the last step's contact force plus the weight, m g + F_contact [N]; the moment the last step's about
the centroid [N m]. Units: N, m.
"""

from __future__ import annotations

import numpy as np

from bbmc.dem3d.layout import DOFS, FREE, FX, MASS, RADIUS, TX
from bbmc.dem3d.model import Model


def free_blocks(model: Model) -> np.ndarray:
    """A bool per block: it has a degree of freedom free to move."""
    return np.any(model.dof[:, :DOFS] == FREE, axis=1)


def reference_force(model: Model) -> float:
    """The largest weight of a block free to move [N] (1 if none weighs)."""
    weights = model.blocks[free_blocks(model), MASS] * float(np.linalg.norm(model.gravity))
    largest = float(np.max(weights, initial=0.0))
    return largest if largest > 0 else 1.0


def unbalanced_force_ratio(model: Model, reference: float, judged: np.ndarray | None = None) -> float:
    """The largest out-of-balance force or moment (module docstring) over `reference` [1], on the free
    degrees of freedom of the `judged` blocks (a bool per block; default all)."""
    b = model.blocks
    free = model.dof == FREE
    if judged is not None:
        free = free & judged[:, None]
    force = np.where(free[:, :3], b[:, FX : FX + 3] + b[:, MASS, None] * model.gravity, 0.0)
    moment = np.where(free[:, 3:], b[:, TX : TX + 3], 0.0)
    largest = np.maximum(np.linalg.norm(force, axis=1), np.linalg.norm(moment, axis=1) / b[:, RADIUS])
    return float(np.max(largest, initial=0.0)) / reference
