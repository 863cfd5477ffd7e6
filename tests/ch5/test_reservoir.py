"""Leaky ESN / ELM / EMA against their equations and against reservoirpy on the same weights."""

import numpy as np
import pytest

from thesis.ch5 import reservoir as R


def _loop(u, w_in, w_res, leak, act=np.tanh):
    x = np.zeros(w_in.shape[0])
    out = []
    for un in u:
        pre = w_in @ un + (w_res @ x if w_res is not None else 0.0)
        x = (1 - leak) * x + leak * act(pre)
        out.append(x)
    return np.array(out)


@pytest.fixture
def setup():
    rng = np.random.default_rng(0)
    u = rng.standard_normal((3, 40, 5))
    lengths = np.array([40, 17, 29])
    w_in = R.input_weights(rng, 30, 5) * 0.4
    w_res = R.reservoir_weights(rng, 30) * 0.9
    return u, lengths, w_in, w_res


def test_weights_follow_the_thesis():
    rng = np.random.default_rng(1)
    w = R.input_weights(rng, 200, 10)
    assert set(np.unique(w)) == {-1.0, 0.0, 1.0}
    wr = R.reservoir_weights(rng, 50)
    assert np.max(np.abs(np.linalg.eigvals(wr))) == pytest.approx(1.0, rel=1e-9)


def test_esn_matches_its_equation_per_part(setup):
    u, lengths, w_in, w_res = setup
    x = R.esn_states(u, lengths, w_in, w_res, 0.3)
    for p in range(3):
        ref = _loop(u[p, :lengths[p]], w_in, w_res, 0.3)
        np.testing.assert_allclose(x[p, :lengths[p]], ref, rtol=1e-12, atol=1e-12)
        assert np.all(x[p, lengths[p]:] == 0)


def test_elm_and_ema_match_their_equations(setup):
    u, lengths, w_in, _ = setup
    x = R.elm_states(u, w_in, 0.2)
    np.testing.assert_allclose(x[1], _loop(u[1], w_in, None, 0.2), rtol=1e-10, atol=1e-12)
    e = R.ema(u, 0.1)
    np.testing.assert_allclose(e[2], _loop(u[2], np.eye(5), None, 0.1, act=lambda v: v),
                               rtol=1e-10, atol=1e-12)


def test_esn_matches_reservoirpy_on_the_same_weights(setup):
    import reservoirpy as rpy  # the refs extra (make env-test)
    from reservoirpy.nodes import Reservoir

    u, lengths, w_in, w_res = setup
    node = Reservoir(W=w_res, Win=w_in, bias=np.zeros(w_res.shape[0]), lr=0.3,
                     activation="tanh")
    ref = np.asarray(node.run(u[0]))
    ours = R.esn_states(u[:1], lengths[:1], w_in, w_res, 0.3)[0]
    np.testing.assert_allclose(ours, ref, rtol=1e-9, atol=1e-10)
    assert rpy.__version__.startswith("0.4")


def test_elm_matches_reservoirpy_without_recurrence(setup):
    from reservoirpy.nodes import Reservoir  # the refs extra (make env-test)

    u, _, w_in, w_res = setup
    node = Reservoir(W=np.zeros_like(w_res), Win=w_in, bias=np.zeros(w_res.shape[0]),
                     lr=0.25, activation="tanh")
    np.testing.assert_allclose(R.elm_states(u[2:], w_in, 0.25)[0], np.asarray(node.run(u[2])),
                               rtol=1e-9, atol=1e-10)


def test_exp_based_tanh_matches_numpy_to_float64_accuracy():
    z = np.concatenate([np.linspace(-30, 30, 20001), [0.0, -0.0, 1e-300, -1e-12, 400.0,
                                                      -400.0, 1e6, -1e6]])
    with np.errstate(all="raise"):  # no overflow warning leaks out
        got = R.tanh(z)
    np.testing.assert_allclose(got, np.tanh(z), rtol=0, atol=1e-15)
    assert got[-4] == 1.0 and got[-3] == -1.0 and got[-2] == 1.0 and got[-1] == -1.0
    buf = z.copy()
    assert R.tanh(buf, out=buf) is buf
    np.testing.assert_array_equal(buf, got)
