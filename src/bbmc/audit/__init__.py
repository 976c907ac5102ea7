"""The audit of the paper's numbers: every derivable number recomputed, compared and judged.

Each `*_checks` function adds rows to an `AuditLog` (`bbmc.audit.log`): our value by the paper's stated
method, the paper's printed value, their difference, the verdict (`bbmc.comparison.judge`) and the
reasoning with the numbers that support it. Corrected values are offered where the paper's method is
wrong. One module per table or group of equations; docs/paper-audit.md tells the story these rows make
up.
"""

from __future__ import annotations

import pandas as pd

from bbmc.audit.equations import equation_checks
from bbmc.audit.fig2a import fig2a_unit_checks
from bbmc.audit.log import AuditInputs, AuditLog
from bbmc.audit.strength import peak_strength_checks, phi_c_checks
from bbmc.audit.table1 import table1_fit_checks
from bbmc.audit.table3 import table3_checks
from bbmc.audit.table4 import table4_checks

__all__ = ["AuditInputs", "AuditLog", "audit"]


def audit(ctx: AuditInputs) -> pd.DataFrame:
    """Every check, in the order of the paper."""
    log = AuditLog()
    table1_fit_checks(log, ctx)
    fig2a_unit_checks(log, ctx)
    peak_strength_checks(log, ctx)
    equation_checks(log, ctx)
    table3_checks(log, ctx)
    phi_c_checks(log, ctx)
    table4_checks(log, ctx)
    return log.table()
