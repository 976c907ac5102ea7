"""The 3D twin of a built 2D scene (`bbmc.dem.model.Model`): its blocks extruded into prisms with the
plane-strain constraints (`bbmc.dem3d.extrusion`, which gives the axes: 2D (x, y) -> 3D (x, z), depth
along y), its joint types and contact rules as the 3D engine's, and its factor of safety by the 3D
strength reduction with the 2D scene's own search settings. It lives here, above both engines, because
`bbmc.dem` and `bbmc.dem3d` must not import each other.

Joint types: a constant Mohr-Coulomb law becomes `MohrCoulomb` (K_n, K_s [Pa/m], c, phi, after_slip);
a Barton-Bandis law with constant stiffnesses becomes `BartonBandis` (its tangent, the same JRC, JCS,
phi_b, phi_max and tangent coefficient). Contact rules become the `pair_joint` table: a contact takes
the first rule naming its two blocks' groups (either order), else the first rule without groups, else
the default law, as the 2D search gives it (`bbmc.dem.contact_search`).

Refused, in one line naming the key, because the 3D engine lacks them: support, water, loads, bridges
(intact rock that breaks into a joint), a tensile strength, stiffness laws other than constant (the
full joint, Bandis), the mobilized law, contact rules by dip or by edge label, prescribed non-zero
velocities; and for the factor of safety a time step other than ``auto``.

Same search: `twin_factor_of_safety` uses the scene's `fos` settings with the 2D engine's failure
displacement (5 % of the median sqrt(area), not the 3D median size), the 2D judged blocks, the scene's
damping, time-step safety factor and equilibrium budget. Units: SI.
"""

from __future__ import annotations

import numpy as np

from bbmc.dem import layout as L
from bbmc.dem.model import Model as Model2D
from bbmc.dem3d.extrusion import extruded_model
from bbmc.dem3d.joint_laws import BartonBandis, JointLaw, MohrCoulomb
from bbmc.dem3d.model import Model as Model3D
from bbmc.fos.strength_reduction import Judged, failure_displacement
from bbmc.fos.strength_reduction3d import StrengthReduction3DResult, factor_of_safety_3d
from bbmc.geometry import polygons as poly


def section_polygons(model: Model2D) -> list[np.ndarray]:
    """Each 2D block's polygon in the world as built (counter-clockwise, (k, 2) [m])."""
    b, start = model.blocks, model.vertex_start
    return [model.local[start[i] : start[i + 1]] + b[i, [L.X, L.Y]] for i in range(len(b))]


def _law(model: Model2D, j: int) -> JointLaw:
    """Joint type j of the 2D model as a 3D joint law; refused in one line naming it."""
    codes, p, key = model.laws[j], model.params[j], f"joint_laws.{model.law_names[j]}"
    if codes[L.BREAKS_INTO] >= 0:
        raise ValueError(f"{key}: intact rock (breaks_into) does not exist in the 3D engine yet")
    if p[L.P_TEN] > 0.0:
        raise ValueError(f"{key}.tensile_strength_MPa: the 3D engine has no tensile strength yet")
    if codes[L.NORMAL_LAW] != L.NORMAL_CONSTANT or codes[L.SHEAR_LAW] != L.SHEAR_CONSTANT:
        raise ValueError(f"{key}: only constant stiffnesses exist in the 3D engine so far")
    after = "zero" if codes[L.AFTER_SLIP] == L.AFTER_SLIP_ZERO else "keep"
    if codes[L.STRENGTH_LAW] == L.STRENGTH_CONSTANT:
        return MohrCoulomb(p[L.P_KN], p[L.P_KS], p[L.P_PHI], p[L.P_COH], after)
    if codes[L.STRENGTH_LAW] == L.STRENGTH_BARTON_BANDIS:
        return BartonBandis(p[L.P_KN], p[L.P_KS], p[L.P_JRC], p[L.P_JCS], p[L.P_PHI_B], p[L.P_PHI_MAX],
                            p[L.P_K_TANGENT], after)  # fmt: skip
    raise ValueError(f"{key}: the mobilized law does not exist in the 3D engine yet")


def _pair_joint(model: Model2D) -> np.ndarray:
    """The 2D joint type of a contact between groups i and j (module docstring); a rule by dip or by
    edge label is refused, naming it."""
    for r in range(len(model.rule_law)):
        if not np.allclose(model.rule_dip[r], [0.0, np.pi / 2]):
            raise ValueError(f"contacts.rules.{r}.dip_deg: the 3D twin takes rules by groups only")
        if not model.rule_edges[r].all():
            raise ValueError(f"contacts.rules.{r}.edges: the 3D twin takes rules by groups only")
    g = len(model.group_names)
    table = np.full((g, g), -1, dtype=np.int64)
    for (g1, g2), law in zip(model.rule_groups, model.rule_law, strict=True):
        if g1 < 0:
            table[table < 0] = law
        elif table[g1, g2] < 0:
            table[g1, g2] = table[g2, g1] = law
    table[table < 0] = model.default_law
    return table


def _refuse_features(model: Model2D) -> None:
    """ValueError in one line naming the key of the first feature the 3D engine lacks."""
    if len(model.support.names):
        raise ValueError("support: the 3D engine has no support elements yet")
    if model.water_unit_weight > 0.0:
        raise ValueError("water: the 3D engine has no water pressures yet")
    if len(model.block_loads) or len(model.edge_loads):
        raise ValueError("loads: the 3D engine has no block forces or edge stresses yet")
    if np.any(model.blocks[:, [L.VPX, L.VPY, L.VPW]] != 0.0):
        raise ValueError("blocks.velocity: the 3D twin takes held blocks, not prescribed velocities")


def twin_model(model: Model2D, depth: float = 1.0, refine: int = 1, constraint: str = "held") -> Model3D:
    """The plane-strain 3D twin of the built 2D `model`, extruded `depth` [m], its faces refined
    `refine` times, held in plane by `constraint` (`bbmc.dem3d.extrusion`); block i is the 2D block i,
    in the same group. ValueError naming the key of what the 3D engine lacks (module docstring)."""
    _refuse_features(model)
    table = _pair_joint(model)
    used = sorted(set(table.ravel().tolist()))
    laws = [_law(model, j) for j in used]
    shapes = section_polygons(model)
    areas = np.array([poly.mass_properties(s)[0] for s in shapes])
    return extruded_model(
        shapes,
        depth,
        model.blocks[:, L.MASS] / areas,
        laws,
        dof_2d=model.dof,
        gravity_2d=model.gravity,
        group=model.block_group,
        pair_joint=np.searchsorted(used, table),
        refine=refine,
        constraint=constraint,
    )


def twin_factor_of_safety(
    model: Model2D, depth: float = 1.0, refine: int = 1, constraint: str = "held"
) -> StrengthReduction3DResult:
    """The factor of safety of the 2D `model`'s 3D twin (`twin_model`) by `bbmc.fos.strength_reduction3d`
    with the 2D search's settings (module docstring)."""
    solver = model.scene.solver
    if solver.time_step.mode != "auto":
        raise ValueError("solver.time_step.mode: the 3D strength reduction's step is 'auto' only")
    twin = twin_model(model, depth, refine, constraint)
    settings = model.scene.fos.model_copy(update={"failure_displacement_m": failure_displacement(model)})
    judged = np.flatnonzero(Judged.of(model).blocks)
    return factor_of_safety_3d(
        twin,
        settings,
        damping=solver.damping,
        safety=solver.time_step.safety_factor,
        equilibrium_steps=solver.steps,
        judged=judged.tolist(),
    )
