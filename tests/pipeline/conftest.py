"""Runs the smoke profile end to end once per test session (real snakemake, real jobs)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))


def snakemake(*args: str, timeout: int = 3300) -> subprocess.CompletedProcess:
    """Run snakemake in the repository root with the project's environment.

    The default timeout is for the whole smoke pipeline while the other pytest worker
    keeps both cores busy: it has taken 1464-2400+ s of wall on two-core hosts, so the
    limit only catches a hung pipeline, not a slow host."""
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    return subprocess.run([SNAKEMAKE, *args], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=timeout)


@pytest.fixture(scope="session")
def smoke_run():
    """The smoke pipeline, run for real (every built chapter, claims, figures, report)."""
    proc = snakemake("--config", "profile=smoke", "--cores", "2")
    if proc.returncode != 0:
        logs = sorted((ROOT / "logs" / "smoke").rglob("*.log"))
        tails = "\n".join(f"--- {p}\n{p.read_text()[-3000:]}" for p in logs)
        pytest.fail(f"smoke pipeline failed (rc={proc.returncode}):\n"
                    f"{proc.stderr[-6000:]}\n{tails}")
    return ROOT
