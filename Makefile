# One command to set up and reproduce, one to set up and test.
# The install step ends with `bbmc warmup`: pip has no post-install hook, and without it the first run
# would compile the engine's kernels (about 20 s) where a user waits for an answer.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
DOCS_STAMP := $(VENV)/.docs-installed


.PHONY: reproduce test test-slow fuzz bench lint docs fit mc audit shear slope fos joint joints kinematics wedge sweep clean

$(STAMP): pyproject.toml
	test -d $(VENV) || $(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	$(BIN)/bbmc warmup
	touch $(STAMP)

reproduce: fit mc audit shear slope fos joint joints kinematics wedge sweep

fit: $(STAMP)
	$(BIN)/bbmc fit --config configs/fit.yaml

mc: $(STAMP)
	$(BIN)/bbmc mc --config configs/mc.yaml

audit: $(STAMP)
	$(BIN)/bbmc audit --config configs/audit.yaml

shear: $(STAMP)
	$(BIN)/bbmc shear --config configs/shear.yaml

slope: $(STAMP)
	$(BIN)/bbmc slope --config configs/slope.yaml

fos: $(STAMP)
	$(BIN)/bbmc fos --config configs/scenes/planar_crack.yaml
	$(BIN)/bbmc fos configs/scenes/bolted_planar.yaml
	$(BIN)/bbmc run configs/scenes/benched_rock_mass.yaml
	$(BIN)/bbmc fos configs/scenes/benched_rock_mass.yaml
	$(BIN)/bbmc fos configs/scenes/wedge_bench_3d.yaml

joint: $(STAMP)
	$(BIN)/bbmc joint --config configs/joint.yaml

joints: $(STAMP)
	$(BIN)/bbmc joints --config configs/joints.yaml

kinematics: $(STAMP)
	$(BIN)/bbmc kinematics configs/kinematics.yaml

wedge: $(STAMP) kinematics
	$(BIN)/bbmc wedge configs/wedge.yaml
	$(BIN)/bbmc wedge configs/wedge_combinations.yaml
	$(BIN)/bbmc wedge configs/wedge_pit.yaml
	$(BIN)/bbmc wedge configs/wedge_bench_le.yaml

sweep: $(STAMP)
	$(BIN)/bbmc sweep --config configs/sweeps/planar_block.yaml
	$(BIN)/bbmc sweep --config configs/sweeps/paper_slope_le.yaml
	$(BIN)/bbmc sweep --config configs/sweeps/paper_slope_dem.yaml
	$(BIN)/bbmc sweep configs/sweeps/benched_rock_mass.yaml
	$(BIN)/bbmc sweep configs/sweeps/benched_rock_mass_crossed.yaml
	$(BIN)/bbmc sweep configs/sweeps/pit_wall_kinematics.yaml
	$(BIN)/bbmc sweep configs/sweeps/classic_wedge.yaml
	$(BIN)/bbmc sweep configs/sweeps/pit_wedge.yaml

test: $(STAMP)
	$(BIN)/pytest -q

test-slow: $(STAMP)
	$(BIN)/pytest -q -m slow

# The fuzz test (tests/test_fuzz.py) at length: FUZZ_EXAMPLES mutated inputs over every seed, drawn afresh.
FUZZ_EXAMPLES ?= 1000
fuzz: $(STAMP)
	BBMC_FUZZ_EXAMPLES=$(FUZZ_EXAMPLES) $(BIN)/pytest -q tests/test_fuzz.py --hypothesis-show-statistics

# docs/benchmarks.md is written from the run's folder (bbmc.bench.page); the page it replaces goes to
# docs/benchmarks-history.md.
bench: $(STAMP)
	$(BIN)/bbmc bench --config configs/bench.yaml
	$(BIN)/python -m bbmc.bench.page results/bench docs/benchmarks.md

# The user guide: installs the docs extra (MkDocs Material, mkdocstrings) into the venv and builds
# docs/ into site/; strict, so a broken link, a page missing from the nav or a bad docstring fails it.
$(DOCS_STAMP): $(STAMP)
	$(BIN)/pip install --quiet -e '.[test,docs]'
	touch $(DOCS_STAMP)

docs: $(DOCS_STAMP)
	$(BIN)/mkdocs build --strict --clean --site-dir site

lint: $(STAMP)
	$(BIN)/ruff check src tests
	$(BIN)/ruff format --check src tests
	$(BIN)/lint-imports

clean:
	rm -rf results/fit results/mc results/audit results/shear results/shear-quick results/slope results/bench site
