"""The `fos:` section of a scene: how `bbmc fos` searches the factor of safety and which blocks decide a
trial (docs/scene-format.md, "Factor of safety")."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from bbmc.config import Section

Pair = Annotated[list[float], Field(min_length=2, max_length=2)]
Positive = Annotated[float, Field(gt=0)]


class Judge(Section):
    """`bbmc fos`: the blocks whose motion decides a trial (docs/scene-format.md, "Factor of safety"):
    every block by default; else those named in `blocks` (block or group names) or whose centroid lies
    in `region_m` (two opposite corners) at the start, or both; of them, those at least
    `min_size_fraction` x the median block size (a sliver that falls does not fail the slope)."""

    blocks: list[str] = Field(default_factory=list)
    region_m: Annotated[list[Pair], Field(min_length=2, max_length=2)] | None = None
    min_size_fraction: Annotated[float, Field(ge=0, lt=1)] = 0.0


class StrengthReduction(Section):
    """`bbmc fos`: how the factor of safety is found (docs/scene-format.md, "Factor of safety")."""

    tolerance: Annotated[float, Field(gt=0, le=0.1)] = 0.01  # bisection ends when the bracket is this narrow
    barton_bandis_reduction: Literal["envelope", "phi_b_jrc"] = "envelope"
    unbalanced_force_ratio: Annotated[float, Field(gt=0, lt=1)] = 1e-5  # below it a trial is stable
    failure_displacement_m: Positive | None = None  # [default: 5 % of the median block size]
    response_multiple: Annotated[float, Field(ge=1)] = 10.0  # a trial's step budget x equilibrium steps
    min_trial_steps: Annotated[int, Field(ge=100)] = 2000
    check_every_steps: Annotated[int, Field(ge=1)] = 100
    trend_window_multiple: Annotated[float, Field(gt=0)] = 1.0  # a trial's trend windows x equilibrium steps
    largest_factor: Annotated[float, Field(gt=1)] = 20.0  # the bracket is sought in [1 / it, it]
    support_form: Literal["active", "passive"] = "active"  # passive: the support's force along its joint / F
    judge: Judge = Judge()  # the blocks whose motion decides a trial [default: every block]
