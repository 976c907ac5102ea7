"""A sweep's `wedge` base: one wedge per sample (`bbmc.slope.wedge.probability`), the whole batch in one
vectorised call, through the compiled fast path (the full geometry with a tension crack).

The base is `bbmc wedge`'s keys (`bbmc.slope.wedge.config`: the planes and their Mohr-Coulomb or
Barton-Bandis strength, face, upper surface, height, tension crack, water, seismic, forces, bolts) and
each plane's Fisher K. A sample's inputs are the base's sections with the study's variables set at
their paths (plane_1.strength.friction_deg, plane_2.strength.jrc, water.filled, seismic.coefficient,
bolts.0.capacity_kN, ...) as arrays over the batch (`model_construct`: the base was validated, the
varied numbers were drawn within their keys' ranges), turned into SI by the sections' own methods, as
`bbmc wedge` turns its config. A Barton-Bandis plane is evaluated at its own normal stress from statics
per sample (`bbmc.slope.wedge.strength`), scaled where asked to the sample's line of intersection
(`probability.intersection_lengths`). Bolts are counted active or passive (`support.support_resultants`)
and join the external forces or the passive resultant, as in `bbmc wedge`.

A plane with `fisher_k` is then drawn about its (possibly varied) mean by Fisher's distribution, from
the sample's own uniforms (`bbmc.sweep.streams`: a function of the base's seed and the sample's number
only), so a sample's draw is the same whatever the batch size, the worker or the order the batches run
in. Samples sharing a mean and K are drawn together.

Outcomes (`bbmc.sweep.models`): a wedge that forms is `valid` with its FS; one that cannot form is
`invalid`, its error the reason (`geometry.REASON_TEXT`) and its `wedge_reason` the reason's name, so
the study's P_f (failed / valid samples) is Swedge's probability of sliding, and
`wedge_summary` adds Swedge's probability of failure over every sample and the count of each reason.
A formed wedge with no driving force (FS = +inf) is a failed run. Outputs per sample: factor_of_safety,
sliding_mode, wedge_reason and the drawn dip_deg / dip_direction_deg of each plane.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from pydantic import BaseModel

from bbmc.slope.wedge import config as keys
from bbmc.slope.wedge.analysis import WedgeOrientations
from bbmc.slope.wedge.geometry import REASON_TEXT, WedgeReason
from bbmc.slope.wedge.mechanics import SlidingMode
from bbmc.slope.wedge.probability import (
    PlaneScatter,
    WedgeProbability,
    intersection_lengths,
    wedge_probability,
)
from bbmc.slope.wedge.support import support_resultants
from bbmc.sweep.config import Wedge
from bbmc.sweep.models import ERROR, FAILED_RUN, FS, INVALID, OUTCOME, VALID
from bbmc.sweep.outcomes import Outcomes
from bbmc.sweep.statistics import clopper_pearson_interval
from bbmc.sweep.streams import sample_uniforms

REASON = "wedge_reason"
MODE = "sliding_mode"
PLANES = ("plane_1", "plane_2")
# Texts indexed by WedgeReason and SlidingMode codes (object arrays: a batch's columns share the strings).
REASON_ERRORS = np.array(
    ["" if r == WedgeReason.FORMED else f"the wedge does not form: {REASON_TEXT[r]}" for r in WedgeReason],
    dtype=object,
)
REASON_NAMES = np.array([r.name.lower() for r in WedgeReason], dtype=object)
MODE_NAMES = np.array([m.name.lower() for m in SlidingMode], dtype=object)
OUTCOMES = np.array([INVALID, VALID, FAILED_RUN], dtype=object)  # by formed + (formed, FS infinite)
DRAWN = [f"{plane}.{key}_drawn" for plane in PLANES for key in ("dip_deg", "dip_direction_deg")]


@dataclass(frozen=True)
class WedgeModel:
    """The base (`bbmc.sweep.config.Wedge`), evaluated a batch at a time."""

    base: Wedge

    def section(self, inputs: pd.DataFrame, path: str, section: BaseModel) -> BaseModel:
        """The base's `section` at `path` with each number a variable sets replaced by its column (an
        array over the batch), nested sections likewise; unvalidated (`model_construct`)."""
        values = {}
        for key, value in section:
            where = f"{path}.{key}"
            if isinstance(value, BaseModel):
                value = self.section(inputs, where, value)
            elif where in inputs:
                value = inputs[where].to_numpy(dtype=float)
            values[key] = value
        return type(section).model_construct(**values)

    def _number(self, inputs: pd.DataFrame, key: str) -> float | np.ndarray | None:
        """A top-level number of the base: a variable's column, else the base's value."""
        return inputs[key].to_numpy(dtype=float) if key in inputs else getattr(self.base, key)

    def _plane(self, inputs: pd.DataFrame, plane: keys.JointPlane, streams: int) -> tuple[np.ndarray, ...]:
        """A plane's dips and dip directions [rad] per sample: drawn about each sample's mean with its
        K if it has one, from the sample's own uniforms (`bbmc.sweep.streams`, streams `streams` and
        `streams` + 1), else the means themselves."""
        count = len(inputs)
        means = [
            np.broadcast_to(np.asarray(m, dtype=float), (count,))
            for m in (plane.dip_deg, plane.dip_direction_deg)
        ]
        if plane.fisher_k is None:
            return np.radians(means[0]), np.radians(means[1])
        samples = inputs.index.to_numpy()
        u = sample_uniforms(self.base.seed, samples, streams)
        v = sample_uniforms(self.base.seed, samples, streams + 1)
        given = (plane.dip_deg, plane.dip_direction_deg, plane.fisher_k)
        if not any(isinstance(g, np.ndarray) for g in given):  # one mean and K: the batch at once
            scatter = PlaneScatter(math.radians(given[0]), math.radians(given[1]), fisher_k=given[2])
            return scatter.from_uniforms(u, v)
        dip, direction = np.empty(count), np.empty(count)
        kappa = np.broadcast_to(np.asarray(plane.fisher_k, dtype=float), (count,))
        table = pd.DataFrame({"dip": means[0], "direction": means[1], "k": kappa})
        # the samples sharing a mean and K, by hashing (np.unique(axis=1) sorts rows: ~2 s a million)
        groups = table.groupby(list(table), sort=False, dropna=False).indices
        for (mean_dip, mean_direction, k), rows in groups.items():
            scatter = PlaneScatter(math.radians(mean_dip), math.radians(mean_direction), fisher_k=k)
            dip[rows], direction[rows] = scatter.from_uniforms(u[rows], v[rows])
        return dip, direction

    def probability(self, inputs: pd.DataFrame) -> tuple[WedgeProbability, list[np.ndarray]]:
        """The batch's wedges (FS, reasons, sliding modes) and the drawn dips and dip directions [rad]
        (plane 1's, then plane 2's)."""
        base = self.base
        planes = [self.section(inputs, name, getattr(base, name)) for name in PLANES]
        drawn = [*self._plane(inputs, planes[0], 0), *self._plane(inputs, planes[1], 2)]
        face, upper = (self.section(inputs, name, getattr(base, name)) for name in ("face", "upper_surface"))
        orientations = WedgeOrientations(*drawn, *face.radians(), *upper.radians())
        crack = base.tension_crack
        geometry = {
            "height_h1": self._number(inputs, "height_h1_m"),
            "height_h": self._number(inputs, "height_m"),
            "overhanging_face": base.face.overhanging,
            "crack": None if crack is None else self.section(inputs, "tension_crack", crack).crack(),
        }
        needs = any(plane.needs_length() for plane in planes)
        length = intersection_lengths(orientations, **geometry) if needs else 0.0
        water = self.section(inputs, "water", base.water)
        seismic = None if base.seismic is None else self.section(inputs, "seismic", base.seismic).seismic()
        bolts = [self.section(inputs, f"bolts.{i}", bolt).bolt() for i, bolt in enumerate(base.bolts)]
        active, passive = support_resultants(bolts)
        forces = [self.section(inputs, f"forces.{i}", force).vector() for i, force in enumerate(base.forces)]
        result = wedge_probability(
            orientations,
            *(plane.plane_strength(length) for plane in planes),
            **geometry,
            unit_weight=self._number(inputs, "unit_weight_kN_m3") * keys.KN,
            water=water.water(),
            water_unit_weight=keys.water_unit_weight(water),
            seismic=seismic,
            forces=sum(forces, active),
            passive=passive,
        )
        return result, drawn

    def __call__(self, inputs: pd.DataFrame) -> pd.DataFrame:
        """Each sample's outcome and outputs. A batch that a sample's combination of values refuses (a
        B-B phi_max + waviness varied to 90 deg or more) is halved until only those samples fail, each
        with the error (a sample's draws do not depend on its batch)."""
        try:
            result, drawn = self.probability(inputs)
        except ValueError as error:
            if len(inputs) > 1:
                half = len(inputs) // 2
                return pd.concat([self(inputs.iloc[:half]), self(inputs.iloc[half:])])
            text = f"{type(error).__name__}: {error}"
            table = pd.DataFrame({ERROR: text, OUTCOME: FAILED_RUN}, index=inputs.index)
            return table.reindex(columns=[FS, MODE, REASON, *DRAWN, ERROR, OUTCOME])
        reason = result.reason
        formed = reason == WedgeReason.FORMED
        fs = result.factor_of_safety
        infinite = formed & ~np.isfinite(fs)
        errors = REASON_ERRORS[reason]
        errors[infinite] = "no driving force: FS is infinite"
        outcome = OUTCOMES[formed.astype(np.int8) + infinite]
        modes = MODE_NAMES[result.mode]
        modes[~formed] = ""
        columns = {FS: np.where(np.isfinite(fs), fs, math.nan), MODE: modes, REASON: REASON_NAMES[reason]}
        columns |= dict(zip(DRAWN, np.degrees(drawn), strict=True))
        return pd.DataFrame({**columns, ERROR: errors, OUTCOME: outcome}, index=inputs.index)


def wedge_summary(samples: pd.DataFrame, outcomes: Outcomes) -> pd.DataFrame:
    """summary.csv's rows of a wedge study beyond the FS statistics: the probability of sliding (failed
    / valid: the study's probability_of_failure), Swedge's probability of failure over every sample
    (failed / (valid + invalid); failed runs and impossible inputs left out) with its Clopper-Pearson
    95 % interval, and the count of each reason a wedge did not form (`invalid_samples.<reason>`)."""
    valid = ~outcomes.excluded
    failures = int((samples.loc[valid, FS].to_numpy(dtype=float) < 1.0).sum())
    counted = int((valid | outcomes.invalid).sum())
    low, high = clopper_pearson_interval(failures, counted)
    values = {
        "probability_of_sliding": failures / max(int(valid.sum()), 1),
        "probability_of_failure_all_samples": failures / counted,
        "pf_all_samples_ci_low": float(low),
        "pf_all_samples_ci_high": float(high),
    }
    reasons = samples.loc[outcomes.invalid, REASON].value_counts(sort=False)
    values |= {f"invalid_samples.{reason}": int(count) for reason, count in reasons.items()}
    return pd.DataFrame([(k, v, "1") for k, v in values.items()], columns=["quantity", "value", "unit"])
