"""The slope of section 5 as block scenes: one geometry, two joint models (Table 4).

* constant: 3DEC's Coulomb slip joint with Table 4's constants (K_n = K_s = 10.7 MPa/mm,
  phi = 14.51 deg, c = 5.4 kPa); cohesion lost where a joint slips (3DEC's default residual of 0).
* barton_bandis: every sub-contact's K_s (eq 18), K_n (eq 8) and phi, c (the modified eq 15, Table
  4's phi_b = 33.4 deg, JRC = 2.04, JCS = 3.87 MPa) recomputed from its own normal stress every
  `update_interval_steps` (the paper's 50). c is the tangent's intercept, kept after slip: the paper
  resets it from the stress state every 50 steps.

The paper's monitored blocks are numbered from the layer resting on the sliding plane, the bedding
joint through the toe: No. 2 is its block at the free face, No. 3 its last block up-dip (the trailing
edge of the sliding zone), No. 1 and No. 4 the blocks at one and two thirds of the way between them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from bbmc import units
from bbmc.config import Section
from bbmc.dem import layout as L
from bbmc.dem.model import Model
from bbmc.geometry import polygons
from bbmc.scene.schema import JointedSlope

JointModel = Literal["constant", "barton_bandis"]
JOINT_MODELS: tuple[JointModel, ...] = ("constant", "barton_bandis")
PAPER_NUMBERS = (1, 2, 3, 4)
Steps = Annotated[int, Field(ge=1)]


class ConstantJoint(Section):
    """Table 4's constant parameters (read from data/paper), and what slip does to c (the scene's
    default, ductile; configs/slope.yaml asks for 3DEC's `zero`)."""

    after_slip: Literal["zero", "keep"] = "keep"


class BartonBandisOptions(Section):
    """The engine's rules where the laws reach 0, the paper's printed constants or their corrections."""

    stress_floor_MPa: Annotated[float, Field(gt=0)] = 0.01
    shear_stiffness_floor: Annotated[float, Field(ge=0, le=1)] = 0.01
    phi_max_deg: Annotated[float, Field(gt=0, lt=90)] = 70.0
    tangent_coefficient: Literal["paper", "corrected"] = "paper"  # Table 4's 0.016, or exact for JRC 2.04
    lg_e: Literal["paper", "corrected"] = "paper"  # K_n = 22.4665 sigma_n as printed, or with lg e = 0.4343
    after_slip: Literal["zero", "keep"] = "keep"


class Run(Section):
    duration_s: Annotated[float, Field(gt=0)] = 3.0  # physical time, the same for both models
    max_steps: Steps = 2_000_000  # a run whose time step collapses stops here
    damping: Annotated[float, Field(ge=0, lt=1)] = 0.8
    safety_factor: Annotated[float, Field(gt=0, le=1)] = 0.5
    update_interval_steps: Steps = 50
    record_every_steps: Steps = 10
    sub_contacts_per_edge: Annotated[int, Field(ge=1, le=64)] = 4


@dataclass(frozen=True)
class Table4:
    """The paper's joint parameters (Table 4) in the units of its CSV files."""

    density_kg_m3: float
    constant: dict[str, float]  # K_s, K_n [MPa/mm], phi [deg], c [kPa]
    nonlinear: dict[str, float]  # K_st coefficient, exponent, K_n coefficient, phi_b, JRC, JCS, eq 15's k
    printed_lg_e: float  # eq 6's 0.3434, behind Table 4's 22.4665


def joint_law(
    kind: JointModel, table4: Table4, constant: ConstantJoint, options: BartonBandisOptions
) -> dict:
    """The scene's joint-law entry of one model, in the scene's units."""
    if kind == "constant":
        c = table4.constant
        return {
            "law": "constant",
            "kn_MPa_per_mm": c["K_n_MPa_per_mm"],
            "ks_MPa_per_mm": c["K_s_MPa_per_mm"],
            "cohesion_MPa": c["c_kPa"] * units.kPa / units.MPa,
            "friction_deg": c["phi_deg"],
            "after_slip": constant.after_slip,
        }
    n = table4.nonlinear
    lg_e = table4.printed_lg_e if options.lg_e == "paper" else float(np.log10(np.e))
    return {
        "law": "barton_bandis",
        "strength": {
            "jrc": n["JRC"],
            "jcs_MPa": n["JCS_MPa"],
            "phi_b_deg": n["phi_b_deg"],
            "phi_max_deg": options.phi_max_deg,
            "tangent_coefficient": n["eq15_coefficient"]
            if options.tangent_coefficient == "paper"
            else "exact",
        },
        # K_n = q sigma_n / lg e: Table 4's coefficient is q / 0.3434 (eq 6's printed lg e)
        "normal_stiffness": {
            "law": "eq8",
            "q_per_mm": n["K_n_coefficient_per_mm"] * table4.printed_lg_e,
            "lg_e": lg_e,
        },
        "shear_stiffness": {
            "law": "simplified",
            "kj_MPa_per_mm": n["K_st_coefficient_MPa_per_mm"],
            "nj": n["K_st_exponent"],
            "d": 1.0,
        },
        "stress_floor_MPa": options.stress_floor_MPa,
        "shear_stiffness_floor": options.shear_stiffness_floor,
        "after_slip": options.after_slip,
    }


def slope_scene(
    name: str,
    geometry: JointedSlope,
    density_kg_m3: float,
    law: dict,
    run: Run,
    monitors: list[dict],
) -> dict:
    """The scene of one slope run: the jointed slope under gravity, every joint with `law`."""
    return {
        "name": name,
        "description": "Jointed limestone slope of the paper's section 5 (bbmc slope).",
        "materials": {"limestone": {"density_kg_m3": density_kg_m3}},
        "blocks": [{"name": "slope", "material": "limestone", "jointed_slope": geometry.model_dump()}],
        "joint_laws": {"joint": law},
        "contacts": {"default_law": "joint", "sub_contacts_per_edge": run.sub_contacts_per_edge},
        "solver": {
            "steps": run.max_steps,
            "damping": run.damping,
            "time_step": {"mode": "auto", "safety_factor": run.safety_factor},
            "update_interval_steps": run.update_interval_steps,
            "stop": {"time_s": run.duration_s},
        },
        "monitoring": {"every_steps": run.record_every_steps, "monitors": monitors},
    }


def block_shape(model: Model, i: int) -> np.ndarray:
    """Block i's vertices where the model starts [m]."""
    return model.local[model.vertex_start[i] : model.vertex_start[i + 1]] + model.blocks[i, [L.X, L.Y]]


def sliding_layer(model: Model, geometry: JointedSlope) -> list[int]:
    """The free blocks resting on the bedding joint through the toe (joint set 0 must pass through
    it), ordered up-dip from the free face."""
    trace = polygons.joint_set_trace(
        geometry.joint_sets[0].dip_deg, geometry.joint_sets[0].dip_direction_to_face_deg
    )
    normal, spacing = trace[:2], geometry.joint_sets[0].spacing_m / trace[2]
    centroids = model.blocks[:, [L.X, L.Y]]
    height = centroids @ normal
    free = ~np.all(model.dof == L.PRESCRIBED, axis=1)
    layer = np.flatnonzero(free & (height > 0) & (height < spacing))
    return [int(i) for i in layer[np.argsort(centroids[layer, 0])]]  # the face looks towards -x


def paper_numbering(layer: list[int]) -> dict[int, int]:
    """Paper block number -> engine block index, for a sliding layer of at least four blocks."""
    if len(layer) < 4:
        raise ValueError(f"the sliding layer has {len(layer)} blocks; the paper monitors four")
    last = len(layer) - 1
    return {2: layer[0], 1: layer[round(last / 3)], 4: layer[round(2 * last / 3)], 3: layer[last]}


def monitored_joints(model: Model, block: int) -> dict[str, list[float]]:
    """Points on the near-horizontal joint under `block` (the sliding plane) and on the near-vertical
    joint behind it (up-dip), at the middle of the block's edges on them [m]."""
    shape = block_shape(model, block)
    edges = np.roll(shape, -1, axis=0) - shape
    middles = shape + edges / 2
    dips = np.degrees(np.arctan2(np.abs(edges[:, 1]), np.abs(edges[:, 0])))
    horizontal = int(np.argmin(np.where(dips < 45, middles[:, 1], np.inf)))
    vertical = int(np.argmax(np.where(dips >= 45, middles[:, 0], -np.inf)))
    return {"near_horizontal": middles[horizontal].tolist(), "near_vertical": middles[vertical].tolist()}
