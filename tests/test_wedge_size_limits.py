"""Swedge's size limits (bbmc.slope.wedge.size_limits): each limit on a wedge worked by hand gives the
height that makes the wedge's extent equal to it; the wedge shrinks about its toe (lengths by s, areas
by s^2, volume by s^3); a cohesionless dry wedge keeps its FS while cohesion's share grows as 1/s; the
smallest limit governs and is named; a limit larger than the wedge changes nothing, bit for bit; a
batch equals its wedges one at a time; the combinations' pairs are scaled too; bad input and a crack
with limits are refused in one line naming the key. Each tolerance is stated where it is used."""

from __future__ import annotations

from dataclasses import fields, replace

import numpy as np
import pandas as pd
import pytest
import yaml

from bbmc.slope.wedge.cases import Plane, WedgeSetting, analyse_case
from bbmc.slope.wedge.combinations import combination_table
from bbmc.slope.wedge.geometry import TensionCrack, wedge_geometries, wedge_geometry
from bbmc.slope.wedge.mechanics import MohrCoulomb
from bbmc.slope.wedge.size_limits import SizeLimits, wedge_extents
from stage_runs import CONFIGS, config_copy, refused, run_stage, set_key

R = np.radians
R2 = np.sqrt(2.0)
# Planes 45/135 and 45/225, vertical face 90/180, horizontal upper surface (test_wedge_geometry's
# wedge by hand): at height h, C1 = (-sqrt2 h, 0, h), C2 = (sqrt2 h, 0, h), T = (0, sqrt2 h, h).
SYMMETRIC = (R(45), R(135), R(45), R(225), R(90), R(180), 0.0, 0.0)
CLASSIC = (R(45), R(105), R(70), R(235), R(65), R(185), R(12), R(195))
H = 10.0


def _extents(g):
    return wedge_extents(g.vertices, g.normal_face, g.normal_upper)


def test_symmetric_wedge_extents_by_hand():
    """At height h: along the crest C1 to C2, 2 sqrt2 h; behind the crest T's horizontal distance,
    sqrt2 h; each plane's trace max(|O C1| = sqrt3 h, |C1 T| = 2 h) = 2 h; each plane's persistence,
    the longest side of O C1 T, 2 h. To 1e-12."""
    e = _extents(wedge_geometry(*SYMMETRIC, height_h=H))
    by_hand = [2 * R2 * H, R2 * H, 2 * H, 2 * H, 2 * H, 2 * H]
    assert [float(getattr(e, f.name)) for f in fields(e)] == pytest.approx(by_hand, rel=1e-12)


@pytest.mark.parametrize("upper_dip", [0.0, 10.0, 20.0])
def test_bench_width_is_horizontal(upper_dip):
    """The symmetric wedge under an upper surface rising into the slope at beta (dip towards the face's
    180): z = h + y tan beta and T = (0, sqrt2 t, t) give t = h / (1 - sqrt2 tan beta); the reach
    behind the crest is T's horizontal sqrt2 t, not its sqrt2 t / cos beta along the upper surface
    (1e-12)."""
    g = wedge_geometry(*SYMMETRIC[:6], R(upper_dip), R(180), height_h1=H)
    t = H / (1 - R2 * np.tan(R(upper_dip)))
    assert _extents(g).behind_crest == pytest.approx(R2 * t, rel=1e-12)


def test_slope_length_counts_every_vertex():
    """Planes 45/135 and 70/170, vertical face 90/180, horizontal top, H1 = h: both joints' face traces
    lean west, C1 = (-sqrt2 h, 0, h), C2 = (-h / (tan 70 sin 170), 0, h) = (-2.096 h, 0, h), T_x =
    -1.268 h: the wedge reaches along the crest from the toe (x = 0) to C2, h / (tan 70 sin 170), not
    the crest's C1 C2 (1e-12)."""
    g = wedge_geometry(R(45), R(135), R(70), R(170), R(90), R(180), 0.0, 0.0, height_h1=H)
    reach = H / (np.tan(R(70)) * np.sin(R(170)))
    assert g.crest_2[0] == pytest.approx(-reach, rel=1e-12)
    assert _extents(g).along_crest == pytest.approx(reach, rel=1e-12)
    assert g.crest_length < 0.4 * reach
    limited = wedge_geometry(
        R(45),
        R(135),
        R(70),
        R(170),
        R(90),
        R(180),
        0.0,
        0.0,
        height_h1=H,
        limits=SizeLimits(slope_length=5.0),
    )
    assert limited.height_h1 == pytest.approx(5.0 * H / reach, rel=1e-12)


@pytest.mark.parametrize(
    ("limit", "value", "height"),
    [
        ("slope_length", 8.0, 8.0 / (2 * R2)),  # 2 sqrt2 h = L
        ("bench_width", 5.0, 5.0 / R2),  # sqrt2 h = B
        ("trace_length_plane_1", 6.0, 3.0),  # 2 h = trace length
        ("persistence_plane_2", 7.0, 3.5),  # 2 h = persistence
        ("volume", 100.0, (3 * 100.0 / 2) ** (1 / 3)),  # 2 h^3 / 3 = V
    ],
)
def test_each_limit_gives_the_height_by_hand(limit, value, height):
    """The limit sets the height at which the wedge's extent equals it (to 1e-12), names itself, and the
    scale factor is that height over the one asked for."""
    g = wedge_geometry(*SYMMETRIC, height_h=H, limits=SizeLimits(**{limit: value}))
    assert g.height_h == pytest.approx(height, rel=1e-12)
    assert g.size_scale == pytest.approx(height / H, rel=1e-12)
    assert str(g.size_limit_names()) == limit
    measured = g.volume if limit == "volume" else getattr(_extents(g), _extent_name(limit))
    assert measured == pytest.approx(value, rel=1e-12)


def _extent_name(limit: str) -> str:
    return {"slope_length": "along_crest", "bench_width": "behind_crest"}.get(limit, limit)


def test_the_smallest_limit_governs_and_every_limit_holds():
    """The classic wedge at H1 30.48 m under five limits: the one with the smallest ratio of limit to
    extent governs; the wedge built meets it exactly (1e-12) and every other one (within 1e-12)."""
    full = _extents(wedge_geometry(*CLASSIC, height_h1=30.48))
    limits = {
        "bench_width": 0.5 * float(full.behind_crest),
        "slope_length": 0.4 * float(full.along_crest),
        "trace_length_plane_1": 0.6 * float(full.trace_length_plane_1),
        "trace_length_plane_2": 0.7 * float(full.trace_length_plane_2),
        "persistence_plane_1": 0.45 * float(full.persistence_plane_1),
    }
    g = wedge_geometry(*CLASSIC, height_h1=30.48, limits=SizeLimits(**limits))
    assert str(g.size_limit_names()) == "slope_length"
    assert g.size_scale == pytest.approx(0.4, rel=1e-12)
    e = _extents(g)
    assert e.along_crest == pytest.approx(limits["slope_length"], rel=1e-12)
    for limit, value in limits.items():
        assert getattr(e, _extent_name(limit)) <= value * (1 + 1e-12)


def test_the_wedge_shrinks_about_its_toe():
    """Limited by a factor s, the classic wedge is the same wedge s times smaller: its vertices s times
    the full wedge's, areas s^2, volume s^3, the same line of intersection and K (to 1e-12)."""
    full = wedge_geometry(*CLASSIC, height_h1=30.48)
    g = wedge_geometry(*CLASSIC, height_h1=30.48, limits=SizeLimits(bench_width=12.0))
    s = float(g.size_scale)
    assert 0.2 < s < 0.5
    assert g.vertices == pytest.approx(s * full.vertices, rel=1e-12, abs=1e-12)
    for name in ("area_1", "area_2", "area_face", "area_upper"):
        assert getattr(g, name) == pytest.approx(s**2 * getattr(full, name), rel=1e-12)
    assert g.volume == pytest.approx(s**3 * full.volume, rel=1e-12)
    assert g.height_h1 == pytest.approx(s * 30.48, rel=1e-12)
    assert [float(g.trend), float(g.plunge)] == pytest.approx(
        [float(full.trend), float(full.plunge)], abs=1e-12
    )
    assert g.short_solution.wedge_factor == pytest.approx(full.short_solution.wedge_factor, rel=1e-12)


def _classic_case(cohesion: float, **limits):
    planes = [
        Plane(R(45), R(105), lambda _length: MohrCoulomb(cohesion, R(20))),
        Plane(R(70), R(235), lambda _length: MohrCoulomb(2 * cohesion, R(30))),
    ]
    setting = WedgeSetting(face=(R(65), R(185)), upper=(R(12), R(195)), unit_weight=25e3, height_h1=30.48)
    return analyse_case(replace(setting, **limits), *planes)


def test_scaling_keeps_a_frictional_dry_wedges_fs_and_raises_cohesions_share():
    """Dry and cohesionless, FS is the planes' friction against the wedge's own weight: the same at any
    size (1e-12). With cohesion c A / D grows as s^2 / s^3 = 1 / s: FS - FS_friction = (that at full
    size) / s (1e-9), so the smaller wedge is the safer."""
    bench = {"bench_width": 12.0}
    frictional = [_classic_case(0.0), _classic_case(0.0, **bench)]
    cohesive = [_classic_case(20e3), _classic_case(20e3, **bench)]
    fs = [float(case.analysis.factor_of_safety) for case in frictional + cohesive]
    s = float(frictional[1].geometry.size_scale)
    assert fs[1] == pytest.approx(fs[0], rel=1e-12)
    assert fs[3] - fs[1] == pytest.approx((fs[2] - fs[0]) / s, rel=1e-9)
    assert fs[3] > fs[2]


def _same(a, b) -> bool:
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


def test_a_limit_larger_than_the_wedge_changes_nothing_bit_for_bit():
    """Limits 1.01 times the wedge's own extents (and volume): every field of the geometry, crack points
    and short solution included, is the unlimited wedge's, bit for bit; the size is the height's."""
    full = wedge_geometry(*CLASSIC, height_h1=30.48)
    e = _extents(full)
    roomy = SizeLimits(
        bench_width=1.01 * e.behind_crest,
        slope_length=1.01 * e.along_crest,
        trace_length_plane_1=1.01 * e.trace_length_plane_1,
        trace_length_plane_2=1.01 * e.trace_length_plane_2,
        persistence_plane_1=1.01 * e.persistence_plane_1,
        persistence_plane_2=1.01 * e.persistence_plane_2,
        volume=1.01 * full.volume,
    )
    g = wedge_geometry(*CLASSIC, height_h1=30.48, limits=roomy)
    assert str(g.size_limit_names()) == "height" and g.size_scale == 1.0
    for f in fields(full):
        if f.name != "short_solution":
            assert _same(getattr(g, f.name), getattr(full, f.name)), f.name
    for f in fields(full.short_solution):
        assert _same(getattr(g.short_solution, f.name), getattr(full.short_solution, f.name)), f.name


def test_a_batch_with_array_limits_equals_one_wedge_at_a_time():
    """Random wedges with random slope lengths and trace lengths in one call equal the same wedges one by
    one (to 1e-12): the same scale, the same governing limit, NaN where no wedge forms."""
    rng = np.random.default_rng(35)
    n = 150
    dips = R(rng.uniform(10, 85, (n, 2)))
    directions = R(rng.uniform(100, 280, (n, 2)))
    args = (dips[:, 0], directions[:, 0], dips[:, 1], directions[:, 1], R(70), R(180), R(10), R(190))
    lengths, traces = rng.uniform(5, 60, n), rng.uniform(5, 40, n)
    batch = wedge_geometries(
        *args, height_h1=20.0, limits=SizeLimits(slope_length=lengths, trace_length_plane_2=traces)
    )
    names = batch.size_limit_names()[batch.formed]
    assert {"height", "slope_length", "trace_length_plane_2"} <= set(names)  # each kind in the sample
    for i in range(n):
        one = wedge_geometries(
            *(np.asarray(a)[i] if np.ndim(a) else a for a in args),
            height_h1=20.0,
            limits=SizeLimits(slope_length=lengths[i], trace_length_plane_2=traces[i]),
        )
        assert one.reason == batch.reason[i]
        if one.reason == 0:
            assert one.size_scale == pytest.approx(batch.size_scale[i], rel=1e-12)
            assert one.size_limited_by == batch.size_limited_by[i]
            assert one.volume == pytest.approx(batch.volume[i], rel=1e-12)
        else:
            assert np.isnan(batch.size_scale[i]) and np.isnan(batch.volume[i])


def test_one_wedge_under_an_array_of_limits():
    """Scalar planes and an array of bench widths: one wedge per width, each its own height (1e-12)."""
    widths = np.array([1.0, 5.0, 100.0])
    g = wedge_geometries(*SYMMETRIC, height_h=H, limits=SizeLimits(bench_width=widths))
    assert g.height_h == pytest.approx(np.minimum(widths / R2, H), rel=1e-12)
    assert list(g.size_limit_names()) == ["bench_width", "bench_width", "height"]
    assert g.reason.shape == (3,) and g.formed.all()


def test_extents_of_a_cracked_wedge():
    """The symmetric wedge with a vertical crack parallel to the face at L along plane 1's upper trace:
    P and Q stand L / sqrt2 behind the crest, plane 1's upper trace is L (shorter than its face trace
    sqrt3 h, which is then its trace length), to 1e-12."""
    crack = TensionCrack(R(90), R(180), 4.0)
    e = _extents(wedge_geometry(*SYMMETRIC, height_h=H, crack=crack))
    assert e.behind_crest == pytest.approx(4.0 / R2, rel=1e-12)
    assert e.trace_length_plane_1 == pytest.approx(np.sqrt(3) * H, rel=1e-12)
    assert e.along_crest == pytest.approx(2 * R2 * H, rel=1e-12)


def test_geometry_refuses_a_crack_with_limits():
    with pytest.raises(ValueError, match="limits: size limits scale the wedge; not with a tension crack"):
        wedge_geometries(
            *SYMMETRIC, height_h=H, crack=TensionCrack(R(90), R(180), 4.0), limits=SizeLimits(bench_width=1.0)
        )


def test_bad_limit_names_itself():
    with pytest.raises(ValueError, match="bench_width: a size limit must be > 0"):
        SizeLimits(bench_width=np.array([3.0, 0.0]))


def test_combinations_scale_every_pair():
    """A set's trace length limits every wedge it bounds, as plane 1 or plane 2; the pit's slope length
    every pair: each formed row's height is the limited wedge's, its own case's (1e-12)."""
    pit = WedgeSetting(face=(R(65), R(180)), upper=(R(10), R(180)), unit_weight=26e3, height_h1=20.0)
    strength = MohrCoulomb(0.0, R(30))
    sets = {
        name: Plane(R(dip), R(direction), lambda _length: strength, trace_length=trace)
        for name, dip, direction, trace in (
            ("S1", 36, 161, None),
            ("S2", 60, 217, 8.0),
            ("S3", 55, 129, None),
        )
    }
    rows = combination_table(replace(pit, slope_length=25.0), sets)
    formed = [r for r in rows if r.forms]
    assert formed and all(r.size_scale < 1.0 for r in formed)
    for row in formed:
        case = analyse_case(replace(pit, slope_length=25.0), sets[row.plane_1], sets[row.plane_2])
        assert row.height_h1_m == pytest.approx(float(case.geometry.height_h1), rel=1e-12)
        assert row.size_limited_by == str(case.geometry.size_limit_names())
    assert any("trace_length" in r.size_limited_by for r in formed if "S2" in (r.plane_1, r.plane_2))


def _run(tmp_path, edit):
    tmp_path.mkdir(parents=True, exist_ok=True)
    config = config_copy(tmp_path, "wedge", edit)
    return run_stage("wedge", tmp_path / "results", config), tmp_path / "results" / "wedge" / config.stem


def test_the_command_scales_the_wedge_and_says_so(tmp_path):
    """bench_width_m 12 on the classic wedge: wedge.csv holds the limited wedge (its reach behind the
    crest 12 m, to 1e-9 relative), its scale and what governs; the command prints it."""
    outcome, folder = _run(tmp_path, set_key("bench_width_m", 12.0))
    assert outcome.exit_code == 0, outcome.output
    w = pd.read_csv(folder / "wedge.csv").iloc[0]
    assert w.size_limited_by == "bench_width"
    assert w.extent_behind_crest_m == pytest.approx(12.0, rel=1e-9)
    assert w.height_h1_m == pytest.approx(30.48 * w.size_scale, rel=1e-9)
    assert "scaled by" in outcome.output and "bench width" in outcome.output


def test_the_command_with_a_larger_limit_writes_the_same_fs(tmp_path):
    """A trace length of 1000 m on plane 1 limits nothing: FS as without it, to the last digit written."""
    outcome, folder = _run(tmp_path, set_key("plane_1.trace_length_m", 1000.0))
    assert outcome.exit_code == 0, outcome.output
    w = pd.read_csv(folder / "wedge.csv").iloc[0]
    assert w.size_limited_by == "height" and w.size_scale == 1.0
    _, plain = _run(tmp_path / "plain", lambda data: None)
    assert w.factor_of_safety == pd.read_csv(plain / "wedge.csv").factor_of_safety[0]


def _crack_and_bench(data):
    data["tension_crack"] = {"dip_deg": 70, "dip_direction_deg": 185, "distance_m": 5}
    data["bench_width_m"] = 10


@pytest.mark.parametrize(
    ("edit", "fragments"),
    [
        (set_key("bench_width_m", 0), ("bench_width_m",)),
        (set_key("slope_length_m", -5), ("slope_length_m",)),
        (set_key("max_volume_m3", "big"), ("max_volume_m3",)),
        (set_key("plane_1.trace_length_m", 0), ("plane_1.trace_length_m",)),
        (set_key("plane_2.persistence_m", -1), ("plane_2.persistence_m",)),
        (_crack_and_bench, ("tension_crack", "distance_m does not scale")),
    ],
)
def test_bad_limits_are_refused_in_one_line(tmp_path, edit, fragments):
    outcome, _ = _run(tmp_path, edit)
    refused(outcome, tmp_path / "results", *fragments)


def test_the_combinations_example_with_a_slope_length(tmp_path):
    """configs/wedge_combinations.yaml with slope_length_m 20: combinations.csv gives every formed pair
    its scale (<= 1) and what governs."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    data = yaml.safe_load((CONFIGS / "wedge_combinations.yaml").read_text())
    data["slope_length_m"] = 20.0
    config = tmp_path / "pit.yaml"
    config.write_text(yaml.safe_dump(data))
    outcome = run_stage("wedge", tmp_path / "results", config)
    assert outcome.exit_code == 0, outcome.output
    table = pd.read_csv(tmp_path / "results" / "wedge" / "pit" / "combinations.csv")
    formed = table[table.forms]
    assert len(formed) == 3
    assert (formed.size_scale <= 1.0).all()
    assert set(formed.size_limited_by) <= {"height", "slope_length"}
    assert "slope_length" in set(formed.size_limited_by)
