"""A study of kinematics (`bbmc sweep` with a `kinematics` base, `bbmc.sweep.kinematic_model`): each
sample's probabilities do not move with the batch size or the number of workers (each sample draws
from its own stream), a set concentrated about a critical mean gives probability 1 and one about a
safe mean 0, and the study's probability is the mean of its samples'."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from bbmc import api

BASE = {
    "kind": "kinematics",
    "face": {"dip_deg": 65, "dip_direction_deg": 180},
    "friction_deg": 30,
    "sets": {
        "J1": {"dip_deg": 35, "dip_direction_deg": 165, "fisher_k": 50},
        "J2": {"dip_deg": 60, "dip_direction_deg": 220, "fisher_k": 35},
        "J3": {"dip_deg": 55, "dip_direction_deg": 130, "fisher_k": 35},
    },
    "orientation_draws": 200,
}


def _study(batch_size: int, samples: int = 24, **base) -> dict:
    return {
        "name": "kinematics",
        "base": {**BASE, **base},
        "variables": [{"path": "friction_deg", "distribution": "normal", "mean": 30, "std": 3}],
        "sampling": {"method": "latin_hypercube", "samples": samples, "seed": 3},
        "batch_size": batch_size,
    }


def _samples(result) -> pd.DataFrame:
    return result.tables["samples"]


def test_a_samples_probabilities_do_not_move_with_the_batch_size_or_the_workers():
    one = _samples(api.study(_study(batch_size=24), workers=1))
    many = _samples(api.study(_study(batch_size=5), workers=2))
    pd.testing.assert_frame_equal(one, many)
    assert one["planar_sliding.J1"].between(0, 1).all()
    assert one["planar_sliding.J1"].std() > 0  # the draws and the friction vary it


def test_the_studys_probability_is_the_mean_of_its_samples_and_has_its_standard_error():
    result = api.study(_study(batch_size=10), workers=1)
    summary = result.tables["summary"].set_index("quantity")["value"]
    column = _samples(result)["wedge_sliding.J2 x J3"]
    assert summary["probability.wedge_sliding.J2 x J3"] == pytest.approx(column.mean(), rel=1e-12)
    assert summary["standard_error.wedge_sliding.J2 x J3"] == pytest.approx(
        column.std(ddof=1) / np.sqrt(column.size), rel=1e-12
    )


def test_concentrated_sets_give_the_classification_of_their_means():
    """K = 1e7 (spread about 0.02 deg): J1 35/165 on the 65/180 face with phi 25 to 35 deg is planar
    sliding every time (dip 35 > phi, daylighting, 15 deg off the face's dip direction), J2 60/220 is
    40 deg off it (outside the 20 deg limits), never."""
    sets = {k: {**v, "fisher_k": 1e7} for k, v in BASE["sets"].items()}
    study = _study(batch_size=24, sets=sets)
    study["variables"][0] = {"path": "friction_deg", "distribution": "uniform", "min": 25, "max": 34}
    samples = _samples(api.study(study, workers=1))
    assert (samples["planar_sliding.J1"] == 1.0).all()
    assert (samples["planar_sliding.J2"] == 0.0).all()
