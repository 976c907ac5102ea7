"""docs/benchmarks.md, written from one `bbmc bench` run's folder: its tables rendered from the run's CSVs,
the machine and the date from its machine.csv, the commit from its provenance.json. The prose says what
each section measures and how (`bbmc.bench.page_text`), never what it measured: a number on the page is
one of the run's, so none can drift from it. Earlier runs' pages are in docs/benchmarks-history.md.

    python -m bbmc.bench.page results/bench docs/benchmarks.md

(`make bench` runs it after the stage.) The page it replaces, if it wrote that page from another run, is
added to the history page (`HISTORY`, beside the page) under its run's date, newest first: a rerun
loses nothing measured. Numbers are shown as `number` rounds them: whole numbers in full,
others to 3 significant figures, below 0.001 in e-notation. A folder without machine.csv or
provenance.json is one line on stderr naming the file, exit status 2, and the page is left as it was.
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from bbmc.bench.page_text import INTRO, SECTIONS, Section

HISTORY = "benchmarks-history.md"  # beside the page
HISTORY_MARK = "<!-- earlier runs: bbmc.bench.page adds each replaced run below this line, newest first -->"
RUN_MARK = re.compile(r"^<!-- written by bbmc\.bench\.page from the run started (\S+), commit (\S+);", re.M)


class PageError(Exception):
    """A bench folder the page cannot be written from: the message names the file."""


@dataclass(frozen=True)
class Run:
    """One bench run's folder: its tables by name (CSV stem), as numbers and as the text the CSV holds,
    its provenance and its machine."""

    folder: Path
    tables: dict[str, pd.DataFrame]
    provenance: dict
    machine: dict[str, str]
    texts: dict[str, pd.DataFrame]


def number(value: object) -> str:
    """A value as the page shows it: yes/no for a truth value, '—' for a missing one, '∞' for an
    infinite one, whole numbers in full with thousands separators, other numbers rounded to 3
    significant figures (with separators), below 0.001 in magnitude as d.dde±XX; text as it is."""
    if isinstance(value, bool | np.bool_):
        return "yes" if value else "no"
    if isinstance(value, int | np.integer):
        return f"{value:,}"
    if not isinstance(value, float | np.floating):
        return "—" if value is None or value == "" else str(value).replace("|", "\\|")
    if math.isnan(value):
        return "—"
    if math.isinf(value):
        return "∞" if value > 0 else "−∞"
    if value == 0:
        return "0"
    if value.is_integer() and abs(value) < 1e15:
        return f"{int(value):,}"
    if abs(value) < 1e-3:
        return f"{value:.2e}"
    decimals = 2 - math.floor(math.log10(abs(value)))
    rounded = round(value, decimals)
    return f"{rounded:,.{max(decimals, 0)}f}"


def markdown_table(frame: pd.DataFrame, columns: list[str]) -> str:
    """The rows of `frame` under the `columns` it has (in that order), as a markdown table."""
    shown = [c for c in columns if c in frame.columns]
    lines = ["| " + " | ".join(shown) + " |", "|" + "---|" * len(shown)]
    for row in frame[shown].itertuples(index=False):
        lines.append("| " + " | ".join(number(v) for v in row) + " |")
    return "\n".join(lines)


def load_run(folder: Path) -> Run:
    """Every CSV of a bench results folder, its provenance.json and machine.csv (`PageError` if either
    is missing or unreadable)."""
    try:
        provenance = json.loads((folder / "provenance.json").read_text())
    except (OSError, ValueError) as error:
        raise PageError(
            f"{folder / 'provenance.json'}: cannot be read ({error.__class__.__name__})"
        ) from None
    if provenance.get("stage") != "bench":
        raise PageError(f"{folder / 'provenance.json'}: key 'stage' is not 'bench': not a bench run")
    try:
        facts = pd.read_csv(folder / "machine.csv", dtype=str, keep_default_na=False)
        machine = dict(zip(facts["key"], facts["value"], strict=True))
    except (OSError, ValueError, KeyError) as error:
        raise PageError(f"{folder / 'machine.csv'}: cannot be read ({error.__class__.__name__})") from None
    files = [p for p in sorted(folder.glob("*.csv")) if p.stem != "machine"]
    tables = {p.stem: pd.read_csv(p) for p in files}
    texts = {p.stem: pd.read_csv(p, dtype=str, keep_default_na=False) for p in files}
    return Run(folder, tables, provenance, machine, texts)


def _seconds(text: str) -> str:
    seconds = float(text)
    return f"{int(seconds // 60)} min {seconds % 60:.0f} s" if seconds >= 60 else f"{seconds:.1f} s"


def run_section(run: Run) -> str:
    """The machine, the date, the commit and each section's wall time."""
    m, p = run.machine, run.provenance
    memory = float(m.get("memory_bytes") or "nan")
    times = {k.removeprefix("seconds_"): v for k, v in m.items() if k.startswith("seconds_")}
    total = sum(float(v) for v in times.values())
    only = p.get("only")
    versions = " / ".join(m.get(k, "—") for k in ("python", "numpy", "numba"))
    lines = [
        "## The run",
        "",
        "| | |",
        "|---|---|",
        f"| started (UTC) | {m.get('started_utc', '—')} |",
        f"| finished (UTC) | {m.get('finished_utc', '—')} |",
        f"| commit | `{p.get('git_commit', 'unknown')}` |",
        f"| sections | {', '.join(times) or '—'}{' (`--only`)' if only else ''} |",
        f"| processor | {m.get('cpu_model', '—')} |",
        f"| logical cores | {m.get('logical_cores', '—')} |",
        f"| memory | {number(memory / 1e9)} GB |",
        f"| platform | {m.get('platform', '—')} |",
        f"| Python / numpy / numba | {versions} |",
        "",
        f"Each section's wall time (the whole run: {_seconds(str(total))}):",
        "",
        "| section | wall time |",
        "|---|---|",
        *(f"| {name} | {_seconds(value)} |" for name, value in times.items()),
    ]
    return "\n".join(lines)


def _setting(value: object) -> str:
    """A config value as the prose shows it: a list as '1, 2', a mapping as 'key value, …'."""
    if isinstance(value, list):
        return ", ".join(_setting(v) for v in value)
    if isinstance(value, dict):
        return ", ".join(f"{k} {_setting(v)}" for k, v in value.items() if v is not None)
    return f"{value:,}" if isinstance(value, int) else str(value)


class _Missing(dict):
    """A setting the run's config does not give shows as '—'."""

    def __missing__(self, key: str) -> str:
        return "—"


def section_text(section: Section, run: Run) -> str:
    """One section: its heading and prose, then each of its tables from the run's CSVs, or a line
    saying the run left it out."""
    config = run.provenance.get("config", {}).get(section.name)
    if config is None or not any(t.csv in run.tables for t in section.tables):
        return f"## {section.heading}\n\nNot measured in this run (section `{section.name}` left out of it)."
    settings = {key: _setting(value) for key, value in config.items()}
    parts = [f"## {section.heading}", "", section.prose.format_map(_Missing(settings)).strip()]
    for table in section.tables:
        frame = run.tables.get(table.csv)
        if frame is None:
            continue
        frame = frame.assign(**{c: run.texts[table.csv][c] for c in table.verbatim if c in frame.columns})
        if table.where is not None:
            column, wanted = table.where
            frame = frame[frame[column] == wanted] if column in frame.columns else frame.iloc[:0]
        if table.present is not None:
            frame = frame[frame[table.present].notna()] if table.present in frame.columns else frame.iloc[:0]
        if table.absent is not None and table.absent in frame.columns:
            frame = frame[frame[table.absent].isna()]
        if frame.empty:
            continue
        parts += ["", f"{table.caption} (`{table.csv}.csv`):", "", markdown_table(frame, table.columns)]
    return "\n".join(parts)


def page(run: Run) -> str:
    """The whole page, from one run."""
    mark = (
        f"<!-- written by bbmc.bench.page from the run started {run.machine.get('started_utc', '—')}, "
        f"commit {run.provenance.get('git_commit', 'unknown')}; do not edit: rerun make bench -->"
    )
    body = [mark + "\n" + INTRO.strip(), run_section(run), *(section_text(s, run) for s in SECTIONS)]
    return "\n\n".join(body) + "\n"


def archived(previous: str, history: str) -> str:
    """`history` with the run of `previous` (a page this module wrote) added below its mark, newest
    first: the page from its run section on, each heading one level down, under the run's date."""
    found = RUN_MARK.search(previous)
    start = previous.find("## The run")
    if found is None or start < 0 or HISTORY_MARK not in history:
        return history
    body = re.sub(r"^(#{2,5}) ", r"#\1 ", previous[start:].replace("## The run\n", "", 1), flags=re.M)
    entry = f"## The run started {found[1]} (commit {found[2][:7]})\n{body.rstrip()}\n"
    head, tail = history.split(HISTORY_MARK, 1)
    return f"{head}{HISTORY_MARK}\n\n{entry}{tail}"


def _replace(target: Path, text: str) -> None:
    """Write `text` to `target` through a file beside it, so that it is whole or not written."""
    handle, staging = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    with os.fdopen(handle, "w", encoding="utf-8") as out:
        out.write(text)
    os.replace(staging, target)


def write_page(folder: Path, target: Path) -> Path:
    """Write the page of the run in `folder` to `target`; the page it replaces, if from another run, is
    added to the history page beside it (`archived`)."""
    text = page(load_run(folder))
    target.parent.mkdir(parents=True, exist_ok=True)
    history = target.parent / HISTORY
    if target.exists() and history.exists():
        previous = target.read_text(encoding="utf-8")
        old, new = RUN_MARK.search(previous), RUN_MARK.search(text)
        if old is not None and new is not None and old[1] != new[1]:
            _replace(history, archived(previous, history.read_text(encoding="utf-8")))
    _replace(target, text)
    return target


def main(argv: list[str] | None = None) -> int:
    """`python -m bbmc.bench.page RESULTS/bench PAGE.md`: 0 when written, 2 on a bad folder."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 2:
        print("usage: python -m bbmc.bench.page RESULTS/bench PAGE.md", file=sys.stderr)
        return 2
    try:
        written = write_page(Path(args[0]), Path(args[1]))
    except PageError as error:
        print(f"bbmc bench page: {error}", file=sys.stderr)
        return 2
    print(f"bbmc bench page: wrote {written}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
