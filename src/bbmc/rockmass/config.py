"""The `rock_mass:` section: a slope profile and joint sets given by their statistics (docs/rock-mass.md).

Units are in the key names (m, deg); every model is a strict, frozen `Section`, so a bad value is one
line naming its key. Lengths that scatter (spacing, trace length, gap) are a positive number (a
constant) or a distribution; the generator (`bbmc.rockmass.generate`) samples them from the seed.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import BeforeValidator, Field, model_validator

from bbmc.config import Section
from bbmc.geometry.polygons import joint_set_trace
from bbmc.rockmass import profile

Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Point = Annotated[list[float], Field(min_length=2, max_length=2)]
SetName = Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_\-]+$")]
CRACK = "tension_crack"  # the crack's edges are labelled joint.tension_crack: no set may take the name


def distinct_set_names(names: list[str]) -> None:
    """ValueError naming the first joint set that takes an earlier set's name (edges are labelled by
    their set's name, so two sets of one name could not be told apart)."""
    for number, name in enumerate(names):
        if names.index(name) != number:
            raise ValueError(f"joint_sets.{number}.name: '{name}' is given twice")


class Constant(Section):
    distribution: Literal["constant"]
    value: Positive


class Exponential(Section):
    distribution: Literal["exponential"]
    mean: Positive


class Lognormal(Section):
    """The mean and standard deviation of the length itself (not of its logarithm)."""

    distribution: Literal["lognormal"]
    mean: Positive
    std: Positive


class TruncatedNormal(Section):
    """A normal distribution of mean `mean` and standard deviation `std` (before truncation), kept
    within [min, max]."""

    distribution: Literal["truncated_normal"]
    mean: float
    std: Positive
    min: NonNegative = 0.0
    max: Positive | None = None

    @model_validator(mode="after")
    def _bounds(self) -> TruncatedNormal:
        if self.max is not None and self.max <= self.min:
            raise ValueError(f"max ({self.max}) must exceed min ({self.min})")
        return self


def _number_is_constant(value: object) -> object:
    """A plain number given for a length: a constant (refused here unless positive, naming the key)."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        if not value > 0:
            raise ValueError("Input should be greater than 0")
        return {"distribution": "constant", "value": value}
    return value


Length = Annotated[
    Constant | Exponential | Lognormal | TruncatedNormal,
    Field(discriminator="distribution"),
    BeforeValidator(_number_is_constant),
]


class DipScatter(Section):
    """A dip that scatters from line to line: normal, of this mean and standard deviation [deg]."""

    mean: Annotated[float, Field(ge=0, le=90)]
    std: NonNegative


class Orientation(Section):
    """A set's 3D orientation: mean dip and dip direction (azimuth, clockwise from north) of its planes,
    and Fisher's K of their poles about the mean (omitted: no scatter)."""

    dip_deg: Annotated[float, Field(ge=0, le=90)]
    dip_direction_deg: Annotated[float, Field(ge=0, lt=360)]
    fisher_k: Positive | None = None


class JointSet(Section):
    """A set of joints along parallel lines (up to their scatter), each line a sequence of traces
    (joints) and gaps (rock bridges); without trace_length_m the set is persistent."""

    name: SetName
    dip_deg: Annotated[float, Field(ge=0, le=90)] | DipScatter | None = None  # in the section's plane
    dip_direction_to_face_deg: Annotated[float, Field(ge=0, le=180)] | None = None  # with dip_deg [0]
    orientation: Orientation | None = None  # 3D, cut by the section at section_azimuth_deg
    spacing_m: Length  # true spacing, normal to the joints
    trace_length_m: Length | None = None  # along a line in the section
    gap_m: Length | None = None
    persistence: Annotated[float, Field(gt=0, le=1)] | None = None  # gap = trace (1 - k) / k
    offset_m: float = 0.0  # of line 0 from the origin (the toe), normal to the joints (0: through it)

    @model_validator(mode="after")
    def _consistent(self) -> JointSet:
        if self.dip_deg == 90 and self.dip_direction_to_face_deg == 90:
            raise ValueError("a vertical set striking across the face is parallel to the section: no trace")
        if (self.dip_deg is None) == (self.orientation is None):
            raise ValueError("give exactly one of dip_deg (in the section) or orientation (3D)")
        if self.orientation is not None and self.dip_direction_to_face_deg is not None:
            raise ValueError(
                "dip_direction_to_face_deg goes with dip_deg; orientation gives dip_direction_deg"
            )
        if self.gap_m is not None and self.persistence is not None:
            raise ValueError("give gap_m or persistence, not both")
        if self.trace_length_m is None and self.gap_m is not None:
            raise ValueError("gap_m needs trace_length_m")
        if self.trace_length_m is None and self.persistence not in (None, 1.0):
            raise ValueError("persistence below 1 needs trace_length_m")
        if self.trace_length_m is not None and self.gap_m is None and self.persistence is None:
            raise ValueError("trace_length_m needs gap_m or persistence")
        return self

    @property
    def persistent(self) -> bool:
        return self.trace_length_m is None or self.persistence == 1.0


class Benches(Section):
    """`count` equal benches from the toe at the origin: faces of `height_m` at `face_angle_deg`,
    separated by berms of `berm_width_m`."""

    height_m: Positive
    face_angle_deg: Annotated[float, Field(gt=0, le=90)]
    berm_width_m: NonNegative
    count: Annotated[int, Field(ge=1)]


class TensionCrack(Section):
    """A vertical open crack from the ground behind the crest down to `depth_m`."""

    distance_behind_crest_m: Positive
    depth_m: Positive


class Profile(Section):
    """The ground surface from the toe to the crest (a polyline, or benches), flat ground in front of the
    toe and behind the crest, and the model's base `depth_m` below the toe."""

    polyline_m: Annotated[list[Point], Field(min_length=2)] | None = None
    benches: Benches | None = None
    toe_extent_m: NonNegative
    crest_extent_m: NonNegative
    depth_m: Positive
    tension_crack: TensionCrack | None = None

    @model_validator(mode="after")
    def _inside(self) -> Profile:
        given = [key for key in ("polyline_m", "benches") if getattr(self, key) is not None]
        if len(given) != 1:
            raise ValueError(f"give exactly one of polyline_m, benches; got {', '.join(given) or 'none'}")
        surface = self.surface()
        crossing = profile.first_crossing(surface, closed=False)
        if crossing is not None:
            i, j, (x, y) = crossing
            raise ValueError(
                f"polyline_m: the ground surface crosses itself at ({x:.4g}, {y:.4g}) (segments {i}, {j})"
            )
        left, right = surface[0, 0] - self.toe_extent_m, surface[-1, 0] + self.crest_extent_m
        if surface[:, 0].min() < left or surface[:, 0].max() > right:
            raise ValueError(
                f"the ground surface runs beyond the model's sides (x = {left:g} and {right:g}): the crest "
                "must be on the right of the toe, and no point of the surface beyond either"
            )
        outline = profile.body_outline(surface, self.toe_extent_m, self.crest_extent_m, self.depth_m)
        if len(outline) < 3:
            raise ValueError(
                "the profile encloses no rock (a vertical face with no ground in front or behind)"
            )
        crossing = profile.first_crossing(outline, closed=True)
        if crossing is not None:
            x, y = crossing[2]
            raise ValueError(f"the ground surface meets the model's base or sides at ({x:.4g}, {y:.4g})")
        crack = self.tension_crack
        if crack is not None:
            if crack.distance_behind_crest_m >= self.crest_extent_m:
                raise ValueError(
                    f"tension_crack.distance_behind_crest_m ({crack.distance_behind_crest_m}) must be less "
                    f"than crest_extent_m ({self.crest_extent_m})"
                )
            height = surface[-1, 1] - outline[:, 1].min()
            if crack.depth_m >= height:
                raise ValueError(
                    f"tension_crack.depth_m ({crack.depth_m}) must be less than the ground's height above "
                    f"the base behind the crest ({height:g} m)"
                )
        return self

    def surface(self) -> np.ndarray:
        """The ground surface [m] from the toe to the crest, without the flat ground beyond them."""
        if self.benches is not None:
            b = self.benches
            return profile.bench_surface(b.height_m, b.face_angle_deg, b.berm_width_m, b.count)
        return np.array(self.polyline_m, dtype=float)


class RockMassConfig(Section):
    """A slope profile cut into convex blocks by joint sets given by their statistics."""

    profile: Profile
    seed: Annotated[int, Field(ge=0)] = 0  # every realization is reproducible from its seed
    section_azimuth_deg: Annotated[float, Field(ge=0, lt=360)] | None = None  # the face's dip direction
    origin_m: Point | None = None  # the world point the sets' lines are laid from [default: the toe]
    joint_sets: Annotated[list[JointSet], Field(min_length=1)]
    min_block_fraction: Annotated[float, Field(ge=0, lt=1)] = 0.02  # of the median block: no smaller cut
    fixed_boundaries: list[Literal["left", "right", "bottom"]] = Field(
        default_factory=lambda: ["right", "bottom"]
    )  # blocks with an edge on these sides of the model have every degree of freedom held
    held_sliver_fraction: Annotated[float, Field(ge=0, lt=1)] = 0.25  # of the median block: a smaller
    # block with a vertex within the median block's size of a fixed side is held too (0: none)

    @model_validator(mode="after")
    def _sets(self) -> RockMassConfig:
        distinct_set_names([s.name for s in self.joint_sets])
        for number, joint_set in enumerate(self.joint_sets):
            if joint_set.name == CRACK:
                raise ValueError(
                    f"joint_sets.{number}.name: '{CRACK}' is the tension crack's; choose another"
                )
            if joint_set.orientation is None:
                continue
            if self.section_azimuth_deg is None:
                raise ValueError(f"section_azimuth_deg is missing: joint_sets.{number} is given in 3D")
            o = joint_set.orientation
            try:
                joint_set_trace(o.dip_deg, o.dip_direction_deg - self.section_azimuth_deg)
            except ValueError:
                raise ValueError(
                    f"joint_sets.{number}.orientation: the set is parallel to the section: no trace"
                ) from None
        return self
