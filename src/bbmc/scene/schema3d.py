"""The 3D scene format: a YAML description of a 3D block system (docs/reference/scene3d-format.md),
validated whole, as `bbmc.scene.schema` does for 2D. A scene is 3D by its top-level ``dimension: 3``.

Units are in the key names (m, MPa, MPa/mm, deg, m/s); `bbmc.dem3d.scene_model` converts to SI. The
keys a 2D scene has too are its models: `Material`, the run's `Stop`, the `fos:` section
(`bbmc.scene.fos_settings.StrengthReduction`), a block's name and the folder name. Axes: x east, y
north, z up (`bbmc.geometry.orientation`). Cross-references (a block's material, a rule's joint type, a
monitor's block) and the geometry (convexity, overlaps, a joint set that cuts nothing, a wedge that
cannot form) are checked when the model is built, before any step runs.
"""

from __future__ import annotations

import difflib
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import Field, field_validator, model_validator

from bbmc.config import ConfigError, Section, read_yaml
from bbmc.scene.fos_settings import StrengthReduction
from bbmc.scene.schema import AfterSlip, FileName, Material, NonNegative, Pair, Positive, Stop

Point = Annotated[list[float], Field(min_length=3, max_length=3)]
Name = Annotated[str, Field(min_length=1, pattern=r"^[^.\s]+$")]
FrictionDeg = Annotated[float, Field(ge=0, lt=90)]


class MohrCoulombJoint(Section):
    """Constant K_n, K_s, cohesion and friction (`bbmc.dem3d.joint_laws.MohrCoulomb`)."""

    law: Literal["mohr_coulomb"]
    kn_MPa_per_mm: Positive
    ks_MPa_per_mm: Positive
    friction_deg: FrictionDeg
    cohesion_MPa: NonNegative = 0.0
    after_slip: AfterSlip = "keep"
    pressure_kPa: NonNegative = 0.0  # a given uniform water pressure on the closed parts of its contacts


class BartonBandisJoint3D(Section):
    """Constant K_n, K_s and the tangent to the Barton-Bandis envelope at each sub-contact's sigma_n
    (`bbmc.dem3d.joint_laws.BartonBandis`; the keys of the 2D barton_bandis law's strength)."""

    law: Literal["barton_bandis"]
    kn_MPa_per_mm: Positive
    ks_MPa_per_mm: Positive
    jrc: Annotated[float, Field(ge=0, le=20)]
    jcs_MPa: Positive
    phi_b_deg: Annotated[float, Field(gt=0, lt=90)]
    phi_max_deg: Annotated[float, Field(gt=0, lt=90)] = 70.0
    tangent_coefficient: Positive | Literal["exact"] = "exact"  # eq 15 prints 0.016
    after_slip: AfterSlip = "keep"
    pressure_kPa: NonNegative = 0.0  # a given uniform water pressure on the closed parts of its contacts


JointType = Annotated[MohrCoulombJoint | BartonBandisJoint3D, Field(discriminator="law")]


class ContactRule3D(Section):
    """Contacts between a block of one group and a block of the other (either order) take `joint_type`."""

    groups: Annotated[list[str], Field(min_length=2, max_length=2)]
    joint_type: str


class Contacts3D(Section):
    default: str  # the joint type of every contact no rule names
    rules: list[ContactRule3D] = Field(default_factory=list)
    refine: Annotated[int, Field(ge=0, le=3)] = 1  # each face triangle split in four this many times


class Box(Section):
    lo_m: Point  # the corner of least x, y, z
    hi_m: Point  # the opposite corner


class Extrusion(Section):
    """A 2D polygon in the x-z section ((x, y)_2D -> (x, z)_3D) extruded along y from y_m[0] to y_m[1]."""

    polygon_m: Annotated[list[Pair], Field(min_length=3)]
    y_m: Pair


class Block3D(Section):
    """One block: `vertices_m` (its convex hull), `box` or `extrusion`; held, or moved at a prescribed
    velocity, or free."""

    name: Name
    material: str
    group: Name | None = None  # [the block's name]
    held: bool = False
    velocity_m_s: Point | None = None  # prescribed on all six dofs (no rotation)
    vertices_m: Annotated[list[Point], Field(min_length=4)] | None = None
    box: Box | None = None
    extrusion: Extrusion | None = None

    @model_validator(mode="after")
    def _one_shape(self) -> Block3D:
        given = [k for k in ("vertices_m", "box", "extrusion") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                f"give exactly one shape of vertices_m, box, extrusion; got {', '.join(given) or 'none'}"
            )
        if self.held and self.velocity_m_s is not None:
            raise ValueError("a block is held or moves at velocity_m_s, not both")
        return self


class Orientation(Section):
    """A plane's dip and dip direction [deg] (`bbmc wedge`'s keys)."""

    dip_deg: Annotated[float, Field(ge=0, le=90)]
    dip_direction_deg: Annotated[float, Field(ge=0, le=360)]


class Face(Orientation):
    """The slope face (`bbmc wedge`'s `face`): `overhanging` where it leans out over the toe."""

    dip_deg: Annotated[float, Field(gt=0, le=90)]
    overhanging: bool = False


class WedgePlane(Orientation):
    """One of the wedge's planes; `joint_type` its contact's [contacts.default]."""

    joint_type: str | None = None


class Wedge3D(Section):
    """A wedge of `bbmc wedge`'s geometry keys (docs/reference/wedge-command.md): the wedge block named
    `name` (group `name`) and the held rock of each plane, `name`.plane_1 and `name`.plane_2
    (`bbmc.slope.wedge.engine_scene`)."""

    name: Name = "wedge"
    material: str
    plane_1: WedgePlane
    plane_2: WedgePlane
    face: Face
    upper_surface: Orientation
    height_h1_m: Positive | None = None  # H1: crest point of plane 1's trace above the toe
    height_m: Positive | None = None  # H: top of the line of intersection above the toe

    @model_validator(mode="after")
    def _one_height(self) -> Wedge3D:
        if (self.height_h1_m is None) == (self.height_m is None):
            raise ValueError("give exactly one of height_h1_m, height_m")
        return self


class JointSet3D(Section):
    """A persistent set as 3DEC's `jset` cuts: planes n . x = n . origin + k spacing for every k; a
    contact across a face one of them made takes `joint_type`, where given."""

    name: Name | None = None  # [J1, J2, ... in order]
    dip_deg: Annotated[float, Field(ge=0, le=90)]
    dip_direction_deg: Annotated[float, Field(ge=0, le=360)]
    spacing_m: Positive
    origin_m: Point = Field(default_factory=lambda: [0.0, 0.0, 0.0])
    joint_type: str | None = None  # of a contact across a face this set cut [contacts' rules]


Side = Literal["bottom", "top", "-x", "+x", "-y", "+y"]


class RockMass3D(Section):
    """A box or an extruded slope profile cut by persistent joint sets into blocks named `name`.1,
    `name`.2, ... (group `name`); blocks with a face on a `held_sides` side of the uncut shape's
    bounding box are held."""

    name: Name = "rock_mass"
    material: str
    box: Box | None = None
    profile: Extrusion | None = None  # a convex slope profile in the x-z section, extruded along y
    joint_sets: Annotated[list[JointSet3D], Field(min_length=1, max_length=4)]
    min_block_fraction: Annotated[float, Field(ge=0, lt=1)] = 0.02  # slivers: x the median volume
    held_sides: list[Side] = Field(default_factory=lambda: ["bottom"])

    @model_validator(mode="after")
    def _one_shape(self) -> RockMass3D:
        if (self.box is None) == (self.profile is None):
            raise ValueError("give exactly one of box, profile")
        names = self.set_names
        if len(set(names)) != len(names):
            raise ValueError(f"joint set names must differ, got {', '.join(names)}")
        return self

    @property
    def set_names(self) -> list[str]:
        return [s.name or f"J{n}" for n, s in enumerate(self.joint_sets, start=1)]


class Water3D(Section):
    """A phreatic plane (`bbmc.dem3d.water.WaterTable`): water of `unit_weight_kN_m3` (the 2D scene's
    key) below a level table at `elevation_m`, or below the plane through `point_m` of `dip_deg` towards
    `dip_direction_deg` (`bbmc wedge`'s plane keys; dip below 90: the table is a surface z(x, y))."""

    elevation_m: float | None = None
    point_m: Point | None = None
    dip_deg: Annotated[float, Field(ge=0, lt=90)] | None = None
    dip_direction_deg: Annotated[float, Field(ge=0, le=360)] | None = None
    unit_weight_kN_m3: Positive = 9.81

    @model_validator(mode="after")
    def _one_plane(self) -> Water3D:
        tilted = (self.point_m, self.dip_deg, self.dip_direction_deg)
        if (self.elevation_m is None) == (self.point_m is None):
            raise ValueError("give exactly one of elevation_m (a level table), point_m (a tilted one)")
        if self.point_m is not None and any(v is None for v in tilted):
            raise ValueError("point_m, dip_deg and dip_direction_deg go together: give all three")
        if self.elevation_m is not None and any(v is not None for v in tilted):
            raise ValueError("elevation_m is a level table: no dip_deg or dip_direction_deg")
        return self


class Seismic3D(Section):
    """Pseudo-static seismic load: a horizontal acceleration k_h g on every block, towards an azimuth
    (clockwise from north, +y; 2D's `towards`)."""

    horizontal_coefficient: Annotated[float, Field(ge=0, le=1)]  # k_h
    towards_deg: Annotated[float, Field(ge=0, le=360)]


class Solver3D(Section):
    steps: Annotated[int, Field(ge=1)]
    damping: Annotated[float, Field(ge=0, lt=1)] = 0.8  # Cundall local damping; 0 for true dynamics
    safety_factor: Annotated[float, Field(gt=0, le=1)] = 0.5  # the time step, x the critical one
    stop: Stop | None = None
    threads: Annotated[int, Field(ge=1)] | None = None  # numba threads; None: every core

    @model_validator(mode="after")
    def _no_trend(self) -> Solver3D:
        if self.stop is not None and self.stop.trend_window_steps is not None:
            raise ValueError("stop.trend_window_steps: not yet in 3D")
        return self


BLOCK_QUANTITIES_3D = ("ux", "uy", "uz", "displacement", "vx", "vy", "vz", "speed", "rotation")
SYSTEM_QUANTITIES_3D = ("kinetic_energy", "unbalanced_force_ratio")


class Monitor3D(Section):
    """A block's quantity (block given) or the system's [m, m/s, deg, J, 1]."""

    name: Annotated[str, Field(min_length=1)]
    quantity: Literal[
        "ux", "uy", "uz", "displacement", "vx", "vy", "vz", "speed", "rotation",
        "kinetic_energy", "unbalanced_force_ratio",
    ]  # fmt: skip
    block: str | None = None

    @model_validator(mode="after")
    def _target(self) -> Monitor3D:
        if (self.quantity in BLOCK_QUANTITIES_3D) != (self.block is not None):
            kind = "block" if self.quantity in BLOCK_QUANTITIES_3D else "system"
            raise ValueError(
                f"'{self.quantity}' is a {kind} quantity: {'give' if kind == 'block' else 'no'} block"
            )
        return self


class Monitoring3D(Section):
    every_steps: Annotated[int, Field(ge=1)] = 100
    monitors: list[Monitor3D] = Field(default_factory=list)


def _not_yet(key: str, value: object) -> None:
    if value is not None:
        raise ValueError(f"{key}: not yet in 3D")


class Scene3D(Section):
    dimension: Literal[3]
    name: FileName | None = None  # [the file name]
    description: str = ""
    gravity_m_s2: Point = Field(default_factory=lambda: [0.0, 0.0, -9.81])
    materials: Annotated[dict[str, Material], Field(min_length=1)]
    joint_types: Annotated[dict[str, JointType], Field(min_length=1)]
    contacts: Contacts3D
    blocks: list[Block3D] = Field(default_factory=list)
    wedge: Wedge3D | None = None
    rock_mass: RockMass3D | None = None
    solver: Solver3D
    monitoring: Monitoring3D = Monitoring3D()
    seismic: Seismic3D | None = None
    water: Water3D | None = None
    support: Any = None  # refused: not yet in 3D
    fos: StrengthReduction = StrengthReduction()
    figure_dpi: Annotated[int, Field(ge=50, le=600)] = 120

    @field_validator("support")
    @classmethod
    def _not_yet_in_3d(cls, value: object) -> None:
        if value is not None:
            raise ValueError("not yet in 3D")

    @model_validator(mode="after")
    def _whole(self) -> Scene3D:
        _not_yet("fos.judge.region_m", self.fos.judge.region_m)
        if self.fos.barton_bandis_reduction != "envelope":
            raise ValueError("fos.barton_bandis_reduction: only 'envelope' exists in 3D so far")
        if not (self.blocks or self.wedge or self.rock_mass):
            raise ValueError("give blocks, wedge and/or rock_mass: a scene needs blocks")
        return self


def scene_dimension(path: Path) -> int:
    """A scene file's `dimension` (2 unless it says 3), read before the scene is validated, so the
    command validates it as a 2D or a 3D scene; ConfigError naming the key for any other value."""
    raw = read_yaml(path) if Path(path).is_file() else None
    if isinstance(raw, dict) and "dimension" not in raw:
        near = difflib.get_close_matches("dimension", [str(k) for k in raw], n=1, cutoff=0.8)
        if near:  # a misspelt `dimension: 3` would read the file as a 2D scene and name another key
            raise ConfigError(f"{path}: key '{near[0]}': unknown key (did you mean 'dimension'?)")
    value = raw.get("dimension", 2) if isinstance(raw, dict) else 2
    if value not in (2, 3) or isinstance(value, bool):
        raise ConfigError(f"{path}: key 'dimension': must be 2 or 3, got {value!r}")
    return int(value)
