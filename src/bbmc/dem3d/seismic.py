"""Pseudo-static seismic load of the 3D engine: a horizontal acceleration k_h |g| on every block, added to
gravity, as the 2D scene's `seismic` section does (`bbmc.scene.schema.Seismic`: horizontal_coefficient
k_h in [0, 1], towards -x or +x; `bbmc.dem.model` adds k_h |g| along it).

In 3D the horizontal direction is an azimuth t (clockwise from north, +y; east is +x):

    g_seismic = g + k_h |g| (sin t, cos t, 0)        [m/s^2]

Source: Hoek & Bray, Rock Slope Engineering (pseudo-static seismic force k W); RocPlane's and Swedge's
seismic coefficient (horizontal).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np


def seismic_gravity(gravity: Sequence[float], coefficient: float, azimuth: float) -> np.ndarray:
    """Gravity [m/s^2] with the pseudo-static horizontal acceleration k_h |g| towards `azimuth` [rad]
    (clockwise from +y) added (module docstring). A k_h outside [0, 1] is refused in one line."""
    if not 0.0 <= coefficient <= 1.0:
        raise ValueError(f"seismic: horizontal_coefficient must be in [0, 1], got {coefficient}")
    g = np.asarray(gravity, dtype=float)
    return g + coefficient * float(np.linalg.norm(g)) * np.array([math.sin(azimuth), math.cos(azimuth), 0.0])
