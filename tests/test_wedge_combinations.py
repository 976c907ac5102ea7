"""bbmc.slope.wedge.combinations and cases: the table of every pair over random joint sets (hypothesis):
one row per pair, sorted, a reason and no FS where no wedge forms; the FS of a pair does not depend on
which set is plane 1 where the height is the wedge's own H; shotcrete through the case against its
force built by hand."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc.slope.wedge.cases import Plane, WedgeSetting, analyse_case
from bbmc.slope.wedge.combinations import combination_table
from bbmc.slope.wedge.geometry import REASON_TEXT, WedgeReason
from bbmc.slope.wedge.mechanics import MohrCoulomb
from bbmc.slope.wedge.support import shotcrete_force

R = np.radians
PIT = WedgeSetting(face=(R(65), R(180)), upper=(R(10), R(180)), unit_weight=26e3, height_h=20.0)
planes = st.tuples(st.floats(5, 89), st.floats(0, 359.9), st.floats(0, 50e3), st.floats(10, 45))


def _plane(dip, direction, cohesion, friction) -> Plane:
    strength = MohrCoulomb(cohesion, R(friction))
    return Plane(R(dip), R(direction), lambda _length: strength)


@settings(max_examples=40, deadline=None)
@given(st.lists(planes, min_size=2, max_size=5))
def test_every_pair_is_one_row_sorted_with_its_reason(sets):
    """C(n, 2) rows; the wedges that form first, by FS ascending, each with a finite FS >= 0; the others
    with NaN and the reason it does not form."""
    named = {f"J{k}": _plane(*s) for k, s in enumerate(sets)}
    rows = combination_table(PIT, named, critical_fs=1.5)
    assert len(rows) == math.comb(len(sets), 2)
    assert {(r.plane_1, r.plane_2) for r in rows} == set(itertools.combinations(named, 2))
    formed = [r for r in rows if r.forms]
    assert rows[: len(formed)] == formed
    fs = [r.factor_of_safety for r in formed]
    assert fs == sorted(fs) and all(f >= 0.0 for f in fs)
    assert all(r.critical == (r.factor_of_safety < 1.5) for r in formed)
    for r in rows[len(formed) :]:
        assert math.isnan(r.factor_of_safety) and not r.critical
        assert r.reason in {REASON_TEXT[w] for w in WedgeReason if w != WedgeReason.FORMED}


@settings(max_examples=60, deadline=None)
@given(planes, planes)
def test_a_pairs_fs_does_not_depend_on_which_set_is_plane_1(a, b):
    """With the wedge's own height H the wedge is the same whichever set is plane 1: its FS and weight
    agree to 1e-9 relative (both orders form, or neither)."""
    one, two = _plane(*a), _plane(*b)
    forward, backward = analyse_case(PIT, one, two), analyse_case(PIT, two, one)
    assert (forward.analysis is None) == (backward.analysis is None)
    if forward.analysis is not None:
        fs = [float(c.analysis.factor_of_safety) for c in (forward, backward)]
        assert fs[1] == pytest.approx(fs[0], rel=1e-9, abs=1e-12)
        weights = [float(c.analysis.loads.weight) for c in (forward, backward)]
        assert weights[1] == pytest.approx(weights[0], rel=1e-9)


def test_shotcrete_is_the_force_on_the_face_traces():
    """Shotcrete through the case (passive, tau_s t (L_1 + L_2) into the face) against the same force
    built from the case's geometry and passed as passive support: equal FS (to 1e-12), and higher than
    without it."""
    one, two = _plane(60, 217, 0.0, 30), _plane(55, 129, 0.0, 30)
    bare = analyse_case(PIT, one, two)
    g = bare.geometry
    force = shotcrete_force(0.1, 500e3, g.trace_face_1 + g.trace_face_2, g.normal_face)
    sprayed = analyse_case(WedgeSetting(**{**vars(PIT), "shotcrete": (0.1, 500e3)}), one, two)
    by_hand = analyse_case(WedgeSetting(**{**vars(PIT), "passive": force}), one, two)
    fs = [float(c.analysis.factor_of_safety) for c in (bare, sprayed, by_hand)]
    assert fs[1] == pytest.approx(fs[2], rel=1e-12)
    assert fs[1] > fs[0]
