"""Make `scanline_example.csv`: a SYNTHETIC scanline survey drawn from known distributions.

The file is not field data. It is a survey simulated here so that `bbmc joints` can be checked against
the truth it should recover (tests/test_field.py runs this script, compares its output with the file
in the repository byte for byte, and fits it). Run it from anywhere:

    python data/field/make_scanline_example.py [OUT.csv]

It uses numpy's uniform draws only, each turned into its distribution by an inverse CDF written here,
so its output does not depend on how numpy samples other distributions. Nothing here comes from bbmc.

The model (x east, y north, z up; angles in degrees at the file, radians inside):

* The exposure is a vertical face striking north (it looks west). A horizontal scanline runs along it,
  trend 000, over LENGTH_M; the face reaches ABOVE_M above the line and BELOW_M below it.
* Each set is a family of planes whose poles follow Fisher's distribution about the set's mean pole
  (concentration K). Along a line normal to the set the planes are spaced by the set's spacing
  distribution (the truth below). A plane of pole n crosses the scanline only if it is not parallel to
  it, and in a Poisson set of planes the share of crossings made by planes of pole n is proportional
  to p(n) |cos delta(n)|, delta the angle between n and the line (Terzaghi 1965). So:
  - positions along the line: the set's normal spacings divided by E_p|cos delta| (integrated below
    over the Fisher distribution; exact for the exponential set, a definition for the other);
  - each crossing's orientation: a Fisher draw kept with probability |cos delta| (rejection).
* Every crossing is a joint (the spacing is that of the joints themselves). Its trace on the face is a
  straight segment whose length follows the set's trace length distribution f; the line meets a trace
  with a chance proportional to its length, so the length of a trace it meets follows l f(l) / E[l]
  (for a lognormal f: lognormal with log-mean raised by sigma^2; for an exponential f: a gamma of
  shape 2), and the line crosses it at a uniform point along it.
* A trace is seen up to the face's edges: the part above the line ends at ABOVE_M / sin(beta) along
  the trace, the part below at BELOW_M / sin(beta), beta the trace's inclination on the face. A part
  that reaches an edge is cut there and that end is hidden (censored_ends counts the hidden ends).
* Readings are rounded as a careful survey would: positions and lengths to the millimetre, dips and
  dip directions to the degree.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.special import ndtri

SEED = 20240624
LENGTH_M = 100.0
TREND_DEG, PLUNGE_DEG = 0.0, 0.0
FACE_NORMAL = np.array([-1.0, 0.0, 0.0])  # the face looks west
ABOVE_M, BELOW_M = 6.0, 2.0

# The truth: what bbmc joints should recover from the file.
TRUTH = {
    "J1": {
        "dip_deg": 35.0,
        "dip_direction_deg": 170.0,
        "fisher_k": 60.0,
        "spacing_m": {"distribution": "exponential", "mean": 0.5},
        "trace_length_m": {"distribution": "lognormal", "mean": 4.0, "std": 2.5},
    },
    "J2": {
        "dip_deg": 80.0,
        "dip_direction_deg": 300.0,
        "fisher_k": 40.0,
        "spacing_m": {"distribution": "lognormal", "mean": 0.6, "std": 0.35},
        "trace_length_m": {"distribution": "exponential", "mean": 2.5},
    },
}


def pole(dip: np.ndarray, dip_direction: np.ndarray) -> np.ndarray:
    """Upward unit normals (x east, y north, z up) of planes of dip and dip direction [rad]."""
    return np.stack(
        [np.sin(dip) * np.sin(dip_direction), np.sin(dip) * np.cos(dip_direction), np.cos(dip)], axis=-1
    )


def line(trend: float, plunge: float) -> np.ndarray:
    """Unit vector of a line of trend and plunge (downward positive) [rad]."""
    return np.array([np.cos(plunge) * np.sin(trend), np.cos(plunge) * np.cos(trend), -np.sin(plunge)])


def fisher_poles(mean: np.ndarray, kappa: float, u_cos: np.ndarray, u_azimuth: np.ndarray) -> np.ndarray:
    """Fisher-distributed unit vectors about `mean` from two arrays of uniforms (inverse CDF of cos theta:
    1 + ln(1 - u (1 - exp(-2 kappa))) / kappa; azimuth about the mean uniform)."""
    cos_t = 1.0 + np.log1p(-u_cos * -np.expm1(-2.0 * kappa)) / kappa
    sin_t = np.sqrt(np.clip(1.0 - cos_t**2, 0.0, None))
    phi = 2.0 * np.pi * u_azimuth
    helper = np.array([0.0, 0.0, 1.0]) if abs(mean[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = np.cross(mean, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(mean, e1)
    return cos_t[:, None] * mean + (sin_t * np.cos(phi))[:, None] * e1 + (sin_t * np.sin(phi))[:, None] * e2


def mean_abs_cos(mean: np.ndarray, kappa: float, direction: np.ndarray, grid: int = 1000) -> float:
    """E|n . direction| over Fisher's distribution about `mean`, by the midpoint rule in the uniforms
    of `fisher_poles` (grid x 2 grid equal-probability cells)."""
    u = (np.arange(grid) + 0.5) / grid
    v = (np.arange(2 * grid) + 0.5) / (2 * grid)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    poles = fisher_poles(mean, kappa, uu.ravel(), vv.ravel())
    return float(np.mean(np.abs(poles @ direction)))


def draw(rng: np.random.Generator, law: dict, size: int, length_biased: bool = False) -> np.ndarray:
    """`size` draws of an exponential or lognormal law {mean, std} by its inverse CDF; with
    `length_biased`, of l f(l) / E[l] instead (gamma of shape 2; lognormal of log-mean + sigma^2)."""
    u = rng.random(size)
    if law["distribution"] == "exponential":
        if length_biased:  # gamma(2, mean): the sum of two exponentials
            return -law["mean"] * (np.log1p(-u) + np.log1p(-rng.random(size)))
        return -law["mean"] * np.log1p(-u)
    sigma2 = np.log1p((law["std"] / law["mean"]) ** 2)
    mu = np.log(law["mean"]) - sigma2 / 2.0 + (sigma2 if length_biased else 0.0)
    return np.exp(mu + np.sqrt(sigma2) * ndtri(u))


def survey_set(
    rng: np.random.Generator,
    name: str,
    truth: dict,
    scanline: np.ndarray | None = None,
    face_normal: np.ndarray = FACE_NORMAL,
    length: float = LENGTH_M,
    heights: tuple[float, float] = (ABOVE_M, BELOW_M),
) -> list[tuple]:
    """The rows of one set along the scanline (default: this survey's; or a unit vector `scanline` over
    `length` on a face of normal `face_normal` reaching `heights` (above, below) [m] vertically above
    and below the line): (set, position, dip, dip direction, length, censored)."""
    if scanline is None:
        scanline = line(np.radians(TREND_DEG), np.radians(PLUNGE_DEG))
    above_m, below_m = heights
    mean = pole(np.radians(truth["dip_deg"]), np.radians(truth["dip_direction_deg"]))
    factor = mean_abs_cos(mean, truth["fisher_k"], scanline)
    positions: list[float] = []
    spacings = draw(rng, truth["spacing_m"], 10_000) / factor
    at = spacings[0] * rng.random()
    for spacing in spacings[1:]:
        if at > length:
            break
        positions.append(at)
        at += spacing
    count = len(positions)
    kept: list[np.ndarray] = []
    while sum(len(k) for k in kept) < count:
        poles = fisher_poles(mean, truth["fisher_k"], rng.random(count), rng.random(count))
        kept.append(poles[rng.random(count) < np.abs(poles @ scanline)])
    poles = np.concatenate(kept)[:count]
    poles[poles[:, 2] < 0] *= -1.0
    lengths = draw(rng, truth["trace_length_m"], count, length_biased=True)
    below = lengths * rng.random(count)
    above = lengths - below
    traces = np.cross(poles, face_normal)
    sin_beta = np.abs(traces[:, 2]) / np.linalg.norm(traces, axis=1)
    reach_above, reach_below = above_m / sin_beta, below_m / sin_beta
    seen = np.minimum(above, reach_above) + np.minimum(below, reach_below)
    censored = (above > reach_above).astype(int) + (below > reach_below).astype(int)
    dips = np.degrees(np.arccos(np.clip(poles[:, 2], -1.0, 1.0)))
    directions = np.degrees(np.arctan2(poles[:, 0], poles[:, 1])) % 360.0
    return [
        (name, p, d, a, s, c)
        for p, d, a, s, c in zip(positions, dips, directions, seen, censored, strict=True)
    ]


def make(out: Path, seed: int = SEED) -> None:
    """Write the survey drawn with `seed` to `out`, sorted by position along the line as it would be
    mapped."""
    rng = np.random.default_rng(seed)
    rows = sorted(
        (row for name, truth in TRUTH.items() for row in survey_set(rng, name, truth)), key=lambda r: r[1]
    )
    lines = [
        "# SYNTHETIC scanline survey, not field data: drawn from known distributions by",
        f"# make_scanline_example.py (seed {seed}; the truth is in that script). Trend 000, plunge 0, "
        f"{LENGTH_M:g} m.",
        "set,position_m,dip_deg,dip_direction_deg,trace_length_m,censored_ends",
    ]
    for name, position, dip, direction, length, censored in rows:
        lines.append(
            f"{name},{position:.3f},{round(dip):d},{round(direction) % 360:d},{length:.3f},{censored:d}"
        )
    out.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    make(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).with_name("scanline_example.csv"))
