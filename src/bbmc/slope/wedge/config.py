"""The keys a wedge is given by (WEDGE.yaml), in degrees, kPa, MPa, kN and metres at the file, and their
turning into the analysis' SI objects here (radians, Pa, N, N/m^3): the joint planes and their strength,
the face, the upper surface, the tension crack, water, seismic, forces and support. `bbmc wedge` reads
these sections, and so does a sweep's `wedge` base (`bbmc.sweep.wedge_model`), which builds them with
its varied numbers as arrays over the samples (`model_construct`): every conversion here is numpy and
broadcasts.

Every rule that a single key cannot state is checked with the whole config (`model_validator`), so a
bad config is refused before any work, in one line naming its key (`bbmc.config`).
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
from numpy.typing import ArrayLike
from pydantic import Field, model_validator

from bbmc import units
from bbmc.config import Section
from bbmc.geometry.orientation import line_vectors
from bbmc.slope.wedge.analysis import Seismic
from bbmc.slope.wedge.geometry import TensionCrack
from bbmc.slope.wedge.loads import force_vector
from bbmc.slope.wedge.mechanics import MohrCoulomb, PlaneStrength
from bbmc.slope.wedge.strength import BartonBandis
from bbmc.slope.wedge.support import Bolt
from bbmc.slope.wedge.water import DRY, HoekBrayWater, PlanePressures, WaterModel

Dip = Annotated[float, Field(ge=0, le=90)]
Azimuth = Annotated[float, Field(ge=0, le=360)]
Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Angle = Annotated[float, Field(gt=0, lt=90)]
Plunge = Annotated[float, Field(ge=-90, le=90)]
KN = 1e3  # N per kN


def scaled_to_intersection(field_length: object) -> bool:
    """Whether a B-B plane's `field_length_m` is `intersection` (it may be a length, or an array of them
    in a sweep's sample)."""
    return isinstance(field_length, str) and field_length == "intersection"


class MohrCoulombStrength(Section):
    """c [kPa] and phi [deg]."""

    law: Literal["mohr_coulomb"]
    cohesion_kPa: NonNegative = 0.0
    friction_deg: Angle

    def strength(self) -> MohrCoulomb:
        return MohrCoulomb(self.cohesion_kPa * units.kPa, self.friction_deg * units.deg)


class BartonBandisStrength(Section):
    """JRC_0, JCS_0 [MPa] at the lab length [m], phi_b and the cap phi_max [deg], the waviness i [deg],
    and the joint's length in the direction of shear [m]: a number, or `intersection` (the wedge's
    line of intersection, `strength.BartonBandis`); none: no scale correction."""

    law: Literal["barton_bandis"]
    jrc: Annotated[float, Field(ge=0, le=20)]
    jcs_MPa: Positive
    phi_b_deg: Angle
    phi_max_deg: Angle = 70.0
    waviness_deg: Annotated[float, Field(ge=0, lt=90)] = 0.0
    lab_length_m: Positive = 0.1
    field_length_m: Positive | Literal["intersection"] | None = None

    @model_validator(mode="after")
    def _below_vertical(self) -> BartonBandisStrength:
        if self.phi_max_deg + self.waviness_deg >= 90.0:
            raise ValueError("phi_max_deg + waviness_deg must be below 90")
        return self

    def strength(self, intersection_length: float = 0.0) -> BartonBandis:
        """The plane's B-B strength; `intersection_length` [m] is used where field_length_m asks for it."""
        field = self.field_length_m
        length = intersection_length if scaled_to_intersection(field) else (0.0 if field is None else field)
        return BartonBandis(
            self.jrc,
            self.jcs_MPa * units.MPa,
            self.phi_b_deg * units.deg,
            self.phi_max_deg * units.deg,
            self.lab_length_m if field is not None else 0.0,
            length,
            self.waviness_deg * units.deg,
        )


class EquivalentMohrCoulombStrength(BartonBandisStrength):
    """The paper's equivalent Mohr-Coulomb (its eqs 11-14, as `bbmc mc` gives it): the tangent c and phi
    of the plane's Barton-Bandis envelope (the keys above, scale and waviness included) at the normal
    stress `sigma_n_kPa`, then held constant, as the paper's 3DEC model holds them. At the plane's own
    normal stress from statics (wedge.csv's sigma_n) it gives the B-B strength exactly; elsewhere the
    constant tangent over-estimates the concave envelope (`strength.BartonBandis.equivalent_mohr_coulomb`)."""

    law: Literal["equivalent_mohr_coulomb"]
    sigma_n_kPa: Positive

    def strength(self, intersection_length: float = 0.0) -> MohrCoulomb:
        """The tangent c [Pa], phi [rad] at sigma_n_kPa of the B-B plane."""
        tangent = super().strength(intersection_length).equivalent_mohr_coulomb(self.sigma_n_kPa * units.kPa)
        return MohrCoulomb(tangent.cohesion, tangent.friction)


Strength = Annotated[
    MohrCoulombStrength | BartonBandisStrength | EquivalentMohrCoulombStrength, Field(discriminator="law")
]


class Orientation(Section):
    """A plane's dip and dip direction [deg]."""

    dip_deg: Dip
    dip_direction_deg: Azimuth

    def radians(self) -> tuple[float, float]:
        return np.radians(self.dip_deg), np.radians(self.dip_direction_deg)


class JointPlane(Orientation):
    """A joint plane (or a joint set's mean plane), its shear strength, and optionally the largest trace
    length and persistence [m] it has (Swedge's Scale Wedge: the wedge is scaled down until its trace
    of this plane, the longer of the one on the face and the one on the upper surface, and its largest
    dimension on this plane fit them; `size_limits`)."""

    strength: Strength
    trace_length_m: Positive | None = None
    persistence_m: Positive | None = None

    def limits_size(self) -> bool:
        """True where the plane limits the wedge's size."""
        return self.trace_length_m is not None or self.persistence_m is not None

    def plane_strength(self, intersection_length: float) -> PlaneStrength:
        """Its strength; a B-B plane scaled to `intersection_length` [m] where it asks for it."""
        if isinstance(self.strength, BartonBandisStrength):
            return self.strength.strength(intersection_length)
        return self.strength.strength()

    def needs_length(self) -> bool:
        """True where the strength is scaled to the wedge's line of intersection."""
        return scaled_to_intersection(getattr(self.strength, "field_length_m", None))


class Face(Orientation):
    """The slope face; `overhanging: true` where it leans out over the toe (Swedge's overhanging face)."""

    dip_deg: Annotated[float, Field(gt=0, le=90)]
    overhanging: bool = False


class Crack(Orientation):
    """A tension crack: its plane and its distance [m] from the crest point C1 along plane 1's trace on
    the upper surface (Hoek & Bray's L)."""

    distance_m: Positive

    def crack(self) -> TensionCrack:
        return TensionCrack(*self.radians(), self.distance_m)


class NoWater(Section):
    model: Literal["dry"]

    def water(self) -> WaterModel:
        return DRY


class HoekBray(Section):
    """Hoek & Bray's water (`water.HoekBrayWater`): the filled fraction of their head, gamma_w [kN/m^3]."""

    model: Literal["hoek_bray"]
    filled: Annotated[float, Field(ge=0, le=1)] = 1.0
    unit_weight_kN_m3: Positive = 9.81

    def water(self) -> WaterModel:
        return HoekBrayWater(self.filled)


class Pressures(Section):
    """A mean water pressure [kPa] on each plane and on the tension crack (`water.PlanePressures`)."""

    model: Literal["pressures"]
    plane_1_kPa: NonNegative
    plane_2_kPa: NonNegative
    crack_kPa: NonNegative = 0.0

    def water(self) -> WaterModel:
        return PlanePressures(
            self.plane_1_kPa * units.kPa, self.plane_2_kPa * units.kPa, self.crack_kPa * units.kPa
        )


Water = Annotated[NoWater | HoekBray | Pressures, Field(discriminator="model")]


def water_unit_weight(water: NoWater | HoekBray | Pressures) -> ArrayLike:
    """gamma_w [N/m^3]: Hoek & Bray's water's own, else 9.81 kN/m^3 (a model that does not use it)."""
    return np.asarray(getattr(water, "unit_weight_kN_m3", 9.81)) * KN


class SeismicSection(Section):
    """k [1] and its direction: down the line of intersection, horizontal along its trend, or `given`
    by trend and plunge [deg] (plunge down positive)."""

    coefficient: Annotated[float, Field(ge=0, le=1)]
    direction: Literal["line", "horizontal", "given"] = "line"
    trend_deg: Azimuth | None = None
    plunge_deg: Plunge | None = None

    @model_validator(mode="after")
    def _given(self) -> SeismicSection:
        given = self.trend_deg is not None and self.plunge_deg is not None
        some = self.trend_deg is not None or self.plunge_deg is not None
        if (self.direction == "given") != given or (some and not given):
            raise ValueError("direction 'given' goes with trend_deg and plunge_deg (and they with it)")
        return self

    def seismic(self) -> Seismic:
        if self.direction != "given":
            return Seismic(self.coefficient, self.direction)
        return Seismic(
            self.coefficient, line_vectors(np.radians(self.trend_deg), np.radians(self.plunge_deg))
        )


class ForceSection(Section):
    """An external force: magnitude [kN] along the line of trend and plunge [deg] (plunge down positive)."""

    magnitude_kN: NonNegative
    trend_deg: Azimuth
    plunge_deg: Plunge

    def vector(self):
        return force_vector(self.magnitude_kN * KN, np.radians(self.trend_deg), np.radians(self.plunge_deg))


class BoltSection(Section):
    """`count` bolts of capacity [kN] each, drilled along trend and plunge [deg] into the rock, active
    (pretensioned) or passive (`support.Bolt`)."""

    capacity_kN: NonNegative
    trend_deg: Azimuth
    plunge_deg: Plunge
    count: Annotated[int, Field(ge=1)] = 1
    form: Literal["active", "passive"] = "active"

    def bolt(self) -> Bolt:
        return Bolt(
            self.capacity_kN * KN,
            np.radians(self.trend_deg),
            np.radians(self.plunge_deg),
            self.count,
            self.form,
        )


class Shotcrete(Section):
    """Shotcrete on the face: thickness [m] and shear strength [kPa] (`support.shotcrete_force`)."""

    thickness_m: Positive
    shear_strength_kPa: Positive


class BoltDirection(Section):
    trend_deg: Azimuth
    plunge_deg: Plunge


class Design(Section):
    """The bolts for a target FS along a given direction or `optimum` (the closed form's,
    `design.optimum_bolt`), the least total force by bisection on the vector solution along it
    (`bolting`); then the count of bolts of `capacity_kN`, or the capacity of each of `count` bolts."""

    target_fs: Annotated[float, Field(gt=0, le=10)]
    bolt: Literal["optimum"] | BoltDirection = "optimum"
    capacity_kN: Positive | None = None
    count: Annotated[int, Field(ge=1)] | None = None
    form: Literal["active", "passive"] = "active"

    @model_validator(mode="after")
    def _one_sizing(self) -> Design:
        if (self.capacity_kN is None) == (self.count is None):
            raise ValueError(
                "give exactly one of capacity_kN (the count is designed) and count (the capacity is)"
            )
        return self


def check_slope(
    face: Face,
    upper_surface: Orientation,
    heights: dict[str, float | None],
    water: NoWater | HoekBray | Pressures,
    crack: Crack | None,
) -> None:
    """The rules of a wedge's slope that no single key states, as `bbmc wedge` and a sweep's wedge base
        both take them: exactly one of the two `heights` (by key), a face steeper than the upper surface's
    apparent dip in the face's dip direction (a ridge's far side dips away: any face is steeper),
        and a water pressure on the tension crack only with a crack. ValueError naming the key."""
    if sum(h is not None for h in heights.values()) != 1:
        raise ValueError(f"key '{', '.join(heights)}': give exactly one")
    turn = math.radians(upper_surface.dip_direction_deg - face.dip_direction_deg)
    apparent = math.degrees(math.atan(math.tan(math.radians(upper_surface.dip_deg)) * math.cos(turn)))
    if not face.overhanging and face.dip_deg <= apparent:
        raise ValueError(
            f"key 'face.dip_deg': the face ({face.dip_deg:g} deg) is not steeper than the upper surface "
            f"({apparent:.3g} deg in the face's dip direction)"
        )
    if isinstance(water, Pressures) and water.crack_kPa and crack is None:
        raise ValueError("key 'water.crack_kPa': a pressure on the tension crack needs tension_crack")
