"""The geometry's share of the variance of FS on a crossed design (bbmc.sweep.shares), the crossed design
itself, and a realization's seed left out of the rank correlations and Sobol' indices.

Synthetic arrays FS[r, s] = 1 + a_r + b_s + e_rs with a ~ N(0, s_a^2), b ~ N(0, s_b^2), e ~ N(0, s_e^2)
have the known share s_a^2 / (s_a^2 + s_b^2 + s_e^2). Every tolerance is stated where it is used; the
generators are seeded, so each test is deterministic.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner
from scipy import integrate, stats

from bbmc.cli import main
from bbmc.sweep import design, report, shares
from bbmc.sweep.config import Config
from bbmc.sweep.models import ERROR, FS, OUTCOME
from bbmc.sweep.outcomes import Outcomes

ROOT = Path(__file__).resolve().parents[1]
PLANAR = ROOT / "configs" / "sweeps" / "planar_block.yaml"


def _synthetic(rng, n: int, m: int, variances=(1.0, 0.5, 0.5), replicates: int = 1) -> np.ndarray:
    s_a, s_b, s_e = np.sqrt(variances)
    a = rng.normal(0.0, s_a, (replicates, n, 1))
    b = rng.normal(0.0, s_b, (replicates, 1, m))
    return 1.0 + a + b + rng.normal(0.0, s_e, (replicates, n, m))


def test_the_anova_estimators_are_unbiased_where_the_plain_ratio_is_not():
    """4000 synthetic 8 x 4 arrays (s^2 = 1, 0.5, 0.5; share 0.5): each variance estimate's mean lies
    within 4 Monte Carlo standard errors of its truth (measured 0.976, 0.515, 0.502: 2.5, 2.0 and 0.8
    standard errors). The plain Var_r(row mean) / Var(all runs) averages 0.601: 0.1 too much, 35
    standard errors (tested above 20), as the module docstring says it must."""
    fs = _synthetic(np.random.default_rng(1), 8, 4, replicates=4000)
    estimates = shares.components(fs)
    error = estimates.std(axis=0, ddof=1) / math.sqrt(len(estimates))
    assert np.all(np.abs(estimates.mean(axis=0) - [1.0, 0.5, 0.5]) <= 4 * error)
    plain = fs.mean(axis=2).var(axis=1, ddof=1) / fs.reshape(4000, -1).var(axis=1, ddof=1)
    assert plain.mean() - 0.5 > 20 * plain.std(ddof=1) / math.sqrt(4000)


def test_an_additive_fs_gives_the_sample_variances_exactly():
    """FS = a_r + b_s (no interaction): the residual is 0, so the estimates are the sample variances of
    a and b (ddof 1) and the share var(a) / (var(a) + var(b)), to rounding."""
    rng = np.random.default_rng(2)
    a, b = rng.normal(0, 2.0, 12), rng.normal(0, 1.0, 7)
    result = shares.geometry_share((a[:, None] + b[None, :]).ravel(), np.zeros(84, dtype=bool), 12, 0)
    assert result.variances == pytest.approx([a.var(ddof=1), b.var(ddof=1), 0.0], abs=1e-12)
    assert result.shares[0] == pytest.approx(a.var(ddof=1) / (a.var(ddof=1) + b.var(ddof=1)), rel=1e-12)


def test_the_bootstrap_interval_covers_the_share_at_its_stated_rate():
    """200 synthetic 20 x 10 arrays of share 0.5, each with its own bootstrap seed: the 95 % interval
    covers 0.5 in a fraction within 4 binomial standard errors of 0.95 (sqrt(0.95 0.05 / 200) = 0.015;
    measured 0.935)."""
    rng = np.random.default_rng(5)
    covered = 0
    for k in range(200):
        result = shares.geometry_share(_synthetic(rng, 20, 10).ravel(), np.zeros(200, dtype=bool), 20, k)
        low, high = result.share_interval[:, 0]
        covered += low <= 0.5 <= high
    assert abs(covered / 200 - 0.95) <= 4 * math.sqrt(0.95 * 0.05 / 200)


def test_a_realization_with_a_run_without_fs_is_left_out_whole():
    """Realization 2 of 6 has one failed run: the share is that of the 5 complete realizations, and the
    table says 5 used, 1 left out, 24 runs. With a single complete realization there is no share."""
    fs = _synthetic(np.random.default_rng(3), 6, 4)[0]
    excluded = np.zeros(fs.shape, dtype=bool)
    excluded[2, 1] = True
    fs_missing = fs.copy()
    fs_missing[2, 1] = np.nan
    result = shares.geometry_share(fs_missing.ravel(), excluded.ravel(), 6, 0)
    assert result.variances == pytest.approx(shares.components(np.delete(fs, 2, axis=0)), rel=1e-12)
    table = result.table().set_index("quantity")["value"]
    assert (table["realizations"], table["realizations_left_out"], table["runs"]) == (5, 1, 24)
    assert table[["geometry_share", "other_inputs_share", "interaction_share"]].sum() == pytest.approx(1.0)
    excluded[1:, 0] = True
    with pytest.raises(ValueError, match="1 of 6 realizations have an FS in every run"):
        shares.geometry_share(fs.ravel(), excluded.ravel(), 6, 0)


def test_the_crossed_design_pairs_every_draw_with_every_realization():
    """5 realizations x 4 draws by Latin hypercube: row r m + s holds realization r's seed and
    persistence and draw s's friction; each group is a Latin hypercube of its own (one point in each
    stratum), and the same seed gives the same design."""
    geometry = [
        ("seed", design.marginal("realization")),
        ("persistence", design.marginal("uniform", min=0, max=1)),
    ]
    others = [("friction", design.marginal("uniform", min=30, max=40))]
    table = design.crossed_table(geometry, others, 5, 4, "latin_hypercube", 7)
    assert list(table.columns) == ["seed", "persistence", "friction"] and len(table) == 20
    grid = {name: table[name].to_numpy().reshape(5, 4) for name in table.columns}
    assert np.all(grid["seed"] == grid["seed"][:, :1]) and np.all(
        grid["persistence"] == grid["persistence"][:, :1]
    )
    assert np.all(grid["friction"] == grid["friction"][:1, :])
    assert sorted(np.floor(grid["persistence"][:, 0] * 5)) == [0, 1, 2, 3, 4]
    assert sorted(np.floor((grid["friction"][0] - 30) / 10 * 4)) == [0, 1, 2, 3]
    assert len(set(grid["seed"][:, 0])) == 5
    pd.testing.assert_frame_equal(table, design.crossed_table(geometry, others, 5, 4, "latin_hypercube", 7))


def _crossed_planar(tmp_path: Path, **sampling) -> Path:
    data = yaml.safe_load(PLANAR.read_text())
    data["variables"] = [
        {"path": "plane_deg", "distribution": "normal", "mean": 35.0, "std": 2.0, "geometry": True},
        {"path": "strength.tan_friction", "distribution": "normal", "mean": 0.8, "std": 0.15},
    ]
    data["sampling"] = {
        "method": "latin_hypercube",
        "realizations": 200,
        "samples": 50,
        "seed": 3,
        **sampling,
    }
    path = tmp_path / "crossed.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_a_crossed_planar_study_measures_the_share_of_its_plane(tmp_path):
    """The planar block with its plane psi ~ N(35, 2) deg as the geometry and tan phi ~ N(0.8, 0.15):
    FS = X Y, X = tan phi, Y = 1 / tan psi independent, so Var(E[FS | psi]) = E[X]^2 Var(Y) and Var(FS)
    = E[X^2] E[Y^2] - E[X]^2 E[Y]^2 (Y's moments by quadrature): a share of 0.1368. 200 x 50 runs:
    the estimate lies within 0.03 of it (measured 0.142, its interval 0.103 to 0.211) and the interval covers
    it; geometry_share.csv and summary.csv hold it, the order not being random there is no convergence."""
    outcome = CliRunner().invoke(main, ["sweep", str(_crossed_planar(tmp_path)), "--results", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output
    out = tmp_path / "sweep" / "planar_block"
    table = pd.read_csv(out / "geometry_share.csv").set_index("quantity")
    psi = stats.norm(35.0, 2.0)
    y1, y2 = (
        integrate.quad(lambda d, k=k: psi.pdf(d) / math.tan(math.radians(d)) ** k, 20, 50)[0] for k in (1, 2)
    )
    x1, x2 = 0.8, 0.8**2 + 0.15**2
    exact = x1**2 * (y2 - y1**2) / (x2 * y2 - x1**2 * y1**2)
    share = table.loc["geometry_share"]
    assert exact == pytest.approx(0.1368, abs=5e-5)
    assert abs(share["value"] - exact) <= 0.03
    assert share["ci_low"] <= exact <= share["ci_high"]
    assert table.loc["runs", "value"] == 10_000
    summary = pd.read_csv(out / "summary.csv").set_index("quantity")["value"]
    assert (
        summary["geometry_share"] == share["value"] and summary["geometry_share_ci_high"] == share["ci_high"]
    )
    assert not (out / "convergence.csv").exists()
    assert "the geometry holds 0.1" in outcome.output


@pytest.mark.parametrize(
    ("change", "fragment"),
    [
        ({"method": "saltelli", "samples": 8}, "crosses a random design, not saltelli"),
        ({"samples": 1}, "needs samples >= 2"),
        ({"realizations": 1}, "sampling.realizations"),
    ],
)
def test_a_crossed_design_it_cannot_make_is_refused_in_one_line(tmp_path, change, fragment):
    """Exit 2, one line naming the study and the key, nothing written."""
    config = _crossed_planar(tmp_path, **change)
    results = tmp_path / "results"
    outcome = CliRunner().invoke(main, ["sweep", str(config), "--results", str(results)])
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.output.strip().splitlines()
    assert len(lines) == 1 and str(config) in lines[0] and fragment in lines[0], outcome.output
    assert not results.exists()


def test_a_crossed_design_without_a_geometry_variable_is_refused(tmp_path):
    """No geometry variable, a realization declared not geometry, a correlation reaching into the
    geometry (its draws are made apart from the others'): each refused by the study's model."""
    data = yaml.safe_load(_crossed_planar(tmp_path).read_text())
    with pytest.raises(ValueError, match="correlates none of its geometry variables"):
        Config.model_validate(
            data | {"correlation": {"between": ["plane_deg", "strength.tan_friction"], "rho": 0.5}}
        )
    data["variables"][0].pop("geometry")
    with pytest.raises(ValueError, match="needs a geometry variable"):
        Config.model_validate(data)
    data["variables"][0].update(distribution="realization", geometry=False)
    for key in ("mean", "std"):
        data["variables"][0].pop(key)
    with pytest.raises(ValueError, match="takes no `geometry: false`"):
        Config.model_validate(data)
    plain = yaml.safe_load(_crossed_planar(tmp_path).read_text())
    plain["sampling"].pop("realizations")
    with pytest.raises(ValueError, match="crossed design: give realizations"):
        Config.model_validate(plain)


def _seed_study(method: str, n: int) -> tuple[Config, report.Inputs, pd.DataFrame, dict | None]:
    """A seed and a friction, FS = friction / 40 + a jump decided by the seed's parity."""
    data = yaml.safe_load(PLANAR.read_text())
    variables = [
        ("rock.seed", design.marginal("realization")),
        ("friction", design.marginal("normal", mean=38, std=2)),
    ]
    data["sampling"] = {"method": method, "samples": n, "seed": 4}
    config = Config.model_validate(data)
    if method == "saltelli":
        table, problem = design.saltelli_table(variables, n, 4)
    else:
        table, problem = design.sample_table(variables, n, method, 4), None
    fs = table["friction"] / 40.0 + 0.5 * (table["rock.seed"] % 2)
    samples = table.assign(**{FS: fs, ERROR: "", OUTCOME: "valid"})
    inputs = report.Inputs(variables, {"rock.seed": None, "friction": None}, {})
    return config, inputs, samples, problem


@pytest.mark.parametrize(("method", "n"), [("latin_hypercube", 64), ("saltelli", 64)])
def test_a_seed_is_neither_ranked_nor_given_sobol_indices(method, n):
    """The seed drives half of FS here (by parity, no order), yet sensitivity.csv and the tornado hold
    the friction only, with its Sobol' indices for a saltelli design."""
    config, inputs, samples, problem = _seed_study(method, n)
    result = report.fs_result(config, samples, inputs, Outcomes.of(samples), None, problem, lambda _: None)
    sensitivity = result.tables["sensitivity"]
    assert sensitivity["input"].tolist() == ["friction"]
    assert sensitivity["spearman_rho"].iloc[0] > 0
    if problem is not None:
        assert np.isfinite(sensitivity[["S1", "ST"]].to_numpy()).all()
    assert "tornado" in result.figures
