"""Issue 36, item 3: shear in one direction reproduces the 2D law exactly. A 3D face contact (turned off
the axes) is driven through a shear in one direction and a varying closure; each step its sub-contacts'
closure and shear increment are fed to the 2D engine's share update (`bbmc.dem.contact_forces`'
`_normal_share`, `_shear_share`, and `bbmc.dem.joint_state.update_joint_laws` for Barton-Bandis), and
the two shear stresses must agree to round-off, for Mohr-Coulomb with after_slip keep and zero and for
Barton-Bandis."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bbmc.dem import layout as L
from bbmc.dem.contact_forces import _normal_share, _shear_share
from bbmc.dem.joint_state import update_joint_laws
from bbmc.dem3d.contact_forces import AREA, DILATION, FIRST_SUB, SLIPPED, SN, TAUX, USX
from bbmc.dem3d.joint_laws import BartonBandis, MobilizedBartonBandis, MohrCoulomb
from bbmc.dem3d.layout import VPX
from bbmc.dem3d.model import build_model
from bbmc.dem3d.solver import run
from bbmc.geometry.polyhedra import box, moved
from bbmc.laws import exact_tangent_coefficient

KN, KS = 1e9, 5e8  # Pa/m
DT, STEPS, SPEED = 0.01, 240, 1e-3  # s, 1, m/s: 2.4 mm of shear
TURN = Rotation.from_euler("zxz", (33.0, -71.0, 117.0), degrees=True).as_matrix()
MC = {"friction": math.atan(0.5), "cohesion": 1e5}
BB = {"jrc": 10.0, "jcs": 50e6, "phi_b": math.radians(30.0)}
FULL = {"jrc": 10.0, "jcs": 50e6, "phi_r": math.radians(25.0), "peak_displacement": 1e-3}


def law_2d(law):
    """The 2D engine's joint type of the same law: (law codes (1, LAW_COLUMNS), params (1, PARAMETERS))."""
    codes = np.zeros((1, L.LAW_COLUMNS), dtype=np.int64)
    codes[0, L.BREAKS_INTO] = -1
    codes[0, L.AFTER_SLIP] = L.AFTER_SLIP_ZERO if law.after_slip == "zero" else L.AFTER_SLIP_KEEP
    p = np.zeros((1, L.PARAMETERS))
    p[0, L.P_KN], p[0, L.P_KS], p[0, L.P_STRENGTH_DIVISOR] = law.kn, law.ks, 1.0
    if isinstance(law, MohrCoulomb):
        codes[0, L.STRENGTH_LAW] = L.STRENGTH_CONSTANT
        p[0, L.P_COH], p[0, L.P_PHI] = law.cohesion, law.friction
    elif isinstance(law, MobilizedBartonBandis):
        codes[0, L.STRENGTH_LAW] = L.STRENGTH_MOBILIZED
        p[0, L.P_JRC], p[0, L.P_JCS], p[0, L.P_PHI_B], p[0, L.P_PHI_MAX] = (
            law.jrc,
            law.jcs,
            law.phi_r,
            law.phi_max,
        )
        p[0, L.P_PEAK_DISPLACEMENT], p[0, L.P_DAMAGE] = law.peak_displacement, law.damage
        p[0, L.P_STRESS_FLOOR] = law.stress_floor
    else:
        codes[0, L.STRENGTH_LAW] = L.STRENGTH_BARTON_BANDIS
        p[0, L.P_JRC], p[0, L.P_JCS], p[0, L.P_PHI_B], p[0, L.P_PHI_MAX] = (
            law.jrc,
            law.jcs,
            law.phi_b,
            law.phi_max,
        )
        p[0, L.P_K_TANGENT] = exact_tangent_coefficient(law.jrc)
    return codes, p


def history_3d(law):
    """A 10 x 6 m block sunk 1 mm into a slab, pushed along its long side at SPEED while its closure
    swings by +-0.5 mm (a prescribed velocity), all turned by TURN: per step, the closure [m], the shear
    increment along the push [m], the shear stress along it [Pa], the slipped flag and the dilation [m]
    of the first share (the closure without the dilation: the geometric one)."""
    slab = moved(box([-20, -20, -5], [20, 20, 0]), TURN, np.zeros(3))
    block = moved(box([-5, -3, -0.001], [5, 3, 2]), TURN, np.zeros(3))
    model = build_model([slab, block], 2500.0, [law], held=[0, 1], refine=1)
    push, down = TURN[:, 0], -TURN[:, 2]
    rows, last, opened = [], 0.0, 0.0
    for k in range(STEPS):
        sink = 0.5e-3 * 2.0 * math.pi / (80 * DT) * math.cos(2.0 * math.pi * k / 80)  # d/dt of 0.5 mm sin
        model.blocks[1, VPX : VPX + 3] = SPEED * push + sink * down
        run(model, 1, DT)
        s = model.subs[model.contacts[0, FIRST_SUB]]
        assert s[AREA] > 0.0
        us = s[USX : USX + 3] @ push
        closure = s[SN] / law.kn - opened  # sigma_n is of the dilation before this step's
        rows.append((closure, us - last, s[TAUX : TAUX + 3] @ push, s[SLIPPED], s[DILATION]))
        opened = s[DILATION]
        last = us
    return np.array(rows)


def history_2d(law, closure, shear):
    """The 2D share through the same closures and shear increments: its shear stress, slip flag and
    dilation."""
    codes, params = law_2d(law)
    subs, state = np.zeros((1, L.SUB_COLUMNS)), np.zeros((1, L.LAW_STATE_COLUMNS))
    subs[0, L.KN], subs[0, L.KS] = law.kn, law.ks
    subs[0, L.COH], subs[0, L.TANPHI] = params[0, L.P_COH], math.tan(params[0, L.P_PHI])
    contacts = np.zeros((1, L.CONTACT_COLUMNS), dtype=np.int64)
    out = []
    for u, dus in zip(closure, shear, strict=True):
        was_closed = subs[0, L.SN] > 0.0
        closed, sn, _, _ = _normal_share(subs, 0, u + subs[0, L.DILATION], 0.0, 0.5, 1.0, 1.0)
        subs[0, L.SN] = sn  # the strength at this step's sigma_n, as the 3D engine takes it
        update_joint_laws(contacts, subs, state, 1, codes, params, False)
        dilates = codes[0, L.STRENGTH_LAW] == L.STRENGTH_MOBILIZED
        _shear_share(subs, state, 0, closed, sn, dus, was_closed, codes[0, L.AFTER_SLIP], 1.0, dilates)
        out.append((subs[0, L.TAU], subs[0, L.SLIPPED], subs[0, L.DILATION]))
    return np.array(out)


@pytest.mark.parametrize(
    "law",
    [
        MohrCoulomb(KN, KS, **MC, after_slip="keep"),
        MohrCoulomb(KN, KS, **MC, after_slip="zero"),
        BartonBandis(KN, KS, **BB, after_slip="keep"),
        BartonBandis(KN, KS, **BB, after_slip="zero"),
        MobilizedBartonBandis(KN, KS, **FULL),
    ],
    ids=["mc-keep", "mc-zero", "bb-keep", "bb-zero", "full-joint"],
)
def test_shear_in_one_direction_reproduces_the_2d_law(law):
    """The 3D share's shear stress along the push is the 2D share's at every step, to 1e-12 of its
    largest (round-off of the 3D vector's projection onto the turned plane; measured 2.7e-15), through
    the elastic rise, the first slip (in the same step: 121 for M-C, 135 for B-B) and the sliding at a
    strength that follows the swinging sigma_n (0.52 to 1.52 mm of closure)."""
    h3 = history_3d(law)
    h2 = history_2d(law, h3[:, 0], h3[:, 1])
    assert np.array_equal(h3[:, 3] != 0.0, h2[:, 1] != 0.0)
    assert h3[:, 3].any()
    scale = np.abs(h2[:, 0]).max()
    assert np.abs(h3[:, 2] - h2[:, 0]).max() < 1e-12 * scale
    assert np.abs(h3[:, 4] - h2[:, 2]).max() <= 1e-12 * max(np.abs(h2[:, 2]).max(), 1e-3)
