"""The engine's machinery: contact search, faults, the run command, determinism."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc.cli import main
from bbmc.dem import joint_state
from bbmc.dem import layout as L
from bbmc.dem.detection import candidate_pairs
from bbmc.dem.motion import first_runaway
from bbmc.dem.solver import (
    SimulationError,
    _check_health,
    _critical,
    initial_state,
    load_scene,
    search_contacts,
)
from bbmc.geometry import polygons
from dem_scenes import block_on_base, constant_joint, edited, run_scene, write_scene
from stage_runs import ROOT


def _run(path, results):
    return CliRunner().invoke(main, ["run", "--config", str(path), "--results", str(results)])


def _boxes_overlap(world, start, a, b, margin):
    pa, pb = world[start[a] : start[a + 1]], world[start[b] : start[b + 1]]
    return not (
        pa[:, 0].min() - margin / 2 > pb[:, 0].max() + margin / 2
        or pb[:, 0].min() - margin / 2 > pa[:, 0].max() + margin / 2
        or pa[:, 1].min() - margin / 2 > pb[:, 1].max() + margin / 2
        or pb[:, 1].min() - margin / 2 > pa[:, 1].max() + margin / 2
    )


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.floats(0, 20), st.floats(0, 20), st.floats(0.05, 3), st.floats(0.05, 3), st.floats(-1.5, 1.5)
        ),
        min_size=2,
        max_size=40,
    ),
    st.floats(0.0, 0.5),
)
def test_grid_search_finds_exactly_the_pairs_an_all_pairs_search_finds(shapes, margin):
    """Random turned rectangles of mixed sizes: the grid broad phase returns every overlapping pair,
    once, and nothing else."""
    polys = [
        polygons.rotated(polygons.rectangle(x, y, w, h), t, np.array([x, y])) for x, y, w, h, t in shapes
    ]
    world = np.vstack(polys)
    start = np.concatenate([[0], np.cumsum([len(p) for p in polys])]).astype(np.int64)
    immobile = np.zeros(len(polys), dtype=bool)
    found = {tuple(p) for p in candidate_pairs(world, start, immobile, margin)}
    expected = {
        (a, b)
        for a in range(len(polys))
        for b in range(a + 1, len(polys))
        if _boxes_overlap(world, start, a, b, margin)
    }
    assert found == expected
    assert len(candidate_pairs(world, start, immobile, margin)) == len(found)


def test_search_skips_pairs_of_two_fixed_blocks():
    world = np.vstack([polygons.rectangle(0, 0, 1, 1), polygons.rectangle(1, 0, 1, 1)])
    start = np.array([0, 4, 8], dtype=np.int64)
    assert len(candidate_pairs(world, start, np.array([True, True]), 0.1)) == 0
    assert len(candidate_pairs(world, start, np.array([True, False]), 0.1)) == 1


def test_same_scene_gives_identical_files(tmp_path):
    path = write_scene(tmp_path, block_on_base(30.0, constant_joint(20.0), steps=1500))
    for name in ("a", "b"):
        assert _run(path, tmp_path / name).exit_code == 0
    for table in ("history", "blocks", "contacts", "summary"):
        first = (tmp_path / "a" / "run" / "block_on_base" / f"{table}.csv").read_bytes()
        assert first == (tmp_path / "b" / "run" / "block_on_base" / f"{table}.csv").read_bytes()


def test_run_writes_every_file(tmp_path):
    path = write_scene(tmp_path, block_on_base(30.0, constant_joint(20.0), steps=500))
    result = _run(path, tmp_path / "out")
    assert result.exit_code == 0, result.output
    written = sorted(p.name for p in (tmp_path / "out" / "run" / "block_on_base").iterdir())
    assert written == [
        "blocks.csv",
        "contacts.csv",
        "history.csv",
        "history.png",
        "provenance.json",
        "scene.png",
        "summary.csv",
        "warnings.csv",
    ]


def test_fixed_time_step_above_critical_is_refused_before_any_step(tmp_path):
    scene = block_on_base(0.0, constant_joint(30.0), steps=100)
    scene["solver"]["time_step"] = {"mode": "fixed", "step_s": 1e-2}
    result = _run(write_scene(tmp_path, scene), tmp_path / "out")
    assert result.exit_code == 2
    assert "key 'solver.time_step.step_s'" in result.output
    assert "critical" in result.output
    assert len(result.output.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def _stiffening_scene(step_s: float) -> dict:
    """Eq 8 normal stiffness (K_n proportional to sigma_n) under a normal stress ramped to 2 MPa."""
    joint = {
        "law": "barton_bandis",
        "strength": {"jrc": 2.13, "jcs_MPa": 3.31, "phi_b_deg": 32.0},
        "normal_stiffness": {"law": "eq8", "q_per_mm": 7.715},
        "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 1.0},
    }
    scene = block_on_base(0.0, joint, steps=4000, gravity=(0.0, 0.0), slider_fix=("rotation",), damping=0.8)
    scene["loads"] = {
        "edge_stresses": [{"block": "slider", "edge": "up", "sigma_n_MPa": 2.0, "ramp_steps": 3000}]
    }
    scene["solver"]["time_step"] = {"mode": "fixed", "step_s": step_s}
    scene["solver"]["update_interval_steps"] = 10
    return scene


def test_fixed_step_that_becomes_unstable_stops_the_run_naming_the_step(tmp_path):
    """The stress-dependent K_n grows 200-fold with the load: a fixed step fine at the start is above
    the critical one later; the run stops with one line naming the step, exit 3, nothing written."""
    model = load_scene(write_scene(tmp_path, _stiffening_scene(1.0)))
    state = initial_state(model)
    search_contacts(model, state)
    joint_state.update_joint_laws(
        state.contacts, state.subs, state.law_state, state.n_sub, model.laws, model.params, True
    )
    start_critical = _critical(model, state)
    result = _run(write_scene(tmp_path, _stiffening_scene(0.5 * start_critical)), tmp_path / "out")
    assert result.exit_code == 3, result.output
    line = result.output.strip()
    assert len(line.splitlines()) == 1
    assert line.startswith("bbmc run: error: step ")
    assert "above the critical step" in line
    assert not (tmp_path / "out").exists()


def test_runaway_block_is_reported_with_the_step_and_the_cause(tmp_path):
    model = load_scene(write_scene(tmp_path, block_on_base(0.0, constant_joint(30.0))))
    state = initial_state(model)
    search_contacts(model, state)
    state.clock[L.DT] = 1e-4
    state.clock[L.STEP] = 123
    state.blocks[1, L.VX] = 1e6
    with pytest.raises(SimulationError, match=r"step 123: block 'slider' has moved .* likely cause: a load"):
        _check_health(model, state)
    state.clock[L.DT] = 1.0
    with pytest.raises(SimulationError, match=r"likely cause: time step 1 s above the critical step"):
        _check_health(model, state)
    state.blocks[1, L.VX] = math.nan
    with pytest.raises(SimulationError, match="non-finite"):
        _check_health(model, state)


def test_first_runaway_is_the_first_block_the_numpy_check_finds():
    """The one-pass health check finds the block the plain numpy definition does: a non-finite
    position (not only a velocity) or a travel (|v| + |w| R) dt / size above the fraction."""
    rng = np.random.default_rng(7)
    blocks = np.zeros((6, L.BLOCK_COLUMNS))
    blocks[:, [L.VX, L.VY, L.W]] = rng.normal(0.0, 1.0, (6, 3))
    blocks[:, L.RADIUS], blocks[:, L.SIZE] = 0.5, 1.0
    dt, fraction = 1e-3, 0.1
    assert first_runaway(blocks, dt, fraction) == -1
    for column, value, block in ((L.TH, math.inf, 4), (L.Y, math.nan, 2), (L.VX, 1e3, 1)):
        blocks[block, column] = value
        b = blocks
        finite = np.all(np.isfinite(b[:, [L.X, L.Y, L.TH, L.VX, L.VY, L.W]]), axis=1)
        travel = (np.hypot(b[:, L.VX], b[:, L.VY]) + np.abs(b[:, L.W]) * b[:, L.RADIUS]) * dt / b[:, L.SIZE]
        bad = ~finite | (travel > fraction)
        assert first_runaway(blocks, dt, fraction) == int(np.argmax(bad)) == block


def test_interpenetration_beyond_the_limit_is_reported(tmp_path):
    """A joint far too soft for its 2 MPa load (closure 7 % of the block size, the limit 5 %): the run
    finishes, and says so on stderr and in its files."""
    scene = block_on_base(
        0.0,
        constant_joint(30.0, k_MPa_per_mm=0.1),
        steps=3000,
        gravity=(0.0, 0.0),
        damping=0.8,
        slider_fix=("rotation",),
    )
    scene["loads"] = {
        "edge_stresses": [{"block": "slider", "edge": "up", "sigma_n_MPa": 2.0, "ramp_steps": 2000}]
    }
    result = _run(write_scene(tmp_path, scene), tmp_path / "out")
    assert result.exit_code == 0
    assert "warning: step" in result.output and "interpenetrate" in result.output
    out = tmp_path / "out" / "run" / "block_on_base"
    assert "interpenetrate" in (out / "warnings.csv").read_text()
    summary = pd.read_csv(out / "summary.csv").set_index("quantity")["value"]
    assert summary["largest_interpenetration"] > 0.05


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"blocks.1.material": "granite"}, "blocks.1.material"),
        ({"contacts.default_law": "nothing"}, "contacts.default_law"),
        ({"monitoring.monitors.0.block": "slidr"}, "monitoring.monitors.0.block"),
        ({"blocks.1.rectangle_m.width_m": -1.0}, "blocks.1.rectangle_m.width_m"),
        ({"solver.damping": 1.5}, "solver.damping"),
        ({"solver.law_update_stress_change": 0.0}, "solver.law_update_stress_change"),
        ({"joint_laws.joint.friction_deg": 95.0}, "joint_laws.joint.friction_deg"),
    ],
)
def test_bad_scene_gives_one_line_naming_the_key(tmp_path, change, key):
    scene = edited(block_on_base(0.0, constant_joint(30.0), steps=10), **change)
    result = _run(write_scene(tmp_path, scene), tmp_path / "out")
    assert result.exit_code == 2, result.output
    assert len(result.output.strip().splitlines()) == 1
    assert f"key '{key}'" in result.output
    assert not (tmp_path / "out").exists()


def test_non_convex_block_is_refused(tmp_path):
    scene = block_on_base(0.0, constant_joint(30.0), steps=10)
    scene["blocks"][1] = {
        "name": "slider",
        "material": "rock",
        "polygon_m": [[0, 0], [1, 0], [0.5, 0.2], [1, 1], [0, 1]],
    }
    result = _run(write_scene(tmp_path, scene), tmp_path / "out")
    assert result.exit_code == 2
    assert "not strictly convex" in result.output


def test_unknown_scene_key_suggests_the_right_one(tmp_path):
    scene = block_on_base(0.0, constant_joint(30.0), steps=10)
    scene["solver"]["dampng"] = 0.5
    result = _run(write_scene(tmp_path, scene), tmp_path / "out")
    assert result.exit_code == 2
    assert "did you mean 'damping'" in result.output


def test_run_needs_a_scene():
    result = CliRunner().invoke(main, ["run"])
    assert result.exit_code == 2
    assert "--config" in result.output


def test_prescribed_velocity_drags_a_block_at_that_speed(tmp_path):
    """A block given x velocity 0.005 m/s moves 0.005 m/s x time, whatever the joint does."""
    scene = block_on_base(0.0, constant_joint(30.0), steps=2000)
    scene["blocks"][1]["velocity"] = {"x_m_s": 0.005}
    h = run_scene(tmp_path, scene).history
    np.testing.assert_allclose(h["ux_mm"] * 1e-3, 0.005 * h["time_s"], rtol=1e-9, atol=1e-12)


def test_prescribed_velocity_waits_for_its_start_step(tmp_path):
    """velocity.start_step: the block is held until that step, then moves at the velocity."""
    scene = block_on_base(0.0, constant_joint(30.0), steps=2000, every=50)
    scene["blocks"][1]["velocity"] = {"x_m_s": 0.005, "start_step": 500}
    h = run_scene(tmp_path, scene).history
    before, after = h[h["step"] <= 500], h[h["step"] > 500]
    assert np.all(before["ux_mm"] == 0.0)
    started = h.loc[h["step"] == 500, "time_s"].iloc[0]
    np.testing.assert_allclose(after["ux_mm"] * 1e-3, 0.005 * (after["time_s"] - started), rtol=1e-9)


def test_loads_act_from_their_start_step(tmp_path):
    """A block force with start_step 600 (ramped over 200 steps): nothing moves before step 600, the
    frictionless block slides after it."""
    scene = block_on_base(0.0, constant_joint(0.0, k_MPa_per_mm=1.0), steps=1200, every=50, gravity=(0, 0))
    scene["loads"] = {
        "block_forces": [{"block": "slider", "force_kN": [1.0, 0.0], "ramp_steps": 200, "start_step": 600}]
    }
    h = run_scene(tmp_path, scene).history
    assert np.all(h.loc[h["step"] <= 600, "ux_mm"] == 0.0)
    assert h["ux_mm"].iloc[-1] > 0.0


def test_equilibrium_stop_waits_until_every_load_acts_in_full(tmp_path):
    """A slowly ramped load is in near balance all along its ramp: the equilibrium stop must not end
    the run before the ramp is over."""
    scene = block_on_base(0.0, constant_joint(30.0), steps=20_000, damping=0.8, gravity=(0, 0), every=50)
    scene["loads"] = {
        "edge_stresses": [
            {"block": "slider", "edge": "up", "sigma_n_MPa": 1.0, "ramp_steps": 3000},
            {"block": "slider", "edge": "up", "tau_MPa": 0.2, "ramp_steps": 2000, "start_step": 3000},
        ]
    }
    scene["solver"]["stop"] = {"unbalanced_force_ratio": 1e-2}
    result = run_scene(tmp_path, scene)
    summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
    assert summary["stopped_by_equilibrium"] == 1
    assert 5000 <= summary["steps"] < 20_000


def test_a_block_out_of_moment_balance_is_not_settled(tmp_path):
    """A block held in x and y but free to turn, under a moment of 1 kN m: its forces balance, its
    moment does not. The unbalanced-force ratio counts the moment (as the force that makes it at the
    block's radius), so the equilibrium stop never fires and the block turns; the same block without
    the moment stops at once. (Before, a block free only to turn was left out of the ratio.)"""
    scene = block_on_base(0.0, constant_joint(30.0), steps=2000, every=100, gravity=(0.0, 0.0))
    scene["blocks"][1]["fix"] = ["x", "y"]
    scene["blocks"][1]["rectangle_m"]["y_m"] = 0.1  # clear of the base: nothing resists the turning
    scene["solver"]["time_step"] = {"step_s": 1e-4}
    scene["solver"]["stop"] = {"unbalanced_force_ratio": 1e-3}
    turning = edited(scene, **{"loads": {"block_forces": [{"block": "slider", "moment_kN_m": 1.0}]}})
    for run, expected in ((turning, 0), (scene, 1)):
        result = run_scene(tmp_path, run)
        summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
        assert summary["stopped_by_equilibrium"] == expected
    assert abs(run_scene(tmp_path, turning).history["rot_deg"].iloc[-1]) > 1.0


def test_the_trend_of_the_motion_ends_a_creep_and_a_run_coming_to_rest(tmp_path):
    """stop.trend_window_steps (`bbmc.dem.verdict`): a block sliding steadily down a 40-degree,
    20-degree-friction incline under heavy damping is called a creep long before it has moved the
    failure displacement; the same block on a 45-degree-friction joint settles and is called coming to
    rest (or in equilibrium) well before the step limit."""
    for friction, reasons in ((20.0, {"creep", "projected"}), (45.0, {"decaying", "equilibrium"})):
        scene = block_on_base(40.0, constant_joint(friction), steps=200_000, every=100, gap_m=-1e-6)
        scene["solver"]["damping"] = 0.8
        scene["solver"]["stop"] = {
            "displacement_m": 1.0,
            "unbalanced_force_ratio": 1e-9,
            "trend_window_steps": 1000,
        }
        result = run_scene(tmp_path, scene)
        summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
        stopped = {reason for reason in reasons if summary.get(f"stopped_by_{reason}")}
        assert stopped, (friction, summary)
        assert summary["steps"] < 200_000
        moved = np.hypot(result.history["ux_mm"].iloc[-1], result.history["uy_mm"].iloc[-1])
        assert moved < 1000.0


def test_displacement_stop_ends_a_sliding_run(tmp_path):
    """stop.displacement_m: a block sliding down a 40-degree, 20-degree-friction incline stops the
    run once it has moved 5 mm, long before the step limit."""
    scene = block_on_base(40.0, constant_joint(20.0), steps=50_000, every=10, gap_m=-1e-6)
    scene["solver"]["stop"] = {"displacement_m": 0.005, "unbalanced_force_ratio": 1e-9}
    result = run_scene(tmp_path, scene)
    summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
    assert summary["stopped_by_displacement"] == 1 and summary["stopped_by_equilibrium"] == 0
    moved = np.hypot(result.history["ux_mm"].iloc[-1], result.history["uy_mm"].iloc[-1])
    assert 5.0 < moved < 6.0
    assert summary["steps"] < 50_000


def test_displacement_stop_sees_a_block_driven_at_a_velocity(tmp_path):
    """A block with every dof prescribed, driven at 0.01 m/s, still ends the run by the displacement
    stop (within half the search margin of the limit)."""
    scene = block_on_base(0.0, constant_joint(30.0), steps=10**7, every=1000)
    scene["blocks"][1]["fix"] = ["y", "rotation"]
    scene["blocks"][1]["velocity"] = {"x_m_s": 0.01}
    scene["solver"]["stop"] = {"displacement_m": 0.002}
    scene["solver"]["time_step"] = {"step_s": 1e-4}  # a held block's joint sets no critical step
    result = run_scene(tmp_path, scene)
    summary = dict(zip(result.summary["quantity"], result.summary["value"], strict=True))
    assert summary["stopped_by_displacement"] == 1
    assert 2.0 < result.history["ux_mm"].iloc[-1] < 2.0 + 0.5 * 0.02 * 200


def test_square_standing_on_its_corner_is_held_by_the_corner_contact(tmp_path):
    """A square standing on its corner (the only contact at step 0, with the automatic step): the
    corner contact holds it up as it tips over onto a face; nothing sinks in, nothing is warned of."""
    scene = block_on_base(0.0, constant_joint(30.0), steps=3000, every=100, damping=0.8)
    scene["blocks"][1].update(
        rectangle_m={"x_m": 0.0, "y_m": 0.0, "width_m": 0.2, "height_m": 0.2},
        rotate_deg=45.0,
        rotate_about_m=[0.0, 0.0],
    )
    result = _run(write_scene(tmp_path, scene), tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert "warning:" not in result.output
    blocks = pd.read_csv(tmp_path / "out" / "run" / "block_on_base" / "blocks.csv")
    assert blocks["uy_mm"].iloc[1] > -100 * (math.sqrt(2) - 1) * 1.01  # its centroid fell to a face at most


def test_fixed_step_error_names_the_scene_file(tmp_path):
    scene = block_on_base(0.0, constant_joint(30.0), steps=100)
    scene["solver"]["time_step"] = {"mode": "fixed", "step_s": 1e-2}
    path = write_scene(tmp_path, scene)
    assert f"{path}: key 'solver.time_step.step_s'" in _run(path, tmp_path / "out").output


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"monitoring.monitors.2.point_m": [0.1, 0.1]}, "point_m applies to ux and uy only"),
        (
            {
                "joint_laws.joint": {
                    "law": "barton_bandis",
                    "strength": {"jrc": 2, "jcs_MPa": 3, "phi_b_deg": 75},
                    "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 1},
                    "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 1},
                }
            },
            "must exceed phi_b_deg",
        ),
    ],
)
def test_meaningless_scene_values_are_refused(tmp_path, change, message):
    scene = edited(block_on_base(0.0, constant_joint(30.0), steps=10), **change)
    result = _run(write_scene(tmp_path, scene), tmp_path / "out")
    assert result.exit_code == 2
    assert message in result.output


def test_the_documented_example_scene_runs_as_written(tmp_path):
    """The first yaml block of docs/scene-format.md is configs/scenes/example.yaml, and it runs."""
    doc = (ROOT / "docs" / "scene-format.md").read_text()
    block = doc.split("```yaml\n", 1)[1].split("```", 1)[0]
    assert block == (ROOT / "configs" / "scenes" / "example.yaml").read_text()
    path = tmp_path / "example.yaml"
    path.write_text(block)
    result = _run(path, tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert "warning:" not in result.output
