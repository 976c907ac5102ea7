"""Plausible ranges of the physical inputs of rock slopes and rock joints, to catch unit and magnitude
slips (a friction coefficient typed where degrees are asked, kN/m^3 where kg/m^3 are).

A value outside its range is not refused: every config validated (`bbmc.config.validate`, so every
file a command loads) warns about it, an `ImplausibleValue` whose message is one line naming the file,
the key, the range and, where converting from a likely wrong unit lands the value inside the range,
that slip (`bbmc ... --strict` makes these warnings errors). The ranges are deliberately wider than
the values of any real rock, so that a warning means a slip rather than an unusual rock. A value
beyond `FAR` times its range (`beyond`), which no unit slip explains, is refused instead, in configs
and in data files alike (`bbmc.io.read_table`). `RANGES` is the one table; docs/plausible-ranges.md
shows it (`markdown_table`, checked by the tests) with its sources. Only typed input is checked:
numbers the program computes (the scenes a stage builds) are not.

Keys are matched by their name, whatever section holds them (the scene's `joint_laws.*.friction_deg`,
a study's `base.strength.friction_deg`); a row given as `section.key` matches that key in that section
only. A study's variables and grid axes are checked by the key their `path` ends in.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass

G = 9.81  # [m/s^2] to turn densities into unit weights
FAR = 1e6  # a value more than this many times beyond its range is refused (`beyond`)


class ImplausibleValue(UserWarning):
    """A config value outside its plausible range; the message is the one line to show."""


@dataclass(frozen=True)
class Slip:
    """A likely wrong unit: `value` converts a number typed in it to the row's unit."""

    label: str
    value: Callable[[float], float]


@dataclass(frozen=True)
class Range:
    keys: tuple[str, ...]
    low: float
    high: float
    unit: str
    what: str
    source: str
    slips: tuple[Slip, ...] = ()

    @property
    def span(self) -> str:
        return f"{number(self.low)} to {number(self.high)} {self.unit}".rstrip()

    def matches(self, path: str) -> bool:
        return any(f".{path}".endswith(f".{key}") for key in self.keys)


def number(value: float) -> str:
    """Three significant digits, without an exponent up to 10^6."""
    return f"{value:.3g}" if abs(value) < 1000 or abs(value) >= 1e6 else f"{value:.0f}"


def _scaled(factor: float) -> Callable[[float], float]:
    return lambda value: value * factor


KPA_AS_MPA = Slip("kPa typed as MPa", _scaled(1e-3))
MM_AS_M = Slip("mm typed as m", _scaled(1e-3))
RADIANS = Slip("radians typed as degrees", math.degrees)

RANGES: tuple[Range, ...] = (
    Range(
        ("friction_deg", "side_friction_deg"), 5, 70, "deg", "the friction angle of a rock joint",
        "Barton (1974, in Hoek & Bray 1981): the weakest clay fillings reach about 10 deg and below; "
        "Barton & Choubey (1977): the total friction angle capped at 70 deg",
        (Slip("a friction coefficient (tan phi) typed as degrees", lambda v: math.degrees(math.atan(v))),
         RADIANS),
    ),
    Range(
        ("phi_b_deg", "phi_r_deg"), 10, 45, "deg", "a basic or residual friction angle",
        "Barton & Choubey (1977): basic angles such as sandstone 25-35, limestone 27-37, basalt "
        "31-38, gneiss 23-29 deg (dry and wet); residual ones lower, on weathered walls",
        (Slip("a friction coefficient (tan phi) typed as degrees", lambda v: math.degrees(math.atan(v))),
         RADIANS),
    ),
    Range(
        ("phi_max_deg",), 45, 80, "deg", "the cap on a joint's total friction angle",
        "Barton & Choubey (1977): 70 deg", (RADIANS,),
    ),
    Range(
        ("tan_friction",), math.tan(math.radians(5)), math.tan(math.radians(70)), "", "a rock joint's "
        "friction coefficient tan phi (5-70 deg)", "as friction_deg",
        (Slip("an angle in degrees typed as tan phi", lambda v: math.tan(math.radians(v))),),
    ),
    Range(
        ("jrc", "jrc0"), 0, 20, "", "the joint roughness coefficient",
        "Barton & Choubey (1977): the ten typical profiles, 0 (smooth) to 20 (rough)",
    ),
    Range(
        ("jcs_MPa", "jcs0_MPa", "sigma_c_MPa"), 0.25, 400, "MPa",
        "a compressive strength of rock (JCS, sigma_c)",
        "ISRM (1981) grades: extremely weak rock 0.25-1 MPa (R0) to extremely strong > 250 MPa (R6); "
        "JCS is sigma_c on fresh walls and less on weathered ones (Barton & Choubey 1977)",
        (KPA_AS_MPA, Slip("GPa typed as MPa", _scaled(1e3))),
    ),
    Range(
        ("ks_MPa_per_mm", "kj_MPa_per_mm"), 1e-5, 1000, "MPa/mm",
        "a rock joint's shear stiffness (1 MPa/mm = 1 GPa/m)",
        "Barton (1982), Barton, Bandis & Bakhtar (1985): K_s = (100/L) tau_p falls as 1/L with the block "
        "length L [m]: about tau_p per mm for a 0.1 m lab sample, 1000 times less for a 100 m block; "
        "0.00001 MPa/mm is a 100 m block at tau_p = 0.01 MPa (half a metre of rock above); the top as "
        "K_n's",
        (Slip("MPa/m (or kPa/mm) typed as MPa/mm", _scaled(1e-3)),
         Slip("GPa/mm typed as MPa/mm", _scaled(1e3))),
    ),
    Range(
        ("kn_MPa_per_mm",), 0.001, 1000, "MPa/mm",
        "a rock joint's normal stiffness (1 MPa/mm = 1 GPa/m)",
        "Goodman (1989, ch. 5): joints s apart in rock of modulus E_r make a mass of modulus E_m with "
        "1/E_m = 1/E_r + 1/(K_n s), so K_n > E_m / s: 0.002 MPa/mm for the weakest masses (E_m = 0.1 "
        "GPa) jointed 50 m apart; Itasca (3DEC manual, Joint Properties): over 100 GPa/m for tight "
        "joints in granite and basalt (Bandis et al. 1983 among its sources)",
        (Slip("MPa/m (or kPa/mm) typed as MPa/mm", _scaled(1e-3)),
         Slip("GPa/mm typed as MPa/mm", _scaled(1e3))),
    ),
    Range(
        ("intact_rock.cohesion_MPa",), 0, 100, "MPa", "the cohesion of intact rock (a law with breaks_into)",
        "Mohr-Coulomb's sigma_c = 2 c cos phi / (1 - sin phi): c is 0.13 to 0.29 sigma_c for phi 60 to "
        "30 deg, so at most about 70 MPa for the strongest rock (ISRM R6, 250 MPa)",
        (KPA_AS_MPA,),
    ),
    Range(
        ("cohesion_MPa",), 0, 1, "MPa", "the cohesion of a rock joint",
        "Barton (1974, in Hoek & Bray 1981): filled joints show peak cohesions of 0 to a few hundred "
        "kPa; a clean joint has none",
        (KPA_AS_MPA,),
    ),
    Range(
        ("cohesion_kPa",), 0, 1000, "kPa", "the cohesion of a rock joint", "as cohesion_MPa",
        (Slip("Pa typed as kPa", _scaled(1e-3)),),
    ),
    Range(
        ("tensile_strength_MPa",), 0, 25, "MPa", "a tensile strength in rock",
        "a joint has little or none; intact rock about a tenth of its compressive strength "
        "(at most about 25 MPa)",
        (KPA_AS_MPA,),
    ),
    Range(
        ("density_kg_m3",), 1000, 5000, "kg/m^3", "the density of rock",
        "most rocks lie within 2000-3000 kg/m^3 (Goodman 1989, ch. 2); wider here for porous and "
        "ore-bearing rock",
        (Slip("a unit weight in kN/m^3 typed as kg/m^3", _scaled(1e3 / G)),
         Slip("g/cm^3 (t/m^3) typed as kg/m^3", _scaled(1e3))),
    ),
    Range(
        ("water.unit_weight_kN_m3",), 9.7, 10.3, "kN/m^3", "the unit weight of water",
        "1000 kg/m^3 (fresh) to 1025 kg/m^3 (sea water) times 9.81 m/s^2",
        (Slip("a density in kg/m^3 typed as kN/m^3", _scaled(G / 1e3)),
         Slip("N/m^3 typed as kN/m^3", _scaled(1e-3))),
    ),
    Range(
        ("unit_weight_kN_m3",), 10, 50, "kN/m^3", "the unit weight of rock", "as density_kg_m3",
        (Slip("a density in kg/m^3 typed as kN/m^3", _scaled(G / 1e3)),
         Slip("N/m^3 typed as kN/m^3", _scaled(1e-3)),
         Slip("a density in t/m^3 (g/cm^3) typed as kN/m^3", _scaled(G))),
    ),
    Range(
        ("horizontal_coefficient", "seismic_coefficient"), 0, 0.5, "", "a pseudo-static seismic "
        "coefficient k_h (a fraction of g)",
        "Hynes-Griffin & Franklin (1984): k_h = half the peak ground acceleration; above 0.5 the "
        "peak would exceed 1 g",
        (Slip("an acceleration in m/s^2 typed as a fraction of g", _scaled(1 / G)),),
    ),
    Range(
        ("face_angle_deg", "face_deg", "plane_deg", "base_dip_deg"), 2, 90, "deg",
        "the dip of a slope face or a sliding plane",
        "a face or plane flatter than 2 deg does not make a slope; below 1.6 a value reads as radians",
        (RADIANS,),
    ),
    Range(
        ("lab_length_m",), 0.02, 1, "m", "the length of a laboratory joint sample",
        "Barton & Bandis (1982): laboratory samples of about 0.1 m", (MM_AS_M,),
    ),
    Range(
        ("field_length_m",), 0.05, 100, "m", "a joint's length in the field (block size)",
        "Barton & Bandis (1982): the block size along the joint, from decimetres to metres",
        (MM_AS_M,),
    ),
    Range(
        ("sigma_n_MPa", "tau_MPa", "normal_stresses_MPa", "tangent_stresses_MPa", "envelope_range_MPa",
         "sigma_n_min_MPa", "sigma_n_max_MPa"), -100, 100, "MPa", "a stress on a joint in a slope",
        "100 MPa is the weight of 4 km of rock at 25 kN/m^3",
        (KPA_AS_MPA,),
    ),
    Range(
        ("steel_capacity_kN", "plate_capacity_kN", "shear_capacity_kN"), 10, 20000, "kN",
        "a rock bolt's, cable's or anchor's capacity or load, per tendon",
        "Hoek, Kaiser & Bawden (1995, ch. 12): a 16 mm rebar about 100 kN, a 25 mm one about 250 kN, a "
        "15.2 mm strand 260 kN; multi-strand anchors reach a few MN",
        (Slip("N typed as kN", _scaled(1e-3)), Slip("MN typed as kN", _scaled(1e3)),
         Slip("tonnes-force typed as kN", _scaled(G))),
    ),
    Range(
        ("pretension_kN",), 0, 20000, "kN", "an anchor's lock-off load", "as steel_capacity_kN",
        (Slip("N typed as kN", _scaled(1e-3)), Slip("MN typed as kN", _scaled(1e3))),
    ),
    Range(
        ("support.spacing_m",), 0.3, 20, "m", "the out-of-plane spacing of bolts or anchors",
        "bolts at 1-3 m, anchors at 2-6 m in practice (Wyllie & Mah 2004, ch. 14)", (MM_AS_M,),
    ),
    Range(
        ("diameter_mm",), 10, 150, "mm", "a bolt's bar (or an anchor's tendon) diameter",
        "rock bolts 16-40 mm, bars to about 75 mm (Hoek, Kaiser & Bawden 1995, ch. 12)",
        (Slip("m typed as mm", _scaled(1e3)),),
    ),
    Range(
        ("area_mm2",), 50, 20000, "mm^2", "a tendon's steel area",
        "a 16 mm bar 200 mm^2; a 15.2 mm strand 140 mm^2, anchors of up to about 55 strands",
        (Slip("m^2 typed as mm^2", _scaled(1e6)), Slip("cm^2 typed as mm^2", _scaled(100))),
    ),
    Range(
        ("bond_strength_kN_per_m",), 10, 3000, "kN/m", "the grout-rock bond of a tendon per metre",
        "Hoek, Kaiser & Bawden (1995) and Wyllie & Mah (2004, ch. 14): a few hundred kN per metre for "
        "bolts and anchors in rock",
        (Slip("kN/mm typed as kN/m", _scaled(1e3)), Slip("N/m typed as kN/m", _scaled(1e-3))),
    ),
    Range(
        ("steel_modulus_GPa",), 150, 220, "GPa", "the Young's modulus of bolt or strand steel",
        "steel 195-210 GPa; strand about 195 GPa", (Slip("MPa typed as GPa", _scaled(1e-3)),),
    ),
)  # fmt: skip


@functools.cache
def _row(path: str) -> Range | None:
    """The row for a dotted key (list indices left out), or None for a key with no plausible range."""
    return next((row for row in RANGES if row.matches(path)), None)


def unit_of(path: str) -> str:
    """The unit of the row for a dotted key ('' for none)."""
    row = _row(path)
    return row.unit if row is not None else ""


def verdict(path: str, value: float) -> str | None:
    """What is wrong with `value` at the dotted key `path`, or None if it is plausible (or unchecked)."""
    row = _row(path)
    if row is None or row.low <= value <= row.high:
        return None
    unit = f" {row.unit}" if row.unit else ""
    line = f"is outside {row.span} for {row.what}"
    for slip in row.slips:
        converted = slip.value(value)
        if row.low <= converted <= row.high:
            return f"{line}: {slip.label}? ({number(converted)}{unit} if so)"
    return line


VALUES_AT_PATH = ("mean", "min", "max", "mode", "values")  # a variable's or grid axis's values


def _numbers(
    tree: object, keys: tuple[str, ...], shown: str, note: str = ""
) -> Iterator[tuple[str, str, float]]:
    """(key path for the table, path shown to the user, value) for every number in a parsed YAML tree;
    in a mapping with a `path` (a study's variable or grid axis), the values of `VALUES_AT_PATH` are
    taken as values at that path (a spread, `std`, is not); the keys of a joint law with `breaks_into`
    (intact rock) are looked up under `intact_rock`."""
    if isinstance(tree, dict):
        target = tree.get("path")
        inside = (*keys, "intact_rock") if "breaks_into" in tree else keys  # a bridge's law: intact rock
        for key, value in tree.items():
            where = f"{shown}.{key}" if shown else str(key)
            if not isinstance(target, str):
                yield from _numbers(value, (*inside, str(key)), where, note)
            elif key in VALUES_AT_PATH:
                yield from _numbers(value, tuple(target.split(".")), where, f" ({target})")
    elif isinstance(tree, list):
        for index, value in enumerate(tree):
            yield from _numbers(value, keys, f"{shown}.{index}", note)
    elif isinstance(tree, int | float) and not isinstance(tree, bool):
        yield ".".join(k for k in keys if not k.isdigit()), f"'{shown}'{note}", float(tree)


def beyond(path: str, value: float) -> str | None:
    """Why `value` at the dotted key `path` is refused, or None: above `FAR` times the high end of its
    range (below `FAR` times a negative low end), or positive and below a positive low end over `FAR`.
    0 or a negative number under a positive low end is no slip of magnitude (a frictionless joint is
    a model's choice): it is left to the key's own checks, and warned about."""
    row = _row(path)
    if row is None:
        return None
    above = (row.high > 0 and value > FAR * row.high) or (row.low < 0 and value < FAR * row.low)
    below = row.low > 0 and 0 < value < row.low / FAR
    if not (above or below):
        return None
    return f"is more than a factor of 10^6 outside {row.span} for {row.what}: no unit slip explains it"


def _lines(tree: object, source: str, judge: Callable[[str, float], str | None]) -> list[str]:
    """One line per number of a parsed config that `judge` finds fault with."""
    lines = []
    for path, shown, value in _numbers(tree, (), ""):
        problem = judge(path, value)
        if problem:
            lines.append(f"{source}: key {shown} = {value:g} {problem}")
    return lines


def implausible_values(tree: object, source: str) -> list[str]:
    """One line per implausible number of a parsed config: `<source>: key '<path>' = <value> ...`."""
    return _lines(tree, source, verdict)


def refused_values(tree: object, source: str) -> list[str]:
    """One line per number of a parsed config that is refused (`beyond`), in the same form."""
    return _lines(tree, source, beyond)


def warn(tree: object, source: str) -> None:
    """An `ImplausibleValue` warning for each implausible number of a parsed config."""
    for line in implausible_values(tree, source):
        warnings.warn(line, ImplausibleValue, stacklevel=2)


def markdown_table() -> str:
    """RANGES as the table of docs/plausible-ranges.md."""
    rows = [
        "| keys | plausible range | for | likely slips caught | source |",
        "|---|---|---|---|---|",
    ]
    for row in RANGES:
        keys = ", ".join(f"`{key}`" for key in row.keys)
        slips = "; ".join(slip.label for slip in row.slips) or "-"
        rows.append(f"| {keys} | {row.span} | {row.what} | {slips} | {row.source} |")
    return "\n".join(rows) + "\n"
