"""Fuzz the command line: valid configs, scenes, studies and data files, mutated, run in-process.

Each example copies one seed (a valid input: a stage's config with its data files, a scene, a study
with its scene, `bbmc bench`'s config with its cheap sections) into a fresh folder, mutates one or
more of its files, and runs the real command (`bbmc.cli.main`) on it. Mutations: a key deleted, a
value swapped for another type, NaN, infinity, huge and tiny numbers, an unknown key, a table cell,
column or row changed or removed, a file truncated, emptied, or re-encoded (UTF-16, latin-1, cp1252,
UTF-8 with a byte-order mark), stray bytes.

Every outcome must be a documented exit status (README, docs/scene-format.md "Exit status"): 0 with
the results written; 2 (bad input) or 3 (a run that went unstable) with one error line on stderr (a
value outside its plausible range may be warned of before it) and no results written; 4 for a study in
which no sample gave a result, its error line followed by its first errors. Never a traceback, and no
Python warning shown as Python shows it (two lines): the command turns them into one line each after a
run that ends well (numpy's overflow, say, from a number within its domain that no rock has: judging
plausibility is not this test's; `make fuzz` counts them in its statistics), and drops them beside an
error line.

Each example's time is capped by the seed's budget: steps, samples and trial lengths are set small in
the seed and held at most there after a mutation (`Seed.caps`); everything else is free. The number of
examples is BBMC_FUZZ_EXAMPLES: 50 in `make test` (the same examples every run, the slope and shear
seeds left out for time), and `make fuzz` runs many more over every seed, drawn afresh each time (a
failure found is kept in .hypothesis/ and tried first next time).
"""

from __future__ import annotations

import copy
import csv
import io
import math
import os
import shutil
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import matplotlib.pyplot as plt
import pytest
import yaml
from click.testing import CliRunner
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from bbmc.cli import main
from stage_runs import CONFIGS, PAPER

EXAMPLES = int(os.environ.get("BBMC_FUZZ_EXAMPLES", "50"))
LONG = "BBMC_FUZZ_EXAMPLES" in os.environ  # make fuzz: fresh draws each run


@dataclass(frozen=True)
class Seed:
    """A valid input: `config` (a YAML file under configs/) for `command`, with the files it reads
    copied beside it (`data`: CSV files of data/paper under their own names; `scenes`: YAML files under
    configs/), `small` (dotted path -> value) making it quick, and `caps` (dotted path -> largest value)
    holding each budget at most there whatever a mutation does."""

    command: str
    config: str
    data: tuple[str, ...] = ()
    scenes: tuple[str, ...] = ()
    small: dict[str, object] = field(default_factory=dict)
    caps: dict[str, float] = field(default_factory=dict)
    args: tuple[str, ...] = ()


SCENE_CAPS = {"solver.steps": 300}
FOS_CAPS = {
    "solver.steps": 200_000,
    "fos.min_trial_steps": 2000,
    "fos.response_multiple": 10,
    "fos.trend_window_multiple": 1,
}
SWEEP_CAPS = {"sampling.samples": 200}
FIT_DATA = ("table1_measurements.csv", "table3_numerical_tests.csv", "fig2a_legends.csv")
MC_DATA = ("table1_measurements.csv", "table3_numerical_tests.csv", "equation_constants.csv")
SLOPE_DATA = (
    "table4_rock_mass.csv",
    "table4_joints_constant.csv",
    "table4_joints_nonlinear.csv",
    "equation_constants.csv",
)
SHEAR_DATA = (*MC_DATA, "table2_rock.csv", "fig2a_legends.csv")
BENCH_HEAVY = ("tradeoff", "economy", "scaling", "engine_cost", "fos", "mobilized", "sweep", "rockmass")
SEEDS = {
    "fit": Seed("fit", "fit.yaml", FIT_DATA, caps={"fig1.points_per_curve": 200}),
    "mc": Seed("mc", "mc.yaml", MC_DATA, caps={"grid.points": 100}),
    "joint": Seed("joint", "joint.yaml"),
    "audit": Seed(
        "audit",
        "audit.yaml",
        (*FIT_DATA, "equation_constants.csv", "table1_fits.csv", "table2_rock.csv", *SLOPE_DATA[:3]),
        ("fit.yaml", "mc.yaml"),
    ),
    "slope": Seed(
        "slope",
        "slope.yaml",
        SLOPE_DATA,
        small={
            "limit_equilibrium.dips_deg": [20, 40],
            "sensitivity.dips_deg": [20, 40],
            "residual.phi_r_deg": [33.4],
        },
        caps={
            "run.duration_s": 0.02,
            "limit_equilibrium.max_steps": 2000,
            "limit_equilibrium.ramp_steps": 100,
            "factor_of_safety.max_steps": 2000,
            "factor_of_safety.min_trial_steps": 2000,
            "factor_of_safety.response_multiple": 10,
            "animation_frames": 2,
            "figure_dpi": 50,
        },
    ),
    "shear": Seed(
        "shear",
        "shear.yaml",
        SHEAR_DATA,
        caps={
            "stress_controlled.normal_ramp_steps": 100,
            "stress_controlled.shear_start_step": 150,
            "stress_controlled.shear_ramp_steps": 300,
            "stress_controlled.max_steps": 1000,
            "constant_velocity.shear_displacement_mm": 0.5,
            "constant_velocity.normal_ramp_steps": 100,
            "constant_velocity.shear_start_step": 150,
            "quick.shear_ramp_steps": 300,
            "figure_dpi": 50,
        },
        args=("--quick",),
    ),
    "bench": Seed(  # its whole config validated; the laws' and the bandwidth's sections run, made small
        "bench",
        "bench.yaml",
        tuple(sorted(set(SHEAR_DATA + SLOPE_DATA))),
        ("shear.yaml", "slope.yaml"),
        small={**dict.fromkeys(BENCH_HEAVY), "support": None},
        caps={
            "laws.array_size": 1000,
            "laws.python_loop_size": 100,
            "laws.repeats": 1,
            "bandwidth.array_MB": 1,
            "bandwidth.repeats": 1,
            "bandwidth.blocks": 100,
            "figure_dpi": 50,
        },
    ),
    **{
        f"run {name}": Seed("run", f"scenes/{name}.yaml", caps=SCENE_CAPS)
        for name in ("example", "incline", "toppling_column", "mobilized_shear_box")
    },
    **{f"fos {name}": Seed("fos", f"scenes/{name}.yaml", caps=FOS_CAPS) for name in ("planar_crack",)},
    **{
        f"sweep {name}": Seed("sweep", f"sweeps/{name}.yaml", caps=SWEEP_CAPS, args=("--workers", "1"))
        for name in ("planar_block", "paper_slope_le", "toppling")
    },
    "sweep scene_run": Seed(
        "sweep",
        "sweeps/scene_run.yaml",
        scenes=("scenes/incline.yaml",),
        caps={"sampling.samples": 4, "solver.steps": 300},
        args=("--workers", "1"),
    ),
}
HEAVY = {"slope", "shear"}  # 5-10 s a run even made small: `make fuzz` only
NAMES = sorted(SEEDS) if LONG else sorted(set(SEEDS) - HEAVY)
SCENE_RUN_STUDY = {
    "name": "incline_friction",
    "base": {"kind": "scene_run", "scene": "incline.yaml", "monitor": "slider_x_mm"},
    "variables": [{"path": "joint_laws.joint.friction_deg", "distribution": "normal", "mean": 20, "std": 3}],
    "sampling": {"method": "monte_carlo", "samples": 4, "seed": 1},
    "batch_size": 2,
}


# --- a seed in a folder -----------------------------------------------------------------------------


def _set(tree: object, path: str, value: object) -> None:
    """The value at a dotted path that exists (list entries by index) set to `value`."""
    *parents, last = path.split(".")
    node = _get(tree, ".".join(parents)) if parents else tree
    if isinstance(node, list):
        node[int(last)] = value
    elif isinstance(node, dict) and last in node:
        node[last] = value


def _get(tree: object, path: str) -> object:
    node = tree
    for key in path.split("."):
        node = node[int(key)] if isinstance(node, list) else node[key]
    return node


def _capped(tree: object, caps: dict[str, float]) -> object:
    """`tree` with every budget that is a number held at most at its cap (a mutation may have made it
    anything: a number above the cap is the only thing that is changed)."""
    for path, cap in caps.items():
        try:
            value = _get(tree, path)
        except (KeyError, IndexError, TypeError, ValueError):
            continue
        number = isinstance(value, int | float) and not isinstance(value, bool)
        if number and value > cap:
            _set(tree, path, type(value)(cap))
    return tree


def _local_paths(tree: dict) -> dict:
    """Data and config paths in a config pointed at the copies beside it (same file names)."""
    for key, value in tree.get("data", {}).items():
        tree["data"][key] = Path(value).name
    for key in ("fit_config", "mc_config", "shear_config", "slope_config"):
        if key in tree:
            tree[key] = Path(tree[key]).name
    base = tree.get("base")
    if isinstance(base, dict) and base.get("scene"):
        base["scene"] = Path(base["scene"]).name
    return tree


def _seed_files(seed: Seed) -> dict[str, bytes]:
    """The seed's files by name: its config (made small), the configs and scenes it reads, its data."""
    trees = {}
    for name in (seed.config, *seed.scenes):
        if name == "sweeps/scene_run.yaml":  # made here: configs/ has no study of a scene_run
            trees[Path(name).name] = copy.deepcopy(SCENE_RUN_STUDY)
            continue
        tree = yaml.safe_load((CONFIGS / name).read_text())
        for path, value in seed.small.items():
            _set(tree, path, value)
        trees[Path(name).name] = _capped(_local_paths(tree), seed.caps)
    files = {name: yaml.safe_dump(tree, sort_keys=False).encode() for name, tree in trees.items()}
    files |= {name: (PAPER / name).read_bytes() for name in seed.data}
    return files


# --- mutations ----------------------------------------------------------------------------------------

NASTY = [
    None,
    "",
    "text",
    "3.3",
    True,
    [],
    {},
    [1, 2, 3],
    0,
    -1,
    0.0,
    -0.0,
    1e308,
    -1e308,
    1e-308,
    5e-324,
    10**20,
    math.nan,
    math.inf,
    -math.inf,
    {"law": "constant"},
]
NASTY_CELLS = [
    "",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "-1",
    "0",
    "1e308",
    "1e-320",
    "1e999",
    "abc",
    "1,5",
    " ",
    "-0",
]
ENCODINGS = ["utf-16", "utf-16-le", "latin-1", "cp1252", "utf-8-sig"]


def _paths(tree: object, prefix: str = "") -> list[str]:
    """Every dotted path in a YAML tree (list entries by index)."""
    items = tree.items() if isinstance(tree, dict) else enumerate(tree) if isinstance(tree, list) else []
    found = []
    for key, value in items:
        path = f"{prefix}{key}"
        found.append(path)
        found.extend(_paths(value, f"{path}."))
    return found


def _numeric_twist(value: object, factor: float) -> object:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return value
    twisted = value * factor
    return int(twisted) if isinstance(value, int) and math.isfinite(twisted) else twisted


@st.composite
def _tree_mutation(draw, tree: object) -> object:
    tree = copy.deepcopy(tree)
    paths = _paths(tree)
    if not paths:
        return draw(st.sampled_from(NASTY))
    path = draw(st.sampled_from(paths))
    *parents, last = path.split(".")
    parent = _get(tree, ".".join(parents)) if parents else tree
    key = int(last) if isinstance(parent, list) else last
    kind = draw(st.sampled_from(["twist", "twist", "twist", "nasty", "nasty", "delete", "unknown", "wrap"]))
    if kind == "delete":
        del parent[key]
    elif kind == "nasty":
        parent[key] = draw(st.sampled_from(NASTY))
    elif kind == "twist":
        factor = draw(st.sampled_from([-1.0, 0.0, 1e-300, 1e-9, 1e-3, 0.1, 0.5, 2.0, 10.0, 1e3, 1e9, 1e300]))
        parent[key] = _numeric_twist(parent[key], factor)
    elif kind == "unknown" and isinstance(parent, dict):
        parent[f"{last}_typo"] = parent[key]
    else:
        parent[key] = [parent[key]] if draw(st.booleans()) else {"value": parent[key]}
    return tree


@st.composite
def _table_mutation(draw, rows: list[list[str]]) -> list[list[str]]:
    rows = copy.deepcopy(rows)
    header, body = rows[0], rows[1:]
    kind = draw(st.sampled_from(["cell", "cell", "twist", "column", "rename", "row", "no_rows", "ragged"]))
    if kind in ("cell", "twist") and body:
        r = draw(st.integers(0, len(body) - 1))
        c = draw(st.integers(0, len(body[r]) - 1)) if body[r] else 0
        if body[r]:
            if kind == "cell":
                body[r][c] = draw(st.sampled_from(NASTY_CELLS))
            else:
                factor = draw(st.sampled_from(["-", "e300", "e-300", "e9", "e-9", "e3", "e-3", "0"]))
                body[r][c] = f"-{body[r][c]}" if factor == "-" else f"{body[r][c]}{factor}"
    elif kind == "column":
        c = draw(st.integers(0, len(header) - 1))
        rows = [[cell for k, cell in enumerate(row) if k != c] for row in rows]
        return rows
    elif kind == "rename":
        c = draw(st.integers(0, len(header) - 1))
        header[c] = draw(st.sampled_from([header[c].upper(), header[c] + "_x", header[0], ""]))
    elif kind == "row" and body:
        r = draw(st.integers(0, len(body) - 1))
        body.insert(r, list(body[r])) if draw(st.booleans()) else body.pop(r)
    elif kind == "no_rows":
        body.clear()
    elif kind == "ragged" and body:
        r = draw(st.integers(0, len(body) - 1))
        body[r] = body[r][:-1] if draw(st.booleans()) else [*body[r], "1"]
    return [header, *body]


@st.composite
def _byte_mutation(draw, content: bytes) -> bytes:
    kind = draw(st.sampled_from(["empty", "truncate", "encoding", "bytes"]))
    if kind == "empty":
        return b""
    if kind == "truncate":
        return content[: draw(st.integers(0, max(len(content) - 1, 0)))]
    if kind == "encoding":
        text = content.decode("utf-8", errors="replace")
        text = text.replace("\n", " # éè°\n", 1) if text.lstrip().startswith(("#", "name", "base")) else text
        if "," in text.split("\n", 1)[0]:  # a table: a non-ASCII note in a new last column
            lines = text.splitlines()
            lines[0] += ",note"
            lines[1:] = [f"{line},talus à 30°" for line in lines[1:]]
            text = "\n".join(lines) + "\n"
        return text.encode(draw(st.sampled_from(ENCODINGS)), errors="replace")
    at = draw(st.integers(0, len(content)))
    return content[:at] + draw(st.binary(min_size=1, max_size=8)) + content[at:]


@st.composite
def _mutated(draw, seed: Seed) -> dict[str, bytes]:
    """The seed's files with 1 to 3 mutations, each of one file: of its parsed content (kept within the
    seed's budget), or of its bytes (after which it is left as it is)."""
    files = _seed_files(seed)
    for _ in range(draw(st.sampled_from([1, 1, 1, 2, 3]))):
        name = draw(st.sampled_from(sorted(files)))
        content = files[name]
        try:
            text = content.decode("utf-8")
        except UnicodeDecodeError:
            text = None
        if text is not None and draw(st.integers(0, 5)):
            if name.endswith(".csv"):
                rows = list(csv.reader(io.StringIO(text)))
                if rows:
                    out = io.StringIO()
                    csv.writer(out, lineterminator="\n").writerows(draw(_table_mutation(rows)))
                    files[name] = out.getvalue().encode()
                    continue
            else:
                try:
                    tree = yaml.safe_load(text)
                except yaml.YAMLError:
                    tree = None
                if tree is not None:
                    tree = _capped(draw(_tree_mutation(tree)), seed.caps)
                    files[name] = yaml.safe_dump(tree, sort_keys=False, allow_unicode=True).encode()
                    continue
        files[name] = draw(_byte_mutation(content))
    return files


# --- the run and its judgment ----------------------------------------------------------------------------


def _run(seed: Seed, files: dict[str, bytes], folder: Path) -> tuple:
    for name, content in files.items():
        (folder / name).write_bytes(content)
    results = folder / "results"
    args = [seed.command, "--config", str(folder / Path(seed.config).name), "--results", str(results)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        outcome = CliRunner().invoke(main, [*args, *seed.args])
    plt.close("all")
    return outcome, results, caught


def _judge(seed: Seed, outcome, results: Path, caught: list) -> list[str]:
    """The outcome checked; what happened, for the statistics of `make fuzz`."""
    if outcome.exception is not None and not isinstance(outcome.exception, SystemExit):
        raise outcome.exception
    code, written = outcome.exit_code, list(results.rglob("provenance.json"))
    assert code in (0, 2, 3, 4), f"undocumented exit status {code}\n{outcome.output}{outcome.stderr}"
    messages = "\n".join(f"{w.category.__name__}: {w.message} ({w.filename}:{w.lineno})" for w in caught)
    assert not messages, (
        f"exit {code} with Python warnings of its own (two lines on stderr each):\n{messages}"
    )
    if code == 0:
        assert written, f"exit 0 without results\n{outcome.output}"
        warned = any(": warning: " in line for line in outcome.stderr.splitlines())
        return ["exit 0", *(["exit 0 with a warning line"] if warned else [])]
    lines = outcome.stderr.strip().splitlines()
    errors = [line for line in lines if ": error: " in line]
    assert len(errors) == 1, f"not one error line:\n{outcome.stderr}"
    if code == 4:  # no sample of a study gave a result: its first errors follow the error line
        assert seed.command == "sweep", outcome.stderr
        lines = lines[: lines.index(errors[0]) + 1]
    assert lines[-1] == errors[0], f"not one error line:\n{outcome.stderr}"
    assert errors[0].startswith(f"bbmc {seed.command}"), errors[0]
    assert all(line.startswith(f"bbmc {seed.command}") for line in lines), outcome.stderr
    assert not written, f"exit {code}, yet written: {written}"
    return [f"exit {code}"]


FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=not LONG,
    database=None if not LONG else settings.default.database,
    suppress_health_check=list(HealthCheck),
    print_blob=True,
)


def _one_change(seed: Seed, name: str, where: str, value: object) -> dict[str, bytes]:
    """The seed's files with one change: a YAML value at a dotted path, or a CSV cell at
    'line:column' (`value` None: that line removed)."""
    files = _seed_files(seed)
    if name.endswith(".csv"):
        rows = list(csv.reader(io.StringIO(files[name].decode())))
        line, column = where.split(":")
        if value is None:
            del rows[int(line) - 1]
        else:
            rows[int(line) - 1][rows[0].index(column)] = str(value)
        out = io.StringIO()
        csv.writer(out, lineterminator="\n").writerows(rows)
        files[name] = out.getvalue().encode()
    else:
        tree = yaml.safe_load(files[name])
        _set(tree, where, value)
        files[name] = yaml.safe_dump(tree, sort_keys=False).encode()
    return files


# What the fuzzer found (each a traceback before its fix), as the one change that shows it. Since a
# number more than a factor of 10^6 outside its plausible range is refused (docs/plausible-ranges.md),
# several end there, before the code they once broke.
FAR_OUT = "more than a factor of 10^6 outside"  # the refusal of a number far beyond its range
FOUND = [
    ("fit", "fig2a_legends.csv", "2:sigma_n_kPa", None, 0, ""),  # fig 2 zipped legends with fits
    ("audit", "table4_joints_constant.csv", "2:c_kPa", 5400, 0, ""),  # no sigma_n gives c: brentq
    ("run incline", "incline.yaml", "materials.rock.density_kg_m3", 5e-324, 2, FAR_OUT),
    ("run example", "example.yaml", "solver.update_interval_steps", 5 * 10**31, 2, "beyond 2^53"),
    ("sweep toppling", "toppling.yaml", "base.crest_block", 10**10, 2, "more than 1,000,000 blocks"),
    ("fos planar_crack", "planar_crack.yaml", "water.unit_weight_kN_m3", 9.81e30, 2, FAR_OUT),  # unstable
    ("shear", "table3_numerical_tests.csv", "6:tau_MPa", 5.5e298, 2, FAR_OUT),  # a '+' in a name
    ("slope", "table4_joints_nonlinear.csv", "2:phi_b_deg", 30.06, 2, "exceeds Table 4's phi_b_deg 30.06"),
    ("mc", "mc.yaml", "joint.jcs_MPa", 3.31e-18, 2, FAR_OUT),  # numpy's warning, then shown one line
    ("audit", "table4_joints_nonlinear.csv", "2:JCS_MPa", 3.87e300, 2, FAR_OUT),  # brentq to 4e306 Pa
    ("fit", "table1_measurements.csv", "2:K_si_GPa_per_m", 5e8, 2, "nonlinear least squares found no"),
    ("shear", "shear.yaml", "joint_options.stress_floor_MPa", 0.001, 2, "stopped at step"),  # before shearing
    ("slope", "slope.yaml", "slope.height_m", 1e-29, 2, "it makes no block"),
    ("joint", "joint.yaml", "lab_length_m", 1e-308, 2, FAR_OUT),  # delta_peak = L/500 (JRC/L)^0.33 overflowed
    ("slope", "slope.yaml", "sensitivity.dips_deg.1", 4e31, 2, "key 'sensitivity.dips_deg.1'"),
    ("shear", "equation_constants.csv", "3:value", 4.881e299, 2, "ks_MPa_per_mm': Input should be greater"),
    ("shear", "fig2a_legends.csv", "3:slope_a", 1e308, 2, "'slope_a' = 1e+308"),  # matplotlib's traceback
    ("audit", "table4_joints_constant.csv", "2:c_kPa", 4.8e300, 2, "'c_kPa' = 4.8e+300"),  # exit 0, warned
]


@pytest.mark.parametrize(("name", "file", "where", "value", "code", "fragment"), FOUND)
def test_what_the_fuzzer_found_ends_in_its_documented_status(
    tmp_path, name, file, where, value, code, fragment
):
    seed = SEEDS[name]
    outcome, results, caught = _run(seed, _one_change(seed, file, where, value), tmp_path)
    _judge(seed, outcome, results, caught)
    assert outcome.exit_code == code, outcome.stderr
    assert fragment in outcome.stderr


UNMUTATED_SLOW = {"bench"}  # its small bench run takes 20 s: make test-slow runs it


@pytest.mark.parametrize(
    "name", [pytest.param(n, marks=pytest.mark.slow) if n in UNMUTATED_SLOW else n for n in NAMES]
)
def test_every_seed_runs_unmutated(tmp_path, name: str) -> None:
    """The seeds are valid: a mutation starts from an input that runs (exit 0, results written)."""
    seed = SEEDS[name]
    outcome, results, caught = _run(seed, _seed_files(seed), tmp_path)
    _judge(seed, outcome, results, caught)
    assert outcome.exit_code == 0, outcome.stderr


@FUZZ
@given(data=st.data())
def test_a_mutated_input_ends_in_a_documented_exit_status(tmp_path_factory, data) -> None:
    name = data.draw(st.sampled_from(NAMES), label="seed")
    seed = SEEDS[name]
    files = data.draw(_mutated(seed), label="files")
    folder = tmp_path_factory.mktemp("fuzz")
    try:
        for what in _judge(seed, *_run(seed, files, folder)):
            event(what)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
