"""The sweep's `wedge` base against `bbmc wedge`: sample for sample, the base with each sample's values
gives the FS that the deterministic path (`bbmc.slope.wedge.cases.analyse_case`, the full geometry) gives
for that wedge, for Mohr-Coulomb, Barton-Bandis (scaled to the line of intersection, with waviness),
bolts active and passive with an external force and a given seismic direction, and a tension crack;
and the keys it refuses."""

from __future__ import annotations

import copy

import numpy as np
import pandas as pd
import pytest

from bbmc import api
from bbmc.config import ConfigError
from bbmc.scene.paths import set_path
from bbmc.slope.wedge.analysis import WedgeOrientations
from bbmc.slope.wedge.cases import analyse_case
from bbmc.slope.wedge.geometry import WedgeReason, wedge_geometries
from bbmc.slope.wedge.probability import intersection_lengths
from bbmc.stages import wedge as stage
from bbmc.sweep.config import Config
from bbmc.sweep.models import FAILED_RUN
from bbmc.sweep.wedge_model import WedgeModel

MC = {"law": "mohr_coulomb", "cohesion_kPa": 20.0, "friction_deg": 30.0}
BB = {
    "law": "barton_bandis",
    "jrc": 8.0,
    "jcs_MPa": 60.0,
    "phi_b_deg": 28.0,
    "waviness_deg": 3.0,
    "field_length_m": "intersection",
}
SLOPE = {
    "face": {"dip_deg": 65.0, "dip_direction_deg": 185.0},
    "upper_surface": {"dip_deg": 12.0, "dip_direction_deg": 195.0},
    "height_h1_m": 30.48,
    "unit_weight_kN_m3": 25.13,
    "water": {"model": "hoek_bray", "filled": 0.5},
}
# Each case: the base's changes, and the paths varied with their ranges (uniform per sample).
CASES = {
    "mohr_coulomb": (
        {"plane_1": {"strength": MC}, "plane_2": {"strength": {**MC, "cohesion_kPa": 40.0}}},
        {
            "plane_1.strength.friction_deg": (15, 40),
            "plane_2.strength.cohesion_kPa": (0, 80),
            "plane_1.dip_deg": (35, 55),
            "water.filled": (0, 1),
            "unit_weight_kN_m3": (22, 28),
        },
    ),
    "barton_bandis": (
        {
            "plane_1": {"strength": BB},
            "plane_2": {"strength": {**BB, "field_length_m": 2.0}},
            "seismic": {"coefficient": 0.05, "direction": "horizontal"},
        },
        {
            "plane_1.strength.jrc": (2, 16),
            "plane_2.strength.jcs_MPa": (20, 120),
            "plane_1.strength.phi_b_deg": (24, 34),
            "plane_2.strength.field_length_m": (0.5, 20),
            "plane_2.dip_direction_deg": (225, 245),
            "seismic.coefficient": (0, 0.2),
        },
    ),
    "bolts": (
        {
            "plane_1": {"strength": MC},
            "plane_2": {"strength": BB},
            "seismic": {"coefficient": 0.1, "direction": "given", "trend_deg": 200.0, "plunge_deg": 10.0},
            "forces": [{"magnitude_kN": 500.0, "trend_deg": 10.0, "plunge_deg": -20.0}],
            "bolts": [
                {"capacity_kN": 200.0, "trend_deg": 10.0, "plunge_deg": 15.0, "count": 4},
                {"capacity_kN": 150.0, "trend_deg": 20.0, "plunge_deg": 25.0, "count": 6, "form": "passive"},
            ],
        },
        {
            "bolts.0.capacity_kN": (0, 800),
            "bolts.1.trend_deg": (0, 40),
            "forces.0.magnitude_kN": (0, 2000),
            "seismic.trend_deg": (150, 250),
            "seismic.plunge_deg": (-10, 30),
            "plane_2.strength.jrc": (2, 16),
        },
    ),
    "crack": (
        {
            "plane_1": {"strength": BB},
            "plane_2": {"strength": MC},
            "tension_crack": {"dip_deg": 70.0, "dip_direction_deg": 165.0, "distance_m": 12.0},
            "water": {"model": "pressures", "plane_1_kPa": 30.0, "plane_2_kPa": 20.0, "crack_kPa": 40.0},
            "bolts": [{"capacity_kN": 300.0, "trend_deg": 5.0, "plunge_deg": 20.0, "count": 3}],
        },
        {
            "tension_crack.distance_m": (4, 30),
            "water.crack_kPa": (0, 100),
            "plane_1.strength.jrc": (2, 16),
            "plane_1.dip_deg": (40, 50),
        },
    ),
}


def _base(changes: dict) -> dict:
    planes = {
        "plane_1": {"dip_deg": 45.0, "dip_direction_deg": 105.0},
        "plane_2": {"dip_deg": 70.0, "dip_direction_deg": 235.0},
    }
    base = {"kind": "wedge", **copy.deepcopy(SLOPE), **copy.deepcopy(planes)}
    for key, value in changes.items():
        base[key] = {**base[key], **value} if key in planes else value
    return base


def _model(base: dict, varied: dict[str, tuple[float, float]]) -> WedgeModel:
    """The sweep's model of `base`, validated in a study varying `varied` (uniform over each range)."""
    variables = [
        {"path": p, "distribution": "uniform", "min": lo, "max": hi} for p, (lo, hi) in varied.items()
    ]
    study = {
        "name": "t",
        "base": base,
        "variables": variables,
        "sampling": {"method": "monte_carlo", "samples": 30},
    }
    return WedgeModel(Config.model_validate(study).base)


@pytest.mark.parametrize("name", CASES)
def test_each_sample_is_the_deterministic_wedge_of_its_values(name):
    """30 samples, each with its own values of the varied keys: the base's FS (fast path, or the full
    geometry with a crack) is `analyse_case`'s for a `bbmc wedge` config of those values, to 1e-9, and
    a wedge that does not form is so in both."""
    changes, varied = CASES[name]
    base = _base(changes)
    model = _model(base, varied)
    rng = np.random.default_rng(3)
    inputs = pd.DataFrame({p: rng.uniform(lo, hi, 30) for p, (lo, hi) in varied.items()})
    out = model(inputs)
    assert (out["outcome"] != FAILED_RUN).all()
    for i, row in inputs.iterrows():
        tree = {k: v for k, v in copy.deepcopy(base).items() if k != "kind"}
        for path, value in row.items():
            set_path(tree, path, float(value))
        config = stage.Config.model_validate(tree)
        case = analyse_case(stage.setting(config), stage.plane(config.plane_1), stage.plane(config.plane_2))
        assert out.loc[i, "wedge_reason"] == WedgeReason(int(case.geometry.reason)).name.lower()
        if case.analysis is None:
            assert np.isnan(out.loc[i, "factor_of_safety"])
            continue
        assert out.loc[i, "factor_of_safety"] == pytest.approx(
            float(case.analysis.factor_of_safety), rel=1e-9
        )
    assert (out["wedge_reason"] == "formed").sum() >= 20  # the comparison is mostly of formed wedges


def test_intersection_lengths_are_the_full_geometrys():
    """|OT| = H / |l_z| from the fast path equals the full geometry's intersection_length (and O R with
    a crack) on random wedges, NaN where they do not form."""
    rng = np.random.default_rng(5)
    n = 2000
    orientations = WedgeOrientations(
        np.radians(rng.uniform(20, 80, n)), np.radians(rng.uniform(60, 160, n)),
        np.radians(rng.uniform(20, 80, n)), np.radians(rng.uniform(200, 300, n)),
        np.radians(65.0), np.radians(185.0), np.radians(12.0), np.radians(195.0),
    )  # fmt: skip
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        full = wedge_geometries(*orientations.angles(), height_h1=30.0)
    fast = intersection_lengths(orientations, height_h1=30.0)
    assert 0 < np.isnan(full.intersection_length).sum() < n
    assert np.allclose(fast, full.intersection_length, rtol=1e-12, equal_nan=True)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        (
            {"plane_1": {"dip_deg": 45, "dip_direction_deg": 105, "friction_deg": 30}},
            "base.plane_1.friction_deg",
        ),
        ({"shotcrete": {"thickness_m": 0.1, "shear_strength_kPa": 1000}}, "base.shotcrete"),
        ({"water_filled": 0.5}, "base.water_filled"),
    ],
)
def test_a_key_the_base_does_not_take_is_refused_naming_it(change, key):
    base = _base({"plane_1": {"strength": MC}, "plane_2": {"strength": MC}})
    base.update(change)
    config = {
        "name": "t",
        "base": base,
        "variables": [{"path": "water.filled", "distribution": "uniform", "min": 0, "max": 1}],
        "sampling": {"method": "monte_carlo", "samples": 10},
    }
    with pytest.raises(ConfigError, match=rf"key '{key}': unknown key") as refused:
        api.study(config, workers=1)
    assert "\n" not in str(refused.value)


def test_a_barton_bandis_study_truncates_jrc_to_its_range_and_runs():
    """A varied JRC is drawn within 0 to 20 (its key's range, `bbmc.sweep.ranges`) and each plane's B-B
    strength follows it: without a scale correction the FS rises with plane 1's JRC at fixed geometry
    (with one it need not: JRC_n falls faster for a rougher joint, Barton & Bandis 1982)."""
    unscaled = {key: value for key, value in BB.items() if key != "field_length_m"}
    base = _base({"plane_1": {"strength": unscaled}, "plane_2": {"strength": unscaled}})
    config = {
        "name": "bb",
        "base": base,
        "variables": [{"path": "plane_1.strength.jrc", "distribution": "normal", "mean": 18, "std": 4}],
        "sampling": {"method": "latin_hypercube", "samples": 200, "seed": 2},
    }
    samples = api.study(config, workers=1).samples
    jrc, fs = samples["plane_1.strength.jrc"], samples["factor_of_safety"]
    assert (samples["outcome"] == "valid").all() and jrc.max() <= 20.0 and jrc.min() >= 0.0
    rising = fs.to_numpy()[np.argsort(jrc.to_numpy())]
    assert np.all(np.diff(rising) >= 0.0) and rising[-1] > 1.5 * rising[0]  # flat where phi_max caps it


def test_a_sample_whose_values_the_law_refuses_fails_alone():
    """phi_max + waviness varied past 90 deg on some samples: those samples fail with the law's error,
    the others of the batch are the wedges they are alone."""
    base = _base({"plane_1": {"strength": BB}, "plane_2": {"strength": MC}})
    model = _model(base, {"plane_1.strength.waviness_deg": (0, 40)})
    inputs = pd.DataFrame({"plane_1.strength.waviness_deg": np.linspace(0.0, 39.0, 40)})
    out = model(inputs)
    refused = inputs["plane_1.strength.waviness_deg"] + BB.get("phi_max_deg", 70.0) >= 90.0
    assert 0 < refused.sum() < 40
    assert (out.loc[refused, "outcome"] == FAILED_RUN).all()
    assert out.loc[refused, "error"].str.contains("max_friction \\+ waviness").all()
    alone = pd.concat([model(inputs.iloc[[i]]) for i in np.flatnonzero(~refused)])
    pd.testing.assert_frame_equal(out.loc[~refused], alone, check_dtype=False)


def test_a_size_limit_in_a_study_is_refused_naming_it():
    """`bbmc wedge`'s trace_length_m on a plane: the study's fast path does not scale wedges, so the base
    refuses it in one line rather than ignore it."""
    base = _base({"plane_1": {"strength": MC, "trace_length_m": 10.0}, "plane_2": {"strength": MC}})
    config = {
        "name": "t",
        "base": base,
        "variables": [{"path": "water.filled", "distribution": "uniform", "min": 0, "max": 1}],
        "sampling": {"method": "monte_carlo", "samples": 10},
    }
    with pytest.raises(
        ConfigError, match=r"key 'base.plane_1.trace_length_m, base.plane_1.persistence_m'"
    ) as refused:
        api.study(config, workers=1)
    assert "\n" not in str(refused.value)
