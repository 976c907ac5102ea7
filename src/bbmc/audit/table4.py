"""Table 4's constant joint parameters and rock mass strength against the laws, and Table 2's JCS."""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from bbmc import laws, units
from bbmc.audit.log import AuditInputs, AuditLog
from bbmc.audit.strength import table4_strength
from bbmc.joint import model as jm


def table4_checks(log: AuditLog, ctx: AuditInputs) -> None:
    """Table 4's constant joint parameters and rock mass strength, and Table 2's JCS."""
    p = ctx.stiffness
    constant = ctx.table4_constant.iloc[0]
    t4 = ctx.table4_nonlinear.iloc[0]
    table4_set = table4_strength(ctx)
    k_n = float(constant["K_n_MPa_per_mm"])
    sigma_for_kn = k_n * units.MPa_per_mm * p.log10_e / p.q
    k_s_there = laws.simplified_shear_stiffness(sigma_for_kn, p.eq18_k_j, p.eq18_n_j, jm.SIGMA_REF, 1.0)
    log.check(
        "Table 4",
        "constant model",
        "K_s [MPa/mm] at the sigma_n where eq 8 gives K_n = 10.7",
        "table4_stiffness",
        float(constant["K_s_MPa_per_mm"]),
        float(k_s_there) / units.MPa_per_mm,
        f"Eq 8 gives K_n = 10.7 MPa/mm at sigma_n = {sigma_for_kn / units.MPa:.3f} MPa, where eq 18 gives "
        "K_s far lower: no normal stress makes both laws give 10.7. The constants are not derived.",
    )
    c_kPa, phi_paper = float(constant["c_kPa"]), float(constant["phi_deg"])
    item, quantity = "constant model", f"phi [deg] paired with c = {c_kPa:g} kPa by eq 15"
    grid = np.geomspace(1e-3, 100.0, 2000) * units.MPa
    phi_range = jm.strength_state(grid, table4_set)["phi"] / units.deg
    span = f"over 0.001-100 MPa its phi stays within {phi_range.min():.1f}-{phi_range.max():.1f} deg"

    def c_above_paper(sigma_n: float) -> float:
        return jm.strength_state(np.array([sigma_n]), table4_set)["c"][0] - c_kPa * units.kPa

    low, high = 1e3, table4_set.jcs * 0.999
    if not (low < high and c_above_paper(low) * c_above_paper(high) < 0):
        log.not_derivable(
            "Table 4",
            item,
            quantity,
            "deg",
            phi_paper,
            np.nan,
            f"Eq 15 with Table 4's set gives c = {c_kPa:g} kPa at no sigma_n from 1 kPa to JCS; {span}.",
        )
    else:
        root = math.exp(optimize.brentq(lambda u: c_above_paper(math.exp(u)), math.log(low), math.log(high)))
        phi_there = jm.strength_state(np.array([root]), table4_set)["phi"][0] / units.deg
        log.check(
            "Table 4",
            item,
            quantity,
            "table4_angle",
            phi_paper,
            float(phi_there),
            f"Eq 15 with Table 4's set gives c = {c_kPa:g} kPa at sigma_n = {root / units.MPa:.3f} MPa, "
            f"where phi = {phi_there:.2f} deg; {span}, so {phi_paper:g} deg cannot come from it.",
        )
    rock2, rock4 = ctx.table2.iloc[0], ctx.table4_rock.iloc[0]
    log.check(
        "Table 4",
        "limestone",
        "cohesion [MPa]",
        "strength_MPa_2dp",
        float(rock4["cohesion_MPa"]),
        float(rock2["cohesion_MPa"]),
        "Table 4 prints 4.12e3 under MPa where Table 2 has 4.12 MPa for the same limestone: a factor "
        "1000 (kPa written as MPa).",
    )
    log.check(
        "Table 4",
        "B-B set",
        "JCS [MPa] = sigma_c / 4",
        "strength_MPa_2dp",
        float(t4["JCS_MPa"]),
        float(rock2["compressive_strength_MPa"]) / 4.0,
        "Section 3 takes JCS as a quarter of sigma_c = 13.24 MPa; Table 4's 3.87 is not, and phi_b "
        "(33.4 vs 32) and JRC (2.04 vs 2.13) change from section 3 without a word.",
    )
    log.check(
        "Table 2",
        "limestone",
        "JCS [MPa] = sigma_c / 4",
        "strength_MPa_2dp",
        ctx.strength.jcs / units.MPa,
        float(rock2["compressive_strength_MPa"]) / 4.0,
        "Section 3's JCS = 13.24 / 4.",
    )
