"""The laws run unchanged as plain Python (NUMBA_DISABLE_JIT=1), as STUMPY does for coverage and
debugging: the same source, the same numbers (to 1e-13: LLVM's and CPython's libm may differ in the
last bit of tan or pow)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from bbmc import laws

SCRIPT = (
    "from bbmc import laws; "
    "print(repr(float(laws.peak_shear_strength(0.1e6, 2.13, 3.31e6, 0.5585, 1.2217))), "
    "repr(float(laws.corrected_shear_stiffness(0.05e6, 9e8, 0.13e6, 0.14e6, 0.312, 0.7188))))"
)


def test_laws_give_the_same_numbers_without_jit() -> None:
    env = os.environ | {"NUMBA_DISABLE_JIT": "1"}
    run = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, check=True)
    strength, stiffness = (float(v) for v in run.stdout.split())
    assert strength == pytest.approx(
        float(laws.peak_shear_strength(0.1e6, 2.13, 3.31e6, 0.5585, 1.2217)), rel=1e-13
    )
    expected = float(laws.corrected_shear_stiffness(0.05e6, 9e8, 0.13e6, 0.14e6, 0.312, 0.7188))
    assert stiffness == pytest.approx(expected, rel=1e-13)
