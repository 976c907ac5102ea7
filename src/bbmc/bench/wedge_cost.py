"""What the wedge analysis costs (wedge_cost.csv), on one core: each repeat a fresh process with numba's
pool capped at one thread (NUMBA_NUM_THREADS=1), every quantity the median of the repeats, each process
warmed up (numba's kernels loaded) before it times anything:

* one deterministic wedge: `cases.analyse_case` on the wedge of `wedge_config` (Hoek & Bray's classic
  wedge in configs/wedge.yaml), its setting and planes built as `bbmc wedge` builds them; the time per
  call over `calls` calls;
* the combination analysis of the ten joint sets of `SETS` (45 pairs) against that config's slope,
  loads and water: `combinations.combination_table`, the time of one table;
* probabilistic samples per second: `samples` samples of the study `study_config` (the classic wedge
  of configs/sweeps/classic_wedge.yaml), its design drawn up front as `bbmc sweep` draws it, through its
  wedge base (`bbmc.sweep.wedge_model`: each sample's planes drawn by Fisher's K from its own uniforms,
  the wedge analysed by the compiled fast path, the sample's outcome row), one batch of all the samples;
  and the analysis alone (`probability.wedge_probability`) of as many wedges of the study's base, their
  planes drawn up front (`PlaneScatter.sample`), the strengths and water at the base's values per sample.

The issue's marks are written beside each (issue 35: a deterministic wedge under 1 ms, every pair of 10
sets under 1 s, at least 1 M probabilistic samples per second per core), and `met` says whether the
median meets its mark.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc.bench.scaling import answer_of_fresh_process
from bbmc.config import load_config
from bbmc.slope.wedge import config as wedge_keys
from bbmc.slope.wedge.analysis import WedgeOrientations
from bbmc.slope.wedge.cases import Plane, WedgeSetting, analyse_case
from bbmc.slope.wedge.combinations import combination_table
from bbmc.slope.wedge.mechanics import MohrCoulomb
from bbmc.slope.wedge.probability import PlaneScatter, wedge_probability
from bbmc.sweep import study
from bbmc.sweep.config import Config

SOURCE = Path(__file__).resolve().parents[2]  # src/: the package, whether installed or not
# Ten joint sets (dip, dip direction) [deg], the classic wedge's two planes first, spread about the face
# (65/185) so that most pairs form a wedge; cohesionless at phi 30 deg.
SETS = (
    (45, 105), (70, 235), (36, 161), (60, 217), (55, 129),
    (77, 13), (50, 150), (65, 260), (40, 200), (80, 90),
)  # fmt: skip
FRICTION_DEG = 30.0
# quantity: (unit, mark, whether the value meets it)
MARKS: dict[str, tuple[str, str, Callable[[float], bool] | None]] = {
    "wedge_ms": ("ms", "under 1 ms", lambda v: v < 1.0),
    "combination_pairs": ("1", "", None),
    "combinations_formed": ("1", "", None),
    "combinations_ms": ("ms", "under 1000 ms", lambda v: v < 1000.0),
    "samples": ("1", "", None),
    "samples_per_second": ("1/s", "at least 1e6", lambda v: v >= 1e6),
    "analysis_samples_per_second": ("1/s", "at least 1e6", lambda v: v >= 1e6),
}


def _seconds(action: Callable[[], object]) -> float:
    start = time.perf_counter()
    action()
    return time.perf_counter() - start


def _deterministic(slope: WedgeSetting, planes: tuple[Plane, Plane], calls: int) -> dict[str, float]:
    strength = MohrCoulomb(0.0, np.radians(FRICTION_DEG))
    sets = {
        f"S{k + 1}": Plane(np.radians(dip), np.radians(direction), lambda _, s=strength: s)
        for k, (dip, direction) in enumerate(SETS)
    }
    analyse_case(slope, *planes)
    table = combination_table(slope, sets)
    return {
        "wedge_ms": 1e3 * _seconds(lambda: [analyse_case(slope, *planes) for _ in range(calls)]) / calls,
        "combination_pairs": len(table),
        "combinations_formed": sum(row.forms for row in table),
        "combinations_ms": 1e3 * _seconds(lambda: combination_table(slope, sets)),
    }


def _probabilistic(study_config: str, samples: int) -> dict[str, float]:
    path = Path(study_config)
    config = load_config(path, Config)
    config = config.model_copy(update={"sampling": config.sampling.model_copy(update={"samples": samples})})
    ranges = study.check_paths(config, path, None)
    inputs, _ = study.design_of(config, path, study.inputs_of(config, path, ranges))
    model = study.model_of(config, None)
    model(inputs.iloc[:100])
    whole = _seconds(lambda: model(inputs))
    b, n, rng = config.base, len(inputs), np.random.default_rng(0)
    planes = (b.plane_1, b.plane_2)
    drawn = [
        PlaneScatter(np.radians(p.dip_deg), np.radians(p.dip_direction_deg), p.fisher_k).sample(n, rng)
        for p in planes
    ]
    surfaces = [np.radians([s.dip_deg, s.dip_direction_deg]) for s in (b.face, b.upper_surface)]
    orientations = WedgeOrientations(*drawn[0], *drawn[1], *surfaces[0], *surfaces[1])
    strengths = [p.plane_strength(0.0) for p in planes]  # the base's strengths: the analysis alone
    loads = {
        "height_h1": b.height_h1_m,
        "height_h": b.height_m,
        "overhanging_face": b.face.overhanging,
        "unit_weight": b.unit_weight_kN_m3 * 1e3,
        "water": b.water.water(),
        "water_unit_weight": float(wedge_keys.water_unit_weight(b.water)),
    }
    analysis = _seconds(lambda: wedge_probability(orientations, *strengths, **loads))
    return {"samples": n, "samples_per_second": n / whole, "analysis_samples_per_second": n / analysis}


def measure_here(
    slope: WedgeSetting, planes: tuple[Plane, Plane], study_config: str, calls: int, samples: int
) -> dict[str, float]:
    """One repeat's readings, in this process, of the wedge of `planes` in `slope` and of the study
    `study_config` (`wedge_cost_table` runs it in fresh ones)."""
    return _deterministic(slope, planes, calls) | _probabilistic(study_config, samples)


def wedge_cost_table(
    wedge_config: Path,
    study_config: Path,
    calls: int,
    samples: int,
    repeats: int,
    progress: Callable[[str], None],
    timeout_s: float | None = 3600.0,
) -> pd.DataFrame:
    """The rows of wedge_cost.csv: quantity, its median over `repeats` fresh processes on one thread,
    unit, the issue's mark where it has one and whether the median meets it (module docstring)."""
    # the measured process builds the wedge as `bbmc wedge` does, with the stage's own functions: a
    # stage sits above bbmc.bench, so only the code run in that process imports it
    code = (
        "import json\nfrom bbmc.bench import wedge_cost\nfrom bbmc.config import load_config\n"
        "from bbmc.stages import wedge as stage\n"
        f"config = load_config({str(wedge_config)!r}, stage.Config)\n"
        "planes = (stage.plane(config.plane_1), stage.plane(config.plane_2))\n"
        f"print(json.dumps(wedge_cost.measure_here(stage.setting(config), planes, {str(study_config)!r}, "
        f"{calls}, {samples})))"
    )
    readings = []
    for k in range(repeats):
        progress(f"wedge: one wedge, 10 sets' pairs and {samples:,} samples, fresh process {k + 1}/{repeats}")
        readings.append(answer_of_fresh_process(code, SOURCE, timeout_s, threads=1))
    rows = []
    for quantity, (unit, mark, meets) in MARKS.items():
        value = statistics.median(r[quantity] for r in readings)
        rows.append((quantity, value, unit, mark, meets(value) if meets else None))
    return pd.DataFrame(rows, columns=["quantity", "value", "unit", "mark", "met"])
