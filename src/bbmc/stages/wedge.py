"""`bbmc wedge`: a rock wedge's limit equilibrium (Hoek & Bray 1981, ch. 8; Swedge): one wedge of two
joint planes against a slope face, the bolts it needs for a target FS, and the combination analysis of
every pair of joint sets.

The config's sections (`bbmc.slope.wedge.config`) are validated whole before any work; a deterministic
wedge that cannot form is refused in one line naming its key and the reason (the combination table
gives such a pair a row with its reason instead). Domain code: `bbmc.slope.wedge` (cases,
combinations, bolting); tables: `bbmc.outputs.wedge_tables`. Writes wedge.csv, design.csv and
combinations.csv, each where the config asks for it, into results/wedge/<name>/.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import numpy as np
from matplotlib.figure import Figure
from pydantic import Field, model_validator

from bbmc import units
from bbmc.config import ConfigKeyError, Section
from bbmc.io import StageResult
from bbmc.outputs import wedge_tables
from bbmc.slope.wedge import config as keys
from bbmc.slope.wedge.bolting import BRACKET_WEIGHTS, BoltDesign, design_bolts
from bbmc.slope.wedge.cases import Plane, WedgeCase, WedgeSetting, analyse_case
from bbmc.slope.wedge.combinations import Combination, combination_table
from bbmc.slope.wedge.geometry import WedgeReason
from bbmc.slope.wedge.support import support_resultants

NAME = "wedge"

# The key at fault where the deterministic wedge does not form, by reason.
REASON_KEYS = {
    WedgeReason.SLOPE_NOT_CONVEX: "face",
    WedgeReason.PARALLEL_PLANES: "plane_2",
    WedgeReason.TRACE_MISSES_CREST: "plane_1, plane_2",
    WedgeReason.NOT_DAYLIGHTING: "plane_1, plane_2",
    WedgeReason.NOT_OUTCROPPING: "plane_1, plane_2",
    WedgeReason.HEIGHT_BELOW_TOE: "height_h1_m, height_m",
    WedgeReason.CRACK_OUTSIDE: "tension_crack",
}


class Combinations(Section):
    """Joint sets by name (mean plane and strength) whose every pair is analysed, an optional basal plane
    analysed with each set, and the FS below which a wedge is critical."""

    sets: dict[str, keys.JointPlane] = Field(min_length=1)
    basal_plane: keys.JointPlane | None = None
    critical_fs: keys.Positive = 1.0

    @model_validator(mode="after")
    def _pairs(self) -> Combinations:
        if len(self.sets) + (self.basal_plane is not None) < 2:
            raise ValueError("give at least two sets, or a set and a basal plane: a wedge needs two planes")
        if self.basal_plane is not None and "basal" in self.sets:
            raise ValueError("a set named 'basal': the name is the basal plane's; rename the set")
        return self


class Config(Section):
    """One wedge (plane_1, plane_2), or the combinations of joint sets, or both, against one slope;
    `name`: the results folder's (default: the config file's stem)."""

    name: Annotated[str, Field(pattern=r"^[A-Za-z0-9_\-]+$")] | None = None
    plane_1: keys.JointPlane | None = None
    plane_2: keys.JointPlane | None = None
    face: keys.Face
    upper_surface: keys.Orientation
    height_h1_m: keys.Positive | None = None  # H1: crest point of plane 1's trace above the toe
    height_m: keys.Positive | None = None  # H: top of the line of intersection above the toe
    tension_crack: keys.Crack | None = None
    unit_weight_kN_m3: keys.Positive
    water: keys.Water = Field(default_factory=lambda: keys.NoWater(model="dry"))
    seismic: keys.SeismicSection | None = None
    forces: list[keys.ForceSection] = Field(default_factory=list)
    bolts: list[keys.BoltSection] = Field(default_factory=list)
    shotcrete: keys.Shotcrete | None = None
    design: keys.Design | None = None
    combinations: Combinations | None = None

    @model_validator(mode="after")
    def _whole(self) -> Config:
        heights = {"height_h1_m": self.height_h1_m, "height_m": self.height_m}
        keys.check_slope(self.face, self.upper_surface, heights, self.water, self.tension_crack)
        if (self.plane_1 is None) != (self.plane_2 is None):
            raise ValueError("key 'plane_1, plane_2': give both planes of the wedge, or neither")
        if self.plane_1 is None and self.combinations is None:
            raise ValueError(
                "key 'plane_1, plane_2, combinations': give a wedge's two planes or combinations"
            )
        if self.design is not None and self.plane_1 is None:
            raise ValueError("key 'design': designs the bolts of the wedge of plane_1 and plane_2: give them")
        return self


@dataclass(frozen=True)
class WedgeRun:
    """What a run found, for its tables and figures: the setting, the deterministic wedge's case and its
    planes (None without them), the bolt designs and the combination table."""

    setting: WedgeSetting
    case: WedgeCase | None
    planes: tuple[Plane, Plane] | None
    designs: list[BoltDesign]
    combinations: list[Combination] | None


def output_name(config: Config, config_path: Path) -> str:
    """The results folder's name: the config's `name`, else its file's stem."""
    return config.name or config_path.stem


def plane(section: keys.JointPlane) -> Plane:
    """The analysis' plane of a config's joint plane."""
    return Plane(*section.radians(), section.plane_strength)


def setting(config: Config) -> WedgeSetting:
    """Everything of the config but its planes, in SI."""
    external = sum((f.vector() for f in config.forces), np.zeros(3))
    active, passive = support_resultants([b.bolt() for b in config.bolts])
    water = config.water
    shotcrete = config.shotcrete
    return WedgeSetting(
        face=config.face.radians(),
        upper=config.upper_surface.radians(),
        unit_weight=config.unit_weight_kN_m3 * keys.KN,
        height_h1=config.height_h1_m,
        height_h=config.height_m,
        overhanging_face=config.face.overhanging,
        crack=config.tension_crack.crack() if config.tension_crack is not None else None,
        water=water.water(),
        water_unit_weight=float(keys.water_unit_weight(water)),
        seismic=config.seismic.seismic() if config.seismic is not None else None,
        forces=external + active,
        passive=passive,
        shotcrete=(shotcrete.thickness_m, shotcrete.shear_strength_kPa * units.kPa) if shotcrete else None,
    )


def _wedge(config: Config, slope: WedgeSetting) -> tuple[WedgeCase, tuple[Plane, Plane]]:
    planes = (plane(config.plane_1), plane(config.plane_2))
    case = analyse_case(slope, *planes)
    if case.analysis is None:
        reason = WedgeReason(int(case.geometry.reason))
        raise ConfigKeyError(REASON_KEYS[reason], f"no wedge: {case.reason}")
    return case, planes


def _designs(config: Config, slope: WedgeSetting, case: WedgeCase, planes) -> list[BoltDesign]:
    d = config.design
    direction = None
    if isinstance(d.bolt, keys.BoltDirection):
        direction = (math.radians(d.bolt.trend_deg), math.radians(d.bolt.plunge_deg))
    return [design_bolts(case, slope, planes, d.target_fs, d.capacity_kN * keys.KN, d.form, direction)]


def figures(run: WedgeRun) -> dict[str, Figure]:
    """The figures of a run: the hook where the wedge's figures (3D view, stereonet, forces) join the
    stage. None yet: they come with the figures module of issue 35 (the i35-fig branch)."""
    return {}


def run(config: Config, progress: Callable[[str], None] = lambda _: None) -> StageResult:
    """Analyse the wedge and design its bolts, and the combinations, as the config asks."""
    slope = setting(config)
    case = planes = None
    designs: list[BoltDesign] = []
    tables = {}
    if config.plane_1 is not None:
        case, planes = _wedge(config, slope)
        tables["wedge"] = wedge_tables.wedge_table(case)
        if config.design is not None:
            progress("designing the bolts")
            designs = _designs(config, slope, case, planes)
            tables["design"] = wedge_tables.design_frame(designs)
    combos = None
    if config.combinations is not None:
        c = config.combinations
        progress(f"the wedges of {len(c.sets)} sets' pairs")
        basal = plane(c.basal_plane) if c.basal_plane is not None else None
        sets = {name: plane(section) for name, section in c.sets.items()}
        combos = combination_table(slope, sets, basal, c.critical_fs)
        tables["combinations"] = wedge_tables.combinations_frame(combos)
    found = WedgeRun(slope, case, planes, designs, combos)
    return StageResult(tables=tables, figures=figures(found))


def summary_lines(result: StageResult) -> list[str]:
    """What the command prints: the wedge's mode and FS, each design, and the critical wedges."""
    lines = []
    if "wedge" in result.tables:
        w = result.tables["wedge"].iloc[0]
        lines.append(
            f"wedge: FS {w.factor_of_safety:.4f}, {w['mode']}, weight {w.weight_kN:,.1f} kN, "
            f"line of intersection {w.line_plunge_deg:.1f}/{w.line_trend_deg:03.0f}"
        )
    designs = result.tables.get("design")
    for _, d in designs.iterrows() if designs is not None else ():
        where = f"trend {d.trend_deg:03.0f}, plunge {d.plunge_deg:.1f}"
        if np.isnan(d.total_force_kN):
            lines.append(
                f"design ({d.bolt}, {d.form}): FS {d.target_fs:g} not reached along {where} "
                f"with up to {BRACKET_WEIGHTS:g} times the wedge's weight"
            )
            continue
        lines.append(
            f"design ({d.bolt}, {d.form}): {d.total_force_kN:,.1f} kN drilled along {where}: "
            f"{d['count']:.0f} bolts of {d.capacity_kN:g} kN give FS {d.factor_of_safety:.3f}"
        )
    if "combinations" in result.tables:
        table = result.tables["combinations"]
        formed = table[table.forms]
        critical = formed[formed.critical]
        lines.append(
            f"combinations: {len(formed)} of {len(table)} pairs form a wedge, {len(critical)} critical"
        )
        if len(formed):
            low = formed.iloc[0]
            lines.append(
                f"lowest FS {low.factor_of_safety:.3f}: {low.plane_1} with {low.plane_2}, {low['mode']}"
            )
    return lines
