"""Joint water of the 3D engine: a phreatic plane, and the pressure it gives at a point.

A `WaterTable` is a plane through `point` with normal `normal` (not horizontal in the plane's sense: its
normal has a vertical component), the phreatic surface z_table(x, y). Below it the water is hydrostatic:

    p(x, y, z) = gamma_w max(z_table(x, y) - z, 0)        [Pa], gamma_w [N/m^3], x, y, z [m]

with z_table(x, y) = z0 + a x + b y, a = -n_x / n_z, b = -n_y / n_z, z0 = (n . point) / n_z. A joint
type may add a given uniform pressure (the `pressure` field of `bbmc.dem3d.joint_laws`' laws): the
limit-equilibrium wedge's "equal uniform pressures" and its given pressure per plane.

How the engine loads the blocks with it (`bbmc.dem3d.contact_forces`): the pressure at each sub-contact's
closed part acts on both blocks across the contact, pushing them apart, p A along the normal at the
closed part's centroid. The springs then carry the effective stress (UDEC's convention, as the 2D engine
`bbmc.dem.water` states it): the total normal stress is sigma_n' + p, and the strength is that of
sigma_n' = sigma_n - p (Terzaghi). Differences from the 2D engine, which loads every block edge below
its phreatic polyline: the 3D engine loads the closed parts of its contacts only (the issue's "pressures
on contact areas"): no pressure on free faces (so no buoyancy of a block under the table, only the
uplift on its contacts, as limit equilibrium counts it) nor on the open part of a contact; and each
share's pressure is its centroid's, so a share the table crosses, and the water's own moment over a
share, are approximate (both shrink with the refinement). Source: Itasca, UDEC/3DEC manuals (effective
stresses at the contacts, joint water pressure); Hoek & Bray, Rock Slope Engineering (water on a sliding
plane, U = p A).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike


@dataclass(frozen=True)
class WaterTable:
    """A phreatic plane: water of `unit_weight` gamma_w [N/m^3] below the plane through `point` [m]
    with normal `normal` (any length, not horizontal)."""

    unit_weight: float
    point: Sequence[float]
    normal: Sequence[float]

    def coefficients(self) -> tuple[float, float, float, float]:
        """(gamma_w [N/m^3], z0 [m], a [1], b [1]): z_table(x, y) = z0 + a x + b y. A gamma_w < 0, or a
        normal that is not three finite numbers with a vertical component, is refused in one line."""
        n, p = np.asarray(self.normal, dtype=float), np.asarray(self.point, dtype=float)
        if n.shape != (3,) or p.shape != (3,) or not (np.all(np.isfinite(n)) and np.all(np.isfinite(p))):
            raise ValueError("water: point and normal must be three finite numbers each")
        if not self.unit_weight >= 0.0:
            raise ValueError(f"water: unit_weight must be >= 0 N/m3, got {self.unit_weight}")
        length = float(np.linalg.norm(n))
        if not length > 0.0 or abs(n[2]) < 1e-9 * length:
            raise ValueError("water: the table's normal must have a vertical component (a plane z(x, y))")
        return float(self.unit_weight), float(n @ p / n[2]), float(-n[0] / n[2]), float(-n[1] / n[2])

    def pressure(self, points: ArrayLike) -> np.ndarray:
        """p = gamma_w max(z_table(x, y) - z, 0) [Pa] at points (..., 3) [m]."""
        gamma, z0, a, b = self.coefficients()
        x = np.asarray(points, dtype=float)
        return gamma * np.maximum(z0 + a * x[..., 0] + b * x[..., 1] - x[..., 2], 0.0)
