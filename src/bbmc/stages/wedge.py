"""`bbmc wedge`: a rock wedge's limit equilibrium (Hoek & Bray 1981, ch. 8; Swedge): one wedge of two
joint planes against a slope face, the bolts it needs for a target FS, and the combination analysis of
every pair of joint sets.

The config's sections (`bbmc.slope.wedge.config`) are validated whole before any work; a deterministic
wedge that cannot form is refused in one line naming its key and the reason (the combination table
gives such a pair a row with its reason instead). Swedge's size limits (bench width, slope length, each
plane's trace length and persistence, the volume) scale the wedge and every pair's down
(`bbmc.slope.wedge.size_limits`). Domain code: `bbmc.slope.wedge` (cases, combinations, bolting);
tables: `bbmc.outputs.wedge_tables`; figures: `bbmc.outputs.wedge_figures`. Writes wedge.csv,
design.csv and combinations.csv, each where the config asks for it, and of the drawn wedge (the
config's, else the combinations' lowest-FS wedge) wedge.png, wedge_net.png, vertices.csv, forces.csv
and wedge.vtu, into results/wedge/<name>/.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Annotated

import numpy as np
from matplotlib.figure import Figure
from pydantic import Field, model_validator

from bbmc import units
from bbmc.config import ConfigKeyError, InputFile, Section
from bbmc.field.set_table import read_set_planes
from bbmc.io import StageResult
from bbmc.outputs import wedge_figure_tables, wedge_figures, wedge_tables, wedge_vtk
from bbmc.slope.wedge import config as keys
from bbmc.slope.wedge.analysis import WedgeOrientations
from bbmc.slope.wedge.bolting import BRACKET_WEIGHTS, BoltDesign, design_bolts, tangent_friction
from bbmc.slope.wedge.cases import Plane, WedgeCase, WedgeSetting, analyse_case
from bbmc.slope.wedge.combinations import Combination, combination_table
from bbmc.slope.wedge.geometry import WedgeReason
from bbmc.slope.wedge.strength import normal_stresses
from bbmc.slope.wedge.support import Bolt, support_resultants

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


def _did_you_mean(name: str, names: list[str]) -> str:
    close = difflib.get_close_matches(name, names, n=1)
    return f" (did you mean '{close[0]}'?)" if close else f" (its sets: {', '.join(names)})"


class Combinations(Section):
    """Joint sets by name (mean plane and strength), typed as `sets` or read from `bbmc kinematics`'
    sets.csv (`sets_file`, each set with `strength`, or its own in `set_strength`), whose every pair is
    analysed; an optional basal plane analysed with each set; the FS below which a wedge is critical."""

    sets: dict[str, keys.JointPlane] = Field(default_factory=dict)
    sets_file: InputFile | None = None
    strength: keys.Strength | None = None
    set_strength: dict[str, keys.Strength] = Field(default_factory=dict)
    basal_plane: keys.JointPlane | None = None
    critical_fs: keys.Positive = 1.0

    def _file_planes(self) -> dict[str, keys.JointPlane]:
        if self.sets_file is None:
            return {}
        found = read_set_planes(self.sets_file)
        return {
            name: keys.JointPlane(
                dip_deg=p.dip_deg,
                dip_direction_deg=p.dip_direction_deg,
                strength=self.set_strength.get(name, self.strength),
            )
            for name, p in found.items()
        }

    def planes(self) -> dict[str, keys.JointPlane]:
        """Every set: those of the file in its order, then those typed."""
        return self._file_planes() | self.sets

    @model_validator(mode="after")
    def _pairs(self) -> Combinations:
        if self.sets_file is None and (self.strength is not None or self.set_strength):
            raise ValueError("key 'strength, set_strength': they are for sets_file's sets; give it")
        if self.sets_file is not None:
            found = read_set_planes(self.sets_file)
            unknown = sorted(set(self.set_strength) - set(found))
            if unknown:
                raise ValueError(
                    f"key 'set_strength.{unknown[0]}': no such set in {self.sets_file}"
                    + _did_you_mean(unknown[0], list(found))
                )
            bare = [name for name in found if name not in self.set_strength]
            if bare and self.strength is None:
                raise ValueError(f"key 'strength': set {bare[0]} of {self.sets_file} has no strength")
            twice = sorted(set(found) & set(self.sets))
            if twice:
                raise ValueError(f"key 'sets.{twice[0]}': also a set of {self.sets_file}")
        names = set(self.planes())
        if len(names) + (self.basal_plane is not None) < 2:
            raise ValueError("give at least two sets, or a set and a basal plane: a wedge needs two planes")
        if self.basal_plane is not None and "basal" in names:
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
    bench_width_m: keys.Positive | None = None  # Swedge's bench width: the wedge's reach behind the crest
    slope_length_m: keys.Positive | None = None  # Swedge's slope length: the wedge's extent along the crest
    max_volume_m3: keys.Positive | None = None  # Swedge's Scale Wedge by volume
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
        if self.tension_crack is not None and self._limits_size():
            raise ValueError(
                "key 'tension_crack': the size limits (bench_width_m, slope_length_m, max_volume_m3, a "
                "plane's trace_length_m or persistence_m) scale the wedge, but the crack's distance_m "
                "does not scale with it: give the crack or the limits"
            )
        return self

    def _limits_size(self) -> bool:
        planes = [self.plane_1, self.plane_2]
        if self.combinations is not None:
            planes += [*self.combinations.planes().values(), self.combinations.basal_plane]
        given = (self.bench_width_m, self.slope_length_m, self.max_volume_m3)
        return any(v is not None for v in given) or any(p is not None and p.limits_size() for p in planes)


@dataclass(frozen=True)
class Drawn:
    """The wedge the figures show and the design bolts: its title, case, planes and their names (the
    config's wedge, or without one the lowest-FS wedge of the combinations)."""

    title: str
    case: WedgeCase
    planes: tuple[Plane, Plane]
    names: tuple[str, str]


def output_name(config: Config, config_path: Path) -> str:
    """The results folder's name: the config's `name`, else its file's stem."""
    return config.name or config_path.stem


def plane(section: keys.JointPlane) -> Plane:
    """The analysis' plane of a config's joint plane."""
    return Plane(*section.radians(), section.plane_strength, section.trace_length_m, section.persistence_m)


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
        bench_width=config.bench_width_m,
        slope_length=config.slope_length_m,
        max_volume=config.max_volume_m3,
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
    capacity = d.capacity_kN * keys.KN if d.capacity_kN is not None else None
    return [design_bolts(case, slope, planes, d.target_fs, (capacity, d.count), d.form, direction)]


def friction_angles(drawn: Drawn) -> dict[str, float]:
    """Each plane's friction angle [rad] for the net's friction cones: Mohr-Coulomb's, or a
    Barton-Bandis plane's tangent angle at its mean normal stress; one cone where both are equal."""
    solution, g = drawn.case.analysis.solution, drawn.case.geometry
    stresses = [float(v) for v in normal_stresses(solution.normal_1, solution.normal_2, g.area_1, g.area_2)]
    angles = [
        math.atan(tangent_friction(s, sigma)) for s, sigma in zip(drawn.case.strengths, stresses, strict=True)
    ]
    if math.isclose(*angles, rel_tol=1e-12):
        return {f"{drawn.names[0]} and {drawn.names[1]}": angles[0]}
    return dict(zip(drawn.names, angles, strict=True))


def drawn_outputs(config: Config, drawn: Drawn) -> tuple[dict[str, Figure], dict, dict[str, bytes]]:
    """The drawn wedge's figures (wedge.png in 3D with its forces, wedge_net.png), the tables of their
    numbers (vertices.csv, forces.csv) and its VTK file (wedge.vtu, for ParaView)."""
    analysis, bolts = drawn.case.analysis, [b.bolt() for b in config.bolts]
    orientations = WedgeOrientations(
        *(math.radians(a) for a in drawn_angles(config, drawn.names)),
    )
    figures = {
        "wedge": wedge_figures.wedge_figure(analysis, bolts, title=drawn.title, names=drawn.names),
        "wedge_net": wedge_figures.wedge_net_figure(
            analysis, orientations, friction_angles(drawn), names=drawn.names
        ),
    }
    tables = {
        "vertices": wedge_figure_tables.vertex_table(analysis.geometry),
        "forces": wedge_figure_tables.force_table(analysis, bolts),
    }
    return figures, tables, {"wedge.vtu": wedge_vtk.wedge_vtu_bytes(analysis.geometry)}


def drawn_angles(config: Config, names: tuple[str, str]) -> list[float]:
    """Dips and dip directions [deg] of the drawn wedge's planes, face and upper surface."""
    joint = {"plane 1": config.plane_1, "plane 2": config.plane_2}
    if config.combinations is not None:
        joint |= config.combinations.planes() | {"basal": config.combinations.basal_plane}
    planes = [joint[name] for name in names] + [config.face, config.upper_surface]
    return [angle for p in planes for angle in (p.dip_deg, p.dip_direction_deg)]


def _lowest(slope: WedgeSetting, sets: dict[str, Plane], combos: list[Combination]) -> Drawn | None:
    """The lowest-FS wedge of the combinations (they are sorted by FS), None where no pair forms one."""
    if not combos or not combos[0].forms:
        return None
    low = combos[0]
    planes = (sets[low.plane_1], sets[low.plane_2])
    case = analyse_case(slope, *planes)
    return Drawn(
        f"Lowest-FS wedge, {low.plane_1} with {low.plane_2}", case, planes, (low.plane_1, low.plane_2)
    )


def run(config: Config, progress: Callable[[str], None] = lambda _: None) -> StageResult:
    """Analyse the wedge and the combinations, as the config asks; design the bolts of the wedge (or
    without one, of the combinations' lowest-FS wedge); draw that wedge in 3D and on the net, and write
    it for ParaView."""
    slope = setting(config)
    tables = {}
    drawn = None
    if config.plane_1 is not None:
        case, planes = _wedge(config, slope)
        tables["wedge"] = wedge_tables.wedge_table(case)
        drawn = Drawn("Wedge", case, planes, ("plane 1", "plane 2"))
    if config.combinations is not None:
        c = config.combinations
        sets = {name: plane(section) for name, section in c.planes().items()}
        progress(f"the wedges of {len(sets)} sets' pairs")
        basal = plane(c.basal_plane) if c.basal_plane is not None else None
        combos = combination_table(slope, sets, basal, c.critical_fs)
        tables["combinations"] = wedge_tables.combinations_frame(combos)
        drawn = drawn or _lowest(slope, sets | {"basal": basal}, combos)
    if drawn is None:
        if config.design is not None:
            raise ConfigKeyError("design", "no pair of the combinations forms a wedge to design bolts for")
        return StageResult(tables=tables)
    if config.design is not None:
        progress(f"designing the bolts of {drawn.names[0]} with {drawn.names[1]}")
        designs = _designs(config, slope, drawn.case, drawn.planes)
        tables["design"] = wedge_tables.design_frame(designs, drawn.names)
    figures, figure_tables, files = drawn_outputs(config, drawn)
    if config.design is not None:
        figures |= _bolted_figure(config, slope, drawn, designs[0])
    return StageResult(tables=tables | figure_tables, figures=figures, files=files)


def _bolted_figure(
    config: Config, slope: WedgeSetting, drawn: Drawn, design: BoltDesign
) -> dict[str, Figure]:
    """wedge_bolted.png: the drawn wedge with the designed bolts in place (none where the target is not
    reached)."""
    if not np.isfinite(design.count):
        return {}
    bolt = Bolt(design.capacity, design.trend, design.plunge, int(design.count), design.form)
    active, passive = support_resultants([bolt])
    bolted = replace(slope, forces=slope.forces + active, passive=slope.passive + passive)
    case = analyse_case(bolted, *drawn.planes)
    bolts = [*(b.bolt() for b in config.bolts), bolt]
    title = f"{drawn.title}, {int(design.count)} designed bolts"
    return {"wedge_bolted": wedge_figures.wedge_figure(case.analysis, bolts, title=title, names=drawn.names)}


def summary_lines(result: StageResult) -> list[str]:
    """What the command prints: the wedge's mode and FS, each design, and the critical wedges."""
    lines = []
    if "wedge" in result.tables:
        w = result.tables["wedge"].iloc[0]
        lines.append(
            f"wedge: FS {w.factor_of_safety:.4f}, {w['mode']}, weight {w.weight_kN:,.1f} kN, "
            f"line of intersection {w.line_plunge_deg:.1f}/{w.line_trend_deg:03.0f}"
        )
        if w.size_limited_by != "height":
            lines.append(f"wedge scaled by {w.size_scale:.4f} to its {w.size_limited_by.replace('_', ' ')}")
    designs = result.tables.get("design")
    for _, d in designs.iterrows() if designs is not None else ():
        where = f"trend {d.trend_deg:03.0f}, plunge {d.plunge_deg:.1f}"
        if np.isnan(d.total_force_kN):
            lines.append(
                f"design of {d.plane_1} with {d.plane_2} ({d.bolt}, {d.form}): "
                f"FS {d.target_fs:g} not reached along {where} "
                f"with up to {BRACKET_WEIGHTS:g} times the wedge's weight"
            )
            continue
        lines.append(
            f"design of {d.plane_1} with {d.plane_2} ({d.bolt}, {d.form}): "
            f"{d.total_force_kN:,.1f} kN drilled along {where}: "
            f"{d['count']:.0f} bolts of {d.capacity_kN:,.4g} kN give FS {d.factor_of_safety:.3f}"
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
