# Lookups shared by every chapter's rules: paths, config slices, code versions.
# Logic lives in the `thesis` package; this file only names things.
import json
import shlex
import sys

from thesis.config import typed_overrides, validate_config
from snakemake.utils import update_config
from thesis.cli import config_slice
from thesis.provenance import code_version
from thesis import resources as _resources
from thesis.cpupins import native_env
from thesis.store import results_name

# `--config` values: a nested one reaches Snakemake as strings (YAML's base loader), so its
# scalars are parsed first (thesis.config.typed_overrides); every override but the run
# switches (profile, perturb, isa) is passed on to each job (`thesis --config-json`), so
# a job computes with the values its params (and so its reruns) name.
_SWITCHES = ("profile", "perturb", "isa")
OVERRIDES = {k: v for k, v in typed_overrides(workflow.config_settings.overwrite_config).items()
             if k not in _SWITCHES}
update_config(config, OVERRIDES)
# A clear error naming the key and the allowed values, before any job runs.
config.update(validate_config(config))

PROFILE = config["profile"]
# `--config perturb=1e-7`: the chapters' perturbed twin runs (thesis.physics.perturbation),
# into results/<profile>-perturbed/ (and its own data, logs and benchmarks); `thesis check`
# decides every claim on them too and marks a verdict they move as fragile.
PERTURB = float(config.get("perturb", 0.0))
# `--config isa=native`: the chapters' native twin runs, every CPU pin lifted
# (thesis.cpupins.native_env: the host's own numpy, OpenBLAS and XLA code paths), into
# results/<profile>-native/; `thesis check` marks a verdict they move as ISA-dependent.
NATIVE = config.get("isa", "pinned") == "native"
if PERTURB and NATIVE:
    raise WorkflowError("perturb and isa=native make two different twin runs: one at a time")
TWIN = bool(PERTURB or NATIVE)
RUNS = results_name(PROFILE, perturbed=bool(PERTURB), native=NATIVE)
# The CLI of this environment (the interpreter running snakemake), independent of PATH;
# a native twin's jobs get native_env's variables (XLA's cap added to the user's flags).
_NATIVE_ENV = native_env() if NATIVE else {}
THESIS = (
    "".join(f"{k}=\"{'${XLA_FLAGS:-} ' if k == 'XLA_FLAGS' else ''}{v}\" "
            for k, v in _NATIVE_ENV.items())
    + f"{sys.executable} -m thesis"
    + (f" --perturb {PERTURB!r}" if PERTURB else "")
    + (f" --config-json {shlex.quote(json.dumps(OVERRIDES, sort_keys=True))}" if OVERRIDES else "")
)
# "coopt" is §8.2 made real (thesis.coopt): a report section like a chapter's.
CHAPTERS = ["ch2", "ch3", "ch4", "ch5", "ch6", "ch7", "coopt"]

# Filled by each chapter's .smk: result files of its target, figures and tables it reports.
CHAPTER_TARGETS = {ch: [] for ch in CHAPTERS}
FIGURES = {ch: [] for ch in CHAPTERS}
TABLES = {ch: [] for ch in CHAPTERS}

# Code each chapter runs; its hash goes into params so code changes trigger reruns.
CORE_CODE = ["__init__.py", "store.py", "cli.py", "config.py", "runctx.py", "seeding.py",
             "jaxsetup.py", "cpupins.py"]
CHAPTER_CODE = {
    "ch2": ["ch2"],
    "ch3": ["ch3", "gaits", "optim", "physics"],
    "ch4": ["ch4", "gaits", "optim", "physics"],
    "ch5": ["ch5", "physics"],
    "ch6": ["ch6", "gaits", "physics"],
    "ch7": ["ch7", "physics", "optim"],
    "coopt": ["coopt", "ch7", "physics"],
}


def result(ch, name):
    """results/<profile>/<chapter>/<artifact>.nc (results/<profile>-perturbed/... for the
    perturbed twin runs)"""
    return f"results/{RUNS}/{ch}/{name}.nc"


def data_path(name):
    """data/synthetic/<name>/<profile>.h5 (a generated input, git-ignored), named after the
    run like its results (<profile>-perturbed, <profile>-native): a twin run makes its own
    copy and never rewrites, and so reruns, the profile's."""
    return f"data/synthetic/{name}/{RUNS}.h5"


def log_path(ch, name):
    return f"logs/{RUNS}/{ch}/{name}.log"


def bench_path(ch, name):
    return f"benchmarks/{RUNS}/{ch}/{name}.tsv"


# What each job needs, measured from benchmarks/<profile>/ (thesis.resources).
RESOURCES = _resources.load()


def res(ch, name, mem_mb, runtime, gpu=False):
    """Cluster resources of the job benchmarked as bench_path(ch, name): the values measured
    for this profile in workflow/resources.yaml (a name with wildcards, "x_seed{seed}",
    takes the largest over its measured instances), else the rule's declared upper
    estimate ``mem_mb`` [MB] and ``runtime`` [min] (a profile never measured here, e.g.
    paper). ``gpu``: the job runs on a GPU in the paper and gpu profiles (one GPU requested through
    the SLURM plugin's ``gpu`` resource)."""
    got = _resources.lookup(RESOURCES, PROFILE, f"{ch}/{name}") or dict(
        mem_mb=mem_mb, runtime=runtime
    )
    if gpu and PROFILE in ("paper", "gpu"):
        got = dict(got, gpu=1)
    return got


def figure_path(ch, name):
    return f"reports/{PROFILE}/figures/{ch}/{name}.png"


def cfg_slice(key):
    """Canonical JSON of the config an experiment ("ch7/ball") or a chapter ("ch3") reads
    (thesis.registry.reads), as params: the rule reruns when that part changes."""
    return json.dumps(config_slice(config, key), sort_keys=True)


def code_of(ch):
    """Hash of the thesis subpackages a chapter runs (params: reruns on code change)."""
    return code_version(*CORE_CODE, *CHAPTER_CODE[ch])
