"""Threads in the 3D engine: the same scene on 1 and on 2 threads ends with the same bits, and a 2D run
imports nothing of the 3D engine (so a 2D scene pays nothing for it)."""

import subprocess
import sys

import numba
import numpy as np
import pytest

from bbmc.bench.engine3d_scene import DAMPING, stack
from bbmc.dem3d.contact_forces import KEY, NONE
from bbmc.dem3d.solver import run, time_step


def _settled(threads):
    model = stack(27)  # 3 layers of 9 staggered boxes on a base: 60 pairs, face and degenerate contacts
    run(model, 150, time_step(model, 0.5, DAMPING), DAMPING, threads)
    return model


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="numba's pool has one thread")
def test_one_and_two_threads_give_the_same_bits():
    """Byte-identical blocks and sub-contacts after 150 steps of a settling stack (each pair's shares
    summed onto its blocks in pair order whatever the thread that updated it); and the stack is loaded
    (touching pairs carry force), so the comparison is not of zeros."""
    one, two = _settled(1), _settled(2)
    assert (one.contacts[:, KEY] != NONE).sum() >= 27
    assert np.abs(one.loads).max() > 0.0
    assert one.blocks.tobytes() == two.blocks.tobytes()
    assert one.subs.tobytes() == two.subs.tobytes()
    assert one.contacts.tobytes() == two.contacts.tobytes()


def test_a_2d_run_imports_nothing_of_the_3d_engine():
    """The 2D engine's solver and its run and fos stages load no module of bbmc.dem3d, in a
    fresh interpreter: a 2D scene's step runs exactly the code it ran before 3D existed. (The command
    line imports the 3D stages to pick one by the scene's `dimension`: 0.14 s of its 4.3 s import,
    measured with -X importtime; no kernel is compiled or loaded before a 3D scene runs.)"""
    code = (
        "import sys\nimport bbmc.dem.solver, bbmc.stages.run, bbmc.stages.fos\n"
        "print(sorted(m for m in sys.modules if m.startswith('bbmc.dem3d')))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
