"""Tests of the Tab. 2.1 networks and their training loop."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.signal

from thesis.ch2.nets import (NetSpec, apply_net, conv2d, first_max_mask, gru_step, init_net,
                               maxpool2, maxpool2_reference)
from thesis.ch2.train import train
from thesis.ch2.transforms import get_transform

TRAIN_CFG = dict(optimizer="rmsprop", learning_rate=1e-3, batch_size=8, max_epochs=12,
                 patience=12, clip_value=1.0, clip_norm=5.0, lr_decay_factor=1.5,
                 lr_decay_start=30, lr_decay_every=10, dropout=0.0)


def _spec(model, transform, d=2, canvas=84):
    return NetSpec(model, get_transform(transform), canvas, d, 3, loc_filters=3, loc_dense=8,
                   gru_units=8, cls_filters=3, cls_dense=8)


@pytest.mark.parametrize("model", ["ffn_spn", "rnn_spn"])
@pytest.mark.parametrize("transform", ["bilinear", "bilinear_no_skew", "chirp_z", "none"])
def test_shapes_and_identity_initialisation(model, transform):
    spec = _spec(model, transform)
    p = init_net(jax.random.key(0), spec)
    x = jnp.asarray(np.random.default_rng(0).random((2, 84, 84)), jnp.float32)
    logits, theta = apply_net(p, spec, x, return_params=True)
    assert logits.shape == (2, 3, 10)
    assert np.all(np.isfinite(np.asarray(logits)))
    if transform == "none":
        assert theta is None
        return
    ident = np.asarray(spec.transform.identity)
    want = (2, len(ident)) if model == "ffn_spn" else (2, 3, len(ident))
    assert theta.shape == want
    np.testing.assert_allclose(np.asarray(theta), np.broadcast_to(ident, want), atol=1e-7)


def test_rnn_steps_differ_after_localisation_weights_move():
    spec = _spec("rnn_spn", "bilinear_no_skew")
    p = init_net(jax.random.key(1), spec)
    p["loc_out"]["w"] = 0.1 * jax.random.normal(jax.random.key(2), p["loc_out"]["w"].shape)
    x = jnp.asarray(np.random.default_rng(1).random((2, 84, 84)), jnp.float32)
    _, theta = apply_net(p, spec, x, return_params=True)
    assert float(jnp.abs(theta[:, 0] - theta[:, 1]).max()) > 1e-4  # one transform per digit


@pytest.mark.parametrize("transform", ["bilinear", "bilinear_no_skew", "chirp_z"])
def test_rnn_step_shift_offsets_only_the_x_translation_of_each_step(transform):
    import dataclasses

    spec = dataclasses.replace(_spec("rnn_spn", transform), step_shift=0.5)
    p = init_net(jax.random.key(0), spec)
    x = jnp.asarray(np.random.default_rng(0).random((2, 84, 84)), jnp.float32)
    _, theta = apply_net(p, spec, x, return_params=True)
    want = np.broadcast_to(np.asarray(spec.transform.identity), (2, 3, spec.transform.n_params))
    want = want.copy()
    want[:, :, 2] += [-0.5, 0.0, 0.5]  # x translation of the left, middle and right crop
    np.testing.assert_allclose(np.asarray(theta), want, atol=1e-7)
    # the crops differ: step 0 looks left of step 2
    crops = spec.transform(jnp.repeat(x, 3, axis=0), theta.reshape(6, -1), spec.out_size)
    assert float(jnp.abs(crops[0] - crops[2]).max()) > 0.1


def test_conv_and_pool_match_reference():
    rng = np.random.default_rng(0)
    x = rng.random((1, 7, 6, 2)).astype(np.float32)
    w = rng.random((3, 3, 2, 1)).astype(np.float32)
    y = np.asarray(conv2d(jnp.asarray(x), jnp.asarray(w), jnp.zeros(1)))[0, :, :, 0]
    ref = sum(scipy.signal.correlate2d(x[0, :, :, c], w[:, :, c, 0], mode="valid") for c in range(2))
    np.testing.assert_allclose(y, ref, rtol=1e-5)
    pooled = np.asarray(maxpool2(jnp.asarray(x)))
    assert pooled.shape == (1, 3, 3, 2)
    assert pooled[0, 1, 2, 1] == x[0, 2:4, 4:6, 1].max()


@pytest.mark.parametrize("shape", [(3, 8, 8, 2), (2, 9, 7, 3)])  # even, and odd borders
def test_maxpool2_derivatives_equal_the_reference_pool_with_ties(shape):
    """Forward, reverse-mode and forward-mode derivatives of the comparison-based pool equal
    those of the ``reduce_window`` pool bit for bit, on inputs drawn from {0, 1, 2} so that
    most windows hold tied maxima (the gradient must go to the same element as XLA's
    select_and_scatter, not be split)."""
    rng = np.random.default_rng(1)
    x = jnp.asarray(rng.integers(0, 3, shape), jnp.float32)
    ct = jnp.asarray(rng.standard_normal((shape[0], shape[1] // 2, shape[2] // 2, shape[3])),
                     jnp.float32)
    y = maxpool2(x)
    assert np.array_equal(np.asarray(y), np.asarray(maxpool2_reference(x)))
    # the draw holds many ties, including windows whose tied maxima are not the first entry
    mask = np.asarray(first_max_mask(x, y))
    xw = np.asarray(x)[:, : 2 * (shape[1] // 2), : 2 * (shape[2] // 2)].reshape(mask.shape)
    ties = (xw == np.asarray(y)[:, :, None, :, None, :]).sum(axis=(2, 4))
    assert (ties > 1).mean() > 0.3
    assert np.all(mask.sum(axis=(2, 4)) == 1)

    def obj(pool):
        return lambda x: jnp.sum(pool(x) * ct)

    g = jax.jit(jax.grad(obj(maxpool2)))(x)
    g_ref = jax.jit(jax.grad(obj(maxpool2_reference)))(x)
    assert np.array_equal(np.asarray(g), np.asarray(g_ref))
    assert np.count_nonzero(np.asarray(g)) == ct.size  # one element per window, not split
    t = jnp.asarray(rng.standard_normal(shape), jnp.float32)
    _, jt = jax.jvp(maxpool2, (x,), (t,))
    _, jt_ref = jax.jvp(maxpool2_reference, (x,), (t,))
    assert np.array_equal(np.asarray(jt), np.asarray(jt_ref))


def test_maxpool2_gradient_goes_to_the_first_of_tied_maxima():
    x = jnp.asarray([[0.0, 2.0], [2.0, 2.0]])[None, :, :, None]
    g = np.asarray(jax.grad(lambda x: jnp.sum(maxpool2(x)))(x))[0, :, :, 0]
    np.testing.assert_array_equal(g, [[0.0, 1.0], [0.0, 0.0]])


def test_gru_step_matches_equations():
    rng = np.random.default_rng(0)
    h, x = rng.normal(size=(2, 4)), rng.normal(size=(2, 3))
    p = {"wx": rng.normal(size=(3, 12)), "wh": rng.normal(size=(4, 12)), "b": rng.normal(size=12)}
    sig = lambda z: 1 / (1 + np.exp(-z))
    gx, gh = x @ p["wx"] + p["b"], h @ p["wh"]
    r, u = sig(gx[:, :4] + gh[:, :4]), sig(gx[:, 4:8] + gh[:, 4:8])
    c = np.tanh(gx[:, 8:] + r * gh[:, 8:])
    ref = (1 - u) * h + u * c
    out = gru_step({k: jnp.asarray(v, jnp.float32) for k, v in p.items()},
                   jnp.asarray(h, jnp.float32), jnp.asarray(x, jnp.float32))
    np.testing.assert_allclose(np.asarray(out), ref, rtol=1e-4, atol=1e-5)


def _easy_data(n, seed):
    """Three fixed-position bright bars whose row encodes the label (learnable fast)."""
    rng = np.random.default_rng(seed)
    y = rng.integers(0, 10, (n, 3))
    x = np.zeros((n, 84, 84), np.float32)
    for s in range(n):
        for i in range(3):
            x[s, 4 + 7 * y[s, i] : 10 + 7 * y[s, i], 28 * i + 4 : 28 * i + 24] = 1.0
    return x, y.astype(np.int32)


def test_training_reduces_loss_and_error():
    spec = _spec("ffn_spn", "chirp_z", d=2)
    data = {"train": _easy_data(64, 0), "valid": _easy_data(16, 1), "test": _easy_data(16, 2)}
    cfg = dict(TRAIN_CFG, optimizer="adam", learning_rate=3e-3, max_epochs=15, patience=15)
    r = train(spec, data, cfg, jax.random.key(0), np.random.default_rng(0))
    assert r.train_loss[-1] < 0.7 * r.train_loss[0]
    assert r.valid_error.min() < 0.8  # chance is 0.9
    assert 0.0 <= r.test_error <= 1.0
    assert len(r.valid_error) == len(r.learning_rate) == r.valid_error.size


def test_nan_loss_is_reported():
    spec = _spec("ffn_spn", "bilinear", d=3)
    x, y = _easy_data(16, 0)
    x[3, 10, 10] = np.nan
    data = {"train": (x, y), "valid": _easy_data(8, 1), "test": _easy_data(8, 2)}
    seen = []

    def on_nan(step):
        seen.append(step)
        raise RuntimeError("diverged")

    cfg = dict(TRAIN_CFG, max_epochs=1)
    with pytest.raises(RuntimeError, match="diverged"):
        train(spec, data, cfg, jax.random.key(0), np.random.default_rng(0), on_nan=on_nan)
    assert len(seen) == 1
