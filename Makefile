# Entry points. `make all` runs the main job (default profile, ends in
# reports/default/index.html); `make test` runs the tests. Both install what they need.
SHELL := /bin/bash
PROFILE ?= default
# uv on PATH, else the one pip installs into this python (`python3 -m uv`, no PATH needed).
UV := $(shell command -v uv 2>/dev/null || echo python3 -m uv)
# One environment for every command: the extras any documented command needs (bench: the
# MuJoCo/MJX peers of Tab. 7.1; slurm: the SLURM executor plugin; refs: the independent
# ESN/SFA implementations the ch5 tests compare with). `uv sync` removes what
# it is not asked for, so a command that synced fewer extras would uninstall another's
# (tests/core/test_makefile.py checks that every sync and run names the same ones).
EXTRAS := --extra bench --extra slurm --extra refs
# pytest on both cores; the smoke pipeline's tests share one module, hence one worker
# (tests/conftest.py)
XDIST := -n 2 --dist loadfile --no-loadscope-reorder --durations=30
SNAKEMAKE := $(UV) run --locked $(EXTRAS) snakemake
export JAX_COMPILATION_CACHE_DIR ?= $(CURDIR)/.cache/jax

.PHONY: all smoke paper test test-fast test-cluster env uv chromium update-reference report lint clean-smoke

all: env
	$(SNAKEMAKE) --config profile=$(PROFILE)
	@echo "report: reports/$(PROFILE)/index.html"

smoke:
	$(MAKE) all PROFILE=smoke

paper:
	$(MAKE) all PROFILE=paper

# The whole test suite, including the smoke pipeline end to end, its regression against
# tests/regression/smoke and the headless-browser check of its report.
test: env chromium
	$(UV) run --locked $(EXTRAS) pytest $(XDIST)

# Everything but the smoke pipeline (quick feedback while developing).
test-fast: env
	$(UV) run --locked $(EXTRAS) pytest $(XDIST) -m "not pipeline and not browser and not cluster"

# Decide the claims of $(PROFILE)'s results (and twin runs, where made) and render its
# report: after a run of single targets or twin runs, which `make all` does not end with.
report: env
	$(UV) run --locked $(EXTRAS) python -m thesis check --profile $(PROFILE)
	$(UV) run --locked $(EXTRAS) python -m thesis report --profile $(PROFILE)

# Rewrite the smoke references on purpose (thesis.regression; prints what changed): the
# smoke run and its perturbed and native twin runs, whose differences decide which
# variables are chaotic and how closely each is compared.
update-reference: env
	$(SNAKEMAKE) --config profile=smoke
	$(SNAKEMAKE) --config profile=smoke perturb=1e-7
	$(SNAKEMAKE) --config profile=smoke isa=native
	$(UV) run --locked $(EXTRAS) python -m thesis.regression update smoke tests/regression/smoke

lint: env
	$(SNAKEMAKE) --lint --config profile=smoke
	for p in smoke default paper gpu; do $(SNAKEMAKE) -n -q --config profile=$$p || exit 1; done

uv:
	@command -v uv >/dev/null 2>&1 || python3 -m uv --version >/dev/null 2>&1 || python3 -m pip install --quiet uv

# Bytecode is compiled at install, the packages' and ours: where the environment forbids
# writing .pyc at import (PYTHONDONTWRITEBYTECODE), every pipeline job and test subprocess
# would otherwise compile jax, pandas and xarray from source again (seconds of CPU each).
env: uv
	$(UV) sync --locked $(EXTRAS) --compile-bytecode
	$(UV) run --locked $(EXTRAS) python -m compileall -q src

# The pipeline through a throwaway single-node SLURM cluster (tests/cluster; needs root:
# installs Debian's slurm-wlm and munge, starts and stops its own daemons).
test-cluster: env
	$(UV) run --locked $(EXTRAS) pytest -m cluster tests/cluster

# Debian's chromium for the browser test (needs root; skipped when already present).
chromium:
	@command -v chromium >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq chromium >/dev/null; \
	  else echo "install Debian's chromium for the browser test (sudo apt-get install chromium)"; fi; }

clean-smoke:
	rm -rf results/smoke reports/smoke logs/smoke benchmarks/smoke data/synthetic/*/smoke.*
