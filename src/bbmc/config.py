"""YAML config -> validated, frozen pydantic models; every failure is one `ConfigError` line.

A config is validated whole before a stage does any work: unknown keys (with the closest valid key
suggested), missing keys, wrong types (strict: "3.3" is not a number) and out-of-range values all
stop the run with `<file>: key '<dotted.key>': <what is wrong>`, the key in the user's own path. Paths
in a config are relative to the config file's folder, `..` taken as written (configs/../results is
results beside configs, even where configs is a link to another folder), and must exist. A valid
config's values outside their plausible range for rock are then warned about (`bbmc.plausibility`).
"""

from __future__ import annotations

import difflib
import os
import re
from collections.abc import Iterator
from pathlib import Path
from types import UnionType
from typing import Annotated, Any, Literal, TypeVar, Union, get_args, get_origin

import yaml
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    ValidationInfo,
    field_validator,
)

from bbmc import plausibility


class ConfigError(Exception):
    """A bad config or input file: the message is the one line the user sees."""


class ConfigKeyError(Exception):
    """A key of the config whose value the run found meaningless (e.g. set windows that catch nothing):
    the command turns it into a `ConfigError` naming the config file, the `key` and the `text`."""

    def __init__(self, key: str, text: str) -> None:
        super().__init__(f"key '{key}': {text}")
        self.key, self.text = key, text


# YAML 1.2's floats, which PyYAML (YAML 1.1) reads as strings when the exponent has no dot (1e4,
# 1E-3, 2.5e+6 are numbers for every engineer) or when the leading zero is left out (.5).
_FLOAT = (
    r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?(?:[eE][-+]?[0-9]+)?"  # 1, 1.5, 1e4, 2.5e+6
    r"|\.[0-9_]+(?:[eE][-+]?[0-9]+)?"  # .5, .5e-3
    r"|\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"
)


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader with YAML 1.2 floats, and a key given twice in one mapping refused (the
    last value would win silently otherwise)."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        seen: dict[object, int] = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            line = key_node.start_mark.line + 1
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None,
                    None,
                    f"key '{key}' is given twice (lines {seen[key]} and {line})",
                    key_node.start_mark,
                )
            seen[key] = line
        return super().construct_mapping(node, deep)


_Loader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != "tag:yaml.org,2002:float"]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_implicit_resolver("tag:yaml.org,2002:float", re.compile(_FLOAT), list("-+0123456789."))


def read_yaml(path: str | Path) -> object:
    """A YAML file's content (YAML 1.2 numbers; a repeated key refused); any file that cannot be read as
    YAML text is a one-line `ConfigError` naming it."""
    path = Path(path)
    if path.is_dir():
        raise ConfigError(f"{path}: is a folder, not a file")
    if not path.is_file():
        raise ConfigError(f"{path}: file not found")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as error:
        raise ConfigError(
            f"{path}: not UTF-8 text (byte {error.start}): a binary file, or another encoding"
        ) from None
    except OSError as error:
        raise ConfigError(f"{path}: cannot read: {error.strerror}") from None
    try:
        return yaml.load(text, Loader=_Loader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or "cannot parse"
        raise ConfigError(f"{path}: invalid YAML{where}: {problem}") from None


LARGEST_WHOLE = 2**53  # whole numbers up to it are exact in floating point, where the engine keeps counts


def _whole_numbers(value: object) -> Iterator[int]:
    if isinstance(value, int) and not isinstance(value, bool):
        yield value
    elif isinstance(value, list | tuple):
        for item in value:
            yield from _whole_numbers(item)


class Section(BaseModel):
    """Base of every config section: frozen, strict types, no unknown keys, no NaN or infinite numbers,
    no whole number beyond 2^53 in size (a step count of 5e31 overflowed the engine's 64-bit integers)."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)

    @field_validator("*")
    @classmethod
    def _whole_numbers_fit(cls, value: object) -> object:
        if any(abs(number) > LARGEST_WHOLE for number in _whole_numbers(value)):
            raise ValueError(
                f"a whole number beyond 2^53 = {LARGEST_WHOLE:,} in size (not exact in floating point)"
            )
        return value


def _existing_file(value: Path, info: ValidationInfo) -> Path:
    base = Path((info.context or {}).get("base_dir", "."))
    path = value if value.is_absolute() else Path(os.path.normpath(base / value))
    if not path.is_file():
        raise ValueError(f"file not found: {path}")
    return path


InputFile = Annotated[Path, Field(strict=False), AfterValidator(_existing_file)]

ModelT = TypeVar("ModelT", bound=BaseModel)


def _unwrapped(annotation: Any) -> Any:
    """The type under `Annotated[...]` and `X | None`; a union of several types stays a union."""
    while get_origin(annotation) is Annotated:
        annotation = get_args(annotation)[0]
    if get_origin(annotation) in (Union, UnionType):
        members = [a for a in get_args(annotation) if a is not type(None)]
        if len(members) == 1:
            return _unwrapped(members[0])
    return annotation


def _is_model(annotation: Any) -> bool:
    return isinstance(annotation, type) and issubclass(annotation, BaseModel)


def _tags(model: type[BaseModel]) -> set[object]:
    """The values of the model's required `Literal` fields: the tags a discriminated union knows it by."""
    return {
        value
        for field in model.model_fields.values()
        if field.is_required() and get_origin(field.annotation) is Literal
        for value in get_args(field.annotation)
    }


def _member(union: Any, label: object) -> Any:
    """The member of a union that pydantic names `label` in an error's location (its tag, or its class
    name); None if none can be told."""
    for member in (_unwrapped(a) for a in get_args(union)):
        if _is_model(member) and (label == member.__name__ or label in _tags(member)):
            return member
    return None


def _child(annotation: Any, part: object) -> Any:
    """The type of `part` (a field name, a mapping key, a list index) inside `annotation`."""
    if _is_model(annotation):
        field = annotation.model_fields.get(str(part))
        return field.annotation if field is not None else None
    origin, args = get_origin(annotation), get_args(annotation)
    if origin is dict and len(args) == 2:
        return args[1]
    if origin is list and args:
        return args[0]
    return None


def _user_location(model: type[BaseModel], loc: tuple[Any, ...]) -> tuple[str, type[BaseModel] | None]:
    """The dotted key of an error's `loc` as the user wrote it (without the union members pydantic adds
    to a location: a joint law's `constant`, a value's `float`), and the model that owns its last key
    (to suggest valid keys from; None where the key is not a model's field)."""
    keys: list[str] = []
    current: Any = model
    owner: type[BaseModel] | None = None
    for part in loc:
        if part == "[key]":  # pydantic's mark of a mapping's key (rather than its value) at fault
            continue
        current = _unwrapped(current)
        if get_origin(current) in (Union, UnionType):
            current = _member(current, part)
            continue
        owner = current if _is_model(current) else None
        keys.append(str(part))
        current = _child(current, part)
    return ".".join(keys), owner


def closest(word: str, choices: list[str], noun: str) -> str:
    """' (did you mean ...?)' with the closest of `choices` to a misspelt `word`, else the list of them
    (`noun`: what they are): the hint every refusal of a name gives."""
    close = difflib.get_close_matches(word, choices, n=1)
    return f" (did you mean '{close[0]}'?)" if close else f" (valid {noun}: {', '.join(choices)})"


def _misspelt_tag(error: dict[str, Any]) -> str | None:
    """The key given in place of a discriminated union's absent tag key (`lwa` for `law`), or None."""
    field = error["ctx"]["discriminator"].strip("'")
    given = [str(name) for name in error["input"]] if isinstance(error["input"], dict) else []
    close = difflib.get_close_matches(field, given, n=1)
    return close[0] if close else None


def _missing_key(model: type[BaseModel], error: dict[str, Any]) -> str | None:
    """The dotted key of an error that is a required key left out (a discriminated union's tag key
    too, unless a misspelling of it was given), or None for any other error."""
    if error["type"] not in ("missing", "union_tag_not_found"):
        return None
    key, _ = _user_location(model, tuple(error["loc"]))
    if error["type"] == "missing":
        return key
    if _misspelt_tag(error) is not None:
        return None
    return ".".join([*filter(None, [key]), error["ctx"]["discriminator"].strip("'")])


def _describe(model: type[BaseModel], error: dict[str, Any]) -> str:
    key, owner = _user_location(model, tuple(error["loc"]))
    kind, context = error["type"], error.get("ctx") or {}
    if kind == "extra_forbidden":
        hint = closest(str(error["loc"][-1]), list(owner.model_fields), "keys") if owner else ""
        return f"key '{key}': unknown key{hint}"
    missing = _missing_key(model, error)
    if missing is not None:
        return f"key '{missing}': missing"
    if kind in ("union_tag_invalid", "union_tag_not_found"):
        field = context["discriminator"].strip("'")
        prefix = f"{key}." if key else ""
        if kind == "union_tag_not_found":
            return f"key '{prefix}{_misspelt_tag(error)}': unknown key (did you mean '{field}'?)"
        key = prefix + field
        tags = re.findall(r"'([^']*)'", context["expected_tags"])
        return f"key '{key}': unknown {field} '{context['tag']}'{closest(context['tag'], tags, field + 's')}"
    message = error["msg"].removeprefix("Value error, ")
    if not isinstance(error["input"], dict):  # a whole section is not repeated back
        message += f", got {error['input']!r}"
    if kind == "literal_error" and isinstance(error["input"], str):
        message += closest(error["input"], re.findall(r"'([^']*)'", context["expected"]), "values")
    inner = re.fullmatch(r"key '([^']*)': (.*)", message, flags=re.DOTALL)
    if key and inner:  # a section's validator naming its own keys: each under the section's path
        key = ", ".join(f"{key}.{name}" for name in inner[1].split(", "))
        message = inner[2]
    return f"key '{key}': {message}" if key else message


def _first_fault(model: type[BaseModel], errors: list[dict[str, Any]]) -> str:
    """The one line of a config's faults: an unknown key first (a misspelt key also shows as a missing
    one); where the fault to report is a missing key, every missing key at once, so that the user
    does not learn them one run at a time."""
    first = sorted(errors, key=lambda e: e["type"] != "extra_forbidden")[0]
    missing = list(dict.fromkeys(k for e in errors if (k := _missing_key(model, e)) is not None))
    if _missing_key(model, first) is None or len(missing) == 1:
        return _describe(model, first)
    keys = ", ".join(f"'{key}'" for key in missing)
    return f"keys {keys}: missing"


def load_config(path: str | Path, model: type[ModelT]) -> ModelT:
    """Read, parse and validate a YAML config; raise `ConfigError` with one line on any fault."""
    path = Path(path)
    if not path.exists():
        raise ConfigError(f"{path}: config file not found")
    raw = read_yaml(path)
    if raw is None:
        raise ConfigError(f"{path}: the file is empty")
    return validate(raw, model, str(path), path.parent)


def validate(
    raw: object,
    model: type[ModelT],
    source: str,
    base_dir: Path = Path("."),
    strict: bool | None = None,
    typed: bool = True,
) -> ModelT:
    """Validate a parsed config (a mapping) against `model`; `source` names it in the one-line
    `ConfigError`; relative paths in it are taken from `base_dir`; `strict=False` lets a config that
    code builds pass numbers of other types (numpy's) where the model's types are strict. A valid
    typed config's values far beyond their plausible range for rock are refused (`ConfigError`), and
    those outside it warned about (`bbmc.plausibility.ImplausibleValue`); `typed=False` (a config the
    program built from numbers it computed, already checked or its own) checks neither."""
    if not isinstance(raw, dict):
        raise ConfigError(f"{source}: top level must be a mapping of keys, got {type(raw).__name__}")
    try:
        settings = model.model_validate(raw, strict=strict, context={"base_dir": base_dir})
    except ValidationError as exc:
        raise ConfigError(f"{source}: {_first_fault(model, exc.errors())}") from None
    if typed:
        refused = plausibility.refused_values(raw, source)
        if refused:
            raise ConfigError(refused[0])
        plausibility.warn(raw, source)
    return settings
