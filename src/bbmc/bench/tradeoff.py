"""The speed-accuracy trade of the solver's knobs on the paper's scenes, measured.

Each knob is varied alone from the scene's own settings (its config's defaults); every setting is
compared with a converged reference run of the same scene (every knob at its accurate end), and the
reference itself with a run twice as fine (its own error, so the reference's convergence is shown, not
assumed). The error is `paper_scenes.relative_error` of what users read; the cost is the wall time of
the run, best of `repeats`, measured side by side in one process (ratios to the default setting's time
are what carry across machines). `resolved` is false where a run's error is not above the reference's
own error (closer to the reference than the reference is to its check: too close to tell).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, replace

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from bbmc.bench.paper_scenes import Knobs, PaperScene, Reading, relative_error

KNOBS = (
    "update_interval_steps",
    "safety_factor",
    "sub_contacts_per_edge",
    "damping",
    "density_scaling",
    "law_update_stress_change",
)
REFERENCES = ("reference", "reference_check")  # measured against each other, not on the front


def best_reading(scene: PaperScene, knobs: Knobs, repeats: int) -> Reading:
    """The scene's reading at `knobs`, with the least wall time of `repeats` runs (runs are deterministic,
    so only the time differs)."""
    readings = [scene.read(knobs) for _ in range(repeats)]
    return min(readings, key=lambda r: r.seconds)


def applies(scene: PaperScene, knob: str) -> bool:
    """The law updates matter only where a joint law depends on the stresses."""
    return knob not in ("update_interval_steps", "law_update_stress_change") or scene.stress_dependent


def settings(
    scene: PaperScene, values: dict[str, list], reference: dict, check: dict
) -> list[tuple[str, object, Knobs]]:
    """(knob, value, knobs) of every run: the default, each knob's values alone, the reference and
    its check (the reference with the overrides of `check`)."""
    default = scene.defaults()
    rows = [("default", None, default)]
    for knob in KNOBS:
        if applies(scene, knob):
            rows += [(knob, v, replace(default, **{knob: v})) for v in values[knob]]
    reference_knobs = replace(default, **reference)
    rows.append(("reference", None, reference_knobs))
    rows.append(("reference_check", None, replace(reference_knobs, **check)))
    return rows


def _label(value: float | None) -> str:
    return "" if value is None else f"{value:g}"


def _status(reading: Reading, reference: Reading) -> str:
    changed = [s for s, r in zip(reading.statuses, reference.statuses, strict=True) if s != r]
    return changed[0] if changed else "as the reference"


def scene_tradeoff(
    scene,
    values: dict[str, list],
    reference: dict,
    check: dict,
    repeats: int,
    progress: Callable[[str], None],
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """One row per setting (error, time, steps) and one row per thing read per setting."""
    runs = settings(scene, values, reference, check)
    scene.read(scene.defaults())  # warm-up: kernels loaded before any timing
    readings = {}
    for knob, value, knobs in runs:
        progress(f"{scene.name}: {knob} {'' if value is None else value}")
        once = knob in REFERENCES  # what it costs is not the point: how close it is
        readings[(knob, value)] = best_reading(scene, knobs, 1 if once else repeats)
    ref, default = readings[("reference", None)], readings[("default", None)]
    check_reading = readings[("reference_check", None)]
    rows, read = [], []
    for knob, value, knobs in runs:
        r = readings[(knob, value)]
        against = check_reading if knob == "reference" else ref
        rows.append(
            {
                "scene": scene.name,
                "what_is_read": scene.what,
                "knob": knob,
                "value": _label(value),
                **asdict(knobs),
                "seconds": r.seconds,
                "time_over_default": r.seconds / default.seconds,
                "steps": r.steps,
                "relative_error": relative_error(r, against),
                "error_measured_against": "reference_check" if knob == "reference" else "reference",
                "status": _status(r, against),
            }
        )
        read += [
            {
                "scene": scene.name,
                "knob": knob,
                "value": _label(value),
                "read": label,
                "value_mm": v * 1e3,
                "status": s,
            }
            for label, v, s in zip(scene.labels, r.values, r.statuses, strict=True)
        ]
    table = pd.DataFrame(rows)
    table["resolved"] = (
        table["relative_error"] > table.loc[table["knob"] == "reference", "relative_error"].iloc[0]
    )
    compared = ~table["knob"].isin(REFERENCES).to_numpy()
    front = np.zeros(len(table), dtype=bool)
    front[compared] = pareto_front(
        table["seconds"].to_numpy()[compared], table["relative_error"].to_numpy()[compared]
    )
    table["on_pareto_front"] = front
    return table, pd.DataFrame(read)


def pareto_front(seconds: np.ndarray, error: np.ndarray) -> np.ndarray:
    """True where no other run is at least as fast and at least as accurate, and better in one (runs with
    an infinite error, i.e. a changed outcome, are never on it)."""
    front = np.zeros(len(seconds), dtype=bool)
    for i in range(len(seconds)):
        if not math.isfinite(error[i]):
            continue
        dominated = (
            (seconds <= seconds[i]) & (error <= error[i]) & ((seconds < seconds[i]) | (error < error[i]))
        )
        front[i] = not dominated.any()
    return front


def timing_noise(table: pd.DataFrame) -> float:
    """The run-to-run spread of wall time in this run: the largest |time / default time - 1| of the knob
    runs whose settings are the default's (the same run timed again)."""
    spread = 0.0
    for _, rows in table.groupby("scene", sort=False):
        default = rows[rows["knob"] == "default"].iloc[0]
        again = rows[rows["knob"].isin(KNOBS)]
        same = np.ones(len(again), dtype=bool)
        for knob in KNOBS:
            same &= (again[knob] == default[knob]).to_numpy() | (again[knob].isna() & pd.isna(default[knob]))
        spread = max(
            spread, float(np.max(np.abs(again["time_over_default"].to_numpy()[same] - 1.0), initial=0.0))
        )
    return spread


def recommended(table: pd.DataFrame, target_error: float) -> pd.DataFrame:
    """For each scene and knob: the values within `target_error` of the reference, the fastest of them,
    and the recommendation: that fastest value if it is faster than the default setting by more than the
    timing noise (`timing_noise`), else the scene's own value if that is within the target, else none
    (no value of this knob alone reaches the target)."""
    noise = timing_noise(table)
    rows = []
    for (scene, knob), group in table[table["knob"].isin(KNOBS)].groupby(["scene", "knob"], sort=False):
        default = table[(table["scene"] == scene) & (table["knob"] == "default")].iloc[0]
        own = _label(default[knob]) if not pd.isna(default[knob]) else ""
        within = group[group["relative_error"] <= target_error]
        fastest = within.loc[within["seconds"].idxmin()] if len(within) else None
        gain = fastest is not None and fastest["time_over_default"] < 1.0 - noise
        if gain:
            choice = fastest["value"]
        elif default["relative_error"] <= target_error:
            choice = own or "off"
        else:
            choice = ""
        rows.append(
            {
                "scene": scene,
                "knob": knob,
                "target_error": target_error,
                "values_within_target": ", ".join(within["value"]),
                "fastest_within_target": "" if fastest is None else fastest["value"],
                "its_error": math.nan if fastest is None else fastest["relative_error"],
                "its_time_over_default": math.nan if fastest is None else fastest["time_over_default"],
                "timing_noise": noise,
                "measurably_faster": bool(gain),
                "recommended": choice,
            }
        )
    return pd.DataFrame(rows)


RUN_KINDS = ("default", *KNOBS, *REFERENCES)
MARKERS = dict(zip(RUN_KINDS, "*osD^v<PX", strict=True))
COLOURS = {kind: f"C{i}" for i, kind in enumerate(RUN_KINDS)}  # the same in every panel


def tradeoff_figure(table: pd.DataFrame, floor: float, dpi: int) -> Figure:
    """Error against wall time, one panel per scene, one marker per knob, the Pareto front drawn.
    Errors below `floor` (and exact zeros) are drawn at the floor."""
    scenes = list(dict.fromkeys(table["scene"]))
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.2 * len(scenes), 4.6), dpi=dpi, squeeze=False)
    for ax, scene in zip(axes[0], scenes, strict=True):
        rows = table[table["scene"] == scene]
        error = np.clip(rows["relative_error"].to_numpy(dtype=float), floor, None)
        for knob in dict.fromkeys(rows["knob"]):
            mine = (rows["knob"] == knob).to_numpy() & np.isfinite(error)
            ax.scatter(
                rows["seconds"][mine],
                error[mine],
                marker=MARKERS[knob],
                s=46,
                label=knob.replace("_", " "),
                color=COLOURS[knob],
            )
            for x, y, v in zip(rows["seconds"][mine], error[mine], rows["value"][mine], strict=True):
                if v:
                    ax.annotate(v, (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7)
        front = rows["on_pareto_front"].to_numpy(dtype=bool)
        order = np.argsort(rows["seconds"].to_numpy()[front])
        ax.step(
            rows["seconds"].to_numpy()[front][order],
            error[front][order],
            where="post",
            color="k",
            lw=1.0,
            label="Pareto front",
        )
        failed = int((~np.isfinite(rows["relative_error"].to_numpy(dtype=float))).sum())
        title = f"{scene}: {rows['what_is_read'].iloc[0]}"
        ax.set(
            xscale="log",
            yscale="log",
            xlabel="wall time of the run [s]",
            ylabel="relative error against the reference [-]",
            title=title + (f"\n({failed} runs changed outcome: not drawn)" if failed else ""),
        )
        ax.title.set_fontsize(9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    return fig
