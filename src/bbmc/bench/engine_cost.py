"""What this engine costs per step against an earlier one (a git commit), side by side in one run.

Made for the cost of corner contacts where none form: the scaling slope of `configs/slope.yaml`
(`bbmc.bench.scaling`) and the shear box of `configs/shear.yaml` (`bbmc.bench.paper_scenes`), each
timed in fresh processes that import bbmc from this source tree or from a checkout of the commit
(a temporary git worktree), alternately, the median of `repeats`, each on one thread (numba's pool
capped by NUMBA_NUM_THREADS=1: the cost per core). The code each process runs uses only what both trees
have (`scaling.measure_here`, `paper_scenes.ShearScene`), so the same measurement runs on both engines.
"""

from __future__ import annotations

import subprocess
import tempfile
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from bbmc.bench.scaling import answer_of_fresh_process

SOURCE = Path(__file__).resolve().parents[2]  # src/ of this tree


def _slope_code(blocks: int, steps: int, slope_config: str) -> str:
    return (
        "import json\nfrom bbmc.bench import scaling\n"
        f"r = scaling.measure_here({blocks}, {steps}, 3, 0.5, {slope_config!r})\n"
        "print(json.dumps({k: r[k] for k in ('blocks', 'sub_contacts', 'seconds_per_step', "
        "'sub_contact_updates_per_s')}))"
    )


def _shear_code(shear_config: str) -> str:
    return (
        "import json\nfrom pathlib import Path\nfrom bbmc.bench.paper_scenes import ShearScene\n"
        f"s = ShearScene(Path({shear_config!r}))\ns.read(s.defaults())\n"
        "best = min((s.read(s.defaults()) for _ in range(3)), key=lambda r: r.seconds)\n"
        "nan = float('nan')\n"
        "print(json.dumps({'blocks': 2, 'sub_contacts': nan, 'seconds_per_step': best.seconds / best.steps, "
        "'sub_contact_updates_per_s': nan}))"
    )


def _median_run(readings: list[dict]) -> dict:
    """The reading of median seconds per step (the lower middle one of an even count)."""
    ordered = sorted(readings, key=lambda r: r["seconds_per_step"])
    return ordered[(len(ordered) - 1) // 2]


def _worktree(commit: str, into: Path) -> Path:
    """A checkout of `commit` of the repository this source tree is in; its src/ folder."""
    subprocess.run(
        ["git", "-C", str(SOURCE), "worktree", "add", "--detach", str(into), commit],
        capture_output=True,
        text=True,
        check=True,
    )
    return into / "src"


def engine_cost_table(
    commit: str,
    block_counts: list[int],
    steps: int,
    repeats: int,
    slope_config: str,
    shear_config: str,
    progress: Callable[[str], None] = lambda _: None,
    timeout_s: float = 1800.0,
) -> pd.DataFrame:
    """One row per scene: seconds per step on this engine and on `commit`'s, the median of `repeats`
    alternating fresh processes on one thread each, their ratio (this over that), and the range of the
    ratios of the runs paired in order. If the commit cannot be checked out (no git, a shallow clone),
    one row says why."""
    root = SOURCE.parent
    slope_in_repo = Path(slope_config).resolve().relative_to(root)
    shear_in_repo = Path(shear_config).resolve().relative_to(root)

    def cases(tree: Path) -> list[tuple[str, str]]:
        """The timed scenes, each side reading its own tree's configs (later commits add sections an
        earlier one would refuse; the scenes' own keys are the same)."""
        slope, shear = str(tree.parent / slope_in_repo), str(tree.parent / shear_in_repo)
        return [
            *((f"slope, about {n} blocks", _slope_code(n, steps, slope)) for n in block_counts),
            ("shear box, Table 3 tests with eq 16", _shear_code(shear)),
        ]

    with tempfile.TemporaryDirectory(prefix="bbmc-engine-") as folder:
        try:
            then = _worktree(commit, Path(folder) / "then")
        except (OSError, subprocess.CalledProcessError) as error:
            reason = getattr(error, "stderr", "") or str(error)
            return pd.DataFrame(
                [{"scene": "all", "skipped": f"commit {commit} not checked out: {reason.strip()}"}]
            )
        try:
            rows = []
            codes = {"now": dict(cases(SOURCE)), "then": dict(cases(then))}
            for scene in codes["now"]:
                runs: dict[str, list[dict]] = {"now": [], "then": []}
                for k in range(repeats):
                    for label, source in (("now", SOURCE), ("then", then)):
                        progress(f"engine cost: {scene}, {label}, run {k + 1} of {repeats}")
                        runs[label].append(answer_of_fresh_process(codes[label][scene], source, timeout_s, 1))
                best = {label: _median_run(readings) for label, readings in runs.items()}
                paired = [
                    now["seconds_per_step"] / then["seconds_per_step"]
                    for now, then in zip(runs["now"], runs["then"], strict=True)
                ]
                rows.append(
                    {
                        "scene": scene,
                        "commit": commit,
                        "blocks": best["now"]["blocks"],
                        "sub_contacts_now": best["now"]["sub_contacts"],
                        "sub_contacts_then": best["then"]["sub_contacts"],
                        "seconds_per_step_now": best["now"]["seconds_per_step"],
                        "seconds_per_step_then": best["then"]["seconds_per_step"],
                        "now_over_then": best["now"]["seconds_per_step"] / best["then"]["seconds_per_step"],
                        "now_over_then_paired_min": min(paired),
                        "now_over_then_paired_max": max(paired),
                        "runs": repeats,
                        "sub_contact_updates_per_s_now": best["now"]["sub_contact_updates_per_s"],
                        "sub_contact_updates_per_s_then": best["then"]["sub_contact_updates_per_s"],
                        "skipped": "",
                    }
                )
            return pd.DataFrame(rows)
        finally:
            subprocess.run(
                ["git", "-C", str(SOURCE), "worktree", "remove", "--force", str(Path(folder) / "then")],
                capture_output=True,
                check=False,
            )
