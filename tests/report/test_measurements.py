"""The measurements page is built from the benchmark files and the results' provenance."""

import numpy as np
import pytest
import xarray as xr

from thesis.report import measurements

HEADER = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"


def _bench(root, profile, ch, name, s, rss, cpu):
    p = root / profile / ch / f"{name}.tsv"
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(HEADER + f"{s}\t0:00:00\t{rss}\t1\t1\t1\t0\t0\t0\t{cpu}\n")


def _result(started, wall, timing):
    return xr.Dataset(
        {"seconds": ("x", np.asarray(timing), {"units": "s", "measurement": "wall_clock",
                                              "long_name": "time per call"}),
         "error": ("x", np.asarray([0.5, 0.25]), {"units": "1"})},
        attrs={"started": started, "wall_seconds": wall})


def test_page_lists_jobs_sums_and_span(tmp_path):
    _bench(tmp_path, "smoke", "ch3", "table3_1", 125.0, 812.4, 240.0)
    _bench(tmp_path, "smoke", "ch7", "ball", 30.0, 600.0, 31.0)
    results = {"ch3/table3_1": _result("2026-01-01T10:00:00+00:00", 100.0, [1.0, 3.0]),
               "ch7/ball": _result("2026-01-01T10:05:00+00:00", 60.0, [2.0, 2.0])}
    md = measurements.measurements_md("smoke", results, tmp_path)
    assert "| ch3 | table3_1 | 2 min 05 s | 4 min 00 s | 812 MB |" in md
    assert "| all | 2 min 35 s |" in md
    # span: 10:00:00 to 10:06:00
    assert "span 6 min 00 s" in md
    # wall-clock variables with their median, other variables not listed
    assert "| ch3/table3_1 | seconds | 2 s |" in md
    assert "| error |" not in md


def test_page_without_benchmarks_says_so(tmp_path):
    md = measurements.measurements_md("default", {}, tmp_path)
    assert "No benchmark files" in md and "span" not in md


def test_malformed_benchmark_is_named(tmp_path):
    p = tmp_path / "smoke" / "ch2" / "data.tsv"
    p.parent.mkdir(parents=True)
    p.write_text("s\n")
    with pytest.raises(ValueError, match="data.tsv"):
        measurements.job_rows("smoke", tmp_path)


@pytest.mark.parametrize("cpu, wall, word", [
    (1000.0, 3000.0, "**kept**"),        # one after another 50 min <= 1 h
    (8000.0, 4000.0, "**exceeded**"),    # 8000 s over 2 cores = 4000 s > 3600 s
    (6000.0, 5000.0, "**kept or not**"),  # 3000 s <= 1 h < 5000 s
])
def test_budget_is_held_against_both_bounds(tmp_path, cpu, wall, word):
    _bench(tmp_path, "default", "ch3", "a", wall / 2, 100.0, cpu / 2)
    _bench(tmp_path, "default", "ch6", "b", wall / 2, 100.0, cpu / 2)
    md = measurements.measurements_md("default", {}, tmp_path, {"hours": 1, "cores": 2})
    assert "## Budget" in md and "within 1 h 00 min 00 s on 2 CPU cores" in md
    assert f"Budget {word}" in md
    assert "| " + measurements._fmt_s(cpu) + " | " + measurements._fmt_s(cpu / 2) in md


def test_no_budget_no_section(tmp_path):
    _bench(tmp_path, "paper", "ch3", "a", 10.0, 100.0, 10.0)
    assert "Budget" not in measurements.measurements_md("paper", {}, tmp_path, None)
    assert "nothing to hold" in measurements.budget_lines([], {"hours": 4, "cores": 2})[-2]
