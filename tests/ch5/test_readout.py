"""Least-squares and naive-Bayes readouts on synthetic cases with known answers."""

import numpy as np

from thesis.ch5 import readout as R


def test_linear_readout_separates_separable_classes():
    rng = np.random.default_rng(0)
    labels = rng.integers(0, 3, 600)
    centres = np.array([[3, 0], [0, 3], [-3, -3]])
    x = centres[labels] + 0.3 * rng.standard_normal((600, 2))
    w = R.fit_linear(x, labels, 3)
    assert w.shape == (3, 3)
    assert np.mean(R.predict_linear(w, x) == labels) == 1.0


def test_linear_readout_is_least_squares_on_pm1_targets():
    rng = np.random.default_rng(1)
    x = rng.standard_normal((50, 4))
    labels = rng.integers(0, 2, 50)
    w = R.fit_linear(x, labels, 2)
    y = -np.ones((50, 2))
    y[np.arange(50), labels] = 1
    xb = np.c_[x, np.ones(50)]
    np.testing.assert_allclose(w, np.linalg.solve(xb.T @ xb, xb.T @ y), rtol=1e-9, atol=1e-12)


def test_bayes_readout_recovers_the_known_posterior_argmax():
    # two terrains, one cell: N(-1, 0.5) vs N(+1, 0.5); the Bayes decision is y > 0
    rng = np.random.default_rng(2)
    labels = np.repeat([0, 1], 5000)
    y = np.where(labels == 0, -1.0, 1.0) + 0.5 * rng.standard_normal(10000)
    model = R.fit_bayes(y[:, None], labels, 2, n_bins=20)
    test = np.linspace(-2, 2, 41)
    pred = R.predict_bayes(model, test[:, None])
    far = np.abs(test) > 0.25
    np.testing.assert_array_equal(pred[far], (test[far] > 0).astype(int))


def test_bayes_prior_decides_when_the_cells_say_nothing():
    labels = np.array([0] * 30 + [1] * 70)
    y = np.zeros((100, 1))
    model = R.fit_bayes(y, labels, 2)
    assert np.all(R.predict_bayes(model, np.zeros((5, 1))) == 1)
    np.testing.assert_allclose(np.exp(model.log_prior), [0.3, 0.7])


def test_bayes_combines_independent_cells():
    # each cell alone is ambiguous for one class pair; together they decide
    rng = np.random.default_rng(3)
    labels = rng.integers(0, 4, 8000)
    a = np.array([0, 0, 1, 1])[labels] + 0.1 * rng.standard_normal(8000)
    b = np.array([0, 1, 0, 1])[labels] + 0.1 * rng.standard_normal(8000)
    y = np.c_[a, b]
    model = R.fit_bayes(y, labels, 4)
    assert np.mean(R.predict_bayes(model, y) == labels) > 0.99
