"""Scaling of the block engine on generated jointed slopes: time per step and peak memory against
the number of blocks (results/bench/scaling.csv and its figure).

Each system is the slope of a `bbmc slope` config (configs/slope.yaml: the paper's section 5, 34
blocks) with every joint set's spacing shrunk by the same factor, so that the generator cuts about the
number of blocks asked (`spacing_scale`; the count is not exact, the table gives the actual one). Its
joints are the config's constant Mohr-Coulomb joints (Table 4, read from the config's data files), its
run settings the config's (`run`: damping, safety factor, sub-contacts per edge), built by
`bbmc.slope.model.slope_scene`.

Each size runs in a fresh Python process, so that its peak resident set size (VmHWM on Linux, else
ru_maxrss: both see numba's and numpy's allocations as well as Python's) is its own. The table also
gives the peak of a process that only imports bbmc and loads the compiled kernels (on the paper slope
itself, `BASELINE_BLOCKS`), and each size's peak above it. Times are wall-clock on one core: the generation
and the model's build once, the contact search at step 0 (`prepare`) and the cycles (`advance`, including
every contact search they trigger) best of the repeats. Compare ratios between sizes, not absolute
numbers across machines.
"""

from __future__ import annotations

import functools
import json
import math
import os
import resource
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from bbmc.dem import layout as L
from bbmc.dem.model import build_model
from bbmc.dem.solver import advance, prepare
from bbmc.dem.state import State
from bbmc.geometry import polygons
from bbmc.scene.schema import JointedSlope, Scene
from bbmc.slope import model as sm
from bbmc.slope.config import load_paper_slope

if TYPE_CHECKING:
    from matplotlib.figure import Figure

BASELINE_BLOCKS = 34  # the paper slope: the baseline process loads every kernel on it
CALIBRATION_SCALE = 1.0 / 3.0  # the second spacing factor at which the block count is calibrated
NLOGN_SLACK = 1.5  # within_NlogN: cost / (N log N) at most this many times the smallest size's
MEMORY_MARGIN = 1.5  # a size's peak above the baseline is estimated this much above the extrapolation
MEMORY_RESOLUTION_MB = 2.0  # peaks above the baseline smaller than this are noise (allocator arenas,
# pages): no growth exponent is read from them
MB = 1.0e6
MAXRSS_BYTES = 1 if sys.platform == "darwin" else 1024  # ru_maxrss is in bytes on macOS, kB on Linux


@functools.cache
def _paper_slope(slope_config: str) -> tuple[JointedSlope, float, dict, sm.Run]:
    """The slope, rock density [kg/m3], constant joint-law entry and run settings of a slope config."""
    config, table4 = load_paper_slope(slope_config)
    law = sm.joint_law("constant", table4, config.constant, config.barton_bandis)
    return config.slope, table4.density_kg_m3, law, config.run


def _slope(slope_config: str, scale: float) -> JointedSlope:
    slope = _paper_slope(slope_config)[0]
    sets = [s.model_copy(update={"spacing_m": s.spacing_m * scale}) for s in slope.joint_sets]
    return slope.model_copy(update={"joint_sets": sets})


def _block_count(slope_config: str, scale: float) -> int:
    slope = _slope(slope_config, scale).model_dump()
    return len(polygons.jointed_slope(**{k: v for k, v in slope.items() if k != "fixed_boundaries"}))


@functools.cache
def _count_law(slope_config: str) -> tuple[float, float]:
    """(a, b) of count(s) = a / s^2 + b / s for spacings scaled by s: whole cells fill the profile's
    area (a), cut cells along its boundary add a term in its perimeter (b); fitted through the counts
    at s = 1 (the paper's slope) and s = CALIBRATION_SCALE."""
    s1, s2 = 1.0, CALIBRATION_SCALE
    n1, n2 = _block_count(slope_config, s1), _block_count(slope_config, s2)
    u1, u2 = 1 / s1, 1 / s2  # n1 = a u1^2 + b u1, n2 = a u2^2 + b u2
    a = (n2 * u1 - n1 * u2) / (u2 * u2 * u1 - u1 * u1 * u2)
    b = (n1 - a * u1 * u1) / u1
    return a, b


def spacing_scale(blocks: int, slope_config: str) -> float:
    """The factor on the config slope's joint spacings that gives about `blocks` blocks."""
    if blocks < 1:
        raise ValueError(f"blocks must be at least 1, got {blocks}")
    a, b = _count_law(slope_config)
    inverse = (-b + math.sqrt(b * b + 4 * a * blocks)) / (2 * a)  # a u^2 + b u = blocks, u = 1 / s
    return 1.0 / inverse


def scaled_slope(blocks: int, slope_config: str) -> dict:
    """The scene (a dict in the scene format) of the config's slope cut into about `blocks` blocks."""
    scale = spacing_scale(blocks, slope_config)
    _, density, law, run = _paper_slope(slope_config)
    scene = sm.slope_scene(f"scaled_slope_{blocks}", _slope(slope_config, scale), density, law, run, [])
    scene["description"] = (
        f"The paper's jointed slope (bbmc slope) with joint spacings x {scale:.4g}: about {blocks} blocks."
    )
    return scene


def _peak_rss_bytes() -> float:
    """This process's peak resident set size [bytes]: VmHWM of /proc/self/status where there is one
    (Linux), else ru_maxrss. Not ru_maxrss on Linux: it keeps the parent's peak across fork and exec,
    so a process started by a larger one (pytest, a stage) would report the parent's size."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return float(line.split()[1]) * 1024  # kB
    except OSError:
        pass
    return float(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * MAXRSS_BYTES)


def measure_here(
    blocks: int, steps: int, repeats: int, min_timed_s: float, slope_config: str, threads: int | None = None
) -> dict:
    """`measure`, in this process (its peak RSS is this process's peak so far), on `threads` threads
    (None: the scene's default, every core).

    The cycles are repeated at least `repeats` times, and more (up to 100) while less than
    `min_timed_s` of cycles has been timed, each repeat from a fresh `prepare`; the best is kept."""
    _run_kernels(slope_config)  # load every compiled kernel first: the first timed search would include it
    entry = scaled_slope(blocks, slope_config)  # the block count's calibration is not timed
    entry["solver"]["threads"] = threads
    start = time.perf_counter()
    model = build_model(Scene.model_validate(entry, strict=False), Path(f"<slope of about {blocks} blocks>"))
    build_s = time.perf_counter() - start
    peak_after_build = _peak_rss_bytes()
    best_search, best_cycles, timed, runs = math.inf, math.inf, 0.0, 0
    while runs < repeats or (timed < min_timed_s and runs < 100):
        start = time.perf_counter()
        state = prepare(model)
        searched = time.perf_counter()
        advance(model, state, steps)
        done = time.perf_counter()
        best_search, best_cycles = min(best_search, searched - start), min(best_cycles, done - searched)
        timed, runs = timed + done - searched, runs + 1
        run = _run_counts(state)
        del state  # a run holds one state: the next `prepare` must not build its own beside this one
    return {
        "blocks_asked": blocks,
        "blocks": len(model.block_names),
        "free_blocks": int(np.sum(~np.all(model.dof == L.PRESCRIBED, axis=1))),
        "spacing_scale": spacing_scale(blocks, slope_config),
        **run,
        "steps": steps,
        "timed_runs": runs,
        "generation_and_build_s": build_s,
        "initial_search_s": best_search,
        "cycles_s": best_cycles,
        "seconds_per_step": best_cycles / steps,
        "sub_contact_updates_per_s": run["sub_contacts"] * steps / best_cycles,
        "peak_rss_after_build_MB": peak_after_build / MB,
        "peak_rss_MB": _peak_rss_bytes() / MB,
    }


def _run_counts(state: State) -> dict:
    """What a run's state at its end tells the table: threads, contacts, sub-contacts (and those with a
    length), the smallest time step [s] and the contact searches after step 0."""
    return {
        "threads": state.threads,
        "contacts": len(state.contacts),
        "sub_contacts": len(state.subs),
        "active_sub_contacts": int(np.sum(state.subs[:, L.LENGTH] > 0)),
        "time_step_s": float(state.dt_range[0]),
        "contact_searches_during_cycles": state.searches - 1,
    }


def _run_kernels(slope_config: str) -> None:
    """A few cycles of the config's slope: every kernel a run uses is compiled or loaded from the cache."""
    scene = Scene.model_validate(scaled_slope(BASELINE_BLOCKS, slope_config), strict=False)
    model = build_model(scene, Path("<the paper slope>"))
    advance(model, prepare(model), 10)


def baseline_here(slope_config: str) -> dict:
    """The peak RSS of a process that imports bbmc and runs the kernels on the config's slope."""
    _run_kernels(slope_config)
    return {"baseline_rss_MB": _peak_rss_bytes() / MB}


def answer_of_fresh_process(
    code: str, source: Path, timeout_s: float | None, threads: int | None = None
) -> dict:
    """Run `code` in a fresh interpreter that imports bbmc from `source` (a src/ folder) first, with at
    most `threads` numba threads (None: every core); its JSON answer (the last line it prints)."""
    env = dict(os.environ)
    if threads is not None:
        env["NUMBA_NUM_THREADS"] = str(threads)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(source), env.get("PYTHONPATH")) if p)
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout_s, env=env, check=False
    )
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        error = (done.stderr.strip().splitlines() or [f"exit status {done.returncode}"])[-1]
        raise RuntimeError(f"a fresh process failed (exit status {done.returncode}): {error}")
    return json.loads(lines[-1])


def _in_subprocess(call: str, timeout_s: float | None) -> dict:
    """Run `bbmc.bench.scaling.<call>` in a fresh interpreter; its JSON answer (the last line printed)."""
    code = f"import json\nfrom bbmc.bench import scaling\nprint(json.dumps(scaling.{call}))"
    source = Path(__file__).resolve().parents[2]  # src/: the package, whether installed or not
    try:
        return answer_of_fresh_process(code, source, timeout_s)
    except RuntimeError as error:
        raise RuntimeError(f"scaling.{call} failed: {error}") from None


def measure(
    blocks: int,
    steps: int,
    repeats: int,
    slope_config: str,
    min_timed_s: float = 0.5,
    timeout_s: float | None = 3600.0,
    threads: int = 1,
) -> dict:
    """Generate, build and run a scaled slope of about `blocks` blocks in a fresh process on `threads`
    threads: blocks, contacts, sub-contacts, times (generation and build, contact search at step 0,
    `steps` cycles best of `repeats`), contact searches during the cycles, and the process's peak RSS
    [MB = 1e6 bytes]."""
    return _in_subprocess(
        f"measure_here({int(blocks)}, {int(steps)}, {int(repeats)}, {min_timed_s!r}, {str(slope_config)!r}, "
        f"{int(threads)})",
        timeout_s,
    )


def baseline(slope_config: str, timeout_s: float | None = 600.0) -> float:
    """Peak RSS [MB] of a fresh process that imports bbmc and loads and runs the compiled kernels."""
    return _in_subprocess(f"baseline_here({str(slope_config)!r})", timeout_s)["baseline_rss_MB"]


def estimated_peak_MB(rows: list[dict], blocks: int, baseline_MB: float) -> float:
    """A size's peak RSS [MB] estimated from the sizes measured before it: the largest one's peak
    above the baseline grown as N^p, p the growth exponent of the peak above the baseline between the
    last two sizes (clipped to [1, 2]; 1 while either is under MEMORY_RESOLUTION_MB), times
    MEMORY_MARGIN; NaN before any size is measured."""
    if not rows:
        return math.nan
    last = rows[-1]
    above = max(last["peak_rss_MB"] - baseline_MB, 0.0)
    exponent = 1.0
    if len(rows) > 1:
        before = rows[-2]
        above_before = before["peak_rss_MB"] - baseline_MB
        if min(above, above_before) >= MEMORY_RESOLUTION_MB and last["blocks"] > before["blocks"]:
            ratio = math.log(above / above_before) / math.log(last["blocks"] / before["blocks"])
            exponent = min(max(ratio, 1.0), 2.0)
    return baseline_MB + MEMORY_MARGIN * above * (blocks / last["blocks"]) ** exponent


def scaling_table(
    block_counts: list[int],
    steps: int,
    repeats: int,
    memory_limit_bytes: float,
    slope_config: str,
    min_timed_s: float = 0.5,
    progress=None,
    threads: Sequence[int] = (1,),
) -> pd.DataFrame:
    """One row per size (ascending) and thread count (`threads`, the first the reference), each measured
    in its own process (`measure`), the same `steps` cycles from the same state at rest for every size.

    A size whose estimated peak (`estimated_peak_MB`) is above `memory_limit_bytes`, or whose process
    fails, gets a row with the reason in `skipped` and no measurements. Derived columns, over the
    measured rows: growth_exponent_vs_previous = log(t / t_prev) / log(N / N_prev) of the seconds
    per step (1 is linear), cost_over_NlogN_relative = (t / (N ln N)) / (t_0 / (N_0 ln N_0)) against
    the smallest size, within_NlogN = that ratio <= NLOGN_SLACK, and memory_growth_exponent, the same
    exponent for the peak RSS above the baseline (NaN where either is under MEMORY_RESOLUTION_MB), each
    among the rows of one thread count; speedup_vs_first_threads, the seconds per step on the first
    thread count over this row's, at the same size. `progress(message)` is called before each process."""
    say = progress or (lambda message: None)
    slope_config = str(Path(slope_config).resolve())  # the processes may run elsewhere
    _run_kernels(slope_config)  # compiles and caches the kernels if need be, here: the processes load them
    say("scaling: baseline process (bbmc imported, kernels loaded)")
    baseline_MB = baseline(slope_config)
    rows, measured = [], []
    for blocks in sorted(block_counts):
        estimate = estimated_peak_MB(measured, blocks, baseline_MB)
        for count in threads:
            row = {
                "blocks_asked": blocks,
                "threads_asked": count,
                "estimated_peak_rss_MB": estimate,
                "skipped": "",
            }
            if estimate * MB > memory_limit_bytes:
                row["skipped"] = (
                    f"estimated peak {estimate:.0f} MB above the limit {memory_limit_bytes / MB:.0f} MB"
                )
            else:
                say(f"scaling: about {blocks} blocks, {steps} steps, {count} thread(s)")
                try:
                    result = measure(blocks, steps, repeats, slope_config, min_timed_s, threads=count)
                except (RuntimeError, subprocess.TimeoutExpired) as error:
                    row["skipped"] = str(error).splitlines()[0]
                else:
                    row.update(result)
                    if count == threads[0]:
                        measured.append(result)
            rows.append(row)
    table = pd.DataFrame(rows)
    table["baseline_rss_MB"] = baseline_MB
    table["peak_rss_above_baseline_MB"] = table.get("peak_rss_MB", np.nan) - baseline_MB
    parts = [_derived(part.copy()) for _, part in table.groupby("threads_asked", sort=False)]
    table = pd.concat(parts).sort_index()
    first = table[table["threads_asked"] == threads[0]].set_index("blocks_asked")["seconds_per_step"]
    table["speedup_vs_first_threads"] = table["blocks_asked"].map(first) / table["seconds_per_step"]
    return table


def _measured(table: pd.DataFrame) -> pd.Series:
    """The rows measured: no skip reason (empty, or NaN once read back from a CSV)."""
    return table["skipped"].fillna("") == ""


def _derived(table: pd.DataFrame) -> pd.DataFrame:
    """The growth columns (see `scaling_table`), NaN on skipped rows."""
    for column in ("growth_exponent_vs_previous", "cost_over_NlogN_relative", "memory_growth_exponent"):
        table[column] = np.nan
    table["within_NlogN"] = False
    done = table.index[_measured(table)]
    if len(done) == 0:
        return table
    cost = table.loc[done, "seconds_per_step"].to_numpy(dtype=float)
    n = table.loc[done, "blocks"].to_numpy(dtype=float)
    memory = table.loc[done, "peak_rss_above_baseline_MB"].to_numpy(dtype=float)
    log_n = np.log(n[1:] / n[:-1])
    table.loc[done, "growth_exponent_vs_previous"] = np.concatenate(
        [[np.nan], np.log(cost[1:] / cost[:-1]) / log_n]
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        positive = np.where(memory >= MEMORY_RESOLUTION_MB, memory, np.nan)
        table.loc[done, "memory_growth_exponent"] = np.concatenate(
            [[np.nan], np.log(positive[1:] / positive[:-1]) / log_n]
        )
    per_nlogn = cost / (n * np.log(n))
    table.loc[done, "cost_over_NlogN_relative"] = per_nlogn / per_nlogn[0]
    table.loc[done, "within_NlogN"] = per_nlogn / per_nlogn[0] <= NLOGN_SLACK
    return table


def _references(ax, n: np.ndarray, n0: float, y0: float, anchor: str) -> None:
    """Lines of slope N and N log N through (n0, y0)."""
    grid = np.geomspace(n.min(), n.max(), 50)
    ax.plot(grid, y0 * grid / n0, "k:", lw=1, label=f"∝ N (through the {anchor})")
    ax.plot(grid, y0 * grid * np.log(grid) / (n0 * math.log(n0)), "k--", lw=1, label="∝ N log N")


def scaling_figure(table: pd.DataFrame, dpi: int = 120) -> Figure:
    """Log-log: the time per step (and the contact search at step 0) against the number of blocks,
    and the peak RSS (total and above the baseline process), with N and N log N reference lines
    through the smallest size (for the memory, the smallest at least MEMORY_RESOLUTION_MB above the
    baseline: below, the peak is noise)."""
    from matplotlib.figure import Figure  # here: the measuring processes need no matplotlib

    measured = table[_measured(table)]
    if measured.empty:
        raise ValueError("no size of the scaling table was measured: nothing to plot")
    groups = dict(tuple(measured.groupby("threads", sort=True)))
    done = next(iter(groups.values()))  # the fewest threads: the reference
    n = done["blocks"].to_numpy(dtype=float)
    fig = Figure(figsize=(11, 4.5), dpi=dpi, layout="constrained")
    time_ax, memory_ax = fig.subplots(1, 2)
    seconds = done["seconds_per_step"].to_numpy(dtype=float)
    for count, rows in groups.items():
        label = f"cycle (per step), {count} thread{'s' if count > 1 else ''}"
        time_ax.plot(rows["blocks"], rows["seconds_per_step"] * 1e3, "o-", label=label)
    time_ax.plot(
        n, done["initial_search_s"].to_numpy(dtype=float) * 1e3, "s-", label="contact search at step 0"
    )
    _references(time_ax, n, n[0], seconds[0] * 1e3, "smallest size")
    time_ax.set(xscale="log", yscale="log", xlabel="blocks [1]", ylabel="wall-clock time [ms]")
    time_ax.set_title("Time per step")
    above = done["peak_rss_above_baseline_MB"].to_numpy(dtype=float)
    memory_ax.plot(n, done["peak_rss_MB"].to_numpy(dtype=float), "o-", label="peak RSS")
    resolved = np.where(above >= MEMORY_RESOLUTION_MB, above, np.nan)  # below: noise, or negative
    memory_ax.plot(
        n, resolved, "s-", label=f"peak RSS above the baseline process (where ≥ {MEMORY_RESOLUTION_MB:g} MB)"
    )
    memory_ax.axhline(
        done["baseline_rss_MB"].iloc[0],
        color="0.6",
        lw=1,
        label="baseline process (bbmc imported, kernels loaded)",
    )
    first = np.flatnonzero(above >= MEMORY_RESOLUTION_MB)
    if len(first):
        _references(memory_ax, n, n[first[0]], above[first[0]], "smallest size shown")
    memory_ax.set(xscale="log", yscale="log", xlabel="blocks [1]", ylabel="resident set size [MB]")
    memory_ax.set_title("Peak memory (peak resident set size of the process)")
    for ax in (time_ax, memory_ax):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    return fig
