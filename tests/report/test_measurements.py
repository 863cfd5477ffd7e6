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
