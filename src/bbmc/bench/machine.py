"""The machine a bench run measured on, and when: written beside its results (machine.csv), so the page
made from them (`bbmc.bench.page`) names the machine and the date of the very run its numbers come from.
"""

from __future__ import annotations

import os
import platform
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path

import pandas as pd


def _cpu_model(cpuinfo: Path = Path("/proc/cpuinfo")) -> str:
    """The processor's name: the first `model name` of /proc/cpuinfo (Linux), else what `platform` says."""
    try:
        for line in cpuinfo.read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown"


def _memory_bytes() -> float:
    """The physical memory, in bytes (page size × pages; NaN where the system does not say)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return float("nan")


def _version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "not installed"


def now_utc() -> str:
    """The time now, UTC, to the second (ISO 8601)."""
    return datetime.now(UTC).replace(microsecond=0).isoformat()


def machine_table(started_utc: str, finished_utc: str, section_seconds: dict[str, float]) -> pd.DataFrame:
    """One row per fact: the processor, its logical cores, the memory (bytes), the platform, the
    Python, numpy and numba versions, the run's start and end (UTC), and each section's wall time
    (s, as `seconds_<section>`)."""
    facts: list[tuple[str, object]] = [
        ("cpu_model", _cpu_model()),
        ("logical_cores", os.cpu_count() or 0),
        ("memory_bytes", _memory_bytes()),
        ("platform", platform.platform()),
        ("python", platform.python_version()),
        ("numpy", _version("numpy")),
        ("numba", _version("numba")),
        ("started_utc", started_utc),
        ("finished_utc", finished_utc),
    ]
    facts += [(f"seconds_{name}", seconds) for name, seconds in section_seconds.items()]
    return pd.DataFrame({"key": [k for k, _ in facts], "value": [v for _, v in facts]})
