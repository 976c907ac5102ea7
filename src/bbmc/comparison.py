"""Comparing our numbers with the paper's: one tolerance per quantity, and the verdict rule.

A tolerance is half a unit of the last digit the paper prints for that quantity: a number we compute
"reproduces" the paper when it rounds to the printed value. Tolerances are never widened to absorb a
difference; a difference beyond them is explained (rounding variant, identified slip) or listed as a
paper inconsistency. The audit stage and the regression tests both use this module.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass


@dataclass(frozen=True)
class Tolerance:
    value: float
    unit: str
    why: str


TOLERANCES: dict[str, Tolerance] = {
    "fit_coefficient": Tolerance(5e-5, "as fitted", "Table 1 prints a, b to 4 decimals"),
    "R2": Tolerance(5e-5, "1", "Table 1 / Fig 2 print R^2 to 4 decimals"),
    "tau_MPa": Tolerance(5e-4, "MPa", "Table 1 prints stresses to 3 decimals"),
    "K_si_GPa_per_m": Tolerance(5e-3, "GPa/m", "Table 1 prints K_si to 2 decimals"),
    "K_MPa_per_mm": Tolerance(5e-5, "MPa/mm", "Table 3 prints stiffnesses to 4 decimals"),
    "Phi_deg": Tolerance(0.05, "deg", "Table 3 prints Phi to 1 decimal"),
    "C_kPa": Tolerance(5e-3, "kPa", "Table 3 prints C to 2 decimals"),
    "d_h_mm": Tolerance(5e-3, "mm", "Table 3 prints d_h to 2 decimals"),
    "constant_3dp": Tolerance(5e-4, "1", "printed to 3 decimals (0.016, 0.312)"),
    "constant_4dp": Tolerance(5e-5, "1", "printed to 4 decimals (0.3434, 0.7188, 22.4665, 0.1164)"),
    "table4_stiffness": Tolerance(0.05, "MPa/mm", "Table 4 prints 10.7"),
    "table4_angle": Tolerance(5e-3, "deg", "Table 4 prints 14.51"),
    "strength_MPa_2dp": Tolerance(5e-3, "MPa", "Tables 2 and 4 print 4.12, 3.31, 3.87"),
}

VERDICTS = ("reproduced", "rounding", "paper inconsistency", "not derivable")


def within(value: float, paper: float, tolerance: float) -> bool:
    """True when `value` rounds to the printed `paper` value (1e-9 relative slack for binary floats)."""
    return abs(value - paper) <= tolerance * (1.0 + 1e-9)


@dataclass(frozen=True)
class Judgement:
    verdict: str
    reproduction: str
    via: str
    via_value: float


def judge(
    paper: float,
    ours: float,
    tolerance: float,
    rounding: Sequence[tuple[str, float]] = (),
    explanations: Sequence[tuple[str, float]] = (),
    corrected: float | None = None,
) -> Judgement:
    """The verdict on one printed number.

    `ours` follows the paper's stated method. If it misses, a `rounding` variant (the same method with
    the paper's inputs rounded or unrounded differently) that hits makes it "rounding"; otherwise the
    number is a paper inconsistency, and an `explanations` variant that hits (an identified slip) is
    named. A `corrected` value that differs from the printed one (the method itself is wrong) makes it
    a paper inconsistency even when the arithmetic is reproduced.
    """
    via, via_value = "", float("nan")
    if within(ours, paper, tolerance):
        reproduction = "reproduced"
    else:
        hit = next(((n, v) for n, v in rounding if within(v, paper, tolerance)), None)
        if hit is None:
            reproduction = "not reproduced"
            hit = next(((n, v) for n, v in explanations if within(v, paper, tolerance)), None)
        else:
            reproduction = "rounding"
        if hit is not None:
            via, via_value = hit
    erratum = corrected is not None and not within(corrected, paper, tolerance)
    verdict = "paper inconsistency" if reproduction == "not reproduced" or erratum else reproduction
    return Judgement(verdict, reproduction, via, via_value)
