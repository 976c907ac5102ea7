"""What every command does with its input alike: a misspelt key is named in the user's own path with
the closest valid key; a value outside its plausible range for rock is a one-line warning (an error
with --strict); the file is given as an argument or with --config, the same; help shows only defaults
that exist. Every refusal is one line naming the file, exit 2, nothing written."""

from __future__ import annotations

import copy
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner, Result

from bbmc import api, paper_tables, plausibility
from bbmc.cli import main
from bbmc.config import ConfigError, validate
from bbmc.dem.model import build_model
from bbmc.geometry.polygons import joint_set_trace
from bbmc.plausibility import ImplausibleValue
from bbmc.scene.schema import Scene
from bbmc.scene.schema3d import Scene3D
from bbmc.stages import audit, bench, fit, joint, joints, kinematics, mc, shear, slope, wedge
from bbmc.sweep.config import Config as Study
from stage_runs import PAPER, config_copy
from stage_runs import refused as _refused

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = ROOT / "configs"
SCENE = CONFIGS / "scenes" / "planar_crack.yaml"
EXAMPLE = CONFIGS / "scenes" / "example.yaml"
STUDY = CONFIGS / "sweeps" / "planar_block.yaml"
STAGE_MODELS = {
    "fit": fit.Config,
    "mc": mc.Config,
    "audit": audit.Config,
    "joint": joint.Config,
    "joints": joints.Config,
    "kinematics": kinematics.Config,
    "shear": shear.Config,
    "slope": slope.Config,
    "bench": bench.Config,
    "wedge": wedge.Config,
    "wedge_combinations": wedge.Config,
    "wedge_pit": wedge.Config,
    "wedge_bench_le": wedge.Config,
}
EVERY_CONFIG = sorted(CONFIGS.glob("**/*.yaml"))


def _invoke(*args: object) -> Result:
    return CliRunner().invoke(main, [str(a) for a in args])


def _model_of(path: Path):
    if path.parent.name == "scenes":
        return Scene3D if yaml.safe_load(path.read_text()).get("dimension") == 3 else Scene
    if path.parent.name == "sweeps":
        return Study
    return STAGE_MODELS[path.stem]


def _source_tree(source: Path, tmp_path: Path) -> dict:
    """The file's content, with a stage config's data paths made absolute (so its copy still finds them)."""
    if source.parent == CONFIGS:
        return yaml.safe_load(config_copy(tmp_path, source.stem, lambda _: None).read_text())
    return yaml.safe_load(source.read_text())


def _parts(dotted: str) -> tuple:
    return tuple(int(p) if p.isdigit() else p for p in dotted.split("."))


def _renamed(tree: dict, path: tuple, new: str) -> dict:
    tree = copy.deepcopy(tree)
    *parents, key = path
    node = tree
    for part in parents:
        node = node[part]
    node[new] = node.pop(key)
    return tree


def _key_paths(tree: object, path: tuple = ()):
    if isinstance(tree, dict):
        for key, value in tree.items():
            yield (*path, key)
            yield from _key_paths(value, (*path, key))
    elif isinstance(tree, list):
        for index, value in enumerate(tree):
            yield from _key_paths(value, (*path, index))


# (command, file, sections added first, the key's dotted path, its misspelling)
TYPOS = [
    ("fos", SCENE, {}, "joint_laws.plane.friction_deg", "friction_dge"),
    ("fos", SCENE, {}, "joint_laws.plane.law", "laws"),
    ("fos", SCENE, {}, "materials.rock.density_kg_m3", "density_kg_m"),
    ("fos", SCENE, {}, "water.unit_weight_kN_m3", "unit_weigth_kN_m3"),
    (
        "fos",
        SCENE,
        {"seismic": {"horizontal_coefficient": 0.1}},
        "seismic.horizontal_coefficient",
        "horizontal_coeficient",
    ),
    ("run", EXAMPLE, {}, "joint_laws.paper_joint.shear_stiffness.kj_MPa_per_mm", "kj_MPa_mm"),
    ("run", EXAMPLE, {}, "blocks.1.brick_wall.block_width_m", "block_widht_m"),
    ("sweep", STUDY, {}, "base.strength.tan_friction", "tan_frictoin"),
    ("sweep", STUDY, {}, "base.plane_deg", "plane_dip_deg"),
    ("sweep", STUDY, {}, "variables.0.distribution", "distrbution"),
    ("mc", CONFIGS / "mc.yaml", {}, "errata.lg_e", "lg_ee"),
    ("slope", CONFIGS / "slope.yaml", {}, "slope.joint_sets.1.spacing_m", "spacing"),
    ("shear", CONFIGS / "shear.yaml", {}, "specimen.length_mm", "lenght_mm"),
]


@pytest.mark.parametrize(("command", "source", "added", "dotted", "typo"), TYPOS)
def test_a_misspelt_key_is_named_in_the_users_path_with_the_closest_key(
    tmp_path, command, source, added, dotted, typo
):
    tree = _source_tree(source, tmp_path) | added
    path = tmp_path / source.name
    path.write_text(yaml.safe_dump(_renamed(tree, _parts(dotted), typo)))
    out = tmp_path / "out"
    shown = ".".join([*dotted.split(".")[:-1], typo])
    key = dotted.rsplit(".", 1)[-1]
    _refused(
        _invoke(command, path, "--results", out), out, str(path), f"key '{shown}'", f"did you mean '{key}'"
    )


@pytest.mark.parametrize("source", EVERY_CONFIG, ids=lambda p: str(p.relative_to(CONFIGS)))
def test_every_key_of_every_config_misspelt_names_the_users_path_and_the_key(source, tmp_path):
    """Each key of each config, scene and study in configs/ in turn given a doubled last letter: a
    refusal names the misspelt key in the user's path (no law variant or union member inserted) and
    suggests the key. Keys the user names (materials, joint laws, variants) are not refused."""
    tree = _source_tree(source, tmp_path)
    refused = 0
    for path in _key_paths(tree):
        key = str(path[-1])
        typo = key + key[-1]
        try:
            validate(_renamed(tree, path, typo), _model_of(source), "f", source.parent)
        except ConfigError as error:
            refused += 1
            shown = ".".join(map(str, (*path[:-1], typo)))
            assert f"key '{shown}'" in str(error) and f"did you mean '{key}'" in str(error), str(error)
    assert refused > 0


def test_a_misspelt_choice_suggests_the_closest(tmp_path):
    tree = yaml.safe_load(SCENE.read_text())
    tree["joint_laws"]["plane"]["law"] = "constnt"
    tree["solver"]["time_step"] = {"mode": "fixd", "step_s": 0.01}
    with pytest.raises(ConfigError, match=r"key 'joint_laws.plane.law': .*did you mean 'constant'"):
        validate(tree, Scene, "s.yaml")
    tree["joint_laws"]["plane"]["law"] = "constant"
    with pytest.raises(ConfigError, match=r"key 'solver.time_step.mode': .*did you mean 'fixed'"):
        validate(tree, Scene, "s.yaml")


# ---------------------------------------------------------------- the labels a contact rule names

BENCHED = CONFIGS / "scenes" / "benched_rock_mass.yaml"
FIRST_SLOPE = ROOT / "docs" / "examples" / "first-slope" / "slope.yaml"


def _ruled(source: Path, edges: str, names: list[str | None]) -> dict:
    """The scene with its first block's joint sets named `names` (None: no name) and a first contact
    rule giving the law 'weak' (friction 20 deg) to the contacts on edges labelled `edges`."""
    tree = yaml.safe_load(source.read_text())
    shape = tree["blocks"][0].get("jointed_slope") or tree["blocks"][0]["rock_mass"]
    for joint_set, name in zip(shape["joint_sets"], names, strict=True):
        joint_set.pop("name", None)
        joint_set.update({"name": name} if name else {})
    tree["joint_laws"]["weak"] = tree["joint_laws"]["joint"] | {"friction_deg": 20}
    tree["contacts"]["rules"] = [{"law": "weak", "edges": edges}, *tree["contacts"].get("rules", [])]
    return tree


@pytest.mark.parametrize(
    ("source", "names", "edges", "key", "hint"),
    [
        (BENCHED, ["bedding", "cross"], "bridge.beding", "contacts.rules.0.edges", "'bridge.bedding'?"),
        (BENCHED, ["bedding", "cross"], "bridge.Bedding", "contacts.rules.0.edges", "'bridge.bedding'?"),
        (BENCHED, ["bedding", "cross"], "jiont.cross", "contacts.rules.0.edges", "'joint.cross'?"),
        (FIRST_SLOPE, ["foliation", None], "joint.foliaton", "contacts.rules.0.edges", "'joint.foliation'?"),
        (FIRST_SLOPE, [None, None], "joint.foliation", "contacts.rules.0.edges", "joint.J1"),
        (FIRST_SLOPE, ["J2", None], "joint.J2", "blocks.0.jointed_slope", "'J2' is given twice"),
    ],
)
def test_a_rule_on_a_label_no_edge_can_carry_is_refused_with_the_closest(
    tmp_path, source, names, edges, key, hint
):
    """A misspelt label (wrong letters or case, or an unnamed set's) selected nothing and left its
    contacts on the default law, the run going on: it is refused naming the file and the key, with the
    closest label the scene's edges can carry; nothing is written."""
    path = tmp_path / source.name
    path.write_text(yaml.safe_dump(_ruled(source, edges, names)))
    out = tmp_path / "out"
    _refused(_invoke("run", path, "--results", out), out, str(path), f"key '{key}'", hint)


def test_a_rule_on_a_named_set_of_a_jointed_slope_gives_its_joints_the_law():
    """The slope's bedding named 'bedding' (the cross joints left unnamed: J2): `edges: joint.bedding`
    gives the law 'weak' to exactly the contacts along a bedding joint, the others keep the default."""
    tree = _ruled(FIRST_SLOPE, "joint.bedding", ["bedding", None])
    tree["solver"]["steps"] = 20
    model = build_model(api.load_scene(tree), FIRST_SLOPE)
    assert model.label_names == ["", "joint.J2", "joint.bedding"]
    assert model.rule_edges[0].tolist() == [False, False, True]
    contacts = api.run(tree).contacts
    bedding = tree["blocks"][0]["jointed_slope"]["joint_sets"][0]
    *normal, factor = joint_set_trace(bedding["dip_deg"], bedding["dip_direction_to_face_deg"])
    place = contacts[["x_m", "y_m"]].to_numpy() @ normal / (bedding["spacing_m"] / factor)
    on_bedding = np.abs(place - np.round(place)) < 1e-3
    assert on_bedding.any() and not on_bedding.all()
    assert contacts["joint_law"].tolist() == np.where(on_bedding, "weak", "joint").tolist()


# ---------------------------------------------------------------- plausible ranges


def _with(source: Path, tmp_path: Path, dotted: str, value: object) -> Path:
    tree = _source_tree(source, tmp_path)
    *parents, key = _parts(dotted)
    node = tree
    for part in parents:
        node = node[part]
    node[key] = value
    path = tmp_path / source.name
    path.write_text(yaml.safe_dump(tree))
    return path


def test_a_friction_coefficient_typed_as_degrees_is_warned_about_naming_the_slip(tmp_path):
    """friction_deg 0.6 in a study: one warning line naming the file, the key, the range and the slip
    (tan phi 0.6 is 31 deg); the study still runs."""
    study = yaml.safe_load(STUDY.read_text())
    study["base"]["strength"] = {"law": "mohr_coulomb", "friction_deg": 0.6}
    study["variables"] = [{"path": "height_m", "distribution": "uniform", "min": 19.0, "max": 21.0}]
    study["sampling"]["samples"] = 20
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    outcome = _invoke("sweep", path, "--workers", 1, "--results", tmp_path / "out")
    assert outcome.exit_code == 0, outcome.output
    warnings = [line for line in outcome.stderr.splitlines() if "warning" in line]
    assert warnings == [
        f"bbmc sweep: warning: {path}: key 'base.strength.friction_deg' = 0.6 is outside 5 to 70 deg "
        "for the friction angle of a rock joint: a friction coefficient (tan phi) typed as degrees? "
        "(31 deg if so)"
    ]


@pytest.mark.parametrize(
    ("command", "source", "dotted", "value", "slip"),
    [
        ("fos", SCENE, "joint_laws.plane.friction_deg", 0.6, "tan phi"),
        ("run", SCENE, "materials.rock.density_kg_m3", 25.5, "kN/m^3 typed as kg/m^3"),
        ("fos", SCENE, "water.unit_weight_kN_m3", 1000, "kg/m^3 typed as kN/m^3"),
        ("fos", SCENE, "joint_laws.plane.cohesion_MPa", 48, "kPa typed as MPa"),
        ("sweep", STUDY, "variables.0.mean", 38.7, "an angle in degrees typed as tan phi"),
        ("mc", CONFIGS / "mc.yaml", "joint.jcs_MPa", 3310, "kPa typed as MPa"),
        ("joint", CONFIGS / "joint.yaml", "lab_length_m", 100, "mm typed as m"),
    ],
)
def test_strict_refuses_an_implausible_value(tmp_path, command, source, dotted, value, slip):
    path = _with(source, tmp_path, dotted, value)
    out = tmp_path / "out"
    _refused(_invoke(command, path, "--strict", "--results", out), out, str(path), dotted, slip, "--strict")


@pytest.mark.parametrize(
    ("key", "value", "slip"),
    [
        ("joint_laws.j.friction_deg", 0.6, "a friction coefficient (tan phi) typed as degrees"),
        ("strength.tan_friction", 35, "an angle in degrees typed as tan phi"),
        ("materials.rock.density_kg_m3", 26, "a unit weight in kN/m^3 typed as kg/m^3"),
        ("materials.rock.density_kg_m3", 2.65, "g/cm^3 (t/m^3) typed as kg/m^3"),
        ("base.unit_weight_kN_m3", 2650, "a density in kg/m^3 typed as kN/m^3"),
        ("base.unit_weight_kN_m3", 26000, "N/m^3 typed as kN/m^3"),
        ("water.unit_weight_kN_m3", 1000, "a density in kg/m^3 typed as kN/m^3"),
        ("joint_laws.j.kn_MPa_per_mm", 20000, "MPa/m (or kPa/mm) typed as MPa/mm"),
        ("joint_laws.j.cohesion_MPa", 48, "kPa typed as MPa"),
        ("base.strength.cohesion_kPa", 48000, "Pa typed as kPa"),
        ("joint_laws.j.strength.jcs_MPa", 50000, "kPa typed as MPa"),
        ("seismic.horizontal_coefficient", 0.98, "an acceleration in m/s^2 typed as a fraction of g"),
        ("base.face_deg", 1.05, "radians typed as degrees"),
        ("field_length_m", 5000, "mm typed as m"),
        ("joint_laws.j.friction_deg", 80, None),
    ],
)
def test_each_slip_is_named_where_it_explains_the_value(key, value, slip):
    """The slip named is one whose conversion brings the value into range; none is guessed otherwise."""
    problem = plausibility.verdict(key, value)
    assert problem is not None and problem.startswith("is outside")
    if slip is None:
        assert "?" not in problem
    else:
        assert f": {slip}?" in problem


def test_a_variable_is_checked_at_its_path_and_its_spread_is_not():
    tree = {"variables": [{"path": "strength.friction_deg", "distribution": "normal", "mean": 0.6, "std": 2}]}
    assert plausibility.implausible_values(tree, "s.yaml") == [
        "s.yaml: key 'variables.0.mean' (strength.friction_deg) = 0.6 is outside 5 to 70 deg for the "
        "friction angle of a rock joint: a friction coefficient (tan phi) typed as degrees? (31 deg if so)"
    ]


def test_the_files_a_config_names_are_checked_too(tmp_path):
    """A study's scene and the audit's mc config, each with an implausible value: --strict refuses it
    naming that file, before any work."""
    scene = _with(SCENE, tmp_path, "joint_laws.plane.friction_deg", 0.6)
    study = {
        "name": "s",
        "base": {"kind": "scene_fos", "scene": scene.name},
        "variables": [
            {"path": "joint_laws.plane.cohesion_MPa", "distribution": "uniform", "min": 0, "max": 1}
        ],
        "sampling": {"method": "monte_carlo", "samples": 2},
    }
    (tmp_path / "study.yaml").write_text(yaml.safe_dump(study))
    out = tmp_path / "out"
    _refused(
        _invoke("sweep", tmp_path / "study.yaml", "--strict", "--results", out),
        out,
        f"{scene}: key 'joint_laws.plane.friction_deg' = 0.6",
    )
    mc_config = _with(CONFIGS / "mc.yaml", tmp_path, "joint.jcs_MPa", 3310)
    audit_config = config_copy(tmp_path, "audit", lambda data: data.update(mc_config=str(mc_config)))
    _refused(
        _invoke("audit", audit_config, "--strict", "--results", out),
        out,
        f"{mc_config}: key 'joint.jcs_MPa' = 3310",
    )


@pytest.mark.parametrize(
    ("key", "value", "plausible"),
    [
        ("shear_stiffness.ks_MPa_per_mm", 0.0001, True),  # the paper's Table 3 tangent K_s near the peak
        ("shear_stiffness.ks_MPa_per_mm", 0.0027, True),
        ("shear_stiffness.ks_MPa_per_mm", 2e-5, True),  # (100 / 50 m) x 0.01 MPa: a field block (Barton 1982)
        ("shear_stiffness.ks_MPa_per_mm", 5e-6, False),
        ("strength.kj_MPa_per_mm", 2e-5, True),
        ("normal_stiffness.kn_MPa_per_mm", 0.002, True),  # E_m / s = 0.1 GPa / 50 m (Goodman 1989)
        ("normal_stiffness.kn_MPa_per_mm", 0.0005, False),
        ("normal_stiffness.kn_MPa_per_mm", 2000, False),
    ],
)
def test_joint_stiffness_ranges_reach_field_blocks(key, value, plausible):
    """K_s falls as 1/L with the block length (docs/plausible-ranges.md): the field's and the paper's
    near-peak K_s are plausible; K_n has its own floor, from a rock mass's modulus."""
    assert (plausibility.verdict(key, value) is None) == plausible


@pytest.mark.parametrize(
    ("key", "value", "refused"),
    [
        ("joint_laws.j.cohesion_kPa", 4.8e300, True),
        ("joint_laws.j.cohesion_kPa", 1e9, False),  # 10^6 x the high end: warned, not refused
        ("joint_laws.j.cohesion_kPa", 1.0001e9, True),
        ("joint_laws.j.friction_deg", 4e-6, True),  # below 5 deg / 10^6
        ("joint_laws.j.friction_deg", 6e-6, False),
        ("joint_laws.j.friction_deg", 0.0, False),  # a frictionless joint: a model's choice
        ("strength.tan_friction", -5.0, False),  # negative: no slip of magnitude, the key's own checks
        ("joint_laws.j.sigma_n_MPa", -1.0001e8, True),  # below 10^6 x a negative low end
        ("joint_laws.j.sigma_n_MPa", -1e-300, False),
        ("solver.steps", 1e300, False),  # no plausible range: not judged here
    ],
)
def test_a_value_far_beyond_its_range_is_refused(key, value, refused):
    assert (plausibility.beyond(key, value) is not None) == refused


@pytest.mark.parametrize("strict", [[], ["--strict"]])
def test_a_config_value_far_beyond_its_range_is_refused_without_strict(tmp_path, strict):
    path = _with(SCENE, tmp_path, "joint_laws.plane.cohesion_MPa", 4.8e300)
    out = tmp_path / "out"
    _refused(
        _invoke("fos", path, *strict, "--results", out),
        out,
        f"{path}: key 'joint_laws.plane.cohesion_MPa' = 4.8e+300 is more than a factor of 10^6 outside",
    )


@pytest.mark.parametrize(
    ("table", "column", "value", "shown"),
    [
        ("table4_joints_constant", "c_kPa", "4.8e300", "= 4.8e+300 is more than a factor of 10^6 outside"),
        ("fig2a_legends", "slope_a", "1e308", "= 1e+308 (1e-311 MPa/mm as ks_MPa_per_mm)"),
        ("fig2a_legends", "sigma_n_kPa", "1e308", "= 1e+308 (1e+305 MPa as sigma_n_MPa)"),
        ("table1_measurements", "K_si_GPa_per_m", "1e-12", "= 1e-12 is more than a factor"),
    ],
)
def test_a_data_file_number_far_beyond_its_range_is_refused(tmp_path, table, column, value, shown):
    """As in a config: one line naming the file, the line and the column (a data file's numbers are the
    paper's: only refused, never warned about)."""
    rows = (PAPER / f"{table}.csv").read_text().splitlines()
    header = rows[0].split(",")
    cells = rows[1].split(",")
    cells[header.index(column)] = value
    path = tmp_path / f"{table}.csv"
    path.write_text("\n".join([rows[0], ",".join(cells), *rows[2:]]) + "\n")
    with pytest.raises(ConfigError, match=re.escape(f"{path}: line 2: column '{column}' {shown}")):
        paper_tables.read(table, path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        paper_tables.read(table, PAPER / f"{table}.csv")


def test_the_python_api_warns_about_an_implausible_value():
    scene = yaml.safe_load(SCENE.read_text())
    scene["joint_laws"]["plane"]["friction_deg"] = 0.6
    with pytest.warns(ImplausibleValue, match=r"<scene dict>: key 'joint_laws.plane.friction_deg' = 0.6"):
        api.load_scene(scene)


@pytest.mark.parametrize("source", EVERY_CONFIG, ids=lambda p: str(p.relative_to(CONFIGS)))
def test_the_shipped_configs_raise_no_warning(source, tmp_path):
    """Each config as shipped (a stage config's paths made absolute, and a `bbmc kinematics` result it
    reads given in its form: `stage_runs.config_copy`) validates with no plausibility warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleValue)
        validate(_source_tree(source, tmp_path), _model_of(source), str(source), source.parent)


def test_the_docs_table_is_the_modules():
    assert plausibility.markdown_table() in (ROOT / "docs" / "plausible-ranges.md").read_text()


# ---------------------------------------------------------------- the file of a command


def _tiny_study(tmp_path: Path) -> Path:
    study = yaml.safe_load(STUDY.read_text())
    study["sampling"]["samples"] = 50
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    return path


def test_sweep_takes_its_study_as_an_argument_or_with_config_alike(tmp_path):
    study = _tiny_study(tmp_path)
    by_argument = _invoke("sweep", study, "--workers", 1, "--results", tmp_path / "a")
    by_option = _invoke("sweep", "--config", study, "--workers", 1, "--results", tmp_path / "b")
    assert by_argument.exit_code == 0 and by_option.exit_code == 0, by_argument.output + by_option.output
    samples = [pd.read_csv(tmp_path / r / "sweep" / "planar_block" / "samples.csv") for r in ("a", "b")]
    pd.testing.assert_frame_equal(*samples)
    assert len(samples[0]) == 50


def test_fos_takes_its_scene_as_an_argument_or_with_config_alike(tmp_path):
    """The same scene through either route: the same file read (the same one-line refusal of its
    misspelt key, before any step runs)."""
    path = tmp_path / "scene.yaml"
    path.write_text(SCENE.read_text().replace("friction_deg: 30", "friction_dge: 30"))
    out = tmp_path / "out"
    lines = {
        _refused(_invoke("fos", *how, path, "--results", out), out, str(path)) for how in ([], ["--config"])
    }
    assert len(lines) == 1 and "did you mean 'friction_deg'" in lines.pop()


@pytest.mark.parametrize("command", ["fos", "run", "sweep"])
def test_a_command_given_no_file_says_so_in_one_line(tmp_path, command):
    _refused(
        _invoke(command, "--results", tmp_path / "out"), tmp_path / "out", f"bbmc {command} ", "--config"
    )


def test_a_file_given_twice_over_is_refused(tmp_path):
    out = tmp_path / "out"
    _refused(_invoke("sweep", STUDY, "--config", EXAMPLE, "--results", out), out, "given twice", "once")


def test_a_missing_default_says_where_it_was_looked_for(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _refused(
        _invoke("fit", "--results", tmp_path / "out"), tmp_path / "out", "configs/fit.yaml", "the default"
    )


@pytest.mark.parametrize("command", sorted(set(main.commands) - {"warmup"}))  # warmup reads no file
def test_help_shows_only_defaults_that_exist(command):
    """Every default a command's help shows that names a file is a file of the repository (run from
    its root, as the help's examples are); fos, run and sweep have none."""
    text = " ".join(_invoke(command, "--help").output.split())
    defaults = re.findall(r"\[default: ([^\]]+)\]", text)
    files = [d for d in defaults if d.endswith(".yaml")]
    assert all((ROOT / f).is_file() for f in files), files
    assert bool(files) == (command not in ("fos", "run", "sweep")), defaults
    metavar = {"fos": "SCENE", "run": "SCENE", "sweep": "STUDY", "wedge": "WEDGE"}.get(command, "CONFIG")
    assert f"[{metavar}.yaml]" in text
