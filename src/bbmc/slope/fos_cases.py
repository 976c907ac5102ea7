"""The scenes strength reduction is verified on, each with the factor of safety it must give and where
that number comes from; the tests (tests/test_fos.py) and `bbmc bench` (fos_cost.csv) run the same
ones.

* A block on a plane (30 deg, rock 2500 kg/m^3): Mohr-Coulomb, FS = tan phi / tan psi, or with
  cohesion (c L + W cos psi tan phi) / (W sin psi); Barton-Bandis (JRC 5, JCS 20 MPa, phi_b 30 deg) on
  a wide, flat block, FS = tau_p(sigma_n) / tau, and with tan phi_b and JRC divided by F the root of
  tau_p(sigma_n; JRC / F, atan(tan phi_b / F)) = tau.
* Hoek & Bray's worked planar example (H 30 m, face 60 deg, plane 30 deg, crack 9 m behind the crest,
  c 48 kPa, phi 30 deg, 25.5 kN/m^3; `bbmc.slope.planar_scene`) against their limit equilibrium.
* Hoek & Bray's toppling example (`bbmc.slope.toppling_scene`) against tan phi / tan 38.15 deg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq

from bbmc import laws
from bbmc.slope import planar, toppling
from bbmc.slope import planar_scene as ps
from bbmc.slope import toppling_scene as ts
from bbmc.slope.limit_equilibrium import G

DENSITY = 2500.0  # kg/m^3
DIP_DEG = 30.0
BLOCK_SOLVER = {"steps": 100_000, "time_step": {"step_s": 1e-3}}
MOHR_COULOMB = {"law": "constant", "kn_MPa_per_mm": 10, "ks_MPa_per_mm": 10, "friction_deg": 40.0}
BARTON_BANDIS = {
    "law": "barton_bandis",
    "strength": {"jrc": 5.0, "jcs_MPa": 20.0, "phi_b_deg": 30.0, "phi_max_deg": 70.0},
    "normal_stiffness": {"law": "constant", "kn_MPa_per_mm": 10},
    "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 10},
}
FLAT_BLOCK = (10.0, 1.0)  # width, height [m]: sigma_n near uniform along the base
HOEK_BRAY_LAW = {
    "law": "constant",
    "kn_MPa_per_mm": 10,
    "ks_MPa_per_mm": 10,
    "friction_deg": 30.0,
    "cohesion_MPa": 0.048,
}
HOEK_BRAY_SOLVER = {"steps": 200_000, "time_step": {"step_s": 1e-2}}
GOODMAN_BRAY = toppling.regular_system(10.0, math.radians(30.0), 10, 5.0, 5.0, 1.0)


@dataclass(frozen=True)
class Case:
    name: str
    scene: dict
    expected: float  # the factor of safety it must give
    source: str  # where `expected` comes from


def block_on_plane(law: dict, width: float, height: float) -> dict:
    """A block `width` x `height` [m] on a fixed base, both turned DIP_DEG about the origin."""
    turn = {"rotate_deg": DIP_DEG, "rotate_about_m": [0.0, 0.0]}
    return {
        "name": "block_on_plane",
        "materials": {"rock": {"density_kg_m3": DENSITY}},
        "blocks": [
            {
                "name": "base",
                "material": "rock",
                "rectangle_m": {"x_m": -2 * width, "y_m": -1.0, "width_m": 3 * width, "height_m": 1.0},
                "fix": ["x", "y", "rotation"],
                **turn,
            },
            {
                "name": "slider",
                "material": "rock",
                "rectangle_m": {"x_m": -width, "y_m": 0.0, "width_m": width, "height_m": height},
                **turn,
            },
        ],
        "joint_laws": {"joint": law},
        "contacts": {"default_law": "joint"},
        "solver": BLOCK_SOLVER,
    }


JENNINGS_JOINT = {**MOHR_COULOMB, "friction_deg": 25.0}
JENNINGS_BRIDGE = {**MOHR_COULOMB, "friction_deg": 45.0, "cohesion_MPa": 0.02, "tensile_strength_MPa": 0.01}
JENNINGS_BLOCK = (10.0, 0.5)  # width, height [m]: low, so the base's normal stress is near uniform


def block_on_bridged_plane(persistence: float, brittle: bool) -> dict:
    """A block on a plane of persistence k (Jennings 1970): the base under it is the joint over k of its
    width, half at each end, and intact rock (a rock bridge) over the middle 1 - k, so the base's normal
    stress, linear along it, loads the joint with k of the block's weight. The bridge is ductile
    (`brittle` False: it keeps its strength as it slips) or breaks into the joint at its first slip."""
    width, height = JENNINGS_BLOCK
    end, middle = 0.5 * persistence * width, (1.0 - persistence) * width
    turn = {"rotate_deg": DIP_DEG, "rotate_about_m": [0.0, 0.0]}
    pieces = [("base_joint_left", end), ("base_bridge", middle), ("base_joint_right", end)]
    x, base = -width, []
    for name, length in pieces:
        group = "bridge" if name == "base_bridge" else "joint"
        rectangle = {"x_m": x, "y_m": -1.0, "width_m": length, "height_m": 1.0}
        base.append(
            {
                "name": name,
                "group": group,
                "material": "rock",
                "rectangle_m": rectangle,
                "fix": ["x", "y", "rotation"],
            }
            | turn
        )
        x += length
    slider = {"x_m": -width, "y_m": 0.0, "width_m": width, "height_m": height}
    bridge = JENNINGS_BRIDGE | ({"breaks_into": "joint"} if brittle else {})
    return {
        "name": f"bridged_plane_k{round(100 * persistence)}" + ("_brittle" if brittle else ""),
        "materials": {"rock": {"density_kg_m3": DENSITY}},
        "blocks": [*base, {"name": "slider", "material": "rock", "rectangle_m": slider, **turn}],
        "joint_laws": {"joint": JENNINGS_JOINT, "bridge": bridge},
        "contacts": {"default_law": "joint", "rules": [{"law": "bridge", "groups": ["slider", "bridge"]}]},
        "solver": BLOCK_SOLVER,
    }


def jennings_factor_of_safety(persistence: float) -> float:
    """Jennings' (1970) weighted strength over the driving force: (k tau_joint + (1 - k) tau_bridge) A /
    (W sin psi), tau = c + sigma_n tan phi with the block's mean normal stress on each part [1]."""
    width, height = JENNINGS_BLOCK
    dip = math.radians(DIP_DEG)
    weight = DENSITY * G * width * height
    sigma = weight * math.cos(dip) / width

    def tau(law: dict) -> float:
        return law.get("cohesion_MPa", 0.0) * 1e6 + sigma * math.tan(math.radians(law["friction_deg"]))

    strength = persistence * tau(JENNINGS_JOINT) + (1.0 - persistence) * tau(JENNINGS_BRIDGE)
    return strength * width / (weight * math.sin(dip))


STEP_PATH = (5.0, 0.3, 0.4, 1.25)  # tread length, step height, slider thickness, bridge length [m]
GLUE = {**MOHR_COULOMB, "cohesion_MPa": 100.0, "tensile_strength_MPa": 100.0}


def step_path(brittle: bool) -> dict:
    """A step path through two sets: a slider of two blocks glued together (a fictitious joint far
    stronger than the rock) on two treads of set 1 (dip 30 deg), joined by a riser of set 2 (dip 60 deg,
    a joint without tension). Each tread is joint except a rock bridge of length b next to the riser,
    the two bridges symmetric about the middle of the treads' span (so a rigid slider loads them with
    the mean normal stress); moving down the treads, the slider pulls away from the riser, which opens.
    Downslope is -x before the turn: the lower tread lies left of the riser."""
    tread, step, thick, bridge_length = STEP_PATH
    turn = {"rotate_deg": DIP_DEG, "rotate_about_m": [0.0, 0.0]}
    held = {"material": "rock", "fix": ["x", "y", "rotation"]} | turn

    def piece(name: str, group: str, x: float, width: float, top: float) -> dict:
        return held | {
            "name": name,
            "group": group,
            "rectangle_m": {"x_m": x, "y_m": -1.0, "width_m": width, "height_m": 1.0 + top},
        }

    blocks = [
        piece("lower_joint", "joint", -tread, tread - bridge_length, 0.0),
        piece("lower_bridge", "bridge", -bridge_length, bridge_length, 0.0),
        piece("upper_bridge", "bridge", 0.0, bridge_length, step),
        piece("upper_joint", "joint", bridge_length, tread - bridge_length, step),
        {
            "name": "slider_lower",
            "material": "rock",
            "rectangle_m": {"x_m": -tread, "y_m": 0.0, "width_m": tread, "height_m": step + thick},
        }
        | turn,
        {
            "name": "slider_upper",
            "material": "rock",
            "rectangle_m": {"x_m": 0.0, "y_m": step, "width_m": tread, "height_m": thick},
        }
        | turn,
    ]
    bridge = JENNINGS_BRIDGE | ({"breaks_into": "joint"} if brittle else {})
    treads = [0.0, 45.0]  # set 1, turned to 30 deg; the riser (set 2) dips 60 deg
    return {
        "name": "step_path" + ("_brittle" if brittle else ""),
        "materials": {"rock": {"density_kg_m3": DENSITY}},
        "blocks": blocks,
        "joint_laws": {"joint": JENNINGS_JOINT, "bridge": bridge, "glue": GLUE},
        "contacts": {
            "default_law": "joint",
            "rules": [
                {"law": "glue", "groups": ["slider_lower", "slider_upper"]},
                {"law": "bridge", "groups": ["slider_lower", "bridge"], "dip_deg": treads},
                {"law": "bridge", "groups": ["slider_upper", "bridge"], "dip_deg": treads},
            ],
        },
        "solver": BLOCK_SOLVER,
    }


def step_path_factor_of_safety() -> float:
    """Limit equilibrium of `step_path`: the slider translates down the treads as one rigid body; the
    riser opens and carries nothing; the treads carry the slider's weight W cos psi at a uniform mean
    normal stress (the bridges, symmetric about the treads' middle, see the mean of a linear stress);
    every part is at its strength together (ductile bridges): FS = sum over the treads' joint and bridge
    parts of (c L + N tan phi) / (W sin psi) [1]."""
    tread, step, thick, bridge_length = STEP_PATH
    dip = math.radians(DIP_DEG)
    weight = DENSITY * G * (tread * (step + thick) + tread * thick)
    sigma = weight * math.cos(dip) / (2.0 * tread)

    def resistance(law: dict, length: float) -> float:
        return length * (
            law.get("cohesion_MPa", 0.0) * 1e6 + sigma * math.tan(math.radians(law["friction_deg"]))
        )

    bridges = 2.0 * bridge_length
    total = resistance(JENNINGS_JOINT, 2.0 * tread - bridges) + resistance(JENNINGS_BRIDGE, bridges)
    return total / (weight * math.sin(dip))


def _flat_block_stresses() -> tuple[float, float]:
    """sigma_n and tau under the flat block [Pa]."""
    weight = DENSITY * G * FLAT_BLOCK[1]
    dip = math.radians(DIP_DEG)
    return weight * math.cos(dip), weight * math.sin(dip)


def _peak(sigma_n: float, jrc: float, phi_b: float) -> float:
    s = BARTON_BANDIS["strength"]
    return float(
        laws.peak_shear_strength(sigma_n, jrc, s["jcs_MPa"] * 1e6, phi_b, math.radians(s["phi_max_deg"]))
    )


def barton_bandis_envelope_fs() -> float:
    sigma_n, tau = _flat_block_stresses()
    s = BARTON_BANDIS["strength"]
    return _peak(sigma_n, s["jrc"], math.radians(s["phi_b_deg"])) / tau


def barton_bandis_phi_b_jrc_fs() -> float:
    sigma_n, tau = _flat_block_stresses()
    s = BARTON_BANDIS["strength"]
    tan_b = math.tan(math.radians(s["phi_b_deg"]))
    return brentq(lambda f: _peak(sigma_n, s["jrc"] / f, math.atan(tan_b / f)) - tau, 0.2, 10.0)


def hoek_bray_slope(fill: float, kh: float) -> ps.PlanarSlope:
    return ps.PlanarSlope(30.0, 60.0, 30.0, 9.0, fill, kh, 25.5e3 / G, G)


def hoek_bray_case(fill: float, kh: float) -> Case:
    slope = hoek_bray_slope(fill, kh)
    expected = planar.factor_of_safety_mohr_coulomb(slope.forces(), 48e3, math.radians(30.0))
    water = {0.0: "dry", 0.5: "half_full", 1.0: "full"}.get(fill, f"fill_{round(100 * fill)}pc")
    name = f"hoek_bray_{water}" + (f"_kh_{round(100 * kh)}pc" if kh else "")
    scene = ps.planar_scene(name, slope, HOEK_BRAY_LAW, HOEK_BRAY_SOLVER)
    return Case(name, scene, float(expected), "Hoek & Bray planar limit equilibrium")


def goodman_bray_case(friction_deg: float) -> Case:
    scene = ts.toppling_scene(GOODMAN_BRAY, friction_deg, ts.TrialSettings())
    expected = math.tan(math.radians(friction_deg)) / math.tan(toppling.limiting_friction(GOODMAN_BRAY))
    return Case(
        f"goodman_bray_phi{friction_deg:g}", scene, expected, "tan phi / tan 38.15 deg (Goodman-Bray)"
    )


def cases() -> list[Case]:
    """Every verification case, in the order of the table in docs/verification.md."""
    dip = math.radians(DIP_DEG)
    cohesive = {**MOHR_COULOMB, "friction_deg": 25.0, "cohesion_MPa": 0.002}
    weight = DENSITY * G * 2.0 * 0.5
    closed = (2e3 * 2.0 + weight * math.cos(dip) * math.tan(math.radians(25.0))) / (weight * math.sin(dip))
    phi_b_jrc = block_on_plane(BARTON_BANDIS, *FLAT_BLOCK) | {"fos": {"barton_bandis_reduction": "phi_b_jrc"}}
    return [
        Case(
            "block_mohr_coulomb",
            block_on_plane(MOHR_COULOMB, 0.8, 0.2),
            math.tan(math.radians(40.0)) / math.tan(dip),
            "tan phi / tan psi",
        ),
        Case(
            "block_mohr_coulomb_cohesion",
            block_on_plane(cohesive, 2.0, 0.5),
            closed,
            "(cL + W cos psi tan phi) / W sin psi",
        ),
        Case(
            "block_below_one",
            block_on_plane({**MOHR_COULOMB, "friction_deg": 25.0}, 0.8, 0.2),
            math.tan(math.radians(25.0)) / math.tan(dip),
            "tan phi / tan psi",
        ),
        Case(
            "block_barton_bandis",
            block_on_plane(BARTON_BANDIS, *FLAT_BLOCK),
            barton_bandis_envelope_fs(),
            "tau_p(sigma_n) / tau",
        ),
        Case(
            "block_barton_bandis_phi_b_jrc",
            phi_b_jrc,
            barton_bandis_phi_b_jrc_fs(),
            "root of tau_p(JRC/F, phi_b/F) = tau",
        ),
        *(hoek_bray_case(fill, kh) for kh in (0.0, 0.1) for fill in (0.0, 0.5, 1.0)),
        goodman_bray_case(40.0),
        goodman_bray_case(45.0),
    ]
