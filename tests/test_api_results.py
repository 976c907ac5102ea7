"""Scenes varied from Python and results one can inspect (issue 33, items 4 and 5): `api.with_values`,
`threads=`, names with dots, the one progress protocol, the FS shown to the decimals its bracket
supports, the mechanism as a table by block, the bridges and support tables of a run, and the column
lists of the guide against the DataFrames."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from click.testing import CliRunner

from bbmc import api
from bbmc.cli import main
from bbmc.dem import kernels
from bbmc.dem import layout as L
from bbmc.outputs.figures import fos_title
from bbmc.plausibility import ImplausibleValue
from bbmc.progress_bar import ProgressBar
from bbmc.slope import fos_cases as fc
from bbmc.stages import fos as fos_stage
from bbmc.stages import run as run_stage

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "configs" / "scenes"
INCLINE, CRACK, BOLTED = SCENES / "incline.yaml", SCENES / "planar_crack.yaml", SCENES / "bolted_planar.yaml"


@pytest.fixture(scope="module")
def crack_fos() -> api.StrengthReductionResult:
    return api.factor_of_safety(CRACK)


def test_with_values_gives_a_new_validated_scene_and_leaves_the_old_one():
    scene = api.load_scene(SCENES / "benched_rock_mass.yaml")
    varied = api.with_values(scene, {"blocks.0.rock_mass.seed": 5, "materials.limestone.density_kg_m3": 2500})
    assert isinstance(varied, api.Scene)
    assert varied.blocks[0].rock_mass.seed == 5 and varied.materials["limestone"].density_kg_m3 == 2500
    assert scene.blocks[0].rock_mass.seed == 3 and scene.materials["limestone"].density_kg_m3 == 2600
    assert api.with_values(scene, {}) == scene
    assert api.get_path(varied.model_dump(), "blocks.0.rock_mass.seed") == 5


@pytest.mark.parametrize(
    "values, fragment",
    [
        (
            {"blocks.0.rock_mass.sed": 5},
            "key 'blocks.0.rock_mass.sed': no 'sed' there (did you mean 'seed'?)",
        ),
        (
            {"blocks.7.name": "x"},
            "key 'blocks.7.name': no '7' there ('blocks' is a list of 1: index 0 only)",
        ),
        ({"materials.limestone.density_kg_m3": -1.0}, "key 'materials.limestone.density_kg_m3'"),
        ({"solver.steps": "many"}, "key 'solver.steps'"),
    ],
)
def test_with_values_refuses_a_bad_path_or_value_in_one_line_naming_it(values, fragment):
    scene = api.load_scene(SCENES / "benched_rock_mass.yaml")
    with pytest.raises(api.ConfigError) as error:
        api.with_values(scene, values)
    assert fragment in str(error.value) and "\n" not in str(error.value)
    assert str(error.value).startswith("<scene benched_rock_mass>: ")


def test_with_values_warns_of_an_implausible_value_as_loading_does():
    scene = api.load_scene(CRACK)
    with pytest.warns(ImplausibleValue, match="density_kg_m3"):
        api.with_values(scene, {"materials.rock.density_kg_m3": 6000.0})


def test_one_and_two_threads_give_the_same_run_and_factor_of_safety_to_the_bit(monkeypatch):
    """`threads=` as `bbmc run --threads`: the threaded path taken on these small scenes too."""
    monkeypatch.setattr(kernels, "THREADED_FROM_CONTACTS", 0)
    one, two = api.run(INCLINE, threads=1), api.run(INCLINE, threads=2)
    assert one.state.threads == 1 and two.state.threads == min(2, kernels.thread_count(None))
    assert np.array_equal(one.state.blocks, two.state.blocks)
    for table in ("history", "blocks", "contacts", "summary"):
        pd.testing.assert_frame_equal(getattr(one, table), getattr(two, table), check_exact=True)
    fos_one, fos_two = api.factor_of_safety(CRACK, threads=1), api.factor_of_safety(CRACK, threads=2)
    assert fos_one.factor_of_safety == fos_two.factor_of_safety
    assert fos_one.bracket == fos_two.bracket
    timeless = [c for c in fos_one.trials_table.columns if c != "wall_time_s"]
    pd.testing.assert_frame_equal(fos_one.trials_table[timeless], fos_two.trials_table[timeless])
    pd.testing.assert_frame_equal(fos_one.mechanism, fos_two.mechanism, check_exact=True)


@pytest.mark.parametrize("threads", [0, 1.5, "2"])
def test_threads_must_be_a_whole_number_of_one_or_more(threads):
    with pytest.raises(api.ConfigError, match="threads"):
        api.run(INCLINE, threads=threads)


@pytest.mark.parametrize("name", ["benched_f62.5", "face 62.5 deg", "pente_à_62,5°", ".hidden", "a..b"])
def test_a_scene_name_is_any_name_a_folder_can_have(name):
    data = yaml.safe_load(INCLINE.read_text())
    assert api.load_scene({**data, "name": name}).name == name


@pytest.mark.parametrize("name", ["", ".", "..", "a/b", "a\\b", "a\0b"])
def test_a_scene_name_that_cannot_name_a_folder_is_refused_in_one_line(name):
    data = yaml.safe_load(INCLINE.read_text())
    with pytest.raises(api.ConfigError) as error:
        api.load_scene({**data, "name": name})
    assert "key 'name': not a folder's name" in str(error.value) and "\n" not in str(error.value)


def test_bbmc_run_and_fos_write_into_a_folder_named_with_dots(tmp_path):
    data = yaml.safe_load(CRACK.read_text()) | {"name": "benched_f62.5"}
    path = tmp_path / "crack.yaml"
    path.write_text(yaml.safe_dump(data))
    for command in ("run", "fos"):
        outcome = CliRunner().invoke(main, [command, str(path), "--results", str(tmp_path / "out")])
        assert outcome.exit_code == 0, outcome.output
        folder = tmp_path / "out" / command / "benched_f62.5"
        assert (folder / "summary.csv").is_file() and (folder / "provenance.json").is_file()
    assert (tmp_path / "out" / "fos" / "benched_f62.5" / "mechanism.png").is_file()


def test_run_and_factor_of_safety_report_progress_in_one_protocol(crack_fos):
    reports: list[api.Progress] = []
    result = api.run(INCLINE, progress=reports.append)
    steps = int(result.summary.set_index("quantity").loc["steps", "value"])
    assert reports and {(r.unit, r.total) for r in reports} == {
        ("steps", api.load_scene(INCLINE).solver.steps)
    }
    done = [r.done for r in reports]
    assert done == sorted(done) and done[-1] == steps and reports[-1].text.startswith(f"step {steps} of")
    trials: list[api.Progress] = []
    fos = api.factor_of_safety(CRACK, progress=trials.append)
    assert {(r.unit, r.total) for r in trials} == {("trials", None)}
    assert trials[0].done == 0 and trials[0].text.startswith("equilibrium")
    assert trials[-1].done == len(fos.trials) and trials[-1].text.startswith(f"trial {len(fos.trials)}: F = ")


def test_the_command_lines_progress_bar_follows_done_of_total(capsys):
    bar = ProgressBar(100, "run", after=-1.0)
    for done in (30, 70, 100):
        bar(api.Progress(done, 100, "steps", f"step {done} of 100"))
    assert bar.bar is not None and bar.bar.pos == 100
    bar.close()


@pytest.mark.parametrize(
    "fs, bracket, bracketed, text",
    [
        (0.83984375, (0.8359375, 0.84375), True, "0.840"),  # the midpoint, once 0.8398
        (1.13671875, (1.1328125, 1.140625), True, "1.137"),
        (1.11328125, (1.109375, 1.1171875), True, "1.113"),
        (1.11, (1.1, 1.12), True, "1.11"),  # a bracket 0.02 wide: two decimals
        (1.05, (1.0, 1.1), True, "1.1"),  # 0.1 wide: one decimal (an FS tolerance of 0.1)
        (20.0, (20.0, float("inf")), False, "> 20"),
        (0.05, (0.0, 0.05), False, "< 0.05"),
        (1.0, (1.0, float(np.nextafter(1.0, 2.0))), True, "1.000000000000"),  # bisected to round-off
    ],
)
def test_the_factor_of_safety_is_shown_to_the_decimals_its_bracket_supports(fs, bracket, bracketed, text):
    assert api.factor_of_safety_text(fs, bracket, bracketed) == text


def test_the_command_the_figures_and_the_result_show_the_same_factor_of_safety(tmp_path, crack_fos):
    text = crack_fos.factor_of_safety_text
    assert text == "1.113" and crack_fos.factor_of_safety == 1.11328125  # the full number kept
    assert f"factor of safety {text} (between 1.10938 (holds) and 1.11719 (fails)" in str(crack_fos)
    assert "(FS 1.113)" in repr(crack_fos) and "factor_of_safety=1.11328125" in repr(crack_fos)
    assert fos_title(crack_fos).startswith(f"FS = {text},")
    assert f"FS = {text}" in api.bracketing_figure(crack_fos).axes[0].get_legend_handles_labels()[1]
    outcome = CliRunner().invoke(main, ["fos", str(CRACK), "--results", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output
    assert f"bbmc fos: factor of safety {text}, {len(crack_fos.trials)} trials" in outcome.output
    written = pd.read_csv(tmp_path / "fos" / "planar_crack" / "mechanism.csv")
    pd.testing.assert_frame_equal(written, crack_fos.mechanism, check_dtype=False)


def test_the_mechanism_is_a_table_by_block(crack_fos):
    """One row per block for each of the two trials; the held block has not moved, the wedge has, as
    far as its vertices in `mechanism_world` say (a translation: its centroid moved as its vertices)."""
    model, table = crack_fos.model, crack_fos.mechanism
    assert list(table["trial"].unique()) == ["last_stable", "first_unstable"]
    assert list(table["factor"].unique()) == list(crack_fos.bracket)
    for _, rows in table.groupby("trial"):
        assert list(rows["block_id"]) == list(range(len(model.block_names)))
        assert list(rows["block"]) == model.block_names
    failing = table[table["trial"] == "first_unstable"].set_index("block")
    assert not failing.loc["rock_below", "free"] and failing.loc["rock_below", "displacement_mm"] == 0.0
    wedge = model.block_names.index("wedge")
    start, end = model.vertex_start[wedge], model.vertex_start[wedge + 1]
    vertices = np.hypot(*(crack_fos.mechanism_world[start:end] - crack_fos.start_world[start:end]).T) * 1e3
    assert failing.loc["wedge", "displacement_mm"] == pytest.approx(vertices.mean(), rel=1e-3)
    assert failing.loc["wedge", "size_m"] == crack_fos.start_blocks[wedge, L.SIZE] > 0


def test_a_run_carries_its_support_and_bridges_tables(tmp_path):
    """The tables `bbmc run` writes as support.csv and bridges.csv; without support or bridges, no rows
    and the same columns."""
    bolted = api.run(BOLTED)
    assert list(bolted.support["support"].unique()) == ["anchors"] and len(bolted.bridges) == 0
    outcome = CliRunner().invoke(main, ["run", str(BOLTED), "--results", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output
    written = pd.read_csv(tmp_path / "run" / "bolted_planar" / "support.csv")
    pd.testing.assert_frame_equal(written, bolted.support, check_dtype=False)
    bridged = api.run(fc.block_on_bridged_plane(0.5, brittle=True))
    assert len(bridged.bridges) > 0 and len(bridged.support) == 0
    assert list(bridged.support.columns) == list(bolted.support.columns)
    assert list(bolted.bridges.columns) == list(bridged.bridges.columns)


FORMAT = ROOT / "docs" / "scene-format.md"


def _names(text: str) -> list[str]:
    """The names a piece of the guide lists: every name in backticks (a span may hold several,
    comma-separated), leaving out what stands in parentheses (the values of a column, its meaning)."""
    while re.search(r"\([^()]*\)", text):
        text = re.sub(r"\([^()]*\)", "", text)
    spans = re.findall(r"`([^`]+)`", text)
    names = [name.strip() for span in spans for name in span.split(",")]
    return [name for name in names if re.fullmatch(r"[A-Za-z_<][A-Za-z0-9_<>]*", name)]


def _guide_row(file: str, nth: int = 0) -> list[str]:
    """The names listed in the row of docs/scene-format.md's tables for `file` (the nth such row)."""
    rows = [
        line
        for line in FORMAT.read_text().splitlines()
        if line.startswith("| ") and f"`{file}`" in re.split(r"(?<!\\)\|", line)[1]
    ]
    return _names(re.split(r"(?<!\\)\|", rows[nth])[2])


def _docstring_attribute(cls: type, name: str) -> list[str]:
    """The names listed in the Attributes entry `name` of a class's docstring."""
    text = cls.__doc__.split(f"        {name}: ", 1)[1]
    return _names(re.split(r"\n        [a-z_]+: ", text, maxsplit=1)[0])


def _same(documented: list[str], actual: list[str], where: str) -> None:
    """Every documented name is an actual one and every actual one documented; a name with <...> in
    it (one column per monitor, per tendon) stands for the actual names it matches, at least one."""
    patterns = [re.compile(re.sub(r"<[^>]+>", ".+", name) + "$") for name in documented]
    undocumented = [a for a in actual if not any(p.match(a) for p in patterns)]
    missing = [d for d, p in zip(documented, patterns, strict=True) if not any(p.match(a) for a in actual)]
    assert not undocumented and not missing, (
        f"{where}: undocumented {undocumented}, documented only {missing}"
    )


@pytest.fixture(scope="module")
def tables() -> dict[str, pd.DataFrame]:
    """The tables `bbmc run` and `bbmc fos` write (their stages' tables, the API's DataFrames) of small
    scenes: the incline's run; the bolted block's run and factor of safety, with its support and
    design; a bridged block's run."""
    incline = api.run(INCLINE)
    bolted, _ = run_stage.run(api.load_scene(BOLTED), BOLTED)
    bridged = api.run(fc.block_on_bridged_plane(0.5, brittle=True))
    fos, found = fos_stage.run(api.load_scene(BOLTED), BOLTED)
    assert fos.tables["fos"] is not None and found.result.mechanism is not None
    return {
        "history.csv": incline.history,
        "blocks.csv": incline.blocks,
        "contacts.csv": incline.contacts,
        "run summary.csv": bolted.tables["summary"],
        "support.csv": bolted.tables["support"],
        "bridges.csv": bridged.bridges,
        "fos.csv": fos.tables["fos"],
        "fos summary.csv": fos.tables["summary"],
        "mechanism.csv": fos.tables["mechanism"],
        "api mechanism": found.result.mechanism,
        "api trials": found.result.trials_table,
    }


def _columns(table: pd.DataFrame) -> list[str]:
    """A table's columns, and a `quantity, value, unit` table's quantities too."""
    return list(table.columns) + (list(table["quantity"]) if "quantity" in table else [])


@pytest.mark.parametrize(
    "file, nth, table",
    [
        ("history.csv", 0, "history.csv"),
        ("blocks.csv", 0, "blocks.csv"),
        ("contacts.csv", 0, "contacts.csv"),
        ("summary.csv", 1, "run summary.csv"),
        ("support.csv", 0, "support.csv"),
        ("bridges.csv", 0, "bridges.csv"),
        ("fos.csv", 0, "fos.csv"),
        ("summary.csv", 0, "fos summary.csv"),
        ("mechanism.csv", 0, "mechanism.csv"),
    ],
)
def test_the_scene_formats_column_lists_are_the_tables_columns(tables, file, nth, table):
    """docs/scene-format.md#outputs against the tables the commands write, both ways."""
    _same(_guide_row(file, nth), _columns(tables[table]), f"docs/scene-format.md, {file}")


def test_the_api_references_column_lists_are_the_dataframes_columns(tables):
    """The docstrings the API reference renders (RunResult's history and blocks, the FS result's
    mechanism and trials table) against the DataFrames, both ways."""
    _same(
        _docstring_attribute(api.RunResult, "history"), _columns(tables["history.csv"]), "RunResult.history"
    )
    _same(_docstring_attribute(api.RunResult, "blocks"), _columns(tables["blocks.csv"]), "RunResult.blocks")
    mechanism = _names(api.StrengthReductionResult.mechanism.__doc__)
    _same(mechanism, _columns(tables["api mechanism"]), "StrengthReductionResult.mechanism")
    trials = _names(api.StrengthReductionResult.trials_table.__doc__)
    _same(trials, _columns(tables["api trials"]), "StrengthReductionResult.trials_table")
