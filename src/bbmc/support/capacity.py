"""A bolt's capacity: the weakest of its steel, its plate and its bond (RocPlane's and Swedge's bolt
models; Hoek, Kaiser & Bawden 1995, ch. 12). Forces [N], lengths [m], bond [N/m]; numpy-vectorised.

* End-anchored tendon (mechanically anchored bolt, cable anchor): T = min(T_steel, T_plate,
  bond x bond length). A capacity not given (None) does not limit.
* Fully grouted bolt at a joint it crosses, l_head from the head to the joint and l_end from the joint
  to the end: T = min(T_steel, T_plate + bond x l_head, bond x l_end): the bolt pulls out of the
  block on the head side (held by its plate and the bond there) or out of the rock beyond the joint.
  Without a plate T_plate = 0.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def anchor_capacity(
    steel: ArrayLike,
    plate: ArrayLike | None = None,
    bond: ArrayLike | None = None,
    bond_length: ArrayLike = 0.0,
) -> NDArray:
    """min(T_steel, T_plate, bond x bond_length) [N]; a capacity given as None does not limit."""
    capacity = np.asarray(steel, dtype=float)
    if plate is not None:
        capacity = np.minimum(capacity, plate)
    if bond is not None:
        capacity = np.minimum(capacity, np.multiply(bond, bond_length))
    return capacity


def grouted_bolt_capacity(
    steel: ArrayLike,
    bond: ArrayLike,
    head_length: ArrayLike,
    end_length: ArrayLike,
    plate: ArrayLike | None = None,
) -> NDArray:
    """min(T_steel, T_plate + bond x l_head, bond x l_end) at a crossing [N] (module docstring)."""
    head_side = np.multiply(bond, head_length) + (0.0 if plate is None else np.asarray(plate, dtype=float))
    return np.minimum(np.minimum(np.asarray(steel, dtype=float), head_side), np.multiply(bond, end_length))
