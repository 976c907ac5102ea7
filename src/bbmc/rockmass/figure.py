"""A figure of a rock mass realization: its blocks, and every edge drawn by what it is (`edge_style`,
which `bbmc run`'s scene.png shares): a set's joints solid and its rock bridges dashed (one colour a
set, the bridges a dark shade of it), fictitious cuts dotted grey, the tension crack solid red, the
model's boundary thin black."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import to_rgb
from matplotlib.figure import Figure

from bbmc.rockmass.config import CRACK
from bbmc.rockmass.generate import RockMass

SET_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive")


def _edges(mass: RockMass) -> dict[str, list[np.ndarray]]:
    """The edges of every block by label, each shared edge once (the first block's)."""
    seen, by_label = set(), {}
    for polygon, labels in zip(mass.polygons, mass.edge_labels, strict=True):
        for k, label in enumerate(labels):
            segment = np.array([polygon[k], polygon[(k + 1) % len(polygon)]])
            key = tuple(sorted(map(tuple, np.round(segment, 9))))
            if key not in seen:
                seen.add(key)
                by_label.setdefault(label, []).append(segment)
    return by_label


def set_name(label: str) -> str | None:
    """The joint set an edge label belongs to: <set> of joint.<set> and bridge.<set>, a scene's own label
    (no kind: `edge_labels` of a polygon) as a set of its own; None for a boundary and a cut."""
    if label in ("", "cut"):
        return None
    kind, dot, name = label.partition(".")
    return name if dot and kind in ("joint", "bridge") else label


def set_colours(labels: list[str]) -> dict[str, str]:
    """One colour per joint set among the edge `labels` (`set_name`), in their order."""
    names = dict.fromkeys(name for name in map(set_name, labels) if name not in (None, CRACK))
    return {name: SET_COLOURS[i % len(SET_COLOURS)] for i, name in enumerate(names)}


def _dark(colour: str) -> tuple[float, float, float]:
    return tuple(0.55 * c for c in to_rgb(colour))


def edge_style(label: str, colours: dict[str, str]) -> dict:
    """How an edge labelled `label` is drawn (`LineCollection` keywords, with its legend label): a set's
    joints solid in the set's colour (`colours`) and its rock bridges dashed in a dark shade of it, with
    white gaps (read on any block edge drawn below); a cut dotted dark grey, the tension crack solid red,
    the boundary thin black."""
    name = set_name(label)
    if name is None and label == "cut":
        return {
            "colors": "0.25",
            "linewidths": 1.3,
            "linestyles": "dotted",
            "gapcolor": "white",
            "label": "cut (intact rock)",
        }
    if name is None:
        return {"colors": "black", "linewidths": 0.8, "label": "boundary"}
    if name == CRACK:
        return {"colors": "tab:red", "linewidths": 1.6, "label": "tension crack"}
    if label.startswith("bridge."):
        dashed = {"linestyles": (0, (4, 2)), "gapcolor": "white"}
        return {
            "colors": [_dark(colours[name])],
            "linewidths": 1.5,
            **dashed,
            "label": f"{name} bridges",
        }
    return {"colors": colours[name], "linewidths": 1.2, "label": f"{name} joints"}


def rock_mass_figure(mass: RockMass, dpi: int = 120, title: str | None = None) -> Figure:
    """The blocks (light grey, held ones darker) with their edges drawn by label."""
    extent = np.ptp(mass.outline, axis=0)
    figure = Figure(figsize=(10, max(3.0, 10 * extent[1] / extent[0] + 1.2)), dpi=dpi)
    ax = figure.add_subplot()
    shades = ["0.80" if held else "0.93" for held in mass.held]
    ax.add_collection(PolyCollection(mass.polygons, facecolors=shades, edgecolors="none"))
    colours = set_colours([f"joint.{name}" for name in mass.sets])
    edges = _edges(mass)
    order = sorted(edges, key=lambda label: (label.startswith("bridge"), label))
    for label in order:
        ax.add_collection(LineCollection(edges[label], **edge_style(label, colours)))
    low, high = mass.outline.min(axis=0), mass.outline.max(axis=0)
    pad = 0.03 * float(extent.max())
    ax.set_xlim(low[0] - pad, high[0] + pad)
    ax.set_ylim(low[1] - pad, high[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(loc="upper left", fontsize=8, framealpha=0.9)
    ax.set_title(title or f"{len(mass.polygons)} blocks, seed {mass.seed} (held blocks darker)")
    figure.tight_layout()
    return figure
