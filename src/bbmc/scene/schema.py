"""The scene format: a YAML description of a 2D block system (docs/scene-format.md), validated whole.

Units are in the key names (m, MPa, MPa/mm, kN, deg); `bbmc.dem.model` converts to SI. Every model
here is a strict, frozen `Section`: unknown keys, wrong types and out-of-range values are refused with
one line naming the key. Cross-references (a block's material, a rule's law, a monitor's block) are
checked when the model is built, before any step runs.
"""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import Annotated, Literal

from pydantic import AfterValidator, Field, model_validator

from bbmc.config import ConfigError, Section
from bbmc.geometry.polygons import MAX_BLOCKS
from bbmc.joint.inputs import FullJointInputs, ResidualAndScale, wall_not_stronger_than_rock
from bbmc.joint.model import BartonBandisJoint
from bbmc.rockmass.config import RockMassConfig, SetName, distinct_set_names
from bbmc.scene.fos_settings import StrengthReduction
from bbmc.support.config import Design, SupportElement

Pair = Annotated[list[float], Field(min_length=2, max_length=2)]
Names = Annotated[list[str], Field(min_length=2, max_length=2)]
Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Steps = Annotated[int, Field(ge=0)]
Dof = Literal["x", "y", "rotation"]
AfterSlip = Literal["zero", "keep"]  # keep: ductile (limit equilibrium's); zero: UDEC's Coulomb slip


def name_part(value: float) -> str:
    """A number as part of a scene's name (letters, digits, _ and - only): 0.15 -> 0p15, 5.5e+298 ->
    5p5e298 (a name made with the '+' of an exponent was refused, a traceback)."""
    return f"{value:g}".replace(".", "p").replace("+", "")


def _exactly_one(model: Section, keys: tuple[str, ...], what: str) -> None:
    given = [key for key in keys if getattr(model, key) is not None]
    if len(given) != 1:
        raise ValueError(f"give exactly one {what} of {', '.join(keys)}; got {', '.join(given) or 'none'}")


class Material(Section):
    density_kg_m3: Positive


class Rectangle(Section):
    x_m: float  # lower-left corner
    y_m: float
    width_m: Positive
    height_m: Positive


class BrickWall(Section):
    origin_m: Pair
    columns: Annotated[int, Field(ge=1)]
    rows: Annotated[int, Field(ge=1)]
    block_width_m: Positive
    block_height_m: Positive
    row_offset: Annotated[float, Field(ge=0, lt=1)] = 0.0

    @model_validator(mode="after")
    def _not_too_many(self) -> BrickWall:
        if self.columns * self.rows > MAX_BLOCKS:
            raise ValueError(
                f"columns x rows is {self.columns * self.rows:,} blocks, more than {MAX_BLOCKS:,}"
            )
        return self


class JointSet(Section):
    """A persistent set of parallel joints, as a geologist gives it; its joints' edges are labelled
    joint.<name> (contact rules select them with `edges`)."""

    name: SetName | None = None  # [J1, J2, ... in the order the sets are given]
    dip_deg: Annotated[float, Field(ge=0, le=90)]
    dip_direction_to_face_deg: Annotated[float, Field(ge=0, le=180)] = (
        0.0  # 0: out of the slope; 180: into it
    )
    spacing_m: Positive  # true spacing, normal to the joints
    offset_m: float = 0.0  # of the first joint from the toe, normal to the joints (0: one passes through it)

    @model_validator(mode="after")
    def _has_trace(self) -> JointSet:
        if self.dip_deg == 90 and self.dip_direction_to_face_deg == 90:
            raise ValueError("a vertical set striking across the face is parallel to the section: no trace")
        return self


class JointedSlope(Section):
    """A slope (free face towards -x, toe at the origin) cut into convex blocks by joint sets."""

    height_m: Positive
    face_angle_deg: Annotated[float, Field(gt=0, le=90)]
    crest_extent_m: NonNegative  # flat top behind the crest
    toe_extent_m: NonNegative  # flat ground in front of the toe
    depth_m: NonNegative  # below the toe (0: the model's base is at the toe's level)
    joint_sets: Annotated[list[JointSet], Field(min_length=1, max_length=4)]
    min_block_fraction: Annotated[float, Field(ge=0, lt=1)] = 0.02  # slivers below this x median are dropped
    fixed_boundaries: list[Literal["left", "right", "bottom"]] = Field(
        default_factory=lambda: ["right", "bottom"]
    )  # blocks with an edge on these sides of the model have every degree of freedom held

    @model_validator(mode="after")
    def _distinct_names(self) -> JointedSlope:
        distinct_set_names(self.set_names)
        return self

    @property
    def set_names(self) -> list[str]:
        """Each set's name: as given, else J<n> for the n-th set (J1 the first)."""
        return [s.name or f"J{n}" for n, s in enumerate(self.joint_sets, start=1)]

    @property
    def joint_labels(self) -> list[str]:
        """The label of each set's joints, joint.<name>: the labels the slope's edges can carry."""
        return [f"joint.{name}" for name in self.set_names]


class Velocity(Section):
    """A prescribed velocity for the degrees of freedom given (the others stay free)."""

    x_m_s: float | None = None
    y_m_s: float | None = None
    rotation_rad_s: float | None = None
    start_step: Steps = 0  # the velocity applies from this step; before it these dofs are held


class BlockEntry(Section):
    """One block (polygon_m or rectangle_m) or a family of blocks from a generator (brick_wall,
    jointed_slope, rock_mass)."""

    name: Annotated[str, Field(min_length=1, pattern=r"^[^.\s]+$")]
    material: str
    group: str | None = None  # contact rules and joint monitors select blocks by group [name]
    polygon_m: Annotated[list[Pair], Field(min_length=3)] | None = None
    edge_labels: list[str] | None = None  # polygon_m: one per edge, edge k from vertex k to k + 1
    rectangle_m: Rectangle | None = None
    brick_wall: BrickWall | None = None
    jointed_slope: JointedSlope | None = None
    rock_mass: RockMassConfig | None = None
    rotate_deg: float = 0.0  # counter-clockwise, about rotate_about_m [default: the centroid]
    rotate_about_m: Pair | None = None
    fix: list[Dof] = Field(default_factory=list)
    velocity: Velocity | None = None

    @model_validator(mode="after")
    def _one_shape(self) -> BlockEntry:
        _exactly_one(self, ("polygon_m", "rectangle_m", "brick_wall", "jointed_slope", "rock_mass"), "shape")
        return self


class ConstantLaw(Section):
    """Constant Mohr-Coulomb joint: stiffness, cohesion, friction, tension cut-off."""

    law: Literal["constant"]
    kn_MPa_per_mm: Positive
    ks_MPa_per_mm: Positive
    cohesion_MPa: NonNegative = 0.0
    friction_deg: Annotated[float, Field(ge=0, lt=90)]
    tensile_strength_MPa: NonNegative = 0.0
    after_slip: AfterSlip = "keep"
    breaks_into: str | None = None  # intact rock (a bridge): the joint law it becomes where it breaks


class BartonBandisStrength(ResidualAndScale, BartonBandisJoint):
    """Eq 9 envelope; its tangent at the sub-contact's sigma_n gives phi and c (eqs 13-15). Optionally,
    as the full joint: phi_r in place of phi_b (Barton & Choubey 1977) and JRC, JCS taken from the lab
    to the field length (Barton & Bandis 1982), the keys and checks of `bbmc.joint.inputs`."""

    phi_max_deg: Annotated[float, Field(gt=0, lt=90)] = 70.0
    tangent_coefficient: Positive | Literal["exact"] = "exact"  # eq 15 prints 0.016


class LinearStrength(Section):
    """tau = slope x + intercept: Table 1's fits of tau_p on sigma_n and tau_ult on tau_p (eq 4)."""

    slope: Positive
    intercept_MPa: float


class ConstantNormal(Section):
    law: Literal["constant"]
    kn_MPa_per_mm: Positive


class Eq8Normal(Section):
    law: Literal["eq8"]
    q_per_mm: Positive
    lg_e: Positive = 0.4342944819032518  # eq 6 prints 0.3434


class ConstantShear(Section):
    law: Literal["constant"]
    ks_MPa_per_mm: Positive


class HyperbolicShear(Section):
    """bandis: eq 3/4 as printed; hyperbolic: eq 2 (R_f = tau_p/tau_ult); corrected: eq 16."""

    law: Literal["bandis", "hyperbolic", "corrected"]
    kj_MPa_per_mm: Positive  # K_j: K_si at sigma_n = 1 MPa
    nj: float
    peak_strength: LinearStrength
    ultimate_strength: LinearStrength
    a: float = 0.0  # eq 16's correction f = a ln(tau/tau_p) + b (corrected only)
    b: float = 1.0


class SimplifiedShear(Section):
    """Eq 17: K_s = D K_j sigma_n^n_j (eq 18: D K_j = 0.1164 MPa/mm as printed)."""

    law: Literal["simplified"]
    kj_MPa_per_mm: Positive
    nj: float
    d: Positive = 1.0


class BartonBandisLaw(Section):
    """Strength and stiffness recomputed from each sub-contact's own stresses every update interval."""

    law: Literal["barton_bandis"]
    strength: BartonBandisStrength
    normal_stiffness: ConstantNormal | Eq8Normal = Field(discriminator="law")
    shear_stiffness: ConstantShear | HyperbolicShear | SimplifiedShear = Field(discriminator="law")
    stress_floor_MPa: Positive = 0.01  # stiffness laws are evaluated at max(sigma_n, floor)
    shear_stiffness_floor: Annotated[float, Field(ge=0, le=1)] = 0.01  # K_s >= floor K_si
    tensile_strength_MPa: NonNegative = 0.0
    after_slip: AfterSlip = "keep"


class BandisNormal(Section):
    """K_n from Bandis et al. (1983)'s closure hyperbola, its K_ni and V_m from JRC_0, JCS_0 and the
    initial aperture (given, or from the rock's sigma_c: a_j = JRC_0/5 (0.2 sigma_c/JCS_0 - 0.1))."""

    law: Literal["bandis"]
    aperture_mm: Positive | None = None
    sigma_c_MPa: Positive | None = None

    @model_validator(mode="after")
    def _one_source(self) -> BandisNormal:
        _exactly_one(self, ("aperture_mm", "sigma_c_MPa"), "initial aperture source")
        return self


class MobilizedLaw(FullJointInputs):
    """The full Barton-Bandis joint (Barton 1982; Barton & Bandis 1982; Bandis et al. 1983; Barton,
    Bandis & Bakhtar 1985): strength and dilation mobilized along each sub-contact's shear path, from
    zero through the peak to the residual; JRC and JCS scaled from the lab length to the field length.
    The joint's own keys and their checks are `bbmc.joint.inputs`'s, shared with `bbmc joint`."""

    law: Literal["barton_bandis_mobilized"]
    normal_stiffness: ConstantNormal | BandisNormal = Field(discriminator="law")
    shear_stiffness: ConstantShear
    stress_floor_MPa: Positive = 0.01  # the stiffness and the dilation are evaluated at >= this

    @model_validator(mode="after")
    def _rock_behind_the_wall(self) -> MobilizedLaw:
        sigma_c = getattr(self.normal_stiffness, "sigma_c_MPa", None)
        if sigma_c is not None:
            wall_not_stronger_than_rock(sigma_c, self.jcs0_MPa)
        return self


JointLaw = Annotated[ConstantLaw | BartonBandisLaw | MobilizedLaw, Field(discriminator="law")]


class ContactRule(Section):
    """Contacts between the two groups (either order), with a dip in the range, and/or on an edge whose
    label is `edges` or starts with `edges.` get `law`; `edges` must be a label the scene's edges can
    carry, or the part of one before a dot (checked when the model is built)."""

    law: str
    groups: Names | None = None
    dip_deg: Pair | None = None
    edges: str | None = None


ROCK_MASS_SUB_CONTACTS = 16  # the default sub-contacts per edge of a scene with a rock mass


class Contacts(Section):
    default_law: str
    rules: list[ContactRule] = Field(default_factory=list)
    sub_contacts_per_edge: Annotated[int, Field(ge=1, le=64)] = 4
    search_margin_m: Positive | None = None  # default: 2 % of the median block size
    interpenetration_limit: Annotated[float, Field(gt=0, lt=1)] = 0.05  # of the smaller block's size


class EdgeStress(Section):
    """Stress on one edge: sigma_n pushes on it (compression > 0), tau drags along it counter-clockwise."""

    block: str
    edge: Literal["up", "down", "left", "right"] | Annotated[int, Field(ge=0)]
    sigma_n_MPa: float = 0.0
    tau_MPa: float = 0.0
    ramp_steps: Steps = 0
    start_step: Steps = 0  # the load acts from this step on (ramped over ramp_steps from there)


class BlockForce(Section):
    block: str
    force_kN: Pair = Field(default_factory=lambda: [0.0, 0.0])  # total over the thickness, at the centroid
    moment_kN_m: float = 0.0
    ramp_steps: Steps = 0
    start_step: Steps = 0


class Loads(Section):
    edge_stresses: list[EdgeStress] = Field(default_factory=list)
    block_forces: list[BlockForce] = Field(default_factory=list)


class TimeStep(Section):
    """auto: safety x critical step (step_s, if given, is an upper limit); fixed: step_s, refused if
    above critical; density_scaling: step_s, inertial masses raised so it is safety x critical."""

    mode: Literal["auto", "fixed", "density_scaling"] = "auto"
    safety_factor: Annotated[float, Field(gt=0, le=1)] = 0.5
    step_s: Positive | None = None

    @model_validator(mode="after")
    def _step_given(self) -> TimeStep:
        if self.mode != "auto" and self.step_s is None:
            raise ValueError(f"time step mode '{self.mode}' needs step_s")
        return self


class Stop(Section):
    """Stop once the loads act in full (and prescribed velocities have started) and the unbalanced
    force ratio (max unbalanced force or moment / max applied force) is below
    `unbalanced_force_ratio`, or once a block that can move has moved further than `displacement_m`
    from where it started; whichever comes first; or once the run has lasted `time_s` of physical
    time; or, with `trend_window_steps`, once the trend of the motion over windows of that many steps
    says it is coming to rest or failing (`bbmc.dem.verdict`; needs displacement_m). Checked at record
    steps."""

    unbalanced_force_ratio: Positive | None = None
    displacement_m: Positive | None = None
    time_s: Positive | None = None
    trend_window_steps: Annotated[int, Field(ge=1)] | None = None

    @model_validator(mode="after")
    def _one_given(self) -> Stop:
        if self.unbalanced_force_ratio is None and self.displacement_m is None and self.time_s is None:
            raise ValueError("give unbalanced_force_ratio, displacement_m and/or time_s")
        if self.trend_window_steps is not None and self.displacement_m is None:
            raise ValueError("trend_window_steps needs displacement_m (the failure displacement)")
        return self


class Solver(Section):
    steps: Annotated[int, Field(ge=1)]
    damping: Annotated[float, Field(ge=0, lt=1)] = 0.8  # Cundall local damping; 0 for true dynamics
    time_step: TimeStep = TimeStep()
    update_interval_steps: Annotated[int, Field(ge=1)] = 50  # stress-dependent laws (the paper: 50)
    # ... and sooner once a sub-contact's sigma_n or tau moved by this fraction since its last evaluation
    law_update_stress_change: Annotated[float, Field(gt=0)] | None = None
    stop: Stop | None = None
    threads: Annotated[int, Field(ge=1)] | None = None  # numba threads of the cycle; None: every core


BLOCK_QUANTITIES = ("ux", "uy", "vx", "vy", "rotation")
JOINT_QUANTITIES = (
    "sigma_n", "tau", "kn", "ks", "cohesion", "friction", "us", "un", "dilation", "shear_path",
)  # fmt: skip
GLOBAL_QUANTITIES = ("kinetic_energy", "strain_energy", "potential_energy", "unbalanced_force_ratio")
Quantity = Literal[
    "ux", "uy", "vx", "vy", "rotation", "bolt_force",
    "sigma_n", "tau", "kn", "ks", "cohesion", "friction", "us", "un", "dilation", "shear_path",
    "kinetic_energy", "strain_energy", "potential_energy", "unbalanced_force_ratio",
]  # fmt: skip


class Monitor(Section):
    """A block (block, optional point_m), a joint (between two groups, or the sub-contact near_m), a
    support element (`bolt_force`: its largest axial force, kN per bolt) or the whole system."""

    name: Annotated[str, Field(min_length=1)]
    quantity: Quantity
    block: str | None = None
    point_m: Pair | None = None
    between: Names | None = None
    near_m: Pair | None = None
    support: str | None = None

    @model_validator(mode="after")
    def _target(self) -> Monitor:
        if (self.quantity == "bolt_force") != (self.support is not None):
            raise ValueError("give support (an element's name) for bolt_force, and only for it")
        if self.quantity == "bolt_force":
            if any(v is not None for v in (self.block, self.point_m, self.between, self.near_m)):
                raise ValueError("'bolt_force' is a support quantity: give support only")
            return self
        if self.quantity in BLOCK_QUANTITIES:
            if self.block is None or self.between is not None or self.near_m is not None:
                raise ValueError(f"'{self.quantity}' is a block quantity: give block (and point_m)")
            if self.point_m is not None and self.quantity not in ("ux", "uy"):
                raise ValueError(f"point_m applies to ux and uy only, not to '{self.quantity}'")
        elif self.quantity in JOINT_QUANTITIES:
            _exactly_one(self, ("between", "near_m"), f"joint for '{self.quantity}'")
            if self.block is not None or self.point_m is not None:
                raise ValueError(f"'{self.quantity}' is a joint quantity: give between or near_m")
        elif any(v is not None for v in (self.block, self.point_m, self.between, self.near_m)):
            raise ValueError(f"'{self.quantity}' is a system quantity: it takes no block or joint")
        return self


class Water(Section):
    """Joint water below a phreatic surface: p = unit weight x (height of the surface above the point),
    0 above it. It pushes on every block edge below the surface, both faces of a joint alike; the
    contact stresses (and so the joint laws) are the effective ones (`bbmc.dem.water`). The surface is
    given in model coordinates, or against a rock mass's profile: its crack's filling, or a height
    above the toe and a depth below the crest at the model's back edge (`bbmc.dem.model`)."""

    phreatic_surface_m: Annotated[list[Pair], Field(min_length=2)] | None = None  # x increasing
    tension_crack_fill_percent: Annotated[float, Field(ge=0, le=100)] | None = None  # a rock mass's crack
    height_above_toe_m: float | None = None  # a rock mass's water table at its toe ...
    depth_below_crest_m: float | None = None  # ... and at its back edge, below the crest's level
    unit_weight_kN_m3: Positive = 9.81

    @model_validator(mode="after")
    def _increasing(self) -> Water:
        if (self.height_above_toe_m is None) != (self.depth_below_crest_m is None):
            raise ValueError("height_above_toe_m and depth_below_crest_m go together: give both")
        _exactly_one(
            self, ("phreatic_surface_m", "tension_crack_fill_percent", "height_above_toe_m"), "water table"
        )
        if self.phreatic_surface_m is None:
            return self
        x = [point[0] for point in self.phreatic_surface_m]
        if any(b <= a for a, b in itertools.pairwise(x)):
            raise ValueError("phreatic_surface_m: the points' x must increase strictly")
        return self


class Seismic(Section):
    """Pseudo-static seismic load (as RocPlane's): a horizontal acceleration k_h g on every block."""

    horizontal_coefficient: Annotated[float, Field(ge=0, le=1)]  # k_h
    towards: Literal["-x", "+x"] = "-x"  # out of the slope (jointed_slope's face looks towards -x)


class Monitoring(Section):
    every_steps: Annotated[int, Field(ge=1)] = 100
    monitors: list[Monitor] = Field(default_factory=list)


def _file_name(name: str) -> str:
    """A scene's name names its results folder: any name a file system takes (`benched_f62.5`, spaces,
    letters of any language), refused only where it cannot be one folder's name: empty, "." or "..",
    or with a path separator (/ or \\) or a NUL character."""
    if name in {"", ".", ".."} or any(c in name for c in "/\\\0"):
        raise ValueError("not a folder's name: empty, '.', '..', or with '/', '\\' or a NUL character")
    return name


FileName = Annotated[str, AfterValidator(_file_name)]


class Scene(Section):
    dimension: Literal[2] = 2  # a 3D scene says 3 (`bbmc.scene.schema3d`)
    name: FileName | None = None  # [the file name]
    description: str = ""
    thickness_m: Positive = 1.0
    gravity_m_s2: Pair = Field(default_factory=lambda: [0.0, -9.81])
    materials: Annotated[dict[str, Material], Field(min_length=1)]
    blocks: Annotated[list[BlockEntry], Field(min_length=1)]
    joint_laws: Annotated[dict[str, JointLaw], Field(min_length=1)]
    contacts: Contacts
    loads: Loads = Loads()
    solver: Solver
    monitoring: Monitoring = Monitoring()
    water: Water | None = None
    seismic: Seismic | None = None
    fos: StrengthReduction = StrengthReduction()
    support: list[SupportElement] = Field(default_factory=list)  # bolts, anchors (docs/how-to/support.md)
    design: Design | None = None  # `bbmc fos`: the support that reaches a target FS
    figure_dpi: Annotated[int, Field(ge=50, le=600)] = 120

    @model_validator(mode="after")
    def _rock_mass_sub_contacts(self) -> Scene:
        """A scene with a rock mass cuts each contact into ROCK_MASS_SUB_CONTACTS shares unless it says
        otherwise: its brittle bridges break at their first failing share, whose peak stress grows with
        the count, and 4 shares left the FS of generated masses up to 5 % above the refined one
        (docs/how-to/solver-settings.md)."""
        given = "sub_contacts_per_edge" in self.contacts.model_fields_set
        if not given and any(entry.rock_mass is not None for entry in self.blocks):
            refined = self.contacts.model_copy(update={"sub_contacts_per_edge": ROCK_MASS_SUB_CONTACTS})
            object.__setattr__(self, "contacts", refined)  # a frozen section: set once, while validated
        return self


def scene_error(path: Path, key: str, message: str) -> ConfigError:
    """The one line of a fault in a scene: the file, the dotted key as written, what is wrong."""
    return ConfigError(f"{path}: key '{key}': {message}")
