"""`bbmc joints`: the example survey is made again by its script and fitted through the command line;
the fit must recover the distributions the script drew from, within tolerances from the sample sizes.
The corrections are checked against closed forms, quadrature and simulations made here.

Tolerances: four standard errors of each estimate at the sample's size (a miss has a chance of about
1e-4 for a normal estimate, 3e-4 for the Rayleigh-distributed angle of a mean pole):
* mean pole: the angle to the true pole, Rayleigh with sigma = 1/sqrt(n_eff K) (Fisher 1953);
  n_eff = (sum w)^2 / sum w^2 for the Terzaghi weights w;
* Fisher's K: relative standard error 1/sqrt(n_eff - 1) ((N - 1)/(N - R) is K times a chi^2 over its
  degrees of freedom, 2(N - 1));
* exponential mean: mean/sqrt(n) for spacings; for trace lengths mean/sqrt(2 n_0 + n_1), the Fisher
  information of the scanline likelihood (n_0 traces seen whole, n_1 with one end hidden);
* lognormal: its log-mean m and log-std s, standard errors s/sqrt(n) and s/sqrt(2n); for trace
  lengths n is the number seen whole only (traces with hidden ends carry less, so this is wider).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from scipy import integrate, stats

from bbmc.field import block
from bbmc.field import distributions as dist
from bbmc.field.analysis import fit_set
from bbmc.field.survey import read_survey
from bbmc.geometry.orientation import (
    dip_and_direction,
    line_direction,
    poles,
    section_trace,
    terzaghi_weights,
)
from bbmc.rockmass import RockMassConfig, generate
from stage_runs import ROOT, config_copy, field_script, refused, run_stage

FIELD = ROOT / "data" / "field"
SCRIPT = FIELD / "make_scanline_example.py"
EXAMPLE = FIELD / "scanline_example.csv"


def _script():
    return field_script("make_scanline_example")


TRUTH = _script().TRUTH


def _run(folder: Path, edit=lambda data: None, survey: Path | None = None):
    """`bbmc joints` on an edited copy of configs/joints.yaml (and another survey) into `folder`."""

    def change(data):
        if survey is not None:
            data["data"]["survey"] = str(survey)
        edit(data)

    config = config_copy(folder, "joints", change)
    return run_stage("joints", folder / "results", config), folder / "results" / "joints"


@pytest.fixture(scope="module")
def out(tmp_path_factory) -> Path:
    outcome, folder = _run(tmp_path_factory.mktemp("joints"))
    assert outcome.exit_code == 0, outcome.output
    return folder


@pytest.fixture(scope="module")
def survey() -> pd.DataFrame:
    return pd.read_csv(EXAMPLE, comment="#")


def _weights(rows: pd.DataFrame) -> np.ndarray:
    normals = poles(np.radians(rows["dip_deg"]), np.radians(rows["dip_direction_deg"]))
    return terzaghi_weights(normals, line_direction(0.0, 0.0), 3.86)


def _row(fits: pd.DataFrame, name: str, quantity: str, family: str) -> pd.Series:
    hit = fits[(fits["set"] == name) & (fits["quantity"] == quantity) & (fits["distribution"] == family)]
    assert len(hit) == 1
    return hit.iloc[0]


def _log_parameters(mean: float, std: float) -> tuple[float, float]:
    s2 = np.log1p((std / mean) ** 2)
    return np.log(mean) - s2 / 2.0, np.sqrt(s2)


# ---------------------------------------------------------------- the example survey


def test_the_example_survey_is_made_by_its_script(tmp_path):
    made = tmp_path / "made.csv"
    subprocess.run([sys.executable, str(SCRIPT), str(made)], check=True)
    assert made.read_bytes() == EXAMPLE.read_bytes()
    assert EXAMPLE.read_text().startswith("# SYNTHETIC")


def test_the_command_writes_its_files(out):
    names = {p.name for p in out.iterdir()}
    assert names == {
        "fits.csv",
        "sets.csv",
        "joint_sets.yaml",
        "histograms.png",
        "rose.png",
        "provenance.json",
    }


@pytest.mark.parametrize("name", sorted(TRUTH))
def test_the_orientation_is_recovered(out, survey, name):
    truth, rows = TRUTH[name], survey[survey["set"] == name]
    fitted = pd.read_csv(out / "sets.csv").set_index("set").loc[name]
    w = _weights(rows)
    n_eff = w.sum() ** 2 / np.sum(w**2)
    true_pole = poles(np.radians(truth["dip_deg"]), np.radians(truth["dip_direction_deg"]))
    pole = poles(np.radians(fitted["dip_deg"]), np.radians(fitted["dip_direction_deg"]))
    angle = np.arccos(min(1.0, abs(float(pole @ true_pole))))
    assert angle < 4.0 / np.sqrt(n_eff * truth["fisher_k"])
    assert abs(fitted["fisher_k"] / truth["fisher_k"] - 1.0) < 4.0 / np.sqrt(n_eff - 1.0)


@pytest.mark.parametrize("name", sorted(TRUTH))
def test_the_spacing_is_recovered_and_its_distribution_chosen(out, name):
    truth = TRUTH[name]["spacing_m"]
    fits = pd.read_csv(out / "fits.csv")
    chosen = fits[(fits["set"] == name) & (fits["quantity"] == "spacing_m") & fits["chosen"]].iloc[0]
    assert chosen["distribution"] == truth["distribution"]
    n = chosen["n"]
    if truth["distribution"] == "exponential":
        assert abs(chosen["mean"] - truth["mean"]) < 4.0 * truth["mean"] / np.sqrt(n)
    else:
        m, s = _log_parameters(chosen["mean"], chosen["std"])
        true_m, true_s = _log_parameters(truth["mean"], truth["std"])
        assert abs(m - true_m) < 4.0 * true_s / np.sqrt(n)
        assert abs(s - true_s) < 4.0 * true_s / np.sqrt(2.0 * n)


@pytest.mark.parametrize("name", sorted(TRUTH))
def test_the_trace_length_is_recovered_and_its_distribution_chosen(out, survey, name):
    truth = TRUTH[name]["trace_length_m"]
    ends = survey.loc[survey["set"] == name, "censored_ends"].to_numpy()
    fits = pd.read_csv(out / "fits.csv")
    chosen = fits[(fits["set"] == name) & (fits["quantity"] == "trace_length_m") & fits["chosen"]].iloc[0]
    assert chosen["distribution"] == truth["distribution"]
    assert chosen["n_censored"] == np.sum(ends > 0) > 0
    whole, one = np.sum(ends == 0), np.sum(ends == 1)
    if truth["distribution"] == "exponential":
        assert abs(chosen["mean"] - truth["mean"]) < 4.0 * truth["mean"] / np.sqrt(2 * whole + one)
    else:
        m, s = _log_parameters(chosen["mean"], chosen["std"])
        true_m, true_s = _log_parameters(truth["mean"], truth["std"])
        assert abs(m - true_m) < 4.0 * true_s / np.sqrt(whole)
        assert abs(s - true_s) < 4.0 * true_s / np.sqrt(2.0 * whole)


def test_the_fits_table_gives_every_candidate_with_its_aic(out):
    fits = pd.read_csv(out / "fits.csv")
    lengths = fits[fits["quantity"] != "dip_deg"]
    assert set(lengths["distribution"]) == set(dist.FAMILIES)
    assert lengths.groupby(["set", "quantity"]).size().eq(3).all()
    assert np.allclose(lengths["aic"], 2 * lengths["parameters"] - 2 * lengths["log_likelihood"])
    assert (lengths.groupby(["set", "quantity"])["delta_aic"].min() == 0).all()
    assert lengths.groupby(["set", "quantity"])["chosen"].sum().eq(1).all()
    spacing = lengths[lengths["quantity"] == "spacing_m"]
    assert spacing["ks_p_value"].between(0, 1).all()
    assert set(fits.loc[fits["quantity"] == "dip_deg", "distribution"]) == {"fisher"}


def test_the_joint_set_block_is_the_scenes_format(out):
    """The block reads as a rock mass's section azimuth and joint sets (`RockMassConfig`), and a rock
    mass made from it holds the fitted sets."""
    text = (out / "joint_sets.yaml").read_text()
    block = yaml.safe_load(text)
    sets = block["joint_sets"]
    fits = pd.read_csv(out / "fits.csv")
    fitted = pd.read_csv(out / "sets.csv").set_index("set")
    assert block["section_azimuth_deg"] == 180
    assert [s["name"] for s in sets] == ["J1", "J2"]
    for entry in sets:
        name = entry["name"]
        assert set(entry) == {"name", "orientation", "spacing_m", "trace_length_m", "persistence", "offset_m"}
        assert entry["orientation"]["dip_deg"] == pytest.approx(fitted.loc[name, "dip_deg"], abs=0.05)
        assert entry["orientation"]["fisher_k"] == pytest.approx(fitted.loc[name, "fisher_k"], rel=1e-3)
        trace = fits[(fits["set"] == name) & (fits["quantity"] == "trace_length_m") & fits["chosen"]].iloc[0]
        assert entry["trace_length_m"]["distribution"] == trace["distribution"]
        assert entry["trace_length_m"]["mean"] == pytest.approx(trace["mean"], rel=1e-3)
    spacing = _row(fits, "J1", "spacing_m", "exponential")
    assert sets[0]["persistence"] == 0.8
    assert sets[0]["spacing_m"] == {
        "distribution": "exponential",
        "mean": pytest.approx(0.8 * spacing["mean"], rel=1e-3),
    }
    profile = {
        "benches": {"height_m": 5, "face_angle_deg": 70, "berm_width_m": 2, "count": 1},
        "depth_m": 2,
        "toe_extent_m": 2,
        "crest_extent_m": 5,
    }
    mass = generate(RockMassConfig.model_validate(block | {"profile": profile}))
    assert {label.split(".")[-1] for labels in mass.edge_labels for label in labels} >= {"J1", "J2"}


# ---------------------------------------------------------------- the corrections, one by one


@pytest.mark.parametrize(
    ("family", "law", "lengths"),
    [
        ("exponential", stats.expon(scale=2.0), [0.1, 3.0, 40.0]),
        ("lognormal", stats.lognorm(0.5, scale=3.0), [0.2, 2.0, 5.0, 12.0, 30.0]),  # both branches
        ("lognormal", stats.lognorm(1.5, scale=0.7), [0.05, 1.0, 20.0, 200.0]),
        ("gamma", stats.gamma(2.5, scale=1.2), [0.1, 2.0, 8.0, 25.0]),  # x below and above the shape
        ("gamma", stats.gamma(0.6, scale=4.0), [0.01, 1.0, 30.0]),
    ],
)
def test_the_partial_mean_is_the_integral_of_the_survival_function(family, law, lengths):
    for length in lengths:
        by_quadrature = integrate.quad(law.sf, length, np.inf, epsabs=0, epsrel=1e-12, limit=400)[0]
        closed = np.exp(dist.log_partial_mean(family, law, np.array([length])))[0]
        assert closed == pytest.approx(by_quadrature, rel=1e-8)


def test_the_exponential_trace_length_has_its_closed_form():
    rng = np.random.default_rng(7)
    lengths = rng.gamma(2.0, 1.5, 300)
    ends = rng.integers(0, 3, 300)
    fitted = dist.fit_trace_lengths(lengths, ends)[0]
    expected = lengths.sum() / (2 * np.sum(ends == 0) + np.sum(ends == 1))
    assert fitted.family == "exponential"
    assert fitted.mean == pytest.approx(expected, rel=1e-6)


def test_without_the_size_bias_the_mean_trace_would_be_twice_too_long():
    """Traces a line meets have the density l f(l)/mean: for exponential traces of mean 2 m a gamma of
    shape 2. A plain fit of the exponential to them gives the mean 4 m; the scanline likelihood 2 m."""
    lengths = np.random.default_rng(11).gamma(2.0, 2.0, 4000)
    ours = dist.fit_trace_lengths(lengths, np.zeros(lengths.size, dtype=int))[0]
    plain = stats.expon.fit(lengths, floc=0)[1]
    tolerance = 4.0 * 2.0 / np.sqrt(2 * lengths.size)
    assert ours.mean == pytest.approx(2.0, abs=tolerance)
    assert plain == pytest.approx(4.0, abs=2 * tolerance)
    assert 0.0 < ours.ks_p_value <= 1.0


def test_the_spacing_takes_the_line_end_as_censored():
    rng = np.random.default_rng(3)
    spacings = rng.exponential(0.5, 100)
    fitted = dist.fit_spacings(spacings, 0.001, 0.3)[0]
    assert fitted.mean == pytest.approx((spacings.sum() + 0.3) / spacings.size, rel=1e-6)


def test_terzaghi_weights_are_one_over_cos_delta_capped():
    line = line_direction(0.0, 0.0)  # north, horizontal
    normals = poles(np.radians([90.0, 90.0, 90.0, 30.0]), np.radians([0.0, 60.0, 89.0, 0.0]))
    weights = terzaghi_weights(normals, line, 3.86)
    assert weights == pytest.approx([1.0, 2.0, 3.86, 1.0 / np.sin(np.radians(30.0))])


def test_a_plane_keeps_its_dip_and_direction_through_its_pole():
    for dip, direction in [(35.0, 170.0), (80.0, 300.0), (5.0, 10.0)]:
        back = np.degrees(dip_and_direction(-poles(np.radians(dip), np.radians(direction))))
        assert back == pytest.approx([dip, direction])


def test_the_trace_in_a_section_has_the_apparent_dip_and_spacing():
    dip, direction, section = np.radians(60.0), np.radians(200.0), np.radians(180.0)
    trace = section_trace(poles(dip, direction), section)
    assert np.tan(trace.apparent_dip) == pytest.approx(np.tan(dip) * abs(np.cos(direction - section)))
    assert trace.dips_towards == pytest.approx(section)
    strike_along = section_trace(poles(dip, np.radians(90.0)), section)  # strikes along the section
    assert strike_along.apparent_dip == pytest.approx(0.0, abs=1e-12)
    assert strike_along.spacing_factor == pytest.approx(np.cos(dip))


def test_lines_thinned_by_the_persistence_give_the_joints_spacing():
    """Lines spaced by the written lognormal, each a joint where a line normal to them crosses it with
    the chance k: the joints' spacing has the fitted mean and standard deviation."""
    joints = dist.Candidate("lognormal", stats.lognorm(0.55, scale=0.46), 0.0, 2, np.nan)
    k = 0.8
    mean, std = block.line_spacing(joints, k)
    rng = np.random.default_rng(5)
    s2 = np.log1p((std / mean) ** 2)
    lines = np.cumsum(rng.lognormal(np.log(mean) - s2 / 2, np.sqrt(s2), 400_000))
    spacing = np.diff(lines[rng.random(lines.size) < k])
    assert spacing.mean() == pytest.approx(joints.mean, rel=0.01)
    assert spacing.std() == pytest.approx(joints.std, rel=0.02)
    with pytest.raises(block.PersistenceError, match=r"give at least 0\.647"):
        block.line_spacing(joints, 0.5)


# ---------------------------------------------------------------- other surveys


def test_a_survey_without_dip_directions_takes_the_sets_mean_one(tmp_path, survey):
    plain = tmp_path / "no_directions.csv"
    survey.drop(columns="dip_direction_deg").to_csv(plain, index=False)

    def directions(data):
        for name in data["sets"]:
            data["sets"][name]["dip_direction_deg"] = TRUTH[name]["dip_direction_deg"]

    outcome, folder = _run(tmp_path, directions, plain)
    assert outcome.exit_code == 0, outcome.output
    fits = pd.read_csv(folder / "fits.csv")
    dips = fits[fits["quantity"] == "dip_deg"].set_index("set")
    assert set(dips["distribution"]) == {"normal"}
    j1, n = dips.loc["J1"], dips.loc["J1", "n"]
    sigma = 1.0 / np.sqrt(TRUTH["J1"]["fisher_k"])  # rad: a Fisher set's dip scatter
    assert abs(j1["mean"] - TRUTH["J1"]["dip_deg"]) < 4.0 * np.degrees(sigma) / np.sqrt(n)
    block_sets = yaml.safe_load((folder / "joint_sets.yaml").read_text())["joint_sets"]
    assert block_sets[0]["orientation"]["fisher_k"] == pytest.approx(
        1.0 / np.radians(j1["std"]) ** 2, rel=1e-3
    )
    assert block_sets[0]["orientation"]["dip_direction_deg"] == TRUTH["J1"]["dip_direction_deg"]


def test_two_joints_read_at_one_position_are_a_spacing_below_the_reading(tmp_path, survey):
    rows = survey[survey["set"] == "J1"].index[:2]
    survey.loc[rows[1], "position_m"] = survey.loc[rows[0], "position_m"]
    path = tmp_path / "shared.csv"
    survey.to_csv(path, index=False)
    outcome, folder = _run(tmp_path, survey=path)
    assert outcome.exit_code == 0, outcome.output
    spacing = _row(pd.read_csv(folder / "fits.csv"), "J1", "spacing_m", "exponential")
    assert spacing["n_censored"] == 2  # the line's end and the shared position


# ---------------------------------------------------------------- bad input: one line, exit 2, no files


def _survey_with(tmp_path: Path, change) -> Path:
    lines = EXAMPLE.read_text().splitlines()
    change(lines)
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def _cell(line: int, column: str, value: str):
    def change(lines):
        header = lines[2].split(",")
        cells = lines[line - 1].split(",")
        cells[header.index(column)] = value
        lines[line - 1] = ",".join(cells)

    return change


@pytest.mark.parametrize(
    ("line", "column", "value", "says"),
    [
        (7, "trace_length_m", "-1.2", "must be a trace length, > 0"),
        (8, "censored_ends", "3", "the number of hidden ends"),
        (9, "dip_deg", "95", "a dip, 0 to 90"),
        (10, "position_m", "100.5", "beyond the scanline's length of 100 m"),
        (11, "set", "J3", "set 'J3' is not among the config's sets (J1, J2)"),
        (12, "dip_direction_deg", "", "give every dip direction of a set, or none"),
        (13, "position_m", "x", "not a number"),
    ],
)
def test_a_bad_cell_names_the_file_line_and_column(tmp_path, line, column, value, says):
    path = _survey_with(tmp_path, _cell(line, column, value))
    outcome, folder = _run(tmp_path, survey=path)
    refused(outcome, folder, str(path), f"line {line}: column '{column}'", says)


def test_a_set_of_the_config_missing_from_the_survey_is_refused(tmp_path):
    outcome, folder = _run(tmp_path, lambda data: data["sets"].update({"J3": {"persistence": 1.0}}))
    refused(outcome, folder, "joints.yaml", "key 'sets.J3'", "no discontinuity of set 'J3'")


def test_a_set_with_too_few_traces_says_how_many_are_needed(tmp_path):
    def few(lines):
        kept = [line for line in lines[3:] if line.startswith("J1")]
        lines[3:] = kept + [line for line in lines[3:] if line.startswith("J2")][:9]

    path = _survey_with(tmp_path, few)
    outcome, folder = _run(tmp_path, survey=path)
    refused(outcome, folder, str(path), "set 'J2' has 9 discontinuities", "at least 10")


def test_a_persistence_too_low_for_the_spacing_is_refused(tmp_path):
    outcome, folder = _run(tmp_path, lambda data: data["sets"]["J2"].update({"persistence": 0.3}))
    refused(outcome, folder, "set 'J2'", "sets.J2.persistence", "give at least")


def test_a_survey_without_dip_directions_needs_the_sets_mean_one(tmp_path, survey):
    plain = tmp_path / "no_directions.csv"
    survey.drop(columns="dip_direction_deg").to_csv(plain, index=False)
    outcome, folder = _run(tmp_path, survey=plain)
    refused(outcome, folder, str(plain), "set 'J1' has none", "sets.J1.dip_direction_deg")


# ---------------------------------------------------------------- many surveys


@pytest.mark.slow
def test_over_many_surveys_the_estimates_centre_on_the_truth(tmp_path):
    """Fifty surveys drawn by the example's script with other seeds, fitted with a cap on Terzaghi's
    weights that never acts (100): the mean of each estimate lies within four standard errors of the
    mean (the estimates' own spread / sqrt 50) of the truth. A single survey cannot show a bias this
    small; the cap's own bias is left out on purpose (docs/field-data.md)."""
    script = _script()
    line = line_direction(0.0, 0.0)
    estimates: dict[str, list] = {name: [] for name in TRUTH}
    for seed in range(50):
        path = tmp_path / f"survey_{seed}.csv"
        script.make(path, seed)
        for name, survey in read_survey(path, 100.0, list(TRUTH)).items():
            fit = fit_set(survey, line, 100.0, 100.0, None)
            truth = TRUTH[name]
            spacing = next(c for c in fit.spacing if c.family == truth["spacing_m"]["distribution"])
            trace = next(c for c in fit.trace_length if c.family == truth["trace_length_m"]["distribution"])
            o = fit.orientation
            estimates[name].append(
                [
                    np.degrees(o.dip),
                    np.degrees(o.dip_direction),
                    o.fisher_k,
                    spacing.mean,
                    trace.mean,
                    trace.std,
                ]
            )
    for name, rows in estimates.items():
        truth, values = TRUTH[name], np.array(rows)
        expected = [
            truth["dip_deg"],
            truth["dip_direction_deg"],
            truth["fisher_k"],
            truth["spacing_m"]["mean"],
            truth["trace_length_m"]["mean"],
            truth["trace_length_m"].get("std", truth["trace_length_m"]["mean"]),
        ]
        error = np.abs(values.mean(axis=0) - expected)
        assert np.all(error < 4.0 * values.std(axis=0, ddof=1) / np.sqrt(len(values))), (name, error)
