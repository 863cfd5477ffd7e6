"""The controller of §6.3: RLS against ridge regression, float32 against float64, padding."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from sklearn.linear_model import Ridge

from thesis.ch6 import controller as C


def _rls_sequence(X, Y, dtype):
    """Run rls_update over the rows of X, Y; the readout after every step."""
    w, p = C.rls_init(X.shape[1], Y.shape[1], dtype)

    def body(carry, xy):
        w, p = carry
        w, p, e = C.rls_update(w, p, xy[0], xy[1])
        return (w, p), (w, e)

    _, (ws, es) = jax.lax.scan(body, (w, p), (jnp.asarray(X, dtype), jnp.asarray(Y, dtype)))
    return np.asarray(ws), np.asarray(es)


def test_rls_equals_ridge_alpha_one_on_all_samples_so_far(x64):
    """P(0) = I, W(0) = 0 and no forgetting: after n samples RLS is the ridge regression
    (alpha = 1, no intercept) on those n samples (closed form in float64, 1e-10)."""
    rng = np.random.default_rng(1)
    X = rng.standard_normal((60, 9))
    X[:, -1] = 1.0  # the bias input of §6.3.2
    Y = rng.standard_normal((60, 3))
    ws, es = _rls_sequence(X, Y, jnp.float64)
    for n in (1, 2, 5, 9, 10, 30, 60):
        Xn, Yn = X[:n], Y[:n]
        ridge = np.linalg.solve(Xn.T @ Xn + np.eye(9), Xn.T @ Yn).T
        np.testing.assert_allclose(ws[n - 1], ridge, atol=1e-10, rtol=0)
    sk = Ridge(alpha=1.0, fit_intercept=False).fit(X, Y).coef_
    np.testing.assert_allclose(ws[-1], sk, atol=1e-10, rtol=0)
    # the error is a priori: e(n) = y(n) - W(n - 1) x(n)
    np.testing.assert_allclose(es[5], Y[5] - ws[4] @ X[5], atol=1e-12)
    np.testing.assert_allclose(es[0], Y[0], atol=0)


def test_rls_keeps_p_symmetric_in_float32():
    rng = np.random.default_rng(2)
    X = np.tanh(rng.standard_normal((500, 31)))
    w, p = C.rls_init(31, 2, jnp.float32)
    for x in X:
        w, p, _ = C.rls_update(w, p, jnp.asarray(x, jnp.float32), jnp.zeros(2, jnp.float32))
    p = np.asarray(p)
    assert np.array_equal(p, p.T)
    assert np.linalg.eigvalsh(p.astype(np.float64)).min() > 0


def _features(rng, n, n_in):
    """Tanh features of a noisy periodic signal, the kind the controller sees."""
    t = np.arange(n) * 0.0082
    base = np.stack([np.sin(2 * np.pi * 1.7 * t + k) for k in range(n_in)], axis=1)
    return base + 0.05 * rng.standard_normal((n, n_in))


@pytest.mark.parametrize("n_hidden,n_buffer", [(12, 16), (50, 5), (128, 0)])
def test_float32_path_follows_float64(x64, n_hidden, n_buffer):
    """Controller features and RLS of 20 s of signals in float32 against float64: the
    outputs agree to 2e-3 rad (the commands are ~1 rad)."""
    rng = np.random.default_rng(3)
    x = _features(rng, 2440, C.N_INPUTS)
    y = np.stack([np.cos(2 * np.pi * 1.7 * np.arange(2440) * 0.0082 + k) for k in range(12)], 1)
    wh, wb = C.draw_hidden(rng, n_hidden)
    outs = {}
    for dtype in (jnp.float32, jnp.float64):
        outs[dtype] = _controller_outputs(x, y, wh, wb, np.ones(n_hidden),
                                          np.ones(n_buffer + 1), dtype)
    diff = np.abs(outs[jnp.float32] - outs[jnp.float64])
    assert diff[-500:].max() < 2e-3
    assert np.abs(outs[jnp.float64][-500:] - y[-500:]).mean() < 0.2  # it learned something


def _controller_outputs(x, y, wh, wb, hidden_mask, slot_mask, dtype, identity=False):
    """A priori outputs of the controller (hidden layer, buffer, RLS learning all along)
    fed with inputs ``x`` (T, 8) and targets ``y`` (T, 12)."""
    wh, wb = jnp.asarray(wh, dtype), jnp.asarray(wb, dtype)
    hm, sm = jnp.asarray(hidden_mask, dtype), jnp.asarray(slot_mask, dtype)
    n_feat = sm.shape[0] * hm.shape[0] + 1
    w, p = C.rls_init(n_feat, y.shape[1], dtype)
    buf = jnp.zeros((sm.shape[0], hm.shape[0]), dtype)

    def body(carry, xy):
        w, p, buf = carry
        x_nl = C.hidden_layer(xy[0], wh, wb, hm, jnp.asarray(identity))
        buf = C.push_buffer(buf, x_nl)
        f = C.features(buf, sm)
        w2, p2, e = C.rls_update(w, p, f, xy[1])
        return (w2, p2, buf), xy[1] - e

    _, out = jax.lax.scan(body, (w, p, buf), (jnp.asarray(x, dtype), jnp.asarray(y, dtype)))
    return np.asarray(out)


@pytest.mark.parametrize("dtype,atol", [(jnp.float64, 1e-12), (jnp.float32, 1e-4)])
def test_zero_padding_leaves_outputs_unchanged(x64, dtype, atol):
    """Hidden units and buffer slots masked to zero (a sweep padded to its largest H and B)
    give the outputs of the unpadded controller: exactly up to float64 round-off; in
    float32 the longer dot products sum in another order, which RLS carries to ~2e-5 rad
    over 600 steps."""
    rng = np.random.default_rng(4)
    x = _features(rng, 600, C.N_INPUTS)
    y = rng.standard_normal((600, 12))
    wh, wb = C.draw_hidden(rng, 20)
    plain = _controller_outputs(x, y, wh[:7], wb[:7], np.ones(7), np.ones(3), dtype)
    padded = _controller_outputs(x, y, wh, wb, (np.arange(20) < 7).astype(float),
                                 (np.arange(6) < 3).astype(float), dtype)
    np.testing.assert_allclose(padded, plain, atol=atol, rtol=0)
    # the masks matter: unmasked extra units change the outputs
    more = _controller_outputs(x, y, wh, wb, np.ones(20), np.ones(3), dtype)
    assert np.abs(more - plain).max() > 1e-3


def test_linear_feedback_is_the_inputs_themselves(x64):
    """identity=True: x_nl is x (zero-padded to H_max), x_rls = [x; 1] (N = 9)."""
    x = jnp.arange(8, dtype=jnp.float64) / 10
    wh, wb = C.draw_hidden(np.random.default_rng(0), 12)
    mask = (jnp.arange(12) < 8).astype(jnp.float64)
    out = C.hidden_layer(x, jnp.asarray(wh), jnp.asarray(wb), mask, jnp.asarray(True))
    np.testing.assert_array_equal(out[:8], x)
    np.testing.assert_array_equal(out[8:], 0.0)
    f = C.features(C.push_buffer(jnp.zeros((1, 12)), out), jnp.ones(1))
    assert f.shape == (13,) and float(f[-1]) == 1.0
    assert C.n_signals(8, 0) == 9
    tanh = C.hidden_layer(x, jnp.asarray(wh), jnp.asarray(wb), jnp.ones(12), jnp.asarray(False))
    np.testing.assert_allclose(tanh, np.tanh(wh @ np.asarray(x) + wb), atol=1e-12)


def test_buffer_holds_the_last_b_plus_one_vectors():
    buf = jnp.zeros((3, 2))
    for k in range(1, 5):
        buf = C.push_buffer(buf, jnp.full(2, float(k)))
    np.testing.assert_array_equal(np.asarray(buf)[:, 0], [4.0, 3.0, 2.0])  # t, t-1, t-2
    f = C.features(buf, jnp.asarray([1.0, 1.0, 0.0]))
    np.testing.assert_array_equal(np.asarray(f), [4, 4, 3, 3, 0, 0, 1])
    assert C.n_signals(50, 5) == 301 and C.n_signals(50, 12) == 651


def test_hidden_draws_are_nested_over_h():
    """The first H units of a larger draw equal a draw of H units (common random numbers
    across a sweep of H), standard normal."""
    big = C.draw_hidden(np.random.default_rng(7), 256)
    small = C.draw_hidden(np.random.default_rng(7), 12)
    np.testing.assert_array_equal(big[0][:12], small[0])
    np.testing.assert_array_equal(big[1][:12], small[1])
    assert big[0].shape == (256, 8) and big[1].shape == (256,)
    assert abs(big[0].mean()) < 0.1 and abs(big[0].std() - 1) < 0.1
