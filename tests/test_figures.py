"""No text of any figure a stage draws falls outside its canvas (a clipped title, a label run off the
figure): every stage's figures, drawn and measured with matplotlib's own text extents. And the block
figures show what loads a scene: its phreatic surface and its seismic load, the mechanism's FS, the
monitors against time (the unbalanced-force ratio on a log axis with its target), the edges by what
they are, and the mechanism's arrows as the blocks moved, to a scale."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.quiver import Quiver, QuiverKey
from matplotlib.text import Annotation, Text

from bbmc import api
from bbmc.config import load_config, read_yaml
from bbmc.dem import layout as L
from bbmc.dem.model import Model, build_model
from bbmc.dem.solver import initial_state
from bbmc.fos.result import StrengthReductionResult, Trial
from bbmc.fos.strength_reduction import factor_of_safety
from bbmc.outputs.figures import (
    WATER_COLOUR,
    bracketing_figure,
    colour_top,
    fos_title,
    history_figure,
    mechanism_figure,
    scene_figure,
)
from bbmc.outputs.vtk import read_vtu
from bbmc.stages import fit, joint, mc, slope, sweep
from stage_runs import config_copy

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = ROOT / "configs"


def _leaves(box, canvas, slack_px: float) -> bool:
    return (
        box.x0 < canvas.x0 - slack_px
        or box.y0 < canvas.y0 - slack_px
        or box.x1 > canvas.x1 + slack_px
        or box.y1 > canvas.y1 + slack_px
    )


def texts_outside(fig: Figure, slack_px: float = 1.0) -> list[str]:
    """What leaves the canvas (by more than `slack_px`): each axes whose drawn extent (its title, labels,
    the tick labels it draws, legends) does, named by its title or label, and each figure-level text
    (a suptitle) that does."""
    canvas_agg = FigureCanvasAgg(fig)  # Figure() objects come without a drawing canvas
    canvas_agg.draw()
    renderer = canvas_agg.get_renderer()
    canvas = fig.bbox
    outside = [
        f"axes '{ax.get_title() or ax.get_ylabel() or ax.get_xlabel()}'"
        for ax in fig.axes
        if _leaves(ax.get_tightbbox(renderer), canvas, slack_px)
    ]
    labels = (getattr(fig, f"_{k}", None) for k in ("suptitle", "supxlabel", "supylabel"))
    figure_texts = [*fig.texts, *labels]
    outside += [
        f"text '{t.get_text()[:60]}'"
        for t in figure_texts
        if isinstance(t, Text) and t.get_visible() and t.get_text().strip()
        and _leaves(t.get_window_extent(renderer), canvas, slack_px)
    ]  # fmt: skip
    return outside


def _assert_inside(figures: dict[str, Figure]) -> None:
    assert figures
    clipped = {name: texts for name, fig in figures.items() if (texts := texts_outside(fig))}
    assert not clipped, clipped


@pytest.mark.parametrize("stage", [fit, mc, joint])
def test_quick_stages_draw_every_text_inside_the_canvas(tmp_path, stage):
    config = load_config(config_copy(tmp_path, stage.NAME, lambda data: None), stage.Config)
    _assert_inside(stage.run(config).figures)


@pytest.mark.slow  # the whole slope stage, 15 s
def test_the_slope_stages_figures_draw_every_text_inside_the_canvas(tmp_path):
    """Figs 7-10, fs_vs_dip, dip_sensitivity and the two mechanisms (the sensitivity cut to two dips and
    no animation, to keep it short: the figures are the same kind); and the slope's ParaView series
    (`vtk_every_records`): one VTU per kept record, each with the 34 blocks."""

    def shorter(data: dict) -> None:
        data["sensitivity"]["dips_deg"] = [20.0, 30.0]
        data["animation_frames"] = 0
        data["vtk_every_records"] = 300  # and its ParaView series, read back below

    config = load_config(config_copy(tmp_path, "slope", shorter), slope.Config)
    result = slope.run(config)
    _assert_inside(result.figures)
    for kind in ("constant", "barton_bandis"):
        pvd = result.files[f"vtk/{kind}/blocks.pvd"]
        vtu = sorted(name for name in result.files if name.startswith(f"vtk/{kind}/blocks_"))
        assert pvd.count("<DataSet") == len(vtu) >= 2
        path = tmp_path / f"{kind}.vtu"
        path.write_bytes(result.files[vtu[-1]])
        mesh, texts = read_vtu(path)
        assert len(np.concatenate(mesh.cell_data["displacement_m"])) == len(texts["block"]) == 34


def _loaded_crack(towards: str = "-x") -> Model:
    """Hoek and Bray's cracked slope (water to the crack) with a seismic load k_h = 0.1."""
    data = read_yaml(CONFIGS / "scenes" / "planar_crack.yaml")
    data["seismic"] = {"horizontal_coefficient": 0.1, "towards": towards}
    return build_model(api.load_scene(data), Path("planar_crack.yaml"))


def _reduction(model: Model, bracket: tuple[float, float], moved: bool = True) -> StrengthReductionResult:
    """A strength reduction's result as the search returns it, the mechanism a 10 mm shift of every
    block that is not held (drawn, not run: the figure is what is tested)."""
    state = initial_state(model)
    start, blocks = state.world, state.blocks
    held = np.all(model.dof == L.PRESCRIBED, axis=1)
    mechanism = start + np.where(held[model.vertex_block, None], 0.0, 0.01) if moved else None
    shifted = blocks.copy()
    shifted[~held, L.X : L.Y + 1] += 0.01
    lo, hi = bracket
    bracketed = lo > 0.0 and hi < math.inf
    trial = Trial(hi, "unstable", "displacement", 100, 0.01, 1e-3, 0.1)
    return StrengthReductionResult(
        factor_of_safety=0.5 * (lo + hi) if bracketed else (lo if hi == math.inf else hi),
        bracket=bracket,
        bracketed=bracketed,
        start="unreduced",
        equilibrium_steps=100,
        equilibrium_seconds=0.1,
        trials=[trial],
        start_world=start,
        mechanism_world=mechanism,
        start_blocks=blocks,
        stable_blocks=blocks,
        mechanism_blocks=shifted if moved else None,
        failure_displacement_m=0.1,
        laws_losing_cohesion=[],
        model=model,
    )


def _annotations(fig: Figure) -> list[Annotation]:
    return [child for child in fig.axes[0].get_children() if isinstance(child, Annotation)]


@pytest.mark.parametrize("towards", ["-x", "+x"])
def test_scene_and_mechanism_draw_the_phreatic_surface_and_the_seismic_load(towards):
    """Both figures draw the water table as a blue line named in the legend, on the scene's own
    polyline (level beyond its ends), and the seismic load as an arrow pointing its way, labelled k_h."""
    model = _loaded_crack(towards)
    world = initial_state(model).world
    figures = [
        scene_figure(model, world, world, model.dof, 80),
        mechanism_figure(_reduction(model, (1.1, 1.12)), 80),
    ]
    for fig in figures:
        water = [line for line in fig.axes[0].lines if line.get_label().startswith("phreatic surface")]
        assert len(water) == 1 and water[0].get_color() == WATER_COLOUR
        x, y = water[0].get_data()
        surface = model.water_surface
        np.testing.assert_allclose(y, np.interp(x, surface[:, 0], surface[:, 1]))
        assert x[0] <= surface[0, 0] and x[-1] >= surface[-1, 0]  # across the whole figure
        assert "phreatic surface" in [t.get_text()[:16] for t in fig.legends[0].get_texts()]
        arrow, label = _annotations(fig)
        (head_x, _), (tail_x, _) = arrow.xy, arrow.xyann
        assert (head_x < tail_x) == (towards == "-x")
        assert f"k_h = 0.1 (towards {towards})" in label.get_text()
    _assert_inside(dict(zip(["scene", "mechanism"], figures, strict=True)))


def test_a_scene_without_water_or_seismic_load_draws_neither():
    model = build_model(api.load_scene(CONFIGS / "scenes" / "incline.yaml"), Path("incline.yaml"))
    world = initial_state(model).world
    for fig in (
        scene_figure(model, world, world, model.dof, 80),
        mechanism_figure(_reduction(model, (1.1, 1.12)), 80),
    ):
        assert not [line for line in fig.axes[0].lines if "phreatic" in line.get_label()]
        assert not _annotations(fig)


@pytest.mark.parametrize(
    "bracket, moved, title",
    [
        ((1.1, 1.12), True, "FS = 1.11, lowest failing trial F = 1.12"),
        ((20.0, math.inf), False, "FS > 20: no trial failed"),
        ((0.0, 0.05), True, "FS < 0.05: every trial failed, the lowest at F = 0.05"),
    ],
)
def test_the_mechanism_title_gives_the_factor_of_safety(bracket, moved, title):
    model = _loaded_crack()
    result = _reduction(model, bracket, moved)
    assert fos_title(result) == title
    drawn = mechanism_figure(result, 80).axes[0].get_title()
    assert drawn.startswith(f"planar_crack: {title}\n")
    assert drawn.endswith("(scaled)" if moved else "no mechanism")


def test_history_is_drawn_against_time():
    history = pd.DataFrame(
        {"step": [0, 100, 200], "time_s": [0.0, 0.5, 1.5], "wedge_x_mm": [0.0, -1.0, -4.0]}
    )
    fig = history_figure(history, 80)
    assert fig.axes[-1].get_xlabel() == "time [s]"
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_xdata(), history["time_s"])


def test_history_draws_the_unbalanced_force_ratio_on_a_log_axis_with_its_stop_target():
    """The ratio's panel (unit 1) is logarithmic, its zero left out, with the stop target as a labelled
    horizontal line; the other panels stay linear; without a target, no line."""
    history = pd.DataFrame(
        {
            "step": [0, 100, 200],
            "time_s": [0.0, 0.5, 1.0],
            "toe_ux_mm": [0.0, -1.0, -1.5],
            "balance_1": [0.0, 1e-2, 1e-6],
        }
    )
    toe, ratio = history_figure(history, 80, target_ratio=1e-5).axes
    assert toe.get_yscale() == "linear" and ratio.get_yscale() == "log"
    target = [line for line in ratio.lines if line.get_label().startswith("stop target")]
    assert len(target) == 1 and set(target[0].get_ydata()) == {1e-5}
    assert "stop target 1e-05" in [t.get_text() for t in ratio.get_legend().get_texts()]
    drawn = next(line for line in ratio.lines if line.get_label() == "balance").get_ydata()
    assert np.isnan(drawn[0]) and drawn[-1] == 1e-6
    assert [line.get_label() for line in history_figure(history, 80).axes[1].lines] == ["balance"]


def test_scene_draws_each_joint_set_its_bridges_and_cuts_in_the_legend():
    """The benched rock mass: each joint set in its own colour, the bedding's rock bridges dashed and
    the fictitious cuts dotted, each named in the legend; every labelled edge drawn once."""
    model = build_model(
        api.load_scene(CONFIGS / "scenes" / "benched_rock_mass.yaml"), Path("benched_rock_mass.yaml")
    )
    world = initial_state(model).world
    fig = scene_figure(model, world, world, model.dof, 80)
    edges = {c.get_label(): c for c in fig.axes[0].collections if isinstance(c, LineCollection)}
    kinds = {"bedding joints", "cross joints", "bedding bridges", "cut (intact rock)"}
    assert set(edges) == kinds
    assert kinds <= {t.get_text() for t in fig.legends[0].get_texts()}
    colours = {label: tuple(edges[label].get_colors()[0]) for label in kinds}
    assert len(set(colours.values())) == 4
    assert edges["bedding joints"].get_linestyle()[0][1] is None
    assert edges["bedding bridges"].get_linestyle()[0][1] is not None
    assert edges["cut (intact rock)"].get_linestyle()[0][1] is not None
    bridges = sum(name.startswith("bridge") for name in np.array(model.label_names)[model.edge_label])
    assert len(edges["bedding bridges"].get_segments()) < bridges  # each shared one once
    _assert_inside({"scene": fig})


def test_the_colour_scale_of_the_mechanism_is_not_set_by_one_sliver():
    """The top of the colour scale: the largest displacement where no block stands out, the one below
    which 95 % of the area lies where one small block moved far more than the rest."""
    area = np.array([10.0, 10.0, 10.0, 0.1])
    assert colour_top(np.array([1.0, 2.0, 3.0, 3.5]), area) == 3.5
    assert colour_top(np.array([1.0, 2.0, 3.0, 50.0]), area) == 3.0


def test_the_mechanism_arrows_point_as_the_blocks_moved_end_inside_the_axes_and_have_a_scale():
    """A block moved 35 degrees down to the left: its arrow is drawn in data units (xy angles and
    scale on equal axes) so that it points at 35 degrees whatever the figure's shape, it ends inside
    the axes, and a scale arrow is labelled in mm."""
    model = _loaded_crack()
    result = _reduction(model, (1.1, 1.12))
    free = ~np.all(model.dof == L.PRESCRIBED, axis=1)
    angle = math.radians(35.0)
    result.mechanism_blocks[free, L.X] = result.start_blocks[free, L.X] - 0.004 * math.cos(angle)
    result.mechanism_blocks[free, L.Y] = result.start_blocks[free, L.Y] - 0.004 * math.sin(angle)
    ax = mechanism_figure(result, 80).axes[0]
    assert ax.get_aspect() == 1.0
    (arrows,) = [c for c in ax.collections if isinstance(c, Quiver)]
    assert arrows.angles == "xy" and arrows.scale_units == "xy"
    tail, (u, v) = arrows.get_offsets()[0], (arrows.U[0], arrows.V[0])
    assert math.degrees(math.atan2(v, u)) == pytest.approx(-145.0)
    tip = tail + np.array([u, v]) / arrows.scale
    (left, right), (bottom, top) = ax.get_xlim(), ax.get_ylim()
    assert left < tip[0] < right and bottom < tip[1] < top
    (key,) = [c for c in ax.get_children() if isinstance(c, QuiverKey)]
    assert key.text.get_text() == "2 mm" and key.U == 2.0


def test_run_fos_and_sweep_figures_draw_every_text_inside_the_canvas(tmp_path):
    """The run's figures (the incline: four monitors; and one monitor alone, whose time axis' label
    a short figure cut), the factor of safety's, and a study's."""
    scene = api.load_scene(CONFIGS / "scenes" / "planar_crack.yaml")
    model = build_model(scene, Path("planar_crack.yaml"))
    result = api.run(CONFIGS / "scenes" / "incline.yaml")
    incline = build_model(api.load_scene(CONFIGS / "scenes" / "incline.yaml"), Path("incline.yaml"))
    reduction = factor_of_safety(model)
    figures = {
        "scene": scene_figure(
            incline, initial_state(incline).world, result.state.world, result.state.dof, 120
        ),
        "history": history_figure(result.history, 120),
        "history of one monitor": history_figure(result.history[["step", "time_s", "slider_x_mm"]], 120),
        "mechanism": mechanism_figure(reduction, 120),
        "bracketing": bracketing_figure(reduction, 120),
    }
    study = load_config(CONFIGS / "sweeps" / "toppling.yaml", sweep.Config)
    figures |= sweep.run(study, CONFIGS / "sweeps" / "toppling.yaml", tmp_path).figures
    _assert_inside(figures)
