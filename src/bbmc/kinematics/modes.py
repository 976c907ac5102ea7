"""The kinematic modes by name, and the critical zone of each on a grid of directions: one table
that the tallies, the sweeps, the probabilities and the stereonet's shaded zones all read, so a
pole drawn in a zone and a pole counted critical can never disagree.

Pole modes test planes by their poles; line modes test lines of intersection:

| mode | tested on | critical where (criteria.py) |
| --- | --- | --- |
| planar_sliding | poles | daylight envelope, outside the friction cone, lateral limits |
| flexural_toppling | poles | outside the slip-limit plane, lateral limits |
| base_plane | poles | direct-toppling zones 1 and 2 (a base plane for toppling blocks) |
| base_plane_sliding | poles | zone 1 (the blocks can also slide on it) |
| base_plane_oblique | poles | zone 3 |
| wedge_sliding | lines | primary critical zone |
| wedge_sliding_one_plane | lines | secondary critical zone |
| direct_toppling | lines | zones 1 and 2 |
| direct_toppling_steep | lines | zone 2 (inside the base planes' friction cone) |
| oblique_toppling | lines | zone 3 |
"""

from __future__ import annotations

import numpy as np

from bbmc.geometry.orientation import downward
from bbmc.kinematics.criteria import (
    base_planes,
    direct_toppling,
    flexural_toppling,
    planar_sliding,
    wedge_sliding,
)
from bbmc.kinematics.face import Face, KinematicLimits

POLE_MODES = ("planar_sliding", "flexural_toppling", "base_plane", "base_plane_sliding", "base_plane_oblique")
LINE_MODES = (
    "wedge_sliding",
    "wedge_sliding_one_plane",
    "direct_toppling",
    "direct_toppling_steep",
    "oblique_toppling",
)


def pole_modes(
    poles: np.ndarray, face: Face, friction: float | np.ndarray, limits: KinematicLimits
) -> dict[str, np.ndarray]:
    """The critical mask of each pole mode for planes of upward unit normals `poles` (N, 3)."""
    base = base_planes(poles, face, friction, limits)
    return {
        "planar_sliding": planar_sliding(poles, face, friction, limits),
        "flexural_toppling": flexural_toppling(poles, face, friction, limits),
        "base_plane": base.zone_1 | base.zone_2,
        "base_plane_sliding": base.zone_1,
        "base_plane_oblique": base.zone_3,
    }


def line_modes(
    lines: np.ndarray, face: Face, friction: float | np.ndarray, limits: KinematicLimits
) -> dict[str, np.ndarray]:
    """The critical mask of each line mode for lines of intersection `lines` (N, 3)."""
    wedge = wedge_sliding(lines, face, friction)
    topple = direct_toppling(lines, face, friction, limits)
    return {
        "wedge_sliding": wedge.primary,
        "wedge_sliding_one_plane": wedge.secondary,
        "direct_toppling": topple.zone_1 | topple.zone_2,
        "direct_toppling_steep": topple.zone_2,
        "oblique_toppling": topple.zone_3,
    }


def critical_zone_masks(
    points: np.ndarray, face: Face, friction: float, limits: KinematicLimits | None = None
) -> dict[str, np.ndarray]:
    """Each mode's critical zone on a grid of lower-hemisphere unit vectors `points` (m, 3): for a
    pole mode the mask of the points that, read as poles, are critical; for a line mode, of the
    points that, read as lines, are critical. The stereonet fills its zones from these masks."""
    limits = KinematicLimits() if limits is None else limits
    down = downward(points)
    return pole_modes(-down, face, friction, limits) | line_modes(down, face, friction, limits)
