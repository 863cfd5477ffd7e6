"""The smoke profile end to end, and its numbers against tests/regression/smoke."""

from __future__ import annotations

import json

import pytest

from thesis import regression, store
from thesis.config import load_config

from .conftest import ROOT, snakemake

pytestmark = pytest.mark.pipeline

REFERENCES = ROOT / "tests" / "regression" / "smoke"


def test_smoke_pipeline_writes_report_and_claims(smoke_run):
    index = ROOT / "reports" / "smoke" / "index.html"
    assert index.exists() and "Provenance" in index.read_text()
    assert (ROOT / "reports" / "smoke" / "summary.md").exists()
    claims = json.loads((ROOT / "results" / "smoke" / "claims.json").read_text())
    assert claims["profile"] == "smoke"
    statuses = {c["status"] for c in claims["claims"]}
    assert statuses <= {"reproduced", "not_reproduced", "inconclusive", "not_run"}
    assert len(claims["claims"]) >= 20


def test_smoke_results_carry_provenance(smoke_run):
    results = store.load_results("smoke", ROOT / "results")
    for key, ds in results.items():
        prov = store.provenance_of(ds)
        assert prov["profile"] == "smoke", key
        assert prov["experiment"] == key, key
        assert prov["thesis_ref"], key
        assert prov["wall_seconds"] >= 0, key


def test_smoke_numbers_match_references(smoke_run):
    results = store.load_results("smoke", ROOT / "results")
    refs = {f"{p.parent.name}/{p.stem}" for p in REFERENCES.glob("*/*.json")}
    assert sorted(set(results) - refs) == [], "results without a reference: make update-reference"
    assert sorted(refs - set(results)) == [], "references whose result was not produced"
    problems = []
    for key, ds in sorted(results.items()):
        ref = json.loads(regression.reference_path(REFERENCES, key).read_text())
        problems += [f"{key}: {p}" for p in regression.compare(ds, ref)]
    assert problems == []


def test_smoke_ch2_models_learn(smoke_run):
    """Every smoke Tab. 2.2 cell is clearly better than chance (0.9 per-digit error with 10
    classes), independently of the claims and of the references."""
    ds = store.load_results("smoke", ROOT / "results")["ch2/table2_2"]
    err = ds["test_error"]
    assert bool((err < 0.8).all()), err.to_series().to_dict()


def test_rerun_is_a_no_op(smoke_run):
    proc = snakemake("--config", "profile=smoke", "--cores", "2", "-n", "-q")
    assert proc.returncode == 0, proc.stderr
    assert "Nothing to be done" in proc.stdout + proc.stderr


def test_snakemake_report_builds(smoke_run):
    out = ROOT / "reports" / "smoke" / "snakemake-report.zip"
    if out.exists():
        out.unlink()
    proc = snakemake("--config", "profile=smoke", "--report", str(out), timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert out.stat().st_size > 1000


@pytest.mark.parametrize("profile", ["default", "paper"])
def test_other_profiles_plan_without_running(profile):
    load_config(profile)
    proc = snakemake("--config", f"profile={profile}", "-n", "-q", timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]


def test_bad_config_stops_before_any_job():
    proc = snakemake("--config", "profile=smoke", "root_seed=-4", "-n", timeout=300)
    assert proc.returncode != 0
    out = proc.stdout + proc.stderr  # snakemake prints the workflow's error on stdout
    assert "root_seed" in out and "minimum 0" in out
    assert "Job stats" not in out
