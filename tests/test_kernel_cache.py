"""The kernel cache follows the source it compiles: a law changed in another file than the kernel that
calls it gives the new answer, not the cached old one (numba's own cache checks the kernel's file only),
and the first compile of the engine says so in one line."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from bbmc import kernel_cache

PACKAGE = Path(kernel_cache.__file__).resolve().parent

# K_s of the hyperbolic law from a kernel (dem/joint_state.py) that calls the laws of laws/stiffness.py:
# K_si = K_j (sigma/sigma_ref)^n_j = 2e9 Pa/m at sigma = 1 MPa, K_s = K_si (1 - tau/tau_ult)^2 at tau = 0.
SHEAR_STIFFNESS = """
import numpy as np
from bbmc.dem import joint_state, layout as L
p = np.zeros(L.PARAMETERS)
p[L.P_K_J], p[L.P_N_J], p[L.P_SIGMA_REF], p[L.P_TAU_P_SLOPE], p[L.P_TAU_ULT_SLOPE] = 2e9, 0.5, 1e6, 1.0, 1.0
print(joint_state._shear_stiffness(L.SHEAR_HYPERBOLIC, 1e6, 0.0, p))
"""


def _copy(tmp_path: Path) -> Path:
    src = tmp_path / "src"
    shutil.copytree(PACKAGE, src / "bbmc", ignore=shutil.ignore_patterns("__pycache__"))
    return src


def _shear_stiffness(src: Path, cache: Path) -> float:
    env = os.environ | {"PYTHONPATH": str(src), "XDG_CACHE_HOME": str(cache)}
    env.pop("NUMBA_DISABLE_JIT", None)
    run = subprocess.run(
        [sys.executable, "-c", SHEAR_STIFFNESS], env=env, capture_output=True, text=True, check=True
    )
    return float(run.stdout)


def test_a_law_changed_in_its_own_file_changes_the_kernel_that_calls_it(tmp_path):
    src, cache = _copy(tmp_path), tmp_path / "cache"
    assert _shear_stiffness(src, cache) == 2e9
    law = src / "bbmc" / "laws" / "stiffness.py"
    text = law.read_text()
    assert text.count("return k_j * (sigma_n / sigma_ref) ** n_j") == 1
    law.write_text(text.replace("return k_j * (sigma_n / sigma_ref) ** n_j", "return 3.0 * k_j"))
    assert _shear_stiffness(src, cache) == 6e9
    assert len(list((cache / "bbmc" / "numba").iterdir())) == 2  # one key per version of the laws


def test_the_key_follows_the_compiled_source_only(tmp_path):
    """The key covers the laws, the kernels and the column layout they read; a figure or the command
    line is not compiled, and editing them keeps the compiled engine."""
    src = _copy(tmp_path)
    package = src / "bbmc"
    names = {path.relative_to(package).as_posix() for path in kernel_cache.compiled_sources(package)}
    engine = {"dem/kernels.py", "dem/joint_state.py", "dem/contact_forces.py", "dem/layout.py"}
    assert {"laws/stiffness.py", "laws/strength.py"} | engine <= names
    assert not {"outputs/figures.py", "outputs/vtk.py", "cli.py"} & names
    key = kernel_cache.source_key(package)
    figures = package / "outputs" / "figures.py"
    figures.write_text(figures.read_text() + "\n# an edit that compiles nothing\n")
    assert kernel_cache.source_key(package) == key
    layout = package / "dem" / "layout.py"
    layout.write_text(layout.read_text() + "\n# an edit of a module the kernels read\n")
    assert kernel_cache.source_key(package) != key


def test_keys_unused_for_a_week_are_removed(tmp_path):
    now = time.time()
    keep, recent, old = (tmp_path / key for key in ("0" * 16, "1" * 16, "2" * 16))
    other = tmp_path / "not-a-key"
    for folder in (keep, recent, old, other):
        folder.mkdir()
        (folder / kernel_cache.STAMP).touch()
    week = kernel_cache.KEEP_DAYS * 86400.0
    for folder in (keep, old, other):
        os.utime(folder / kernel_cache.STAMP, (now - week - 60.0, now - week - 60.0))
    os.utime(recent / kernel_cache.STAMP, (now - week + 3600.0, now - week + 3600.0))
    assert kernel_cache.prune(tmp_path, keep, now) == [old]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([keep.name, recent.name, other.name])


def test_a_cold_engine_cache_is_announced_once(tmp_path, monkeypatch, capsys):
    monkeypatch.delenv("NUMBA_DISABLE_JIT", raising=False)
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(kernel_cache, "_announced", False)
    kernel_cache.announce_engine_compile()
    kernel_cache.announce_engine_compile()
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and "compiling the block engine" in lines[0]

    version = f"py{sys.version_info.major}{sys.version_info.minor}"
    kernels = kernel_cache.source_subfolder(tmp_path, PACKAGE / "dem" / "kernels.py")
    (tmp_path / "dem_0123").mkdir()  # another copy of the source: its compiled engine is not this one's
    (tmp_path / "dem_0123" / f"kernels.cycle-758.{version}.nbi").touch()
    monkeypatch.setattr(kernel_cache, "_announced", False)
    kernel_cache.announce_engine_compile()
    assert "compiling the block engine" in capsys.readouterr().err
    kernels.mkdir()
    (kernels / f"kernels.cycle-758.{version}.nbi").touch()
    monkeypatch.setattr(kernel_cache, "_announced", False)
    kernel_cache.announce_engine_compile()
    assert capsys.readouterr().err == ""


def test_the_keyed_cache_holds_when_numba_was_imported_first(tmp_path):
    """numba reads NUMBA_CACHE_DIR when it is imported: a script that imports numba before bbmc still
    compiles into the keyed directory, and a NUMBA_CACHE_DIR set by hand is replaced by it."""
    script = (
        "import numba, bbmc, os; from bbmc import kernel_cache as k; "
        "print(numba.config.CACHE_DIR); print(os.environ['NUMBA_CACHE_DIR']); print(k.source_key())"
    )
    env = os.environ | {"XDG_CACHE_HOME": str(tmp_path), "NUMBA_CACHE_DIR": str(tmp_path / "by-hand")}
    run = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True)
    config, variable, key = run.stdout.split()
    assert config == variable == str(tmp_path / "bbmc" / "numba" / key)
