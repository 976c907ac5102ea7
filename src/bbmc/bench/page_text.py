"""The words of docs/benchmarks.md (`bbmc.bench.page`): what each section of `bbmc bench` measures and
how, and which columns of which CSV its tables show. No measured number is written here: the prose
holds only the section's settings (`{repeats}` and the like, filled from the run's config), and the
tables are the run's CSVs.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Table:
    """Rows of one CSV (those where `where`'s column equals its value, `present`'s is given and
    `absent`'s is not), shown under `columns` (those the CSV has); `verbatim` columns (settings, not
    measurements) as the CSV writes them, not rounded."""

    csv: str
    caption: str
    columns: list[str]
    where: tuple[str, object] | None = None
    present: str | None = None
    absent: str | None = None
    verbatim: tuple[str, ...] = ()


@dataclass(frozen=True)
class Section:
    """A section of `configs/bench.yaml` (`name`), its heading, its prose and its tables."""

    name: str
    heading: str
    prose: str
    tables: list[Table] = field(default_factory=list)


# the columns of a table timing this engine per step against an earlier commit (engine_cost, support_cost)
PER_STEP_AGAINST_A_COMMIT = [
    "scene",
    "blocks",
    "seconds_per_step_now",
    "seconds_per_step_then",
    "now_over_then",
    "now_over_then_paired_min",
    "now_over_then_paired_max",
]


INTRO = """
# Benchmarks

What `make bench` (`bbmc bench configs/bench.yaml`) measures, and what it measured in one run. This
page is written from that run's results folder by `python -m bbmc.bench.page results/bench
docs/benchmarks.md`, which `make bench` runs after the stage: every number below is one of the run's
CSVs, so do not edit it by hand. Earlier runs, and the conclusions drawn from them, are kept in
[the benchmarks' history](benchmarks-history.md). What to choose from these numbers is in
[choosing solver settings](how-to/solver-settings.md).

Wall times depend on the machine and on its load (this project's machine is shared: the timing noise of
a run is measured in the tradeoff section); compare the ratios, which are measured side by side in the
same run. The tables show each CSV's own columns, in its units (a column's name ends with them: `_s`
seconds, `_MB` 10⁶ bytes, `_per_s` per second; ratios and relative errors are plain fractions,
0.01 = 1 %), rounded as the page's generator rounds them: whole numbers in full, other numbers to 3
significant figures, below 0.001 as d.dd e-XX; — is a value the run does not have, ∞ an infinite
error (the outcome changed). The CSVs have more columns than shown.

Each section of `configs/bench.yaml` is optional (one left out is skipped, with a line saying so), and
`bbmc bench --only scaling,engine_cost` runs only the sections it names
([the commands](reference/commands.md)).
"""

SECTIONS = [
    Section(
        "tradeoff",
        "Speed against accuracy",
        """
What each solver knob costs and buys on the paper's own scenes, built exactly as `bbmc shear` and
`bbmc slope` build them: **shear**, the ten stress-controlled tests of Table 3 with eq 16's K_s, read
as each test's d_h; **slope_barton_bandis** and **slope_constant**, the section 5 slope, read as the
displacement of blocks 1–4 after 3 s. Each knob is varied alone from the scene's own settings; every
run is compared with a **reference** run of the same scene (the knobs at their accurate end:
{reference}), and the reference with a **check** finer again ({reference_check}), whose difference
is the reference's own error (the rows `reference`). `relative_error` is the largest difference over
what is read, over the largest reference value; a run whose outcome changes (a test slides instead of
holding: `status`) has an infinite error. Wall times are the best of {repeats} runs on one core;
`time_over_default` is the ratio to the scene's default setting in the same run. `tradeoff.png` plots
the error against the time with the Pareto front, `tradeoff_readings.csv` has every value read.
""",
        [
            Table(
                "tradeoff",
                "Each knob's error and time",
                ["scene", "knob", "value", "relative_error", "time_over_default", "seconds", "status"],
                verbatim=("value",),
            ),
            Table(
                "recommended",
                "Each knob's fastest value within the target error, and whether it is faster by more "
                "than the run's timing noise (the same settings timed twice)",
                [
                    "scene",
                    "knob",
                    "target_error",
                    "fastest_within_target",
                    "its_error",
                    "its_time_over_default",
                    "timing_noise",
                    "measurably_faster",
                    "recommended",
                ],
                verbatim=("target_error", "fastest_within_target", "recommended"),
            ),
        ],
    ),
    Section(
        "economy",
        "Work the engine leaves out",
        """
Each economy switched off alone on the same scene, side by side, best of {repeats}: `speedup` is the
time without it over the time with it, and `identical_results` that every reading is bit-identical
with and without it (as `tests/test_bench.py` also checks).
""",
        [
            Table(
                "economy",
                "The gain of each economy",
                [
                    "scene",
                    "what_is_left_out",
                    "seconds_with",
                    "seconds_without",
                    "speedup",
                    "identical_results",
                ],
            )
        ],
    ),
    Section(
        "scaling",
        "Scaling",
        """
The slope of `configs/slope.yaml` cut into more blocks by finer joint spacings (its constant joints),
each size and thread count ({threads}) in a fresh process, {steps} steps from the same state at rest,
best of {repeats}. `growth_exponent_vs_previous` is log(t / t_prev) / log(N / N_prev) of the time
per step (1 is linear); `cost_over_NlogN_relative` is (t / (N ln N)) over the same for the smallest
size; peak memory is the process's high-water mark (`VmHWM`) above a bare process that imported bbmc,
one run's (each repeat's state is released before the next is prepared);
`speedup_vs_first_threads` is the time per step on the first thread count over this row's. A size
whose estimated peak is above {memory_limit_GB} GB is skipped, with the reason. `scaling.png` plots
both thread counts.
""",
        [
            Table(
                "scaling",
                "Time per step, memory and generation against the block count",
                [
                    "blocks",
                    "threads",
                    "sub_contacts",
                    "seconds_per_step",
                    "sub_contact_updates_per_s",
                    "growth_exponent_vs_previous",
                    "cost_over_NlogN_relative",
                    "initial_search_s",
                    "peak_rss_above_baseline_MB",
                    "generation_and_build_s",
                    "speedup_vs_first_threads",
                    "skipped",
                ],
            )
        ],
    ),
    Section(
        "engine_cost",
        "What the engine costs per step",
        """
This engine on one thread against the engine of commit {commit} (the last before corner contacts,
edge-to-edge contacts only), checked out into a temporary git worktree: the scaling slope at each
size and the paper's shear box, {steps} steps, the median of {repeats} alternating fresh processes
(one thread each); `now_over_then_paired_min` and `_max` are the range of the ratios of the runs
paired in order.
""",
        [
            Table(
                "engine_cost",
                "This engine against the earlier one",
                [
                    *PER_STEP_AGAINST_A_COMMIT,
                    "sub_contact_updates_per_s_now",
                    "sub_contact_updates_per_s_then",
                    "skipped",
                ],
            )
        ],
    ),
    Section(
        "fos",
        "What a factor of safety costs",
        """
Every factor of safety the verification report checks, and the paper slope's, by strength reduction at
its own settings (`default`) and with one setting changed at a time (the config's variants):
`error_pct` against the expected value (`expected_from` in the CSV says where it comes from),
`bracket_holds_expected` whether the last stable and first unstable factors bracket it, the trials and
equilibrium steps the search took, and its wall time.
""",
        [
            Table(
                "fos_cost",
                "Each factor of safety and its cost",
                [
                    "case",
                    "variant",
                    "expected",
                    "factor_of_safety",
                    "error_pct",
                    "bracket_holds_expected",
                    "trials",
                    "equilibrium_steps",
                    "wall_time_s",
                ],
            )
        ],
    ),
    Section(
        "mobilized",
        "The full Barton–Bandis joint",
        """
One law update per sub-contact over {sub_contacts} sub-contacts, best of {repeats}, measured side by
side in one process: the full joint (`mobilized`) against the peak-only law of the paper (`peak_only`),
each with its own stiffness laws and with constant stiffnesses (the strength laws alone, like for
like), and a constant joint. Then the shear box's largest τ error against the law, as a fraction of
the peak, for each update interval and, with the 50-step interval, each stress-change trigger.
""",
        [
            Table(
                "mobilized_cost",
                "Cost per law update",
                ["law", "ns_per_sub_contact_update"],
                ("part", "update"),
            ),
            Table(
                "mobilized_cost",
                "Error against the update schedule",
                [
                    "update_interval_steps",
                    "law_update_stress_change",
                    "largest_tau_error_of_peak",
                    "steps",
                    "wall_time_s",
                ],
                ("part", "trade"),
            ),
        ],
    ),
    Section(
        "sweep",
        "Probabilistic studies",
        """
`bbmc sweep`'s throughput: planar limit-equilibrium FS of {le_samples} samples in one vectorised call
(best of {repeats}); DEM FS by strength reduction, one sample per task, for a block on a plane and for
the paper's B-B slope ({dem_samples} samples); the paper slope's study on 1 and 2 local processes and
on a 2-worker dask LocalCluster; and the overhead per task of each scheduler (empty planar tasks).
""",
        [
            Table(
                "sweep_cost",
                "Limit equilibrium",
                ["what", "samples", "seconds", "per_second"],
                ("part", "le_throughput"),
            ),
            Table(
                "sweep_cost",
                "The engine, one core",
                ["what", "samples", "seconds", "per_minute"],
                ("part", "dem_throughput"),
            ),
            Table("sweep_cost", "Speed-up", ["what", "samples", "seconds", "speed_up"], ("part", "speed_up")),
            Table(
                "sweep_cost",
                "Overhead per task",
                ["what", "samples", "seconds_per_task"],
                ("part", "task_overhead"),
            ),
        ],
    ),
    Section(
        "laws",
        "The joint laws' throughput",
        """
Each law evaluated over {array_size} values as a numpy ufunc and inside an njit kernel loop, and over
{python_loop_size} values as its plain Python source in a Python loop (its calls to other laws still
run compiled, so the Python column flatters plain Python for the composite laws); best of {repeats}.
""",
        [
            Table(
                "laws",
                "Evaluations per second",
                [
                    "law",
                    "ufunc_evals_per_s",
                    "njit_kernel_evals_per_s",
                    "python_evals_per_s",
                    "njit_over_python",
                    "ufunc_over_python",
                    "njit_over_ufunc",
                ],
            )
        ],
    ),
    Section(
        "rockmass",
        "Rock masses",
        """
A benched slope cut by three joint sets into a rock mass (its joint spacings times {spacing_scale}; at
their own spacings, about 10,000 blocks): its generation time, best of {repeats}, and the engine's
time per step over {steps} steps with its bridges and cuts as intact rock against the same geometry
with plain joints.
""",
        [Table("rockmass_cost", "Generation and the cost of bridges", ["quantity", "value", "unit"])],
    ),
    Section(
        "bandwidth",
        "Memory bandwidth",
        """
The physical limit per core: a STREAM triad, a = b + s c, over three float64 arrays of {array_MB} MB
each, in one numba kernel on 1 thread and on every thread, the thread counts taking turns, best of
{repeats}. Bytes are counted as STREAM counts them, 3 × 8 per element (the write-allocate read of a is
not counted, so the bus carries up to 4/3 of the figure). Then the bytes one sub-contact update moves
on the scaling slope of about {blocks} blocks (`bbmc.bench.bandwidth.bytes_per_update`: its
sub-contact row read and written back, its share of its contact's row, of the block rows and of the
vertices, each array streamed once per step; `_gathers_missing` adds a contact's reads of its two
blocks and four vertices, all missing the cache), and the most updates per second that bandwidth
carries at each.
""",
        [
            Table("bandwidth", "The triad", ["threads", "array_MB", "GB_per_s", "repeats"]),
            Table(
                "bandwidth_limit",
                "The most sub-contact updates per second the bandwidth carries",
                [
                    "threads",
                    "GB_per_s",
                    "blocks",
                    "sub_contacts_per_block",
                    "bytes_per_update",
                    "bytes_per_update_gathers_missing",
                    "updates_per_s_limit",
                    "updates_per_s_limit_gathers_missing",
                ],
            ),
        ],
    ),
    Section(
        "support",
        "Support",
        """
What support elements cost where a scene has none: this engine against commit {commit} (the last before
them) on the scaling slope and the shear box, {steps} steps, alternating fresh processes, {repeats}
each, one thread. Then the design search of `{design_scene}` (limit-equilibrium trials, then the engine's
strength reduction that confirms the design), best of {repeats}.
""",
        [
            Table(
                "support_cost",
                "This engine against the one before support",
                [
                    *PER_STEP_AGAINST_A_COMMIT,
                    "skipped",
                ],
                absent="design_value",
            ),
            Table(
                "support_cost",
                "The design search",
                [
                    "scene",
                    "design_value",
                    "limit_equilibrium_trials",
                    "engine_trials",
                    "engine_fs",
                    "wall_time_s",
                ],
                present="design_value",
            ),
        ],
    ),
    Section(
        "kinematics",
        "Orientation analysis",
        """
Sets found in a synthetic survey of {readings} readings (four sets and 10 % random readings; BIC over 0
to 6 sets) and the kinematic tally of one face (every pole; the line modes on the documented subsample
of pairs above 5,000 readings), the compass sweep at 1° for {compass_readings} readings (every pair),
and the modes' Monte Carlo over {samples} draws per set (four sets and their six pairs), each on one
core, best of {repeats}. The `mark` column gives issue 34's targets.
""",
        [
            Table(
                "kinematics_cost",
                "Set finding, tallies, the compass and the Monte Carlo",
                ["quantity", "value", "unit", "mark"],
            )
        ],
    ),
    Section(
        "wedge",
        "Wedge analysis",
        """
One deterministic wedge (Hoek & Bray's classic wedge of `{wedge_config}`, `cases.analyse_case`, the time
per call over {calls} calls), the combination analysis of ten joint sets against its slope (45 pairs,
`combinations.combination_table`, the time of one table), and {samples} probabilistic samples of the
study `{study_config}`: `samples_per_second` through its sweep base (each sample's planes drawn by
Fisher's K, the wedge analysed by the compiled fast path, its outcome row), `analysis_samples_per_second`
the analysis alone (`probability.wedge_probability`) on planes drawn up front. Each the median of
{repeats} fresh processes on one thread (NUMBA_NUM_THREADS=1). The `mark` column gives issue 35's
targets and `met` whether the median meets them.
""",
        [
            Table(
                "wedge_cost",
                "One wedge, ten sets' pairs and the probabilistic samples",
                ["quantity", "value", "unit", "mark", "met"],
            )
        ],
    ),
    Section(
        "engine3d",
        "The 3D block engine",
        """
Sub-contact updates per second per core (one thread) of the 3D engine on a stack of boxes
(`bbmc.bench.engine3d_scene`) beside the 2D engine's on a slope of about as many blocks, the 3D rate on
2 threads with its speed-up and whether the two runs ended with the same bits, the wall time of a 3D
wedge's factor of safety, and the modules of the 3D engine a 2D run loads. Each the median of fresh
processes, 3D and 2D taking turns. The `mark` column gives issue 36's targets and `met` whether the
median meets them.
""",
        [Table("engine3d", "The 3D engine beside the 2D one", ["quantity", "value", "unit", "mark", "met"])],
    ),
]
