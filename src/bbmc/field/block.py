"""The `joint_sets:` block of a scene's `rock_mass` (docs/scene-format.md) from fitted sets.

Each set is written in its 3D form: the Fisher mean plane and K (from the dips alone: K = 1/sigma^2,
`bbmc.geometry.orientation`), the section's azimuth, the spacing, the trace length and the persistence.

Spacing and persistence. In a scene a set is a family of lines, `spacing_m` apart, each line joint over
the share k (the persistence) of its length and intact rock (bridges) over the rest. A line normal to
the set meets a joint on each of its lines with the chance k, independently, so the joints along it
are the lines thinned by k: their spacing is the sum of a geometric number (mean 1/k) of line
spacings. The survey measures the joints' spacing (mean m, variance v), so the lines' spacing X has
(Wald's identities for a geometric sum)

    E[X] = k m,    Var[X] = k (v - (1 - k) m^2),

which needs v / m^2 > 1 - k: joints more regular than that cannot come from lines of persistence k.
An exponential spacing stays exponential (a thinned Poisson process is one, of mean k m); a lognormal
one is written with these two moments. k = 1 (persistent sets) writes the fitted spacing unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bbmc import units
from bbmc.field.distributions import Candidate
from bbmc.geometry.orientation import SetOrientation


class PersistenceError(ValueError):
    """A persistence too low for the regularity of the joints' fitted spacing."""


@dataclass(frozen=True)
class BlockEntry:
    """One set of the block: its fitted orientation, spacing and trace length, and the given
    persistence; a set whose spacing was not measured has `spacing` None and says why in `unmeasured`
    (it is written with `spacing_m: null`, which a rock mass refuses until the spacing is given)."""

    name: str
    orientation: SetOrientation
    spacing: Candidate | None
    trace_length: Candidate | None
    persistence: float
    unmeasured: str = ""


def _number(value: float) -> str:
    return f"{value:.4g}"


def _law(family: str, mean: float, std: float) -> str:
    if family == "exponential":
        return f"{{distribution: exponential, mean: {_number(mean)}}}"
    return f"{{distribution: {family}, mean: {_number(mean)}, std: {_number(std)}}}"


def lowest_persistence(spacing: Candidate) -> float:
    """1 - v / m^2 of the joints' fitted spacing: lines of a lower persistence cannot make it."""
    return max(0.0, 1.0 - (spacing.std / spacing.mean) ** 2)


def line_spacing(spacing: Candidate, persistence: float) -> tuple[float, float]:
    """Mean and standard deviation [m] of the spacing of lines of `persistence` k whose joints have the
    fitted `spacing`: k m and sqrt(k (v - (1 - k) m^2)); `PersistenceError` where none exists."""
    mean, variance = spacing.mean, spacing.std**2
    line_variance = persistence * (variance - (1.0 - persistence) * mean**2)
    if line_variance <= 0.0 and spacing.family != "exponential":
        raise PersistenceError(
            f"its joints' spacing (coefficient of variation {spacing.std / spacing.mean:.3g}) is more "
            f"regular than lines of persistence {persistence:g} can make: give at least "
            f"{lowest_persistence(spacing):.3g}"
        )
    return persistence * mean, float(np.sqrt(max(line_variance, 0.0)))


def joint_sets_yaml(entries: list[BlockEntry], section_azimuth_deg: float, comments: list[str]) -> str:
    """The block's YAML text, `comments` first (each a line of its own after '# '): the section's
    azimuth and the sets, as a rock mass (`bbmc.rockmass.RockMassConfig`) reads them."""
    lines = [f"# {text}" for text in comments]
    lines.append(f"section_azimuth_deg: {_number(section_azimuth_deg)}   # the face's dip direction")
    lines.append("joint_sets:")
    for entry in entries:
        o = entry.orientation
        lines += [
            f"  - name: {entry.name}",
            f"    orientation: {{dip_deg: {o.dip / units.deg:.1f}, "
            f"dip_direction_deg: {o.dip_direction / units.deg:.1f}, fisher_k: {_number(o.fisher_k)}}}",
        ]
        if entry.spacing is None or entry.trace_length is None:
            lines += [f"    spacing_m: null   # must be given: {entry.unmeasured}", "    offset_m: 0"]
            continue
        mean, std = line_spacing(entry.spacing, entry.persistence)
        trace = entry.trace_length
        lines += [
            f"    spacing_m: {_law(entry.spacing.family, mean, std)}",
            f"    trace_length_m: {_law(trace.family, trace.mean, trace.std)}",
            f"    persistence: {_number(entry.persistence)}",
            "    offset_m: 0",
        ]
    return "\n".join(lines) + "\n"
