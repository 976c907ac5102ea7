"""The user guide cannot rot: every example it shows runs, and every link, file, module and key it
names exists.

Conventions of the pages (README.md, docs/):

* A fenced block with `title="PATH"` shows the repository file PATH: either its text verbatim (the
  README, which GitHub renders) or `--8<-- "PATH"` (MkDocs' snippets include it when the guide is
  built). Every scene or study file shown in a tutorial or how-to page is run by a command there.
* In the README, the tutorials, the how-to pages, docs/rock-mass.md and the API reference's
  docs/reference/api/api.md, every ```sh block is run
  line by line (each line a `bbmc` command) and every ```python block is executed, in the page's
  order, in one temporary folder that sees the repository's configs/, data/ and docs/. An HTML
  comment on the line before a block changes that: `<!-- not run: REASON -->` skips it;
  `<!-- slow -->` runs it only in the slow test of the page. `<!-- output: TEXT -->` after a block:
  TEXT must be in what the block printed.
"""

from __future__ import annotations

import contextlib
import importlib
import io
import re
import shlex
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path
from typing import get_args

import pytest
import yaml
from click.testing import CliRunner
from pydantic import BaseModel

from bbmc.cli import main
from bbmc.scene.schema import Scene
from bbmc.scene.schema3d import Scene3D
from bbmc.sweep.config import Config as Study

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
README = ROOT / "README.md"
RUN_PAGES = [
    README,
    *sorted((DOCS / "tutorials").glob("*.md")),
    *sorted((DOCS / "how-to").glob("*.md")),
    DOCS / "rock-mass.md",
    DOCS / "reference" / "api" / "api.md",
    DOCS / "reference" / "scene3d-format.md",
]
ALL_PAGES = [README, *sorted(DOCS.rglob("*.md"))]
SHOWN_INPUTS = ("docs/examples/", "configs/scenes/", "configs/sweeps/")
REPO_PREFIXES = ("src/", "configs/", "docs/", "tests/", "data/")


@dataclass
class Block:
    """A fenced block of a page, with the HTML comments right before and right after it."""

    lang: str
    title: str | None
    body: str
    line: int
    before: list[str] = field(default_factory=list)
    after: list[str] = field(default_factory=list)

    def marker(self, name: str) -> str | None:
        """The text of a `<!-- name: text -->` (or `<!-- name -->`) comment before the block."""
        for comment in self.before:
            if comment == name or comment.startswith(name + ":"):
                return comment[len(name) + 1 :].strip()
        return None

    @property
    def outputs(self) -> list[str]:
        return [c.split(":", 1)[1].strip() for c in self.after if c.startswith("output:")]


COMMENT = re.compile(r"^<!--\s*(.*?)\s*-->$")


def blocks(page: Path) -> list[Block]:
    lines = page.read_text(encoding="utf-8").split("\n")
    found, k = [], 0
    while k < len(lines):
        opening = re.match(r"^```(\w*)(.*)$", lines[k])
        if not opening:
            k += 1
            continue
        end = next(i for i in range(k + 1, len(lines)) if lines[i].startswith("```"))
        title = re.search(r'title="([^"]+)"', opening.group(2))
        block = Block(opening.group(1), title and title.group(1), "\n".join(lines[k + 1 : end]) + "\n", k + 1)
        i = k - 1
        while i >= 0 and COMMENT.match(lines[i]):
            block.before.insert(0, COMMENT.match(lines[i]).group(1))
            i -= 1
        i = end + 1
        while i < len(lines) and COMMENT.match(lines[i]):
            block.after.append(COMMENT.match(lines[i]).group(1))
            i += 1
        found.append(block)
        k = end + 1
    return found


def prose(page: Path) -> str:
    """The page without its fenced blocks (links and inline code are read from this)."""
    return re.sub(r"^```.*?^```", "", page.read_text(encoding="utf-8"), flags=re.M | re.S)


def _name(page: Path) -> str:
    return str(page.relative_to(ROOT))


# ---------------------------------------------------------------------------------------------------
# (a) the examples run


def _commands(block: Block) -> list[list[str]]:
    commands = []
    for line in block.body.splitlines():
        words = shlex.split(line, comments=True)
        if not words:
            continue
        assert words[0] == "bbmc", (
            f"line {block.line}: `{line}` is not a bbmc command; mark the block <!-- not run: why -->"
        )
        commands.append(words[1:])
    return commands


def _workspace(tmp_path: Path) -> Path:
    for name in ("configs", "data", "docs"):
        (tmp_path / name).symlink_to(ROOT / name, target_is_directory=True)
    return tmp_path


def _run_page(page: Path, tmp_path: Path, monkeypatch, with_slow: bool) -> None:
    monkeypatch.chdir(_workspace(tmp_path))
    namespace: dict[str, object] = {"__name__": "__docs__"}
    for block in blocks(page):
        assert block.lang not in ("bash", "shell", "console", "py"), (
            f"{_name(page)}:{block.line}: write ```sh or ```python, the languages the tests run"
        )
        if block.lang not in ("sh", "python"):
            continue
        if block.marker("not run") is not None:
            assert block.marker("not run"), f"{_name(page)}:{block.line}: say why it is not run"
            continue
        if block.marker("slow") is not None and not with_slow:
            continue
        where = f"{_name(page)}:{block.line}"
        if block.lang == "sh":
            printed = ""
            for args in _commands(block):
                outcome = CliRunner().invoke(main, args)
                assert outcome.exit_code == 0, f"{where}: bbmc {' '.join(args)}\n{outcome.output}"
                printed += outcome.output
        else:
            buffer = io.StringIO()
            with contextlib.redirect_stdout(buffer):
                exec(compile(block.body, where, "exec"), namespace)
            printed = buffer.getvalue()
        for text in block.outputs:
            assert text in printed, f"{where}: expected {text!r} in\n{printed}"


def _has_slow(page: Path) -> bool:
    return any(b.marker("slow") is not None for b in blocks(page))


@pytest.mark.parametrize("page", RUN_PAGES, ids=_name)
def test_every_example_of_the_page_runs(page, tmp_path, monkeypatch):
    _run_page(page, tmp_path, monkeypatch, with_slow=False)


@pytest.mark.slow
@pytest.mark.parametrize("page", [p for p in RUN_PAGES if _has_slow(p)], ids=_name)
def test_every_example_of_the_page_runs_with_the_slow_ones(page, tmp_path, monkeypatch):
    _run_page(page, tmp_path, monkeypatch, with_slow=True)


@pytest.mark.parametrize("page", ALL_PAGES, ids=_name)
def test_a_file_shown_is_the_file_itself(page):
    for block in blocks(page):
        if block.title is None:
            continue
        path = ROOT / block.title
        assert path.is_file(), f"{_name(page)}:{block.line}: no file {block.title}"
        included = block.body.strip() == f'--8<-- "{block.title}"'
        assert included or block.body == path.read_text(encoding="utf-8"), (
            f"{_name(page)}:{block.line}: the block differs from {block.title}; include it with "
            f'--8<-- "{block.title}" or copy it exactly'
        )


@pytest.mark.parametrize("page", RUN_PAGES, ids=_name)
def test_every_scene_or_study_shown_is_run_on_its_page(page):
    run = {
        arg
        for block in blocks(page)
        if block.lang == "sh" and block.marker("not run") is None
        for args in _commands(block)
        for arg in args
    }
    for block in blocks(page):
        if block.title and block.title.startswith(SHOWN_INPUTS):
            assert block.title in run, f"{_name(page)}:{block.line}: {block.title} is shown but never run"


def test_the_readme_is_a_front_page():
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 250
    assert not re.search(r"\bissue \d+", text, re.I)


def test_the_readme_links_every_tutorial():
    linked = set(re.findall(r"\]\((docs/tutorials/[^)#\s]+\.md)", README.read_text(encoding="utf-8")))
    tutorials = {str(p.relative_to(ROOT)) for p in (DOCS / "tutorials").glob("*.md")}
    assert tutorials, "no tutorial found"
    assert tutorials <= linked, f"not linked from README.md: {sorted(tutorials - linked)}"


# ---------------------------------------------------------------------------------------------------
# (b) links, files, modules and keys


def slugify(text: str) -> str:
    """A heading's anchor as MkDocs makes it (Python-Markdown's toc.slugify on the heading's text)."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text).replace("`", "").replace("*", "")
    text = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode("ascii")
    text = re.sub(r"[^\w\s-]", "", text).strip().lower()
    return re.sub(r"[-\s]+", "-", text)


def anchors(page: Path) -> set[str]:
    seen: dict[str, int] = {}
    found = set()
    for heading in re.findall(r"^#{1,6} (.+)$", prose(page), flags=re.M):
        slug = slugify(heading)
        found.add(slug if slug not in seen else f"{slug}_{seen[slug]}")
        seen[slug] = seen.get(slug, 0) + 1
    return found


LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


@pytest.mark.parametrize("page", ALL_PAGES, ids=_name)
def test_every_link_and_anchor_exists(page):
    for target in LINK.findall(re.sub(r"`[^`\n]*`", "", prose(page))):
        if re.match(r"[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        resolved = (page.parent / path).resolve() if path else page
        assert resolved.exists(), f"{_name(page)}: broken link {target}"
        if page != README:
            assert resolved.is_relative_to(DOCS), (
                f"{_name(page)}: {target} leaves docs/ (the site has no such page)"
            )
        if anchor:
            assert anchor in anchors(resolved), (
                f"{_name(page)}: no heading '#{anchor}' in {path or 'the page'}"
            )


def _inline_code(page: Path) -> list[str]:
    return re.findall(r"`([^`\n]+)`", prose(page))


@pytest.mark.parametrize("page", ALL_PAGES, ids=_name)
def test_every_repository_file_named_exists(page):
    for span in _inline_code(page):
        if span.startswith(REPO_PREFIXES) and not re.search(r"[<*{\s]", span):
            assert (ROOT / span.rstrip("/")).exists(), f"{_name(page)}: `{span}` does not exist"


def _resolves(dotted: str) -> bool:
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            target = importlib.import_module(".".join(parts[:cut]))
        except ModuleNotFoundError:
            continue
        for name in parts[cut:]:
            if not hasattr(target, name):
                return False
            target = getattr(target, name)
        return True
    return False


@pytest.mark.parametrize("page", ALL_PAGES, ids=_name)
def test_every_module_and_function_named_exists(page):
    for span in _inline_code(page):
        if re.fullmatch(r"bbmc(\.\w+)+", span):
            assert _resolves(span), f"{_name(page)}: `{span}` is not a module or an attribute of one"


def _fields(model: type[BaseModel], seen: set | None = None) -> set[str]:
    """Every key of a config model and of the models it holds."""
    seen = set() if seen is None else seen
    if model in seen:
        return set()
    seen.add(model)
    names = set(model.model_fields)
    for info in model.model_fields.values():
        stack = [info.annotation]
        while stack:
            kind = stack.pop()
            if isinstance(kind, type) and issubclass(kind, BaseModel):
                names |= _fields(kind, seen)
            stack.extend(get_args(kind))
    return names


def _table_keys(page: Path) -> set[str]:
    """The keys in the first column of every table whose header's first column is `key`."""
    keys, in_table = set(), False
    for line in prose(page).splitlines():
        if line.startswith("| key |"):
            in_table = True
            continue
        if not line.startswith("|"):
            in_table = False
        elif in_table and not line.startswith("|---"):
            keys |= set(re.findall(r"`(\w+)`", line.split("|")[1]))
    return keys


@pytest.mark.parametrize(
    "page, model",
    [
        (DOCS / "scene-format.md", Scene),
        (DOCS / "reference" / "study-format.md", Study),
        (DOCS / "reference" / "scene3d-format.md", Scene3D),
    ],
    ids=["scene-format", "study-format", "scene3d-format"],
)
def test_every_key_documented_is_read_and_every_key_read_is_documented(page, model):
    documented, read = _table_keys(page), _fields(model)
    assert documented, page
    assert documented <= read, f"documented but not read: {sorted(documented - read)}"
    named = {word for span in _inline_code(page) for word in re.findall(r"\w+", span)}
    for block in blocks(page):
        if block.lang == "yaml":
            named |= set(re.findall(r"(\w+):", block.body))
    assert read <= named, f"read but never named in {_name(page)}: {sorted(read - named)}"


def test_every_page_is_in_the_guide_and_every_entry_exists():
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))

    def entries(nav):
        for item in nav:
            value = next(iter(item.values())) if isinstance(item, dict) else item
            yield from entries(value) if isinstance(value, list) else [value]

    listed = list(entries(config["nav"]))
    assert len(listed) == len(set(listed))
    pages = {str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md")}
    assert set(listed) == pages, (
        f"not in the nav: {sorted(pages - set(listed))}; missing: {sorted(set(listed) - pages)}"
    )
    assert config["strict"] is True


# ---------------------------------------------------------------------------------------------------
# docs/architecture.md


ARCHITECTURE = DOCS / "architecture.md"


def _architecture_files() -> list[str]:
    return re.findall(r"^\| `(src/bbmc/[^`]*)` \|", ARCHITECTURE.read_text(encoding="utf-8"), flags=re.M)


def test_the_architecture_table_names_every_file_and_package_that_exists():
    named = _architecture_files()
    assert len(named) == len(set(named))
    for path in named:
        assert (ROOT / path).exists(), f"{path} is in the table but does not exist"
    package = ROOT / "src" / "bbmc"
    engine = sorted(f"src/bbmc/dem/{p.name}" for p in (package / "dem").glob("*.py"))
    top = sorted(
        f"src/bbmc/{p.name}" + ("/" if p.is_dir() else "")
        for p in package.iterdir()
        if p.suffix == ".py" or (p.is_dir() and (p / "__init__.py").exists() and p.name != "dem")
    )
    missing = [path for path in engine + top if path not in named]
    assert not missing, f"not in docs/architecture.md: {missing}"


def test_every_step_of_the_time_step_exists_in_the_engine():
    """`module.function` spans of the time-step walk name real functions; a bare name is an engine
    module, a name in one (a function, a layout constant), a string it uses, or a scene key."""
    text = ARCHITECTURE.read_text(encoding="utf-8")
    walk = text[text.index("## One time step") :]
    modules = {
        p.stem: importlib.import_module(f"bbmc.dem.{p.stem}")
        for p in (ROOT / "src" / "bbmc" / "dem").glob("*.py")
        if p.stem != "__init__"
    }
    words = {w for m in modules.values() for w in re.findall(r'"(\w+)"', Path(m.__file__).read_text())}
    names = set().union(*(vars(m) for m in modules.values())) | _fields(Scene) | words
    for span in re.findall(r"`([\w.]+)`", walk):
        head, _, tail = span.partition(".")
        if head in modules and tail:
            assert hasattr(modules[head], tail), f"`{span}`: bbmc.dem.{head} has no {tail}"
        elif not tail:
            assert span in names or span in modules, f"`{span}` is in no engine module and is no scene key"
