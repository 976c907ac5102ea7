"""`bbmc warmup`: compile every numba kernel of the engine and the laws into the on-disk cache once, so
that a user's first `bbmc run` loads them instead of compiling them (`bbmc run
configs/scenes/example.yaml`: 3.4-4.2 s after a warm-up, 20-24 s on a cold cache).

pip has no post-install hook, so `make` calls it after installing (the `.venv/.installed` step), and a
study calls `warm_if_cold` once per machine before its workers start (`bbmc.sweep.runner`), so that
its workers load the engine instead of each compiling it at once. It compiles through the run path
`bbmc.api` takes, not from a list of kernels: two small built-in scenes are validated, built and
simulated, and the factor of safety of one of them found by strength reduction, so every
kernel those paths call is compiled with the exact argument types a real run gives it, and a kernel
added to the engine later is warmed without an edit here, as long as these scenes reach it (a slow
test fails naming any kernel of `bbmc.dem` a cold warm-up leaves uncompiled; a setting that selects
other kernels, a thread count say, needs a run with it here):

* `PLAIN`: a brick wall under a slab on constant Mohr–Coulomb joints, the automatic time step;
* `FEATURED`: a block on the paper's peak-only Barton–Bandis joint, one on the full (mobilized)
  joint, two joined by intact rock that breaks into a joint, joint water, a pseudo-static k_h, edge
  and block loads, a law update on stress change; then its factor of safety
  (strength-reduction trials);
* `SCENE_3D`: the 3D engine (`bbmc.dem3d`): a wedge and a box on Mohr–Coulomb and Barton–Bandis
  joints under a pseudo-static k_h, run on one thread and on two, then its factor of safety.

Then every numpy ufunc of `bbmc.laws` is called once on float64 arrays (its loop for the type numpy
callers pass). A kernel is counted as compiled when this call wrote it into the cache folder
(`bbmc.kernel_cache`); a second call writes nothing: everything is loaded from the cache.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bbmc import kernel_cache, laws
from bbmc.config import validate
from bbmc.dem.model import build_model
from bbmc.dem.solver import simulate
from bbmc.dem3d.scene_run import run_scene
from bbmc.fos.strength_reduction import factor_of_safety
from bbmc.fos.strength_reduction3d import factor_of_safety_3d
from bbmc.scene.schema import Scene
from bbmc.scene.schema3d import Scene3D
from bbmc.slope.scene3d import build_scene3d

_MOHR_COULOMB = {"law": "constant", "kn_MPa_per_mm": 10, "ks_MPa_per_mm": 5, "friction_deg": 35}


def _rectangle(name: str, x: float, y: float, width: float, height: float) -> dict:
    """A rectangular block of rock, its lower left corner at (x, y) [m], `width` and `height` [m]."""
    return {
        "name": name,
        "material": "rock",
        "rectangle_m": {"x_m": x, "y_m": y, "width_m": width, "height_m": height},
    }


_BASE = _rectangle("base", -0.5, -0.4, 3.5, 0.4) | {"fix": ["x", "y", "rotation"]}

PLAIN: dict = {
    "name": "warmup_plain",
    "materials": {"rock": {"density_kg_m3": 2500}},
    "blocks": [
        _BASE,
        {
            "name": "wall",
            "material": "rock",
            "brick_wall": {
                "origin_m": [0.0, 0.0],
                "columns": 2,
                "rows": 2,
                "block_width_m": 0.4,
                "block_height_m": 0.2,
                "row_offset": 0.25,
            },
        },
        _rectangle("cap", 0.0, 0.4, 0.9, 0.1),
    ],
    "joint_laws": {"rock": _MOHR_COULOMB},
    "contacts": {"default_law": "rock"},
    "solver": {"steps": 300, "stop": {"unbalanced_force_ratio": 1e-5}},
    "monitoring": {
        "every_steps": 100,
        "monitors": [
            {"name": "cap_uy", "block": "cap", "point_m": [0.9, 0.5], "quantity": "uy"},
            {"name": "bed_sn", "between": ["wall", "base"], "quantity": "sigma_n"},
            {"name": "balance", "quantity": "unbalanced_force_ratio"},
        ],
    },
}

FEATURED: dict = {
    "name": "warmup_featured",
    "materials": {"rock": {"density_kg_m3": 2600}},
    "blocks": [
        _BASE,
        _rectangle("peak", 0.0, 0.0, 0.4, 0.2),
        _rectangle("full", 0.8, 0.0, 0.4, 0.2),
        _rectangle("lower", 1.6, 0.0, 0.4, 0.2),
        _rectangle("upper", 1.6, 0.2, 0.4, 0.2),
    ],
    "joint_laws": {
        "joint": _MOHR_COULOMB | {"cohesion_MPa": 0.01},
        "intact": _MOHR_COULOMB
        | {"cohesion_MPa": 0.002, "tensile_strength_MPa": 0.001, "friction_deg": 45, "breaks_into": "joint"},
        "paper": {
            "law": "barton_bandis",
            "strength": {"jrc": 2.13, "jcs_MPa": 3.31, "phi_b_deg": 32},
            "normal_stiffness": {"law": "eq8", "q_per_mm": 7.715},
            "shear_stiffness": {"law": "simplified", "kj_MPa_per_mm": 2.0, "nj": 0.5},
            "stress_floor_MPa": 0.01,
        },
        "mobilized": {
            "law": "barton_bandis_mobilized",
            "jrc0": 10.0,
            "jcs0_MPa": 100.0,
            "phi_b_deg": 30.0,
            "phi_r_deg": 25.0,
            "lab_length_m": 0.1,
            "normal_stiffness": {"law": "bandis", "sigma_c_MPa": 150.0},
            "shear_stiffness": {"law": "constant", "ks_MPa_per_mm": 100},
        },
    },
    "contacts": {
        "default_law": "joint",
        "rules": [
            {"law": "paper", "groups": ["peak", "base"]},
            {"law": "mobilized", "groups": ["full", "base"]},
            {"law": "intact", "groups": ["upper", "lower"]},
        ],
    },
    "loads": {
        "edge_stresses": [{"block": "upper", "edge": "up", "sigma_n_MPa": 0.01, "ramp_steps": 100}],
        "block_forces": [{"block": "full", "force_kN": [1.0, 0.0], "ramp_steps": 100}],
    },
    "water": {"phreatic_surface_m": [[-0.5, 0.1], [3.0, 0.05]]},
    "seismic": {"horizontal_coefficient": 0.05},
    "solver": {
        "steps": 3000,
        "update_interval_steps": 10,
        "law_update_stress_change": 0.1,
        "stop": {"unbalanced_force_ratio": 1e-4},
    },
    "fos": {"tolerance": 0.1, "min_trial_steps": 100, "response_multiple": 1, "largest_factor": 8},
    "monitoring": {
        "every_steps": 100,
        "monitors": [
            {"name": "full_ux", "block": "full", "quantity": "ux"},
            {"name": "full_dilation", "between": ["full", "base"], "quantity": "dilation"},
            {"name": "peak_ks", "between": ["peak", "base"], "quantity": "ks"},
            {"name": "bridge_sn", "near_m": [1.8, 0.2], "quantity": "sigma_n"},
            {"name": "strain", "quantity": "strain_energy"},
        ],
    },
}


SCENE_3D: dict = {
    "name": "warmup_3d",
    "dimension": 3,
    "materials": {"rock": {"density_kg_m3": 2600}},
    "joint_types": {
        "mc": {"law": "mohr_coulomb", "kn_MPa_per_mm": 1, "ks_MPa_per_mm": 0.5, "friction_deg": 35},
        "bb": {"law": "barton_bandis", "kn_MPa_per_mm": 1, "ks_MPa_per_mm": 0.5, "jrc": 8, "jcs_MPa": 60,
               "phi_b_deg": 30},
    },
    "contacts": {"default": "bb", "rules": [{"groups": ["box", "base"], "joint_type": "mc"}]},
    "blocks": [
        {"name": "base", "material": "rock", "held": True, "box": {"lo_m": [20, -2, -1], "hi_m": [24, 2, 0]}},
        {"name": "box", "material": "rock", "box": {"lo_m": [21, -1, 0], "hi_m": [23, 1, 1]}},
    ],
    "wedge": {
        "material": "rock",
        "plane_1": {"dip_deg": 40, "dip_direction_deg": 130},
        "plane_2": {"dip_deg": 60, "dip_direction_deg": 220},
        "face": {"dip_deg": 80, "dip_direction_deg": 180},
        "upper_surface": {"dip_deg": 0, "dip_direction_deg": 180},
        "height_m": 4,
    },
    "seismic": {"horizontal_coefficient": 0.02, "towards_deg": 180},
    "solver": {"steps": 200},
    "fos": {"tolerance": 0.1, "min_trial_steps": 100, "response_multiple": 1, "largest_factor": 4},
}  # fmt: skip


@dataclass(frozen=True)
class Warmup:
    """What one warm-up did: `compiled` kernels written into the cache `folder` by this call,
    `cached` kernels in it afterwards, in `seconds` [s] of wall time."""

    compiled: int
    cached: int
    folder: Path
    seconds: float


def _model(scene: dict):
    """The engine's model of a built-in scene, validated and built as `bbmc.api.run` builds it."""
    return build_model(validate(scene, Scene, "<scene dict>"), Path(f"{scene['name']}.yaml"))


def _warm_ufuncs() -> None:
    """Call every numpy ufunc of `bbmc.laws` once on float64 arrays, which compiles its float64 loop."""
    ones = np.ones(1)
    with np.errstate(all="ignore"):
        for name in laws.__all__:
            law = getattr(laws, name)
            law(*[ones] * law.nin)


def _warm_3d() -> None:
    """Run `SCENE_3D` on one thread and on two (the engine's serial and threaded paths) and search its
    factor of safety, as `bbmc run` and `bbmc fos` do."""
    scene = validate(SCENE_3D, Scene3D, "<scene dict>")
    for threads in (1, 2):
        variant = scene.model_copy(update={"solver": scene.solver.model_copy(update={"threads": threads})})
        run_scene(build_scene3d(variant), variant)
    built = build_scene3d(scene)
    factor_of_safety_3d(built.model, scene.fos, equilibrium_steps=20_000)


def warm(progress: Callable[[str], None] = lambda _: None) -> Warmup:
    """Compile (or load) every kernel of the engine and the laws through the public run path: the two
    scenes `PLAIN` and `FEATURED` run, the latter's factor of safety, the laws' ufuncs. `progress` is
    told each part as it starts."""
    started = time.perf_counter()
    folder = kernel_cache.current_folder()
    before = kernel_cache.kernel_files(folder)
    progress("the block engine on constant joints")
    simulate(_model(PLAIN))
    progress("the block engine with water, rock bridges, Barton-Bandis and the full joint")
    simulate(_model(FEATURED))
    progress("strength reduction (factor of safety trials)")
    factor_of_safety(_model(FEATURED))
    progress("the 3D block engine, on one thread and two, and its factor of safety")
    _warm_3d()
    progress("the joint laws as numpy ufuncs")
    _warm_ufuncs()
    compiled = len(kernel_cache.written_since(before, folder))
    return Warmup(compiled, len(kernel_cache.kernel_files(folder)), folder, time.perf_counter() - started)


def warm_if_cold(progress: Callable[[str], None] = lambda _: None) -> Warmup | None:
    """`warm` if this process's cache holds no compiled engine of this copy of the source
    (`bbmc.kernel_cache.engine_is_cold`), after one line to `progress`; None if it is warm or the
    kernels run as plain Python (NUMBA_DISABLE_JIT). A check of a few milliseconds when warm."""
    if kernel_cache.jit_disabled() or not kernel_cache.engine_is_cold(kernel_cache.current_folder()):
        return None
    progress("compiling the block engine once, before the workers start (a cold cache: 20-90 s)")
    return warm()
