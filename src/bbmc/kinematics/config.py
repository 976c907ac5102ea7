"""The keys a kinematic analysis is given by, in degrees at the file: the slope face, the lateral
limits of each mode, and one set's orientation. `bbmc kinematics` and the sweep's `kinematics` base
read the same sections, and turn them into the analysis' radians here."""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import Field

from bbmc.config import Section
from bbmc.kinematics.face import Face, KinematicLimits

Dip = Annotated[float, Field(ge=0, le=90)]
Azimuth = Annotated[float, Field(ge=0, le=360)]
Friction = Annotated[float, Field(gt=0, lt=90)]
Limit = Annotated[float, Field(gt=0, le=90)]


class FaceSection(Section):
    """The slope face: its dip and dip direction [deg]."""

    dip_deg: Annotated[float, Field(gt=0, le=90)]
    dip_direction_deg: Azimuth

    def face(self) -> Face:
        return Face(math.radians(self.dip_deg), math.radians(self.dip_direction_deg))


class LimitsSection(Section):
    """Lateral limits [deg] of each mode (Rocscience Dips' defaults), and whether they are Dips'
    straight lines through the net's centre (false) or mplstereonet's curved small circles (true)."""

    planar_deg: Limit = 20.0
    flexural_toppling_deg: Limit = 30.0
    direct_toppling_deg: Limit = 20.0
    curved: bool = False

    def limits(self) -> KinematicLimits:
        return KinematicLimits(
            math.radians(self.planar_deg),
            math.radians(self.flexural_toppling_deg),
            math.radians(self.direct_toppling_deg),
            self.curved,
        )


class SetOrientationSection(Section):
    """A joint set's mean plane [deg], Fisher's K of its poles about it, and its own friction angle
    [deg] (none: the analysis' friction_deg)."""

    dip_deg: Dip
    dip_direction_deg: Azimuth
    fisher_k: Annotated[float, Field(gt=0)]
    friction_deg: Friction | None = None
