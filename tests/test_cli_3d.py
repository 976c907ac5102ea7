"""`bbmc run` and `bbmc fos` on 3D scenes (`dimension: 3`): bad input in one line, exit 2, nothing
written; a run's history and summary; the example wedge's FS beside `bbmc wedge`'s limit equilibrium."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest
import yaml
from click.testing import CliRunner

from bbmc.cli import main

ROOT = Path(__file__).resolve().parents[1]
SCENE = {
    "dimension": 3,
    "materials": {"rock": {"density_kg_m3": 2500}},
    "joint_types": {
        "mc": {"law": "mohr_coulomb", "kn_MPa_per_mm": 1, "ks_MPa_per_mm": 0.5, "friction_deg": 30}
    },
    "contacts": {"default": "mc"},
    "blocks": [
        {"name": "base", "material": "rock", "held": True, "box": {"lo_m": [0, 0, -1], "hi_m": [4, 4, 0]}},
        {"name": "top", "material": "rock", "box": {"lo_m": [1, 1, 0], "hi_m": [2, 2, 1]}},
    ],
    "solver": {"steps": 3000, "stop": {"unbalanced_force_ratio": 1e-3}},
    "monitoring": {"every_steps": 50, "monitors": [{"name": "settle", "quantity": "uz", "block": "top"}]},
}


def write(tmp_path: Path, **changes) -> Path:
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump({**SCENE, **changes}), encoding="utf-8")
    return path


def refused(outcome, results: Path, *fragments: str) -> None:
    assert outcome.exit_code == 2, outcome.output
    lines = outcome.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in outcome.output, outcome.stderr
    assert all(f in lines[0] for f in fragments), lines[0]
    assert not results.exists() or not any(results.rglob("*.*")), "something was written"


@pytest.mark.parametrize("command", ["run", "fos"])
@pytest.mark.parametrize(
    "changes, fragments",
    [
        ({"support": [{"name": "bolt"}]}, ("key 'support'", "not yet in 3D")),
        ({"water": {"unit_weight_kN_m3": 9.81}}, ("key 'water'", "give exactly one of elevation_m")),
        (
            {
                "blocks": [
                    SCENE["blocks"][0],
                    {**SCENE["blocks"][1], "box": {"lo_m": [1, 1, -0.5], "hi_m": [2, 2, 1]}},
                ]
            },
            ("scene.yaml", "key 'blocks'", "'base' and 'top'", "overlap"),
        ),
        ({"contacts": {"default": "wet"}}, ("key 'contacts.default'", "no joint type 'wet'")),
        ({"dimension": 4}, ("key 'dimension'", "2 or 3")),
    ],
)
def test_bad_3d_input_is_one_line_exit_2_and_nothing_written(tmp_path, command, changes, fragments):
    results = tmp_path / "results"
    outcome = CliRunner().invoke(main, [command, str(write(tmp_path, **changes)), "--results", str(results)])
    refused(outcome, results, *fragments)


@pytest.mark.parametrize("command", ["run", "fos"])
def test_a_misspelt_dimension_is_named_not_read_as_a_2d_scene(tmp_path, command):
    """`dimensionn: 3` would make the file a 2D scene, refused on some other key; the near miss is named."""
    scene = {("dimensionn" if k == "dimension" else k): v for k, v in SCENE.items()}
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(scene), encoding="utf-8")
    results = tmp_path / "results"
    outcome = CliRunner().invoke(main, [command, str(path), "--results", str(results)])
    refused(outcome, results, "key 'dimensionn'", "did you mean 'dimension'")


def test_a_3d_run_writes_its_history_and_stops_once_balanced(tmp_path):
    """A 1 m cube set on a held base settles under its weight (closure m g / (K_n A) = 0.0245 mm) and
    stops once the unbalanced-force ratio is below 1e-3, before its 3000 steps."""
    results = tmp_path / "results"
    args = ["run", str(write(tmp_path)), "--results", str(results), "--threads", "1"]
    outcome = CliRunner().invoke(main, args)
    assert outcome.exit_code == 0, outcome.output
    out = results / "run" / "scene"
    history = pd.read_csv(out / "history.csv")
    summary = dict(pd.read_csv(out / "summary.csv")[["quantity", "value"]].values)
    assert summary["stopped_by_ratio"] == 1 and summary["steps"] < 3000
    closure_mm = 2500 * 9.81 / 1e9 * 1e3  # m g / (K_n A), A = 1 m2, in mm
    assert history["settle_mm"].iloc[-1] == pytest.approx(-closure_mm, rel=0.05)  # 5 %: damped, ratio 1e-3
    assert {"provenance.json", "history.png", "mechanism.png", "blocks.csv", "contacts.csv"} <= {
        p.name for p in out.iterdir()
    }


def test_the_example_wedge_fs_matches_its_limit_equilibrium(tmp_path):
    """configs/scenes/wedge_bench_3d.yaml (the classic wedge on Barton-Bandis joints) by strength
    reduction, against `bbmc wedge configs/wedge_bench_le.yaml` (the same wedge, LE FS 2.9085): within
    1 % (the issue's wedge tolerance); measured 2.9004 (-0.28 %)."""
    results = tmp_path / "results"
    le = CliRunner().invoke(
        main, ["wedge", str(ROOT / "configs/wedge_bench_le.yaml"), "--results", str(results)]
    )
    assert le.exit_code == 0, le.output
    limit = float(pd.read_csv(results / "wedge" / "wedge_bench_le" / "wedge.csv")["factor_of_safety"].iloc[0])
    assert limit == pytest.approx(2.9085, abs=1e-4)
    args = ["fos", str(ROOT / "configs/scenes/wedge_bench_3d.yaml"), "--results", str(results)]
    outcome = CliRunner().invoke(main, args)
    assert outcome.exit_code == 0, outcome.output
    assert "bbmc fos: factor of safety 2.90" in outcome.output
    summary = dict(
        pd.read_csv(results / "fos" / "wedge_bench_3d" / "summary.csv")[["quantity", "value"]].values
    )
    assert summary["factor_of_safety"] == pytest.approx(limit, rel=0.01)
    trials = pd.read_csv(results / "fos" / "wedge_bench_3d" / "fos.csv")
    assert set(trials["verdict"]) == {"stable", "unstable"}
