"""`bbmc warmup` compiles the engine into numba's cache once: a second call compiles nothing, and a
warm-up from a cold cache reaches every kernel of the engine (so a kernel added to it later is warmed
without an edit of `bbmc.warmup`, or this test says which one is not)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest
from click.testing import CliRunner

from bbmc.cli import main


def _warmup(env: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "bbmc", "warmup"], env=env, capture_output=True, text=True)


def _jit_env(**more: str) -> dict[str, str]:
    env = os.environ | more
    env.pop("NUMBA_DISABLE_JIT", None)
    return env


@pytest.mark.slow  # two warm-ups in fresh processes, 11 s
def test_a_second_warmup_loads_every_kernel_from_the_cache():
    """Not timed (the machine's load varies): the second call says it compiled nothing."""
    first = _warmup(_jit_env())
    assert first.returncode == 0, first.stderr
    assert "bbmc warmup: the block engine on constant joints..." in first.stderr
    second = _warmup(_jit_env())
    assert second.returncode == 0, second.stderr
    assert "bbmc warmup: nothing to compile: every kernel loaded from the cache" in second.stdout


def test_warmup_without_the_jit_compiles_nothing(monkeypatch):
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "1")
    outcome = CliRunner().invoke(main, ["warmup"])
    assert outcome.exit_code == 0
    assert "nothing to compile" in outcome.output


# Every dispatcher of bbmc.dem after a warm-up from a cold cache: those never compiled, except the
# ones numba inlines into their callers (compiled there, never on their own).
UNCOMPILED_ENGINE_KERNELS = """
import gc, json
from numba.core.dispatcher import Dispatcher
from bbmc import warmup
warmup.warm()
print(json.dumps(sorted(
    f"{o.py_func.__module__}.{o.py_func.__name__}"
    for o in gc.get_objects()
    if issubclass(type(o), Dispatcher)
    and o.py_func.__module__.startswith("bbmc.dem")
    and not o.overloads
    and o.targetoptions.get("inline", "never") == "never"
)))
"""


@pytest.mark.slow
def test_a_cold_warmup_compiles_every_kernel_of_the_engine(tmp_path):
    env = _jit_env(XDG_CACHE_HOME=str(tmp_path / "cache"))
    run = subprocess.run(
        [sys.executable, "-c", UNCOMPILED_ENGINE_KERNELS], env=env, capture_output=True, text=True, check=True
    )
    assert json.loads(run.stdout.splitlines()[-1]) == []
