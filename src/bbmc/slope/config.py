"""The config of the paper's jointed limestone slope (`bbmc slope`, configs/slope.yaml) and Table 4,
read from the data files it names (`load_table4`); `load_paper_slope` reads both, for every user of the
paper's slope (the sweep's base, the benchmarks)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

from pydantic import Field, model_validator

from bbmc import paper_tables
from bbmc.config import InputFile, Section, load_config
from bbmc.scene.fos_settings import StrengthReduction
from bbmc.scene.schema import JointedSlope
from bbmc.slope import model as sm

Dip = Annotated[float, Field(gt=0, lt=90)]  # of the bedding [deg]


class Inputs(Section):
    table4_rock_mass: InputFile
    table4_joints_constant: InputFile
    table4_joints_nonlinear: InputFile
    equation_constants: InputFile


class Claims(Section):
    """Thresholds that turn a measure into a yes or no; stated in claims.csv beside each verdict."""

    alike_fraction: float = Field(gt=0, lt=1)  # rates within this fraction of each other are alike
    separation_mm: float = Field(gt=0)  # neighbours drawn apart by more than this have separated
    quadratic_r2: float = Field(gt=0, le=1)  # R^2 of a quadratic fit at least this
    onset_displacement_mm: float = Field(gt=0)  # the slide has started once block 2 moved this far


class LimitEquilibrium(Section):
    block_length_m: float = Field(gt=0)
    block_thickness_m: float = Field(gt=0)
    dips_deg: list[Dip] = Field(min_length=2)  # the sweep drawn in fs_vs_dip.png
    tolerance_deg: float = Field(gt=0)  # bisection of the engine's critical dip
    agreement_deg: dict[sm.JointModel, float]  # stated agreement, engine vs limit equilibrium
    max_steps: int = Field(ge=1)
    ramp_steps: int = Field(ge=0)  # the block's weight is ramped on over these steps
    equilibrium_ratio: float = Field(gt=0)
    slide_mm: float = Field(gt=0)


class Sensitivity(Section):
    dips_deg: list[Dip] = Field(min_length=1)


class FactorOfSafety(StrengthReduction):
    """Strength reduction on the slope's scenes (`bbmc fos`'s settings) and the step budget of the
    equilibrium every trial starts from."""

    max_steps: int = Field(ge=1)


class Residual(Section):
    """The slope with the full Barton-Bandis joint (residual strength after slip) against the peak-only
    joint (`slope.safety.residual_comparison`); the paper gives no r/R, so phi_r is a list to try."""

    phi_r_deg: list[Annotated[float, Field(gt=0, lt=90)]] = Field(min_length=1)  # each <= Table 4's phi_b
    lab_length_m: float = Field(gt=0)  # Table 4's JRC and JCS are taken at this length
    field_length_m: float = Field(gt=0)  # the joints' length in the slope
    update_interval_steps: int = Field(ge=1)


class Config(Section):
    data: Inputs
    slope: JointedSlope
    constant: sm.ConstantJoint
    barton_bandis: sm.BartonBandisOptions
    run: sm.Run
    snapshots: list[float] = Field(min_length=1, max_length=6)  # fractions of duration_s (Fig 8)
    claims: Claims
    limit_equilibrium: LimitEquilibrium
    sensitivity: Sensitivity
    factor_of_safety: FactorOfSafety
    residual: Residual
    animation_frames: int = Field(ge=0, le=200)  # 0: no GIF
    vtk_every_records: int | None = Field(default=None, ge=1)  # vtk/<model>/ for ParaView [default: none]
    figure_dpi: int = Field(ge=50, le=600)

    @model_validator(mode="after")
    def _checks(self) -> Config:
        if any(not 0 < f <= 1 for f in self.snapshots):
            raise ValueError("snapshots are fractions of run.duration_s, each in (0, 1]")
        if self.slope.joint_sets[0].offset_m != 0:
            raise ValueError(
                "slope.joint_sets.0 is the bedding: its offset_m must be 0 (the sliding plane "
                "through the toe)"
            )
        if set(self.limit_equilibrium.agreement_deg) != set(sm.JOINT_MODELS):
            raise ValueError(f"limit_equilibrium.agreement_deg needs {', '.join(sm.JOINT_MODELS)}")
        return self


def load_paper_slope(path: str | Path) -> tuple[Config, sm.Table4]:
    """The slope config at `path`, validated (a `ConfigError` naming the file and key otherwise), and the
    Table 4 read from the data files it names."""
    config = load_config(path, Config)
    return config, load_table4(config.data)


def load_table4(data: Inputs) -> sm.Table4:
    """Table 4 (rock mass, constant and nonlinear joints) and the printed lg e, from the data files."""
    rock = paper_tables.read("table4_rock_mass", data.table4_rock_mass, ["density_kg_per_m3"])
    constant = paper_tables.read("table4_joints_constant", data.table4_joints_constant)
    nonlinear = paper_tables.read("table4_joints_nonlinear", data.table4_joints_nonlinear)
    constants = paper_tables.printed_constants(
        paper_tables.read("equation_constants", data.equation_constants)
    )
    return sm.Table4(
        density_kg_m3=float(rock["density_kg_per_m3"].iloc[0]),
        constant={k: float(v) for k, v in constant.iloc[0].items()},
        nonlinear={k: float(v) for k, v in nonlinear.iloc[0].items()},
        printed_lg_e=constants["eq6.lg_e"],
    )
