"""The range of values a key of a sweep's base accepts, read from the base's own config model.

A sampled input outside the range its key accepts is physically impossible: a negative cohesion,
spacing or unit weight, a tan phi below 0, a friction angle of 90 deg or more, a JRC above 20. The
range is the key's own check, the one a config gets (docs/scene-format.md for a scene; the planar and
toppling bases of `bbmc.sweep.config`), found in the model's JSON schema (pydantic's minimum,
exclusiveMinimum, maximum, exclusiveMaximum) at the key's dotted path. The design truncates each
input's distribution to this range (`bbmc.sweep.design.Truncated`); a sample still outside it (an
input drawn without truncation) is counted apart and not run. Values are in the key's own unit.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from pydantic import BaseModel


@dataclass(frozen=True)
class Range:
    """low (<= or <) x (<= or <) high; `integer`: the key takes whole numbers only."""

    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False  # x > low (else x >= low)
    high_open: bool = False  # x < high (else x <= high)
    integer: bool = False

    def contains(self, values: ArrayLike) -> NDArray[np.bool_]:
        x = np.asarray(values, dtype=float)
        above = x > self.low if self.low_open else x >= self.low
        below = x < self.high if self.high_open else x <= self.high
        return above & below

    def __str__(self) -> str:
        parts = []
        if self.low > -math.inf:
            parts.append(f"{'>' if self.low_open else '>='} {self.low:g}")
        if self.high < math.inf:
            parts.append(f"{'<' if self.high_open else '<='} {self.high:g}")
        return " and ".join(parts) or "any number"


@functools.cache
def _schema(model: type[BaseModel]) -> dict:
    return model.model_json_schema()


def _kind_matches(node: dict, value: object) -> bool:
    kind = node.get("type")
    if isinstance(value, dict):
        return kind == "object" or "properties" in node
    if isinstance(value, list):
        return kind == "array"
    return kind in ("number", "integer")


def _resolve(node: dict, defs: dict, value: object) -> dict:
    """The schema node that applies to `value`: references followed, a union narrowed by its
    discriminator (a joint law's `law`) or else to the first variant of the value's kind."""
    while True:
        if "$ref" in node:
            node = defs[node["$ref"].rsplit("/", 1)[-1]]
        elif len(node.get("allOf", ())) == 1:
            node = node["allOf"][0]
        elif "oneOf" in node or "anyOf" in node:
            discriminator = node.get("discriminator")
            tag = (
                value.get(discriminator["propertyName"])
                if discriminator and isinstance(value, dict)
                else None
            )
            if tag in (discriminator or {}).get("mapping", {}):
                node = {"$ref": discriminator["mapping"][tag]}
                continue
            variants = [_resolve(v, defs, value) for v in node.get("oneOf", node.get("anyOf"))]
            node = next((v for v in variants if _kind_matches(v, value)), {})
        else:
            return node


def key_range(model: type[BaseModel], tree: object, path: str) -> Range:
    """The range of the number at `path` (dotted, list entries by index) of `tree`, an input of `model`
    that holds the path; a key the schema does not bound gets the unbounded Range."""
    schema = _schema(model)
    defs = schema.get("$defs", {})
    node, value = schema, tree
    for key in path.split("."):
        node = _resolve(node, defs, value)
        if isinstance(value, list):
            node, value = node.get("items", {}), value[int(key)]
        else:
            properties = node.get("properties", {})
            node = properties.get(key, node.get("additionalProperties", {}))
            value = value[key]
        if not isinstance(node, dict):  # additionalProperties: false/true
            node = {}
    node = _resolve(node, defs, value)
    low_open, high_open = "exclusiveMinimum" in node, "exclusiveMaximum" in node
    return Range(
        low=float(node.get("exclusiveMinimum", node.get("minimum", -math.inf))),
        high=float(node.get("exclusiveMaximum", node.get("maximum", math.inf))),
        low_open=low_open,
        high_open=high_open,
        integer=node.get("type") == "integer",
    )


def impossible_inputs(table: pd.DataFrame, ranges: dict[str, Range]) -> pd.Series:
    """Per sample, "" or the error of its inputs outside the ranges their keys accept
    ("impossible input: strength.tan_friction = -0.159 (accepts > 0)")."""
    messages = np.full(len(table), "", dtype=object)
    for path in table.columns:
        outside = ~ranges[path].contains(table[path].to_numpy())
        if outside.any():
            found = [
                f"{path} = {value:g} (accepts {ranges[path]})" for value in table[path].to_numpy()[outside]
            ]
            before = messages[outside]
            messages[outside] = np.where(before == "", "impossible input: ", before + "; ") + np.array(
                found, dtype=object
            )
    return pd.Series(messages, index=table.index, dtype=object)
