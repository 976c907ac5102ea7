"""A sweep's `kinematics` base: for each sample (a face, a friction angle and sets, any of them
varied by the study), the probability that each kinematic mode is feasible, by Monte Carlo over the
sets' orientations (`bbmc.kinematics.probabilistic.mode_probabilities`: `orientation_draws` Fisher
draws of each set about its mean).

Each sample draws from its own generator, seeded by (the base's seed, the sample's number), so a
sample's result does not depend on the batch it runs in, the batch size or the worker. A study's
probability of a mode is then the mean over samples of these probabilities: the probability over
the inputs' distributions and the orientations together. With `orientation_draws: 1` each sample is
one draw, and its outputs are 0 or 1.

Outputs, one column per mode and set (pole modes) or pair of sets (line modes):
`<mode>.<set>` and `<mode>.<set a> x <set b>`, each a probability 0 to 1.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from bbmc.geometry.orientation import upward_pole
from bbmc.kinematics.config import FaceSection, LimitsSection
from bbmc.kinematics.modes import LINE_MODES, POLE_MODES
from bbmc.kinematics.probabilistic import mode_probabilities
from bbmc.scene.paths import set_path
from bbmc.sweep.models import ERROR, FAILED_RUN, OUTCOME, VALID


def output_column(mode: str, group: str) -> str:
    return f"{mode}.{group}"


def output_columns(base: dict) -> list[str]:
    """The outputs of a base, in mode_probabilities' order: each pole mode per set, then each line
    mode per pair of sets."""
    names = list(base["sets"])
    pairs = [f"{a} x {b}" for i, a in enumerate(names) for b in names[i + 1 :]]
    return [output_column(m, n) for n in names for m in POLE_MODES] + [
        output_column(m, p) for p in pairs for m in LINE_MODES
    ]


@dataclass(frozen=True)
class KinematicsModel:
    """The base's data (`bbmc.sweep.config.Kinematics`, dumped), evaluated sample by sample."""

    base: dict

    def _one(self, tree: dict, sample: int) -> dict[str, float]:
        names = list(tree["sets"])
        sets = [tree["sets"][name] for name in names]
        means = np.array([upward_pole(s["dip_deg"], s["dip_direction_deg"]) for s in sets])
        friction = [math.radians(s["friction_deg"] or tree["friction_deg"]) for s in sets]
        rows = mode_probabilities(
            means,
            [s["fisher_k"] for s in sets],
            FaceSection(**tree["face"]).face(),
            friction,
            LimitsSection(**tree["lateral_limits"]).limits(),
            samples=tree["orientation_draws"],
            rng=np.random.default_rng([tree["seed"], sample]),
            set_names=names,
        )
        return {output_column(r.mode, r.group): r.probability for r in rows}

    def __call__(self, inputs: pd.DataFrame) -> pd.DataFrame:
        rows = []
        for sample, values in inputs.iterrows():
            tree = copy.deepcopy(self.base)
            for path, value in values.items():
                set_path(tree, str(path), float(value))
            try:
                rows.append({**self._one(tree, int(sample)), ERROR: "", OUTCOME: VALID})
            except ValueError as error:
                rows.append({ERROR: f"{type(error).__name__}: {error}", OUTCOME: FAILED_RUN})
        columns = [*output_columns(self.base), ERROR, OUTCOME]
        return pd.DataFrame(rows, index=inputs.index).reindex(columns=columns)


def kinematics_summary(base: dict, samples: pd.DataFrame, valid: np.ndarray) -> dict[str, float]:
    """Each output's probability over the study (the mean over the valid samples) and its standard
    error (the samples' standard deviation / sqrt(n))."""
    values = {}
    for column in output_columns(base):
        x = samples.loc[valid, column].astype(float).to_numpy()
        values[f"probability.{column}"] = float(x.mean())
        values[f"standard_error.{column}"] = (
            float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else math.nan
        )
    return values
