"""The documented commands share one environment: none uninstalls what another needs.

`uv sync` removes every package it is not asked for, so `make all` syncing without the
extras that `make test` installed would uninstall them (the Tab. 7.1 peers then fail until
reinstalled). Every `uv sync` / `uv run` the Makefile's targets print must name the same
extras, and every `uv sync` the README shows must name them too.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TARGETS = ("all", "smoke", "test", "test-fast", "test-cluster", "update-reference", "lint",
           "report")


def _uv_lines(target: str) -> list[str]:
    out = subprocess.run(["make", "-n", "-B", target, "UV=uv"], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout
    return [line for line in out.splitlines() if re.search(r"\buv (sync|run)\b", line)]


def _extras(line: str) -> frozenset[str]:
    return frozenset(re.findall(r"--extra[= ](\S+)", line))


def test_every_uv_call_names_the_same_extras():
    seen = {}
    for target in TARGETS:
        lines = _uv_lines(target)
        assert lines, f"make {target} runs no uv command"
        for line in lines:
            seen[(target, line)] = _extras(line)
    sets = set(seen.values())
    assert len(sets) == 1, {k: sorted(v) for k, v in seen.items()}
    assert {"bench", "slurm"} <= next(iter(sets))


def test_readme_syncs_keep_the_makefiles_extras():
    """A `uv sync` the README tells a user to run (e.g. for CUDA JAX) names every extra the
    Makefile's commands use, so it does not uninstall them."""
    makefile = _extras(_uv_lines("all")[0])
    syncs = re.findall(r"uv sync(?:\s+--[\w-]+(?:[= ](?!-)[\w-]+)?)+",
                       (ROOT / "README.md").read_text())
    assert syncs, "the README shows no uv sync"
    for line in syncs:
        assert makefile <= _extras(line.replace("\n", " ")), (line, sorted(makefile))
