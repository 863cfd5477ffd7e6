"""The width pilot (``thesis bench chirpz-widths``, thesis.ch2.width_pilot) on a tiny
configuration: its layout, its flags and that it refuses a width it cannot build."""

import copy
import logging

import numpy as np
import pytest

from thesis import registry
from thesis.ch2.train import FAILED_ERROR
from thesis.config import load_config
from thesis.runctx import RunContext


def _ctx(pilot: dict) -> RunContext:
    full = copy.deepcopy(load_config("smoke"))
    c = full["ch2"]
    c["data"].update(canvas=84)
    c["train"].update(batch_size=5)
    c["width_pilot"] = pilot
    return RunContext(key="ch2/width_pilot", profile="smoke", config=c, full_config=full,
                      log=logging.getLogger("test"))


def test_width_pilot_layout_and_flags():
    assert registry.BENCHMARKS["chirpz-widths"] == "ch2/width_pilot"
    widths = [{"loc_filters": 2, "loc_dense": 4, "cls_filters": 2, "cls_dense": 4},
              {"loc_filters": 2, "loc_dense": 4, "cls_filters": 4, "cls_dense": 8}]
    ds = registry.resolve("ch2/width_pilot")(_ctx(
        {"model": "ffn_spn", "transform": "bilinear", "d": 3, "seed": 0, "widths": widths,
         "steps": [2, 5], "n_train": 30, "n_eval": 10}))
    assert ds["error"].dims == ("width", "steps", "split")
    assert list(ds["split"].values) == ["test", "train_pool", "train_seen"]
    assert list(ds["steps"].values) == [2, 5]
    err = ds["error"].values
    assert np.all((err >= 0) & (err <= 1))
    # failed is exactly the train-pool (validation) error at or above FAILED_ERROR
    np.testing.assert_array_equal(ds["failed"].values,
                                  (ds["error"].sel(split="train_pool") >= FAILED_ERROR).values)
    assert ((ds["inside_fraction"] >= 0) & (ds["inside_fraction"] <= 1)).all()
    assert ds["n_params"].values[1] > ds["n_params"].values[0]  # the wider classifier
    assert np.all(ds["cpu_seconds"].values > 0)
    assert np.isfinite(ds["step_cpu_seconds"].values).all()
    assert ds.attrs["model"] == "ffn_spn" and ds.attrs["d"] == 3


def test_width_pilot_names_a_width_it_cannot_build():
    with pytest.raises(ValueError, match=r"widths\[0\] lacks \['cls_dense'\]"):
        registry.resolve("ch2/width_pilot")(_ctx(
            {"model": "ffn_spn", "transform": "bilinear", "d": 3, "seed": 0,
             "widths": [{"loc_filters": 2, "loc_dense": 4, "cls_filters": 2}],
             "steps": [2], "n_train": 10, "n_eval": 5}))
