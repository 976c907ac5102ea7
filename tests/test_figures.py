"""No text of any figure a stage draws falls outside its canvas (a clipped title, a label run off the
figure): every stage's figures, drawn and measured with matplotlib's own text extents."""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Text

from bbmc import api
from bbmc.config import load_config
from bbmc.dem.figures import bracketing_figure, history_figure, mechanism_figure, scene_figure
from bbmc.dem.model import build_model
from bbmc.dem.solver import initial_state
from bbmc.dem.strength_reduction import factor_of_safety
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
        assert len(np.concatenate(meshio.read(path).cell_data["displacement"])) == 34


def test_run_fos_and_sweep_figures_draw_every_text_inside_the_canvas(tmp_path):
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
        "mechanism": mechanism_figure(model, reduction, 120),
        "bracketing": bracketing_figure(reduction, 120),
    }
    study = load_config(CONFIGS / "sweeps" / "toppling.yaml", sweep.Config)
    figures |= sweep.run(study, CONFIGS / "sweeps" / "toppling.yaml", tmp_path).figures
    _assert_inside(figures)
