"""`bbmc wedge`'s combinations from `bbmc kinematics`' sets.csv (`combinations.sets_file`) and the design
of the combinations' lowest-FS wedge: the file's sets give the typed sets' table exactly; strengths
from `strength` and `set_strength`; the design reaches its target through Barton-Bandis planes; bad
files and keys refused in one line naming the file or key, nothing written."""

from __future__ import annotations

import pandas as pd
import pytest
import yaml

from bbmc.config import ConfigError
from bbmc.field.set_table import read_set_planes
from stage_runs import CONFIGS, refused, run_stage

# configs/wedge_combinations.yaml's sets, in bbmc kinematics' sets.csv columns (with a random row).
SETS_CSV = """set,dip_deg,dip_direction_deg,pole_trend_deg,pole_plunge_deg,fisher_k,alpha95_deg
S1,36,161,341,54,55.4,2.2
S2,60,217,37,30,30.3,2.8
S3,55,129,309,35,45.5,2.5
S4,77,13,193,13,84.5,1.9
random,,,,,,
"""
MC = {"law": "mohr_coulomb", "cohesion_kPa": 0, "friction_deg": 30}


def _config(tmp_path, combinations: dict, design: dict | None = None, sets_csv: str = SETS_CSV):
    (tmp_path / "sets.csv").write_text(sets_csv)
    data = yaml.safe_load((CONFIGS / "wedge_combinations.yaml").read_text())
    data["combinations"] = combinations
    if design is not None:
        data["design"] = design
    path = tmp_path / "pit.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def _run(tmp_path, config):
    outcome = run_stage("wedge", tmp_path / "results", config)
    return outcome, tmp_path / "results" / "wedge" / config.stem


def test_the_files_sets_give_the_typed_sets_table(tmp_path):
    """The four sets read from sets.csv (random skipped), one strength for all: combinations.csv equals
    configs/wedge_combinations.yaml's, typed, to the bit."""
    typed, typed_folder = _run(tmp_path / "typed", CONFIGS / "wedge_combinations.yaml")
    assert typed.exit_code == 0, typed.output
    (tmp_path / "file").mkdir()
    config = _config(tmp_path / "file", {"sets_file": "sets.csv", "strength": MC, "critical_fs": 1.5})
    outcome, folder = _run(tmp_path / "file", config)
    assert outcome.exit_code == 0, outcome.output
    pd.testing.assert_frame_equal(
        pd.read_csv(folder / "combinations.csv"), pd.read_csv(typed_folder / "combinations.csv")
    )


def test_set_strength_and_design_of_the_lowest_wedge(tmp_path):
    """S3 given phi 20 by name lowers S2-S3's FS; with no plane_1/plane_2 the design is the lowest-FS
    wedge's (S2 with S3), and its bolts, through Barton-Bandis planes (whose closed-form direction uses
    the tangent phi), give at least the target FS by the vector solution."""
    weak = {"law": "mohr_coulomb", "friction_deg": 20}
    config = _config(tmp_path, {"sets_file": "sets.csv", "strength": MC, "set_strength": {"S3": weak}})
    outcome, folder = _run(tmp_path, config)
    assert outcome.exit_code == 0, outcome.output
    low = pd.read_csv(folder / "combinations.csv").iloc[0]
    assert (low.plane_1, low.plane_2) == ("S2", "S3")
    assert low.factor_of_safety < 0.633  # the typed table's S2-S3 at phi 30 on both
    bb = {"law": "barton_bandis", "jrc": 8, "jcs_MPa": 60, "phi_b_deg": 28, "field_length_m": "intersection"}
    design = {"target_fs": 1.5, "capacity_kN": 250, "form": "passive"}
    (tmp_path / "bb").mkdir()
    config = _config(tmp_path / "bb", {"sets_file": "sets.csv", "strength": bb}, design)
    outcome, folder = _run(tmp_path / "bb", config)
    assert outcome.exit_code == 0, outcome.output
    row = pd.read_csv(folder / "design.csv").iloc[0]
    assert (row.plane_1, row.plane_2) == ("S2", "S3")
    assert row.factor_of_safety >= 1.5
    assert "design of S2 with S3" in outcome.output


@pytest.mark.parametrize(
    ("combinations", "sets_csv", "fragments"),
    [
        ({"sets_file": "sets.csv"}, SETS_CSV, ("combinations.strength", "S1")),
        ({"sets_file": "none.csv", "strength": MC}, SETS_CSV, ("sets_file", "not found")),
        (
            {"sets_file": "sets.csv", "strength": MC, "set_strength": {"S9": MC}},
            SETS_CSV,
            ("set_strength.S9",),
        ),
        (
            {"sets": {"S1": {"dip_deg": 30, "dip_direction_deg": 10, "strength": MC}}, "strength": MC},
            "",
            ("sets_file",),
        ),
        (
            {"sets_file": "sets.csv", "strength": MC},
            "set,dip_deg\nS1,40\n",
            ("sets.csv", "dip_direction_deg"),
        ),
        ({"sets_file": "sets.csv", "strength": MC}, SETS_CSV.replace("S2,60", "S2,95"), ("row 3", "dip_deg")),
        ({"sets_file": "sets.csv", "strength": MC}, SETS_CSV.replace("S2,", "S1,"), ("row 3", "given twice")),
    ],
)
def test_bad_sets_files_and_keys(tmp_path, combinations, sets_csv, fragments):
    """Each: exit 2, one line naming the file or key, nothing written."""
    config = _config(tmp_path, combinations, sets_csv=sets_csv)
    outcome = run_stage("wedge", tmp_path / "results", config)
    refused(outcome, tmp_path / "results", *fragments)


def test_reader_skips_random_and_keeps_order(tmp_path):
    """read_set_planes: the sets in the file's order, K read, `random` skipped; an empty table refused."""
    path = tmp_path / "sets.csv"
    path.write_text(SETS_CSV)
    planes = read_set_planes(path)
    assert list(planes) == ["S1", "S2", "S3", "S4"]
    assert (planes["S2"].dip_deg, planes["S2"].dip_direction_deg, planes["S2"].fisher_k) == (
        60.0,
        217.0,
        30.3,
    )
    path.write_text("set,dip_deg,dip_direction_deg\nrandom,,\n")
    with pytest.raises(ConfigError, match="no set"):
        read_set_planes(path)
