"""SFA against its definition and against sklearn-sfa on a mixture of slow and fast signals."""

import numpy as np
import pytest

from thesis.ch5 import sfa as S


def _mixture(seed=0, n=2000):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 50.0
    slow = np.stack([np.sin(2 * np.pi * 0.05 * t), np.cos(2 * np.pi * 0.11 * t)], 1)
    fast = rng.standard_normal((n, 3))
    src = np.concatenate([slow, fast], 1)
    mix = rng.standard_normal((5, 5))
    return src @ mix.T, slow


def test_sfa_recovers_the_slow_subspace_and_meets_its_constraints():
    x, slow = _mixture()
    f = S.fit_sfa(x[None], np.array([len(x)]), 2)
    y = f.transform(x)
    np.testing.assert_allclose(y.mean(0), 0, atol=1e-9)            # eq. 5.4
    np.testing.assert_allclose(np.cov(y.T, bias=True), np.eye(2), atol=1e-8)  # 5.5, 5.6
    assert f.delta[0] <= f.delta[1]
    # the slow outputs span the slow sources: regression of the sources on y is exact
    coef, res, *_ = np.linalg.lstsq(np.c_[y, np.ones(len(y))], slow, rcond=None)
    assert np.max(np.abs(np.c_[y, np.ones(len(y))] @ coef - slow)) < 1e-4


def test_sfa_matches_sksfa_slow_subspace():
    from sksfa import SFA  # the refs extra (make env-test)

    x, _ = _mixture(1)
    ours = S.fit_sfa(x[None], np.array([len(x)]), 2).transform(x)
    ref = SFA(n_components=2, fill_mode=None).fit(x).transform(x)
    # same subspace: each of ours is a combination of theirs with no residual
    coef, *_ = np.linalg.lstsq(ref, ours - ours.mean(0), rcond=None)
    assert np.max(np.abs(ref @ coef - (ours - ours.mean(0)))) < 1e-6
    # and the slowest output agrees up to sign
    c = np.corrcoef(ours[:, 0], ref[:, 0])[0, 1]
    assert abs(c) == pytest.approx(1.0, abs=1e-6)


def test_differences_stay_inside_parts():
    x = np.zeros((2, 4, 1))
    x[0, :, 0] = [0, 1, 2, 99]
    x[1, :, 0] = [10, 12, 0, 0]
    d = S.part_differences(x, np.array([3, 2]))
    np.testing.assert_array_equal(d[:, 0], [1, 1, 2])


def test_quadratic_expansion_has_products_of_different_signals_only():
    x = np.array([[2.0, 3.0, 5.0]])
    np.testing.assert_array_equal(S.quadratic_expansion(x), [[2, 3, 5, 6, 10, 15]])


def test_fewer_inputs_than_requested_slow_features_keeps_them_all():
    x, _ = _mixture(2)
    f = S.fit_sfa(x[None, :, :3], np.array([len(x)]), 4)
    assert f.w.shape == (3, 3)


def test_quadratic_expansion_follows_triu_order_for_many_inputs():
    x = np.random.default_rng(0).normal(size=(3, 5, 7))
    i, j = np.triu_indices(7, k=1)
    np.testing.assert_array_equal(S.quadratic_expansion(x),
                                  np.concatenate([x, x[..., i] * x[..., j]], axis=-1))
