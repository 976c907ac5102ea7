"""The 3D engine's joint water and pseudo-static seismic load (issue 36, item 3): a block on the incline
(40 deg towards 117 deg, off the axes) under a uniform joint pressure, under water and under a seismic
coefficient against their closed forms, and a phreatic plane's load on a turned block against hand
statics (the divergence theorem over its wet part)."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bbmc.dem3d.joint_laws import MohrCoulomb
from bbmc.dem3d.layout import FX, TX, X, Z
from bbmc.dem3d.model import build_model
from bbmc.dem3d.seismic import seismic_gravity
from bbmc.dem3d.solver import time_step
from bbmc.dem3d.water import WaterTable, add_water_loads
from bbmc.geometry.polyhedra import box, moved
from bbmc.geometry.polyhedron_cutting import cut
from bbmc.geometry.polyhedron_mass import mass_properties
from test_dem3d_engine import DIP_DIRECTION, KN, PSI, RHO, G, Track, block_on_incline

GAMMA_W = 9810.0  # N/m3
B, H, PHI = 10.0, 1.0, math.radians(45.0)  # a low block (the base's normal force stays within its kern
# while it slides, e = tan(phi) h / 2 < b / 6, and the base closed all over) that holds dry: phi > psi
MASS = RHO * B * 10.0 * H


def acceleration_down_the_dip(uplift=0.0, **model_args):
    """The block's acceleration down the dip [m/s2] (undamped, a straight line through its velocity
    from 0.3 s to 1 s, after the springs' first swing)."""
    model, frame, _ = block_on_incline(B, H, math.degrees(PHI), uplift=uplift, **model_args)
    track = Track(model, time_step(model))
    t = track.run(1.0, 20)
    along = np.array(track.v) @ frame[:, 0]
    return np.polyfit(t[t > 0.3], along[t > 0.3], 1)[0]


WEIGHT = MASS * G
LIMIT_PRESSURE = WEIGHT * (math.cos(PSI) - math.sin(PSI) / math.tan(PHI)) / 100.0  # 3.023 kPa
LIMIT_COEFFICIENT = math.tan(PHI - PSI)  # k_h: 0.0875


def uniform_pressure(p):
    """The block's model arguments under a joint pressure p [Pa] on its base."""
    return {"uplift": p, "laws": [MohrCoulomb(KN, KN / 2, PHI, pressure=p)]}


def seismic(k):
    """The block's model arguments under a seismic coefficient k towards the dip direction."""
    return {
        "uplift": RHO * H * k * G * math.sin(PSI),
        "gravity": seismic_gravity((0.0, 0.0, -G), k, DIP_DIRECTION),
    }


def moved_late(model_args):
    """How far the block moves from 1.5 s to 2 s [m], local damping 0.8."""
    model, _, _ = block_on_incline(B, H, math.degrees(PHI), **model_args)
    track = Track(model, time_step(model))
    t = track.run(2.0, 20, damping=0.8)
    return np.linalg.norm(track.x[-1] - track.x[np.searchsorted(t, 1.5)])


def test_a_uniform_joint_pressure_lowers_the_effective_normal_force_by_p_a():
    """p = 8 kPa on the base (A = 100 m2) of a block that holds dry: it slides at m a = W sin psi -
    (W cos psi - p A) tan phi = 1.991 m/s2, within 1e-4 (the dry block's fit is good to 1e-5; measured
    4e-7). Its limit, tan psi = (W cos psi - p A) tan phi / (W sin psi), is at p* = 3.023 kPa: at 0.9 p*
    it holds (moves < 1 mm from 1.5 s to 2 s; measured 1e-14 m), at 1.1 p* it slides (> 1 cm; 2.5 cm)."""
    p = 8e3
    a = acceleration_down_the_dip(**uniform_pressure(p))
    expected = (WEIGHT * math.sin(PSI) - (WEIGHT * math.cos(PSI) - p * 100.0) * math.tan(PHI)) / MASS
    assert a == pytest.approx(expected, rel=1e-4)
    assert moved_late(uniform_pressure(0.9 * LIMIT_PRESSURE)) < 1e-3
    assert moved_late(uniform_pressure(1.1 * LIMIT_PRESSURE)) > 1e-2


def test_a_seismic_coefficient_out_of_the_slope_slides_the_block_at_the_closed_form():
    """k_h 0.3 towards the dip direction: the horizontal acceleration is cos psi down the dip and sin psi
    off the plane, so a = g ((sin psi + k_h cos psi) - (cos psi - k_h sin psi) tan phi) = 2.937 m/s2
    within 1e-4 (measured 2e-6); the limit k_h = tan(phi - psi) = 0.0875: at 0.9 of it the block holds
    (< 1 mm from 1.5 s to 2 s), at 1.1 it slides (> 1 cm)."""
    k = 0.3
    a = acceleration_down_the_dip(**seismic(k))
    expected = G * ((math.sin(PSI) + k * math.cos(PSI)) - (math.cos(PSI) - k * math.sin(PSI)) * math.tan(PHI))
    assert a == pytest.approx(expected, rel=1e-4)
    assert moved_late(seismic(0.9 * LIMIT_COEFFICIENT)) < 1e-3
    assert moved_late(seismic(1.1 * LIMIT_COEFFICIENT)) > 1e-2


def face_loads(block, table):
    """The force [N] and torque about the centroid [N m] of `table`'s water on a lone free block."""
    model = build_model([block], RHO, [MohrCoulomb(KN, KN / 2, 0.5)], water=table)
    model.blocks[:, FX : TX + 3] = 0.0
    faces = (model.vertices, model.vertex_start, model.face_vertices, model.face_start,
             model.block_face_start, model.face_normal)  # fmt: skip
    add_water_loads(model.blocks, model.dof, *faces, np.array(table.coefficients()))
    return (
        model.blocks[0, FX : FX + 3].copy(),
        model.blocks[0, TX : TX + 3].copy(),
        model.blocks[0, X : Z + 1],
    )


TURN = Rotation.from_euler("zxz", (33, -71, 117), degrees=True).as_matrix()
TURNED_BOX = moved(box([-4, -1, -2], [6, 5, 3]), TURN, np.array([1.0, 2.0, 0.5]))


@pytest.mark.parametrize("z0", [0.5, 20.0], ids=["crossing", "submerged"])
def test_a_phreatic_table_loads_a_block_as_hand_statics_say(z0):
    """The table z = z0 - 0.1 x + 0.2 y (tilted off the axes) on a 10 x 6 x 5 m box turned by Euler
    angles (33, -71, 117) deg, across it (z0 0.5) or over it (z0 20): by the divergence theorem the faces'
    load is -integral of grad p over the wet volume V_w, F = gamma_w V_w (-a, -b, 1) with a, b the table's
    slopes (Archimedes' buoyancy, and the seepage force of a tilted table), its torque about the centroid
    (c_w - x) x F, c_w the wet part's centroid (the box cut by the table, `polyhedron_cutting.cut`;
    crossing: 239.5 of 300 m3 wet). To 1e-9 of |F| (and of 10 m x |F|): each wet face part is integrated
    exactly, its linear pressure's resultant and moment (measured 1e-15 and 2e-14)."""
    table = WaterTable(GAMMA_W, (0.0, 0.0, z0), (0.1, -0.2, 1.0))
    force, torque, centroid = face_loads(TURNED_BOX, table)
    below, _ = cut(TURNED_BOX, np.array([0.1, -0.2, 1.0]), z0)  # z - z_table < 0: wet
    wet = mass_properties(below)
    assert (wet.volume < 300.0) == (z0 == 0.5)  # crossing: part of the box's 300 m3 is wet
    expected = GAMMA_W * wet.volume * np.array([0.1, -0.2, 1.0])
    assert np.abs(force - expected).max() < 1e-9 * np.linalg.norm(expected)
    moment = np.cross(wet.centroid - centroid, expected)
    assert np.abs(torque - moment).max() < 1e-9 * np.linalg.norm(expected) * 10.0


def test_a_block_above_the_table_is_dry():
    """The table at z = -10 m, below the whole box: no load."""
    force, torque, _ = face_loads(TURNED_BOX, WaterTable(GAMMA_W, (0.0, 0.0, -10.0), (0.0, 0.0, 1.0)))
    assert np.all(force == 0.0) and np.all(torque == 0.0)


def test_a_submerged_block_slides_at_its_buoyant_weight():
    """The incline's block (b 10, h 5, phi 20 deg) under a level table above it: its faces' load is
    the buoyancy gamma_w V, so it slides at a = g (1 - rho_w / rho) (sin psi - cos psi tan phi) = 2.143
    m/s2, within 1e-4 (the dry block's fit is good to 1e-5; measured 9e-6)."""
    table = WaterTable(GAMMA_W, (0.0, 0.0, 50.0), (0.0, 0.0, 1.0))
    model, frame, _ = block_on_incline(10.0, 5.0, 20.0, uplift=GAMMA_W * 5.0 * math.cos(PSI), water=table)
    track = Track(model, time_step(model))
    t = track.run(1.0, 20)
    along = np.array(track.v) @ frame[:, 0]
    a = np.polyfit(t[t > 0.3], along[t > 0.3], 1)[0]
    rho_w = GAMMA_W / G
    expected = G * (1.0 - rho_w / RHO) * (math.sin(PSI) - math.cos(PSI) * math.tan(math.radians(20.0)))
    assert a == pytest.approx(expected, rel=1e-4)


def test_water_and_seismic_refuse_bad_input_in_one_line():
    slab, block = box([-20, -20, -10], [20, 20, 0]), box([-4, -1, 0], [6, 5, 3])
    for water, match in (
        (WaterTable(GAMMA_W, (0, 0, 0), (1, 0, 0)), "vertical component"),
        (WaterTable(-1.0, (0, 0, 0), (0, 0, 1)), "unit_weight"),
    ):
        with pytest.raises(ValueError, match=match):
            build_model([slab, block], RHO, [MohrCoulomb(KN, KN, 0.5)], held=[0], water=water)
    with pytest.raises(ValueError, match="joint type 0: pressure"):
        build_model([slab, block], RHO, [MohrCoulomb(KN, KN, 0.5, pressure=-1.0)], held=[0])
    with pytest.raises(ValueError, match="horizontal_coefficient"):
        seismic_gravity((0, 0, -G), 1.5, 0.0)
