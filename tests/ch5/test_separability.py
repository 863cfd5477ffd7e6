"""Leave-one-trial-out separability: the per-fold readouts from per-trial sums
equal the readouts fitted on the other trials' data, and the measurement tells separable
from inseparable terrains."""

import numpy as np
import pytest

from thesis.ch5 import readout
from thesis.ch5 import separability as SP
from thesis.ch5 import sfa
from thesis.ch5 import tuning as T


def _trials(rng, labels, shift, n=120, d=5):
    """Per trial (n, d) signals: white noise plus ``shift`` times a terrain-specific mean
    and a terrain-specific slow oscillation."""
    t = np.arange(n)[:, None]
    out = []
    for r in labels:
        mean = np.eye(d)[r % d] * shift
        slow = shift * np.sin(2 * np.pi * (r + 1) * t / n) * np.eye(d)[(r + 1) % d]
        out.append(rng.normal(size=(n, d)) + mean + slow)
    return out


def test_loto_linear_equals_fitting_on_the_other_trials():
    rng = np.random.default_rng(0)
    labels = np.array([0, 1, 2, 0, 1, 2, 0, 3])
    feats = _trials(rng, labels, 0.7)
    pred = SP.loto_linear(feats, labels, 5)
    for j in range(len(feats)):
        others = [k for k in range(len(feats)) if k != j]
        w = readout.fit_linear(np.concatenate([feats[k] for k in others]),
                               np.concatenate([np.full(len(feats[k]), labels[k])
                                               for k in others]), 5)
        np.testing.assert_array_equal(pred[j], readout.predict_linear(w, feats[j]))


def test_sfa_from_moments_equals_fit_sfa():
    rng = np.random.default_rng(1)
    x = np.cumsum(rng.normal(size=(3, 200, 4)), axis=1) + rng.normal(size=(3, 200, 4))
    lengths = np.array([200, 150, 90])
    ref = sfa.fit_sfa(x, lengths, 3)
    flat = np.concatenate([x[i, :n] for i, n in enumerate(lengths)])
    d = sfa.part_differences(x, lengths)
    mean = flat.mean(0)
    got = sfa.sfa_from_moments(mean, flat.T @ flat / len(flat) - np.outer(mean, mean),
                               d.T @ d / len(d), 3)
    np.testing.assert_allclose(got.delta, ref.delta, rtol=1e-8)
    np.testing.assert_allclose(np.abs(got.transform(flat)), np.abs(ref.transform(flat)),
                               atol=1e-8)


@pytest.mark.parametrize("supervised", [True, False])
def test_separable_terrains_score_high_and_inseparable_ones_do_not(supervised):
    rng = np.random.default_rng(2)
    labels = np.repeat([0, 1, 2], 4)

    def score(shift):
        feats = _trials(rng, labels, shift)
        if supervised:
            pred = SP.loto_linear(feats, labels, 5)
        else:
            pred = SP.loto_unsupervised(feats, [np.array([60, 60])] * len(feats), labels, 5,
                                        n_slow=2, n_bins=10, ica_seed=0, ica_max_iter=200)
        return 100 * np.mean(np.concatenate([p == r for p, r in zip(pred, labels)]))

    assert score(6.0) > 90.0
    assert score(0.0) < 50.0  # three balanced terrains: chance 33 %


def test_cells_and_start_params():
    class Recs:
        gait = np.array([0, 0, 0, 0, 1, 1, 2])
        frequency = np.array([1.0, 1.0, 0.5, 0.5, 1.0, 1.0, 1.0])
        terrain = np.array([0, 1, 0, 0, 2, 1, 0])

    found = SP.cells(Recs, 2)
    assert [(g, f, list(ids)) for g, f, ids in found] == [("bound_right", 1.0, [0, 1]),
                                                            ("turn_left", 1.0, [4, 5])]
    assert SP.cells(Recs, 3) == []
    ranges = {"pca_rate": (0.1, 1.0), "leak": (0.001, 1.0), "input_scaling": (0.01, 1.0),
              "spectral_radius": (0.0, 1.5)}
    p = SP.start_params("rc", ranges)
    assert p == T.decode([0.5] * 4, ("pca_rate", "leak", "input_scaling", "spectral_radius"),
                         ranges)
    assert p["leak"] == pytest.approx(10 ** -1.5) and p["spectral_radius"] == 0.75
