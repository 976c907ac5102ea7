"""What the 3D engine costs (engine3d.csv), beside the 2D engine in the same run: each reading the median
of `repeats` fresh processes, the 3D and the 2D scene taking turns, each process warmed up (numba's
kernels loaded) before it times anything.

* sub-contact updates per second per core (one thread: NUMBA_NUM_THREADS=1) on the 3D stack of
  `bbmc.bench.engine3d_scene` at each of `block_counts`, and the 2D engine's on the scaling slope of
  about as many blocks (`bbmc.bench.scaling.measure_here`), and their ratio;
* at `threads_blocks` blocks, the 3D rate on 2 threads, its speed-up over 1, and whether the two runs
  ended with the same bits (a digest of the blocks and sub-contacts);
* the wall time of a 3D wedge's factor of safety by strength reduction;
* the modules of `bbmc.dem3d` that a 2D run's engine imports (the 2D solver and the run stage): none, so
  a 2D scene's step pays nothing for 3D (the command line imports the 3D stages, 0.14 s of its 4.3 s).

Issue 36's marks are written beside each: at least 15 M updates/s per core at 10,000 blocks, 2 threads at
least 1.6 x, bitwise identical, the wedge's strength reduction under 30 s, nothing of 3D in a 2D run.
"""

from __future__ import annotations

import statistics
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from bbmc.bench.scaling import answer_of_fresh_process

SOURCE = Path(__file__).resolve().parents[2]  # src/: the package, whether installed or not
TARGET_RATE, TARGET_RATE_BLOCKS = 15e6, 10_000  # updates/s per core, at this many blocks
TARGET_SPEEDUP = 1.6
TARGET_WEDGE_S = 30.0
IMPORTS_2D = (
    "import json, sys\nimport bbmc.dem.solver, bbmc.stages.run\n"
    "print(json.dumps({'modules': sorted(m for m in sys.modules if m.startswith('bbmc.dem3d'))}))"
)

WEDGE_CODE = (
    "import json\nfrom bbmc.bench import engine3d_scene\n"
    "print(json.dumps(engine3d_scene.wedge_srm_seconds()))"
)


def _stack_code(blocks: int, steps: int, threads: int) -> str:
    return (
        "import json\nfrom bbmc.bench import engine3d_scene\n"
        f"print(json.dumps(engine3d_scene.measure_stack({blocks}, {steps}, {threads})))"
    )


def _slope_code(blocks: int, steps: int, slope_config: str) -> str:
    return (
        "import json\nfrom bbmc.bench import scaling\n"
        f"r = scaling.measure_here({blocks}, {steps}, 1, 0.5, {slope_config!r}, 1)\n"
        "print(json.dumps({k: r[k] for k in ('blocks', 'sub_contacts', 'sub_contact_updates_per_s')}))"
    )


def _medians(codes: dict[str, tuple[str, int]], repeats: int, progress: Callable[[str], None],
             timeout_s: float) -> dict[str, list[dict]]:  # fmt: skip
    """Each code's readings over `repeats` rounds, the codes taking turns in every round: {label: runs}."""
    runs: dict[str, list[dict]] = {label: [] for label in codes}
    for k in range(repeats):
        for label, (code, threads) in codes.items():
            progress(f"engine3d: {label}, fresh process {k + 1}/{repeats}")
            runs[label].append(answer_of_fresh_process(code, SOURCE, timeout_s, threads))
    return runs


def _median(readings: list[dict], key: str) -> float:
    return statistics.median(r[key] for r in readings)


def engine3d_table(
    block_counts: list[int],
    steps: int,
    threads_blocks: int,
    repeats: int,
    slope_config: str,
    progress: Callable[[str], None] = lambda _: None,
    timeout_s: float = 3600.0,
) -> pd.DataFrame:
    """The rows of engine3d.csv: quantity, value, unit, the issue's mark where it has one and whether the
    value meets it (module docstring)."""
    rows = []
    for n in block_counts:
        codes = {f"3D stack of {n} blocks": (_stack_code(n, steps, 1), 1),
                 f"2D slope of {n} blocks": (_slope_code(n, steps, slope_config), 1)}  # fmt: skip
        three, two = _medians(codes, repeats, progress, timeout_s).values()
        rate_3d, rate_2d = (
            _median(three, "sub_contact_updates_per_s"),
            _median(two, "sub_contact_updates_per_s"),
        )
        mark, met = ("at least 1.5e7", rate_3d >= TARGET_RATE) if n >= TARGET_RATE_BLOCKS else ("", None)
        rows += [
            (f"blocks_3d_{n}", three[0]["blocks"], "1", "", None),
            (f"sub_contacts_3d_{n}", three[0]["sub_contacts"], "1", "", None),
            (f"touching_sub_contacts_3d_{n}", three[0]["touching_sub_contacts"], "1", "", None),
            (f"rate_3d_{n}", rate_3d, "1/s", mark, met),
            (f"blocks_2d_{n}", two[0]["blocks"], "1", "", None),
            (f"rate_2d_{n}", rate_2d, "1/s", "", None),
            (f"rate_3d_over_2d_{n}", rate_3d / rate_2d, "1", "", None),
        ]  # fmt: skip
    codes = {f"3D stack of {threads_blocks} blocks, {t} thread(s)": (_stack_code(threads_blocks, steps, t), t)
             for t in (1, 2)}  # fmt: skip
    one, two = _medians(codes, repeats, progress, timeout_s).values()
    speedup = _median(two, "sub_contact_updates_per_s") / _median(one, "sub_contact_updates_per_s")
    same = all(r["digest"] == one[0]["digest"] for r in one + two)
    progress("engine3d: the 3D wedge's strength reduction")
    wedge = [answer_of_fresh_process(WEDGE_CODE, SOURCE, timeout_s, 1) for _ in range(repeats)]
    seconds = _median(wedge, "seconds")
    modules = answer_of_fresh_process(IMPORTS_2D, SOURCE, timeout_s)["modules"]
    rows += [
        (f"speedup_2_threads_{threads_blocks}", speedup, "1", "at least 1.6", speedup >= TARGET_SPEEDUP),
        (f"bitwise_1_2_threads_{threads_blocks}", float(same), "1", "1: identical", same),
        ("wedge_srm_s", seconds, "s", "under 30 s", seconds < TARGET_WEDGE_S),
        ("wedge_srm_fs", wedge[0]["factor_of_safety"], "1", "", None),
        ("dem3d_modules_in_a_2d_run", len(modules), "1", "none", not modules),
    ]
    return pd.DataFrame(rows, columns=["quantity", "value", "unit", "mark", "met"])
