"""Geometry that cannot be a physical start state is refused when the scene is loaded, naming the block
(or both blocks): one line, exit 2, nothing written."""

from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from bbmc.cli import main
from bbmc.config import ConfigError
from bbmc.dem.model import built_scene
from bbmc.geometry import polygons
from dem_scenes import block_on_base, constant_joint, edited, write_scene

STAR = [[math.cos(a), math.sin(a)] for a in np.radians(90 + 144 * np.arange(5))]


def _refused(tmp_path, scene: dict) -> str:
    results = tmp_path / "out"
    outcome = CliRunner().invoke(main, ["run", str(write_scene(tmp_path, scene)), "--results", str(results)])
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.stderr.strip().splitlines()
    assert ": error: " in lines[-1], outcome.stderr
    assert all(": warning: " in line for line in lines[:-1]), outcome.stderr  # implausible values
    assert not results.exists()
    return lines[-1]


def _with_slider(polygon) -> dict:
    scene = block_on_base(0.0, constant_joint(30.0), steps=10)
    scene["blocks"][1] = {"name": "slider", "material": "rock", "polygon_m": polygon}
    return scene


@pytest.mark.parametrize(
    ("polygon", "fault"),
    [
        ([[0, 0], [0, 0], [0.4, 0.2]], "two vertices coincide (vertices 0 and 1"),
        ([[0, 0], [0.2, 0.1], [0.4, 0.2]], "no area (its vertices lie on one line)"),
        ([[0, 0], [0.4, 0.2], [0.4, 0], [0, 0.2]], "edges cross each other"),
        ([[x + 1, y + 1] for x, y in STAR], "edges cross each other"),
        ([[0, 0], [0.4, 0], [0.2, 0.05], [0.4, 0.2], [0, 0.2]], "not strictly convex (a reflex"),
        (
            [[0, 0], [0.2, 0], [0.4, 0], [0.4, 0.2], [0, 0.2]],
            "not strictly convex (a reflex or straight angle",
        ),
        ([[1e12, 0], [1e12 + 1e-4, 0], [1e12, 1e-4]], "too small (0.000122 m across) for its distance"),
        ([[0, 0], [1e200, 0], [0, 1e200]], "its size (1e+200 m across) is beyond what floating point"),
        ([[0, 0], [1e-200, 0], [0, 1e-200]], "its size (1e-200 m across) is beyond what floating point"),
    ],
)
def test_a_block_that_is_no_rigid_convex_polygon_is_refused_by_name(tmp_path, polygon, fault):
    line = _refused(tmp_path, _with_slider(polygon))
    assert "key 'blocks.1.polygon_m': block 'slider': " in line
    assert fault in line, line


def test_blocks_overlapping_at_the_start_are_refused_naming_both(tmp_path):
    """The slider sunk 30 % of its height into the base: deeper than the interpenetration limit."""
    line = _refused(tmp_path, block_on_base(0.0, constant_joint(30.0), steps=10, gap_m=-0.06))
    assert "key 'blocks': blocks 'base' and 'slider' overlap by 0.06 m at the start" in line
    assert "(contacts.interpenetration_limit: 5 %)" in line


def test_crossing_blocks_are_refused_though_no_vertex_is_inside_the_other(tmp_path):
    """Two bars crossing like a plus sign: no vertex of one lies in the other, yet they overlap."""
    scene = block_on_base(0.0, constant_joint(30.0), steps=10)
    scene["blocks"][1]["rectangle_m"] = {"x_m": -0.1, "y_m": 0.5, "width_m": 2.0, "height_m": 0.1}
    post = {"x_m": 0.5, "y_m": 0.2, "width_m": 0.1, "height_m": 1.0}
    scene["blocks"].append({"name": "post", "material": "rock", "rectangle_m": post})
    assert "blocks 'slider' and 'post' overlap by 0.1 m" in _refused(tmp_path, scene)


def test_two_held_blocks_that_overlap_are_refused(tmp_path):
    scene = block_on_base(0.0, constant_joint(30.0), steps=10, gap_m=-0.1, slider_fix=("x", "y", "rotation"))
    assert "blocks 'base' and 'slider' overlap" in _refused(tmp_path, scene)


def test_a_block_pressed_in_less_than_the_limit_still_runs(tmp_path):
    """1 % of the slider's size into the base (under the 5 % limit): a start in compression, as the
    scene format allows."""
    scene = block_on_base(0.0, constant_joint(30.0, k_MPa_per_mm=0.001), steps=10, gap_m=-0.0028)
    outcome = CliRunner().invoke(main, ["run", str(write_scene(tmp_path, scene)), "--results", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output


@pytest.mark.parametrize(
    ("change", "key", "fault"),
    [
        (
            {"columns": 10_000, "rows": 1_000},
            "blocks.1.brick_wall",
            "columns x rows is 10,000,000 blocks, more than 1,000,000",
        ),
    ],
)
def test_a_generator_asked_for_too_many_blocks_is_refused(tmp_path, change, key, fault):
    scene = block_on_base(0.0, constant_joint(30.0), steps=10)
    wall = {"origin_m": [0, 0], "columns": 2, "rows": 2, "block_width_m": 0.2, "block_height_m": 0.1}
    scene["blocks"][1] = {"name": "wall", "material": "rock", "brick_wall": wall | change}
    line = _refused(tmp_path, edited(scene, **{"monitoring.monitors": []}))
    assert f"key '{key}" in line and fault in line, line


def test_a_slope_cut_into_too_many_blocks_is_refused(tmp_path):
    slope = {
        "height_m": 10.0,
        "face_angle_deg": 60.0,
        "crest_extent_m": 25.0,
        "toe_extent_m": 0.0,
        "depth_m": 0.0,
        "joint_sets": [{"dip_deg": 20, "spacing_m": 0.001}, {"dip_deg": 80, "spacing_m": 0.01}],
    }
    scene = block_on_base(0.0, constant_joint(30.0), steps=10)
    scene["blocks"] = [{"name": "slope", "material": "rock", "jointed_slope": slope}]
    line = _refused(tmp_path, edited(scene, **{"monitoring.monitors": []}))
    assert "key 'blocks.0.jointed_slope': the joint sets would cut the slope into up to" in line
    assert "more than 1,000,000" in line


def test_a_coordinate_that_is_no_number_is_a_fault():
    assert polygons.shape_fault(np.array([[0.0, 0.0], [1.0, math.nan], [0.0, 1.0]])) == (
        "a vertex coordinate is not a finite number"
    )
    assert (
        polygons.shape_fault(np.array([[0.0, 0.0], [1.0, 0.0]])) == "a block needs at least 3 vertices, got 2"
    )


def test_a_repeated_vertex_that_is_not_a_neighbour_is_named():
    """A polygon through the same point twice (two loops meeting there)."""
    loops = np.array([[0, 0], [1, 0], [1, 1], [0, 0], [-1, 0], [-1, -1]], dtype=float)
    assert polygons.shape_fault(loops) == "two vertices coincide (vertices 0 and 3)"


_polygon = st.lists(st.tuples(st.floats(-10, 10), st.floats(-10, 10)).map(list), min_size=3, max_size=7).map(
    lambda p: polygons.counter_clockwise(np.array(p, dtype=float))
)


@settings(max_examples=200, deadline=None)
@given(st.lists(_polygon, min_size=1, max_size=6))
def test_judging_many_polygons_at_once_is_judging_each_alone(shapes):
    """`shape_faults` over a whole scene names the same faults as one polygon at a time (a convex
    hull of random points is often among them)."""
    start = np.concatenate([[0], np.cumsum([len(s) for s in shapes])])
    together = polygons.shape_faults(np.concatenate(shapes), start)
    alone = {k: polygons.shape_fault(s) for k, s in enumerate(shapes)}
    assert together == {k: fault for k, fault in alone.items() if fault is not None}


@pytest.mark.parametrize(
    ("size", "x", "y"), [(1e-6, 0.0, 0.0), (1e6, 0.0, 0.0), (1.0, 5e5, 5e6), (1e-3, 1e5, 0)]
)
def test_a_square_of_any_size_anywhere_is_sound_with_its_mass_properties(size, x, y):
    """A square anywhere (UTM-like coordinates included) is a sound block, with area size^2, its centre
    as centroid and polar second moment size^4 / 6 to round-off of its own size."""
    square = polygons.rectangle(x, y, size, size)
    assert polygons.shape_fault(square) is None
    area, centroid, polar = polygons.mass_properties(square)
    assert area == pytest.approx(size**2, rel=1e-9)
    assert centroid == pytest.approx([x + size / 2, y + size / 2], rel=1e-15, abs=1e-12 * size)
    assert polar == pytest.approx(size**4 / 6, rel=1e-9)


def test_a_density_whose_mass_leaves_floating_point_is_refused(tmp_path):
    """5e-324 kg/m^3 (allowed: > 0) makes the slider's mass 0 in floating point, and the base's a
    subnormal number: the time step divided by them (a ZeroDivisionError from the engine). A scene file
    has it refused first, more than a factor of 10^6 below any rock's density; a scene the program
    builds is not judged so (its numbers are its own) and meets the engine's check."""
    scene = edited(
        block_on_base(0.0, constant_joint(30.0), steps=10), **{"materials.rock.density_kg_m3": 5e-324}
    )
    line = _refused(tmp_path, scene)
    assert "key 'materials.rock.density_kg_m3' = 4.94066e-324 is more than a factor of 10^6 outside" in line
    with pytest.raises(ConfigError) as refused:
        built_scene(scene, "built.yaml")
    line = str(refused.value)
    assert "key 'materials.rock.density_kg_m3': block 'base': its mass (1.48e-323 kg) and moment" in line
    assert line.endswith("are beyond floating point")
