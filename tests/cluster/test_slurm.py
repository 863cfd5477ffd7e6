"""The pipeline through a real SLURM scheduler (``make test-cluster``; marker ``cluster``).

A throwaway single-node cluster (``tests/cluster/slurm-up.sh``) runs the smoke profile's
chapters 3 and 7 with ``snakemake --profile profiles/slurm``, in a copy of the repository
(so the local smoke results of ``tests/pipeline`` are not touched). Checked:

* a job killed by the scheduler (``scancel`` while it runs) fails the workflow, leaves no
  result file (nor a temporary one) and is run again by the next invocation;
* every job of the run went through ``sbatch``: the scheduler's own record of finished
  jobs (``jobcomp/filetxt``, written by slurmctld) lists each job the executor plugin
  submitted, as completed;
* the results equal the local run's within the smoke regression tolerances
  (``tests/regression/smoke``).

The scheduler's job list of the session is kept in ``logs/cluster/jobs.tsv``.

Needs root (the script installs Debian's slurm-wlm and munge and starts the daemons).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from thesis import regression, resources, store

pytestmark = pytest.mark.cluster

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tests" / "cluster" / "slurm-up.sh"
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
REFERENCES = ROOT / "tests" / "regression" / "smoke"
CHAPTERS = ("ch3", "ch7")
#: The job the scheduler kills: the first of ch3, long enough to be caught running.
KILLED = ("ch3_table3_1_part", "results/smoke/ch3/parts/table3_1_part_seed0.nc")


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """Boot the cluster, yield the environment its clients need, stop it afterwards."""
    if os.geteuid() != 0 and shutil.which("slurmctld") is None:
        pytest.fail("the cluster test needs root (it installs and starts SLURM)")
    sandbox = tmp_path_factory.mktemp("slurm")
    env = dict(os.environ, THESIS_SLURM_DIR=str(sandbox / "cluster"))
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    up = subprocess.run([str(SCRIPT), "start"], env=env, capture_output=True, text=True,
                        timeout=600)
    assert up.returncode == 0, up.stdout + up.stderr
    env["SLURM_CONF"] = str(sandbox / "cluster" / "slurm.conf")
    try:
        yield env
    finally:
        subprocess.run([str(SCRIPT), "stop"], env=env, timeout=120)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """A copy of the repository's tracked files (results of the run land here)."""
    dest = tmp_path_factory.mktemp("repo")
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True,
                           check=True).stdout.decode().split("\0")
    for f in filter(None, files):
        src = ROOT / f
        if src.is_file():
            (dest / f).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / f)
    return dest


def _snakemake(workdir, env, *args, timeout=2400, background=False):
    """snakemake with the repository's SLURM profile; the status checks use ``squeue``
    (this cluster has no accounting database, so ``sacct`` fails) every few seconds."""
    cmd = [SNAKEMAKE, "--profile", "profiles/slurm", "--config", "profile=smoke",
           "--slurm-status-command", "squeue",
           "--slurm-init-seconds-before-status-checks", "5", "--retries", "0",
           "--slurm-keep-successful-logs", *args]  # the per-job logs are the test's record
    if background:
        return subprocess.Popen(cmd, cwd=workdir, env=env, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True)
    return subprocess.run(cmd, cwd=workdir, env=env, capture_output=True, text=True,
                          timeout=timeout)


def _squeue(env) -> list[tuple[str, str]]:
    out = subprocess.run(["squeue", "--states=all", "--noheader", "--format=%i|%T"],
                         env=env, capture_output=True, text=True, check=True).stdout
    return [tuple(line.split("|")) for line in out.split()]


#: Where the scheduler's record of the run is kept once the throwaway cluster is gone.
JOB_LIST = ROOT / "logs" / "cluster" / "jobs.tsv"


def _keep_job_list(env, submitted: dict[str, list[str]]) -> None:
    """Write the scheduler's record of every job of the session (:func:`_jobcomp`) to
    :data:`JOB_LIST`, each job with its rule (from the executor plugin's per-job logs):
    the evidence of what ran through ``sbatch`` after the sandbox is deleted."""
    rule_of = {job: rule for rule, jobs in submitted.items() for job in jobs}
    cols = ("state", "start", "end", "time_limit", "cpus", "mem")
    rows = ["\t".join(("rule", "job", *cols))]
    for job, rec in _jobcomp(env).items():
        rows.append("\t".join([rule_of.get(job, "?"), job, *(rec[c] or "" for c in cols)]))
    JOB_LIST.parent.mkdir(parents=True, exist_ok=True)
    JOB_LIST.write_text("\n".join(rows) + "\n")


def _jobcomp(env) -> dict[str, dict[str, str]]:
    """Job id -> {"state", "start", "end", "time_limit" [min], "cpus", "mem" (e.g.
    "1600M")}, from the scheduler's completion record (one line per finished job, in
    the order they finished)."""
    path = Path(env["THESIS_SLURM_DIR"]) / "jobcomp.log"
    out = {}
    for line in path.read_text().splitlines():
        fields = dict(re.findall(r"(\w+)=(\S*)", line))
        if "JobId" in fields:
            tres = dict(kv.split("=", 1) for kv in fields.get("Tres", "").split(",") if "=" in kv)
            out[fields["JobId"]] = {"state": fields.get("JobState"),
                                    "start": fields.get("StartTime"),
                                    "end": fields.get("EndTime"),
                                    "time_limit": fields.get("TimeLimit"),
                                    "cpus": fields.get("ProcCnt"), "mem": tres.get("mem")}
    return out


def _megabytes(text: str) -> float:
    """SLURM's memory notation ("1600M", "2G") in MB."""
    scale = {"K": 1 / 1024, "M": 1, "G": 1024, "T": 1024 ** 2}
    return float(text[:-1]) * scale[text[-1]] if text[-1] in scale else float(text)


def _submitted(workdir) -> dict[str, list[str]]:
    """Rule -> job ids the executor plugin submitted (its per-job log files)."""
    out: dict[str, list[str]] = {}
    for log in (Path(workdir) / ".snakemake" / "slurm_logs").rglob("*.log"):
        rule = log.relative_to(Path(workdir) / ".snakemake" / "slurm_logs").parts[0]
        out.setdefault(rule.removeprefix("rule_"), []).append(log.stem)
    return out


@pytest.fixture(scope="module")
def killed_run(cluster, workdir):
    """Start the killed job's rule, ``scancel`` its job once it runs; the failed run."""
    proc = _snakemake(workdir, cluster, KILLED[1], background=True)
    deadline = time.monotonic() + 600
    job = None
    while time.monotonic() < deadline and proc.poll() is None:
        running = [j for j, state in _squeue(cluster) if state == "RUNNING"]
        if running:
            job = running[0]
            time.sleep(3)  # let the job's process start its work
            subprocess.run(["scancel", job], env=cluster, check=True)
            break
        time.sleep(1)
    out, _ = proc.communicate(timeout=600)
    return dict(job=job, returncode=proc.returncode, output=out)


@pytest.fixture(scope="module")
def full_run(cluster, workdir, killed_run):
    """The smoke profile's chapters 3 and 7 through the scheduler, after the kill."""
    proc = _snakemake(workdir, cluster, *CHAPTERS)
    assert proc.returncode == 0, proc.stdout[-6000:] + proc.stderr[-6000:]
    return proc


def test_killed_job_leaves_no_result(killed_run, workdir):
    assert killed_run["job"] is not None, "no job of the rule was ever seen running"
    assert killed_run["returncode"] != 0, killed_run["output"][-3000:]
    out = Path(workdir) / KILLED[1]
    assert not out.exists()
    leftovers = list(out.parent.glob(f".{out.name}.*")) if out.parent.exists() else []
    assert leftovers == []


def test_killed_job_is_rerun_and_every_job_went_through_sbatch(full_run, killed_run,
                                                               cluster, workdir):
    assert (Path(workdir) / KILLED[1]).exists()
    record = {j: r["state"] for j, r in _jobcomp(cluster).items()}
    submitted = _submitted(workdir)
    _keep_job_list(cluster, submitted)
    assert record.get(killed_run["job"]) == "CANCELLED", record
    # targets before --quiet, whose choices would otherwise swallow them
    plan = subprocess.run([SNAKEMAKE, *CHAPTERS, "--config", "profile=smoke", "--forceall",
                           "-n", "--quiet", "rules"], cwd=workdir, env=cluster,
                          capture_output=True, text=True, check=True)
    rules = {m.group(1) for m in re.finditer(r"^(\w+)\s+\d+$", plan.stdout, re.M)}
    rules -= {"ch3", "ch7", "total"}  # target rules run no job
    assert rules and rules <= set(submitted), (rules, submitted)
    for rule in rules:
        states = [record.get(j) for j in submitted[rule]]
        assert "COMPLETED" in states, (rule, submitted[rule], record)
    rerun = [record.get(j) for j in submitted[KILLED[0]]]
    assert rerun.count("CANCELLED") == 1 and rerun.count("COMPLETED") == 1, rerun


def test_jobs_requested_the_measured_resources(full_run, cluster, workdir):
    """Each job asked SLURM for what workflow/resources.yaml measured for its rule."""
    table = resources.load(ROOT / resources.RESOURCES_FILE)
    record = _jobcomp(cluster)
    checked = 0
    for rule, jobs in _submitted(workdir).items():
        key = rule.replace("_", "/", 1)  # a rule with a seed wildcard: its parts' largest
        want = (resources.lookup(table, "smoke", key)
                or resources.lookup(table, "smoke", key + "_seed{seed}"))
        assert want is not None, f"rule {rule} has no measured smoke resources"
        for job in jobs:
            got = record[job]
            assert got["time_limit"] == str(want["runtime"]), (rule, got, want)
            assert _megabytes(got["mem"]) == want["mem_mb"], (rule, got, want)
            checked += 1
    assert checked


def test_cluster_results_match_the_local_references(full_run, workdir):
    results = store.load_results("smoke", Path(workdir) / "results")
    keys = sorted(k for k in results if k.split("/")[0] in CHAPTERS)
    assert keys
    problems = []
    for key in keys:
        ref = json.loads(regression.reference_path(REFERENCES, key).read_text())
        problems += [f"{key}: {p}" for p in regression.compare(results[key], ref)]
    assert problems == []
