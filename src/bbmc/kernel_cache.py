"""Numba's on-disk kernel cache, keyed to the source of everything the kernels are compiled from.

Numba's own cache (`cache=True`) checks a compiled function against its own source file only. A
kernel that calls a joint law from another module, or reads a column constant of `bbmc.dem.layout`,
has that code compiled in; after the other file changes (an update, an edit) numba still serves the
old kernel, and the engine gives the old answer with no sign. bbmc therefore gives numba one cache
directory per version of that source:

    <cache>/bbmc/numba/<key>/

<cache> is $XDG_CACHE_HOME, else ~/.cache. <key> hashes numba's version and the source of every bbmc
module that imports numba together with every bbmc module those import, directly or through others
(`compiled_sources`): any change there starts a fresh cache, while an edit elsewhere (a figure, the
command line) keeps it. A key not used for `KEEP_DAYS` days is removed. `use_keyed_cache` sets
NUMBA_CACHE_DIR to the directory before any kernel is decorated; child processes (a sweep's workers)
inherit it and compute the same key from the same source. It replaces a NUMBA_CACHE_DIR set by hand.

Inside a key's directory numba keeps each source folder's kernels in a folder of its own, named after
the folder's absolute path (`source_subfolder`): two copies of the same source (a second checkout, a
git worktree, a package copied to a dask worker by `client.upload_file`) share a key but not their
compiled kernels, and the first run from each copy compiles. `engine_is_cold` therefore looks in this
copy's folder, and a study warms the engine once per machine before its workers start
(`bbmc.sweep.runner`). `kernel_files` and `written_since` count what a call wrote into the cache.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import sys
import time
from importlib import metadata
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent
KEEP_DAYS = 7.0
STAMP = "last_used"  # touched at every import: its age tells how long a key has gone unused
_KEY = re.compile(r"[0-9a-f]{16}")
_IMPORTS_NUMBA = re.compile(r"^\s*(?:import numba\b|from numba\b)", re.MULTILINE)
_IMPORT = re.compile(r"^[ \t]*import[ \t]+(bbmc[\w.]*)", re.MULTILINE)
_FROM_IMPORT = re.compile(r"^[ \t]*from[ \t]+(bbmc[\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)", re.MULTILINE)
_COMMENT = re.compile(r"#[^\n]*")
_announced = False


def _module_file(package: Path, module: str) -> Path | None:
    """The file of bbmc module `module` ("bbmc.dem.kernels") under `package` (the bbmc folder)."""
    path = package.joinpath(*module.split(".")[1:])
    candidates = [path / "__init__.py"] + ([path.with_suffix(".py")] if path != package else [])
    return next((candidate for candidate in candidates if candidate.is_file()), None)


def _bbmc_imports(package: Path, text: str) -> set[Path]:
    """The files of the bbmc modules a source `text` imports, anywhere in it: `import bbmc.x`, and
    `from bbmc.x import y` giving bbmc.x and, where y is a module, bbmc.x.y. Read as text, not parsed
    (parsing every module costs a fifth of a second at each start): an import quoted in a docstring
    only adds a file to the key."""
    found = {_module_file(package, module) for module in _IMPORT.findall(text)}
    for module, names in _FROM_IMPORT.findall(text):
        found.add(_module_file(package, module))
        for name in _COMMENT.sub("", names).strip("()").split(","):
            if name.split():
                found.add(_module_file(package, f"{module}.{name.split()[0]}"))
    return {path for path in found if path is not None}


def compiled_sources(package: Path = PACKAGE) -> list[Path]:
    """Every module of `package` that imports numba, and every module of it those import, directly or
    through others: all the source numba can compile into a kernel or read as a constant."""
    texts = {path: path.read_text(encoding="utf-8") for path in package.rglob("*.py")}
    pending = [path for path, text in texts.items() if _IMPORTS_NUMBA.search(text)]
    seen: set[Path] = set()
    while pending:
        path = pending.pop()
        if path not in seen:
            seen.add(path)
            pending.extend(_bbmc_imports(package, texts[path]) - seen)
    return sorted(seen)


def source_key(package: Path = PACKAGE) -> str:
    """16 hex digits of a SHA-256 over numba's version and the path and bytes of `compiled_sources`."""
    digest = hashlib.sha256(f"numba {metadata.version('numba')}\0".encode())
    for path in compiled_sources(package):
        digest.update(path.relative_to(package).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def cache_root() -> Path:
    """<cache>/bbmc/numba: $XDG_CACHE_HOME, else ~/.cache."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "bbmc" / "numba"


def prune(root: Path, keep: Path, now: float, keep_days: float = KEEP_DAYS) -> list[Path]:
    """Remove every key directory under `root` but `keep` whose stamp is older than `keep_days` days;
    return those removed. Kept that long, a key still in use by a long run is never removed under it."""
    removed = []
    for folder in root.iterdir() if root.is_dir() else ():
        if folder == keep or not folder.is_dir() or not _KEY.fullmatch(folder.name):
            continue
        stamp = folder / STAMP
        used = (stamp if stamp.exists() else folder).stat().st_mtime
        if now - used > keep_days * 86400.0:
            shutil.rmtree(folder, ignore_errors=True)
            removed.append(folder)
    return removed


def use_keyed_cache(package: Path = PACKAGE) -> Path | None:
    """Point numba's cache at <cache>/bbmc/numba/<key> (module docstring), mark it used and prune the
    old keys; return it, or None where it cannot be created (numba then keeps its own default)."""
    root = cache_root()
    folder = root / source_key(package)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        (folder / STAMP).touch()
        prune(root, folder, time.time())
    except OSError:
        return None
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    numba = sys.modules.get("numba")
    if numba is not None:  # imported before bbmc: numba read its configuration already
        numba.config.CACHE_DIR = str(folder)
    return folder


def source_subfolder(folder: Path, source: Path) -> Path:
    """Where numba keeps the kernels of the file `source` under the cache `folder`: <folder>/<name of
    the file's folder>_<SHA-1 of that folder's absolute path> (numba's
    `_CacheLocator.get_suitable_cache_subpath`)."""
    parent = os.path.dirname(os.path.abspath(source))
    return folder / f"{os.path.basename(parent)}_{hashlib.sha1(parent.encode()).hexdigest()}"


def engine_is_cold(folder: Path, package: Path = PACKAGE) -> bool:
    """True when `folder` holds no compiled engine cycle of this copy of the source (`package`) for this
    Python: the next run compiles it."""
    version = f"py{sys.version_info.major}{sys.version_info.minor}"
    kernels = source_subfolder(folder, package / "dem" / "kernels.py")
    return not any(kernels.glob(f"kernels.cycle-*.{version}.nbi"))


def current_folder() -> Path:
    """The folder numba compiles into in this process: the keyed cache (`use_keyed_cache`), or where
    it could not be made numba's own, beside the source."""
    return Path(os.environ.get("NUMBA_CACHE_DIR") or PACKAGE)


def kernel_files(folder: Path) -> dict[Path, float]:
    """The compiled kernels under `folder` (numba's *.nbc files), each with its modification time [s
    since the epoch]."""
    return {path: path.stat().st_mtime for path in folder.rglob("*.nbc")}


def written_since(before: dict[Path, float], folder: Path) -> list[Path]:
    """The compiled kernels under `folder` written (new or rewritten) since `before` =
    `kernel_files(folder)`: what the calls in between compiled rather than loaded."""
    return sorted(path for path, mtime in kernel_files(folder).items() if before.get(path) != mtime)


def jit_disabled() -> bool:
    """True when NUMBA_DISABLE_JIT is set (to anything but 0): the kernels run as plain Python."""
    return os.environ.get("NUMBA_DISABLE_JIT", "0") != "0"


def announce_engine_compile() -> None:
    """Say once per process, on stderr, that the block engine is about to be compiled, when its cache
    is cold (after an install or an update); nothing otherwise, nor with NUMBA_DISABLE_JIT=1."""
    global _announced
    folder = os.environ.get("NUMBA_CACHE_DIR")
    if _announced or not folder or jit_disabled():
        return
    _announced = True
    if engine_is_cold(Path(folder)):
        print(
            "bbmc: compiling the block engine, once after an install or an update (20-60 s)...",
            file=sys.stderr,
            flush=True,
        )
