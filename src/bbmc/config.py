"""YAML config -> validated, frozen pydantic models; every failure is one `ConfigError` line.

A config is validated whole before a stage does any work: unknown keys (with the closest valid key
suggested), missing keys, wrong types (strict: "3.3" is not a number) and out-of-range values all
stop the run with `<file>: key '<dotted.key>': <what is wrong>`. Paths in a config are relative to the
config file's folder and must exist.
"""

from __future__ import annotations

import difflib
from pathlib import Path
from typing import Annotated, Any, TypeVar

import yaml
from pydantic import AfterValidator, BaseModel, ConfigDict, Field, ValidationError, ValidationInfo


class ConfigError(Exception):
    """A bad config or input file: the message is the one line the user sees."""


class Section(BaseModel):
    """Base of every config section: frozen, strict types, no unknown keys, no NaN or infinite numbers."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)


def _existing_file(value: Path, info: ValidationInfo) -> Path:
    base = Path((info.context or {}).get("base_dir", "."))
    path = value if value.is_absolute() else base / value
    if not path.is_file():
        raise ValueError(f"file not found: {path}")
    return path


InputFile = Annotated[Path, Field(strict=False), AfterValidator(_existing_file)]

ModelT = TypeVar("ModelT", bound=BaseModel)


def _dotted(loc: tuple[Any, ...]) -> str:
    return ".".join(str(part) for part in loc)


def _parent_model(model: type[BaseModel], loc: tuple[Any, ...]) -> type[BaseModel] | None:
    """The model class that owns the last key of `loc`, to suggest valid keys from."""
    current: Any = model
    for part in loc[:-1]:
        if not (isinstance(current, type) and issubclass(current, BaseModel)):
            return None
        field = current.model_fields.get(str(part))
        if field is None:
            return None
        current = field.annotation
    return current if isinstance(current, type) and issubclass(current, BaseModel) else None


def _describe(model: type[BaseModel], error: dict[str, Any]) -> str:
    loc = tuple(error["loc"])
    key = _dotted(loc)
    if error["type"] == "extra_forbidden":
        parent = _parent_model(model, loc)
        valid = list(parent.model_fields) if parent else []
        close = difflib.get_close_matches(str(loc[-1]), valid, n=1)
        hint = f" (did you mean '{close[0]}'?)" if close else f" (valid keys: {', '.join(valid)})"
        return f"key '{key}': unknown key{hint}"
    if error["type"] == "missing":
        return f"key '{key}': missing"
    message = error["msg"].removeprefix("Value error, ")
    return f"key '{key}': {message}, got {error['input']!r}"


def load_config(path: str | Path, model: type[ModelT]) -> ModelT:
    """Read, parse and validate a YAML config; raise `ConfigError` with one line on any fault."""
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"{path}: config file not found")
    try:
        raw = yaml.safe_load(path.read_text(encoding="utf-8"))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or "cannot parse"
        raise ConfigError(f"{path}: invalid YAML{where}: {problem}") from None
    if not isinstance(raw, dict):
        raise ConfigError(f"{path}: top level must be a mapping of keys, got {type(raw).__name__}")
    try:
        return model.model_validate(raw, context={"base_dir": path.parent})
    except ValidationError as exc:
        errors = sorted(exc.errors(), key=lambda e: e["type"] != "extra_forbidden")
        raise ConfigError(f"{path}: {_describe(model, errors[0])}") from None
