"""The layers contract (pyproject.toml's [tool.importlinter], docs/architecture.md): imports run down the
layers, and no package has an import cycle among its modules or subpackages. import-linter counts every
import, function-level and type-checking ones too; a planted upward import or cycle must break it."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from importlinter.api import read_configuration

ROOT = Path(__file__).resolve().parents[1]
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")
LABEL = 18  # the architecture picture's label column: a row's names start after it


def _lint(root: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(root / "src")}
    return subprocess.run([str(LINT_IMPORTS), "--no-cache"], cwd=root, env=env, capture_output=True,
                          text=True, timeout=120)  # fmt: skip


def _copy(tmp_path: Path) -> Path:
    shutil.copytree(ROOT / "src" / "bbmc", tmp_path / "src" / "bbmc",
                    ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    return tmp_path


def test_the_imports_keep_the_contract():
    result = _lint(ROOT)
    assert result.returncode == 0, result.stdout[-3000:]
    assert "2 kept, 0 broken" in result.stdout


TYPE_ONLY = (
    "\nfrom typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n    from bbmc.scene.schema import Scene\n"
)
IN_A_FUNCTION = (
    "\n\ndef _planted():\n    from bbmc.fos import strength_reduction\n\n    return strength_reduction\n"
)
PLANTED = {
    # an engine's import of an analysis, inside a function
    "function level": ("dem/layout.py", IN_A_FUNCTION, "bbmc.dem.layout -> bbmc.fos.strength_reduction"),
    # geometry reaching up to the scene format, for a type only
    "type checking": ("geometry/polygons.py", TYPE_ONLY, "bbmc.geometry.polygons -> bbmc.scene.schema"),
    # the exit statuses importing the program that imports the command line
    "module level": ("exit_status.py", "\nimport bbmc.program\n", "bbmc.exit_status -> bbmc.program"),
}


@pytest.mark.parametrize("kind", PLANTED)
def test_a_planted_upward_import_breaks_the_layers(tmp_path, kind):
    module, planted, arrow = PLANTED[kind]
    root = _copy(tmp_path)
    path = root / "src" / "bbmc" / module
    path.write_text(path.read_text() + planted)
    result = _lint(root)
    assert result.returncode == 1
    assert "imports run down BROKEN" in result.stdout
    assert arrow in result.stdout


def test_a_planted_cycle_inside_a_layer_breaks_the_second_contract(tmp_path):
    """The kernels' column layout importing the run loop: a cycle inside the engine, no layer crossed."""
    root = _copy(tmp_path)
    path = root / "src" / "bbmc" / "dem" / "layout.py"
    path.write_text(
        path.read_text() + "\n\ndef _planted():\n    from bbmc.dem import solver\n\n    return solver\n"
    )
    result = _lint(root)
    assert result.returncode == 1
    assert "imports run down KEPT" in result.stdout
    assert "no import cycle among the modules and packages of any package BROKEN" in result.stdout


def _contract_layers() -> list[set[str]]:
    contracts = read_configuration(str(ROOT / "pyproject.toml"))["contracts_options"]
    (layers,) = [contract["layers"] for contract in contracts if contract["type"] == "layers"]
    return [{name.strip() for name in re.split(r"[:|]", layer)} for layer in layers]


def test_the_architecture_page_draws_the_contracts_layers():
    """docs/architecture.md's picture holds the contract's layers, top to bottom, each name once (its
    first row: the command line, whose four layers are drawn as one chain)."""
    layers = _contract_layers()
    names = set().union(*layers)
    page = (ROOT / "docs" / "architecture.md").read_text()
    picture = page.split("```text\n", 1)[1].split("```", 1)[0]
    rows: list[list[str]] = []
    for line in picture.splitlines():
        if line.lstrip().startswith(("┌", "├", "└")):
            rows.append([])
        else:
            rows[-1] += [word for word in re.findall(r"[a-z_][a-z_0-9]*", line[LABEL:]) if word in names]
    drawn = [row for row in rows if row]
    assert sorted(word for row in drawn for word in row) == sorted(names)
    assert [set(row) for row in drawn] == [set().union(*layers[:4]), *layers[4:]]
