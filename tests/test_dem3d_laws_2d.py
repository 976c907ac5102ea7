"""Issue 36, item 3: shear in one direction reproduces the 2D law exactly. A 3D face contact (turned off
the axes) is driven through a shear in one direction and a varying closure; each step its sub-contacts'
closure and shear increment are fed to the 2D engine's share update (`bbmc.dem.contact_forces`'
`_normal_share`, `_shear_share`, and `bbmc.dem.joint_state.update_joint_laws` for Barton-Bandis), and
the two shear stresses must agree to round-off, for Mohr-Coulomb with after_slip keep and zero and for
Barton-Bandis."""

import math

import numpy as np
import pytest
from pydantic import TypeAdapter
from scipy.spatial.transform import Rotation

from bbmc.dem import layout as L
from bbmc.dem.contact_forces import _normal_share, _shear_share
from bbmc.dem.joint_state import update_joint_laws
from bbmc.dem.joint_types import _joint_law_row
from bbmc.dem3d import joint_laws as D3
from bbmc.dem3d.contact_forces import AREA, DILATION, FIRST_SUB, SLIPPED, SN, TAUX, USX
from bbmc.dem3d.joint_laws import BartonBandis, MobilizedBartonBandis, MohrCoulomb, joint_tables
from bbmc.dem3d.layout import VPX
from bbmc.dem3d.model import build_model
from bbmc.dem3d.scene_laws import law_from_scene
from bbmc.dem3d.solver import run
from bbmc.geometry.polyhedra import box, moved
from bbmc.laws import exact_tangent_coefficient
from bbmc.scene.schema import JointLaw as SceneJointLaw

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


CONSTANT = {"law": "constant", "kn_MPa_per_mm": 10.0, "ks_MPa_per_mm": 5.0, "friction_deg": 35.0,
            "cohesion_MPa": 0.1, "after_slip": "zero"}  # fmt: skip
PEAK = {"law": "barton_bandis", "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 10.0},
        "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 5.0},
        "strength": {"jrc": 12.0, "jcs_MPa": 80.0, "phi_b_deg": 30.0, "phi_r_deg": 26.0,
                     "lab_length_m": 0.1, "field_length_m": 2.0}}  # fmt: skip
MOBILIZED = {"law": "barton_bandis_mobilized", "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 10.0},
             "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 5.0}, "jrc0": 12.0, "jcs0_MPa": 80.0,
             "phi_b_deg": 30.0, "rebound_ratio": 0.7, "field_length_m": 2.0}  # fmt: skip


@pytest.mark.parametrize("keys", [CONSTANT, PEAK, MOBILIZED], ids=["constant", "barton_bandis", "mobilized"])
def test_a_scene_law_gives_the_3d_engine_the_2d_engines_parameters(keys):
    """A scene's joint law as a 3D joint type (`law_from_scene`): its stiffnesses, c, phi, JRC, JCS (at
    the field length), phi_b or phi_r, phi_max, the tangent's k, delta_peak, M and the stress floor are
    the 2D engine's for the same law (`bbmc.dem.joint_types`), to the bit, and so is its strength code."""
    law = TypeAdapter(SceneJointLaw).validate_python(keys)
    codes_3d, params_3d = joint_tables([law_from_scene("j", law)])
    codes_2d, params_2d = _joint_law_row(law)
    pairs = [(D3.P_KN, L.P_KN), (D3.P_KS, L.P_KS), (D3.P_COH, L.P_COH), (D3.P_PHI, L.P_PHI),
             (D3.P_JRC, L.P_JRC), (D3.P_JCS, L.P_JCS), (D3.P_PHI_B, L.P_PHI_B), (D3.P_PHI_MAX, L.P_PHI_MAX),
             (D3.P_PEAK_DISPLACEMENT, L.P_PEAK_DISPLACEMENT), (D3.P_DAMAGE, L.P_DAMAGE)]  # fmt: skip
    if keys is not CONSTANT:
        pairs.append(
            (D3.P_STRESS_FLOOR, L.P_STRESS_FLOOR) if keys is MOBILIZED else (D3.P_K_TANGENT, L.P_K_TANGENT)
        )
    for i3, i2 in pairs:
        assert params_3d[0, i3] == params_2d[i2]
    assert codes_3d[0, D3.STRENGTH_LAW] == codes_2d[L.STRENGTH_LAW]
    assert (codes_3d[0, D3.AFTER_SLIP] == D3.AFTER_SLIP_ZERO) == (codes_2d[L.AFTER_SLIP] == L.AFTER_SLIP_ZERO)


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        ({"tensile_strength_MPa": 1.0}, "joint_laws.j.tensile_strength_MPa"),
        ({"breaks_into": "other"}, "joint_laws.j.breaks_into"),
        (
            {"normal_stiffness": {"law": "eq8", "q_per_mm": 7.0}},
            "joint_laws.j.normal_stiffness: the law 'eq8'",
        ),
        (
            {"shear_stiffness": {"law": "simplified", "kj_MPa_per_mm": 1.0, "nj": 0.5}},
            "joint_laws.j.shear_stiffness",
        ),
    ],
)
def test_a_scene_law_the_3d_engine_lacks_is_refused_in_one_line(edit, key):
    """What the 3D engine lacks (bonds, bridges, stress-dependent stiffness): one line naming the key."""
    base = CONSTANT if set(edit) & {"tensile_strength_MPa", "breaks_into"} else PEAK
    law = TypeAdapter(SceneJointLaw).validate_python({**base, **edit})
    with pytest.raises(ValueError, match=key):
        law_from_scene("j", law)
    bandis = TypeAdapter(SceneJointLaw).validate_python(
        {**MOBILIZED, "normal_stiffness": {"law": "bandis", "aperture_mm": 0.2}}
    )
    with pytest.raises(ValueError, match="normal_stiffness: the law 'bandis'"):
        law_from_scene("j", bandis)
