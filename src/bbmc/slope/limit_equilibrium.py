"""Planar sliding of one block on a bedding plane: factor of safety as rock engineers compute it, and
the dip at which the engine's block starts to slide.

The block is a rectangle `length_m` along the plane and `thickness_m` normal to it, on a fixed base
dipping at the bedding dip. Its weight per metre W = rho g L h gives a uniform sigma_n = rho g h cos(psi)
and tau = rho g h sin(psi) on the plane (the limit-equilibrium idealisation; in the engine the base
stress varies along the block because the weight acts off the base's middle).

* Mohr-Coulomb: FS = (c + sigma_n tan(phi)) / tau.
* Barton-Bandis: FS = tau_p(sigma_n) / tau, tau_p from eq 9 (phi_b + JRC lg(JCS / sigma_n), capped at
  phi_max), which is what the engine's tangent (eq 15) gives at the block's sigma_n.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from scipy.optimize import brentq

from bbmc import laws, units
from bbmc.dem.model import built_scene
from bbmc.dem.solver import simulate

G = 9.81  # [m/s^2], as the scenes' default gravity


def stresses(dip_deg: float, thickness_m: float, density_kg_m3: float) -> tuple[float, float]:
    """sigma_n and tau on the plane under a block of this thickness [Pa]."""
    weight = density_kg_m3 * G * thickness_m
    psi = math.radians(dip_deg)
    return weight * math.cos(psi), weight * math.sin(psi)


def factor_of_safety(law: dict, dip_deg: float, thickness_m: float, density_kg_m3: float) -> float:
    """FS of planar sliding for a scene joint-law entry (constant or barton_bandis) [1]."""
    sigma_n, tau = stresses(dip_deg, thickness_m, density_kg_m3)
    if law["law"] == "constant":
        strength = law["cohesion_MPa"] * units.MPa + sigma_n * math.tan(math.radians(law["friction_deg"]))
    else:
        s = law["strength"]
        strength = float(
            laws.peak_shear_strength(
                sigma_n,
                s["jrc"],
                s["jcs_MPa"] * units.MPa,
                math.radians(s["phi_b_deg"]),
                math.radians(s["phi_max_deg"]),
            )
        )
    return strength / tau


def critical_dip(law: dict, thickness_m: float, density_kg_m3: float, low: float, high: float) -> float:
    """The dip [deg] where FS = 1 (Brent's method), or NaN where FS does not cross 1 between low and
    high (a block that holds, or slides, at every dip there)."""

    def excess(dip: float) -> float:
        return factor_of_safety(law, dip, thickness_m, density_kg_m3) - 1.0

    if not excess(low) * excess(high) < 0:
        return math.nan
    return brentq(excess, low, high, xtol=1e-10)


def block_scene(
    law: dict, dip_deg: float, length_m: float, thickness_m: float, density_kg_m3: float, settings: dict
) -> dict:
    """The engine's block on its bedding plane: a fixed base turned to `dip_deg` (down to the left).
    The block's weight is a force ramped on over `ramp_steps` (gravity off): dropped on its joint at
    full weight, the block overshoots its static closure, and the transient slips the joint early."""
    turn = {"rotate_deg": -dip_deg, "rotate_about_m": [0.0, 0.0]}
    weight_kN = density_kg_m3 * G * length_m * thickness_m / 1e3
    return {
        "name": "planar_block",
        "gravity_m_s2": [0.0, 0.0],
        "loads": {
            "block_forces": [
                {"block": "block", "force_kN": [0.0, -weight_kN], "ramp_steps": settings["ramp_steps"]}
            ]
        },
        "materials": {"limestone": {"density_kg_m3": density_kg_m3}},
        "blocks": [
            {
                "name": "bedding",
                "material": "limestone",
                "rectangle_m": {
                    "x_m": -3 * length_m,
                    "y_m": -thickness_m,
                    "width_m": 5 * length_m,
                    "height_m": thickness_m,
                },
                "fix": ["x", "y", "rotation"],
                **turn,
            },
            {
                "name": "block",
                "material": "limestone",
                "rectangle_m": {"x_m": 0.0, "y_m": 0.0, "width_m": length_m, "height_m": thickness_m},
                "fix": ["rotation"],
                **turn,
            },
        ],
        "joint_laws": {"joint": law},
        "contacts": {"default_law": "joint"},
        "solver": {
            "steps": settings["max_steps"],
            "damping": settings["damping"],
            "update_interval_steps": settings["update_interval_steps"],
            "stop": {
                "unbalanced_force_ratio": settings["equilibrium_ratio"],
                "displacement_m": settings["slide_m"],
            },
        },
        "monitoring": {"every_steps": 500},
    }


class UndecidedError(ValueError):
    """The engine's block neither came to rest nor slid within its steps, or the bracket of a critical
    dip does not hold at one end and slide at the other."""


def engine_slides(scene: dict) -> bool:
    """Run the block: True if it moved `slide_m` (slides), False if it came to rest (holds).
    UndecidedError if it did neither within max_steps (creeping too close to FS = 1 to decide)."""
    model = built_scene(scene, f"{scene['name']}.yaml")
    summary = simulate(model).summary.set_index("quantity")["value"]
    if summary["stopped_by_displacement"]:
        return True
    if summary["stopped_by_equilibrium"]:
        return False
    raise UndecidedError(f"undecided after {int(summary['steps'])} steps")


def engine_critical_dip(
    slides: Callable[[float], bool], low: float, high: float, tolerance_deg: float
) -> float:
    """Bisect the dip [deg] at which `slides(dip)` turns True (it must hold at low and slide at high)."""
    if slides(low) or not slides(high):
        raise UndecidedError(f"the engine's block must hold at {low:g} deg and slide at {high:g} deg")
    while high - low > tolerance_deg and low < 0.5 * (low + high) < high:  # (or adjacent numbers)
        middle = 0.5 * (low + high)
        low, high = (low, middle) if slides(middle) else (middle, high)
    return 0.5 * (low + high)
