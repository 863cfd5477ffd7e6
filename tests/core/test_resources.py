"""thesis.resources: cluster requests measured from Snakemake benchmark files."""

from __future__ import annotations

import re

import pytest
import yaml

from thesis import config
from thesis import resources as R

HEADER = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"


def _bench(path, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER + "".join(
        f"{s}\t0:00:00\t{rss}\t0\t0\t0\t0\t0\t0\t{cpu}\n" for s, rss, cpu in rows))


def test_worst_case_over_repeated_runs(tmp_path):
    _bench(tmp_path / "b.tsv", [(10.0, 500.0, 9.0), (30.0, 400.0, 50.0)])
    m = R.read_benchmark(tmp_path / "b.tsv")
    assert m == {"s": 30.0, "max_rss": 500.0, "cpu_time": 50.0, "runs": 2.0}


def test_requirement_margins():
    got = R.requirement({"s": 600.0, "max_rss": 1000.0, "cpu_time": 1200.0, "runs": 1})
    assert got["mem_mb"] == 2000  # 1.5 x 1000 + 500
    assert got["runtime"] == 30  # 3 x 10 min
    assert got["measured"]["cores_used"] == 2.0
    short = R.requirement({"s": 2.0, "max_rss": 100.0, "cpu_time": 1.0, "runs": 1})
    assert short["runtime"] == R.RUNTIME_FLOOR_MIN and short["mem_mb"] == 700


def test_empty_or_broken_benchmark_names_the_file(tmp_path):
    (tmp_path / "e.tsv").write_text(HEADER)
    with pytest.raises(ValueError, match="e.tsv"):
        R.read_benchmark(tmp_path / "e.tsv")
    (tmp_path / "x.tsv").write_text("s\tmax_rss\n1\tfoo\n")
    with pytest.raises(ValueError, match="x.tsv"):
        R.read_benchmark(tmp_path / "x.tsv")


def test_update_writes_profile_section_and_keeps_unmeasured_names(tmp_path):
    bench = tmp_path / "benchmarks"
    _bench(bench / "smoke" / "ch3" / "table3_1.tsv", [(60.0, 700.0, 60.0)])
    out = tmp_path / "resources.yaml"
    changes = R.update("smoke", bench, out)
    assert changes == ["smoke ch3/table3_1: new -> 1600 MB, 5 min"]
    (bench / "smoke" / "ch3" / "table3_1.tsv").unlink()
    _bench(bench / "smoke" / "ch7" / "ball.tsv", [(400.0, 1000.0, 400.0)])
    R.update("smoke", bench, out)
    table = yaml.safe_load(out.read_text())
    assert set(table["smoke"]) == {"ch3/table3_1", "ch7/ball"}
    assert table["smoke"]["ch7/ball"]["runtime"] == 20
    with pytest.raises(ValueError, match="no benchmark files"):
        R.update("paper", bench, out)


def test_update_replacing_a_rerun_chapter_drops_its_unmeasured_names(tmp_path):
    bench = tmp_path / "benchmarks"
    for seed in range(5):
        _bench(bench / "default" / "ch2" / f"table2_2_ffn_spn_seed{seed}.tsv",
               [(60.0, 700.0, 60.0)])
    _bench(bench / "default" / "ch3" / "table3_1.tsv", [(60.0, 700.0, 60.0)])
    out = tmp_path / "resources.yaml"
    R.update("default", bench, out)
    for seed in (3, 4):
        (bench / "default" / "ch2" / f"table2_2_ffn_spn_seed{seed}.tsv").unlink()
    (bench / "default" / "ch3" / "table3_1.tsv").unlink()
    changes = R.update("default", bench, out, replace=("ch2",))
    assert changes == [f"default ch2/table2_2_ffn_spn_seed{s}: dropped (no benchmark in a "
                       "rerun chapter)" for s in (3, 4)]
    table = yaml.safe_load(out.read_text())
    assert set(table["default"]) == {f"ch2/table2_2_ffn_spn_seed{s}" for s in range(3)} | {
        "ch3/table3_1"}  # ch3 was not rerun: its entry stays


def test_lookup_exact_pattern_and_missing():
    table = {"default": {"ch2/table2_2_ffn_spn_seed0": {"mem_mb": 3000, "runtime": 40},
                         "ch2/table2_2_ffn_spn_seed1": {"mem_mb": 3500, "runtime": 30},
                         "ch2/table2_2_rnn_spn_seed0": {"mem_mb": 9000, "runtime": 90},
                         "ch3/table3_1": {"mem_mb": 1600, "runtime": 10}}}
    assert R.lookup(table, "default", "ch3/table3_1") == {"mem_mb": 1600, "runtime": 10}
    assert R.lookup(table, "default", "ch2/table2_2_ffn_spn_seed{seed}") == {
        "mem_mb": 3500, "runtime": 40}
    assert R.lookup(table, "default", "ch3/fig3_4") is None
    assert R.lookup(table, "paper", "ch3/table3_1") is None


def test_committed_file_covers_the_smoke_profile():
    """The smoke profile (what CI and the cluster test run) is measured for every chapter and
    the report; every section's entries carry both requests. A profile without a section
    (default until it has been run with this code, paper) requests the rules' estimates."""
    table = R.load()
    assert "smoke" in table
    chapters = {name.split("/")[0] for name in table["smoke"]}
    assert {"ch2", "ch3", "ch4", "ch5", "ch6", "ch7", "report"} <= chapters, chapters
    for profile, entries in table.items():
        for name, entry in entries.items():
            assert entry["mem_mb"] >= R.MEM_EXTRA_MB and entry["runtime"] >= 1, (profile, name)


def _rule_blocks():
    """(file, text) of every rule declared in workflow/rules/*.smk."""
    for path in sorted((config.repo_root() / "workflow" / "rules").glob("*.smk")):
        parts = re.split(r"^\s*rule\b", path.read_text(), flags=re.M)
        yield from ((path.name, block) for block in parts[1:])


def test_every_job_is_benchmarked_under_the_name_it_requests_resources_for():
    """A rule that runs a job writes a benchmark file and asks the cluster for what that
    same file measured: the two names must agree, or the rule requests another job's
    resources (a loop variable left over from an earlier loop did exactly that)."""
    jobs = 0
    for name, block in _rule_blocks():
        if "shell:" not in block:
            continue
        jobs += 1
        bench = re.search(r"bench_path\(\s*([^)]*?)\s*\)", block)
        req = re.search(r"\bres\(\s*(\"[^\"]+\"\s*,\s*[^,]+?)\s*,\s*mem_mb", block)
        assert bench and req, (name, block[:120])
        assert re.sub(r"\s", "", bench.group(1)) == re.sub(r"\s", "", req.group(1)), (
            name, bench.group(1), req.group(1))
    assert jobs >= 20
