"""`bbmc kinematics`: orientation readings as recorded -> joint sets found in them -> what can fail
where: the kinematic analysis of a slope face, around the compass and over face angles, and the
probability of each mode from the sets' scatter; the sets written for a rock mass.

A new command rather than more of `bbmc joints`: that one fits sets a field crew has already named
along one scanline; this one starts from unlabelled readings of any sheets (face mapping, scanlines,
oriented core) and a slope face, and reuses `bbmc joints`' fits (`bbmc.field.analysis`) for the
spacing and trace length of the sets found where the readings carry scanline positions.

Domain code: reading (`bbmc.field.readings`), set finding (`bbmc.field.set_finding`), the sets for a
rock mass (`bbmc.field.found_sets`), kinematics (`bbmc.kinematics`), stereonets and charts
(`bbmc.outputs.stereonet_figures`, `bbmc.outputs.kinematic_charts`). docs/reference/kinematics-command.md
lists the keys and the files.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterable
from dataclasses import replace
from typing import Annotated, Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

from bbmc import units
from bbmc.config import ConfigKeyError, InputFile, Section
from bbmc.field.block import joint_sets_yaml
from bbmc.field.found_sets import Scanline, block_entry, scanline_fit
from bbmc.field.readings import Readings, SamplingFace, SamplingLine, read_readings
from bbmc.field.set_finding import FoundSets, Window, find_sets
from bbmc.geometry.orientation import DIPS_MAX_WEIGHT, line_vectors, pole_trend_and_plunge
from bbmc.io import StageResult
from bbmc.kinematics import compass
from bbmc.kinematics.config import Azimuth, Dip, FaceSection, Friction, LimitsSection
from bbmc.kinematics.intersections import pair_chunks, pair_lines, pair_plan
from bbmc.kinematics.probabilistic import mode_probabilities
from bbmc.kinematics.tallies import kinematic_tally
from bbmc.outputs import kinematic_charts as charts
from bbmc.outputs import stereonet_figures as nets

NAME = "kinematics"

Plunge = Annotated[float, Field(ge=-90, le=90)]


class LineSampling(Section):
    """A scanline or borehole: trend and plunge [deg] (a hole's plunge < 0: drilled upward)."""

    trend_deg: Azimuth
    plunge_deg: Plunge


class FaceSampling(Section):
    """A mapped face: dip and dip direction [deg]."""

    dip_deg: Dip
    dip_direction_deg: Azimuth


class Sampling(Section):
    """The geometry the sheet's readings were sampled on, for Terzaghi's weights: a line or a face."""

    line: LineSampling | None = None
    face: FaceSampling | None = None

    @model_validator(mode="after")
    def _one(self) -> Sampling:
        if (self.line is None) == (self.face is None):
            raise ValueError("give the sampling line or the sampling face, not both or neither")
        return self


class Sheet(Section):
    """One data sheet of readings (docs/reference/orientation-data.md)."""

    file: InputFile
    convention: Literal["dip_direction", "strike_rhr", "pole", "core"] | None = None
    declination_deg: Annotated[float, Field(ge=-180, le=180)] = 0.0
    sampling: Sampling | None = None
    core_reference: Literal["top", "bottom"] = "bottom"
    scanline_length_m: Annotated[float, Field(gt=0)] | None = None  # positions along sampling.line

    @model_validator(mode="after")
    def _scanline(self) -> Sheet:
        if self.scanline_length_m is not None and (self.sampling is None or self.sampling.line is None):
            raise ValueError(
                "scanline_length_m goes with the scanline the readings were mapped along: give sampling.line"
            )
        return self


class SetWindow(Section):
    """A set window (as Dips'): the readings within half_angle_deg of the pole of this plane."""

    dip_deg: Dip
    dip_direction_deg: Azimuth
    half_angle_deg: Annotated[float, Field(gt=0, le=90)]


class SetsSection(Section):
    """How sets are found: by BIC among at most max_sets sets of at least min_set_size readings, or
    exactly `count` sets, or the given `windows`."""

    max_sets: Annotated[int, Field(ge=1, le=12)] = 6
    min_set_size: Annotated[int, Field(ge=2)] = 10
    seed: Annotated[int, Field(ge=0)] = 0
    count: Annotated[int, Field(ge=1, le=12)] | None = None
    windows: dict[str, SetWindow] | None = None

    @model_validator(mode="after")
    def _one_override(self) -> SetsSection:
        if self.count is not None and self.windows is not None:
            raise ValueError("give a count of sets or set windows, not both")
        if self.windows is not None and not self.windows:
            raise ValueError("windows: give at least one set window")
        return self


class FaceAngles(Section):
    from_deg: Annotated[float, Field(gt=0, le=90)] = 30.0
    to_deg: Annotated[float, Field(gt=0, le=90)] = 90.0
    step_deg: Annotated[float, Field(gt=0, le=30)] = 5.0

    @model_validator(mode="after")
    def _ordered(self) -> FaceAngles:
        if self.to_deg < self.from_deg:
            raise ValueError("to_deg must not be below from_deg")
        return self


class Probability(Section):
    samples: Annotated[int, Field(ge=100, le=10_000_000)] = 1_000_000  # Fisher draws per set
    seed: Annotated[int, Field(ge=0)] = 0


class RockMass(Section):
    persistence: Annotated[float, Field(gt=0, le=1)] = 1.0  # written for every set with a fitted spacing


class Config(Section):
    """Readings, how sets are found in them, a slope face and a friction angle."""

    surveys: list[Sheet] = Field(min_length=1)
    max_terzaghi_weight: Annotated[float, Field(ge=1, le=100)] = DIPS_MAX_WEIGHT
    sets: SetsSection = Field(default_factory=SetsSection)
    face: FaceSection
    friction_deg: Friction
    set_friction_deg: dict[str, Friction] = Field(default_factory=dict)  # a set's own, by its name
    lateral_limits: LimitsSection = Field(default_factory=LimitsSection)
    compass_step_deg: Annotated[float, Field(gt=0, le=45)] = 1.0
    face_angles: FaceAngles = Field(default_factory=FaceAngles)
    probability: Probability = Field(default_factory=Probability)
    rock_mass: RockMass = Field(default_factory=RockMass)
    projection: Literal["equal_area", "equal_angle"] = "equal_area"
    figure_dpi: Annotated[int, Field(ge=50, le=600)] = 120


def _sampling(sheet: Sheet) -> SamplingLine | SamplingFace | None:
    s = sheet.sampling
    if s is None:
        return None
    if s.line is not None:
        return SamplingLine(s.line.trend_deg * units.deg, s.line.plunge_deg * units.deg)
    return SamplingFace(s.face.dip_deg * units.deg, s.face.dip_direction_deg * units.deg)


def read_sheets(config: Config) -> list[Readings]:
    """Every sheet's readings, checked row by row (ConfigError naming the file, row and column)."""
    return [
        read_readings(
            s.file,
            convention=s.convention,
            declination=s.declination_deg * units.deg,
            sampling=_sampling(s),
            max_weight=config.max_terzaghi_weight,
            core_reference=s.core_reference,
        )
        for s in config.surveys
    ]


def _found(config: Config, poles: np.ndarray, weights: np.ndarray) -> FoundSets:
    s = config.sets
    windows = None
    if s.windows is not None:
        windows = [
            Window.about_plane(
                name, w.dip_deg * units.deg, w.dip_direction_deg * units.deg, w.half_angle_deg * units.deg
            )
            for name, w in s.windows.items()
        ]
    try:
        found = find_sets(
            poles,
            weights,
            count=s.count,
            windows=windows,
            max_sets=s.max_sets,
            min_set_size=s.min_set_size,
            seed=s.seed,
        )
    except ValueError as error:
        raise ConfigKeyError("sets", str(error)) from None
    if not found.sets:
        raise ConfigKeyError(
            "sets",
            f"no set found in the {len(poles)} readings (all random at a minimum set size of "
            f"{s.min_set_size}): give a count of sets or set windows",
        )
    return found


def set_names(found: FoundSets) -> list[str]:
    """The windows' names, else S1, S2, ... by decreasing count of readings."""
    return [s.window or f"S{k + 1}" for k, s in enumerate(found.sets)]


def _deg(value: float) -> float:
    return float(value) / units.deg


def _readings_table(sheets: list[Readings], labels: np.ndarray, names: list[str]) -> pd.DataFrame:
    frames = []
    for r in sheets:
        frames.append(
            pd.DataFrame(
                {
                    "file": r.path.name,
                    "line": r.lines,
                    "convention": r.convention,
                    "dip_deg": np.degrees(r.dip),
                    "dip_direction_deg": np.degrees(r.dip_direction),
                    "terzaghi_weight": r.terzaghi,
                    "weight": r.weights,
                    "type": r.kind,
                    "location": r.location,
                    "set_in_field": r.set_label,
                }
            )
        )
    table = pd.concat(frames, ignore_index=True)
    table["set"] = ["random" if k < 0 else names[k] for k in labels]
    return table


def _sets_table(found: FoundSets, names: list[str], fits: dict) -> pd.DataFrame:
    rows = []
    for name, s in zip(names, found.sets, strict=True):
        st = s.statistics
        trend, plunge = pole_trend_and_plunge(st.orientation.dip, st.orientation.dip_direction)
        fit, reason = fits[name]
        rows.append(
            {
                "set": name,
                "dip_deg": _deg(st.orientation.dip),
                "dip_direction_deg": _deg(st.orientation.dip_direction),
                "pole_trend_deg": _deg(trend),
                "pole_plunge_deg": _deg(plunge),
                "fisher_k": st.fisher_k,
                "alpha95_deg": _deg(st.alpha95),
                "spherical_variance": st.spherical_variance,
                "n": st.count,
                "n_weighted": st.weighted_count,
                "n_effective": st.effective_count,
                "share": s.share,
                "spacing": "fitted" if fit is not None else f"must be given: {reason}",
            }
        )
    return pd.DataFrame(rows)


def _rows_table(rows: Iterable[object]) -> pd.DataFrame:
    """A table of dataclass rows, one column per field."""
    return pd.DataFrame([vars(row) for row in rows])


def _fits(config: Config, sheets: list[Readings], found: FoundSets, names: list[str]) -> dict:
    scanlines = []
    for sheet, readings in zip(config.surveys, sheets, strict=True):
        if sheet.scanline_length_m is None:
            scanlines.append(None)
            continue
        line = line_vectors(
            sheet.sampling.line.trend_deg * units.deg, sheet.sampling.line.plunge_deg * units.deg
        )
        scanlines.append(Scanline(readings, line, sheet.scanline_length_m))
    bounds = np.cumsum([0] + [r.count for r in sheets])
    labels = [found.labels[a:b] for a, b in itertools.pairwise(bounds)]
    return {
        name: scanline_fit(name, labels, k, scanlines, config.max_terzaghi_weight)
        for k, name in enumerate(names)
    }


def _friction(config: Config, names: list[str]) -> np.ndarray:
    """Each set's friction angle [rad]: its own from `set_friction_deg`, else `friction_deg`; a name
    that is no set found is a fault of that key."""
    for name in config.set_friction_deg:
        if name not in names:
            raise ConfigKeyError(
                f"set_friction_deg.{name}", f"no set '{name}' was found (the sets: {', '.join(names)})"
            )
    return np.radians([config.set_friction_deg.get(n, config.friction_deg) for n in names])


def _set_pairs_table(tally) -> pd.DataFrame:
    return pd.DataFrame(
        [
            {
                "set_a": p.set_a,
                "set_b": p.set_b,
                "trend_deg": _deg(p.trend),
                "plunge_deg": _deg(p.plunge),
                "critical_modes": " ".join(p.critical_modes) or "none",
            }
            for p in tally.set_pairs
        ]
    )


def run(config: Config, progress: Callable[[str], None] = lambda _: None) -> StageResult:
    """Read, find the sets, analyse the face and the compass, draw and tabulate; `progress` is told
    each step."""
    sheets = read_sheets(config)
    poles = np.vstack([r.poles for r in sheets])
    weights = np.concatenate([r.weights for r in sheets])
    progress(f"read {len(poles)} readings from {len(sheets)} sheets; finding the sets")
    found = _found(config, poles, weights)
    names = set_names(found)
    face, limits = config.face.face(), config.lateral_limits.limits()
    friction = math.radians(config.friction_deg)
    set_friction = _friction(config, names)
    reading_friction = np.where(found.labels >= 0, set_friction[np.maximum(found.labels, 0)], friction)
    means = np.array([s.mean_pole for s in found.sets])
    progress(f"found {len(found.sets)} sets ({found.method}); the face's kinematics")
    tally = kinematic_tally(
        poles, face, reading_friction, limits, found.labels, weights, means, set_friction, names
    )
    options = {
        "limits": limits,
        "sets": found.labels,
        "weights": weights,
        "set_names": names,
        "plan": tally.plan,
    }
    progress("every face dip direction around the compass, and the face angles")
    around = compass.compass_sweep(
        poles, face.dip, reading_friction, config.compass_step_deg * units.deg, **options
    )
    a = config.face_angles
    dips = np.radians(np.arange(a.from_deg, a.to_deg + 1e-9, a.step_deg))
    angles = compass.face_angle_sweep(poles, face.dip_direction, dips, reading_friction, **options)
    progress(f"the modes' probabilities from {config.probability.samples:,} draws per set")
    rng = np.random.default_rng(config.probability.seed)
    kappas = [s.statistics.fisher_k for s in found.sets]
    probabilities = mode_probabilities(
        means, kappas, face, set_friction, limits, config.probability.samples, rng, names
    )
    fits = _fits(config, sheets, found, names)
    entries = [
        block_entry(n, s.statistics, *fits[n], config.rock_mass.persistence)
        for n, s in zip(names, found.sets, strict=True)
    ]
    comments = [
        f"Joint sets found by bbmc kinematics in {', '.join(s.file.name for s in config.surveys)} "
        f"({found.method}); orientation: Terzaghi-weighted mean plane and Fisher's K.",
        "Spacing and trace length: fitted along the scanline where the readings carry positions "
        "(docs/field-data.md); persistence as given in the config.",
    ]
    progress("stereonets and charts")
    figures = _figures(config, found, names, poles, weights, around, angles)
    return StageResult(
        tables={
            "readings": _readings_table(sheets, found.labels, names),
            "sets": _sets_table(found, names, fits),
            "set_count": _rows_table(found.bic),
            "modes": _rows_table(tally.rows),
            "set_pairs": _set_pairs_table(tally),
            "compass": pd.DataFrame(around.rows()),
            "face_angles": pd.DataFrame(angles.rows()),
            "probability": _rows_table(probabilities),
        },
        figures=figures,
        files={"joint_sets.yaml": joint_sets_yaml(entries, config.face.dip_direction_deg, comments)},
    )


def _figures(
    config: Config,
    found: FoundSets,
    names: list[str],
    poles: np.ndarray,
    weights: np.ndarray,
    around: compass.FaceSweep,
    angles: compass.FaceSweep,
) -> dict:
    face, limits = config.face.face(), config.lateral_limits.limits()
    friction = math.radians(config.friction_deg)
    survey = nets.PoleSurvey(poles, found.labels, weights, config.max_terzaghi_weight, dict(enumerate(names)))
    means = nets.SetMeans(
        np.arange(len(found.sets)),
        np.array([s.mean_pole for s in found.sets]),
        np.array([s.statistics.alpha95 for s in found.sets]),
    )
    dpi = config.figure_dpi
    figures = {"poles": nets.pole_figure(survey, means, face, config.projection, dpi=dpi)}
    own = ", ".join(f"{n} {v:g}°" for n, v in config.set_friction_deg.items())
    note = f"Zones drawn for φ = {config.friction_deg:g}°; sets counted at their own φ: {own}" if own else ""
    lines = _some_intersections(poles)
    for mode, drawing in charts.mode_drawings(face, friction, limits).items():
        points = {"survey": survey} if drawing.vectors == "poles" else {"lines": lines}

        def draw(ax, drawing=drawing, points=points) -> nets.NetDrawing:
            drawn = nets.kinematic_plot(ax, drawing, face, friction, **points)
            return replace(drawn, notes=[*drawn.notes, note]) if note else drawn

        figures[f"net_{mode}"] = nets.net_figure(
            f"Kinematic analysis, {drawing.name}", draw, config.projection, dpi
        )
    figures["compass"] = charts.compass_chart(around, config.friction_deg, dpi)
    figures["face_angles"] = charts.face_angle_chart(angles, config.friction_deg, dpi)
    return figures


def _some_intersections(poles: np.ndarray, count: int = 3000) -> np.ndarray:
    """The lines of intersection of `count` pairs of readings drawn at random (seeded, as the tallies
    sample pairs): the nets show them as points; the tallies count every pair of their own plan."""
    plan = pair_plan(len(poles), max_exact_readings=0, sample_pairs=count)
    i, j = next(pair_chunks(plan), (np.array([], int), np.array([], int)))
    lines, defined = pair_lines(poles, i, j)
    return lines[defined]
