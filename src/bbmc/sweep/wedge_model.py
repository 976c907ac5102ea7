"""A sweep's `wedge` base: one wedge per sample (`bbmc.slope.wedge.probability`), the whole batch in one
vectorised call through the compiled fast path.

Each sample's inputs are the base's values with the study's variables set at their paths
(plane_1.friction_deg, plane_2.cohesion_kPa, plane_1.dip_deg, water_filled, seismic_coefficient, ...).
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

from bbmc import units
from bbmc.scene.paths import get_path
from bbmc.slope.wedge.analysis import Seismic, WedgeOrientations
from bbmc.slope.wedge.geometry import REASON_TEXT, WedgeReason
from bbmc.slope.wedge.mechanics import MohrCoulomb, SlidingMode
from bbmc.slope.wedge.probability import PlaneScatter, WedgeProbability, wedge_probability
from bbmc.slope.wedge.water import HoekBrayWater
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
    """The base's data (`bbmc.sweep.config.Wedge`, dumped), evaluated a batch at a time."""

    base: dict

    def _column(self, inputs: pd.DataFrame, path: str) -> np.ndarray:
        """The sample's value at `path` (a variable's column, else the base's value), per sample."""
        given = inputs[path].to_numpy(dtype=float) if path in inputs else get_path(self.base, path)
        return np.broadcast_to(np.asarray(given, dtype=float), (len(inputs),))

    def _plane(self, inputs: pd.DataFrame, plane: str, streams: int) -> tuple[np.ndarray, ...]:
        """A plane's dips and dip directions [rad] per sample: drawn about each sample's mean with its
        K if it has one, from the sample's own uniforms (`bbmc.sweep.streams`, streams `streams` and
        `streams` + 1), else the means themselves."""
        keys = [f"{plane}.{key}" for key in ("dip_deg", "dip_direction_deg", "fisher_k")]
        means = np.stack([self._column(inputs, key) for key in keys[:2]])
        if self.base[plane]["fisher_k"] is None:
            return np.radians(means[0]), np.radians(means[1])
        samples = inputs.index.to_numpy()
        u = sample_uniforms(self.base["seed"], samples, streams)
        v = sample_uniforms(self.base["seed"], samples, streams + 1)
        dip, direction = np.empty(len(inputs)), np.empty(len(inputs))
        table = pd.DataFrame({"dip": means[0], "direction": means[1], "k": self._column(inputs, keys[2])})
        # the samples sharing a mean and K, by hashing (np.unique(axis=1) sorts rows: ~2 s a million)
        groups = table.groupby(list(table), sort=False, dropna=False).indices
        for (mean_dip, mean_direction, k), rows in groups.items():
            scatter = PlaneScatter(math.radians(mean_dip), math.radians(mean_direction), fisher_k=k)
            dip[rows], direction[rows] = scatter.from_uniforms(u[rows], v[rows])
        return dip, direction

    def probability(self, inputs: pd.DataFrame) -> tuple[WedgeProbability, list[np.ndarray]]:
        """The batch's wedges (FS, reasons, sliding modes) and the drawn dips and dip directions [rad]
        (plane 1's, then plane 2's)."""
        drawn = [*self._plane(inputs, "plane_1", 0), *self._plane(inputs, "plane_2", 2)]
        face, upper = ([math.radians(self.base[s][k]) for k in ("dip_deg", "dip_direction_deg")]
                       for s in ("face", "upper_surface"))  # fmt: skip
        strengths = [
            MohrCoulomb(
                self._column(inputs, f"{plane}.cohesion_kPa") * units.kPa,
                np.radians(self._column(inputs, f"{plane}.friction_deg")),
            )
            for plane in PLANES
        ]
        heights = {
            key: None if self.base[f"{key}_m"] is None else self._column(inputs, f"{key}_m")
            for key in ("height_h1", "height_h")
        }
        result = wedge_probability(
            WedgeOrientations(*drawn, *face, *upper),
            *strengths,
            **heights,
            overhanging_face=self.base["overhanging_face"],
            unit_weight=self._column(inputs, "unit_weight_kN_m3") * 1e3,
            water=HoekBrayWater(self._column(inputs, "water_filled")),
            water_unit_weight=self._column(inputs, "water_unit_weight_kN_m3") * 1e3,
            seismic=Seismic(self._column(inputs, "seismic_coefficient"), self.base["seismic_direction"]),
        )
        return result, drawn

    def __call__(self, inputs: pd.DataFrame) -> pd.DataFrame:
        try:
            result, drawn = self.probability(inputs)
        except ValueError as error:
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
