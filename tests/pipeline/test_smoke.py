"""The smoke profile end to end, its numbers against tests/regression/smoke, and its report
in headless Chromium (renders, every image loads).

One module, so that pytest-xdist's ``--dist loadfile`` keeps every test that reads the
session's smoke pipeline on one worker and the pipeline runs once.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys

import jax
import pytest

from thesis import registry, regression, store
from thesis.config import load_config
from thesis.report.chapters import CHAPTERS

from ..ch2_chance import better_than_chance
from . import layouts_ch2, layouts_ch3, layouts_ch7, layouts_coopt, layouts_model
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
    """Every smoke result against the reference of this host's class (the canonical one
    unless the class has its own for that result: ``thesis.regression``)."""
    results = {k: ds for k, ds in store.load_results("smoke", ROOT / "results").items()
               if k not in registry.MEASUREMENTS}  # `snakemake ch2_pilot`, not regressed
    refs = {f"{p.parent.name}/{p.stem}" for p in REFERENCES.glob("*/*.json")}
    assert sorted(set(results) - refs) == [], "results without a reference: make update-reference"
    assert sorted(refs - set(results)) == [], "references whose result was not produced"
    host = regression.host_class()
    problems = []
    for key, ds in sorted(results.items()):
        path = regression.reference_file(REFERENCES, key, host)
        ref = json.loads(path.read_text())
        problems += [f"{key} ({path.parent.parent.name}): {p}"
                     for p in regression.compare(ds, ref)]
    assert problems == [], f"host class {host}"


def test_smoke_ch2_models_learn(smoke_run):
    """Every smoke Tab. 2.2 cell is better than chance (0.9 per-digit error with 10
    classes) by a one-sided binomial test, independently of the claims and the references."""
    ds = store.load_results("smoke", ROOT / "results")["ch2/table2_2"]
    err = ds["test_error"]
    ok = better_than_chance(err.values, int(ds.attrs["n_test"]))
    assert ok.all(), err.to_series().to_dict()


LAYOUTS = {**layouts_ch2.CHECKS, **layouts_ch3.CHECKS, **layouts_ch7.CHECKS,
           **layouts_coopt.CHECKS, **layouts_model.CHECKS}


@pytest.mark.parametrize("key", sorted(LAYOUTS))
def test_smoke_result_layout(smoke_run, key):
    """The layout of a smoke result (dims, units, relations between variables) that the
    claims and the report read, derived from the smoke configuration: checked on what the
    pipeline wrote instead of on a second, in-process run of each experiment."""
    ds = store.read_dataset(store.result_path("smoke", key, ROOT / "results"))
    with jax.numpy_dtype_promotion("standard"):
        LAYOUTS[key](ds, load_config("smoke"))


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


def test_ch2_pilot_is_a_target_outside_the_default_one():
    """``snakemake ch2_pilot`` plans the width pilot and the training-step bench (through
    ``thesis bench``); the default target (``make all``) plans neither."""
    def plan(*target):
        proc = snakemake(*target, "--forceall", "-n", "-p", "--config", "profile=smoke",
                         timeout=300)
        assert proc.returncode == 0, proc.stderr[-4000:]
        return proc.stdout + proc.stderr
    def jobs(out, rule):  # the plan's job count of a rule ("job stats")
        m = re.search(rf"^{rule}\s+(\d+)$", out, flags=re.M)
        return int(m.group(1)) if m else 0
    pilot = plan("ch2_pilot")
    for rule, nc, bench in (("ch2_width_pilot", "width_pilot", "chirpz-widths"),
                            ("ch2_train_step", "train_step", "chirpz-train")):
        assert jobs(pilot, rule) == 1 and f"results/smoke/ch2/{nc}.nc" in pilot
        assert f"-m thesis bench {bench} --profile smoke" in pilot
    default = plan()
    assert jobs(default, "report") == 1 and jobs(default, "ch2_table2_2") == 1
    assert jobs(default, "ch2_width_pilot") == 0 and jobs(default, "ch2_train_step") == 0
    assert "ch2/width_pilot.nc" not in default and "ch2/train_step.nc" not in default


def test_fixed_teachers_do_not_wait_for_chapter3():
    """ch6 with fixed teachers (the default) plans without chapter 3; a screen of chapter
    3's optima (``ch6.teacher.source = screen``) plans its table3_1 first."""
    def jobs(*config):
        proc = snakemake("ch6", "--forceall", "-n", "--config", "profile=smoke", *config,
                         timeout=300)
        assert proc.returncode == 0, proc.stderr[-4000:]
        return proc.stdout + proc.stderr
    fixed = jobs()
    assert "ch6_teacher" in fixed and "ch3_table3_1" not in fixed
    screen = jobs('ch6={"teacher": {"source": "screen"}}')
    assert "ch3_table3_1" in screen and "--input table3_1=" in screen


def test_nested_config_values_are_typed_and_reach_the_jobs():
    """A nested ``--config`` number is a number (Snakemake hands it over as a string), and
    the job's command carries every override, so it computes with what its params name;
    without overrides the command is unchanged."""
    def plan(*config):
        proc = snakemake("results/smoke/ch3/table3_1.nc", "--forceall", "-n", "-p",
                         "--config", "profile=smoke", *config, timeout=300)
        assert proc.returncode == 0, proc.stderr[-4000:]
        return proc.stdout + proc.stderr
    nested = plan('ch3={"model": {"solver_iterations": 31}}')
    assert """--config-json '{"ch3": {"model": {"solver_iterations": 31}}}' run ch3/""" in nested
    assert "--config-json" not in plan()


def test_perturbed_twin_runs_plan_beside_the_profile():
    """``--config perturb=1e-7`` plans every chapter but ch6 (its runs carry their own
    twins) into results/smoke-perturbed/ with ``thesis --perturb``, and no claims or report
    job (the profile's own claims read the twins); an out-of-range size is refused."""
    proc = snakemake("--config", "profile=smoke", "perturb=1e-7", "-n", timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    out = proc.stdout + proc.stderr
    assert "results/smoke-perturbed/ch3/table3_1.nc" in out
    assert "results/smoke-perturbed/ch7/ball.nc" in out
    assert "data/synthetic/puppy/smoke-perturbed.h5" in out
    assert "data/synthetic/cluttered_mnist/smoke-perturbed.h5" in out
    assert "synthetic/puppy/smoke.h5" not in out and "cluttered_mnist/smoke.h5" not in out
    commands = [line for line in out.splitlines() if " -m thesis " in line]
    assert commands and all("-m thesis --perturb 1e-07 " in line for line in commands)
    assert "results/smoke/" not in out.replace("results/smoke-perturbed/", "")
    assert "ch6_" not in out and "rule claims" not in out and "reports/smoke" not in out
    assert "ch7_table7_1" not in out and "ch2_chirpz_scaling" not in out  # timings
    one = snakemake("ch7", "--config", "profile=smoke", "perturb=1e-7", "-n", timeout=300)
    assert one.returncode == 0 and "ch7_ball" in one.stdout + one.stderr
    assert "ch7_table7_1" not in one.stdout + one.stderr  # a chapter's target too
    bad = snakemake("--config", "profile=smoke", "perturb=0.5", "-n", timeout=300)
    assert bad.returncode != 0
    assert "perturb" in bad.stdout + bad.stderr


def test_native_twin_runs_plan_beside_the_profile():
    """``--config isa=native`` plans every chapter, ch6 included, into results/smoke-native/
    with every CPU pin lifted in each job's environment (thesis.cpupins.native_env), and no
    claims, report or timing job; it cannot be combined with a perturbation, and another
    value is refused with the allowed ones."""
    proc = snakemake("--config", "profile=smoke", "isa=native", "-n", timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    out = proc.stdout + proc.stderr
    assert "results/smoke-native/ch3/table3_1.nc" in out
    assert "results/smoke-native/ch6/teacher.nc" in out
    commands = [line for line in out.splitlines() if " -m thesis " in line]
    assert commands and all('NPY_DISABLE_CPU_FEATURES=""' in line for line in commands)
    assert all("--xla_cpu_max_isa=AMX_FP16" in line for line in commands)
    # the prefix runs under the jobs' `set -euo pipefail` with XLA_FLAGS unset
    prefix = commands[0].split("Shell command: ", 1)[-1].split(f"{sys.executable} -m thesis")[0]
    probe = subprocess.run(
        ["bash", "-c", "set -euo pipefail; " + prefix + f"{sys.executable} -c "
         "'import os; print(os.environ[\"XLA_FLAGS\"])'"],
        env={k: v for k, v in os.environ.items() if k != "XLA_FLAGS"},
        capture_output=True, text=True, timeout=60)
    assert probe.returncode == 0, probe.stderr
    assert probe.stdout.split() == ["--xla_cpu_max_isa=AMX_FP16"]
    assert "results/smoke/" not in out.replace("results/smoke-native/", "")
    assert "data/synthetic/cluttered_mnist/smoke-native.h5" in out
    assert "synthetic/puppy/smoke.h5" not in out and "cluttered_mnist/smoke.h5" not in out
    assert "rule claims" not in out and "reports/smoke" not in out
    assert "ch7_table7_1" not in out and "ch2_chirpz_scaling" not in out
    both = snakemake("--config", "profile=smoke", "isa=native", "perturb=1e-7", "-n",
                     timeout=300)
    assert both.returncode != 0 and "one at a time" in both.stdout + both.stderr
    bad = snakemake("--config", "profile=smoke", "isa=avx9", "-n", timeout=300)
    assert bad.returncode != 0
    assert "'isa'" in bad.stdout + bad.stderr and "native" in bad.stdout + bad.stderr


def test_bad_config_stops_before_any_job():
    proc = snakemake("--config", "profile=smoke", "root_seed=-4", "-n", timeout=300)
    assert proc.returncode != 0
    out = proc.stdout + proc.stderr  # snakemake prints the workflow's error on stdout
    assert "root_seed" in out and "minimum 0" in out
    assert "Job stats" not in out


# ---------------------------------------------------------------- browser ------------
CHECK = """
<script>
window.addEventListener('load', function () {
  var imgs = Array.from(document.images);
  var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  var d = document.createElement('div');
  d.id = 'imgcheck';
  var shown = Array.from(document.querySelectorAll('#status ~ table tr[data-chapter]'))
    .filter(function (r) { return r.getBoundingClientRect().height > 0; })
    .map(function (r) { return r.dataset.chapter; });
  d.textContent = 'IMAGES ' + ok + '/' + imgs.length + ' H2 ' +
                  document.querySelectorAll('h2').length + ' FIRST ' +
                  document.querySelector('h2').id + ' STATUS ' + shown.join(',') + ' END';
  document.body.appendChild(d);
});
</script>
"""

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--virtual-time-budget=5000"]


def _chromium() -> str:
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is not installed (make test installs Debian's chromium)")
        pytest.skip("chromium not installed here; `make chromium` installs it")
    return path


@pytest.mark.browser
def test_report_renders_and_all_images_load(smoke_run, tmp_path):
    chromium = _chromium()
    index = ROOT / "reports" / "smoke" / "index.html"
    page = index.read_text().replace("</body>", CHECK + "</body>")
    probe = tmp_path / "index.html"
    probe.write_text(page)
    profile_dir = tmp_path / "profile"
    dom = subprocess.run([chromium, *FLAGS, f"--user-data-dir={profile_dir}", "--dump-dom",
                          probe.as_uri()], capture_output=True, text=True, timeout=120)
    m = re.search(r"IMAGES (\d+)/(\d+) H2 (\d+)", dom.stdout)
    assert m, f"page did not finish loading:\n{dom.stderr[-2000:]}"
    ok, total, h2 = map(int, m.groups())
    assert ok == total
    assert total == page.count("<img ")
    assert h2 >= 7  # six chapters and the claims
    # the first screen: the generated status, one visible row per report section
    status = re.search(r"FIRST (\S+) STATUS (\S*) END", dom.stdout)
    assert status and status.group(1) == "status", dom.stdout[-500:]
    assert status.group(2).split(",") == [*CHAPTERS, "ch8"]
    shot = tmp_path / "shot.png"
    subprocess.run([chromium, *FLAGS, f"--user-data-dir={profile_dir}",
                    f"--screenshot={shot}", "--window-size=1200,2000", index.as_uri()],
                   capture_output=True, timeout=120)
    assert shot.exists() and shot.stat().st_size > 10_000


OVERFLOW = """
<script>
window.addEventListener('load', function () {
  var root = document.documentElement;
  var wide = Array.from(document.body.querySelectorAll('*')).filter(function (e) {
    return e.getBoundingClientRect().right > root.clientWidth + 1;
  }).slice(0, 5).map(function (e) {
    return e.tagName + (e.id ? '#' + e.id : '') + (e.className ? '.' + e.className : '');
  });
  var d = document.createElement('div');
  d.id = 'overflowcheck';
  d.textContent = 'WIDTH ' + root.scrollWidth + ' ' + root.clientWidth + ' WIDEST ' +
                  wide.join(',') + ' END';
  document.body.appendChild(d);
});
</script>
"""


@pytest.mark.browser
def test_report_has_no_horizontal_overflow_at_1400px(smoke_run, tmp_path):
    """At a 1400-px-wide window the page never scrolls sideways: the claims table wraps
    (fixed layout, numbers in words, raw keys folded away) and wide data tables scroll
    inside their own box (document scrollWidth <= clientWidth)."""
    chromium = _chromium()
    index = ROOT / "reports" / "smoke" / "index.html"
    probe = tmp_path / "index.html"
    probe.write_text(index.read_text().replace("</body>", OVERFLOW + "</body>"))
    dom = subprocess.run([chromium, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}",
                          "--window-size=1400,2000", "--dump-dom", probe.as_uri()],
                         capture_output=True, text=True, timeout=120)
    m = re.search(r"WIDTH (\d+) (\d+) WIDEST (.*?) END", dom.stdout)
    assert m, f"page did not finish loading:\n{dom.stderr[-2000:]}"
    scroll, client = int(m.group(1)), int(m.group(2))
    assert client >= 1300, f"the window is not 1400 px wide ({client})"
    assert scroll <= client, f"horizontal overflow {scroll} > {client}: {m.group(3)}"
