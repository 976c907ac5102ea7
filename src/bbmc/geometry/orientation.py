"""Orientations of a mapped joint set: poles, Terzaghi's weights, the set's mean and scatter, and its
trace in a vertical section.

Axes: x east, y north, z up. Angles in radians: dip psi from the horizontal (0 to pi/2), dip direction
alpha clockwise from north, a line's trend clockwise from north and its plunge downward positive.

* Pole of a plane: n = (sin psi sin alpha, sin psi cos alpha, cos psi), the upward unit normal.
* Direction of a line: l = (cos p sin t, cos p cos t, -sin p).
* Orientation bias (Terzaghi 1965): a line meets a plane whose normal makes the angle delta with it
  with a probability proportional to |cos delta| = |n . l|, so a joint is counted with the weight
  w = 1 / |cos delta|. Planes nearly parallel to the line (delta near 90 deg) would get unbounded
  weights from a handful of joints, so w is capped at `max_weight` (1 / sin 15 deg = 3.86 is the
  default of Rocscience's Dips, its "minimum bias angle" of 15 deg; any cap is a judgement).
* Mean pole and Fisher's K (Fisher 1953): the weighted resultant of the poles (weights scaled to sum
  to the number of joints N), R its length, K = (N - 1) / (N - R). Poles are axes: each is first turned
  to the side of the set's principal axis (the largest eigenvector of sum w n n^T).
* Without dip directions, the dips alone: their weighted mean and standard deviation (a normal fit).
  For a concentrated Fisher set each component of a pole's deviation has the variance 1/K, and a dip's
  deviation is one such component, so K = 1 / sigma_dip^2 (sigma in radians) is the set's equivalent
  concentration (valid for K of about 10 and more, and for sets neither nearly flat nor nearly
  vertical: the dips of a steep set fold at 90 deg, which biases their mean and spread).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from bbmc.geometry.polygons import joint_set_trace


def pole_components(
    dip: float | np.ndarray, dip_direction: float | np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The components (x, y, z) of the upward unit normals of planes of `dip` and `dip_direction` [rad],
    n = (sin psi sin alpha, sin psi cos alpha, cos psi), each of its own broadcast shape (n_z has the
    shape of `dip`): the form for tests of many faces against many planes, where stacking (`poles`)
    would first broadcast every sine to the full (F, N)."""
    dip, dip_direction = np.asarray(dip, dtype=float), np.asarray(dip_direction, dtype=float)
    return np.sin(dip) * np.sin(dip_direction), np.sin(dip) * np.cos(dip_direction), np.cos(dip)


def poles(dip: np.ndarray, dip_direction: np.ndarray) -> np.ndarray:
    """Upward unit normals (..., 3) of planes of `dip` and `dip_direction` [rad] (broadcast together):
    n = (sin psi sin alpha, sin psi cos alpha, cos psi) (`pole_components`)."""
    return np.stack(np.broadcast_arrays(*pole_components(dip, dip_direction)), axis=-1)


def upward(normals: np.ndarray) -> np.ndarray:
    """Unit normals (..., 3) of planes turned to their upward sense, n_z >= 0 (a plane's pole is an axis;
    bbmc's poles are upward). A horizontal normal (n_z = 0) keeps the sense it was given in."""
    normals = np.asarray(normals, dtype=float)
    return np.where(normals[..., 2:3] < 0.0, -normals, normals)


def downward(lines: np.ndarray) -> np.ndarray:
    """Unit vectors (..., 3) of lines turned to their downward sense, l_z <= 0 (the lower hemisphere; a
    plunge is downward positive). A horizontal line (l_z = 0) keeps the sense it was given in."""
    lines = np.asarray(lines, dtype=float)
    return np.where(lines[..., 2:3] > 0.0, -lines, lines)


def wrapped_azimuth(angle: float | np.ndarray, full_turn: float = 2.0 * np.pi) -> np.ndarray:
    """`angle` as an azimuth in [0, `full_turn`) (2 pi [rad], or 360 [deg]): angle mod full_turn, where
    the modulo of a tiny negative angle, which rounds up to exactly `full_turn`, is taken as 0."""
    wrapped = np.mod(angle, full_turn)
    return wrapped - full_turn * (wrapped >= full_turn)


def line_direction(trend: float, plunge: float) -> np.ndarray:
    """Unit vector (3,) of a line of `trend` and `plunge` (downward positive) [rad] (`line_vectors`)."""
    return line_vectors(trend, plunge)


def dip_and_direction(pole: np.ndarray) -> tuple[float, float]:
    """Dip and dip direction [rad] of the plane with normal `pole` (either sense): with n the upward unit
    normal, dip = acos(n_z), dip direction = atan2(n_x, n_y) (mod 2 pi)."""
    pole = upward(pole / np.linalg.norm(pole))
    dip = float(np.arccos(np.clip(pole[2], -1.0, 1.0)))
    return dip, float(wrapped_azimuth(np.arctan2(pole[0], pole[1])))


# Rocscience Dips' default cap on the weights: its "minimum bias angle" of 15 deg, w <= 1 / sin 15 deg.
DIPS_MAX_WEIGHT = 1.0 / np.sin(np.radians(15.0))


def terzaghi_weights(normals: np.ndarray, line: np.ndarray, max_weight: float) -> np.ndarray:
    """w = 1 / |cos delta| per joint, delta the angle between its normal and the scanline, capped at
    `max_weight` (Terzaghi 1965). `line`: one unit vector (3,), or one per joint (n, 3)."""
    cos_delta = np.abs(np.sum(normals * line, axis=-1))
    with np.errstate(divide="ignore"):
        return np.minimum(1.0 / cos_delta, max_weight)


def face_weights(normals: np.ndarray, face_normals: np.ndarray, max_weight: float) -> np.ndarray:
    """w = 1 / sin theta per joint mapped on a planar face, theta the angle between its plane and the
    face (between their normals), capped at `max_weight`: a face of area A is cut by joints of a set of
    spacing s along traces of total length A sin theta / s, so the face samples each set in proportion
    to sin theta (Rocscience Dips, "Terzaghi Weighting": W = cosec a, a the minimum angle between the
    plane and the traverse, for a planar traverse as for a linear one). `face_normals`: (3,) or (n, 3)."""
    cos_theta = np.clip(np.abs(np.sum(normals * face_normals, axis=-1)), 0.0, 1.0)
    with np.errstate(divide="ignore"):
        return np.minimum(1.0 / np.sqrt(1.0 - cos_theta**2), max_weight)


@dataclass(frozen=True)
class SetOrientation:
    """A set's mean plane and scatter. `fisher_k` is estimated from the poles (`from_dip_directions`)
    or equivalent to the dips' scatter (1 / sigma^2); `dip_std` is the weighted std of the dips."""

    dip: float  # rad
    dip_direction: float  # rad
    fisher_k: float
    dip_std: float  # rad
    from_dip_directions: bool
    normal: np.ndarray
    deviation: np.ndarray  # per joint: angle between its pole and the mean pole [rad] (dips: dip - mean)


def _normalised(weights: np.ndarray) -> np.ndarray:
    return weights * weights.size / weights.sum()


def fisher_orientation(normals: np.ndarray, weights: np.ndarray) -> SetOrientation:
    """The weighted mean pole and Fisher's K = (N - 1) / (N - R) of poles taken as axes (Fisher 1953; the
    estimator Rocscience Dips uses): N the number of poles, the `weights` scaled to sum to N, R the length
    of the weighted resultant of the poles turned to the side of the principal axis. Angles [rad]."""
    w = _normalised(weights)
    _, vectors = np.linalg.eigh((normals * w[:, None]).T @ normals)
    axis = vectors[:, -1]
    aligned = np.where((normals @ axis)[:, None] < 0, -normals, normals)
    resultant = (aligned * w[:, None]).sum(axis=0)
    length = float(np.linalg.norm(resultant))
    mean = resultant / length
    count = normals.shape[0]
    kappa = (count - 1) / (count - length) if count - length > 1e-12 * count else np.inf
    dip, direction = dip_and_direction(mean)
    mean = upward(mean)
    aligned = np.where((aligned @ mean)[:, None] < 0, -aligned, aligned)
    deviation = np.arccos(np.clip(aligned @ mean, -1.0, 1.0))
    dips = np.arccos(np.clip(np.abs(aligned[:, 2]), 0.0, 1.0))
    spread = float(np.sqrt(np.sum(w * (dips - dip) ** 2) / (count - 1)))
    return SetOrientation(dip, direction, float(kappa), spread, True, mean, deviation)


def dip_orientation(dips: np.ndarray, dip_direction: float, weights: np.ndarray) -> SetOrientation:
    """A set known by its dips and one dip direction [rad]: the dips' weighted mean and standard
    deviation sigma, and the equivalent Fisher K = 1 / sigma^2."""
    w = _normalised(weights)
    count = dips.size
    mean = float(np.sum(w * dips) / count)
    spread = float(np.sqrt(np.sum(w * (dips - mean) ** 2) / (count - 1)))
    kappa = 1.0 / spread**2 if spread > 0 else np.inf
    normal = poles(np.array(mean), np.array(dip_direction))
    return SetOrientation(mean, dip_direction, float(kappa), spread, False, normal, dips - mean)


def fisher_log_likelihood(deviation: np.ndarray, kappa: float) -> float:
    """Log-likelihood of Fisher's density kappa / (4 pi sinh kappa) exp(kappa cos theta) [1/sr] (Fisher
    1953) at the angles `deviation` [rad] from the mean pole."""
    log_norm = np.log(kappa / (2.0 * np.pi)) - kappa - np.log1p(-np.exp(-2.0 * kappa))
    return float(np.sum(log_norm + kappa * np.cos(deviation)))


def fisher_deviation_cdf(theta: np.ndarray, kappa: float) -> np.ndarray:
    """P(angle from the mean pole <= theta [rad]) under Fisher's distribution (Fisher 1953):
    (1 - exp(-kappa (1 - cos theta))) / (1 - exp(-2 kappa))."""
    return -np.expm1(-kappa * (1.0 - np.cos(theta))) / -np.expm1(-2.0 * kappa)


def fisher_deviation_pdf(theta: np.ndarray, kappa: float) -> np.ndarray:
    """Density [1/rad] of the angle theta [rad] from the mean pole under Fisher's distribution (Fisher
    1953), the derivative of `fisher_deviation_cdf`: kappa sin theta exp(-kappa (1 - cos theta)) /
    (1 - exp(-2 kappa))."""
    return kappa * np.sin(theta) * np.exp(-kappa * (1.0 - np.cos(theta))) / -np.expm1(-2.0 * kappa)


@dataclass(frozen=True)
class SectionTrace:
    """A set's trace in a vertical section: its apparent dip [rad], the azimuth [rad] of the section's
    horizontal direction it dips towards, and the factor by which the true spacing is divided to give
    the spacing of the traces in the section (normal to them)."""

    apparent_dip: float
    dips_towards: float
    spacing_factor: float


def section_trace(normal: np.ndarray, section_azimuth: float) -> SectionTrace:
    """The trace of planes of `normal` in the vertical section along `section_azimuth` [rad]: the
    normal's projection on the section, m, gives tan(apparent dip) = |m_h| / m_z and the traces'
    spacing s / |m| for a true spacing s."""
    along = np.array([np.sin(section_azimuth), np.cos(section_azimuth), 0.0])
    normal = upward(normal)
    horizontal, vertical = float(normal @ along), float(normal[2])
    factor = float(np.hypot(horizontal, vertical))
    if factor < 1e-9:
        return SectionTrace(np.nan, np.nan, 0.0)
    towards = section_azimuth if horizontal >= 0 else wrapped_azimuth(section_azimuth + np.pi)
    return SectionTrace(float(np.arctan2(abs(horizontal), vertical)), float(towards), factor)


@dataclass(frozen=True)
class OrientationGoodness:
    """How well the set's orientation model fits: its log-likelihood, parameter count and KS p-value
    (Fisher: the angles from the mean pole, parameters mean direction and K; normal: the dips [deg])."""

    family: str
    log_likelihood: float
    parameters: int
    ks_p_value: float
    description: str


def goodness(orientation: SetOrientation, dips: np.ndarray) -> OrientationGoodness:
    """Fisher's distribution at the angles from the mean pole, or the normal at the `dips` [rad]."""
    o = orientation
    dip_deg, direction_deg, std_deg = np.degrees([o.dip, o.dip_direction, o.dip_std])
    if o.from_dip_directions:
        ks = stats.kstest(o.deviation, lambda theta: fisher_deviation_cdf(theta, o.fisher_k)).pvalue
        text = f"fisher(dip={dip_deg:.2f}, dip_direction={direction_deg:.2f}, K={o.fisher_k:.6g})"
        return OrientationGoodness(
            "fisher", fisher_log_likelihood(o.deviation, o.fisher_k), 3, float(ks), text
        )
    law = stats.norm(dip_deg, std_deg)
    values = np.degrees(dips)
    ks = stats.kstest(values, law.cdf).pvalue
    text = f"norm(loc={dip_deg:.6g}, scale={std_deg:.6g})"
    return OrientationGoodness("normal", float(np.sum(law.logpdf(values))), 2, float(ks), text)


@dataclass(frozen=True)
class SectionTraces:
    """The orientation of each line of a set: its plane's true dip [deg] and dip direction relative to
    the face [deg], and its trace in the section: unit normal (n_y >= 0) and spacing factor."""

    dip_deg: np.ndarray
    dip_direction_to_face_deg: np.ndarray
    normal: np.ndarray  # (n, 2)
    factor: np.ndarray  # a true spacing S puts traces S / factor apart in the section

    @property
    def apparent_dip_deg(self) -> np.ndarray:
        """The traces' dip in the section [deg]: > 0 dipping out of the slope (towards -x), < 0 into it."""
        return np.degrees(np.arctan2(-self.normal[:, 0], self.normal[:, 1]))


def section_traces(dip_deg: np.ndarray, dip_direction_to_face_deg: np.ndarray) -> SectionTraces:
    """The traces in the section of planes of these dips and dip directions relative to the face."""
    rows = np.array(
        [joint_set_trace(d, b) for d, b in zip(dip_deg, dip_direction_to_face_deg, strict=True)]
    ).reshape(-1, 3)
    normal = rows[:, :2].reshape(-1, 2) * np.where(rows[:, 1:2] < 0, -1.0, 1.0)
    dips, directions = np.asarray(dip_deg, float), np.asarray(dip_direction_to_face_deg, float)
    return SectionTraces(dips, directions, normal, rows[:, 2])


def upward_pole(dip_deg: float, dip_direction_deg: float) -> np.ndarray:
    """The upward unit normal (east, north, up) (3,) of a plane of this dip and dip direction (azimuth)
    [deg]: `poles` at the file's degrees."""
    return poles(np.radians(dip_deg), np.radians(dip_direction_deg))


def plane_of_pole(pole: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Dip and dip direction [deg] of planes with these unit normals (n, 3) (either sense): with n the
    upward normal, dip = acos(n_z), dip direction = atan2(n_x, n_y) in [0, 360)."""
    up = upward(pole)
    dip = np.degrees(np.arccos(np.clip(up[:, 2], -1.0, 1.0)))
    return dip, wrapped_azimuth(np.degrees(np.arctan2(up[:, 0], up[:, 1])), 360.0)


def line_vectors(trend: np.ndarray, plunge: np.ndarray) -> np.ndarray:
    """Unit vectors (..., 3) of lines of `trend` and `plunge` (downward positive) [rad]:
    l = (cos p sin t, cos p cos t, -sin p); the two broadcast together."""
    trend, plunge = np.broadcast_arrays(np.asarray(trend, dtype=float), np.asarray(plunge, dtype=float))
    return np.stack(
        [np.cos(plunge) * np.sin(trend), np.cos(plunge) * np.cos(trend), -np.sin(plunge)], axis=-1
    )


def trend_and_plunge(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Trend in [0, 2 pi) and plunge (0 to pi/2) [rad] of lines along `vectors` (..., 3), either sense:
    an upward vector is turned down first (the lower hemisphere). A horizontal line keeps the trend of
    the sense it was given in."""
    v = np.asarray(vectors, dtype=float)
    v = v / np.linalg.norm(v, axis=-1, keepdims=True)
    v = downward(v)
    plunge = np.arcsin(np.clip(-v[..., 2], 0.0, 1.0))
    return wrapped_azimuth(np.arctan2(v[..., 0], v[..., 1])), plunge


def pole_trend_and_plunge(dip: np.ndarray, dip_direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The lower-hemisphere pole of planes of `dip` and `dip_direction` [rad]: trend = dip direction +
    pi, plunge = pi/2 - dip."""
    dip, dip_direction = np.asarray(dip, dtype=float), np.asarray(dip_direction, dtype=float)
    return wrapped_azimuth(dip_direction + np.pi), np.pi / 2.0 - dip


def intersection_lines(normals_1: np.ndarray, normals_2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The lines of intersection of planes of unit normals `normals_1` and `normals_2` (..., 3): unit
    vectors pointing down (l = n1 x n2 / |n1 x n2|, turned to z <= 0), and sin of the angle between the
    planes (|n1 x n2|). Planes closer to parallel than 1e-9 rad give a NaN line and sine 0: they have no
    line of intersection, and the caller must say so."""
    cross = np.cross(normals_1, normals_2)
    sine = np.linalg.norm(cross, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        lines = np.where(sine[..., None] > 1e-9, cross / sine[..., None], np.nan)
    return downward(lines), sine


def apparent_dip(dip: np.ndarray, dip_direction: np.ndarray, trend: np.ndarray) -> np.ndarray:
    """The apparent dip [rad] of a plane (`dip`, `dip_direction`) along a vertical section of azimuth
    `trend` [rad]: tan(apparent dip) = tan(dip) cos(trend - dip direction) (Priest 1993, eq. 2.6);
    negative where the plane rises along `trend`."""
    dip = np.asarray(dip, dtype=float)
    return np.arctan(
        np.tan(dip) * np.cos(np.asarray(trend, dtype=float) - np.asarray(dip_direction, dtype=float))
    )


def angle_between_axes(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The angle [rad] between axes `a` and `b` (unit vectors (..., 3), either sense): 0 to pi/2."""
    return np.arccos(np.clip(np.abs(np.sum(a * b, axis=-1)), 0.0, 1.0))


def fisher_sample(mean: np.ndarray, kappa: float, count: int, rng: np.random.Generator) -> np.ndarray:
    """`count` unit vectors (count, 3) from Fisher's distribution of mean direction `mean` and
    concentration `kappa` (Fisher 1953), drawn exactly from `rng`'s uniforms (`fisher_directions`)."""
    return fisher_directions(mean, kappa, rng.random(count), rng.random(count))


def fisher_directions(mean: np.ndarray, kappa: float, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Unit vectors (n, 3) from Fisher's distribution of mean direction `mean` and concentration
    `kappa` (Fisher 1953), one per pair of uniforms on [0, 1) (`u`, `v`): the angle theta from the mean
    by inverting its distribution, cos theta = 1 + ln(u + (1 - u) exp(-2 kappa)) / kappa, and the
    azimuth 2 pi v about the mean. `kappa` = inf gives the mean itself."""
    mean = np.asarray(mean, dtype=float) / np.linalg.norm(mean)
    u, azimuth = np.asarray(u, dtype=float), np.asarray(v, dtype=float) * 2.0 * np.pi
    if np.isinf(kappa):
        cos_theta = np.ones(u.size)
    else:
        cos_theta = np.clip(1.0 + np.log(u + (1.0 - u) * np.exp(-2.0 * kappa)) / kappa, -1.0, 1.0)
    sin_theta = np.sqrt(1.0 - cos_theta**2)
    helper = np.array([1.0, 0.0, 0.0]) if abs(mean[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(mean, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(mean, e1)
    in_plane = cos_theta[:, None] * mean + (sin_theta * np.cos(azimuth))[:, None] * e1
    return in_plane + (sin_theta * np.sin(azimuth))[:, None] * e2
