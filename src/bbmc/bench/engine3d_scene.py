"""What the 3D engine's bench section times, in the fresh process that `bbmc.bench.engine3d` starts (so
that a 2D run, and the bench stage itself, import nothing of `bbmc.dem3d`).

The scene (`stack`): a cube of unit blocks (1 x 1 x 0.5 m, 1 mm gaps between neighbours of a layer) in
layers staggered by a quarter block every other layer, so that each block rests on the four below it
by quarter faces (face–face contacts clipped to partial overlaps, the sub-contacts' usual work), on a
held base; Mohr-Coulomb joints K_n 1 GPa/m, K_s 0.5 GPa/m, phi 30 deg; density 2500 kg/m3; the face
triangulation refined once; local damping 0.8 at half the critical step. It settles under gravity while
it is timed. A sub-contact update is one row of the engine's sub-contact table in one step, every row of
every candidate pair counted (as the 2D engine's `bbmc.bench.scaling` counts them); the rows of
touching pairs are given too. The 3D wedge is 3DEC's sliding wedge of issue 36 (planes 40/130 and 60/220,
c 0, phi 40 deg; tests/test_dem3d_wedge_fos.py), its factor of safety by strength reduction. Units: m,
kg, s.
"""

from __future__ import annotations

import hashlib
import math
import time

from bbmc.dem3d.contact_forces import KEY, NONE, SUB_COUNT
from bbmc.dem3d.joint_laws import MohrCoulomb
from bbmc.dem3d.model import Model, build_model
from bbmc.dem3d.solver import run, time_step
from bbmc.fos.strength_reduction3d import factor_of_safety_3d
from bbmc.geometry.polyhedra import box
from bbmc.scene.fos_settings import StrengthReduction
from bbmc.slope.wedge.engine_scene import wedge_scene
from bbmc.slope.wedge.geometry import wedge_geometries

GAP = 0.001  # m between neighbours of a layer
KN = 1e9  # Pa/m
DAMPING = 0.8
WEDGE_ANGLES_DEG = (40.0, 130.0, 60.0, 220.0, 70.0, 175.0, 0.0, 175.0)  # planes 1, 2, face, upper surface
WEDGE_HEIGHT = 10.0  # m, H1


def stack(blocks: int) -> Model:
    """The stack of about `blocks` blocks (the nearest cube of a side count), on a held base (module
    docstring)."""
    side = max(1, round(blocks ** (1.0 / 3.0)))
    polyhedra = [box([-1.0, -1.0, -1.0], [side + 1.0, side + 1.0, 0.0], name="base")]
    for k in range(side):
        shift = 0.25 * (k % 2)
        for j in range(side):
            for i in range(side):
                lo = (i + shift, j + shift, 0.5 * k)
                polyhedra.append(box(lo, (lo[0] + 1.0 - GAP, lo[1] + 1.0 - GAP, lo[2] + 0.5)))
    law = MohrCoulomb(KN, KN / 2, math.radians(30.0))
    return build_model(polyhedra, 2500.0, [law], held=[0], refine=1)


def _warm_up() -> None:
    """Every kernel a run uses loaded (or compiled), on 1 and on several threads, before anything is timed."""
    model = stack(8)
    dt = time_step(model)
    run(model, 2, dt, DAMPING)
    run(model, 2, dt, DAMPING, threads=2)


def measure_stack(blocks: int, steps: int, threads: int) -> dict:
    """`steps` steps of the stack of about `blocks` blocks on `threads` threads, after one untimed step
    (the search at step 0): its sub-contact rows and rate, and a digest of the blocks and sub-contacts
    at the end (the same bits for any thread count)."""
    _warm_up()
    model = stack(blocks)
    dt = time_step(model, 0.5, DAMPING)
    run(model, 1, dt, DAMPING, threads)
    start = time.perf_counter()
    run(model, steps, dt, DAMPING, threads)
    seconds = time.perf_counter() - start
    touching = model.contacts[:, KEY] != NONE
    digest = hashlib.sha256(model.blocks.tobytes() + model.subs.tobytes()).hexdigest()
    return {
        "blocks": len(model.blocks),
        "pairs": len(model.contacts),
        "sub_contacts": len(model.subs),
        "touching_sub_contacts": int(model.contacts[touching, SUB_COUNT].sum()),
        "seconds_per_step": seconds / steps,
        "sub_contact_updates_per_s": len(model.subs) * steps / seconds,
        "digest": digest,
    }


def wedge_srm_seconds() -> dict:
    """The wall time [s] of the 3D wedge's factor of safety by strength reduction (module docstring),
    kernels loaded first, and the factor found."""
    _warm_up()
    geometry = wedge_geometries(*(math.radians(a) for a in WEDGE_ANGLES_DEG), height_h1=WEDGE_HEIGHT)
    law = MohrCoulomb(KN, KN / 2, math.radians(40.0))
    start = time.perf_counter()
    result = factor_of_safety_3d(wedge_scene(geometry, 2500.0, law), StrengthReduction(tolerance=1e-3))
    return {"seconds": time.perf_counter() - start, "factor_of_safety": result.factor_of_safety}
