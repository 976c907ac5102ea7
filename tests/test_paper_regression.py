"""Stage CSVs against the paper, cell by cell (data/paper/*.csv).

Each cell either reproduces the printed value within the one tolerance of its quantity
(`bbmc.comparison.TOLERANCES`: half a unit of the printed digit), or is a difference the audit
explains; such a cell is asserted as that known deviation (ours - paper), so a change in either our
number or the explanation fails the test. No cell is skipped and no tolerance is widened.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from bbmc.comparison import TOLERANCES, VERDICTS, within
from stage_runs import paper_table, run_stage

REPRODUCED = None

# ours - paper for every Table 3 cell (row order of data/paper/table3_numerical_tests.csv); None where
# the printed value is reproduced. docs/paper-audit.md gives the reasons (F-numbers there).
TABLE3_KNOWN: dict[str, tuple[str, list[float | None]]] = {
    # eq 4: rows 2-3 reproduced with n_j = 0.4811 (digit swap), row 8 unexplained, row 1 bracket at 0
    "K_st_uncorrected_MPa_per_mm": (
        "K_MPa_per_mm",
        [
            -1.200e-4,
            -1.000e-4,
            -7.019e-3,
            -4.467e-4,
            -6.285e-3,
            REPRODUCED,
            2.565e-4,
            1.4887e-3,
            6.9167e-2,
            1.7832e-4,
        ],
    ),
    # eq 16 output vs the authors' calibrated stiffnesses
    "K_st_corrected_MPa_per_mm": (
        "K_MPa_per_mm",
        [
            -4.3134e-2,
            1.9219e-4,
            -6.4614e-3,
            -8.6994e-3,
            3.2302e-4,
            2.1789e-4,
            -4.3770e-3,
            1.4682e-2,
            -3.2812e-3,
            -4.5993e-3,
        ],
    ),
    # eq 8 arithmetic; 2.2466 and 3.3699 are truncated, not rounded (lg e erratum is asserted below)
    "K_n_MPa_per_mm": (
        "K_MPa_per_mm",
        [
            REPRODUCED,
            REPRODUCED,
            5.1136e-5,
            5.1136e-5,
            7.6704e-5,
            7.6704e-5,
            REPRODUCED,
            REPRODUCED,
            REPRODUCED,
            REPRODUCED,
        ],
    ),
    # eq 15 with section 3's parameters: Phi and C need a rougher joint
    "Phi_deg": ("Phi_deg", [-1.8490, None, -1.1899, None, -0.86483, None, -0.73084, None, None, None]),
    "C_kPa": ("C_kPa", [-5.1463e-2, None, -7.1607e-2, None, -7.5302e-2, None, -9.7576e-2, None, None, None]),
}

TABLE1_KNOWN: dict[tuple[str, str], float | None] = {
    ("K_si_vs_sigma_n", "a"): REPRODUCED,
    ("K_si_vs_sigma_n", "b"): REPRODUCED,
    ("K_si_vs_sigma_n", "correlation_coefficient"): REPRODUCED,
    # the fit used Table 3's 0.0815 where Table 1 prints 0.082 (rounding)
    ("tau_p_vs_sigma_n", "a"): -1.000e-3,
    ("tau_p_vs_sigma_n", "b"): 2.000e-4,
    ("tau_p_vs_sigma_n", "correlation_coefficient"): 2.4101e-3,
    # not reproducible from the printed data
    ("tau_ult_vs_tau_p", "a"): 1.3003e-2,
    ("tau_ult_vs_tau_p", "b"): -1.1319e-3,
    ("tau_ult_vs_tau_p", "correlation_coefficient"): 9.7071e-3,
}


@pytest.fixture(scope="module")
def results(tmp_path_factory: pytest.TempPathFactory):
    folder = tmp_path_factory.mktemp("results")
    for stage in ("fit", "mc", "audit"):
        outcome = run_stage(stage, folder)
        assert outcome.exit_code == 0, outcome.output
    return folder


def _assert_cell(ours: float, paper: float, tolerance_key: str, known: float | None) -> None:
    tol = TOLERANCES[tolerance_key].value
    if known is None:
        assert within(ours, paper, tol), f"ours {ours!r} vs paper {paper!r}: beyond ±{tol}"
    else:
        assert not within(ours, paper, tol), f"known deviation vanished: ours {ours!r} = paper {paper!r}"
        assert ours - paper == pytest.approx(known, rel=2e-3, abs=tol / 10)


TABLE3_CELLS = [
    (column, row)
    for column, (_, known) in TABLE3_KNOWN.items()
    for row in range(len(known))
    if column[:3] != "Phi"
] + [("Phi_deg", r) for r in (0, 2, 4, 6)]
TABLE3_CELLS = [(c, r) for c, r in TABLE3_CELLS if not (c == "C_kPa" and r not in (0, 2, 4, 6))]


@pytest.mark.parametrize(("column", "row"), TABLE3_CELLS)
def test_table3_cell(results, column: str, row: int) -> None:
    ours = pd.read_csv(results / "mc" / "table3_mc.csv")
    paper = paper_table("table3_numerical_tests.csv")
    assert np.allclose(ours["sigma_n_MPa"], paper["sigma_n_MPa"]) and np.allclose(
        ours["tau_MPa"], paper["tau_MPa"]
    )
    tolerance_key, known = TABLE3_KNOWN[column]
    _assert_cell(float(ours.loc[row, column]), float(paper.loc[row, column]), tolerance_key, known[row])


@pytest.mark.parametrize(("relation", "column"), list(TABLE1_KNOWN))
def test_table1_fit_cell(results, relation: str, column: str) -> None:
    ours = pd.read_csv(results / "fit" / "table1_fits.csv")
    row = ours[(ours["relation"] == relation) & ours["method"].isin(["log-log", "ols"])].iloc[0]
    paper = paper_table("table1_fits.csv").set_index("relation").loc[relation]
    ours_value = float(row["R2" if column == "correlation_coefficient" else column])
    key = "R2" if column == "correlation_coefficient" else "fit_coefficient"
    _assert_cell(ours_value, float(paper[column]), key, TABLE1_KNOWN[(relation, column)])


def test_audit_gives_every_number_a_verdict_and_a_reason(results) -> None:
    audit = pd.read_csv(results / "audit" / "audit.csv")
    assert len(audit) > 100
    assert set(audit["verdict"]) <= set(VERDICTS)
    assert audit["reasoning"].str.len().min() > 20
    derivable = audit[audit["verdict"] != "not derivable"]
    assert derivable["ours"].map(lambda v: not math.isnan(v)).all()


def test_audit_agrees_with_the_stage_csvs(results) -> None:
    """The audit judges the same numbers the stages write (no second computation drifting apart)."""
    audit = pd.read_csv(results / "audit" / "audit.csv")
    mc = pd.read_csv(results / "mc" / "table3_mc.csv")
    rows = audit[(audit["source"] == "Table 3") & audit["quantity"].str.startswith("K_st uncorrected")]
    assert np.allclose(
        rows["ours"].to_numpy(), mc["K_st_uncorrected_MPa_per_mm"].to_numpy(), rtol=1e-12, atol=0
    )


@pytest.mark.parametrize(
    ("source", "quantity", "verdict", "corrected"),
    [
        ("Eq 6", "constant", "paper inconsistency", math.log10(math.e)),
        ("Eq 8", "c [1/mm]", "paper inconsistency", 7.715 * math.log(10)),
        ("Eq 18", "c [MPa/mm]", "paper inconsistency", 0.2400),
        ("Eq 16", "a", "reproduced", None),
        ("Eq 16", "b", "reproduced", None),
        ("Eq 15", "pi JRC / (180 ln 10)", "reproduced", None),
    ],
)
def test_audit_equation_verdicts(results, source, quantity, verdict, corrected) -> None:
    audit = pd.read_csv(results / "audit" / "audit.csv")
    row = audit[(audit["source"] == source) & (audit["quantity"] == quantity)].iloc[0]
    assert row["verdict"] == verdict
    if corrected is not None:
        assert row["corrected"] == pytest.approx(corrected, rel=1e-3)


def test_stiffness_cannot_produce_the_displacements(results) -> None:
    """Table 3's stiffnesses, integrated, give displacements one to two orders below the printed ones."""
    audit = pd.read_csv(results / "audit" / "audit.csv")
    rows = audit[audit["quantity"].str.startswith("d_h N-")]
    finite = rows[np.isfinite(rows["ours"])]
    assert len(rows) == 20
    assert (finite["paper"] / finite["ours"]).min() > 10
