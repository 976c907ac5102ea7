"""The 3D engine's rigid-body motion (`bbmc.dem3d.motion`) and its time step (`bbmc.dem3d.time_step`).

Free flight against the conservation laws and closed forms, damping and density scaling off unless a
test says otherwise: energy and world angular momentum over 10^4 steps, second order, the Dzhanibekov
flips, the torque-free symmetric top's precession, constant force and torque, the quaternion's
normalisation, local damping, and the critical step against the exact eigenvalues of a spring bed.
"""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bbmc.dem3d.layout import (
    FX,
    I1,
    J1,
    MX,
    PRESCRIBED,
    QW,
    TX,
    VPX,
    VSTART,
    VX,
    WPX,
    WX,
    X,
)
from bbmc.dem3d.motion import (
    angular_momentum,
    body_angular_velocity,
    kinetic_energy,
    move_blocks,
    new_blocks,
    step_motion,
)
from bbmc.dem3d.quaternion import quaternion_from_matrix, rotation_matrix
from bbmc.dem3d.time_step import contact_stiffness, critical_time_step, scale_masses

NO_GRAVITY = np.zeros(3)
MOMENTS = np.array([1.0, 2.0, 3.0])  # [kg m^2]: three distinct principal moments
TILT = Rotation.from_euler("zyx", [0.3, 0.5, -0.2]).as_matrix()  # principal axes off the world's


def _block(moments=MOMENTS, axes=TILT, mass=5.0):
    return new_blocks(np.zeros((1, 3)), axes[None], np.array([mass]), np.asarray(moments)[None], np.ones(1))


def _free(n=1):
    return np.zeros((n, 6), np.int64)


def _spin(blocks, dt, steps, every=1):
    """Free flight; returns the largest relative errors of E and |L| seen at every `every`th step."""
    dof = _free(len(blocks))
    e0, l0 = kinetic_energy(blocks)[0], np.linalg.norm(angular_momentum(blocks)[0])
    worst_e = worst_l = 0.0
    for s in range(steps):
        move_blocks(blocks, dof, NO_GRAVITY, 0.0, dt, s)
        if s % every == every - 1:
            worst_e = max(worst_e, abs(kinetic_energy(blocks)[0] / e0 - 1.0))
            worst_l = max(worst_l, abs(np.linalg.norm(angular_momentum(blocks)[0]) / l0 - 1.0))
    return worst_e, worst_l


def test_free_flight_keeps_energy_and_angular_momentum_to_second_order():
    """Spin about a non-principal axis, |w| 2.2 rad/s, 10^4 steps of 1 ms (w dt 2e-3, 22 rad turned):
    E within 1e-6 (measured 4.4e-9) and |L| within 1e-6 (the splitting keeps world L exactly: measured
    3e-13, round-off); E's error is O(dt^2) (measured ratio 4.0 at half the step over the same time)."""
    blocks = _block()
    blocks[0, WX : WX + 3] = [1.0, 0.3, 2.0]
    l0 = angular_momentum(blocks)[0]
    coarse = blocks.copy()
    e1, l1 = _spin(coarse, 1e-3, 10_000, every=5)
    assert e1 < 1e-6
    assert l1 < 1e-6
    assert np.linalg.norm(angular_momentum(coarse)[0] - l0) < 1e-11 * np.linalg.norm(l0)
    e2, _ = _spin(blocks.copy(), 5e-4, 20_000, every=10)
    assert e1 / e2 >= 3.5


def test_the_orientation_converges_at_second_order():
    """The orientation after 2 s against a run at dt/16: the error shrinks by >= 3.5 when dt halves
    (a first-order scheme gives 2; measured 4.00 and 4.00)."""
    start = _block()
    start[0, WX : WX + 3] = [1.0, 0.3, 2.0]

    def orientation(dt):
        blocks = start.copy()
        _spin(blocks, dt, round(2.0 / dt), every=10**9)
        return rotation_matrix(blocks[0, QW : QW + 4])

    reference = orientation(1e-3 / 16)
    errors = [np.abs(orientation(dt) - reference).max() for dt in (1e-2, 5e-3, 2.5e-3)]
    assert errors[0] / errors[1] >= 3.5
    assert errors[1] / errors[2] >= 3.5


def _principal_history(axis, dt=1e-3, steps=20_000, perturbation=1e-3):
    """Spin at 2 pi rad/s about principal `axis` (0, 1, 2 of moments 1, 2, 3) with a small perturbation;
    returns the body-frame angular velocities at every 10th step and the worst E, |L| errors."""
    blocks = _block()
    body = np.full(3, perturbation * 2.0 * math.pi)
    body[axis] = 2.0 * math.pi
    blocks[0, WX : WX + 3] = TILT @ body
    e0, l0 = kinetic_energy(blocks)[0], np.linalg.norm(angular_momentum(blocks)[0])
    history, worst_e, worst_l = [], 0.0, 0.0
    for s in range(steps):
        move_blocks(blocks, _free(), NO_GRAVITY, 0.0, dt, s)
        if s % 10 == 0:
            history.append(body_angular_velocity(blocks)[0])
            worst_e = max(worst_e, abs(kinetic_energy(blocks)[0] / e0 - 1.0))
            worst_l = max(worst_l, abs(np.linalg.norm(angular_momentum(blocks)[0]) / l0 - 1.0))
    return np.array(history), worst_e, worst_l


@pytest.mark.parametrize("axis", [0, 2])
def test_spin_about_the_major_and_minor_axes_is_stable(axis):
    """20 s (20 turns) about the smallest or largest moment's axis: w stays within 1 % of that axis
    (its share of |w| > 0.99; the perturbation is 1e-3 and only oscillates)."""
    history, worst_e, worst_l = _principal_history(axis)
    share = np.abs(history[:, axis]) / np.linalg.norm(history, axis=1)
    assert share.min() > 0.99
    assert np.all(history[:, axis] > 0.0)
    assert worst_e < 1e-6 and worst_l < 1e-10


def test_spin_about_the_intermediate_axis_flips_and_keeps_e_and_l():
    """Dzhanibekov: about the intermediate axis, w_2 reverses again and again (the growth rate is
    2 pi sqrt((I2 - I1)(I3 - I2) / (I1 I3)) = 3.6 /s, so from 1e-3 a flip every ~4.5 s: >= 3 in 20 s),
    while E stays within 1e-5 (w dt = 6.3e-3 here; measured 3.6e-6, 5 flips) and |L| to round-off (1e-10)."""
    history, worst_e, worst_l = _principal_history(1)
    signs = np.sign(history[:, 1])
    flips = np.count_nonzero(signs[1:] != signs[:-1])
    assert flips >= 3
    assert np.abs(history[:, 1]).max() > 0.99 * 2.0 * math.pi  # each flip is a full reversal
    assert worst_e < 1e-5 and worst_l < 1e-10


def test_torque_free_symmetric_top_precesses_at_the_closed_form_rates():
    """I1 = I2 = 1, I3 = 3: in the body, w's transverse part turns about e3 at (I3 - I1) / I1 w3 (Euler's
    equations); in the world, the symmetry axis turns about L at |L| / I1 (Landau & Lifshitz, Mechanics,
    section 33). Both within 1e-5 relative after 5 s (the phase error is O((w dt)^2), w dt 3e-3)."""
    moments = np.array([1.0, 1.0, 3.0])
    blocks = _block(moments)
    w_body = np.array([0.5, 0.0, 1.0])
    blocks[0, WX : WX + 3] = TILT @ w_body
    L = angular_momentum(blocks)[0]
    dt, steps = 1e-3, 5000
    axis0 = rotation_matrix(blocks[0, QW : QW + 4])[:, 2]
    body_turn = world_turn = 0.0
    previous_body, previous_axis = w_body[:2], axis0
    e_l = L / np.linalg.norm(L)
    for s in range(steps):
        move_blocks(blocks, _free(), NO_GRAVITY, 0.0, dt, s)
        now_body = body_angular_velocity(blocks)[0, :2]
        cross = previous_body[0] * now_body[1] - previous_body[1] * now_body[0]
        body_turn += math.atan2(cross, previous_body @ now_body)
        axis = rotation_matrix(blocks[0, QW : QW + 4])[:, 2]
        a, b = previous_axis - (previous_axis @ e_l) * e_l, axis - (axis @ e_l) * e_l
        world_turn += math.atan2(np.cross(a, b) @ e_l, a @ b)
        previous_body, previous_axis = now_body, axis
    time = steps * dt
    assert body_turn == pytest.approx((moments[2] - moments[0]) / moments[0] * w_body[2] * time, rel=1e-5)
    assert world_turn == pytest.approx(np.linalg.norm(L) / moments[0] * time, rel=1e-5)


def test_constant_torque_and_constant_force_are_exact():
    """From rest at t = 0 (the leapfrog's start: v(-dt/2) = -a dt/2): under a constant torque about a
    principal axis w(t + dt/2) = T (t + dt/2) / I and the angle T t^2 / 2 I; under gravity v = g (t +
    dt/2), x = g t^2 / 2: central differences are exact for a constant acceleration, to round-off (1e-11
    relative: 3000 steps, w turned into the principal frame and back in each)."""
    blocks = _block()
    torque = 0.7 * TILT[:, 1]  # about principal axis 2 (I = 2), in the world frame
    g = np.array([0.0, 0.0, -9.81])
    dt, steps = 1e-3, 3000
    blocks[0, VX : VX + 3] = -0.5 * g * dt
    blocks[0, WX : WX + 3] = -0.5 * torque / MOMENTS[1] * dt
    q0 = blocks[0, QW : QW + 4].copy()
    for s in range(steps):
        blocks[0, TX : TX + 3] = torque
        step_motion(blocks, _free(), dt, gravity=g, step=s)
    t = steps * dt
    for column, expected in ((VX, g * (t - 0.5 * dt)), (X, 0.5 * g * t**2),
                             (WX, torque / MOMENTS[1] * (t - 0.5 * dt))):  # fmt: skip
        assert np.linalg.norm(blocks[0, column : column + 3] - expected) < 1e-11 * np.linalg.norm(expected)
    angle = 0.5 * 0.7 / MOMENTS[1] * t**2
    turned = Rotation.from_rotvec(angle * TILT[:, 1]).as_matrix() @ rotation_matrix(q0)
    assert rotation_matrix(blocks[0, QW : QW + 4]) == pytest.approx(turned, abs=1e-12)


def test_the_quaternion_stays_unit_and_turns_body_points_by_r_of_q():
    """10^4 steps of a tumbling block with a changing torque: |q| = 1 to 1e-15 (renormalised each step);
    R(q) is a rotation (R R^T = 1 to 1e-14) and turns body points as the rotation the block has made
    about its axis w dt: checked against scipy's rotation of the same rotation vector step by step."""
    blocks = _block()
    blocks[0, WX : WX + 3] = [3.0, -1.0, 2.0]
    rng = np.random.default_rng(7)
    worst = 0.0
    for s in range(10_000):
        blocks[0, TX : TX + 3] = rng.normal(size=3)
        move_blocks(blocks, _free(), NO_GRAVITY, 0.0, 1e-3, s)
        worst = max(worst, abs(np.linalg.norm(blocks[0, QW : QW + 4]) - 1.0))
    assert worst < 4e-16
    r = rotation_matrix(blocks[0, QW : QW + 4])
    assert r @ r.T == pytest.approx(np.eye(3), abs=1e-14)
    assert quaternion_from_matrix(r) == pytest.approx(
        np.sign(blocks[0, QW]) * blocks[0, QW : QW + 4], abs=1e-14
    )


def test_a_body_point_follows_the_block_about_a_fixed_principal_axis():
    """About a principal axis the rotation is a plain turn: after n steps of w the body point b is at
    R_axis(n w dt) R0 b."""
    blocks = _block()
    w = 1.3 * TILT[:, 2]
    blocks[0, WX : WX + 3] = w
    for s in range(1000):
        move_blocks(blocks, _free(), NO_GRAVITY, 0.0, 1e-3, s)
    b = np.array([0.2, -0.4, 0.9])
    expected = Rotation.from_rotvec(w * 1.0).as_matrix() @ TILT @ b
    assert rotation_matrix(blocks[0, QW : QW + 4]) @ b == pytest.approx(expected, abs=1e-12)


def test_held_rotations_about_world_x_and_y_leave_z_free():
    """A plane-strain twin: rotation held about world x and y, free about z, principal axes tilted. The
    constrained kick gives w_z = T_z t / J_zz (J_zz = e_z^T R J R^T e_z, constant under turns about z)
    and w_x = w_y = 0 exactly; a prescribed w_x applies from its start step."""
    blocks = _block()
    dof = _free()
    dof[0, 3:5] = PRESCRIBED
    j_zz = TILT[2] @ np.diag(MOMENTS) @ TILT[2]
    for s in range(1000):
        blocks[0, TX : TX + 3] = [5.0, -3.0, 0.4]
        move_blocks(blocks, dof, NO_GRAVITY, 0.0, 1e-3, s)
    assert blocks[0, WX : WX + 2] == pytest.approx([0.0, 0.0], abs=0.0)
    assert blocks[0, WX + 2] == pytest.approx(0.4 * 1.0 / j_zz, rel=1e-12)
    blocks[0, WPX] = 0.25
    blocks[0, VSTART] = 1002
    move_blocks(blocks, dof, NO_GRAVITY, 0.0, 1e-3, 1001)
    assert blocks[0, WX] == 0.0
    move_blocks(blocks, dof, NO_GRAVITY, 0.0, 1e-3, 1002)
    assert blocks[0, WX] == 0.25


def test_prescribed_translation_moves_at_its_velocity_from_its_start_step():
    blocks = _block()
    dof = _free()
    dof[0, :3] = PRESCRIBED
    blocks[0, VPX : VPX + 3] = [1.0, 0.0, -2.0]
    blocks[0, VSTART] = 10
    for s in range(20):
        step_motion(blocks, dof, 0.1, step=s)
    assert blocks[0, X : X + 3] == pytest.approx([1.0, 0.0, -2.0], rel=1e-12)


def _oscillate(damping, steps=4000, dt=1e-3):
    """A block on a translational spring k = 100 N/m and a rotational one k_r = 50 N m/rad (the torque
    -k_r phi, phi the rotation vector from the start); returns the total energy at start and end [J]."""
    blocks = _block()
    k, k_r = 100.0, 50.0
    blocks[0, VX : VX + 3] = [0.3, -0.2, 0.1]
    blocks[0, WX : WX + 3] = [0.2, 0.1, -0.3]
    start = Rotation.from_matrix(TILT)

    def energy():
        phi = (Rotation.from_quat(blocks[0, QW : QW + 4], scalar_first=True) * start.inv()).as_rotvec()
        x = blocks[0, X : X + 3]
        return kinetic_energy(blocks)[0] + 0.5 * k * x @ x + 0.5 * k_r * phi @ phi, x, phi

    e0 = energy()[0]
    for s in range(steps):
        _, x, phi = energy()
        blocks[0, FX : FX + 3] = -k * x
        blocks[0, TX : TX + 3] = -k_r * phi
        move_blocks(blocks, _free(), NO_GRAVITY, damping, dt, s)
    return e0, energy()[0]


def test_local_damping_removes_energy_and_none_keeps_it():
    """Undamped, the spring block keeps its energy within 1 % over 4 s (velocities at half steps and the
    small-angle torque: measured 0.15 %); with Cundall damping 0.8 on all six dofs it loses > 99 %
    (measured 99.98 %)."""
    e0, e_end = _oscillate(0.0)
    assert e_end == pytest.approx(e0, rel=1e-2)
    e0, e_end = _oscillate(0.8)
    assert e_end < 1e-2 * e0


def _spring_bed_stiffness(kn, ks, half, offset, axes, n=40):
    """The exact 6 x 6 stiffness (u, theta about the centroid) of a square spring bed of side 2 half,
    centre at `offset`, normal axes[:, 2], by the midpoint rule on n x n cells (exact for the quadratic
    moments up to O(1/n^2))."""
    s = (np.arange(n) + 0.5) / n * 2 * half - half
    cell = (2 * half / n) ** 2
    normal = axes[:, 2]
    d = kn * np.outer(normal, normal) + ks * (np.eye(3) - np.outer(normal, normal))
    k = np.zeros((6, 6))
    for a in s:
        for b in s:
            r = offset + a * axes[:, 0] + b * axes[:, 1]
            cross = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
            g = np.hstack([np.eye(3), -cross])  # displacement of the point: u + theta x r = u - [r]x theta
            k += cell * g.T @ d @ g
    return k


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_critical_step_bounds_a_face_contacts_exact_one(seed):
    """A block on a square face contact (rocking, shear lever and twist), oriented at random: the step
    from `contact_stiffness` and `critical_time_step` is below the exact critical step 2 / sqrt(lambda_max)
    of M^-1/2 K M^-1/2 for the block against a held one (a bound, with the neighbour's factor 2 it is
    sqrt(2) x more), and not needlessly short (> 0.3 x exact; measured 0.50-0.56)."""
    rng = np.random.default_rng(seed)
    axes = Rotation.random(random_state=rng).as_matrix()
    kn, ks, half = 1e9, 1e8 * (1 + 4 * rng.random()), 0.5 + rng.random()
    offset = -axes[:, 2] * (0.5 + rng.random()) + rng.normal(scale=0.2, size=3)
    mass, moments = 2600.0, np.array([400.0, 500.0, 700.0])
    blocks = new_blocks(np.zeros((1, 3)), np.eye(3)[None], np.array([mass]), moments[None], np.ones(1))
    area, polar = (2 * half) ** 2, (2 * half) ** 4 / 6.0
    k_t, k_r = contact_stiffness(kn, ks, area, polar, offset, axes[:, 2])
    step = critical_time_step(blocks, _free(), np.array([k_t]), np.array([k_r]), 0.0)
    k = _spring_bed_stiffness(kn, ks, half, offset, axes)
    scale = 1.0 / np.sqrt(np.r_[np.full(3, mass), moments])
    exact = 2.0 / math.sqrt(np.linalg.eigvalsh(scale[:, None] * k * scale[None, :]).max())
    assert 0.3 * exact < step < exact


@pytest.mark.parametrize("held", [(), (0,), (2,), (0, 2), (1, 2), (0, 1, 2)])
def test_the_critical_step_counts_the_free_rotations_only(held):
    """A block of principal moments (1, 3, 100) kg m^2 oriented at random, its rotations about the world
    axes `held` prescribed, on a rotational stiffness k_r alone: the step is 2 / sqrt(2 k_r / J) with J
    the least eigenvalue of its world inertia R diag(J) R^T restricted to the free axes (numpy's, to
    1e-12: round-off); the least principal moment with all three free, +inf with none. A plane-strain
    twin free about y alone so takes its step from its moment about y (`bbmc.dem3d.time_step`)."""
    axes = Rotation.random(random_state=np.random.default_rng(7)).as_matrix()
    moments = np.array([1.0, 3.0, 100.0])
    blocks = _block(moments=moments, axes=axes)
    dof = _free()
    dof[0, [3 + r for r in held]] = PRESCRIBED
    k_r = 1e6
    step = critical_time_step(blocks, dof, np.zeros(1), np.array([k_r]), 0.0)
    free = [r for r in range(3) if r not in held]
    if not free:
        assert step == math.inf
        return
    inertia = axes @ np.diag(moments) @ axes.T
    least = np.linalg.eigvalsh(inertia[np.ix_(free, free)]).min()
    assert step == pytest.approx(2.0 / math.sqrt(2.0 * k_r / least), rel=1e-12)
    assert least >= moments.min() * (1 - 1e-12)


def test_density_scaling_makes_the_fixed_step_a_safe_fraction_of_the_critical_one():
    """After `scale_masses` for dt and safety 0.5, the critical step is >= dt / 0.5, and masses and
    moments are never lowered below the true ones."""
    blocks = _block()
    k_t, k_r = np.array([1e10]), np.array([1e9])
    dt, safety, damping = 1e-3, 0.5, 0.8
    assert critical_time_step(blocks, _free(), k_t, k_r, damping) < dt
    scale_masses(blocks, _free(), k_t, k_r, dt, safety, damping)
    assert critical_time_step(blocks, _free(), k_t, k_r, damping) >= dt / safety * (1 - 1e-12)
    soft = _block()
    scale_masses(soft, _free(), np.array([1.0]), np.array([1.0]), dt, safety, damping)
    assert np.all(soft[0, MX : MX + 3] == 5.0) and np.all(soft[0, J1 : J1 + 3] == soft[0, I1 : I1 + 3])


def test_a_step_at_the_critical_bound_is_stable_and_one_past_the_exact_limit_is_not():
    """A block on a translational spring against a held one (omega^2 = k/m): at `critical_time_step`
    the motion stays bounded; at 1.01 x the exact limit 2 sqrt(m/k) it grows."""
    k, mass = 1e6, 5.0
    blocks = _block(mass=mass)
    bound = critical_time_step(blocks, _free(), np.array([k]), np.array([0.0]), 0.0)

    def amplitude(dt):
        b = _block(mass=mass)
        b[0, X] = 1e-3
        for s in range(2000):
            b[0, FX : FX + 3] = -k * b[0, X : X + 3]
            move_blocks(b, _free(), NO_GRAVITY, 0.0, dt, s)
        return abs(b[0, X])

    assert amplitude(bound) < 2e-3
    assert amplitude(1.01 * 2.0 * math.sqrt(mass / k)) > 1.0


def test_a_block_with_a_non_positive_moment_or_a_left_handed_frame_is_refused():
    with pytest.raises(ValueError, match="block 0"):
        _block(moments=[1.0, 0.0, 2.0])
    with pytest.raises(ValueError, match="block 0: the principal axes are left-handed"):
        _block(axes=np.diag([1.0, 1.0, -1.0]))
