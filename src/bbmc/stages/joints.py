"""`bbmc joints`: a joint survey along a scanline -> each set's statistics -> a scene's joint sets.

The config names the survey (a CSV, `bbmc.field.survey`), the scanline's orientation and length, the
azimuth of the section the scene will cut, the cap on Terzaghi's weights and, per set, the persistence
to write (a scanline does not measure it) and, for a set mapped without dip directions, its mean dip
direction. The fitting is in `bbmc.field`; docs/field-data.md gives the format and the corrections.
"""

from __future__ import annotations

import difflib
from typing import Annotated

import numpy as np
import pandas as pd
from pydantic import Field, field_validator, model_validator

from bbmc import units
from bbmc.config import ConfigError, InputFile, Section
from bbmc.field import block, figures
from bbmc.field import distributions as dist
from bbmc.field.analysis import MIN_TRACES, MIN_WHOLE, SCENE_FAMILIES, SetFit, fit_set
from bbmc.field.survey import SetSurvey, read_survey, set_names
from bbmc.geometry.orientation import goodness, line_direction, section_trace
from bbmc.io import StageResult

NAME = "joints"
COMMAND_HELP = """Fit joint sets to a scanline survey (set, position, dip, dip direction, trace
    length, hidden ends) and write them as a scene's joint sets (docs/field-data.md).

    \b
    Example:
      bbmc joints configs/joints.yaml
    writes results/joints/fits.csv (every candidate distribution: parameters, AIC, n, KS p-value),
    sets.csv (orientation, Terzaghi factor, frequency, trace in the section), joint_sets.yaml (the
    block a scene's rock_mass reads), histograms.png, rose.png, provenance.json
    """  # `bbmc joints --help`


Azimuth = Annotated[float, Field(ge=0, le=360)]


class Scanline(Section):
    trend_deg: Azimuth  # clockwise from north
    plunge_deg: float = Field(ge=-90, le=90)  # downward positive
    length_m: float = Field(gt=0)  # positions run from 0 to it


class SetOptions(Section):
    persistence: float = Field(gt=0, le=1)  # the share of a set's lines that is joint, as the scene takes it
    dip_direction_deg: Azimuth | None = None  # the set's mean dip direction, for a survey without them


class Inputs(Section):
    survey: InputFile  # the scanline survey (CSV, docs/field-data.md)


class Config(Section):
    """A scanline survey and what the fitted sets are written for."""

    data: Inputs
    scanline: Scanline
    section_azimuth_deg: Azimuth  # the section of the scene the joint sets are written for
    max_terzaghi_weight: float = Field(ge=1, le=100)  # cap on w = 1/|cos delta|
    sets: dict[str, SetOptions] = Field(min_length=1)
    figure_dpi: int = Field(ge=50, le=600)

    @field_validator("sets")
    @classmethod
    def _names(cls, value: dict[str, SetOptions]) -> dict[str, SetOptions]:
        for name in value:
            if not name.strip() or name != name.strip():
                raise ValueError(f"set name {name!r}: give a name without leading or trailing spaces")
        return value

    @model_validator(mode="after")
    def _sets_mapped(self) -> Config:
        mapped = set_names(self.data.survey)
        for name in self.sets:
            if name not in mapped:
                close = difflib.get_close_matches(name, list(mapped), n=1)
                hint = f"did you mean '{close[0]}'?" if close else f"its sets: {', '.join(mapped)}"
                raise ValueError(
                    f"key 'sets.{name}': no discontinuity of set '{name}' in {self.data.survey} ({hint})"
                )
        return self


def _checked_counts(config: Config, surveys: dict[str, SetSurvey]) -> None:
    for name, survey in surveys.items():
        whole = int(np.sum(survey.censored_ends == 0))
        if survey.position.size < MIN_TRACES:
            raise ConfigError(
                f"{config.data.survey}: column 'set': set '{name}' has {survey.position.size} "
                f"discontinuities: fitting a set needs at least {MIN_TRACES}"
            )
        if whole < MIN_WHOLE:
            raise ConfigError(
                f"{config.data.survey}: column 'censored_ends': set '{name}' has {whole} traces seen whole "
                f"(censored_ends 0): fitting its trace length needs at least {MIN_WHOLE}"
            )
        given = config.sets[name].dip_direction_deg
        if survey.dip_direction is None and given is None:
            raise ConfigError(
                f"{config.data.survey}: column 'dip_direction_deg': set '{name}' has none: give its mean dip "
                f"direction as sets.{name}.dip_direction_deg in the config"
            )
        if survey.dip_direction is not None and given is not None:
            raise ConfigError(
                f"{config.data.survey}: column 'dip_direction_deg': set '{name}' has dip directions, and the "
                f"config gives sets.{name}.dip_direction_deg too: give them in one place"
            )


def fit_sets(config: Config) -> list[SetFit]:
    """Every set of the config fitted to its survey, in the config's order."""
    sets = read_survey(config.data.survey, config.scanline.length_m, list(config.sets))
    _checked_counts(config, sets)
    line = line_direction(config.scanline.trend_deg * units.deg, config.scanline.plunge_deg * units.deg)
    fits = []
    for name, survey in sets.items():
        given = config.sets[name].dip_direction_deg
        fit = fit_set(
            survey,
            line,
            config.scanline.length_m,
            config.max_terzaghi_weight,
            None if given is None else given * units.deg,
        )
        if not np.isfinite(fit.orientation.fisher_k):
            raise ConfigError(
                f"{config.data.survey}: column 'dip_deg': set '{name}': no scatter in its orientations"
            )
        fits.append(fit)
    return fits


def _fit_rows(fit: SetFit, chosen: dict[tuple[str, str], dist.Candidate]) -> list[dict]:
    name = fit.survey.name
    censored = {
        "spacing": int(fit.censored_tail is not None) + int(np.sum(fit.spacings == 0)),
        "trace_length": int(np.sum(fit.survey.censored_ends > 0)),
    }
    count = {"spacing": fit.spacings.size, "trace_length": fit.count}
    rows = []
    for quantity, candidates in (("spacing", fit.spacing), ("trace_length", fit.trace_length)):
        least = min(c.aic for c in candidates)
        for c in candidates:
            rows.append(
                {
                    "set": name,
                    "quantity": f"{quantity}_m",
                    "distribution": c.family,
                    "chosen": c is chosen[name, quantity],
                    "mean": c.mean,
                    "std": c.std,
                    "scipy": c.scipy,
                    "log_likelihood": c.log_likelihood,
                    "parameters": c.parameters,
                    "aic": c.aic,
                    "delta_aic": c.aic - least,
                    "n": count[quantity],
                    "n_censored": censored[quantity],
                    "ks_p_value": c.ks_p_value,
                }
            )
    return rows


def _orientation_row(fit: SetFit) -> dict:
    o = fit.orientation
    check = goodness(o, fit.survey.dip)
    log_l = check.log_likelihood
    return {
        "set": fit.survey.name,
        "quantity": "dip_deg",
        "distribution": check.family,
        "chosen": True,
        "mean": o.dip / units.deg,
        "std": o.dip_std / units.deg,
        "scipy": check.description,
        "log_likelihood": log_l,
        "parameters": check.parameters,
        "aic": 2 * check.parameters - 2 * log_l,
        "delta_aic": 0.0,
        "n": fit.count,
        "n_censored": 0,
        "ks_p_value": check.ks_p_value,
    }


def _set_row(fit: SetFit, section_azimuth: float, persistence: float) -> dict:
    o = fit.orientation
    section = section_trace(o.normal, section_azimuth)
    return {
        "set": fit.survey.name,
        "n": fit.count,
        "n_one_end_hidden": int(np.sum(fit.survey.censored_ends == 1)),
        "n_both_ends_hidden": int(np.sum(fit.survey.censored_ends == 2)),
        "dip_deg": o.dip / units.deg,
        "dip_direction_deg": o.dip_direction / units.deg,
        "fisher_k": o.fisher_k,
        "dip_std_deg": o.dip_std / units.deg,
        "orientation_from": "dip and dip direction" if o.from_dip_directions else "dips, dip direction given",
        "terzaghi_factor": fit.spacing_factor,
        "weights_capped": fit.capped,
        "normal_frequency_per_m": fit.normal_frequency,
        "position_reading_m": fit.survey.resolution,
        "persistence": persistence,
        "apparent_dip_in_section_deg": section.apparent_dip / units.deg,
        "dips_towards_deg": section.dips_towards / units.deg,
        "section_spacing_factor": section.spacing_factor,
    }


def run(config: Config) -> StageResult:
    """Fit every set; tabulate the fits and the sets, draw them, write the scene's joint-set block."""
    fits = fit_sets(config)
    chosen = {}
    for fit in fits:
        chosen[fit.survey.name, "spacing"] = dist.best(fit.spacing, SCENE_FAMILIES)
        chosen[fit.survey.name, "trace_length"] = dist.best(fit.trace_length, SCENE_FAMILIES)
    entries = []
    for fit in fits:
        name, persistence = fit.survey.name, config.sets[fit.survey.name].persistence
        try:
            block.line_spacing(chosen[name, "spacing"], persistence)
        except block.PersistenceError as error:
            raise ConfigError(
                f"{config.data.survey}: set '{name}': {error} (sets.{name}.persistence)"
            ) from None
        entries.append(
            block.BlockEntry(
                name, fit.orientation, chosen[name, "spacing"], chosen[name, "trace_length"], persistence
            )
        )
    rows = []
    for fit in fits:
        rows.append(_orientation_row(fit))
        rows.extend(_fit_rows(fit, chosen))
    scanline = config.scanline
    comments = [
        f"Joint sets fitted by bbmc joints to {config.data.survey.name}: scanline trend "
        f"{scanline.trend_deg:g} deg, plunge {scanline.plunge_deg:g} deg, {scanline.length_m:g} m.",
        "Orientation: Terzaghi-weighted mean plane; Fisher's K from the poles, or 1/sigma^2 of the dips",
        "where the survey has no dip directions. Spacing: normal to the set, between the set's lines",
        "(the joints' spacing thinned back by the persistence). Trace length: corrected for size bias",
        "and censoring. Persistence: as given in the config (a scanline does not measure it).",
        "docs/field-data.md",
    ]
    section_azimuth = config.section_azimuth_deg * units.deg
    dpi = config.figure_dpi
    return StageResult(
        tables={
            "fits": pd.DataFrame(rows),
            "sets": pd.DataFrame(
                [_set_row(f, section_azimuth, config.sets[f.survey.name].persistence) for f in fits]
            ),
        },
        figures={
            "histograms": figures.histograms(fits, chosen, dpi),
            "rose": figures.rose(fits, scanline.trend_deg * units.deg, section_azimuth, dpi),
        },
        files={"joint_sets.yaml": block.joint_sets_yaml(entries, config.section_azimuth_deg, comments)},
    )
