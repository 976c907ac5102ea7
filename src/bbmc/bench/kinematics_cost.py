"""What the orientation analysis costs (kinematics_cost.csv), on one core, best of `repeats`:

* finding the sets in `readings` readings (BIC over 0 to 6 sets; a synthetic survey of four sets and
  10 % random readings, `bbmc.field.synthetic`), and their kinematic tally for one face (every pole
  mode; the line modes on the documented subsample of pairs above 5,000 readings);
* the compass sweep at 1 deg for a survey of `compass_readings` readings (all its pairs);
* the Monte Carlo of the modes' probabilities: orientation samples (poles drawn, each set's) per
  second, every pole and the lines of every pair of sets classified.

The issue's marks are printed beside each: 100,000 readings clustered and analysed in under 10 s,
the compass at 1 deg in under 2 s, and at least 1 M orientation samples per second.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
import pandas as pd

from bbmc.field.set_finding import find_sets
from bbmc.field.synthetic import KnownSet, synthetic_survey
from bbmc.geometry.orientation import poles as upward_poles
from bbmc.kinematics.compass import compass_sweep
from bbmc.kinematics.face import Face
from bbmc.kinematics.probabilistic import mode_probabilities
from bbmc.kinematics.tallies import kinematic_tally

FACE = Face(np.radians(65.0), np.radians(180.0))
FRICTION = np.radians(30.0)
SETS = ((35.0, 165.0, 50.0), (60.0, 220.0, 35.0), (55.0, 130.0, 35.0), (75.0, 10.0, 60.0))


def _survey(count: int, seed: int = 0) -> np.ndarray:
    per_set = round(0.9 * count / len(SETS))
    known = [KnownSet(np.radians(d), np.radians(a), k, per_set) for d, a, k in SETS]
    return synthetic_survey(known, count - per_set * len(SETS), np.random.default_rng(seed)).poles


def _best(action: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return min(times)


def kinematics_cost_table(
    readings: int, compass_readings: int, samples: int, repeats: int, progress: Callable[[str], None]
) -> pd.DataFrame:
    """The rows of kinematics_cost.csv: quantity, value, unit, and the issue's mark where it has one."""
    poles = _survey(readings)
    progress(f"kinematics: sets in {readings:,} readings and their tally")
    found = find_sets(poles)
    finding = _best(lambda: find_sets(poles), repeats)
    means = np.array([s.mean_pole for s in found.sets])
    tally = _best(lambda: kinematic_tally(poles, FACE, FRICTION, sets=found.labels, set_means=means), repeats)
    small = _survey(compass_readings, seed=1)
    progress(f"kinematics: the compass at 1 deg for {compass_readings} readings")
    around = _best(lambda: compass_sweep(small, FACE.dip, FRICTION), repeats)
    progress(f"kinematics: {samples:,} Monte Carlo draws per set")
    kappas = [k for _, _, k in SETS]
    true_means = upward_poles(np.radians([d for d, _, _ in SETS]), np.radians([a for _, a, _ in SETS]))
    draws = _best(lambda: mode_probabilities(true_means, kappas, FACE, FRICTION, samples=samples), repeats)
    rows = [
        ("readings", readings, "1", ""),
        ("sets_found", len(found.sets), "1", ""),
        ("set_finding_time", finding, "s", ""),
        ("tally_time", tally, "s", ""),
        ("sets_and_tally_time", finding + tally, "s", "under 10 s"),
        ("compass_readings", compass_readings, "1", ""),
        ("compass_1deg_time", around, "s", "under 2 s"),
        ("orientation_samples_per_second", samples * len(SETS) / draws, "1/s", "at least 1e6"),
    ]
    return pd.DataFrame(rows, columns=["quantity", "value", "unit", "mark"])
