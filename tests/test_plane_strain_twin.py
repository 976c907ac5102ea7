"""Issue 36's plane-strain twin: a 2D scene extruded into 3D prisms with the out-of-plane constraints
(`bbmc.dem3d.extrusion`, `bbmc.fos.plane_strain_twin`) has the 2D blocks' mass properties per unit
depth, moves as the 2D engine does, and gives the 2D engine's factor of safety within 1 % (the issue's
tolerance) with the same search settings. Measured numbers are in each test's docstring."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from bbmc.dem import layout as L
from bbmc.dem.model import build_model as build_2d
from bbmc.dem.solver import advance, prepare
from bbmc.dem3d import monitors
from bbmc.dem3d.extrusion import extruded_model
from bbmc.dem3d.joint_laws import MohrCoulomb
from bbmc.dem3d.layout import FREE, I1, MASS, PRESCRIBED, QW, X, Z
from bbmc.dem3d.quaternion import rotation_matrix
from bbmc.dem3d.solver import run, time_step
from bbmc.fos.plane_strain_twin import section_polygons, twin_factor_of_safety, twin_model
from bbmc.fos.strength_reduction import factor_of_safety
from bbmc.geometry import polygons
from bbmc.scene.schema import Scene
from bbmc.slope import fos_cases as fc

DEPTH = 2.0  # m: any depth; the twin's forces are depth x the 2D engine's per-metre ones
LAW = MohrCoulomb(1e10, 1e10, math.radians(30.0))


def _model_2d(scene: dict):
    return build_2d(Scene.model_validate(scene, strict=False), Path("<test>"))


def test_prisms_have_the_2d_blocks_area_times_depth_centroid_and_in_plane_moment():
    """A triangle and a pentagon away from the origin: mass rho A d, centroid (x_c, d/2, y_c), and the
    moment about the extrusion axis rho d J_p (J_p the section's polar moment), to 1e-12 relative
    (round-off of the two mass integrals); y is a principal axis; the out-of-plane dofs held."""
    shapes = [
        np.array([[10.0, 5.0], [14.0, 5.0], [11.0, 9.0]]),
        np.array([[20.0, 0.0], [23.0, 0.5], [24.0, 3.0], [21.5, 4.5], [19.5, 2.5]]),
    ]
    model = extruded_model(shapes, DEPTH, 2500.0, [LAW])
    for i, shape in enumerate(shapes):
        area, centroid, polar = polygons.mass_properties(polygons.counter_clockwise(shape))
        assert model.blocks[i, MASS] == pytest.approx(2500.0 * area * DEPTH, rel=1e-12)
        assert model.blocks[i, X : Z + 1] == pytest.approx([centroid[0], DEPTH / 2, centroid[1]], rel=1e-12)
        axes = rotation_matrix(model.blocks[i, QW : QW + 4])
        inertia = axes @ np.diag(model.blocks[i, I1 : I1 + 3]) @ axes.T
        assert inertia[1, 1] == pytest.approx(2500.0 * DEPTH * polar, rel=1e-12)
        assert inertia[1, [0, 2]] == pytest.approx([0.0, 0.0], abs=1e-9 * inertia[1, 1])
        assert model.dof[i].tolist() == [FREE, PRESCRIBED, FREE, PRESCRIBED, FREE, PRESCRIBED]


def _incline(width: float, height: float, friction_deg: float, steps: int, dt: float) -> dict:
    """`bbmc.slope.fos_cases.block_on_plane` (30 deg) undamped, `steps` fixed steps of `dt` [s]."""
    law = {**fc.MOHR_COULOMB, "friction_deg": friction_deg}
    scene = fc.block_on_plane(law, width, height)
    return scene | {"solver": {"steps": steps, "damping": 0.0, "time_step": {"mode": "fixed", "step_s": dt}}}


@pytest.mark.parametrize("constraint", ["held", "walls"])
@pytest.mark.parametrize("friction_deg, height, tolerance", [(20.0, 1.0, 1e-5), (45.0, 4.0, 2e-3)])
def test_a_block_on_an_incline_moves_as_in_2d(constraint, friction_deg, height, tolerance):
    """A 2 m block on the 30 deg plane, undamped, 600 steps of 0.1 ms from touching: it drops onto its
    springs, bounces and slides (phi 20 deg, 1 m tall, 3.3 mm), or rocks on its base (phi 45 deg, 4 m
    tall, 1.05e-3 rad). The twin's centroid (x, z) and turn about -y are the 2D engine's (x, y, theta)
    to `tolerance` x the movement. Measured: 7.4e-6 sliding (the two engines' arithmetic differs, both
    integrate the same linear spring bed exactly); 8.8e-4 rocking, of the order of the tilt: the 2D
    engine takes the normal of the face a corner presses on (the base's), the 3D one the separating
    axis, and the two differ by the tilt. Out of plane it does not move (held: exactly; walls: within
    the in-plane tolerance x the movement, measured 5e-11 m sliding and 4.6e-9 m rocking, 1.4e-6 of the
    movement, since a share's friction acts at its centre of pressure whether stuck or slipping)."""
    steps, dt = 600, 1e-4
    model = _model_2d(_incline(2.0, height, friction_deg, steps, dt))
    state = prepare(model)
    advance(model, state, steps)
    twin = twin_model(model, DEPTH, constraint=constraint)
    start = twin.blocks[1, X : Z + 1].copy()
    r0 = rotation_matrix(twin.blocks[1, QW : QW + 4])
    run(twin, steps, dt)
    moved_2d = state.blocks[1, [L.X, L.Y]] - model.blocks[1, [L.X, L.Y]]
    moved_3d = twin.blocks[1, X : Z + 1] - start
    turn = rotation_matrix(twin.blocks[1, QW : QW + 4]) @ r0.T
    scale = float(np.hypot(*moved_2d))
    assert scale > 1e-3
    assert moved_3d[[0, 2]] == pytest.approx(moved_2d, abs=tolerance * scale)
    assert abs(moved_3d[1]) <= (0.0 if constraint == "held" else tolerance * scale)
    theta = state.blocks[1, L.TH]
    assert -math.atan2(turn[0, 2], turn[0, 0]) == pytest.approx(
        theta, rel=tolerance, abs=tolerance * scale / height
    )


def _fs_both(scene: dict, **twin) -> tuple[float, float]:
    model = _model_2d(scene)
    fs_2d = factor_of_safety(model)
    fs_3d = twin_factor_of_safety(model, **twin)
    assert fs_2d.bracketed and fs_3d.bracketed
    return fs_2d.factor_of_safety, fs_3d.factor_of_safety


@pytest.mark.parametrize("constraint", ["held", "walls"])
def test_the_cracked_planar_slope_twin_gives_the_2d_fs(constraint):
    """Hoek & Bray's planar slope with its tension crack, dry (`bbmc.slope.fos_cases`, H 30 m, face 60
    deg, plane 30 deg, c 48 kPa, phi 30 deg; the crack's water is refused by the 3D engine, so dry),
    both engines with the scene's search (tolerance 0.01 in F: a bracket 0.0078 wide, 0.6 % of the FS,
    so a 1 % difference shows): the twin's FS within 1 % of the 2D engine's (the issue's). Measured:
    2D 1.3477, 3D 1.3477 (the same bracket, [1.3438, 1.3516]) with either constraint; the 3D search
    about 2 s."""
    fs_2d, fs_3d = _fs_both(fc.hoek_bray_case(0.0, 0.0).scene, constraint=constraint)
    assert fs_3d == pytest.approx(fs_2d, rel=0.01)


def test_what_the_3d_engine_lacks_is_refused_naming_the_key():
    """Water, loads and a tensile strength, one line each naming the scene's key."""
    wet = _model_2d(fc.hoek_bray_case(0.5, 0.0).scene)
    with pytest.raises(ValueError, match=r"^water: "):
        twin_model(wet)
    loaded = _model_2d(fc.goodman_bray_case(40.0).scene)
    with pytest.raises(ValueError, match=r"^loads: "):
        twin_model(loaded)
    bonded = {**fc.MOHR_COULOMB, "tensile_strength_MPa": 0.1}
    with pytest.raises(ValueError, match=r"^joint_laws\.joint\.tensile_strength_MPa: "):
        twin_model(_model_2d(fc.block_on_plane(bonded, 2.0, 1.0)))


def test_section_polygons_are_the_2d_blocks():
    model = _model_2d(fc.hoek_bray_case(0.0, 0.0).scene)
    shapes = section_polygons(model)
    assert len(shapes) == 2
    area = polygons.mass_properties(shapes[1])[0]
    assert model.blocks[1, L.MASS] == pytest.approx(25.5e3 / fc.G * area, rel=1e-12)


def _toppling_toe(columns: int, friction_deg: float) -> dict:
    """The first `columns` columns of Goodman & Bray's toppling slope on their steps
    (`bbmc.slope.fos_cases.GOODMAN_BRAY`), the ramped block forces replaced by gravity tilted by the
    base dip (the 3D engine has no loads), so both engines run the same scene."""
    scene = dict(fc.goodman_bray_case(friction_deg).scene)
    scene.pop("loads")
    scene.pop("monitoring")
    scene["blocks"] = scene["blocks"][: 2 * columns]
    dip = fc.GOODMAN_BRAY.base_dip
    scene["gravity_m_s2"] = [-fc.G * math.sin(dip), -fc.G * math.cos(dip)]
    return scene


def test_three_toppling_columns_settle_in_3d_as_in_2d():
    """Goodman & Bray's first three columns (4, 8, 12 m tall, 10 m wide) at phi 60 deg, 2,000 steps of
    each engine at the 2D engine's step (0.30 ms; the twin's own is 0.27 ms) and damping 0.8: both
    settle (unbalanced-force ratio below 1e-5; measured 2D 6e-12, 3D 2e-11) and the three columns'
    centroids move as in 2D within 5 % (measured 14.7, 35.1, 60.9 um in 2D, 14.6, 34.3, 59.9 um in 3D:
    2.2 % at most; the two engines take a rocking corner's normal differently,
    `test_a_block_on_an_incline_moves_as_in_2d`, and the damped path to rest follows), whatever the
    depth (0.25, 1, 4, 20 m: 2.5 % at most). Before the clipping passed over degenerate edges
    (`bbmc.dem3d.polygon_clip.clip_polygon`) the held twin never settled: its prisms' end edges
    coincide exactly, the overlap of two columns' faces came with two near-copies of a corner, and the
    round-off edge between them cut every share away for a step, dropping the contact's shear."""
    steps = 2000
    model = _model_2d(_toppling_toe(3, 60.0))
    state = prepare(model)
    advance(model, state, steps)
    moved_2d = np.hypot(*(state.blocks[:, [L.X, L.Y]] - model.blocks[:, [L.X, L.Y]]).T)
    twin = twin_model(model, DEPTH)
    start = twin.blocks[:, X : Z + 1].copy()
    reference = monitors.reference_force(twin)
    assert time_step(twin, 0.5, 0.8) > 0.8 * state.dt_range[0]
    run(twin, steps, state.dt_range[0], 0.8)
    assert monitors.unbalanced_force_ratio(twin, reference) < 1e-5
    moved_3d = np.linalg.norm(twin.blocks[:, X : Z + 1] - start, axis=1)
    columns = [1, 3, 5]
    assert moved_2d[columns].min() > 1e-5
    assert moved_3d[columns] == pytest.approx(moved_2d[columns], rel=0.05)


def test_the_toppling_toe_twin_gives_the_2d_fs():
    """Goodman & Bray's first three columns at phi 40 deg (gravity tilted by the base dip, as
    `_toppling_toe`), both engines with the scene's search (tolerance 0.01 in F: a bracket 0.0078
    wide, 0.5 % of the FS, so a 1 % difference shows): the held twin's FS within 1 % of the 2D
    engine's (the issue's). Measured: 2D 1.4492, 3D 1.4492 (the same bracket, [1.4453, 1.4531]);
    the 3D search about 3 s. The whole ten-column slope, too long to run here (the 3D search 170 s):
    2D 1.0977, 3D 1.0977 (the same bracket); 3D 1.0742 with the step of the least principal moment,
    2.4 x shorter, whose trials' step budgets covered 2.4 x less time."""
    fs_2d, fs_3d = _fs_both(_toppling_toe(3, 40.0))
    assert fs_3d == pytest.approx(fs_2d, rel=0.01)
