"""The paper's tables (data/paper, README there) as bbmc reads them: each table's columns with the range
of their numbers, how many rows it has, and the printed constants by name.

Every stage that reads a table reads it through `read`, so a number gets the same checks wherever it is
read, as a config's numbers do: a finite number within the physical range of its quantity (> 0 for a
stress, a stiffness, a density; 0-90 deg for a friction angle; 0-20 for JRC; 0-1 for R^2), not far
beyond the plausible range of its quantity where it has one (`Column.of`: over 10^6 times its high end,
as a config's number is refused; docs/plausible-ranges.md), a blank cell only where the paper leaves
one. Any fault is one `ConfigError` line naming the file, line and column.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from bbmc.config import ConfigError
from bbmc.io import ANGLE_DEG, NON_NEGATIVE, NUMBER, POSITIVE, TEXT, Column, read_table, require_distinct

JRC = Column(0.0, 20.0).of("jrc")
R2 = Column(0.0, 1.0, low_open=True)
EQUATION = Column(low=1.0)
# A column of a physical quantity is also refused far beyond its plausible range (`Column.of`)
STRESS = POSITIVE.of("sigma_n_MPa")
SHEAR = POSITIVE.of("tau_MPa")
KS = POSITIVE.of("ks_MPa_per_mm")  # 1 GPa/m = 1 MPa/mm
KN = POSITIVE.of("kn_MPa_per_mm")
DENSITY = POSITIVE.of("density_kg_m3")
FRICTION = ANGLE_DEG.of("friction_deg")
JOINT_COHESION_KPA = NON_NEGATIVE.of("cohesion_kPa")
ROCK_COHESION_MPA = NON_NEGATIVE.of("intact_rock.cohesion_MPa")

# table name -> (columns, rows: None for any number of rows)
TABLES: dict[str, tuple[dict[str, Column], int | None]] = {
    "table1_measurements": (
        {"sigma_n_MPa": STRESS, "tau_p_MPa": SHEAR, "K_si_GPa_per_m": KS, "tau_ult_MPa": SHEAR},
        None,
    ),
    "table1_fits": (
        {"relation": TEXT, "formula": TEXT, "a": NUMBER, "b": NUMBER, "correlation_coefficient": R2},
        None,
    ),
    "fig2a_legends": (
        {
            "sigma_n_kPa": POSITIVE.of("sigma_n_MPa", 1e-3),
            "slope_a": POSITIVE.of("ks_MPa_per_mm", 1e-3, reciprocal=True),  # eq 1: K_si = 1/a [kPa/mm]
            "intercept_b": NUMBER,
            "R2": R2,
        },
        None,
    ),
    "table2_rock": (
        {
            "density_kg_per_m3": DENSITY,
            "cohesion_MPa": ROCK_COHESION_MPA,
            "friction_angle_deg": FRICTION,
            "compressive_strength_MPa": POSITIVE.of("sigma_c_MPa"),
        },
        1,
    ),
    "table3_numerical_tests": (
        {
            "sigma_n_MPa": STRESS,
            "tau_MPa": SHEAR,
            "K_st_uncorrected_MPa_per_mm": NON_NEGATIVE.of("ks_MPa_per_mm"),
            "K_st_corrected_MPa_per_mm": KS,
            "K_n_MPa_per_mm": KN,
            "Phi_deg": FRICTION.or_blank(),  # printed once per normal stress
            "C_kPa": JOINT_COHESION_KPA.or_blank(),
            "d_h_test_mm": POSITIVE,
            "d_h_numerical_uncorrected_mm": POSITIVE,
            "d_h_numerical_corrected_mm": POSITIVE,
        },
        None,
    ),
    "table4_rock_mass": ({"density_kg_per_m3": DENSITY, "cohesion_MPa": ROCK_COHESION_MPA}, 1),
    "table4_joints_constant": (
        {"K_s_MPa_per_mm": KS, "K_n_MPa_per_mm": KN, "phi_deg": FRICTION, "c_kPa": JOINT_COHESION_KPA},
        1,
    ),
    "table4_joints_nonlinear": (
        {
            "K_st_coefficient_MPa_per_mm": POSITIVE.of("kj_MPa_per_mm"),
            "K_st_exponent": POSITIVE,
            "K_n_coefficient_per_mm": POSITIVE,
            "phi_b_deg": ANGLE_DEG.of("phi_b_deg"),
            "JRC": JRC,
            "JCS_MPa": POSITIVE.of("jcs_MPa"),
            "eq15_coefficient": POSITIVE,
        },
        1,
    ),
    "equation_constants": ({"equation": EQUATION, "name": TEXT, "value": NUMBER}, None),
}

# The printed constants every reader needs, by name (eq<equation>.<name>), with the range of each.
CONSTANTS: dict[str, Column] = {
    "eq4.K_j": POSITIVE.of("kj_MPa_per_mm"),  # GPa/m at 1 MPa
    "eq4.n_j": POSITIVE,
    "eq4.tau_p_slope": POSITIVE,
    "eq4.tau_p_intercept": NUMBER,
    "eq4.tau_ult_slope": POSITIVE,
    "eq4.tau_ult_intercept": NUMBER,
    "eq6.lg_e": POSITIVE,
    "eq7.q": POSITIVE,
    "eq7.p": NUMBER,
    "eq8.K_n_coefficient": POSITIVE,
    "eq15.tangent_coefficient": POSITIVE,
    "eq16.correction_a": NUMBER,
    "eq16.correction_b": NUMBER,
    "eq18.K_st_coefficient": POSITIVE.of("kj_MPa_per_mm"),
    "eq18.K_st_exponent": POSITIVE,
}
LEGEND_CURVES = ["sigma_n_kPa", "slope_a", "intercept_b"]  # Fig 2a's legends as eq 1's curves
FIT_RELATIONS = ("inverse_tau_vs_inverse_dh", "K_si_vs_sigma_n", "tau_ult_vs_tau_p", "tau_p_vs_sigma_n")


def read(name: str, path: Path, columns: list[str] | None = None) -> pd.DataFrame:
    """Table `name` of `TABLES` from `path`: the `columns` the reader uses (default: all), each cell
    checked. Also, by table: the printed constants by name (each of `CONSTANTS` once, in its range),
    Table 1's fits by relation (each of `FIT_RELATIONS` once), and Table 1's measurements as two
    regressions need them (two or more different sigma_n and tau_p)."""
    every, rows = TABLES[name]
    table = read_table(path, {c: every[c] for c in columns or every}, rows)
    if name == "equation_constants":
        _check_constants(table, path)
    elif name == "table1_fits":
        _check_unique(table, path, "relation", FIT_RELATIONS)
    elif name == "table1_measurements":
        require_distinct(table, path, "sigma_n_MPa", "K_si and tau_p are fitted against them")
        require_distinct(table, path, "tau_p_MPa", "tau_ult is fitted against them")
    return table


def printed_constants(table: pd.DataFrame) -> dict[str, float]:
    """The printed constants by name, e.g. ``eq4.K_j``, from the table `read` gives."""
    return {_key(row): float(row.value) for row in table.itertuples()}


def _key(row) -> str:
    return f"eq{row.equation:g}.{row.name}"


def _check_constants(table: pd.DataFrame, path: Path) -> None:
    if any(float(e) != int(e) for e in table["equation"]):
        raise ConfigError(f"{path}: column 'equation': equation numbers are whole numbers")
    keys = [_key(row) for row in table.itertuples()]
    for k, row in enumerate(table.itertuples()):
        key, column = keys[k], CONSTANTS.get(keys[k])
        if key in keys[:k]:
            raise ConfigError(f"{path}: line {row.Index}: constant '{key}' is given twice")
        if column is not None and not column.holds(row.value):
            raise ConfigError(
                f"{path}: line {row.Index}: column 'value' of '{key}' {column.rule}, got {row.value:g}"
            )
        refusal = column.refusal(row.value) if column is not None else None
        if refusal:
            raise ConfigError(f"{path}: line {row.Index}: column 'value' of '{key}' {refusal}")
    missing = [key for key in CONSTANTS if key not in keys]
    if missing:
        raise ConfigError(f"{path}: no constant {', '.join(missing)} (column 'equation' and 'name')")


def _check_unique(table: pd.DataFrame, path: Path, column: str, needed: tuple[str, ...]) -> None:
    values = list(table[column])
    for value in needed:
        if values.count(value) != 1:
            count = "no row" if value not in values else f"{values.count(value)} rows"
            raise ConfigError(f"{path}: column '{column}': {count} for '{value}', where one is needed")
