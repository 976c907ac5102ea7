"""bbmc.slope.wedge.probability and the sweep's `wedge` base: P_f against the closed form through the
wedge factor, the orientation draws against their sets' K, and a study's probabilities and invalid
samples."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from numpy import radians as R
from scipy import stats

from bbmc import api
from bbmc.config import ConfigError
from bbmc.geometry.orientation import fisher_orientation, poles
from bbmc.slope.wedge.analysis import WedgeOrientations, analyse_wedges
from bbmc.slope.wedge.geometry import WedgeReason, wedge_geometry
from bbmc.slope.wedge.mechanics import MohrCoulomb, SlidingMode
from bbmc.slope.wedge.probability import PlaneScatter, scattered_orientations, wedge_probability
from bbmc.sweep.streams import sample_uniforms

# Hoek & Bray's classic wedge (issue 35; limiting phi 21.91 deg) and 3DEC's sliding wedge's planes (40/130,
# 60/220; limiting phi 33.36 deg) on a face 70/175 under an upper surface 10/180, each with its mean phi.
GEOMETRIES = {
    "classic": (WedgeOrientations(R(45), R(105), R(70), R(235), R(65), R(185), R(12), R(195)), 25.0),
    "3dec": (WedgeOrientations(R(40), R(130), R(60), R(220), R(70), R(175), R(10), R(180)), 36.0),
}


@pytest.mark.parametrize("name", GEOMETRIES)
def test_pf_with_one_normal_phi_against_the_wedge_factor_closed_form(name):
    """Dry, c = 0, one phi on both planes: FS = K tan phi / tan psi_i (Hoek & Bray 1981, ch. 8), so
    P_f = P(phi < atan(tan psi_i / K)) = Phi((atan(tan psi_i / K) - mu) / sigma) exactly, phi normal and
    not truncated (sigma 4 deg: phi < 0 has probability < 1e-9). K and psi_i from the short solution's
    angles, not the vector solution. Tolerance: 3 binomial standard errors of 200 000 draws."""
    orientations, mean_deg = GEOMETRIES[name]
    n, mu, sigma = 200_000, R(mean_deg), R(4)
    phi = mu + sigma * np.random.default_rng(7).standard_normal(n)
    strength = MohrCoulomb(0.0, phi)
    result = wedge_probability(orientations, strength, strength, unit_weight=25e3, height_h1=30.0)
    short = wedge_geometry(*orientations.angles(), height_h1=30.0)
    limit = math.atan(math.tan(short.plunge) / short.short_solution.wedge_factor)
    exact = stats.norm.cdf((limit - mu) / sigma)
    assert 0.05 < exact < 0.95  # the test can fail both ways
    assert np.all(result.mode == SlidingMode.BOTH)
    assert result.formed == n
    assert result.probability_of_sliding == result.probability_of_failure
    assert abs(result.probability_of_failure - exact) < 3.0 * math.sqrt(exact * (1.0 - exact) / n)


@pytest.mark.parametrize(("dip", "direction", "kappa"), [(45, 105, 10.0), (70, 235, 50.0), (86, 10, 200.0)])
def test_orientation_sampling_reproduces_each_sets_k(dip, direction, kappa):
    """The drawn planes' poles give back the set's K by bbmc's one estimator (fisher_orientation: K =
    (N - 1) / (N - R)) within 4 % (the estimate's relative standard deviation is 1 / sqrt(N - 1) = 0.7 %
    at N = 20 000), and its mean plane within 0.5 deg; a set near vertical (86 deg) draws poles on both
    sides of the horizontal, each taken as its upward pole's plane (dips 0 to 90 deg)."""
    scatter = PlaneScatter(R(dip), R(direction), fisher_k=kappa)
    drawn_dip, drawn_direction = scatter.sample(20_000, np.random.default_rng(3))
    assert np.all((drawn_dip >= 0.0) & (drawn_dip <= np.pi / 2.0))
    fitted = fisher_orientation(poles(drawn_dip, drawn_direction), np.ones(drawn_dip.size))
    assert fitted.fisher_k == pytest.approx(kappa, rel=0.04)
    mean = poles(R(dip), R(direction))
    assert math.degrees(math.acos(min(abs(float(fitted.normal @ mean)), 1.0))) < 0.5


def test_normal_dips_beyond_vertical_are_the_plane_from_its_other_side():
    """A normal dip drawn past 90 deg is the same plane with dip 180 - dip towards the opposite
    direction: every dip is 0 to 90 deg and each drawn plane has the pole of the drawn (dip, direction)
    up to sign (checked by rebuilding it from a second draw of the same generator)."""
    scatter = PlaneScatter(R(85), R(30), dip_std=R(5), dip_direction_std=R(3))
    dip, direction = scatter.sample(5_000, np.random.default_rng(11))
    rng = np.random.default_rng(11)
    raw_dip, raw_direction = (
        R(85) + R(5) * rng.standard_normal(5_000),
        R(30) + R(3) * rng.standard_normal(5_000),
    )
    assert np.all((dip >= 0.0) & (dip <= np.pi / 2.0))
    assert np.any(raw_dip > np.pi / 2.0)
    cosines = np.abs(np.sum(poles(dip, direction) * poles(raw_dip, raw_direction), axis=1))
    assert np.allclose(cosines, 1.0, atol=1e-12)


def test_scattered_wedges_count_those_that_do_not_form_apart():
    """Wide scatter: some wedges do not form; P_f counts every sample, the probability of sliding the
    formed ones; the reasons add up to the samples."""
    plane_1, plane_2 = PlaneScatter(R(45), R(105), fisher_k=15.0), PlaneScatter(R(70), R(235), fisher_k=15.0)
    orientations = scattered_orientations(
        plane_1, plane_2, (R(65), R(185)), (R(12), R(195)), 20_000, np.random.default_rng(5)
    )
    strength = MohrCoulomb(0.0, R(30))
    result = wedge_probability(orientations, strength, strength, unit_weight=25e3, height_h1=30.0)
    counts = result.reason_counts()
    assert 0 < result.formed < result.samples
    assert sum(counts.values()) == result.samples and counts[WedgeReason.FORMED] == result.formed
    assert np.all(np.isnan(result.factor_of_safety[result.reason != WedgeReason.FORMED]))
    assert result.probability_of_failure == pytest.approx(result.failed / result.samples)
    assert result.probability_of_sliding == pytest.approx(result.failed / result.formed)
    assert result.probability_of_failure < result.probability_of_sliding


KEYS = ("dip_deg", "dip_direction_deg")


def _mc(friction_deg: float) -> dict:
    return {"law": "mohr_coulomb", "friction_deg": friction_deg}


def _study_config(**base) -> dict:
    return {
        "name": "wedge_test",
        "base": {
            "kind": "wedge",
            "plane_1": {"dip_deg": 45, "dip_direction_deg": 105, "fisher_k": 15, "strength": _mc(20)},
            "plane_2": {"dip_deg": 70, "dip_direction_deg": 235, "fisher_k": 15, "strength": _mc(30)},
            "face": {"dip_deg": 65, "dip_direction_deg": 185},
            "upper_surface": {"dip_deg": 12, "dip_direction_deg": 195},
            "height_h1_m": 30.48,
            "unit_weight_kN_m3": 26.0,
            **base,
        },
        "variables": [
            {"path": "plane_1.strength.friction_deg", "distribution": "normal", "mean": 25, "std": 4},
            {"path": "plane_2.strength.friction_deg", "distribution": "normal", "mean": 25, "std": 4},
        ],
        "sampling": {"method": "monte_carlo", "samples": 4000, "seed": 1},
        "batch_size": 1000,
    }


def test_a_wedge_study_gives_pf_and_counts_the_wedges_that_do_not_form():
    """Through bbmc.api.study: the invalid samples are the wedges that do not form (NaN FS, their reason
    named), counted by reason; probability_of_failure is over the formed wedges (Swedge's probability of
    sliding), probability_of_failure_all_samples over every sample, each from the samples' own FS."""
    result = api.study(_study_config(), workers=1)
    samples = result.samples
    summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
    invalid = samples["outcome"] == "invalid"
    formed = samples["wedge_reason"] == "formed"
    failed = int((samples.loc[formed, "factor_of_safety"] < 1.0).sum())
    assert invalid.sum() > 0 and (invalid == ~formed).all()
    assert samples.loc[invalid, "factor_of_safety"].isna().all()
    assert samples.loc[invalid, "error"].str.startswith("the wedge does not form").all()
    assert summary["invalid_samples"] == invalid.sum()
    reasons = {k: v for k, v in summary.items() if k.startswith("invalid_samples.")}
    assert sum(reasons.values()) == invalid.sum()
    assert summary["probability_of_failure"] == pytest.approx(failed / formed.sum())
    assert summary["probability_of_sliding"] == summary["probability_of_failure"]
    assert summary["probability_of_failure_all_samples"] == pytest.approx(failed / len(samples))
    assert summary["pf_all_samples_ci_low"] < summary["probability_of_failure_all_samples"]
    assert summary["pf_all_samples_ci_high"] > summary["probability_of_failure_all_samples"]
    assert "fs_at_mean_inputs" not in summary  # a scattered wedge has no one wedge at the mean
    drawn = [np.radians(samples[f"plane_{i}.{key}_drawn"].to_numpy()) for i in (1, 2) for key in KEYS]
    again = analyse_wedges(
        WedgeOrientations(*drawn, R(65), R(185), R(12), R(195)),
        *(MohrCoulomb(0.0, R(samples[f"plane_{i}.strength.friction_deg"].to_numpy())) for i in (1, 2)),
        unit_weight=26e3,
        height_h1=30.48,
    )  # the full geometry: each sample's FS is the wedge it reports, to rounding
    assert np.allclose(again.factor_of_safety, samples["factor_of_safety"], rtol=1e-9, equal_nan=True)


def test_a_wedge_study_with_varied_means_and_the_draws_repeat():
    """A mean dip varied per sample with Fisher scatter about it runs (sample by sample draws), and the
    same study gives the same samples again (each sample's draws from its own uniforms)."""
    config = _study_config()
    config["variables"].append({"path": "plane_1.dip_deg", "distribution": "uniform", "min": 40, "max": 50})
    config["sampling"]["samples"] = 300
    first, again = api.study(config, workers=1), api.study(config, workers=1)
    assert first.samples["factor_of_safety"].equals(again.samples["factor_of_safety"])
    assert first.samples["plane_1.dip_deg_drawn"].nunique() == 300


def test_a_wedge_base_needs_exactly_one_height():
    with pytest.raises(ConfigError, match=r"key 'base.height_h1_m, base.height_m': give exactly one$"):
        api.study(_study_config(height_m=40.0), workers=1)


def test_a_samples_wedge_does_not_move_with_the_batch_size_or_the_workers():
    """Each sample draws its planes from its own uniforms (`bbmc.sweep.streams`), so batches of 1,000
    on one process and of 37 on two give the same samples to the bit."""
    config = _study_config()
    config["sampling"]["samples"] = 400
    one = api.study(config, workers=1).samples
    config["batch_size"] = 37
    many = api.study(config, workers=2).samples
    pd.testing.assert_frame_equal(one, many)


def test_sample_uniforms_are_the_samples_own_and_uniform():
    """The uniforms of a sample do not depend on which other samples are drawn with it, and 10^5 of
    them pass a KS test against the uniform law (p > 1e-3) in each of the four streams."""
    samples = np.arange(100_000)
    for stream in range(4):
        u = sample_uniforms(7, samples, stream)
        assert np.array_equal(u[[5, 77, 99_999]], sample_uniforms(7, np.array([5, 77, 99_999]), stream))
        assert stats.kstest(u, "uniform").pvalue > 1e-3
        assert u.min() > 0.0 and u.max() < 1.0
