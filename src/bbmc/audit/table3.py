"""Table 3's stiffnesses: both K_st columns (eqs 4 and 16) and K_n (eq 8) recomputed, and whether the
stated stiffnesses give the printed displacements d_h."""

from __future__ import annotations

import math
from dataclasses import replace

from bbmc import units
from bbmc.audit.log import AuditInputs, AuditLog
from bbmc.joint import model as jm


def table3_checks(log: AuditLog, ctx: AuditInputs) -> None:
    """Table 3: both K_st columns, K_n, and whether the stiffnesses give the displacements (its Phi and C:
    `bbmc.audit.strength.phi_c_checks`)."""
    p = ctx.stiffness
    corrected_p = replace(p, log10_e=math.log10(math.e))
    variants = {
        "unrounded K_si fit": replace(p, k_j=ctx.k_j_unrounded * units.GPa_per_m, n_j=ctx.n_j_unrounded),
        "exponent n_j = 0.4811 (0.4881 with two digits swapped)": replace(p, n_j=0.4811),
    }
    t3 = ctx.table3
    sigma_n, tau = t3["sigma_n_MPa"].to_numpy() * units.MPa, t3["tau_MPa"].to_numpy() * units.MPa
    ours = jm.stiffness_state(sigma_n, tau, p)
    alt = {name: jm.stiffness_state(sigma_n, tau, q) for name, q in variants.items()}
    bandis = jm.stiffness_state(sigma_n, tau, replace(p, form="corrected"))
    k_n_fixed = jm.stiffness_state(sigma_n, tau, corrected_p)["K_n"] / units.MPa_per_mm
    for i, row in enumerate(t3.itertuples()):
        item = f"sigma_n = {row.sigma_n_MPa:g} MPa, tau = {row.tau_MPa:g} MPa"
        unc = ours["K_st_uncorrected"][i] / units.MPa_per_mm
        zero_at = math.sqrt(ours["tau_p_fit"][i] * ours["tau_ult_fit"][i]) / units.MPa
        beyond = (
            f" The bracket of eq 4 reaches 0 at tau = sqrt(tau_p tau_ult) = {zero_at:.5f} MPa, below this "
            "tau: the law gives 0 (the paper prints a small number for it)."
            if unc == 0.0
            else ""
        )
        log.check(
            "Table 3",
            item,
            "K_st uncorrected [MPa/mm] (eq 4)",
            "K_MPa_per_mm",
            row.K_st_uncorrected_MPa_per_mm,
            unc,
            "Eq 4 as printed: K_si, tau_p and tau_ult all from the printed Table 1 fits (tau_p fitted, "
            f"{ours['tau_p_fit'][i] / units.MPa:.5f} MPa). Bandis et al. (1983)'s R_f = tau_p/tau_ult "
            f"would give {bandis['K_st_uncorrected'][i] / units.MPa_per_mm:.4f}." + beyond,
            rounding=(
                (
                    "the unrounded K_si fit",
                    alt["unrounded K_si fit"]["K_st_uncorrected"][i] / units.MPa_per_mm,
                ),
            ),
            explanations=tuple(
                (name, values["K_st_uncorrected"][i] / units.MPa_per_mm) for name, values in alt.items()
            ),
        )
        cor = ours["K_st_corrected"][i] / units.MPa_per_mm
        log.check(
            "Table 3",
            item,
            "K_st corrected [MPa/mm] (eq 16)",
            "K_MPa_per_mm",
            row.K_st_corrected_MPa_per_mm,
            cor,
            "Eq 16 with the printed a, b and the eq 4 reading above. The printed column is the stiffness "
            "the authors tuned in 3DEC until d_h matched the test, and eq 16 is a regression through it "
            "(a, b are recovered from it, see 'Equations'): not eq 16's output.",
        )
        kn = ours["K_n"][i] / units.MPa_per_mm
        log.check(
            "Table 3",
            item,
            "K_n [MPa/mm] (eq 8)",
            "K_MPa_per_mm",
            row.K_n_MPa_per_mm,
            kn,
            f"Eq 8 reproduces the arithmetic, but eq 6 takes lg e = 0.3434 for 0.4343: K_n is "
            f"{kn / k_n_fixed[i]:.4f} times too high; corrected {k_n_fixed[i]:.4f}.",
            rounding=(("truncation to 4 decimals", math.floor(kn * 1e4) / 1e4),),
            corrected=float(k_n_fixed[i]),
        )
        for law, column, label in (
            ("K_st_uncorrected", "d_h_numerical_uncorrected_mm", "N-U"),
            ("K_st_corrected", "d_h_numerical_corrected_mm", "N-C"),
        ):
            d_h = jm.tangent_displacement(sigma_n[i], tau[i], p, law) / units.mm
            printed = getattr(row, column)
            log.check(
                "Table 3",
                item,
                f"d_h {label} from the stated stiffness [mm] (integral of d tau / K_st)",
                "d_h_mm",
                printed,
                d_h,
                "A joint loaded to tau under the stated stiffness law moves the integral of dtau/K_st "
                f"(elastic, no slip): {d_h:.4g} mm, {printed / d_h if d_h > 0 else math.inf:.3g} times "
                "less than printed. No unit (MPa/m), specimen length (60, 120 mm) or use of K_si maps the "
                "stiffnesses onto the displacements: the table's stiffnesses cannot have produced them.",
            )
