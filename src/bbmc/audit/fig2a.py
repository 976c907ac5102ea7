"""What the Fig 2a legends imply (eq 1 read with tau in kPa and d_h in mm) against Table 1's stiffnesses
and strengths and Table 3's test displacements."""

from __future__ import annotations

import numpy as np

from bbmc import laws, units
from bbmc.audit.log import AuditInputs, AuditLog


def fig2a_unit_checks(log: AuditLog, ctx: AuditInputs) -> None:
    """What the Fig 2a legends imply (tau in kPa, d_h in mm) against Table 1 and Table 3."""
    for legend in ctx.legends.itertuples():
        sigma_n = legend.sigma_n_kPa * units.kPa / units.MPa
        measured = ctx.table1[np.isclose(ctx.table1["sigma_n_MPa"], sigma_n)].iloc[0]
        implied_k = (1.0 / legend.slope_a) * units.kPa_per_mm / units.GPa_per_m
        log.check(
            "Fig 2a vs Table 1",
            f"sigma_n = {sigma_n:g} MPa",
            "K_si = 1/a of the legend (tau in kPa, d_h in mm)",
            "K_si_GPa_per_m",
            float(measured["K_si_GPa_per_m"]),
            implied_k,
            f"Eq 1 makes K_si = 1/m. Read in kPa and mm (the only reading of the right size for Table 3's "
            f"displacements) the legend gives {implied_k:.5f} GPa/m, "
            f"{measured['K_si_GPa_per_m'] / implied_k:.0f} times below Table 1; read in MPa, 1000 times "
            "more. No one unit or specimen-length factor links the two at all four stresses.",
        )
        implied_ult = (1.0 / legend.intercept_b) * units.kPa / units.MPa
        log.check(
            "Fig 2a vs Table 1",
            f"sigma_n = {sigma_n:g} MPa",
            "tau_ult = 1/b of the legend [MPa]",
            "tau_MPa",
            float(measured["tau_ult_MPa"]),
            implied_ult,
            "Eq 1 makes tau_ult = 1/n; every legend has n < 0, a negative asymptote: the curve stiffens "
            f"without bound at d_h = a/|b| = {legend.slope_a / abs(legend.intercept_b):.1f} mm instead of "
            "levelling off.",
        )
    for row in ctx.table3.itertuples():
        legend = ctx.legends[
            np.isclose(ctx.legends["sigma_n_kPa"] * units.kPa, row.sigma_n_MPa * units.MPa)
        ].iloc[0]
        d_h = laws.hyperbolic_shear_displacement(row.tau_MPa * 1e3, legend.slope_a, legend.intercept_b)
        log.check(
            "Fig 2a vs Table 3",
            f"sigma_n = {row.sigma_n_MPa:g} MPa, tau = {row.tau_MPa:g} MPa",
            "test d_h from the Fig 2a legend (kPa, mm)",
            "d_h_mm",
            row.d_h_test_mm,
            float(d_h),
            f"Eq 1 with the legend solved for d_h: {float(d_h) / row.d_h_test_mm:.2f} times the test value. "
            "The legends are in kPa and mm and of the right size, but do not pass through Table 3's test "
            "points (short by about a quarter at the peak).",
        )
