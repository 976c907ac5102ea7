"""The `support:` and `design:` sections of a scene (docs/how-to/support.md), validated whole.

Units are in the key names (m, mm, mm^2, kN, kN/m, GPa); `bbmc.dem.support_elements` converts to SI. A
bolt's forces are per bolt; its out-of-plane `spacing_m` turns them into forces per metre run, the
plane-strain section's unit.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, model_validator

from bbmc.config import Section

Pair = Annotated[list[float], Field(min_length=2, max_length=2)]
Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Strain = Annotated[float, Field(gt=0, le=1)]


class Tendon(Section):
    """What every bolt has: where it runs (head at the face, end in the rock), its steel and spacing."""

    name: Annotated[str, Field(min_length=1, pattern=r"^[^\s]+$")]
    head_m: Pair  # the plate's end, at the face
    end_m: Pair  # the far end, in the rock behind
    spacing_m: Positive = 1.0  # out of plane: one bolt per spacing_m of slope length
    diameter_mm: Positive | None = None  # a bar's; or give the steel's area_mm2 (a cable's strands)
    area_mm2: Positive | None = None
    steel_modulus_GPa: Positive = 200.0
    steel_capacity_kN: Positive  # the tendon's tensile (yield) capacity
    plate_capacity_kN: Positive | None = None  # the plate's (face plate and nut); none: not limiting
    rupture_strain: Strain = 0.1  # elongation at rupture over the free (anchor) or debonded length

    @model_validator(mode="after")
    def _one_size(self) -> Tendon:
        if (self.diameter_mm is None) == (self.area_mm2 is None):
            raise ValueError("give exactly one of diameter_mm, area_mm2")
        if self.head_m == self.end_m:
            raise ValueError("head_m and end_m are the same point: a bolt has a length")
        return self

    @property
    def area_m2(self) -> float:
        if self.area_mm2 is not None:
            return self.area_mm2 * 1e-6
        return math.pi * (self.diameter_mm * 1e-3) ** 2 / 4.0

    @property
    def diameter_m(self) -> float:
        """The bar's diameter, or that of a bar of the same area [m]."""
        return math.sqrt(4.0 * self.area_m2 / math.pi)

    @property
    def length_m(self) -> float:
        return math.dist(self.head_m, self.end_m)


class Anchor(Tendon):
    """An end-anchored tendon (mechanically anchored bolt, or a cable anchor with a free length):
    fixed at its two ends only, stiffness E A / L over its length L, pretensioned, pull-out at the
    bond length at its end."""

    type: Literal["anchor"]
    pretension_kN: NonNegative = 0.0
    bond_strength_kN_per_m: Positive | None = None  # shear strength of the grout-rock bond per metre
    bond_length_m: Positive | None = None  # the fixed (bonded) length at the end

    @model_validator(mode="after")
    def _bond_pair(self) -> Anchor:
        if (self.bond_strength_kN_per_m is None) != (self.bond_length_m is None):
            raise ValueError("give both bond_strength_kN_per_m and bond_length_m, or neither")
        return self


class GroutedBolt(Tendon):
    """A fully grouted bolt (dowel): bonded all along, so it acts only where it crosses a joint, as an
    axial spring (and a shear spring with `shear_capacity_kN`) between the two blocks (UDEC's local
    reinforcement)."""

    type: Literal["grouted_bolt"]
    bond_strength_kN_per_m: Positive  # pull-out: bond per metre of embedded length on each side
    debonded_length_m: Positive | None = None  # over which a crossing stretches [default: 10 diameters]
    shear_capacity_kN: Positive | None = None  # none: axial only, as RocPlane's dowels
    shear_stiffness_MN_per_m: Positive | None = None  # [default: the axial stiffness]


SupportElement = Annotated[Anchor | GroutedBolt, Field(discriminator="type")]


class Design(Section):
    """`bbmc fos`: the smallest capacity, or the largest spacing, of one support element that gives
    `target_fs` (limit equilibrium first, then the engine's strength reduction)."""

    target_fs: Annotated[float, Field(gt=1, le=5)]
    support: (
        str | Annotated[list[str], Field(min_length=1)]
    )  # an element's name, or several: one value for all
    vary: Literal["capacity", "spacing"]  # steel_capacity_kN [kN] or spacing_m [m]
    range: Pair  # the values searched: [smallest, largest]
    tolerance: Annotated[float, Field(gt=0, le=0.2)] = 0.02  # of the value: the search's last step

    @property
    def elements(self) -> list[str]:
        """The names of the elements the design varies together (a pattern of rows)."""
        return [self.support] if isinstance(self.support, str) else list(self.support)

    @model_validator(mode="after")
    def _range(self) -> Design:
        low, high = self.range
        if not 0 < low < high:
            raise ValueError("range must be [smallest, largest] with 0 < smallest < largest")
        return self
