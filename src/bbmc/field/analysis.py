"""One mapped joint set's statistics from a scanline: orientation, spacing and trace length, each
corrected for the way a scanline samples (see `bbmc.geometry.orientation` and
`bbmc.field.distributions` for the corrections and their sources).

Spacing. The distances between consecutive joints of a set along the line are apparent spacings. A set
whose normal makes the angle delta with the line has its joints 1 / |cos delta| times further apart
along the line than along its normal, and Terzaghi's weights w = 1 / |cos delta| (one per joint, from
its own orientation, capped) count how many joints of the set the line stands for. The normal
spacings are the apparent ones times N / sum(w): their mean is then the line's length per weighted
joint, 1 / (Terzaghi's corrected frequency). For a set of parallel joints this is |cos delta|; with
scattered orientations, the harmonic mean of the |cos delta| of the joints met.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bbmc.field import distributions as dist
from bbmc.field.survey import SetSurvey
from bbmc.geometry.orientation import (
    SetOrientation,
    dip_orientation,
    fisher_orientation,
    poles,
    terzaghi_weights,
)

MIN_TRACES = 10  # per set: 9 spacings for at most 2 parameters
MIN_WHOLE = 5  # traces seen whole (both ends), without which a trace length's spread is not identified
SCENE_FAMILIES = ("exponential", "lognormal")  # the distributions a scene's joint set reads


@dataclass(frozen=True)
class SetFit:
    """A set's fitted statistics; `spacings` are the normal spacings [m] (the censored tail apart)."""

    survey: SetSurvey
    orientation: SetOrientation
    weights: np.ndarray
    capped: int  # joints whose weight reached the cap
    spacing_factor: float  # N / sum(w): normal spacing / apparent spacing
    spacings: np.ndarray
    censored_tail: float | None
    spacing: list[dist.Candidate]
    trace_length: list[dist.Candidate]

    @property
    def count(self) -> int:
        return self.survey.position.size

    @property
    def normal_frequency(self) -> float:
        """Joints per metre normal to the set: 1 / mean normal spacing, censored tail included."""
        covered = self.spacings.sum() + (self.censored_tail or 0.0)
        return (self.count - 1) / covered


def fit_set(
    survey: SetSurvey, line: np.ndarray, length: float, max_weight: float, dip_direction: float | None
) -> SetFit:
    """Fit the set `survey` mapped along the scanline of direction `line` and `length` [m]; its mean
    `dip_direction` [rad] stands in for each joint's where the survey has none."""
    if survey.dip_direction is not None:
        normals = poles(survey.dip, survey.dip_direction)
        weights = terzaghi_weights(normals, line, max_weight)
        orientation = fisher_orientation(normals, weights)
    else:
        normals = poles(survey.dip, np.full(survey.dip.size, dip_direction))
        weights = terzaghi_weights(normals, line, max_weight)
        orientation = dip_orientation(survey.dip, dip_direction, weights)
    factor = survey.position.size / weights.sum()
    spacings = np.diff(survey.position) * factor
    tail = (length - survey.position[-1]) * factor
    censored_tail = tail if tail > 0 else None
    return SetFit(
        survey=survey,
        orientation=orientation,
        weights=weights,
        capped=int(np.sum(weights >= max_weight)),
        spacing_factor=float(factor),
        spacings=spacings,
        censored_tail=censored_tail,
        spacing=dist.fit_spacings(spacings, survey.resolution * factor, censored_tail),
        trace_length=dist.fit_trace_lengths(survey.trace_length, survey.censored_ends),
    )
