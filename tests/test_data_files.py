"""Every number read from a data file gets the checks a config number gets: a finite number within the
physical range of its quantity, in a column of the right name, in a table of the right shape. A fault is
one line naming the file, the line and the column; exit 2; nothing written."""

from __future__ import annotations

import pytest

from stage_runs import PAPER, config_copy, run_stage, set_key

MC_DATA = {
    "table1_measurements.csv": "data.table1",
    "table3_numerical_tests.csv": "data.table3",
    "equation_constants.csv": "data.equation_constants",
}
AUDIT_DATA = {
    "table1_fits.csv": "data.table1_fits",
    "table2_rock.csv": "data.table2",
    "table4_joints_constant.csv": "data.table4_constant",
    "table4_joints_nonlinear.csv": "data.table4_nonlinear",
    "table4_rock_mass.csv": "data.table4_rock",
}


def _edited(tmp_path, name: str, edit) -> str:
    """A copy of data/paper/<name> in tmp_path, its lines (header first) changed by `edit`."""
    lines = (PAPER / name).read_text().splitlines()
    path = tmp_path / name
    path.write_text("\n".join(edit(lines)) + "\n")
    return str(path)


def _cell(row: int, column: int, value: str):
    """An edit: line `row` (1 = the header), 0-based `column` set to `value`."""

    def edit(lines: list[str]) -> list[str]:
        cells = lines[row - 1].split(",")
        cells[column] = value
        lines[row - 1] = ",".join(cells)
        return lines

    return edit


def _refused(tmp_path, stage: str, name: str, edit) -> str:
    keys = MC_DATA if stage == "mc" else AUDIT_DATA
    config = config_copy(tmp_path, stage, set_key(keys[name], _edited(tmp_path, name, edit)))
    results = tmp_path / "results"
    outcome = run_stage(stage, results, config)
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.stderr.strip().splitlines()
    assert len(lines) == 1, outcome.stderr
    assert not results.exists()
    assert f"{tmp_path / name}: " in lines[0], lines[0]
    return lines[0].split(f"{name}: ", 1)[1]


@pytest.mark.parametrize(
    ("stage", "name", "edit", "message"),
    [
        (
            "mc",
            "table1_measurements.csv",
            _cell(3, 2, "nan"),
            "line 3: column 'K_si_GPa_per_m': not a finite number: 'nan'",
        ),
        (
            "mc",
            "table1_measurements.csv",
            _cell(3, 2, "inf"),
            "line 3: column 'K_si_GPa_per_m': not a finite",
        ),
        ("mc", "table1_measurements.csv", _cell(2, 0, "1e999"), "line 2: column 'sigma_n_MPa': not a finite"),
        (
            "mc",
            "table1_measurements.csv",
            _cell(2, 1, ""),
            "line 2: column 'tau_p_MPa': blank, a value is needed",
        ),
        (
            "mc",
            "table1_measurements.csv",
            _cell(4, 3, "-0.1"),
            "line 4: column 'tau_ult_MPa' must be > 0, got -0.1",
        ),
        ("mc", "table1_measurements.csv", _cell(1, 1, "tau_p_kPa"), "missing column 'tau_p_MPa'"),
        (
            "mc",
            "table1_measurements.csv",
            _cell(1, 3, "sigma_n_MPa"),
            "line 1: column 'sigma_n_MPa' is named twice",
        ),
        ("mc", "table1_measurements.csv", lambda lines: lines[:1], "no data rows under the header"),
        (
            "mc",
            "table1_measurements.csv",
            lambda lines: [*lines, "0.3,0.2,1,0.2,9"],
            "line 6: 5 cells, the header",
        ),
        (
            "mc",
            "table1_measurements.csv",
            lambda lines: [lines[0], lines[1], lines[1]],
            "column 'sigma_n_MPa' needs at least 2 different values (K_si and tau_p are fitted against them)",
        ),
        (
            "mc",
            "table3_numerical_tests.csv",
            _cell(5, 1, "abc"),
            "line 5: column 'tau_MPa': not a number: 'abc'",
        ),
        (
            "mc",
            "equation_constants.csv",
            _cell(3, 2, "-0.4881"),
            "line 3: column 'value' of 'eq4.n_j' must be > 0",
        ),
        ("mc", "equation_constants.csv", _cell(3, 0, "4.5"), "column 'equation': equation numbers are whole"),
        ("mc", "equation_constants.csv", _cell(3, 1, "K_j"), "line 3: constant 'eq4.K_j' is given twice"),
        ("mc", "equation_constants.csv", lambda lines: lines[:-1], "no constant eq18.K_st_exponent"),
        (
            "audit",
            "table1_fits.csv",
            _cell(3, 7, "1.2"),
            "line 3: column 'correlation_coefficient' must be > 0 and <= 1, got 1.2",
        ),
        (
            "audit",
            "table1_fits.csv",
            lambda lines: lines[:-1],
            "column 'relation': no row for 'tau_p_vs_sigma_n'",
        ),
        (
            "audit",
            "table2_rock.csv",
            _cell(2, 6, "-13.24"),
            "line 2: column 'compressive_strength_MPa' must be > 0",
        ),
        (
            "audit",
            "table4_joints_constant.csv",
            _cell(2, 2, "95"),
            "line 2: column 'phi_deg' must be > 0 and < 90, got 95",
        ),
        (
            "audit",
            "table4_joints_constant.csv",
            lambda lines: [*lines, lines[1]],
            "2 data rows, where the table has 1",
        ),
        (
            "audit",
            "table4_joints_nonlinear.csv",
            _cell(2, 4, "25"),
            "line 2: column 'JRC' must be >= 0 and <= 20, got 25",
        ),
        (
            "audit",
            "table4_rock_mass.csv",
            _cell(2, 4, "-4.12e3"),
            "line 2: column 'cohesion_MPa' must be >= 0",
        ),
    ],
)
def test_a_bad_number_or_shape_in_a_data_file_is_one_line(tmp_path, stage, name, edit, message):
    assert _refused(tmp_path, stage, name, edit).startswith(message)


def test_a_table_with_blank_lines_and_a_byte_order_mark_reads_as_written(tmp_path):
    """Excel's "CSV UTF-8" starts with a byte-order mark; blank lines are skipped, and a fault below one
    names the line it is on in the file."""
    name = "table1_measurements.csv"
    text = (PAPER / name).read_text()
    path = tmp_path / name
    path.write_bytes(b"\xef\xbb\xbf" + text.replace("\n", "\n\n", 1).encode())
    config = config_copy(tmp_path, "mc", set_key("data.table1", str(path)))
    assert run_stage("mc", tmp_path / "first", config).exit_code == 0
    assert "line 5: column 'tau_p_MPa'" in _refused(
        tmp_path, "mc", name, lambda lines: [lines[0], "", *lines[1:3], "0.15,x,0.74,0.113", *lines[4:]]
    )


def test_fit_names_a_normal_stress_with_too_few_test_points(tmp_path):
    """Fig 2a's line through the test points at each normal stress needs two different d_h."""
    name = "table3_numerical_tests.csv"
    config = config_copy(
        tmp_path, "fit", set_key("data.table3", _edited(tmp_path, name, lambda lines: [lines[0], *lines[2:]]))
    )
    outcome = run_stage("fit", tmp_path / "results", config)
    assert outcome.exit_code == 2, outcome.output
    assert (
        "column 'd_h_test_mm' needs at least 2 different values at sigma_n_MPa = 0.05 (Fig 2a's line is "
        "fitted through them), got 1"
    ) in outcome.stderr


def test_the_audit_names_tables_that_do_not_line_up(tmp_path):
    """A Fig 2a legend at a normal stress Table 1 does not have: the audit compares them row by row."""
    legends = _edited(tmp_path, "fig2a_legends.csv", _cell(2, 0, "60"))
    fit_config = config_copy(tmp_path, "fit", set_key("data.fig2a_legends", legends))
    config = config_copy(tmp_path, "audit", set_key("fit_config", str(fit_config)))
    outcome = run_stage("audit", tmp_path / "results", config)
    assert outcome.exit_code == 2, outcome.output
    assert f"{legends}: line 2: sigma_n_kPa 60 is at no normal stress (or at several) of " in outcome.stderr
