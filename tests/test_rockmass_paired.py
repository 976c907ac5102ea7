"""Paired realizations (`bbmc.rockmass.traces`, docs/rock-mass.md): one seed draws one joint network in
world coordinates, whatever profile cuts it, so studies over a face angle, a bench width or a height
compare like with like (common random numbers)."""

from __future__ import annotations

import copy
import pathlib

import numpy as np
import pandas as pd
import pytest
import yaml
from matplotlib.path import Path

from bbmc.rockmass import RockMassConfig, generate
from test_rockmass import _raw

ROOT = pathlib.Path(__file__).resolve().parents[1]
PROFILES = {
    "face 60": {"face_angle_deg": 60},
    "face 70": {"face_angle_deg": 70},
    "face 80": {"face_angle_deg": 80},
    "berm 8 m": {"berm_width_m": 8},
    "benches 14 m": {"height_m": 14},
}


def _mass(seed: int, **benches):
    raw = _raw()
    raw["profile"]["benches"] = {**raw["profile"]["benches"], **benches}
    return generate(RockMassConfig.model_validate(raw), seed)


def _lines(mass) -> pd.DataFrame:
    return mass.lines.set_index(["set", "line"])[["position_m", "apparent_dip_deg"]]


def _inside(outline: np.ndarray, start: np.ndarray, end: np.ndarray) -> bool:
    """Whether the segment lies inside the body (50 points along it, 1 mm in from the outline)."""
    points = start + np.linspace(0, 1, 50)[:, None] * (end - start)
    return bool(Path(outline).contains_points(points, radius=-1e-3).all())


@pytest.mark.parametrize("seed", [1, 4])
def test_one_seed_gives_the_same_lines_dips_and_traces_whatever_the_profile(seed):
    masses = {name: _mass(seed, **benches) for name, benches in PROFILES.items()}
    reference = masses["face 70"]
    for name, mass in masses.items():
        lines, expected = _lines(mass), _lines(reference)
        shared = lines.index.intersection(expected.index)
        assert len(shared) > 0.8 * min(len(lines), len(expected)), name
        pd.testing.assert_frame_equal(lines.loc[shared], expected.loc[shared], check_exact=True)
        # a whole trace (both ends in the body) that lies inside the other body too is a whole trace there,
        # with the same ends: the traces and the bridges between them are drawn along the line in world
        # coordinates, not from where the line enters the body
        theirs = reference.traces[~reference.traces["censored"]]
        ends = {(row.set, row.line): set() for row in theirs.itertuples()}
        for row in theirs.itertuples():
            ends[(row.set, row.line)].add(
                (round(row.x0_m, 9), round(row.y0_m, 9), round(row.x1_m, 9), round(row.y1_m, 9))
            )
        compared = 0
        for row in mass.traces[~mass.traces["censored"]].itertuples():
            start, end = np.array([row.x0_m, row.y0_m]), np.array([row.x1_m, row.y1_m])
            if not _inside(reference.outline, start, end):
                continue
            key = (round(row.x0_m, 9), round(row.y0_m, 9), round(row.x1_m, 9), round(row.y1_m, 9))
            assert key in ends.get((row.set, row.line), set()), (name, row)
            compared += 1
        assert compared > 50, name


def test_the_issues_example_bedding_lies_at_the_same_place_at_every_face_angle():
    scene = yaml.safe_load(
        (ROOT / "configs" / "scenes" / "benched_rock_mass.yaml").read_text(encoding="utf-8")
    )
    raw = scene["blocks"][0]["rock_mass"] | {"seed": 1}
    found = {}
    for angle in (60, 70, 80):
        changed = copy.deepcopy(raw)
        changed["profile"]["benches"]["face_angle_deg"] = angle
        mass = generate(RockMassConfig.model_validate(changed))
        bedding = mass.lines[mass.lines["set"] == "bedding"].set_index("line")
        found[angle] = bedding[["position_m", "apparent_dip_deg"]]
    for angle in (60, 80):
        shared = found[angle].index.intersection(found[70].index)
        assert len(shared) >= 5
        pd.testing.assert_frame_equal(found[angle].loc[shared], found[70].loc[shared], check_exact=True)


def test_two_seeds_draw_different_networks():
    first, second = _lines(_mass(1)), _lines(_mass(2))
    shared = first.index.intersection(second.index).drop(
        [(name, 0) for name in ("bedding", "cross", "steep")]
    )
    assert len(shared) > 20  # line 0 of each set lies at its offset whatever the seed
    assert not np.any(
        first.loc[shared, "position_m"].to_numpy() == second.loc[shared, "position_m"].to_numpy()
    )
    bedding = [key for key in shared if key[0] == "bedding"]
    assert not np.any(
        first.loc[bedding, "apparent_dip_deg"].to_numpy()
        == second.loc[bedding, "apparent_dip_deg"].to_numpy()
    )


def test_the_lines_are_laid_from_the_origin():
    persistent = {"name": "cross", "dip_deg": 70, "dip_direction_to_face_deg": 180, "spacing_m": 3.0}
    masses = {}
    for origin in (None, [0.0, 0.0], [7.5, 4.0]):
        raw = _raw(joint_sets=[persistent], origin_m=origin)
        masses[str(origin)] = mass = generate(RockMassConfig.model_validate(raw))
        line = mass.traces[mass.traces["line"] == 0].iloc[0]
        along = np.array([line.x1_m - line.x0_m, line.y1_m - line.y0_m])
        to_origin = np.array(origin or [0.0, 0.0]) - np.array([line.x0_m, line.y0_m])
        assert abs(along[0] * to_origin[1] - along[1] * to_origin[0]) < 1e-9 * np.hypot(*along)  # through it
    pd.testing.assert_frame_equal(masses["None"].traces, masses["[0.0, 0.0]"].traces)  # default: the toe
