"""Which law a contact gets, checked: a contact rule's `edges` must name a label the scene's edges can
carry, and the generator's fictitious cuts are glued unless a rule names them (`bbmc.dem.model` builds
the rules' arrays; `bbmc.dem.contact_search` applies them to each new contact)."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from bbmc.config import closest
from bbmc.dem import layout as L
from bbmc.dem.block_shapes import possible_labels
from bbmc.rockmass.cut import CUT
from bbmc.scene.schema import Contacts, Scene, scene_error

GLUED_CUT = "cut (glued)"  # the joint type of the cuts without a rule of their own (`cuts_glued_or_warned`)


class BreakableCut(UserWarning):
    """A scene gives the generator's fictitious cuts a law that can slip or break."""


def _rule_labels(scene: Scene) -> list[str]:
    """What a contact rule's `edges` may name: every label the scene's edges can carry
    (`possible_labels`: a realization may lack some) and each of its dotted prefixes (`bridge` for all
    the bridge.<set>)."""
    labels = {label for entry in scene.blocks for label in possible_labels(entry)}
    parts = [label.split(".") for label in labels]
    return sorted({".".join(p[:n]) for p in parts for n in range(1, len(p) + 1)})


def check_rule_edges(edges: str, scene: Scene, path: Path, key: str) -> None:
    """ConfigError naming `key` and the closest valid label where no edge of the scene can carry `edges`
    (a misspelt label would otherwise select nothing and leave its contacts on the default law)."""
    choices = _rule_labels(scene)
    if edges not in choices:
        hint = closest(edges, choices, "labels") if choices else " (no edge of the scene carries a label)"
        raise scene_error(path, key, f"no edge can carry the label '{edges}'{hint}")


def cuts_glued_or_warned(
    contacts: Contacts,
    law_names: list[str],
    law_codes: np.ndarray,
    params: np.ndarray,
    rule_groups: np.ndarray,
    rule_dip: np.ndarray,
    rule_law: np.ndarray,
    rule_edges: np.ndarray,
    label_names: list[str],
) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The rule for the generator's fictitious cuts (edges labelled `cut`): they only make blocks
    convex and are not rock that can break, so they never decide a factor of safety. Without a contact
    rule naming `edges: cut`, a first rule glues them: the joint type GLUED_CUT, intact rock elastic
    with the default law's stiffness and of infinite cohesion and tensile strength, which neither slips
    nor breaks and which strength reduction leaves infinite (its strength / F). It breaks into the
    default law only where no bond forms: where it first touches after the initial assembly, or where
    its edges stop facing each other. A rule that names `edges: cut` opts into the law it gives,
    breakable: a `BreakableCut` warning says so."""
    chosen = [rule for rule in contacts.rules if rule.edges == CUT]
    if chosen:
        names = ", ".join(sorted({f"'{rule.law}'" for rule in chosen}))
        warnings.warn(
            f"contacts.rules give the fictitious cuts (edges: {CUT}) the law {names}, which can slip or "
            f"break: the factor of safety may be that of rock which is not there (without a rule on "
            f"edges: {CUT} they are glued)",
            BreakableCut,
            stacklevel=3,
        )
        return law_names, law_codes, params, rule_groups, rule_dip, rule_law, rule_edges
    default = law_names.index(contacts.default_law)
    glued_codes = law_codes[default].copy()
    glued_codes[[L.STRENGTH_LAW, L.AFTER_SLIP]] = [L.STRENGTH_CONSTANT, L.AFTER_SLIP_KEEP]
    glued_codes[L.BREAKS_INTO] = default
    glued = params[default].copy()
    glued[[L.P_COH, L.P_TEN]] = math.inf
    glued_rule = np.array([[label == CUT for label in label_names]])
    return (
        [*law_names, GLUED_CUT],
        np.vstack([law_codes, glued_codes]),
        np.vstack([params, glued]),
        np.vstack([[[-1, -1]], rule_groups]),
        np.vstack([[[0.0, math.pi / 2]], rule_dip]),
        np.concatenate([[len(law_names)], rule_law]),
        np.vstack([glued_rule, rule_edges]),
    )
