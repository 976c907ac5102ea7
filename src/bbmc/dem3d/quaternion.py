"""Unit quaternions as rotations: products, rotating vectors, the rotation matrix and back.

A quaternion is q = (w, x, y, z), scalar first; the unit quaternion (cos a/2, sin a/2 n) is the
rotation by the angle a [rad] about the unit axis n, right-handed, and R(q) its rotation matrix. The
product p * q rotates by q first, then by p: R(p * q) = R(p) R(q). Kernels pass the four components as
scalars and get tuples back (no arrays allocated in the hot loop).
"""

import math

import numba
import numpy as np

# below this angle [rad] sin(a/2)/a is its Taylor series 1/2 - a^2/48 (exact to round-off there)
SMALL_ANGLE = 1e-4


@numba.njit(cache=True, inline="always")
def multiply(a0, a1, a2, a3, b0, b1, b2, b3):
    """Hamilton product a * b (rotation by b, then by a)."""
    return (
        a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
        a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
        a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
        a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
    )


@numba.njit(cache=True, inline="always")
def rotate(q0, q1, q2, q3, v0, v1, v2):
    """R(q) v for a unit q: v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)."""
    t0 = 2.0 * (q2 * v2 - q3 * v1)
    t1 = 2.0 * (q3 * v0 - q1 * v2)
    t2 = 2.0 * (q1 * v1 - q2 * v0)
    return (
        v0 + q0 * t0 + q2 * t2 - q3 * t1,
        v1 + q0 * t1 + q3 * t0 - q1 * t2,
        v2 + q0 * t2 + q1 * t1 - q2 * t0,
    )


@numba.njit(cache=True, inline="always")
def rotate_back(q0, q1, q2, q3, v0, v1, v2):
    """R(q)^T v for a unit q: the world vector v in the body frame."""
    return rotate(q0, -q1, -q2, -q3, v0, v1, v2)


@numba.njit(cache=True, inline="always")
def from_rotation_vector(t0, t1, t2):
    """The unit quaternion of the rotation by the angle |t| about t / |t| [rad]."""
    angle = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    s = 0.5 - angle * angle / 48.0 if angle < SMALL_ANGLE else math.sin(0.5 * angle) / angle
    return math.cos(0.5 * angle), s * t0, s * t1, s * t2


@numba.njit(cache=True, inline="always")
def normalised(q0, q1, q2, q3):
    """q / |q|: a unit quaternion again after round-off has moved it off the unit sphere."""
    n = 1.0 / math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return q0 * n, q1 * n, q2 * n, q3 * n


@numba.njit(cache=True, inline="always")
def angle_between(p0, p1, p2, p3, q0, q1, q2, q3):
    """Angle of the rotation that takes orientation p to orientation q [rad], in [0, pi]: 2 atan2 of the
    vector and scalar parts of p^-1 q (exact near 0, where an arccos of the dot product loses half the
    digits)."""
    r0, r1, r2, r3 = multiply(p0, -p1, -p2, -p3, q0, q1, q2, q3)
    return 2.0 * math.atan2(math.sqrt(r1 * r1 + r2 * r2 + r3 * r3), abs(r0))


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """R(q) of a unit quaternion (4,) as a (3, 3) array: its columns are the body axes in the world."""
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quaternion_from_matrix(matrix: np.ndarray, name: str = "block") -> np.ndarray:
    """The unit quaternion (w >= 0) of a rotation matrix (3, 3), by Shepperd's method (J. Guidance and
    Control 1(3), 1978): the largest of 4w^2, 4x^2, 4y^2, 4z^2 (from the trace and the diagonal) is
    taken to divide by, so no component is found by dividing by a small one. A matrix that is not a
    rotation (not orthonormal, or a reflection: determinant -1) is refused, naming `name`."""
    m = np.asarray(matrix, dtype=float)
    if m.shape != (3, 3) or not np.allclose(m @ m.T, np.eye(3), atol=1e-9):
        raise ValueError(f"{name}: the principal axes are not an orthonormal 3 x 3 matrix")
    if np.linalg.det(m) < 0.0:
        raise ValueError(f"{name}: the principal axes are left-handed (determinant -1); flip one axis")
    trace = np.trace(m)
    k = int(np.argmax([trace, m[0, 0], m[1, 1], m[2, 2]]))
    if k == 0:
        s = 2.0 * np.sqrt(1.0 + trace)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    elif k == 1:
        s = 2.0 * np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [(m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
    elif k == 2:
        s = 2.0 * np.sqrt(1.0 - m[0, 0] + m[1, 1] - m[2, 2])
        q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 - m[0, 0] - m[1, 1] + m[2, 2])
        q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    q /= np.linalg.norm(q)
    return -q if q[0] < 0.0 else q
