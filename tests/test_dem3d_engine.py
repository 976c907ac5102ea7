"""The assembled 3D engine: blocks from polyhedra, sub-contact forces, the cycle. Issue 36's block on an
incline in 3D (the plane dipping 40 deg towards 117 deg, off the axes, so an axis bias would show), a
face's rocking stiffness against its closed form, and the refinement study."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bbmc.dem3d.joint_laws import BartonBandis, MohrCoulomb, joint_tables, strength
from bbmc.dem3d.layout import FX, QW, TX, VX, X, Z
from bbmc.dem3d.model import build_model
from bbmc.dem3d.quaternion import rotation_matrix
from bbmc.dem3d.solver import forces, run, search, time_step
from bbmc.geometry.polyhedra import box, moved

G = 9.81
RHO = 2500.0  # kg/m3
KN = 1e9  # Pa/m: a 10 m block sinks ~0.1 mm under its weight, so the geometry stays the drawn one
PSI, DIP_DIRECTION = math.radians(40.0), math.radians(117.0)


def incline_frame(psi=PSI, alpha=DIP_DIRECTION):
    """Columns: down the dip, along the strike, the plane's upward normal (right-handed)."""
    u = np.array([math.cos(psi) * math.sin(alpha), math.cos(psi) * math.cos(alpha), -math.sin(psi)])
    n = np.array([math.sin(psi) * math.sin(alpha), math.sin(psi) * math.cos(alpha), math.cos(psi)])
    return np.column_stack([u, np.cross(n, u), n])


def block_on_incline(b, h, phi_deg, refine=1, uplift=0.0, **model_args):
    """A held base whose top is the incline, and a block b (down the dip) x 10 m (strike) x h on it, sunk
    by its static closure (under the effective stress: less the water's `uplift` [Pa]) so that it starts
    without a bounce; `model_args` go to `build_model` (default: M-C of phi_deg, K_s = K_n / 2). Returns
    (model, frame, the block's downhill bottom edge's middle in the world)."""
    frame = incline_frame()
    sink = (RHO * h * G * math.cos(PSI) - uplift) / KN
    base = moved(box([-60, -20, -10], [30, 20, 0]), frame, np.zeros(3))
    block = moved(box([-b / 2, -5, -sink], [b / 2, 5, h - sink]), frame, np.zeros(3))
    model_args.setdefault("laws", [MohrCoulomb(KN, KN / 2, math.radians(phi_deg))])
    model = build_model([base, block], RHO, held=[0], refine=refine, **model_args)
    return model, frame, frame @ np.array([b / 2, 0.0, -sink])


class Track:
    """Samples of block 1 every `every` steps: time, centroid, velocity, orientation."""

    def __init__(self, model, dt):
        self.model, self.dt = model, dt
        self.x0 = model.blocks[1, X : Z + 1].copy()
        self.r0 = rotation_matrix(model.blocks[1, QW : QW + 4])
        self.t, self.x, self.v, self.r = [], [], [], []

    def run(self, seconds, samples, damping=0.0):
        steps = round(seconds / self.dt / samples)
        for _ in range(samples):
            run(self.model, steps, self.dt, damping)
            self.t.append(self.model.step * self.dt)
            self.x.append(self.model.blocks[1, X : Z + 1].copy())
            self.v.append(self.model.blocks[1, VX : VX + 3].copy())
            self.r.append(rotation_matrix(self.model.blocks[1, QW : QW + 4]) @ self.r0.T)
        return np.array(self.t)

    def point(self, p0):
        """Where the material point at p0 (at the start) is at each sample."""
        return np.array([x + r @ (p0 - self.x0) for x, r in zip(self.x, self.r, strict=True)])

    def turn(self):
        """The rotation vector since the start at each sample [rad]."""
        return np.array([Rotation.from_matrix(r).as_rotvec() for r in self.r])


def sliding_acceleration(refine):
    """The measured acceleration down the dip of the sliding block (b 10, h 5, phi 20 deg, undamped):
    the slope of a straight line through its velocity from 0.5 s to 1.5 s (after the shear springs'
    first swing), and the largest turn [rad]."""
    model, frame, _ = block_on_incline(10.0, 5.0, 20.0, refine)
    dt = time_step(model)
    track = Track(model, dt)
    t = track.run(1.5, 30)
    along = np.array(track.v) @ frame[:, 0]
    late = t > 0.5
    return np.polyfit(t[late], along[late], 1)[0], np.abs(track.turn()).max()


EXPECTED_SLIDING = G * (math.sin(PSI) - math.cos(PSI) * math.tan(math.radians(20.0)))  # 3.571 m/s2


def test_a_face_rocking_stiffness_is_exact_at_any_refinement():
    """A 10 x 6 m face tilted by 1e-4 rad about five horizontal axes, closed all over: its moment about
    the footprint's centre is K_n theta I_axis exactly (I the footprint's second moment about the axis)
    at refinement 0, 1 and 2, and its force K_n A u_centre: the stress is integrated, not sampled (one
    point per share would leave refinement 0's two triangles no stiffness about the line through them).
    Tolerance 1e-6 relative: the 1e-4 rad tilt's second-order terms are 1e-8."""
    for refine in (0, 1, 2):
        for axis in ([1, 0, 0], [0, 1, 0], [1, 1, 0], [1, -1, 0], [1, 2, 0]):
            axis = np.asarray(axis, float) / np.linalg.norm(axis)
            turn = Rotation.from_rotvec(1e-4 * axis).as_matrix()
            block = moved(box([-5, -3, -0.001], [5, 3, 4.999]), turn, np.zeros(3))
            base = box([-20, -20, -10], [20, 20, 0])
            model = build_model([base, block], RHO, [MohrCoulomb(KN, KN / 2, 0.5)], held=[0], refine=refine)
            search(model)
            forces(model, 0.0)
            force, torque = model.blocks[1, FX : FX + 3], model.blocks[1, TX : TX + 3]
            about_centre = torque + np.cross(model.blocks[1, X : Z + 1], force)
            second = 6 * 10**3 / 12 * axis[1] ** 2 + 10 * 6**3 / 12 * axis[0] ** 2
            assert about_centre @ axis == pytest.approx(-KN * 1e-4 * second, rel=1e-6)
            assert force[2] == pytest.approx(KN * 60 * 0.001, rel=1e-6)


def test_block_on_incline_stable_just_above_the_dip_and_sliding_just_below():
    """b 10, h 10, phi 40.1 deg on psi 40 deg with local damping 0.8. The weight's line meets the base
    4.2 m below its centre, so a linear spring bed opens the uphill part of the base and the block rocks
    onto a strip 2.4 m wide; the first swings of the shear and rocking springs, released at once under
    full gravity, slip it about 1 cm (measured 1.04 cm at 2 s, against tau/K_s = 1.3 mm elastic). Then
    it holds: from 1.5 s to 2 s it moves less than 2 mm and |v| < 5 mm/s (measured 0 to 1e-5 mm and
    0 mm/s: at rest; while a share's shear force jumped from its centroid to its centre of pressure as it
    slipped, the rocking's swings ratcheted a creep of 1 mm/s). At phi 39.9 deg the same run slides on,
    its speed growing, as the closed form under local damping says: a = (1 - 0.8) g (sin psi - cos psi
    tan phi) = 4.54 mm/s2 (each step's damping opposes the velocity by 0.8 x the unbalanced force), so
    from its speed v at 1.5 s it moves v 0.5 s + a (0.5 s)^2 / 2 by 2 s, within 25 % (the rocking's
    swings ride on it; measured 3.02 mm against 2.67 mm, +13 %, and |v| 4.20 -> 7.15 mm/s)."""
    moved_late, speed = {}, {}
    for phi in (40.1, 39.9):
        model, _, _ = block_on_incline(10.0, 10.0, phi)
        track = Track(model, time_step(model))
        t = track.run(2.0, 20, damping=0.8)
        x, late = np.array(track.x), np.searchsorted(t, 1.5)
        moved_late[phi] = np.linalg.norm(x[-1] - x[late])
        speed[phi] = np.linalg.norm(track.v[late]), np.linalg.norm(track.v[-1])
        if phi == 40.1:
            assert np.linalg.norm(x[-1] - track.x0) < 0.03
            assert speed[phi][1] < 5e-3
    assert moved_late[40.1] < 2e-3
    damped = 0.2 * G * (math.sin(PSI) - math.cos(PSI) * math.tan(math.radians(39.9)))
    assert speed[39.9][1] > speed[39.9][0]
    assert moved_late[39.9] == pytest.approx(speed[39.9][0] * 0.5 + damped * 0.5**2 / 2, rel=0.25)


def test_sliding_block_accelerates_as_the_closed_form_says():
    """b 10, h 5, phi 20 deg, undamped: a = g (sin psi - cos psi tan phi) = 3.571 m/s2 within 0.5 %
    (the issue's tolerance; measured 0.003 %), without turning (< 0.1 deg; measured 0.001 deg)."""
    a, turn = sliding_acceleration(1)
    assert a == pytest.approx(EXPECTED_SLIDING, rel=5e-3)
    assert turn < math.radians(0.1)


def test_sliding_does_not_depend_on_the_refinement():
    """The sliding acceleration at refinement 0, 1 and 2 (2, 8 and 32 sub-contacts on the base): the
    three within 0.5 % of each other and of 3.571 m/s2 (measured: 0.003 % off each, spread 1e-14
    relative; the stresses are integrated over each share, so the sum does not see the cut)."""
    found = [sliding_acceleration(refine)[0] for refine in (0, 1, 2)]
    assert max(found) - min(found) < 5e-3 * EXPECTED_SLIDING
    for a in found:
        assert a == pytest.approx(EXPECTED_SLIDING, rel=5e-3)


def test_slender_block_topples_about_its_downhill_edge_without_sliding():
    """b/h 0.5 (b 10, h 20) with phi 45 deg > psi: the weight falls outside the base (b/h < tan psi), so
    it topples. In 1.5 s it turns more than 5 deg (measured 13.1) about the strike (the rotation
    vector within 2 deg of it, measured 0.005 deg, turning down the dip), while the middle of its
    downhill edge moves less than 3 cm along the plane (measured 0.76 cm: the elastic shear and the
    edge's nominal strip, 1 % of the block's size wide, sinking), against more than 1 m for the
    centroid (measured 2.41 m)."""
    model, frame, edge = block_on_incline(10.0, 20.0, 45.0)
    track = Track(model, time_step(model))
    track.run(1.5, 15)
    turn = track.turn()[-1]
    assert np.linalg.norm(turn) > math.radians(5.0)
    strike = frame[:, 1]
    assert turn @ strike > np.linalg.norm(turn) * math.cos(math.radians(2.0))
    slip = (track.point(edge)[-1] - edge) @ frame[:, 0]
    assert abs(slip) < 0.03
    assert (track.x[-1] - track.x0) @ frame[:, 0] > 1.0


def test_slender_block_on_a_weak_plane_slides_without_toppling():
    """b/h 0.5 (b 10, h 20) with phi 20 deg: Hoek & Bray's chart puts it in 'sliding and toppling'
    (psi > phi, b/h < tan psi), but once it slides the base carries N tan(phi) along the plane, so the
    resultant of weight and inertia leans tan(phi) = 0.364 off the normal, which is inside the base
    (b/h = 0.5): it slides without toppling (Sagaseta 1986, Rock Mech. Rock Eng. 19, 261-266). The
    engine agrees: a = 3.571 m/s2 within 0.5 % (measured 0.32 %: the tall block's slower rocking swings
    are still in the fitted window) and it turns less than 0.2 deg (measured 0.09 deg)."""
    model, frame, _ = block_on_incline(10.0, 20.0, 20.0)
    track = Track(model, time_step(model))
    t = track.run(1.5, 30)
    along = np.array(track.v) @ frame[:, 0]
    late = t > 0.5
    assert np.polyfit(t[late], along[late], 1)[0] == pytest.approx(EXPECTED_SLIDING, rel=5e-3)
    assert np.abs(track.turn()).max() < math.radians(0.2)


def test_frictionless_block_dropped_on_a_face_rebounds_to_its_height():
    """A 2 x 2 x 1 m block dropped flat from 0.5 m onto a held slab, frictionless and undamped: the
    contact is elastic, so it comes back up to within 1 % of its fall (measured 0.026 %, 0.13 mm).
    The step is a tenth of the critical one, about 38 steps in the 5 ms contact: the spring engages
    part-way through a step, an error of first order in dt, and at half the critical step (7 steps in
    the contact) the block comes back 1.2 % higher."""
    law = MohrCoulomb(KN, KN / 2, 0.0)
    slab = box([-5, -5, -1], [5, 5, 0])
    resting = build_model([slab, box([-1, -1, -1e-5], [1, 1, 1])], RHO, [law], held=[0])
    dt = time_step(resting, safety=0.1)
    model = build_model([slab, box([-1, -1, 0.5], [1, 1, 1.5])], RHO, [law], held=[0])
    z0 = model.blocks[1, Z]
    heights = []
    for _ in range(round(1.0 / dt)):  # the fall and the climb back take 0.64 s
        run(model, 1, dt)
        heights.append(model.blocks[1, Z])
    heights = np.array(heights)
    bottom = heights.argmin()
    assert heights[bottom] < 0.5
    assert heights[bottom:].max() == pytest.approx(z0, rel=0, abs=0.01 * 0.5)


def test_barton_bandis_strength_is_the_tangent_of_the_peak_envelope():
    """The B-B law's (c, tan phi) at sigma_n are the tangent's of `bbmc.laws` (the same functions):
    c + sigma_n tan phi equals the peak strength tau_p at that sigma_n to 1e-12."""
    from bbmc import laws

    law = BartonBandis(KN, KN / 2, jrc=8.0, jcs=50e6, phi_b=math.radians(30.0))
    codes, params = joint_tables([law])
    for sigma in (1e4, 2e5, 3e6):
        c, tan_phi, _ = strength(codes, params, 0, sigma, False, 0.0)
        tau_p = laws.peak_shear_strength(sigma, 8.0, 50e6, math.radians(30.0), math.radians(70.0))
        assert c + sigma * tan_phi == pytest.approx(float(tau_p), rel=1e-12)


def test_very_slender_block_on_a_weak_plane_slides_and_topples():
    """b/h 0.25 (b 10, h 40) with phi 20 deg: now tan(phi) = 0.364 > b/h, so sliding does not keep it
    from toppling; and toppling alone about the downhill edge would need, from rest, a friction of
    0.383 N at the edge (rigid blocks: alpha = M_edge / I_edge), more than the plane holds, so it slides
    and topples at once (Sagaseta 1986's region; it is narrow here, 14 deg < phi < 21 deg). In 1.2 s it
    turns more than 3 deg about the strike (measured 6.3) and its downhill edge slips more than 0.1 m
    down the plane (measured 0.29 m; a rigid pivot's closed form starts the edge at 0.70 m/s2, 0.48 m
    by then, but on a spring bed the block first pivots about a centre of pressure inside the base,
    which asks less friction, so it slips less)."""
    model, frame, edge = block_on_incline(10.0, 40.0, 20.0)
    track = Track(model, time_step(model))
    track.run(1.2, 12)
    turn = track.turn()[-1]
    assert turn @ frame[:, 1] > math.radians(3.0)
    assert (track.point(edge)[-1] - edge) @ frame[:, 0] > 0.1


def test_a_contact_takes_the_joint_type_of_its_blocks_groups():
    """Two blocks side by side on a held base: the base–block contacts (groups 0 and 1) take joint type 1,
    the block–block contact (groups 1 and 1) type 0; a table that is not square and symmetric, or names
    a joint type or group that does not exist, is refused in one line."""
    frame = incline_frame()
    base = moved(box([-60, -20, -10], [30, 20, 0]), frame, np.zeros(3))
    left = moved(box([-5, -5, 0], [5, 0, 5]), frame, np.zeros(3))
    right = moved(box([-5, 0, 0], [5, 5, 5]), frame, np.zeros(3))
    laws = [MohrCoulomb(KN, KN / 2, math.radians(60.0)), MohrCoulomb(KN, KN / 2, math.radians(20.0))]
    model = build_model([base, left, right], RHO, laws, held=[0], group=[0, 1, 1],
                        pair_joint=np.array([[0, 1], [1, 0]]))  # fmt: skip
    search(model)
    types = {(int(r[0]), int(r[1])): int(r[2]) for r in model.contacts}
    assert types[(1, 0)] == types[(2, 0)] == 1
    assert types[(1, 2)] == 0
    with pytest.raises(ValueError, match="pair_joint: must be a square, symmetric"):
        build_model([base, left], RHO, laws, held=[0], group=[0, 1], pair_joint=np.array([[0, 1], [0, 0]]))
    with pytest.raises(ValueError, match=r"pair_joint: joint types must be 0\.\.1"):
        build_model([base, left], RHO, laws, held=[0], group=[0, 1], pair_joint=np.array([[0, 2], [2, 0]]))
    with pytest.raises(ValueError, match=r"group: must be 0\.\.1"):
        build_model([base, left], RHO, laws, held=[0], group=[0, 2], pair_joint=np.array([[0, 1], [1, 0]]))
