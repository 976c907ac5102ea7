"""Support on a wedge as force vectors: bolts (active or passive) and shotcrete, summed into the active
and passive resultants that `mechanics.wedge_factor_of_safety` takes.

* A bolt (Swedge, "How bolts are implemented"; Hoek & Bray 1981, ch. 8): a force of its capacity T
  [N] per bolt times the number of bolts, along the bolt's line of trend t and plunge p [rad] as it is
  drilled from the face into the rock (plunge downward positive): the tensioned bolt pulls the wedge
  towards its anchor, along the drilling direction,
      T_vec = n T (cos p sin t, cos p cos t, -sin p).
  This is the planar model's convention (`bbmc.slope.planar`: a bolt drilled psi_T below the horizontal
  into the slope acts at theta = psi_p + psi_T from the plane's up-dip direction, i.e. along the hole).
  Every bolt acts through the centroid; its length and position do not enter the FS (Swedge).
* Active or passive, RocPlane's and Swedge's two ways of counting a support force, as in the planar
  model: an active bolt (pretensioned: it acts before any movement, exactly as an external force of
  the same size and direction) joins the active resultant, which sets the sliding mode and direction
  and whose component along the sliding direction s reduces the driving force; a passive bolt (grouted,
  mobilised by movement) adds its normal parts to the planes in contact and its component against the
  sliding, -T_vec . s, to the resisting force, and never changes the mode. For a planar wedge these are
  the planar model's forms, FS = (c A + (N + T_n) tan phi) / (D - T_s) and (... + T_s) / D.
* Capacity: the planar model takes T >= 0 as given (a bolt pulls, it cannot push) and so does this
  module; a bolt's capacity from its steel, plate and bond is `bbmc.support.capacity`'s
  (`anchor_capacity`, `grouted_bolt_capacity`: the weakest of them), passed in as T.
* Shotcrete (Swedge, "Applying shotcrete"): the largest force the shotcrete can exert on the wedge is
  its shear strength tau_s [Pa] times its thickness t [m] times the perimeter of the wedge's exposed
  face that the shotcrete has to shear through: the traces of joints 1 and 2 on the slope face (the
  shotcrete covers the face, not the upper surface), L = L_1 + L_2 [m] (`geometry.WedgeGeometry`'s
  `trace_face_1 + trace_face_2`),
      S = tau_s t (L_1 + L_2)   [N],
  normal to the slope face and into the slope, always passive. Swedge's example: L_1 10 m, L_2 12 m,
  t 0.1 m, tau_s 100 t/m^2: S = 220 t.

SI: forces N, lengths m, stresses Pa, angles rad; arrays broadcast over samples.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bbmc.slope.wedge.loads import force_vector

SUPPORT_FORMS = ("active", "passive")


@dataclass(frozen=True)
class Bolt:
    """`count` bolts of capacity `force` [N] each, drilled along trend and plunge [rad] (downward
    positive, into the rock), counted in `form`, "active" or "passive" (module docstring)."""

    force: ArrayLike
    trend: ArrayLike
    plunge: ArrayLike
    count: ArrayLike = 1
    form: str = "active"

    def __post_init__(self) -> None:
        if self.form not in SUPPORT_FORMS:
            raise ValueError(f"bolt form must be one of {SUPPORT_FORMS}, not {self.form!r}")
        if np.any(~(np.asarray(self.force, dtype=float) >= 0.0)):
            raise ValueError("bolt force must be >= 0 (a bolt pulls, it cannot push)")
        if np.any(~(np.asarray(self.count, dtype=float) >= 0.0)):
            raise ValueError("bolt count must be >= 0")

    @property
    def vector(self) -> NDArray:
        """n T along the bolt's drilling direction (..., 3) [N]."""
        total = np.asarray(self.count, dtype=float) * np.asarray(self.force, dtype=float)
        return force_vector(total, self.trend, self.plunge)


def shotcrete_force(
    thickness: ArrayLike, shear_strength: ArrayLike, face_traces: ArrayLike, face_normal: ArrayLike
) -> NDArray:
    """S = tau_s t L into the slope (..., 3) [N] (module docstring, Swedge): thickness t [m], shear
    strength tau_s [Pa], L the traces of joints 1 and 2 on the face summed [m], and the face's unit
    normal out of the rock (`WedgeGeometry.normal_face`). A passive force."""
    t, tau, length = (np.asarray(v, dtype=float) for v in (thickness, shear_strength, face_traces))
    if np.any(~(t >= 0.0)) or np.any(~(tau >= 0.0)) or np.any(~(length >= 0.0)):
        raise ValueError("shotcrete thickness, shear strength and face traces must be >= 0")
    return -(t * tau * length)[..., None] * np.asarray(face_normal, dtype=float)


def support_resultants(bolts: Iterable[Bolt], passive: ArrayLike = 0.0) -> tuple[NDArray, NDArray]:
    """The active and the passive support resultants (..., 3) [N]: each bolt's vector in its form's sum,
    and `passive` (shotcrete, or other passive forces already summed) added to the passive one."""
    active, held = np.zeros(3), np.asarray(passive, dtype=float) + np.zeros(3)
    for bolt in bolts:
        if bolt.form == "active":
            active = active + bolt.vector
        else:
            held = held + bolt.vector
    return active, held
