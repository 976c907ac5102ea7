"""Probabilistic wedges: joint orientations scattered about their sets' means, strength, water and
seismic drawn per sample, every sample one wedge through the compiled fast path
(`analysis.analyse_wedges(..., essentials_only=True)`; the full geometry with a tension crack), and
the two probabilities Swedge separates (Rocscience Swedge, help "Probabilistic Analysis": "probability
of failure" and "probability of sliding"):

    P_f       = N_failed / N_samples        every sample counted, a wedge that does not form as safe
    P_sliding = N_failed / N_formed         over the kinematically valid wedges only

N_failed the wedges that form with FS < 1. A wedge that does not form (its `geometry.WedgeReason`) has
no FS: it is counted in N_samples and by its reason, never as a number.

Orientations (`PlaneScatter`): about the set's mean pole, Fisher's distribution of concentration K
(`bbmc.geometry.orientation.fisher_sample`, drawn exactly), or independent normal dip and dip
direction. A normal dip drawn outside 0 to 90 deg is the same plane seen from its other side: its
upward pole (`orientation.plane_of_pole`) gives the dip and dip direction the wedge takes (a dip of 95
deg towards 120 is 85 deg towards 300). Strength, water and seismic are arrays over the samples, drawn
by the caller (`bbmc.sweep.wedge_model` draws them from a study's distributions).

The binomial intervals of both probabilities (Clopper & Pearson) are the sweep's
(`bbmc.sweep.statistics.clopper_pearson_interval`, on `WedgeProbability`'s counts): `bbmc.sweep`
imports the slope models, so this module cannot import it back. Angles rad, SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ndtri

from bbmc.geometry.orientation import fisher_directions, fisher_sample, plane_of_pole, poles
from bbmc.slope.wedge.analysis import WedgeOrientations, analyse_wedges
from bbmc.slope.wedge.essentials import wedge_essentials
from bbmc.slope.wedge.geometry import TensionCrack, WedgeReason, wedge_geometries
from bbmc.slope.wedge.mechanics import PlaneStrength

Array = NDArray[np.float64]


@dataclass(frozen=True)
class PlaneScatter:
    """A joint plane's orientation distribution: the mean `dip` and `dip_direction` [rad], scattered by
    Fisher's K [1] about the mean pole (`fisher_k`; inf or None: no scatter), or else by independent
    normal dip and dip direction of standard deviations `dip_std`, `dip_direction_std` [rad]."""

    dip: float
    dip_direction: float
    fisher_k: float | None = None
    dip_std: float = 0.0
    dip_direction_std: float = 0.0

    def __post_init__(self) -> None:
        if self.fisher_k is not None and not self.fisher_k > 0.0:
            raise ValueError(f"fisher_k: K must be > 0, got {self.fisher_k}")
        if self.fisher_k is not None and (self.dip_std or self.dip_direction_std):
            raise ValueError("fisher_k, dip_std: give Fisher's K or the normal spreads, not both")
        if self.dip_std < 0.0 or self.dip_direction_std < 0.0:
            raise ValueError("dip_std, dip_direction_std: a standard deviation must be >= 0")

    def sample(self, count: int, rng: np.random.Generator) -> tuple[Array, Array]:
        """`count` dips and dip directions [rad] of planes drawn from this distribution (module
        docstring): each an upward pole's plane."""
        mean = poles(np.asarray(self.dip), np.asarray(self.dip_direction))
        if self.fisher_k is not None:
            normals = fisher_sample(mean, float(self.fisher_k), count, rng)
        else:
            dip = self.dip + self.dip_std * rng.standard_normal(count)
            direction = self.dip_direction + self.dip_direction_std * rng.standard_normal(count)
            normals = poles(dip, direction)
        dip_deg, direction_deg = plane_of_pole(normals)
        return np.radians(dip_deg), np.radians(direction_deg)

    def from_uniforms(self, u: Array, v: Array) -> tuple[Array, Array]:
        """Dips and dip directions [rad] of planes drawn from this distribution by inversion of the
        uniforms `u`, `v` on (0, 1), one plane per pair: Fisher's angle and azimuth
        (`fisher_directions`), or the normal dip and dip direction (their quantiles)."""
        mean = poles(np.asarray(self.dip), np.asarray(self.dip_direction))
        if self.fisher_k is not None:
            normals = fisher_directions(mean, float(self.fisher_k), u, v)
        else:
            normals = poles(
                self.dip + self.dip_std * ndtri(u), self.dip_direction + self.dip_direction_std * ndtri(v)
            )
        dip_deg, direction_deg = plane_of_pole(normals)
        return np.radians(dip_deg), np.radians(direction_deg)


def scattered_orientations(
    plane_1: PlaneScatter,
    plane_2: PlaneScatter,
    face: tuple[float, float],
    upper: tuple[float, float],
    count: int,
    rng: np.random.Generator,
) -> WedgeOrientations:
    """`count` wedges' orientations: planes 1 and 2 drawn from their distributions (plane 1 first, from
    the same generator), the face and the upper surface fixed, each (dip, dip direction) [rad]."""
    dip_1, direction_1 = plane_1.sample(count, rng)
    dip_2, direction_2 = plane_2.sample(count, rng)
    return WedgeOrientations(dip_1, direction_1, dip_2, direction_2, *face, *upper)


@dataclass(frozen=True)
class WedgeProbability:
    """Per sample the FS (NaN where the wedge does not form), the `WedgeReason` code and the
    `mechanics.SlidingMode` code; the counts and the two probabilities (module docstring)."""

    factor_of_safety: Array
    reason: NDArray[np.int8]
    mode: NDArray[np.int8]

    @property
    def samples(self) -> int:
        return int(self.reason.size)

    @property
    def formed(self) -> int:
        """The kinematically valid wedges (they form)."""
        return int(np.count_nonzero(self.reason == WedgeReason.FORMED))

    @property
    def failed(self) -> int:
        """The wedges that form with FS < 1."""
        return int(np.count_nonzero((self.reason == WedgeReason.FORMED) & (self.factor_of_safety < 1.0)))

    @property
    def probability_of_failure(self) -> float:
        """P_f = failed / samples."""
        return self.failed / self.samples

    @property
    def probability_of_sliding(self) -> float:
        """failed / formed (NaN if no wedge forms)."""
        return self.failed / self.formed if self.formed else float("nan")

    def reason_counts(self) -> dict[WedgeReason, int]:
        """How many samples have each reason (the formed ones under FORMED); reasons with none left out."""
        codes, counts = np.unique(self.reason, return_counts=True)
        return {WedgeReason(int(c)): int(k) for c, k in zip(codes, counts, strict=True)}


def intersection_lengths(
    orientations: WedgeOrientations,
    *,
    height_h1: ArrayLike | None = None,
    height_h: ArrayLike | None = None,
    overhanging_face: ArrayLike = False,
    crack: TensionCrack | None = None,
) -> Array:
    """The length [m] of each wedge's line of intersection from the toe O (`geometry.WedgeGeometry.
    intersection_length`, the length a Barton-Bandis plane is scaled to; NaN where the wedge does not
    form). Without a crack from the compiled fast path: the top T lies on the line through O, so
    |OT| = H / |l_z|, H the wedge's total height [m] and l the unit line of intersection; with a crack
    the full geometry's O R (R the crack's foot)."""
    heights = {"height_h1": height_h1, "height_h": height_h, "overhanging_face": overhanging_face}
    if crack is not None:
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            return wedge_geometries(*orientations.angles(), crack=crack, **heights).intersection_length
    essentials = wedge_essentials(*orientations.angles(), **heights)
    return essentials.height_h / np.abs(essentials.line[..., 2])


def wedge_probability(
    orientations: WedgeOrientations, strength_1: PlaneStrength, strength_2: PlaneStrength, **loads: ArrayLike
) -> WedgeProbability:
    """The FS of every sampled wedge (`orientations` and the strengths and `loads` arrays over the
    samples, as `analysis.analyse_wedges` takes them: unit_weight, height_h1 or height_h, water, seismic,
    forces, passive, crack, ...) by the compiled fast path, or with a tension crack (`crack`) by the
    full geometry, and the probabilities over them; fixed orientations with drawn strengths give every
    sample the one geometry."""
    fast = loads.get("crack") is None
    analysis = analyse_wedges(orientations, strength_1, strength_2, essentials_only=fast, **loads)
    fs = np.asarray(analysis.factor_of_safety)
    reason, mode = (np.broadcast_to(a, fs.shape) for a in (analysis.geometry.reason, analysis.solution.mode))
    return WedgeProbability(fs, reason, mode)
