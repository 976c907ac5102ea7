"""Make the example pit-wall survey: SYNTHETIC, UNLABELLED orientation readings drawn from known sets.

The files are not field data. They are a survey simulated here so that `bbmc kinematics` can be checked
against the truth it should recover (tests/test_kinematics_stage.py runs this script, compares its
output with the files in the repository byte for byte, and finds the sets again). Run it from anywhere:

    python data/field/make_pit_survey.py [OUT_FOLDER]

Two data sheets, as a mapping crew would hand them in, neither saying which set a reading belongs to:

* `pit_face_mapping.csv`: a horizontal scanline along the toe of a pit wall (face dip 65 deg towards
  180), trend 090, 150 m, the face reaching 8 m above the line and 1 m below it. Dip and dip direction,
  the position along the line, the visible trace length and its hidden ends, the type (bedding or
  joint), and the bench. The sets cross the line as `make_scanline_example.survey_set` draws them
  (Terzaghi's sampling bias included), and a tenth of the readings are random (poles uniform on the
  sphere, positions uniform, trace lengths exponential of mean 2 m).
* `pit_core.csv`: an oriented borehole drilled into the wall, trend 000, plunge 60 deg, 60 m, each
  fracture recorded as alpha and beta (alpha: the angle between the core axis and the plane; beta: from
  the bottom-of-hole reference line, clockwise looking down the hole, to the lowest point of the
  fracture's ellipse, the point furthest down the hole) with its depth along the hole.

Readings are rounded as a careful crew would: angles to the degree, lengths to the centimetre.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

SEED = 20261127
FACE_DIP_DEG, FACE_DIP_DIRECTION_DEG = 65.0, 180.0
SCANLINE_TREND_DEG, SCANLINE_LENGTH_M = 90.0, 150.0
HEIGHTS_M = (8.0, 1.0)  # the face above and below the scanline
HOLE_TREND_DEG, HOLE_PLUNGE_DEG, HOLE_LENGTH_M = 0.0, 60.0, 60.0
RANDOM_SHARE = 0.10  # of all readings of a sheet

# The truth: what bbmc kinematics should find again.
TRUTH = {
    "J1": {
        "dip_deg": 35.0,
        "dip_direction_deg": 165.0,
        "fisher_k": 50.0,
        "type": "bedding",
        "spacing_m": {"distribution": "exponential", "mean": 1.0},
        "trace_length_m": {"distribution": "lognormal", "mean": 6.0, "std": 3.0},
    },
    "J2": {
        "dip_deg": 60.0,
        "dip_direction_deg": 220.0,
        "fisher_k": 35.0,
        "type": "joint",
        "spacing_m": {"distribution": "lognormal", "mean": 1.5, "std": 0.7},
        "trace_length_m": {"distribution": "exponential", "mean": 4.0},
    },
    "J3": {
        "dip_deg": 55.0,
        "dip_direction_deg": 130.0,
        "fisher_k": 35.0,
        "type": "joint",
        "spacing_m": {"distribution": "exponential", "mean": 1.5},
        "trace_length_m": {"distribution": "exponential", "mean": 4.0},
    },
    "J4": {
        "dip_deg": 75.0,
        "dip_direction_deg": 10.0,
        "fisher_k": 60.0,
        "type": "joint",
        "spacing_m": {"distribution": "exponential", "mean": 0.8},
        "trace_length_m": {"distribution": "lognormal", "mean": 5.0, "std": 2.0},
    },
}


def _scanline_script():
    """The scanline example's script, whose drawing of a set along a line this survey reuses."""
    path = Path(__file__).with_name("make_scanline_example.py")
    spec = importlib.util.spec_from_file_location("make_scanline_example", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def random_rows(rng: np.random.Generator, count: int, length: float) -> list[tuple]:
    """`count` random readings: poles uniform on the sphere (turned up), positions uniform on the line,
    trace lengths exponential of mean 2 m, all seen whole. Rows as `survey_set` gives them."""
    z = rng.random(count)
    azimuth = 2.0 * np.pi * rng.random(count)
    dips = np.degrees(np.arccos(z))
    positions = length * rng.random(count)
    lengths = -2.0 * np.log1p(-rng.random(count))
    directions = np.degrees(azimuth) % 360.0
    return [
        ("random", p, d, a, s, 0) for p, d, a, s in zip(positions, dips, directions, lengths, strict=True)
    ]


def with_random(rng: np.random.Generator, rows: list[tuple], length: float) -> list[tuple]:
    """The sets' rows and as many random ones as make RANDOM_SHARE of the whole, sorted by position."""
    extra = round(len(rows) * RANDOM_SHARE / (1.0 - RANDOM_SHARE))
    return sorted(rows + random_rows(rng, extra, length), key=lambda r: r[1])


def core_angles(dip: np.ndarray, direction: np.ndarray, hole: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """alpha and beta [deg] of planes (dip, dip direction [deg]) cut by a hole of unit vector `hole`
    (down the hole). alpha = 90 - the angle between the hole and the pole. The reference line is the
    core's bottom line (the direction straight down, projected on the plane normal to the hole); beta
    is measured clockwise looking down the hole from it to the ellipse's lowest point, the direction in
    that plane in which the fracture lies furthest down the hole: the pole's projection on that plane,
    taken with the sense in which the plane advances down the hole (minus its component along it)."""
    s = _scanline_script()
    n = s.pole(np.radians(dip), np.radians(direction))
    cos_hole = n @ hole
    alpha = np.degrees(np.arcsin(np.clip(np.abs(cos_hole), 0.0, 1.0)))
    down = np.array([0.0, 0.0, -1.0])
    bottom = down - (down @ hole) * hole
    bottom /= np.linalg.norm(bottom)
    right = np.cross(hole, bottom)  # looking down the hole, clockwise from bottom turns towards here
    towards = -(n - cos_hole[:, None] * hole) * np.sign(cos_hole)[:, None]
    beta = np.degrees(np.arctan2(towards @ right, towards @ bottom)) % 360.0
    return alpha, beta


def face_sheet(rng: np.random.Generator) -> list[str]:
    s = _scanline_script()
    scanline = s.line(np.radians(SCANLINE_TREND_DEG), 0.0)
    face = s.pole(np.radians(FACE_DIP_DEG), np.radians(FACE_DIP_DIRECTION_DEG))
    rows = [
        row
        for name, truth in TRUTH.items()
        for row in s.survey_set(rng, name, truth, scanline, face, SCANLINE_LENGTH_M, HEIGHTS_M)
    ]
    rows = with_random(rng, rows, SCANLINE_LENGTH_M)
    lines = [
        "# SYNTHETIC face mapping, not field data: drawn from known sets by make_pit_survey.py",
        f"# (seed {SEED}; the truth is in that script). Scanline trend {SCANLINE_TREND_DEG:03.0f}, plunge 0, "
        f"{SCANLINE_LENGTH_M:g} m, along a face {FACE_DIP_DEG:g}/{FACE_DIP_DIRECTION_DEG:03.0f}.",
        "dip_deg,dip_direction_deg,position_m,trace_length_m,censored_ends,type,location",
    ]
    for name, position, dip, direction, length, censored in rows:
        kind = TRUTH[name]["type"] if name in TRUTH else "joint"
        bench = "bench 2" if position < SCANLINE_LENGTH_M / 2 else "bench 3"
        lines.append(
            f"{round(dip):d},{round(direction) % 360:d},{position:.2f},{length:.2f},{censored:d},{kind},{bench}"
        )
    return lines


def core_sheet(rng: np.random.Generator) -> list[str]:
    s = _scanline_script()
    hole = s.line(np.radians(HOLE_TREND_DEG), np.radians(HOLE_PLUNGE_DEG))
    rows = [
        row
        for name, truth in TRUTH.items()
        for row in s.survey_set(rng, name, truth, hole, hole, HOLE_LENGTH_M, (1e9, 1e9))
    ]
    rows = with_random(rng, rows, HOLE_LENGTH_M)
    dip = np.array([r[2] for r in rows])
    direction = np.array([r[3] for r in rows])
    alpha, beta = core_angles(dip, direction, hole)
    lines = [
        "# SYNTHETIC oriented core, not field data: drawn from known sets by make_pit_survey.py",
        f"# (seed {SEED}). Hole trend {HOLE_TREND_DEG:03.0f}, plunge {HOLE_PLUNGE_DEG:g}, "
        f"{HOLE_LENGTH_M:g} m; beta from the bottom-of-hole line, clockwise looking down the hole.",
        "depth_m,alpha_deg,beta_deg,type",
    ]
    for row, a, b in zip(rows, alpha, beta, strict=True):
        kind = TRUTH[row[0]]["type"] if row[0] in TRUTH else "joint"
        lines.append(f"{row[1]:.2f},{round(a):d},{round(b) % 360:d},{kind}")
    return lines


def make(folder: Path, seed: int = SEED) -> None:
    """Write both sheets drawn with `seed` into `folder`."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "pit_face_mapping.csv").write_text("\n".join(face_sheet(rng)) + "\n")
    (folder / "pit_core.csv").write_text("\n".join(core_sheet(rng)) + "\n")


if __name__ == "__main__":
    make(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent)
