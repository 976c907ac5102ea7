"""The `bbmc` command line: each command loads one config, runs its stage, writes results atomically.

Every command takes its file as an argument or through --config (the same). Any bad input ends with
one line on stderr naming the file and the key (or line), exit status 2, and nothing written. A value
outside its plausible range (`bbmc.plausibility`) is a one-line warning, or with --strict an error.
Ctrl-C stops any command within a fraction of a second with one line, exit status 130, and nothing
written (a sweep keeps its finished batches).
"""

from __future__ import annotations

import functools
import time
from pathlib import Path
from types import ModuleType

import click

from bbmc import __version__, kernel_cache
from bbmc import warmup as warmup_module
from bbmc.command_outcome import report_written, reported, scene_at_fault
from bbmc.config import ConfigError, load_config
from bbmc.io import provenance, write_stage
from bbmc.progress import Progress
from bbmc.progress_bar import ProgressBar
from bbmc.scene.paths import with_threads
from bbmc.scene.schema3d import scene_dimension
from bbmc.stages import audit as audit_stage
from bbmc.stages import bench as bench_stage
from bbmc.stages import fit as fit_stage
from bbmc.stages import fos as fos_stage
from bbmc.stages import fos3d as fos3d_stage
from bbmc.stages import joint as joint_stage
from bbmc.stages import joints as joints_stage
from bbmc.stages import kinematics as kinematics_stage
from bbmc.stages import mc as mc_stage
from bbmc.stages import run as run_stage
from bbmc.stages import run3d as run3d_stage
from bbmc.stages import shear as shear_stage
from bbmc.stages import slope as slope_stage
from bbmc.stages import sweep as sweep_stage
from bbmc.stages import wedge as wedge_stage


def _config_path(name: str, noun: str, argument: str | None, option: str | None, default: str | None) -> Path:
    """The command's file, given as its argument or with --config (or its default); a `ConfigError`
    if given twice over, or not at all where there is no default."""
    what = f"{noun.upper()}.yaml"
    if argument is not None and option is not None and argument != option:
        raise ConfigError(
            f"the {noun} is given twice ({argument} and --config {option}): give the {noun} once"
        )
    given = argument or option
    if given is None and default is None:
        raise ConfigError(f"give the {noun}: bbmc {name} {what} (or bbmc {name} --config {what})")
    if given is None and not Path(default).is_file():
        raise ConfigError(
            f"{default}: not found from this folder (the default {noun}): give the {noun}: bbmc {name} {what}"
        )
    return Path(given or default)


def _scene_stage(config_path: Path, two: ModuleType, three: ModuleType) -> ModuleType:
    """The stage for the scene's dimension: `three` for a scene with ``dimension: 3``, else `two`."""
    return three if scene_dimension(config_path) == 3 else two


def _run_stage(
    stage: ModuleType,
    config_path: Path,
    results: str,
    strict: bool,
    progress_after_s: float | None = None,
    **options: object,
) -> None:
    """Load the stage's config, run it, write its results. `progress_after_s`: the stage reports its
    steps, shown on stderr once the run has lasted that long (None: a stage without progress).
    `options`: the command's own options, passed to the stage's run and recorded in its provenance.
    A stage with `output_name(settings, config_path)` writes into that folder under its own, and one
    with `summary_lines(result)` prints them."""
    with reported(stage.NAME, strict):
        settings = load_config(config_path, stage.Config)
        with scene_at_fault(config_path):
            if progress_after_s is None:
                result = stage.run(settings)
            else:
                started = time.perf_counter()

                def progress(step: str) -> None:
                    if time.perf_counter() - started >= progress_after_s:
                        click.echo(f"bbmc {stage.NAME}: {step}", err=True)

                result = stage.run(settings, progress, **options)
        record = provenance(stage.NAME, config_path, settings) | options
        out_dir = Path(results) / stage.NAME
        if hasattr(stage, "output_name"):
            out_dir = out_dir / stage.output_name(settings, config_path)
        written = write_stage(out_dir, result, record)
    for line in stage.summary_lines(result) if hasattr(stage, "summary_lines") else ():
        click.echo(f"bbmc {stage.NAME}: {line}")
    report_written(stage.NAME, out_dir, written)


def _file_options(name: str, noun: str, default: str | None = None):
    """The options every command shares: its file (an argument, or --config: the same), --results,
    --strict. The command is called with the file as `config_path`."""

    def decorate(function):
        @functools.wraps(function)
        def command(config_argument: str | None, config_option: str | None, **kwargs) -> None:
            with reported(name):
                config_path = _config_path(name, noun, config_argument, config_option, default)
            function(config_path=config_path, **kwargs)

        shown = f" [default: {default}]" if default else ""
        what = f"{noun.upper()}.yaml"
        options = [
            click.argument("config_argument", metavar=f"[{what}]", required=False),
            click.option(
                "--config", "config_option", metavar=what, help=f"The same as the {what} argument.{shown}"
            ),
            click.option(
                "--results",
                default="results",
                show_default=True,
                type=click.Path(file_okay=False),
                help=f"Folder under which the command writes <results>/{name}/.",
            ),
            click.option(
                "--strict",
                is_flag=True,
                help="Refuse values outside their plausible range (docs/plausible-ranges.md) instead of "
                "warning about them.",
            ),
        ]
        for option in reversed(options):
            command = option(command)
        return command

    return decorate


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="bbmc")
def main() -> None:
    """Barton-Bandis joints in a Mohr-Coulomb slip model, reproduced against the paper.

    \b
    Every command takes its file as an argument or with --config; values outside their plausible
    range for rock are warned about (--strict: refused).

    \b
    Example (the whole pipeline is `make reproduce`):
      bbmc fit configs/fit.yaml
      bbmc mc  configs/mc.yaml
      bbmc shear configs/shear.yaml
      bbmc run configs/scenes/incline.yaml
    """


PAPER_STAGES = (fit_stage, mc_stage, joint_stage, joints_stage, audit_stage)  # their help: COMMAND_HELP


def _register(stage: ModuleType) -> None:
    """Add `bbmc <stage.NAME>`: load its config, run it, write its results (help: its COMMAND_HELP)."""

    @main.command(name=stage.NAME, help=stage.COMMAND_HELP)
    @_file_options(stage.NAME, "config", f"configs/{stage.NAME}.yaml")
    def command(config_path: Path, results: str, strict: bool) -> None:
        _run_stage(stage, config_path, results, strict)


for _stage in PAPER_STAGES:
    _register(_stage)


_THREADS = click.option(
    "--threads",
    type=click.IntRange(min=1),
    default=None,
    help="Threads of the engine [default: the scene's solver.threads, else every core]; "
    "the results are the same for any number.",
)


@main.command(name="run")
@_file_options("run", "scene")
@click.option("--vtk", is_flag=True, help="Also write vtk/: every record for ParaView (VTU + PVD).")
@_THREADS
def run_command(config_path: Path, results: str, strict: bool, vtk: bool, threads: int | None) -> None:
    """Run a block scene (docs/scene-format.md) on the DEM engine.

    \b
    Example:
      bbmc run configs/scenes/incline.yaml          (or: bbmc run --config configs/scenes/incline.yaml)
    writes results/run/<scene name>/history.csv (the monitors), blocks.csv, contacts.csv,
    summary.csv, warnings.csv, scene.png, history.png, provenance.json; with --vtk also vtk/
    (blocks_*.vtu, contacts_*.vtu, blocks.pvd, contacts.pvd: open a .pvd in ParaView).
    A run that goes unstable stops with one line naming the step and the likely cause (exit 3)
    and writes nothing.
    """
    with reported(run_stage.NAME, strict):
        stage = _scene_stage(config_path, run_stage, run3d_stage)
        scene = with_threads(load_config(config_path, stage.Config), threads)
        progress = ProgressBar(scene.solver.steps, f"bbmc run {config_path.name}")
        try:
            with scene_at_fault(config_path):
                result, outcome = stage.run(scene, config_path, progress, vtk)
        finally:
            progress.close()
        for warning in outcome.warnings:
            click.echo(f"bbmc run: warning: {warning}", err=True)
        out_dir = Path(results) / run_stage.NAME / run_stage.output_name(scene, config_path)
        written = write_stage(out_dir, result, provenance(run_stage.NAME, config_path, scene))
    report_written(run_stage.NAME, out_dir, written)


@main.command(name="fos")
@_file_options("fos", "scene")
@_THREADS
def fos_command(config_path: Path, results: str, strict: bool, threads: int | None) -> None:
    """The factor of safety of a block scene by shear-strength reduction (its `fos:` section).

    \b
    Example:
      bbmc fos configs/scenes/planar_crack.yaml
    writes results/fos/<scene name>/fos.csv (every trial: F, verdict, steps, largest displacement,
    wall time), summary.csv (factor_of_safety, trials, time), mechanism.csv (every block's ux_mm,
    uy_mm, rotation_deg and velocity at the end of the last stable and the first unstable trial),
    mechanism.png, bracketing.png, provenance.json; with support, also without it and support.csv;
    with a design: section, design.csv. Each trial is reported on stderr once the search has lasted 2 s.
    """
    with reported(fos_stage.NAME, strict):
        stage = _scene_stage(config_path, fos_stage, fos3d_stage)
        scene = with_threads(load_config(config_path, stage.Config), threads)
        started = time.perf_counter()

        def progress(report: Progress) -> None:
            if time.perf_counter() - started >= 2.0:
                click.echo(f"bbmc fos: {report.text}", err=True)

        with scene_at_fault(config_path):
            result, found = stage.run(scene, config_path, progress)
        out_dir = Path(results) / fos_stage.NAME / run_stage.output_name(scene, config_path)
        written = write_stage(out_dir, result, provenance(fos_stage.NAME, config_path, scene))
    for line in stage.command_lines(scene, result, found, time.perf_counter() - started):
        click.echo(f"bbmc fos: {line}", err=line.startswith("warning: "))
    report_written(fos_stage.NAME, out_dir, written)


@main.command(name="sweep")
@_file_options("sweep", "study")
@click.option(
    "--scheduler",
    default=None,
    help="A dask.distributed scheduler's address (tcp://HOST:PORT) [default: local processes].",
)
@click.option(
    "--workers", type=click.IntRange(min=1), default=None, help="Local processes [default: every core]."
)
def sweep_command(
    config_path: Path, results: str, strict: bool, scheduler: str | None, workers: int | None
) -> None:
    """A probabilistic analysis or parameter study: sample the inputs, run every sample, report P_f
    (a sampled study) or FS against the parameters (a grid).

    \b
    Example:
      bbmc sweep configs/sweeps/planar_block.yaml
      bbmc sweep configs/sweeps/planar_block.yaml --scheduler tcp://127.0.0.1:8786
    writes results/sweep/<name>/samples.csv, summary.csv (FS at the mean inputs, mean and std of FS,
    P_f with its 95 % interval, reliability indices, impossible samples, truncations),
    convergence.csv, convergence.png, sensitivity.csv, fs_distribution.png, tornado.png,
    provenance.json, and for a crossed design (sampling.realizations) geometry_share.csv; a grid
    study writes samples.csv, summary.csv, fs_against_parameter.csv and .png instead. Finished
    batches are kept in results/sweep/<name>.progress/: the same command run again after an
    interruption runs only the missing samples. Progress and the time left on stderr.
    Exit status 4 (nothing written) if no sample gave a result, with the first errors.
    """
    with reported(sweep_stage.NAME, strict):
        settings = load_config(config_path, sweep_stage.Config)
        root = Path(results) / sweep_stage.NAME

        def say(news: Progress) -> None:
            click.echo(f"bbmc sweep: {news.text}", err=True)

        result = sweep_stage.run(settings, config_path, root, scheduler, workers, say)
        out_dir = root / settings.name
        record = provenance(sweep_stage.NAME, config_path, settings) | {"scheduler": scheduler}
        written = write_stage(out_dir, result, record)
    report_written(sweep_stage.NAME, out_dir, written)


@main.command(name="bench")
@_file_options("bench", "config", "configs/bench.yaml")
@click.option(
    "--only",
    default=None,
    metavar="SECTIONS",
    help="Run only these sections of the config, comma-separated (e.g. scaling,engine_cost); "
    "the results folder then holds only theirs. [default: every section the config gives]",
)
def bench_command(config_path: Path, results: str, strict: bool, only: str | None) -> None:
    """Measure what speed costs in accuracy, the work the engine leaves out, its growth, the laws' speed.

    \b
    Example:
      bbmc bench configs/bench.yaml
    writes results/bench/tradeoff.csv (each knob alone on the paper's scenes: wall time, error against a
    converged reference, Pareto front), tradeoff_readings.csv (what was read, per run),
    recommended.csv (each knob's fastest value within the target error), economy.csv (the gain of each
    piece of work the engine leaves out), scaling.csv (time per step and peak memory, 100 to 100,000
    blocks), engine_cost.csv (time per step against an earlier commit), fos_cost.csv (each
    verification factor of safety: error, trials, wall time, and its change with one solver setting),
    mobilized_cost.csv (the full Barton-Bandis law's update cost and update schedules), sweep_cost.csv
    (sweep throughput, speed-up on 2 processes and a LocalCluster, task overhead),
    laws.csv (ufunc vs njit vs Python), rockmass_cost.csv (a rock mass's generation, its bridges'
    cost per step), bandwidth.csv (the memory bandwidth, a STREAM triad on 1 and every thread),
    bandwidth_limit.csv (bytes per sub-contact update, the most updates/s the bandwidth carries),
    support_cost.csv (support's cost where a scene has none; the design search's time),
    kinematics_cost.csv (set finding, tallies, the compass, Monte Carlo draws per second),
    wedge_cost.csv (one wedge, the pairs of 10 sets, wedge samples per second, against issue 35's marks),
    machine.csv (the machine, the run's dates, each section's time), tradeoff.png, scaling.png,
    provenance.json. `python -m bbmc.bench.page results/bench docs/benchmarks.md` writes the
    benchmarks page from them.
    Takes minutes; wall times depend on the machine: compare the ratios. Each section of the
    config (tradeoff, economy, scaling, engine_cost, fos, mobilized, sweep, laws, rockmass,
    bandwidth, support, kinematics, wedge) is optional;
    `bbmc bench --only scaling,engine_cost` runs those alone.
    """
    options = {} if only is None else {"only": [name.strip() for name in only.split(",")]}
    _run_stage(bench_stage, config_path, results, strict, progress_after_s=0.0, **options)


@main.command(name="kinematics")
@_file_options("kinematics", "config", "configs/kinematics.yaml")
def kinematics_command(config_path: Path, results: str, strict: bool) -> None:
    """Joint sets found in orientation readings as recorded (face mapping, scanlines, oriented core;
    no set labels needed), and the kinematic analysis of a slope face: planar and wedge sliding,
    flexural and direct toppling (docs/reference/kinematics-command.md).

    \b
    Example:
      bbmc kinematics configs/kinematics.yaml
    writes results/kinematics/readings.csv (each reading, its weight and its set), sets.csv (mean
    plane, Fisher K, alpha95, counts), set_count.csv (BIC by number of sets), modes.csv (% critical
    per mode, set and set pair, with the denominator), set_pairs.csv, compass.csv and compass.png
    (every face dip direction), face_angles.csv and .png, probability.csv (each mode's probability
    from the sets' scatter), joint_sets.yaml (the sets for a rock mass), poles.png and one stereonet
    per mode (net_*.png), provenance.json
    """
    _run_stage(kinematics_stage, config_path, results, strict, progress_after_s=2.0)


@main.command(name="wedge")
@_file_options("wedge", "wedge", "configs/wedge.yaml")
def wedge_command(config_path: Path, results: str, strict: bool) -> None:
    """A rock wedge's limit equilibrium (Hoek & Bray; Swedge): two joint planes against a slope face,
    water, seismic, forces, bolts and shotcrete; the bolts for a target FS; and the wedge of every pair
    of joint sets (docs/reference/wedge-command.md).

    \b
    Example:
      bbmc wedge configs/wedge.yaml
      bbmc wedge configs/wedge_combinations.yaml
    writes results/wedge/<name>/ (the config's name, else its file's stem): wedge.csv (every number
    of the wedge: vertices, areas, volume, weight, line of intersection, H1, H, the loads, normal
    reactions, each plane's c and phi, driving and resisting forces, mode, FS), design.csv (with a
    design: section: the bolts' direction, force, count and the FS they give), combinations.csv (with
    a combinations: section: every pair's wedge, mode, FS, weight and what drives it, sorted by FS,
    critical ones marked), and of the wedge drawn (the config's, else the lowest-FS pair) wedge.png,
    wedge_net.png, wedge_bolted.png (with a design), vertices.csv, forces.csv, wedge.vtu;
    provenance.json. Prints the FS, the designs and the critical wedges. A deterministic wedge that
    cannot form is refused in one line with the reason.
    """
    _run_stage(wedge_stage, config_path, results, strict, progress_after_s=2.0)


@main.command(name="slope")
@_file_options("slope", "config", "configs/slope.yaml")
def slope_command(config_path: Path, results: str, strict: bool) -> None:
    """The paper's jointed limestone slope (section 5, Figs 7-10): constant M-C against the B-B update.

    \b
    Example:
      bbmc slope configs/slope.yaml
    writes results/slope/claims.csv (each claim of section 5.2, measured in both runs),
    fig7_blocks.csv, fig8_vectors.csv, fig9_joints.csv, fig10_displacements.csv, fig10_fits.csv,
    fs_vs_dip.csv, critical_dip.csv, dip_sensitivity.csv, factor_of_safety.csv (strength reduction
    and planar limit equilibrium, both models), residual_strength.csv (the full B-B joint against the
    peak-only one), fig7.png ... fig10.png, fs_vs_dip.png,
    dip_sensitivity.png, fos_constant.png, fos_barton_bandis.png (mechanisms), animation.gif,
    provenance.json
    """
    _run_stage(slope_stage, config_path, results, strict, progress_after_s=2.0)


@main.command(name="shear")
@_file_options("shear", "config", "configs/shear.yaml")
@click.option(
    "--quick", is_flag=True, help="A first look: the config's `quick` settings, into <results>/shear-quick/."
)
def shear_command(config_path: Path, results: str, strict: bool, quick: bool) -> None:
    """The paper's shear tests (Table 3, Figs 4 and 6) on the block engine, and its calibration of eq 16.

    \b
    Example:
      bbmc shear configs/shear.yaml
    writes results/shear/table3_shear.csv (Table 3 beside ours, cell by cell, with verdicts),
    stress_tests.csv (every load and law against the closed form), velocity_curves.csv,
    velocity_peaks.csv, test_curves.csv, calibration.csv (a, b, R^2 beside eq 16's),
    calibration_tests.csv, fig4.png, fig6.png, calibration.png, scenes/*.yaml (every scene run;
    each runs with bbmc run), provenance.json
    """
    name = "shear-quick" if quick else shear_stage.NAME
    with reported(name, strict):
        settings = load_config(config_path, shear_stage.Config)
        if quick:
            settings = shear_stage.quick_config(settings)
        started = time.perf_counter()

        def progress(step: str) -> None:
            if time.perf_counter() - started > 2.0:
                click.echo(f"bbmc {name}: {step}", err=True)

        with scene_at_fault(config_path):
            result = shear_stage.run(settings, progress)
        out_dir = Path(results) / name
        written = write_stage(out_dir, result, provenance(name, config_path, settings) | {"quick": quick})
    report_written(name, out_dir, written)


@main.command(name="warmup")
def warmup_command() -> None:
    """Compile the block engine's and the joint laws' kernels into numba's cache, so that the first
    `bbmc run` after an install or an update loads them (seconds) instead of compiling them (about
    20 s). `make` runs it once after installing. A second call compiles nothing and takes seconds.

    \b
    Example:
      bbmc warmup
    runs two small built-in scenes and one factor of safety through the engine and calls every law's
    ufunc once; says which part it is at on stderr, then how many kernels it compiled (or loaded from
    the cache) and the seconds it took. Writes nothing but numba's cache (~/.cache/bbmc/numba/).
    """
    if kernel_cache.jit_disabled():
        click.echo("bbmc warmup: NUMBA_DISABLE_JIT is set: nothing to compile")
        return
    with reported("warmup"):
        done = warmup_module.warm(lambda part: click.echo(f"bbmc warmup: {part}...", err=True))
    where = f"the cache {done.folder}"
    if not done.cached:  # the keyed cache could not be made and numba keeps its files elsewhere, or nowhere
        click.echo(
            f"bbmc warmup: ran in {done.seconds:.1f} s, but found no compiled kernel in {done.folder}: "
            "numba keeps them elsewhere or not at all"
        )
    elif done.compiled:
        click.echo(
            f"bbmc warmup: compiled {done.compiled} kernels into {where} in {done.seconds:.1f} s; "
            "the next run loads them from it"
        )
    else:
        click.echo(
            f"bbmc warmup: nothing to compile: every kernel loaded from {where} ({done.cached} in it), "
            f"{done.seconds:.1f} s"
        )
