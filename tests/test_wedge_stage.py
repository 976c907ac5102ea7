"""`bbmc wedge` through the real command line: Hoek & Bray's classic wedge in SI (configs/wedge.yaml) gives
their FS, dry and wet; the bolt design is checked by the vector solution and the bisection along the
optimum direction finds the closed form's force; the combination table of the pit wall's four sets
(configs/wedge_combinations.yaml) row by row; bad input refused in one line naming the file and key,
with nothing written. Each tolerance is stated where it is used."""

from __future__ import annotations

import math

import meshio
import numpy as np
import pandas as pd
import pytest
import yaml

from bbmc.outputs.wedge_vtk import enclosed_volume
from bbmc.slope.wedge.analysis import Seismic, WedgeOrientations, analyse_wedges
from bbmc.slope.wedge.geometry import TensionCrack
from bbmc.slope.wedge.loads import force_vector
from bbmc.slope.wedge.mechanics import MohrCoulomb
from bbmc.slope.wedge.strength import BartonBandis
from bbmc.slope.wedge.water import HoekBrayWater, PlanePressures
from stage_runs import CONFIGS, config_copy, refused, run_stage, set_key

R = np.radians


def _run(tmp_path, edit=None, example="wedge"):
    """`bbmc wedge` on configs/<example>.yaml, or on an `edit`ed copy of configs/wedge.yaml; the outcome
    and the folder it writes."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    config = CONFIGS / f"{example}.yaml" if edit is None else config_copy(tmp_path, "wedge", edit)
    outcome = run_stage("wedge", tmp_path / "results", config)
    return outcome, tmp_path / "results" / "wedge" / config.stem


def _feet_and_pounds_fs() -> float:
    """The classic wedge in Hoek & Bray's own units (ft, psf, pcf) with their water."""
    orientations = WedgeOrientations(R(45), R(105), R(70), R(235), R(65), R(185), R(12), R(195))
    analysis = analyse_wedges(
        orientations,
        MohrCoulomb(500.0, R(20)),
        MohrCoulomb(1000.0, R(30)),
        unit_weight=160.0,
        water_unit_weight=62.5,
        height_h1=100.0,
        water=HoekBrayWater(),
    )
    return float(analysis.factor_of_safety)


def test_classic_wedge_in_si_gives_hoek_and_brays_fs(tmp_path):
    """configs/wedge.yaml prints and writes FS 1.2180 (the issue's value, within 5e-4); converted to SI,
    the FS equals the one computed in feet and pounds to 1e-6 (the config's constants are rounded to
    7-8 significant figures); H is 130 ft = 39.62 m (to 0.01 m: Hoek & Bray's H rounded to the foot)."""
    outcome, folder = _run(tmp_path)
    assert outcome.exit_code == 0, outcome.output
    assert "FS 1.2180" in outcome.output
    wedge = pd.read_csv(folder / "wedge.csv").iloc[0]
    assert wedge.factor_of_safety == pytest.approx(1.2180, abs=5e-4)
    assert wedge.factor_of_safety == pytest.approx(_feet_and_pounds_fs(), abs=1e-6)
    assert wedge["mode"] == "sliding along the line of intersection"
    assert wedge.height_m == pytest.approx(130 * 0.3048, abs=0.1)
    assert wedge.wedge_factor_k == pytest.approx(1.505, abs=5e-4)  # the K of the classic wedge
    assert wedge.driving_kN == pytest.approx(wedge.driving_weight_kN + wedge.driving_water_kN, rel=1e-12)
    assert {"O_x_m", "C1_z_m", "T_y_m", "area_1_m2", "volume_m3", "normal_2_kN"} <= set(wedge.index)
    assert (folder / "provenance.json").is_file()


def test_classic_wedge_dry(tmp_path):
    """Dry: 1.8464 within 5e-4 (the issue's value)."""
    outcome, folder = _run(tmp_path, set_key("water", {"model": "dry"}))
    assert outcome.exit_code == 0, outcome.output
    assert pd.read_csv(folder / "wedge.csv").factor_of_safety[0] == pytest.approx(1.8464, abs=5e-4)


def test_bolt_design_optimum_and_given_direction_agree(tmp_path):
    """The optimum's closed form reaches the target exactly; the vector solution with the count of bolts
    (rounded up) reaches at least it; bisection on the vector solution along the optimum's direction
    (rounded to 1e-6 deg in the config) finds the closed form's least force to 1e-6 relative."""
    outcome, folder = _run(tmp_path)
    optimum = pd.read_csv(folder / "design.csv").iloc[0]
    assert optimum.closed_form_fs == pytest.approx(1.5, rel=1e-12)
    assert optimum.factor_of_safety >= 1.5
    assert optimum["count"] == math.ceil(optimum.total_force_kN / optimum.capacity_kN)
    direction = {
        "trend_deg": round(float(optimum.trend_deg), 6),
        "plunge_deg": round(float(optimum.plunge_deg), 6),
    }
    outcome, folder = _run(tmp_path / "given", set_key("design.bolt", direction))
    assert outcome.exit_code == 0, outcome.output
    given = pd.read_csv(folder / "design.csv").iloc[0]
    assert given.bolt == "given"
    assert given.total_force_kN == pytest.approx(optimum.total_force_kN, rel=1e-6)


def test_bolt_design_for_a_given_count_gives_each_bolts_capacity(tmp_path):
    """`count: 40` instead of `capacity_kN`: each bolt's capacity is the least force over 40, and the
    vector solution with those bolts gives the target (to the bisection's 1e-9); capacity and count
    together, or neither, are refused in one line naming `design`."""

    def by_count(data):
        data["design"]["count"] = 40
        del data["design"]["capacity_kN"]

    outcome, folder = _run(tmp_path / "count", by_count)
    assert outcome.exit_code == 0, outcome.output
    row = pd.read_csv(folder / "design.csv").iloc[0]
    assert row["count"] == 40
    assert row.capacity_kN == pytest.approx(row.total_force_kN / 40, rel=1e-12)
    assert row.factor_of_safety == pytest.approx(1.5, rel=1e-9)
    outcome, _ = _run(tmp_path / "both", set_key("design.count", 40))
    refused(outcome, tmp_path / "both" / "results", "wedge.yaml", "design", "exactly one")


def test_a_bolt_along_the_sliding_direction_reaches_no_target(tmp_path):
    """Bolts drilled down the line of intersection (31/158) pull the wedge out: no force reaches FS 1.5;
    design.csv says so with NaN, and the command in words, not with a number."""
    outcome, folder = _run(tmp_path, set_key("design.bolt", {"trend_deg": 158, "plunge_deg": 31}))
    assert outcome.exit_code == 0, outcome.output
    design = pd.read_csv(folder / "design.csv").iloc[0]
    assert np.isnan(design.total_force_kN) and np.isnan(design["count"])
    assert "FS 1.5 not reached along trend 158, plunge 31.0" in outcome.output


def test_bolts_in_the_config_give_the_designs_fs(tmp_path):
    """The designed bolts typed into the config's bolts: section give the FS the design reported (the
    config's bolt path and the design's check are one vector solution: to 1e-9)."""
    _, folder = _run(tmp_path)
    d = pd.read_csv(folder / "design.csv").iloc[0]
    bolts = [
        {
            "capacity_kN": float(d.capacity_kN),
            "trend_deg": float(d.trend_deg),
            "plunge_deg": float(d.plunge_deg),
            "count": int(d["count"]),
            "form": "active",
        }
    ]

    def edit(data):
        data["bolts"] = bolts
        del data["design"]

    outcome, folder = _run(tmp_path / "bolted", edit)
    assert outcome.exit_code == 0, outcome.output
    assert pd.read_csv(folder / "wedge.csv").factor_of_safety[0] == pytest.approx(
        d.factor_of_safety, rel=1e-9
    )


def test_barton_bandis_with_jrc_zero_is_mohr_coulomb(tmp_path):
    """JRC 0 makes the B-B envelope sigma_n tan phi_b: the classic wedge without cohesion gives the same
    FS with M-C (c 0, phi) and B-B (JRC 0, phi_b = phi), to 1e-12."""

    def strengths(law):
        def edit(data):
            for key, phi in (("plane_1", 20), ("plane_2", 30)):
                mc = {"law": "mohr_coulomb", "cohesion_kPa": 0, "friction_deg": phi}
                bb = {"law": "barton_bandis", "jrc": 0, "jcs_MPa": 50, "phi_b_deg": phi}
                data[key]["strength"] = mc if law == "mc" else bb

        return edit

    fs = []
    for law in ("mc", "bb"):
        outcome, folder = _run(tmp_path / law, strengths(law))
        assert outcome.exit_code == 0, outcome.output
        fs.append(pd.read_csv(folder / "wedge.csv").factor_of_safety[0])
    assert fs[1] == pytest.approx(fs[0], rel=1e-12)


def test_combinations_of_the_pit_walls_sets(tmp_path):
    """configs/wedge_combinations.yaml: six pairs of S1 36/161, S2 60/217, S3 55/129, S4 77/013 against
    the face 65/180. S4 dips into the wall: its three pairs do not form (a row with the reason, no FS).
    S1-S2 slides on S1 alone: FS = tan 30 / tan 36 (planar, c = 0; to 1e-9). Sorted by FS; critical
    below 1.5."""
    outcome, folder = _run(tmp_path, example="wedge_combinations")
    assert outcome.exit_code == 0, outcome.output
    table = pd.read_csv(folder / "combinations.csv")
    assert len(table) == 6
    formed = table[table.forms]
    assert list(zip(formed.plane_1, formed.plane_2, strict=True)) == [
        ("S2", "S3"),
        ("S1", "S2"),
        ("S1", "S3"),
    ]
    assert formed.factor_of_safety.is_monotonic_increasing
    s1_s2 = formed[(formed.plane_1 == "S1") & (formed.plane_2 == "S2")].iloc[0]
    assert s1_s2["mode"] == "sliding on plane 1"
    assert s1_s2.factor_of_safety == pytest.approx(math.tan(R(30)) / math.tan(R(36)), rel=1e-9)
    assert list(formed.critical) == [True, True, False]
    lost = table[~table.forms]
    assert set(lost.plane_2) == {"S4"}
    assert lost.factor_of_safety.isna().all()
    assert lost.reason.str.contains("does not daylight").all()
    assert "lowest FS 0.633: S2 with S3" in outcome.output
    assert "3 of 6 pairs form a wedge, 2 critical" in outcome.output


@pytest.mark.parametrize(
    ("key", "value", "fragments"),
    [
        ("plane_1.dip_deg", 95, ("plane_1.dip_deg",)),
        ("plane_2.dip_deg", -5, ("plane_2.dip_deg",)),
        ("face.dip_deg", 10, ("face.dip_deg", "not steeper than the upper surface")),
        ("height_h1_m", 0, ("height_h1_m",)),
        ("height_h1_m", -30, ("height_h1_m",)),
        ("height_m", 40, ("height_h1_m, height_m", "exactly one")),
        ("water.model", "flooded", ("water.model", "flooded")),
        ("plane_1.strength.law", "hoek_brown", ("plane_1.strength.law",)),
        ("plane_2.dip_direction_deg", 15, ("plane_1, plane_2", "no wedge", "does not daylight")),
        (
            "tension_crack",
            {"dip_deg": 70, "dip_direction_deg": 165, "distance_m": 500},
            ("tension_crack", "no wedge", "crack"),
        ),
    ],
)
def test_bad_input_is_one_line_naming_the_key(tmp_path, key, value, fragments):
    """Each bad input: exit 2, one line naming the file and the key, nothing written."""
    outcome, _ = _run(tmp_path, set_key(key, value))
    line = refused(outcome, tmp_path / "results", "wedge.yaml", *fragments)
    assert "Traceback" not in line


CLASSIC_SI = (MohrCoulomb(23940.129, R(20)), MohrCoulomb(47880.259, R(30)))  # configs/wedge.yaml's c, phi


def _si_classic(strength_1=CLASSIC_SI[0], strength_2=CLASSIC_SI[1], **loads) -> float:
    """The classic wedge built here in SI from configs/wedge.yaml's numbers (a direct call of the
    analysis, no config), with Hoek & Bray's water unless `loads` give another."""
    orientations = WedgeOrientations(R(45), R(105), R(70), R(235), R(65), R(185), R(12), R(195))
    loads = {"water": HoekBrayWater(), "water_unit_weight": 9817.966} | loads
    analysis = analyse_wedges(
        orientations, strength_1, strength_2, unit_weight=25133.994, height_h1=30.48, **loads
    )
    return float(analysis.factor_of_safety)


@pytest.mark.parametrize(
    ("key", "value", "direct"),
    [
        (
            "tension_crack",
            {"dip_deg": 70, "dip_direction_deg": 165, "distance_m": 12.192},  # Hoek & Bray's, L = 40 ft
            {"crack": TensionCrack(R(70), R(165), 12.192)},
        ),
        ("seismic", {"coefficient": 0.1, "direction": "horizontal"}, {"seismic": Seismic(0.1, "horizontal")}),
        (
            "forces",
            [{"magnitude_kN": 20000, "trend_deg": 340, "plunge_deg": 10}],
            {"forces": force_vector(2e7, R(340), R(10))},
        ),
        (
            "water",
            {"model": "pressures", "plane_1_kPa": 60, "plane_2_kPa": 40},
            {"water": PlanePressures(6e4, 4e4)},
        ),
    ],
    ids=["crack", "seismic", "force", "pressures"],
)
def test_the_configs_loads_are_the_analysis_loads_in_si(tmp_path, key, value, direct):
    """Each load typed in the config (degrees, kN, kPa, m) gives the FS of the analysis called directly in
    SI with the same load (to 1e-12: the same arithmetic once the units are turned)."""
    outcome, folder = _run(tmp_path, set_key(key, value))
    assert outcome.exit_code == 0, outcome.output
    fs = pd.read_csv(folder / "wedge.csv").factor_of_safety[0]
    assert fs == pytest.approx(_si_classic(**direct), rel=1e-12)


def test_barton_bandis_scaled_to_the_line_of_intersection(tmp_path):
    """field_length_m: intersection scales JRC and JCS from the lab length to the wedge's line of
    intersection (76.5 m for the classic wedge): the FS of a direct call with that length, to 1e-12."""
    bb = {"law": "barton_bandis", "jrc": 8, "jcs_MPa": 60, "phi_b_deg": 28, "field_length_m": "intersection"}

    def edit(data):
        data["plane_1"]["strength"] = bb
        data["plane_2"]["strength"] = bb

    outcome, folder = _run(tmp_path, edit)
    assert outcome.exit_code == 0, outcome.output
    wedge = pd.read_csv(folder / "wedge.csv").iloc[0]
    length = wedge.intersection_length_m
    strength = BartonBandis(8, 60e6, R(28), R(70), 0.1, length)
    assert wedge.factor_of_safety == pytest.approx(
        _si_classic(strength_1=strength, strength_2=strength), rel=1e-12
    )
    unscaled = BartonBandis(8, 60e6, R(28))
    assert wedge.factor_of_safety < _si_classic(strength_1=unscaled, strength_2=unscaled)


def test_combinations_with_a_basal_plane(tmp_path):
    """A basal plane is paired with every set (the set as plane 1): 6 + 4 rows; the names are kept."""

    def edit(data):
        combinations = yaml.safe_load((CONFIGS / "wedge_combinations.yaml").read_text())
        data.clear()
        data.update(combinations)
        data["combinations"]["basal_plane"] = {
            "dip_deg": 30,
            "dip_direction_deg": 200,
            "strength": {"law": "mohr_coulomb", "friction_deg": 30},
        }

    outcome, folder = _run(tmp_path, edit)
    assert outcome.exit_code == 0, outcome.output
    table = pd.read_csv(folder / "combinations.csv")
    assert len(table) == 10
    assert sorted(table[table.plane_2 == "basal"].plane_1) == ["S1", "S2", "S3", "S4"]


def test_the_drawn_wedge_and_its_files(tmp_path):
    """Each run draws one wedge: the config's (wedge.png, wedge_net.png), or without one the combinations'
    lowest-FS wedge (S2 with S3, named in the legends). vertices.csv and wedge.vtu hold that wedge:
    the VTK file's volume (divergence theorem over its triangles) is wedge.csv's (1e-9 relative), its
    top vertex T is at H above the toe; forces.csv's weight is wedge.csv's."""
    outcome, folder = _run(tmp_path / "one")
    assert outcome.exit_code == 0, outcome.output
    for name in ("wedge.png", "wedge_net.png", "wedge.vtu", "vertices.csv", "forces.csv"):
        assert (folder / name).stat().st_size > 0, name
    wedge = pd.read_csv(folder / "wedge.csv").iloc[0]
    mesh = meshio.read(folder / "wedge.vtu")
    assert enclosed_volume(mesh.points, mesh.cells_dict["triangle"]) == pytest.approx(
        wedge.volume_m3, rel=1e-9
    )
    vertices = pd.read_csv(folder / "vertices.csv").set_index("vertex")
    assert vertices.loc["T", "up_m"] == pytest.approx(wedge.height_m, rel=1e-12)
    forces = pd.read_csv(folder / "forces.csv").set_index("symbol")
    assert forces.loc["W", "size_kN"] == pytest.approx(wedge.weight_kN, rel=1e-12)
    outcome, folder = _run(tmp_path / "pairs", example="wedge_combinations")
    assert outcome.exit_code == 0, outcome.output
    lowest = pd.read_csv(folder / "combinations.csv").iloc[0]
    drawn = pd.read_csv(folder / "forces.csv").set_index("symbol")
    assert drawn.loc["W", "size_kN"] == pytest.approx(lowest.weight_kN, rel=1e-12)
    assert (folder / "wedge.png").stat().st_size > 10_000


def test_each_planes_strength_at_its_stress_is_written(tmp_path):
    """wedge.csv's c and phi per plane: Mohr-Coulomb's own (configs/wedge.yaml: 23.94 kPa, 20 deg; 47.88
    kPa, 30 deg), and for a Barton-Bandis plane the tangent at its sigma_n, which rebuilds its shear
    stress there: tau = c_t + sigma_n tan phi_t (1e-9 relative)."""
    outcome, folder = _run(tmp_path / "mc")
    assert outcome.exit_code == 0, outcome.output
    w = pd.read_csv(folder / "wedge.csv").iloc[0]
    assert (w.cohesion_1_kPa, w.friction_1_deg) == pytest.approx((23.940129, 20.0), rel=1e-12)
    assert (w.cohesion_2_kPa, w.friction_2_deg) == pytest.approx((47.880259, 30.0), rel=1e-12)
    bb = {"law": "barton_bandis", "jrc": 10, "jcs_MPa": 80, "phi_b_deg": 25}
    outcome, folder = _run(tmp_path / "bb", set_key("plane_1.strength", bb))
    assert outcome.exit_code == 0, outcome.output
    w = pd.read_csv(folder / "wedge.csv").iloc[0]
    sigma = w.sigma_n_1_kPa * 1e3
    tau = BartonBandis(10.0, 80e6, R(25)).shear_stress(sigma)
    rebuilt = w.cohesion_1_kPa * 1e3 + sigma * math.tan(R(w.friction_1_deg))
    assert rebuilt == pytest.approx(float(tau), rel=1e-9)
    secant = 25.0 + 10.0 * math.log10(80e6 / sigma)  # B-B's friction angle at sigma_n [deg]
    assert w.friction_1_deg < secant and w.cohesion_1_kPa > 0.0  # the concave envelope's tangent


def test_the_papers_equivalent_mohr_coulomb_at_the_planes_own_stress_is_barton_bandis(tmp_path):
    """`law: equivalent_mohr_coulomb` holds the B-B tangent at a given sigma_n constant (the paper's eqs
    11-14). At each plane's own sigma_n from the B-B run (wedge.csv) the FS is the B-B FS (1e-9
    relative: statics does not depend on the strength); taken at a tenth of that stress the constant
    tangent over-estimates the concave envelope at the plane's real stress, and FS rises."""
    bb = {"law": "barton_bandis", "jrc": 10, "jcs_MPa": 80, "phi_b_deg": 25, "field_length_m": "intersection"}

    def both(law: str, scale: float = 1.0, sigmas=(0.0, 0.0)):
        def edit(data):
            for k, key in enumerate(("plane_1", "plane_2")):
                extra = {"law": law, "sigma_n_kPa": sigmas[k] * scale} if law != "barton_bandis" else {}
                data[key]["strength"] = bb | extra

        return edit

    outcome, folder = _run(tmp_path / "bb", both("barton_bandis"))
    assert outcome.exit_code == 0, outcome.output
    w = pd.read_csv(folder / "wedge.csv").iloc[0]
    sigmas = (float(w.sigma_n_1_kPa), float(w.sigma_n_2_kPa))
    fs = {}
    for scale in (1.0, 0.1):
        outcome, folder = _run(tmp_path / f"eq{scale}", both("equivalent_mohr_coulomb", scale, sigmas))
        assert outcome.exit_code == 0, outcome.output
        fs[scale] = pd.read_csv(folder / "wedge.csv").factor_of_safety[0]
    assert fs[1.0] == pytest.approx(w.factor_of_safety, rel=1e-9)
    assert fs[0.1] > w.factor_of_safety


def test_an_upper_surface_dipping_away_from_the_face_is_a_ridge_not_refused(tmp_path):
    """The face steeper than the upper surface is judged on the upper surface's apparent dip in the
    face's dip direction: an upper surface 45/005 behind a face 40/185 dips away (a ridge) and is taken
    (the wedge forms or gives its own reason); 12/195 behind a face 10/185 is refused naming the key."""
    outcome, _ = _run(tmp_path / "ridge", set_key("upper_surface", {"dip_deg": 45, "dip_direction_deg": 5}))
    assert "not steeper than the upper surface" not in outcome.output
    outcome, _ = _run(tmp_path / "flat", set_key("face", {"dip_deg": 10, "dip_direction_deg": 185}))
    refused(outcome, tmp_path / "flat" / "results", "wedge.yaml", "face.dip_deg", "not steeper")
