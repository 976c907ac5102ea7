"""Keys of a scene by dotted path (`blocks.0.rock_mass.seed`, `materials.rock.density_kg_m3`): read or
set one in a parsed scene, and a validated scene with some of its values changed (`with_values`), as
sweeps and studies vary a base scene and as a script does from Python."""

from __future__ import annotations

from collections.abc import Mapping

from bbmc.config import ConfigError, closest, validate
from bbmc.scene.schema import Scene


def _step(tree: object, key: str) -> tuple[object, object]:
    """The child of a mapping (by key) or a list (by index) and the key to reach it."""
    if isinstance(tree, list):
        index = int(key) if key.lstrip("-").isdigit() else None
        if index is None or not -len(tree) <= index < len(tree):
            raise KeyError(key)
        return tree[index], index
    if isinstance(tree, dict) and key in tree:
        return tree[key], key
    raise KeyError(key)


def get_path(tree: object, path: str) -> object:
    """The value at a dotted path (list entries by index); KeyError naming the first missing part."""
    for key in path.split("."):
        tree, _ = _step(tree, key)
    return tree


def set_path(tree: object, path: str, value: object) -> None:
    """Set the value at a dotted path that exists (KeyError naming the first missing part otherwise)."""
    *parents, last = path.split(".")
    for key in parents:
        tree, _ = _step(tree, key)
    _, key = _step(tree, last)
    tree[key] = value


def _no_such_key(tree: object, path: str, source: str) -> ConfigError:
    """The one line for a path that leads nowhere: the path, its first missing part, and the closest
    key there (or the range of indices of a list)."""
    parts = path.split(".")
    for depth, key in enumerate(parts):
        try:
            tree, _ = _step(tree, key)
        except KeyError:
            where = ".".join(parts[:depth]) or "the top level"
            if isinstance(tree, list):
                indices = f"indices 0 to {len(tree) - 1}" if len(tree) > 1 else "index 0 only"
                hint = f" ('{where}' is a list of {len(tree)}: {indices})"
            elif isinstance(tree, dict):
                hint = closest(key, [str(k) for k in tree], "keys")
            else:
                hint = f" ('{where}' is a value, not a section)"
            return ConfigError(f"{source}: key '{path}': no '{key}' there{hint}")
    raise AssertionError(f"{path} exists")  # only called for a path that raised KeyError


def with_values(scene: Scene, values: Mapping[str, object]) -> Scene:
    """A new scene: `scene` with the value at each dotted path of `values` replaced (list entries by
    index, e.g. ``{"blocks.0.rock_mass.seed": 5, "materials.rock.density_kg_m3": 2600}``), validated
    whole as a scene file is: a path that is no key of the scene, or a value the scene format refuses,
    raises `ConfigError` in one line naming the path; a value outside its plausible range for rock is
    warned about (`bbmc.plausibility.ImplausibleValue`), as on loading. `scene` itself is unchanged
    (a validated scene is frozen). The values are in the scene format's units (the key's own: m, deg,
    MPa, kg/m³)."""
    source = f"<scene {scene.name}>" if scene.name else "<scene>"
    tree = scene.model_dump(mode="python")
    for path, value in values.items():
        try:
            set_path(tree, path, value)
        except KeyError:
            raise _no_such_key(tree, path, source) from None
    return validate(tree, Scene, source)


def with_threads(scene: Scene, threads: int | None) -> Scene:
    """The scene with solver.threads set to `threads` (`bbmc run --threads`, `bbmc.api.run(threads=)`),
    or as it is (None: the scene's own, else every core). The results are the same to the bit for any
    number of threads (each contact's force is computed alone, each block sums its contacts' in
    contact order)."""
    if threads is None:
        return scene
    if not (isinstance(threads, int) and threads >= 1):
        raise ConfigError(f"threads: {threads!r}: give a whole number of 1 or more")
    return scene.model_copy(update={"solver": scene.solver.model_copy(update={"threads": threads})})
