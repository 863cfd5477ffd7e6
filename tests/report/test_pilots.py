"""The ch2 width pilot's and training-step bench's report tables (thesis.report.pilots),
from tiny synthetic datasets laid out as the experiments write them, and the report's
word on how to make them when they are absent."""

import numpy as np
import xarray as xr

from thesis.report import pilots, status
from thesis.report.chapters import ch2
from thesis.report.model import NOT_RUN


def _width_pilot() -> xr.Dataset:
    widths = ["loc 2/8, cls 2/8", "loc 4/16, cls 4/16"]
    err = np.array([[[0.50, 0.55, 0.45], [0.30, 0.35, 0.25]],
                    [[0.20, 0.21, 0.123], [0.10, 0.11, 0.05]]])
    cpu = np.array([[10.0, 20.0], [30.0, 70.0]])
    return xr.Dataset(
        {"error": (("width", "steps", "split"), err),
         "cpu_seconds": (("width", "steps"), cpu),
         "wall_seconds": (("width", "steps"), 2 * cpu),
         "step_cpu_seconds": (("width",), (cpu[:, 1] - cpu[:, 0]) / 1000),
         "inside_fraction": (("width", "steps"), np.full((2, 2), 0.875)),
         "failed": (("width", "steps"), np.array([[1, 0], [0, 0]], np.int8)),
         "n_params": (("width",), [1234.0, 5678.0])},
        coords={"width": widths, "steps": [1000, 2000],
                "split": ["test", "train_pool", "train_seen"]},
        attrs={"model": "ffn_spn", "transform": "bilinear", "d": 2, "seeds": [0],
               "n_train": 300, "n_eval": 50, "backend": "cpu", "host": "testhost"})


def _train_step() -> xr.Dataset:
    parts = ["step", "forward", "localisation", "transform", "classifier", "update"]
    sec = np.zeros((1, 2, 1, 6))
    sec[0, 0, 0] = [0.0045, 0.002, 0.001, 0.0005, 0.002, 0.0001]  # chirp_z
    sec[0, 1, 0] = [0.003, 0.001, 0.0, 0.0, 0.002, 0.0001]  # none: no localisation
    return xr.Dataset(
        {"seconds": (("model", "transform", "d", "part"), sec),
         "cpu_seconds": (("model", "transform", "d", "part"), 2 * sec),
         "n_params": (("model", "transform", "d"), [[[100.0], [80.0]]]),
         "step_flops": (("model", "transform", "d"), [[[2.5e9], [1.0e9]]])},
        coords={"model": ["rnn_spn"], "transform": ["chirp_z", "none"], "d": [3],
                "part": parts},
        attrs={"batch": 2, "repeats": 2, "backend": "cpu"})


def test_width_pilot_rows_are_read_from_the_dataset():
    t = pilots.width_pilot_table({"ch2/width_pilot": _width_pilot()})
    assert t.id == "width_pilot" and len(t.rows) == 4
    row = {(r[0], r[1]): dict(zip(t.columns, r)) for r in t.rows}
    wide = row[("loc 4/16, cls 4/16", "1000")]
    assert wide["test (%)"] == "20.0" and wide["seen (%)"] == "12.3"
    assert wide["parameters"] == "5678" and wide["CPU [s]"] == "30"
    assert wide["CPU per update [ms]"] == "40"  # (70 - 30) s over 1 000 updates
    assert row[("loc 2/8, cls 2/8", "1000")]["failed"] == "yes"
    assert row[("loc 2/8, cls 2/8", "2000")]["grid on canvas"] == "0.88"
    assert "ffn_spn bilinear d = 2" in t.note and "testhost" in t.note


def test_train_step_rows_mark_the_parts_a_cell_lacks():
    t = pilots.train_step_table({"ch2/train_step": _train_step()})
    rows = {r[0]: dict(zip(t.columns, r)) for r in t.rows}
    assert rows["rnn_spn chirp_z d=3"]["step [ms]"] == "4.5"
    assert rows["rnn_spn chirp_z d=3"]["step [GFLOP]"] == "2.5"
    assert rows["rnn_spn chirp_z d=3"]["step CPU [ms]"] == "9"
    assert rows["rnn_spn none d=3"]["localisation [ms]"] == "—"
    assert rows["rnn_spn none d=3"]["classifier [ms]"] == "2"


def test_absent_datasets_say_how_to_make_them():
    for t in pilots.tables({}):
        assert len(t.rows) == 1 and t.rows[0][1:] == [NOT_RUN] * (len(t.columns) - 1)
        assert t.rows[0][0].startswith(NOT_RUN) and "snakemake ch2_pilot" in t.rows[0][0]
    ids = [t.id for t in ch2.tables({})]
    assert ids == ["table2_2", "width_pilot", "train_step"]


def test_status_names_the_pilot_target_and_whether_it_ran():
    def pilot_row(results):
        return next(r for r in status.optional_runs(results, {}, "smoke")
                    if "width pilot" in r[0])
    what, command, here = pilot_row({})
    assert command == "snakemake ch2_pilot --config profile=smoke --cores 2"
    assert here == "not run"
    assert pilot_row({"ch2/width_pilot": _width_pilot()})[2] == "not run"  # one of two
    both = {"ch2/width_pilot": _width_pilot(), "ch2/train_step": _train_step()}
    assert pilot_row(both)[2] == "on disk"
