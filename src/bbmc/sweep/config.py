"""The config of `bbmc sweep` (SWEEP.yaml): the base model, the variables and their distributions, the
sampling, and what each sample records. Units are in the key names, as everywhere in bbmc."""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, model_validator

from bbmc.config import InputFile, Section
from bbmc.kinematics.config import FaceSection, Friction, LimitsSection, SetOrientationSection
from bbmc.slope import toppling
from bbmc.slope.wedge import config as wedge_keys

Positive = Annotated[float, Field(gt=0)]
Angle = Annotated[float, Field(gt=0, lt=90)]


class MohrCoulombPlane(Section):
    """c and phi, the friction given as an angle or as its tangent (tan_friction: a friction
    coefficient, whose normal distribution makes a cohesionless dry block's FS exactly normal)."""

    law: Literal["mohr_coulomb"]
    cohesion_kPa: Annotated[float, Field(ge=0)] = 0.0
    friction_deg: Angle | None = None
    tan_friction: Positive | None = None

    @model_validator(mode="after")
    def _one_friction(self) -> MohrCoulombPlane:
        if (self.friction_deg is None) == (self.tan_friction is None):
            raise ValueError("give exactly one of friction_deg and tan_friction")
        return self


class BartonBandisPlane(Section):
    law: Literal["barton_bandis"]
    jrc: Annotated[float, Field(ge=0, le=20)]
    jcs_MPa: Positive
    phi_b_deg: Angle
    phi_max_deg: Angle = 70.0


class PlanarSupport(Section):
    """A support force per metre run on the planar block (`bbmc.slope.planar.Support`): its angle from
    the plane's up-dip direction towards the plane (a bolt plunging psi_T below the horizontal: plane_deg
    + psi_T), counted in RocPlane's active or passive form."""

    force_kN_per_m: Annotated[float, Field(ge=0)]
    angle_deg: Annotated[float, Field(ge=-180, le=180)]
    form: Literal["active", "passive"] = "active"


class Planar(Section):
    """Hoek & Bray's planar failure with a tension crack (`bbmc.slope.planar`), one sample per set of
    parameters (the whole batch in one vectorised call)."""

    kind: Literal["planar"]
    height_m: Positive
    face_deg: Angle
    plane_deg: Angle
    crack_depth_m: Annotated[float, Field(ge=0)] = 0.0  # z: the crack's foot below the crest (0: none)
    water_fill: Annotated[float, Field(ge=0, le=1)] = 0.0  # z_w / z
    unit_weight_kN_m3: Positive = 26.0
    seismic_coefficient: Annotated[float, Field(ge=0, le=1)] = 0.0
    strength: MohrCoulombPlane | BartonBandisPlane = Field(discriminator="law")
    support: PlanarSupport | None = None


class TopplingSupport(Section):
    """A support force per metre run on one block of the toppling system (`bbmc.slope.toppling.
    BlockSupport`, RocTopple's): on its downhill face at height_m above its base, at angle_deg from the
    base's up-dip direction towards the base (a horizontal force: the base dip); not reduced with the
    friction. Or placed by level_m, its vertical height above the toe on the slope face, as RocTopple
    places line loads (`toppling.face_support`: the block and the point from the geometry)."""

    block: Annotated[int, Field(ge=1)] = 1  # 1: the toe block
    force_kN_per_m: Annotated[float, Field(ge=0)]
    angle_deg: Annotated[float, Field(ge=-180, le=180)]
    height_m: Annotated[float, Field(ge=0)] = 0.0
    level_m: Annotated[float, Field(ge=0)] | None = None


class Toppling(Section):
    """Goodman & Bray's toppling of a regular block system (`bbmc.slope.toppling.regular_system`): FS by
    tan phi reduction, one friction angle on bases and sides unless side_friction_deg is given."""

    kind: Literal["toppling"]
    width_m: Positive
    base_dip_deg: Angle
    crest_block: Annotated[int, Field(ge=1)]
    a1_m: float
    a2_m: float
    b_m: float
    friction_deg: Angle
    side_friction_deg: Angle | None = None
    # with a support or water only (without, the FS does not depend on it): density x g if a density is
    # given, else unit_weight_kN_m3, else 26 kN/m^3
    density_kg_m3: Positive | None = None
    unit_weight_kN_m3: Positive | None = None
    water_level_m: float | None = None  # a horizontal phreatic line this high above the toe (none: dry)
    support: TopplingSupport | None = None

    @model_validator(mode="after")
    def _forms_a_system(self) -> Toppling:
        system = toppling.regular_system(
            self.width_m, math.radians(self.base_dip_deg), self.crest_block, self.a1_m, self.a2_m, self.b_m
        )
        if self.density_kg_m3 is not None and self.unit_weight_kN_m3 is not None:
            raise ValueError("give density_kg_m3 or unit_weight_kN_m3, not both")
        if self.support is not None and self.support.block > system.n_blocks:
            raise ValueError(
                f"support.block: the system has blocks 1 to {system.n_blocks}, not {self.support.block}"
            )
        return self


class SceneBase(Section):
    """A block scene: its factor of safety by strength reduction (`scene_fos`), or a monitor's value at
    the end of a `bbmc run` (`scene_run`). The scene is a scene file (docs/scene-format.md), or the
    paper's slope as `bbmc slope` builds it from its config (`slope_config`, `joint_model`) with the
    strength-reduction settings of that config's `factor_of_safety`."""

    kind: Literal["scene_fos", "scene_run"]
    scene: InputFile | None = None
    slope_config: InputFile | None = None
    joint_model: Literal["constant", "barton_bandis"] | None = None
    monitor: str | None = None  # scene_run: the monitor's column in history.csv (e.g. slider_x_mm)

    @model_validator(mode="after")
    def _source(self) -> SceneBase:
        if (self.scene is None) == (self.slope_config is None):
            raise ValueError("give exactly one of scene and slope_config")
        if (self.slope_config is None) != (self.joint_model is None):
            raise ValueError("slope_config goes with joint_model (constant or barton_bandis)")
        if (self.kind == "scene_run") != (self.monitor is not None):
            raise ValueError("a scene_run base needs `monitor` (a history.csv column); scene_fos takes none")
        return self


class Kinematics(Section):
    """Probabilistic kinematics (`bbmc.sweep.kinematic_model`): per sample, the probability that each
    mode is feasible for the face, from `orientation_draws` Fisher draws of each set (seeded by `seed`
    and the sample's number). Any number in it can be varied: friction_deg, face.dip_deg,
    sets.J1.fisher_k, ..."""

    kind: Literal["kinematics"]
    face: FaceSection
    friction_deg: Friction
    sets: dict[str, SetOrientationSection] = Field(min_length=1)
    lateral_limits: LimitsSection = Field(default_factory=LimitsSection)
    orientation_draws: Annotated[int, Field(ge=1, le=10_000_000)] = 10_000
    seed: Annotated[int, Field(ge=0)] = 0


class WedgePlane(wedge_keys.JointPlane):
    """A wedge's joint plane (`bbmc.sweep.wedge_model`) as `bbmc wedge` takes it (its mean dip and dip
    direction [deg] and `strength`: Mohr-Coulomb or Barton-Bandis, `bbmc.slope.wedge.config`), and
    Fisher's K of its poles about the mean (none: the plane as given, or as a study's variables draw its
    dip and dip direction)."""

    fisher_k: Positive | None = None

    @model_validator(mode="after")
    def _no_size_limit(self) -> WedgePlane:
        if self.limits_size():
            raise ValueError(
                "key 'trace_length_m, persistence_m': a study's wedges are not scaled to size limits "
                "(bbmc wedge takes them; the study's fast path does not)"
            )
        return self


class Wedge(Section):
    """A wedge of two joint planes on a slope face under an upper surface (`bbmc.slope.wedge`), one
    wedge per sample, in `bbmc wedge`'s keys (`bbmc.slope.wedge.config`): the planes and their strength,
    the face and the upper surface, H1 (`height_h1_m`) or H (`height_m`), a tension crack, water, seismic,
    external forces and bolts; every number of them can be varied. The batch goes through the compiled
    fast path, or with a tension crack through the full geometry. Planes with `fisher_k` are drawn about
    their means from each sample's own uniforms (seeded by `seed` and the sample's number)."""

    kind: Literal["wedge"]
    plane_1: WedgePlane
    plane_2: WedgePlane
    face: wedge_keys.Face
    upper_surface: wedge_keys.Orientation
    height_h1_m: Positive | None = None
    height_m: Positive | None = None
    tension_crack: wedge_keys.Crack | None = None
    unit_weight_kN_m3: Positive  # required, as `bbmc wedge` requires it
    water: wedge_keys.Water = Field(default_factory=lambda: wedge_keys.NoWater(model="dry"))
    seismic: wedge_keys.SeismicSection | None = None
    forces: list[wedge_keys.ForceSection] = Field(default_factory=list)
    bolts: list[wedge_keys.BoltSection] = Field(default_factory=list)
    seed: Annotated[int, Field(ge=0)] = 0

    @model_validator(mode="after")
    def _slope(self) -> Wedge:
        heights = {"height_h1_m": self.height_h1_m, "height_m": self.height_m}
        wedge_keys.check_slope(self.face, self.upper_surface, heights, self.water, self.tension_crack)
        return self

    @property
    def scattered(self) -> bool:
        """Whether a plane's orientation is drawn by Fisher's K (each sample then a wedge of its own)."""
        return self.plane_1.fisher_k is not None or self.plane_2.fisher_k is not None


class Variable(Section):
    """A varying input by its dotted path in the base (e.g. strength.friction_deg, or
    joint_laws.joint.friction_deg in a scene; list entries by their index) and its distribution:
    normal (mean, std), lognormal (mean, std of the variable), uniform (min, max), triangular (min,
    mode, max), truncated_normal (mean, std, min, max), or realization (no parameters: a seed per sample,
    for a whole-number key such as a rock mass's seed). `truncate` (default true): the distribution is
    truncated to the range the key accepts (a cohesion >= 0, a friction angle in [0, 90) deg:
    `bbmc.sweep.ranges`), renormalised; false keeps the whole distribution, and a sample drawn outside
    the range is counted as impossible and not run. `geometry` (default: true for a realization, false
    otherwise) puts the variable in the geometry group of a crossed design (`Sampling.realizations`):
    drawn once per realization, with its seed (a set's persistence moves every trace: a different
    rock mass)."""

    path: Annotated[str, Field(min_length=1)]
    distribution: Literal["normal", "lognormal", "uniform", "triangular", "truncated_normal", "realization"]
    mean: float | None = None
    std: float | None = None
    min: float | None = None
    max: float | None = None
    mode: float | None = None
    truncate: bool = True
    geometry: bool | None = None

    @property
    def is_geometry(self) -> bool:
        """Whether the variable is drawn once per realization in a crossed design."""
        return self.distribution == "realization" if self.geometry is None else self.geometry

    def parameters(self) -> dict[str, float]:
        """The distribution's parameters as given (`bbmc.sweep.design.marginal` checks them)."""
        names = {
            "normal": ("mean", "std"),
            "lognormal": ("mean", "std"),
            "uniform": ("min", "max"),
            "triangular": ("min", "mode", "max"),
            "truncated_normal": ("mean", "std", "min", "max"),
            "realization": (),
        }[self.distribution]
        return {name: getattr(self, name) for name in names}

    @model_validator(mode="after")
    def _given(self) -> Variable:
        names = {"mean", "std", "min", "max", "mode"}
        needed = set(self.parameters())
        missing = sorted(n for n in needed if getattr(self, n) is None)
        extra = sorted(n for n in names - needed if getattr(self, n) is not None)
        if missing:
            raise ValueError(f"a {self.distribution} distribution needs {', '.join(missing)}")
        if extra:
            raise ValueError(f"a {self.distribution} distribution takes no {', '.join(extra)}")
        if self.distribution == "realization" and self.geometry is False:
            raise ValueError("a realization is the geometry: it takes no `geometry: false`")
        return self


class GridAxis(Section):
    path: Annotated[str, Field(min_length=1)]
    values: Annotated[list[float], Field(min_length=1)]


class Correlation(Section):
    between: Annotated[list[str], Field(min_length=2, max_length=2)]
    rho: Annotated[float, Field(gt=-1, lt=1)]


class Sampling(Section):
    """monte_carlo, latin_hypercube, sobol (scrambled; samples a power of 2), saltelli (SALib's design
    for Sobol indices: samples x (variables + 2) runs), or grid (the cartesian product of `grid`).
    `realizations` n crosses a random design (`bbmc.sweep.design.crossed_table`): n draws of the
    geometry variables, each paired with the same `samples` m draws of the others, n x m runs; with a
    grid, it runs every grid point with the same n draws of the variables
    (`bbmc.sweep.design.grid_realizations_table`), n x (grid points) runs."""

    method: Literal["monte_carlo", "latin_hypercube", "sobol", "saltelli", "grid"]
    samples: Annotated[int, Field(ge=1, le=10_000_000)] | None = None
    seed: Annotated[int, Field(ge=0)] = 0
    realizations: Annotated[int, Field(ge=2, le=100_000)] | None = None


class Config(Section):
    name: Annotated[str, Field(pattern=r"^[A-Za-z0-9_\-]+$")]
    base: Planar | Toppling | SceneBase | Kinematics | Wedge = Field(discriminator="kind")
    variables: list[Variable] = Field(default_factory=list)
    grid: list[GridAxis] = Field(default_factory=list)
    correlation: Correlation | None = None
    sampling: Sampling
    batch_size: Annotated[int, Field(ge=1, le=1_000_000)] = 100  # samples per task
    figure_dpi: Annotated[int, Field(ge=50, le=600)] = 120

    @model_validator(mode="after")
    def _design(self) -> Config:
        if self.sampling.method == "grid":
            self._grid()
        else:
            if not self.variables or self.grid:
                raise ValueError(f"sampling.method {self.sampling.method} takes `variables` and no `grid`")
            if self.sampling.samples is None:
                raise ValueError(f"sampling.samples is needed for {self.sampling.method}")
        paths = [v.path for v in self.variables] + [a.path for a in self.grid]
        if len(set(paths)) != len(paths):
            raise ValueError("a path is given twice")
        if self.correlation is not None and not set(self.correlation.between) <= {
            v.path for v in self.variables
        }:
            raise ValueError("correlation.between must name two of the variables' paths")
        if self.sampling.method != "grid" and self.sampling.realizations is not None:
            self._crossed()
        elif any(v.geometry is not None for v in self.variables) and self.sampling.method == "grid":
            raise ValueError("a grid study draws every variable once per realization: it takes no `geometry`")
        elif any(v.geometry for v in self.variables):
            raise ValueError("`geometry: true` groups a variable in a crossed design: give realizations")
        return self

    def _grid(self) -> None:
        """A grid study takes `grid` axes, and `variables` only with `realizations` (each drawn once per
        realization, the same draws at every grid point); it samples no `samples`."""
        if not self.grid:
            raise ValueError("sampling.method grid needs `grid` axes")
        if self.sampling.samples is not None:
            raise ValueError(
                "sampling.samples is not used by a grid (its samples are the grid points x realizations): "
                "remove it"
            )
        if self.variables and self.sampling.realizations is None:
            raise ValueError(
                "a grid study takes `variables` only with sampling.realizations (each drawn once per "
                "realization, e.g. the rock mass's seed)"
            )
        if self.sampling.realizations is not None and not self.variables:
            raise ValueError(
                "sampling.realizations in a grid study draws the `variables` once per realization: give one "
                "(e.g. {path: blocks.0.rock_mass.seed, distribution: realization})"
            )

    def _crossed(self) -> None:
        """A crossed design needs a random design, at least 2 samples per realization, a geometry and
        another variable, and no correlation reaching into the geometry."""
        if self.sampling.method not in ("monte_carlo", "latin_hypercube", "sobol"):
            raise ValueError(f"sampling.realizations crosses a random design, not {self.sampling.method}")
        if self.sampling.samples < 2:
            raise ValueError("sampling.realizations needs samples >= 2 (draws of the other inputs)")
        geometry = {v.path for v in self.variables if v.is_geometry}
        if not geometry or len(geometry) == len(self.variables):
            raise ValueError(
                "sampling.realizations needs a geometry variable (a realization, or `geometry: true`) and "
                "another one"
            )
        if self.correlation is not None and set(self.correlation.between) & geometry:
            raise ValueError("a crossed design correlates none of its geometry variables")
