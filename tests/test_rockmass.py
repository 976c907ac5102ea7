"""The rock mass generator (`bbmc.rockmass`): profiles, joint sets drawn from their statistics, convex
labelled blocks. The statistics are checked over many realizations with Kolmogorov-Smirnov tests at a
significance of 0.001 (fixed seeds: the outcome is the same on every run)."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from matplotlib.collections import LineCollection
from scipy import stats

from bbmc.bench.rockmass_cost import rockmass_cost
from bbmc.config import ConfigError
from bbmc.geometry.polygons import polygon_area, shape_fault, shape_faults
from bbmc.rockmass import RockMassConfig, cut, from_file, generate, profile
from bbmc.rockmass.distributions import length
from bbmc.rockmass.figure import rock_mass_figure
from test_figures import texts_outside

ALPHA = 0.001  # KS significance: a test fails when its p-value is below this
REALIZATIONS = 100

BENCHES = {"height_m": 10, "face_angle_deg": 70, "berm_width_m": 4, "count": 3}
SETS = {
    "bedding": {
        "name": "bedding",
        "dip_deg": {"mean": 35, "std": 4},
        "spacing_m": {"distribution": "lognormal", "mean": 2.0, "std": 0.8},
        "trace_length_m": {"distribution": "lognormal", "mean": 8, "std": 3},
        "gap_m": {"distribution": "exponential", "mean": 2},
    },
    "cross": {
        "name": "cross",
        "dip_deg": 70,
        "dip_direction_to_face_deg": 180,
        "spacing_m": {"distribution": "truncated_normal", "mean": 3, "std": 1.5, "min": 1},
        "trace_length_m": {"distribution": "exponential", "mean": 5},
        "persistence": 0.6,
    },
    "steep": {
        "name": "steep",
        "orientation": {"dip_deg": 60, "dip_direction_deg": 20, "fisher_k": 40},
        "spacing_m": {"distribution": "exponential", "mean": 4},
    },
}


def _raw(*sets: str, **changes) -> dict:
    raw = {
        "profile": {
            "benches": BENCHES,
            "toe_extent_m": 10,
            "crest_extent_m": 30,
            "depth_m": 10,
            "tension_crack": {"distance_behind_crest_m": 6, "depth_m": 8},
        },
        "seed": 1,
        "section_azimuth_deg": 200,
        "joint_sets": [SETS[name] for name in sets or SETS],
    }
    return copy.deepcopy({**raw, **changes})


def _config(*sets: str, **changes) -> RockMassConfig:
    return RockMassConfig.model_validate(_raw(*sets, **changes))


OVERHANG = {
    "polyline_m": [[0, 0], [6, 12], [4, 18], [10, 24], [16, 24], [18, 30]],
    "toe_extent_m": 8,
    "crest_extent_m": 15,
    "depth_m": 6,
    "tension_crack": {"distance_behind_crest_m": 4, "depth_m": 10},
}


def _edges(mass, label_prefix: str) -> float:
    """Total length [m] of the edges whose label starts with the prefix (a shared edge counted twice)."""
    total = 0.0
    for polygon, labels in zip(mass.polygons, mass.edge_labels, strict=True):
        step = np.roll(polygon, -1, axis=0) - polygon
        lengths = np.hypot(step[:, 0], step[:, 1])
        total += sum(lengths[k] for k, label in enumerate(labels) if label.startswith(label_prefix))
    return total


# --- the profile -------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("height", "angle", "berm", "count"), [(10, 70, 4, 3), (15, 60, 8, 5), (12, 90, 3, 2), (20, 45, 0, 1)]
)
def test_benches_overall_angle_has_the_closed_form(height, angle, berm, count):
    surface = profile.bench_surface(height, angle, berm, count)
    cot = 1 / math.tan(math.radians(angle))
    expected = math.degrees(math.atan(count * height / (count * height * cot + (count - 1) * berm)))
    assert profile.overall_angle_deg(surface) == pytest.approx(expected, rel=1e-12)
    assert surface[-1, 1] == pytest.approx(count * height)
    outline = profile.body_outline(surface, 10, 20, 5)
    assert polygon_area(outline) > 0  # counter-clockwise
    assert outline[:, 1].min() == -5 and outline[:, 0].max() == pytest.approx(surface[-1, 0] + 20)


def test_a_profile_that_crosses_itself_is_found():
    assert profile.first_crossing(np.array([[0, 0], [10, 10], [10, 0], [5, 8]], float), closed=False)[:2] == (
        0,
        2,
    )
    assert (
        profile.first_crossing(np.array([[0, 0], [5, 5], [2, 2]], float), closed=False) is not None
    )  # folds back
    assert profile.first_crossing(np.array([[0, 0], [6, 12], [4, 18], [10, 24]], float), closed=False) is None


# --- the blocks --------------------------------------------------------------------------------------


CASES = {
    "benches, three sets, crack": _raw(),
    "overhang, 3D sets": _raw("bedding", "steep", profile=OVERHANG),
    "benches, persistent sets only": _raw(
        "steep", joint_sets=[SETS["steep"], {**SETS["cross"], "persistence": 1.0}]
    ),
}


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_blocks_are_convex_counter_clockwise_and_tile_the_body(case, seed):
    mass = generate(RockMassConfig.model_validate(CASES[case]), seed)
    body = polygon_area(mass.outline)
    assert len(mass.polygons) > 20
    for polygon, splits in zip(mass.polygons, mass.split_vertices, strict=True):
        assert polygon_area(polygon) > 0
        assert shape_fault(np.delete(polygon, splits, axis=0)) is None
        straight = np.isin(np.arange(len(polygon)), splits)
        assert shape_faults(polygon, np.array([0, len(polygon)]), straight) == {}
    assert sum(polygon_area(p) for p in mass.polygons) == pytest.approx(body, rel=1e-9)
    assert all(len(p) == len(labels) for p, labels in zip(mass.polygons, mass.edge_labels, strict=True))


def _on_outline(point: np.ndarray, outline: np.ndarray, tolerance: float) -> bool:
    a, b = outline, np.roll(outline, -1, axis=0)
    ab, ap = b - a, point - a
    f = np.clip((ap * ab).sum(axis=1) / (ab * ab).sum(axis=1), 0, 1)
    return bool(np.min(np.hypot(*(a + f[:, None] * ab - point).T)) < tolerance)


def test_edges_are_labelled_by_what_lies_along_them():
    mass = generate(_config(min_block_fraction=0.0))
    assert mass.skipped.empty
    allowed = {"", "cut", "joint.tension_crack"} | {
        f"{kind}.{name}" for kind in ("joint", "bridge") for name in SETS
    }
    assert {label for labels in mass.edge_labels for label in labels} <= allowed
    for polygon, labels in zip(mass.polygons, mass.edge_labels, strict=True):
        for k, label in enumerate(labels):
            middle = 0.5 * (polygon[k] + polygon[(k + 1) % len(polygon)])
            assert (label == "") == _on_outline(middle, mass.outline, 1e-6)
    for name in SETS:  # each interior edge is in two blocks
        joints = mass.traces[mass.traces["set"] == name]["length_m"].sum()
        along = mass.lines[mass.lines["set"] == name]["length_m"].sum()
        assert _edges(mass, f"joint.{name}") / 2 == pytest.approx(joints, rel=1e-6)
        assert (_edges(mass, f"joint.{name}") + _edges(mass, f"bridge.{name}")) / 2 == pytest.approx(
            along, rel=1e-6
        )
    assert _edges(mass, "joint.tension_crack") / 2 == pytest.approx(8.0)  # the crack's depth


def test_split_vertices_lie_on_a_straight_edge_where_its_label_changes():
    mass = generate(_config())
    count = 0
    for polygon, labels, splits in zip(mass.polygons, mass.edge_labels, mass.split_vertices, strict=True):
        for k in splits:
            before, after = polygon[k] - polygon[k - 1], polygon[(k + 1) % len(polygon)] - polygon[k]
            assert abs(before[0] * after[1] - before[1] * after[0]) <= 1e-9 * np.hypot(*before) * np.hypot(
                *after
            )
            assert labels[k - 1] != labels[k]
            count += 1
    assert count > 50


def test_no_cut_leaves_a_sliver_and_blocks_on_fixed_sides_are_held():
    mass = generate(_config())
    uncut = generate(_config(min_block_fraction=0.0))  # the first pass, whose median sets the bound
    median = np.median([polygon_area(p) for p in uncut.polygons])
    assert len(mass.skipped) > 0 and len(mass.polygons) < len(uncut.polygons)
    assert min(polygon_area(p) for p in mass.polygons) >= 0.02 * median * (1 - 1e-9)
    assert min(polygon_area(p) for p in uncut.polygons) < 0.02 * median
    right, bottom = mass.outline[:, 0].max(), mass.outline[:, 1].min()
    areas = np.array([polygon_area(p) for p in mass.polygons])
    median = np.median(areas)
    slivers = 0
    for polygon, block_area, held in zip(mass.polygons, areas, mass.held, strict=True):
        on_side = max(
            np.sum(np.abs(polygon[:, 0] - right) < 1e-6), np.sum(np.abs(polygon[:, 1] - bottom) < 1e-6)
        )
        gap = min(right - polygon[:, 0].max(), polygon[:, 1].min() - bottom)
        sliver = block_area < 0.25 * median and gap <= np.sqrt(median) and on_side < 2
        slivers += sliver
        assert held == (on_side >= 2 or sliver)
    assert slivers > 0  # the rule acts in this realization
    none = generate(_config(held_sliver_fraction=0.0))
    assert sum(none.held) == sum(mass.held) - slivers


def test_a_joint_through_a_concave_corner_makes_it_convex_and_no_cut_is_added_there():
    through_toe = {**SETS["cross"], "persistence": 1.0, "offset_m": 0.0}  # a persistent line through the toe
    mass = generate(_config(joint_sets=[through_toe], profile={**_raw()["profile"], "tension_crack": None}))
    cuts = [
        np.array([p[k], p[(k + 1) % len(p)]])
        for p, labels in zip(mass.polygons, mass.edge_labels, strict=True)
        for k, label in enumerate(labels)
        if label == "cut"
    ]
    touching_toe = [c for c in cuts if np.min(np.hypot(*c.T)) < 1e-9]
    assert cuts and not touching_toe  # the bench toes above are cut; the slope's toe is not


# --- reproducibility ---------------------------------------------------------------------------------


def test_every_realization_is_reproduced_from_its_seed():
    first, again, other = generate(_config(), 7), generate(_config(), 7), generate(_config(), 8)
    assert len(first.polygons) == len(again.polygons)
    assert all(np.array_equal(a, b) for a, b in zip(first.polygons, again.polygons, strict=True))
    assert first.edge_labels == again.edge_labels and first.held == again.held
    pd.testing.assert_frame_equal(first.traces, again.traces)
    for name in SETS:
        for field in ("dip_deg", "spacing_m", "trace_length_m", "gap_length_m"):
            assert np.array_equal(getattr(first.sets[name], field), getattr(again.sets[name], field))
    assert not first.traces.equals(other.traces)
    assert generate(_config(seed=7)).traces.equals(first.traces)  # the config's seed is the default


def test_a_set_draws_the_same_lines_whatever_the_other_sets():
    alone = generate(_config("bedding"), 5).sets["bedding"]
    with_others = generate(_config(), 5).sets["bedding"]
    assert np.array_equal(alone.spacing_m, with_others.spacing_m)
    assert np.array_equal(alone.dip_deg, with_others.dip_deg)


# --- the statistics ----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def realizations():
    config = _config(min_block_fraction=0.0)
    return [generate(config, seed) for seed in range(REALIZATIONS)]


def _pooled(masses, name: str, field: str) -> np.ndarray:
    return np.concatenate([getattr(m.sets[name], field) for m in masses])


def _distribution(spec):
    return length(
        RockMassConfig.model_validate(_raw(joint_sets=[{**SETS["steep"], "spacing_m": spec}]))
        .joint_sets[0]
        .spacing_m
    )


@pytest.mark.parametrize(
    ("name", "field", "spec"),
    [
        ("bedding", "spacing_m", SETS["bedding"]["spacing_m"]),
        ("cross", "spacing_m", SETS["cross"]["spacing_m"]),
        ("steep", "spacing_m", SETS["steep"]["spacing_m"]),
        ("bedding", "trace_length_m", SETS["bedding"]["trace_length_m"]),
        ("cross", "trace_length_m", SETS["cross"]["trace_length_m"]),
        ("bedding", "gap_length_m", SETS["bedding"]["gap_m"]),
    ],
)
def test_spacings_trace_lengths_and_gaps_follow_their_distributions(realizations, name, field, spec):
    drawn = _pooled(realizations, name, field)
    assert len(drawn) > 1000
    assert stats.kstest(drawn, _distribution(spec).cdf).pvalue > ALPHA


def test_dips_follow_their_distribution_in_the_traces_drawn(realizations):
    drawn = _pooled(realizations, "bedding", "dip_deg")
    assert stats.kstest(drawn, stats.norm(35, 4).cdf).pvalue > ALPHA
    measured = []  # from the traces' end points: one per line that has a trace in the body
    for mass in realizations:
        first = mass.traces[mass.traces["set"] == "bedding"].groupby("line").first()
        measured.append(np.degrees(np.arctan2(first["y1_m"] - first["y0_m"], first["x1_m"] - first["x0_m"])))
    measured = np.concatenate(measured)
    assert len(measured) > 1000
    assert stats.kstest(measured, stats.norm(35, 4).cdf).pvalue > ALPHA


def test_a_3d_set_scatters_about_its_mean_pole_as_fishers_distribution(realizations):
    dip, direction = (
        _pooled(realizations, "steep", "dip_deg"),
        _pooled(realizations, "steep", "dip_direction_to_face_deg"),
    )
    poles = np.column_stack(
        [
            np.sin(np.radians(dip)) * np.cos(np.radians(direction)),
            np.sin(np.radians(dip)) * np.sin(np.radians(direction)),
            np.cos(np.radians(dip)),
        ]
    )
    mean = np.array(
        [
            np.sin(np.radians(60)) * np.cos(np.radians(20 - 200)),
            np.sin(np.radians(60)) * np.sin(np.radians(20 - 200)),
            np.cos(np.radians(60)),
        ]
    )
    angle = np.arccos(np.clip(poles @ mean, -1, 1))
    k = 40.0
    cdf = lambda theta: (1 - np.exp(k * (np.cos(theta) - 1))) / (1 - np.exp(-2 * k))  # noqa: E731
    assert stats.kstest(angle, cdf).pvalue > ALPHA


def _whole_traces_counted(mass, name: str, mean_dip_deg: float) -> np.ndarray:
    """The lengths of the set's uncensored traces, but for each line's last trace that starts at or
    behind its pivot (toe + position x the mean normal): that trace's cycle is the one over the pivot
    (left out of the draws: picked for covering it) or, when the body ends behind the pivot, may run
    out of the body with its gap (not counted as in the body)."""
    normal = np.array([-math.sin(math.radians(mean_dip_deg)), math.cos(math.radians(mean_dip_deg))])
    traces = mass.traces[mass.traces["set"] == name]
    positions = mass.lines[mass.lines["set"] == name].set_index("line")["position_m"]
    kept = []
    for number, rows in traces.groupby("line"):
        start, end = rows[["x0_m", "y0_m"]].to_numpy(), rows[["x1_m", "y1_m"]].to_numpy()
        along = (end - start) / rows["length_m"].to_numpy()[:, None]
        t = np.sum((start - positions[number] * normal) * along, axis=1)
        behind = np.flatnonzero(t <= 1e-9)
        last = behind[np.argmax(t[behind])] if behind.size else -1
        kept += [
            length for k, length in enumerate(rows["length_m"]) if k != last and not rows["censored"].iloc[k]
        ]
    return np.array(kept)


def test_the_blocks_are_made_of_the_draws(realizations):
    for mass in realizations[:10]:
        whole = _whole_traces_counted(mass, "bedding", 35.0)
        drawn = mass.sets["bedding"].trace_length_m
        assert len(whole) > 30
        assert np.all(np.min(np.abs(whole[:, None] - drawn[None, :]), axis=1) < 1e-9)
        cross = mass.traces[mass.traces["set"] == "cross"]
        normal = np.array([np.sin(np.radians(70)), np.cos(np.radians(70))])  # dips 70 into the slope
        positions = np.sort(cross.groupby("line").first()[["x0_m", "y0_m"]].to_numpy() @ normal)
        measured = np.diff(positions)
        assert np.all(
            np.min(np.abs(measured[:, None] - mass.sets["cross"].spacing_m[None, :]), axis=1) < 1e-9
        )


def _persistence(masses, name: str) -> tuple[float, float]:
    """The share of the set's lines that is joint, from the blocks' edges, and its standard error (the
    ratio estimator's over the lines, each line's joint and total lengths from the traces)."""
    joint = sum(_edges(m, f"joint.{name}") for m in masses)
    measured = joint / (joint + sum(_edges(m, f"bridge.{name}") for m in masses))
    lines = pd.concat([m.lines[m.lines["set"] == name].assign(seed=m.seed) for m in masses])
    traces = pd.concat([m.traces[m.traces["set"] == name].assign(seed=m.seed) for m in masses])
    per_line = traces.groupby(["seed", "line"])["length_m"].sum()
    along = lines.set_index(["seed", "line"])["length_m"]
    on = per_line.reindex(along.index, fill_value=0.0)
    n = len(along)
    error = math.sqrt(n / (n - 1) * np.sum((on - measured * along) ** 2)) / along.sum()
    return measured, error


@pytest.mark.parametrize(("name", "expected"), [("bedding", 8 / (8 + 2)), ("cross", 0.6)])
def test_persistence_measured_along_the_lines_matches_k(realizations, name, expected):
    measured, error = _persistence(realizations, name)
    assert error < 0.01  # enough lines for the check to mean something
    assert abs(measured - expected) < 4 * error  # 4 standard errors: p ~ 6e-5 for a normal estimate


# --- 3D sets in the section --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("dip", "direction", "azimuth"),
    [(50, 200, 200), (50, 240, 200), (70, 10, 200), (35, 100, 30), (80, 130, 90)],
)
def test_a_3d_set_has_the_closed_form_apparent_dip_and_spacing_in_the_section(dip, direction, azimuth):
    joint_set = {
        "name": "j",
        "orientation": {"dip_deg": dip, "dip_direction_deg": direction},
        "spacing_m": 2.5,
        "offset_m": 0.3,
    }
    mass = generate(_config(joint_sets=[joint_set], section_azimuth_deg=azimuth, min_block_fraction=0.0))
    beta = math.radians(direction - azimuth)
    apparent = math.degrees(math.atan(math.tan(math.radians(dip)) * abs(math.cos(beta))))
    apparent *= 1 if math.cos(beta) > 0 else -1  # > 0: dips out of the slope, towards -x
    spacing = 2.5 / math.sqrt(1 - math.sin(math.radians(dip)) ** 2 * math.sin(beta) ** 2)
    traces = mass.traces.groupby("line").first()
    measured = np.degrees(
        np.arctan2(-(traces["y1_m"] - traces["y0_m"]), np.abs(traces["x1_m"] - traces["x0_m"]))
    )
    measured = np.where(traces["x1_m"] > traces["x0_m"], -measured, measured)
    assert np.allclose(measured, apparent, atol=1e-9)
    angle = math.radians(apparent)
    normal = np.array([-math.sin(angle), math.cos(angle)])
    positions = np.sort(traces[["x0_m", "y0_m"]].to_numpy() @ normal)
    assert np.allclose(np.diff(positions), spacing, rtol=1e-9)


def test_the_scatter_of_a_3d_set_reaches_each_line_through_the_same_projection(realizations):
    for mass in realizations[:5]:
        sample = mass.sets["steep"]
        beta = np.radians(sample.dip_direction_to_face_deg)
        closed = np.degrees(np.arctan(np.tan(np.radians(sample.dip_deg)) * np.cos(beta)))
        assert np.allclose(sample.apparent_dip_deg, closed, atol=1e-9)


# --- speed -------------------------------------------------------------------------------------------


def test_the_cutting_work_grows_with_the_blocks_made_not_with_blocks_times_lines(monkeypatch):
    calls = {"n": 0}
    split = cut._split

    def counted(*args):
        calls["n"] += 1
        return split(*args)

    monkeypatch.setattr(cut, "_split", counted)
    per_block = []
    for scale in (2.0, 0.7):
        sets = [
            {**s, "spacing_m": {**s["spacing_m"], "mean": s["spacing_m"]["mean"] * scale}}
            for s in SETS.values()
        ]
        calls["n"] = 0
        mass = generate(_config(joint_sets=sets, min_block_fraction=0.0))
        per_block.append(calls["n"] / len(mass.polygons))
    assert per_block[1] < 1.5 * per_block[0]  # 8 times the blocks, about the same tests per block


# --- bad input ---------------------------------------------------------------------------------------


def _set(changes: dict) -> dict:
    return {"joint_sets": [{**SETS["bedding"], **changes}]}


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (_set({"spacing_m": 0}), "key 'joint_sets.0.spacing_m': Input should be greater than 0, got 0"),
        (
            _set({"spacing_m": {"distribution": "exponential", "mean": -1}}),
            "key 'joint_sets.0.spacing_m.mean': Input should be greater than 0",
        ),
        (
            _set({"spacing_m": {"distribution": "truncated_normal", "mean": 1, "std": 1, "min": -1}}),
            "key 'joint_sets.0.spacing_m.min'",
        ),
        (
            _set({"gap_m": None, "persistence": 0}),
            "key 'joint_sets.0.persistence': Input should be greater than 0",
        ),
        (
            _set({"gap_m": None, "persistence": 1.2}),
            "key 'joint_sets.0.persistence': Input should be less than or equal to 1",
        ),
        (
            {"profile": {**OVERHANG, "polyline_m": [[0, 0], [10, 10], [10, 0], [5, 8]]}},
            "key 'profile': polyline_m: the ground surface crosses itself",
        ),
        (
            {"profile": {**OVERHANG, "polyline_m": [[0, 0], [10, -10], [20, 5]]}},
            "key 'profile': the ground surface meets the model's base or sides",
        ),
        (_set({"spacing_m": 500, "offset_m": 100}), "key 'joint_sets': the sets make no block"),
        (
            {"profile": {**OVERHANG, "polyline_m": [[0, 0], [-5, 5], [-10, 10]], "crest_extent_m": 0}},
            "key 'profile': the ground surface runs beyond the model's sides",
        ),
        (
            {
                "profile": {
                    **OVERHANG,
                    "polyline_m": [[0, 0], [0, 10]],
                    "toe_extent_m": 0,
                    "crest_extent_m": 0,
                }
            },
            "key 'profile': the profile encloses no rock",
        ),
        (
            {"profile": {**OVERHANG, "tension_crack": {"distance_behind_crest_m": 20, "depth_m": 3}}},
            "tension_crack.distance_behind_crest_m",
        ),
        (_set({"name": "tension_crack"}), "joint_sets.0.name: 'tension_crack' is the tension crack's"),
        (
            _set({"spacing_m": 0.001}),
            "key 'joint_sets.0.spacing_m': the body reaches 71 m from the set's line 0 (in the section): "
            "about 71,002 lines at this spacing, more than 10,000 on one side",
        ),
    ],
)
def test_bad_input_is_one_line_naming_the_key(tmp_path, changes, message):
    path = tmp_path / "mass.yaml"
    raw = {**_raw("bedding"), **changes}
    path.write_text(yaml.safe_dump(raw))
    with pytest.raises(ConfigError) as error:
        from_file(path)
    text = str(error.value)
    assert text.startswith(f"{path}: ") and "\n" not in text
    assert message in text


def test_the_bench_function_reports_blocks_and_seconds():
    cost = rockmass_cost(repeats=1, spacing_scale=4.0)
    assert set(cost) == {"blocks", "lines", "traces", "skipped_cuts", "seconds", "blocks_per_s"}
    assert cost["blocks"] > 100 and cost["seconds"] > 0


# --- the figure --------------------------------------------------------------------------------------


def test_the_figure_draws_joints_solid_bridges_dashed_cuts_dotted_inside_its_canvas(tmp_path):
    figure = rock_mass_figure(generate(_config()))
    collections = {c.get_label(): c for c in figure.axes[0].collections if isinstance(c, LineCollection)}
    assert set(collections) == {
        "boundary", "cut (intact rock)", "tension crack", "bedding joints", "bedding bridges", "cross joints",
        "cross bridges", "steep joints",
    }  # fmt: skip
    dashes = {label: c.get_linestyle()[0][1] for label, c in collections.items()}
    assert dashes["bedding joints"] is None and dashes["bedding bridges"] is not None
    assert dashes["cut (intact rock)"] is not None
    assert not texts_outside(figure)
    figure.savefig(tmp_path / "mass.png")
    assert (tmp_path / "mass.png").stat().st_size > 10_000


def test_the_docs_example_is_the_tested_rock_mass_and_generates(tmp_path):
    text = (Path(__file__).resolve().parents[1] / "docs" / "rock-mass.md").read_text(encoding="utf-8")
    example = text.split("```yaml\n", 1)[1].split("```", 1)[0]
    path = tmp_path / "mass.yaml"
    path.write_text(example)
    assert RockMassConfig.model_validate(yaml.safe_load(example)) == _config()
    assert len(from_file(path).polygons) > 100
