"""The 3D engine's joint water and pseudo-static seismic load (issue 36, item 3): a block on the incline
(40 deg towards 117 deg, off the axes) under a uniform joint pressure and under a seismic coefficient
against their closed forms, and a phreatic plane's load on a face contact against hand statics."""

import math

import numpy as np
import pytest

from bbmc.dem3d.contact_forces import FIRST_SUB, PRESSURE, SUB_COUNT, contact_forces
from bbmc.dem3d.joint_laws import MohrCoulomb
from bbmc.dem3d.layout import FX, TX, X, Z
from bbmc.dem3d.model import build_model
from bbmc.dem3d.seismic import seismic_gravity
from bbmc.dem3d.solver import _geometry, search, time_step
from bbmc.dem3d.water import WaterTable
from bbmc.geometry.polyhedra import box
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


def one_step_load(water, refine):
    """A 10 x 6 m block sunk 1 mm into a slab (the slab held), its footprint x in [-4, 6], y in [-1, 5]:
    the force on it [N], its torque about the footprint's centre (1, 2, 0) [N m], and the sub-contacts'
    pressures, from one evaluation of the contact forces."""
    slab = box([-20, -20, -10], [20, 20, 0])
    block = box([-4, -1, -0.001], [6, 5, 3])
    model = build_model([slab, block], RHO, [MohrCoulomb(KN, KN / 2, 0.5)], held=[0], refine=refine,
                        water=water)  # fmt: skip
    search(model)
    model.blocks[:, FX : TX + 3] = 0.0
    contact_forces(model.blocks, _geometry(model), model.contacts, model.contact_values, model.subs,
                   model.law_codes, model.law_params, model.refine, 0.0)  # fmt: skip
    force, torque = model.blocks[1, FX : FX + 3], model.blocks[1, TX : TX + 3]
    about = torque + np.cross(model.blocks[1, X : Z + 1] - np.array([1.0, 2.0, 0.0]), force)
    first, count = model.contacts[0, FIRST_SUB], model.contacts[0, SUB_COUNT]
    return force, about, model.subs[first : first + count, PRESSURE]


def test_a_phreatic_plane_over_the_whole_contact_adds_its_hand_statics_uplift():
    """The table z = 3 - 0.1 x + 0.2 y (through (0, 0, 3), tilted off the axes) above the whole
    footprint (A 60 m2, centroid (1, 2)): the force on the block is K_n A 1 mm + U along z, U = gamma_w
    (z_table(1, 2) - z) A = gamma_w 3.301 m x 60 m2 (linear pressure: the centroids' sum is exact), to
    1e-9; no horizontal force. Its moment about the footprint's centre: the pressure's first moment,
    gamma_w (0.2 I_x, 0.1 I_y) (I the footprint's second moments, 180 and 500 m4), is placed at the
    shares' centroids, which miss each share's own second moment: refinement 0, 1 and 2 give 61 / 73 %,
    90 / 93 % and 97.6 / 98.3 % of it (about x / y), the shortfall a quarter per refinement (to 1e-6:
    each triangle's second moment is 1/16 of its parent's) and within 3 % at refinement 2."""
    table = WaterTable(GAMMA_W, (0.0, 0.0, 3.0), (0.1, -0.2, 1.0))
    found = []
    for refine in (0, 1, 2):
        force, about, _ = one_step_load(table, refine)
        uplift = GAMMA_W * (3.0 - 0.1 + 0.4 + 0.001) * 60.0
        assert force[2] == pytest.approx(KN * 60.0 * 0.001 + uplift, rel=1e-9)
        assert np.abs(force[:2]).max() < 1e-9 * force[2]
        found.append(about[:2] / (GAMMA_W * np.array([0.2 * 180.0, 0.1 * 500.0])))
    shortfall = 1.0 - np.array(found)
    assert np.all(shortfall > 0.0)
    assert shortfall[1:] / shortfall[:-1] == pytest.approx(0.25, rel=1e-6)
    assert shortfall[2].max() < 0.03


def test_a_contact_above_the_table_is_dry():
    """The table at z = -1 m, below the whole footprint: no pressure anywhere, the force K_n A u alone."""
    force, _, pressure = one_step_load(WaterTable(GAMMA_W, (0.0, 0.0, -1.0), (0.0, 0.0, 1.0)), 1)
    assert np.all(pressure == 0.0)
    assert force[2] == pytest.approx(KN * 60.0 * 0.001, rel=1e-9)  # the shares summed: round-off


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
