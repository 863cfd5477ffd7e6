"""Readouts of chapter 5: least squares on +-1 targets (§5.2.1, §5.3.2) and the naive-Bayes
readout of the ICA "terrain cells" (eq. 5.8-5.9).

Supervised: one output per terrain, trained to +1 on its terrain and -1 elsewhere by
ordinary least squares with a bias column (``W_out = (X^T X)^-1 X^T y``, eq. 5.1, taken as
the minimum-norm least-squares solution so that a rank-deficient X -- e.g. a constant
PCA component -- does not fail); each time step is classified by the largest output.

Unsupervised: the labels are used only to calibrate this readout. Per ICA output i and
terrain r, a histogram of the training outputs estimates P(y_i | r) (eq. 5.9: the
outputs are treated as independent); bins: ``n_bins`` equal-width bins between the 1st
and 99th percentile of the training outputs (values beyond go to the edge bins), with
add-one (Laplace) smoothing so that an empty bin does not veto a terrain. The prior
P(r) is the terrains' share of the training time steps ("related to our dataset").
Each time step is classified by the largest posterior (eq. 5.8; P(y) is not needed).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["fit_linear", "predict_linear", "BayesReadout", "fit_bayes", "predict_bayes"]


def _with_bias(x: np.ndarray) -> np.ndarray:
    return np.concatenate([np.asarray(x, np.float64), np.ones((len(x), 1))], axis=1)


def fit_linear(features: np.ndarray, labels: np.ndarray, n_classes: int) -> np.ndarray:
    """Least-squares readout (eq. 5.1) on +-1 targets.

    Args:
        features: (n, F) time steps x features; labels: (n,) class indices.
    Returns:
        (F + 1, n_classes) weights, the last row the bias.
    """
    y = -np.ones((len(labels), int(n_classes)))
    y[np.arange(len(labels)), np.asarray(labels, int)] = 1.0
    w, *_ = np.linalg.lstsq(_with_bias(features), y, rcond=None)
    return w


def predict_linear(w: np.ndarray, features: np.ndarray) -> np.ndarray:
    """(n,) class of each time step: the output node with the largest value (§5.3.2)."""
    return np.argmax(_with_bias(features) @ w, axis=1)


@dataclass(frozen=True)
class BayesReadout:
    """Histogram naive-Bayes readout.

    Attributes:
        edges: (k, n_bins + 1) bin edges per terrain cell.
        log_lik: (k, n_bins, C) log P(bin | terrain) per cell.
        log_prior: (C,) log P(terrain).
    """

    edges: np.ndarray
    log_lik: np.ndarray
    log_prior: np.ndarray


def _bins(edges: np.ndarray, y: np.ndarray) -> np.ndarray:
    """(n, k) bin index of every value, values beyond the edges in the edge bins."""
    n_bins = edges.shape[1] - 1
    idx = np.empty(y.shape, int)
    for i in range(y.shape[1]):
        idx[:, i] = np.clip(np.searchsorted(edges[i], y[:, i], side="right") - 1, 0,
                            n_bins - 1)
    return idx


def fit_bayes(y: np.ndarray, labels: np.ndarray, n_classes: int, n_bins: int = 20,
              percentiles: tuple[float, float] = (1.0, 99.0)) -> BayesReadout:
    """Calibrate the readout of eq. 5.8-5.9 on training outputs.

    Args:
        y: (n, k) terrain-cell (ICA) outputs; labels: (n,) terrain indices.
        n_bins: histogram bins per cell; percentiles: range of the bins.
    """
    y = np.asarray(y, np.float64)
    labels = np.asarray(labels, int)
    k = y.shape[1]
    lo, hi = np.percentile(y, percentiles, axis=0)
    hi = np.where(hi > lo, hi, lo + 1e-12)
    edges = np.stack([np.linspace(lo[i], hi[i], n_bins + 1) for i in range(k)])
    idx = _bins(edges, y)
    counts = np.ones((k, n_bins, int(n_classes)))  # add-one smoothing
    for i in range(k):
        np.add.at(counts[i], (idx[:, i], labels), 1.0)
    log_lik = np.log(counts / counts.sum(axis=1, keepdims=True))
    prior = np.bincount(labels, minlength=int(n_classes)).astype(np.float64)
    log_prior = np.log(np.maximum(prior, 1e-300) / prior.sum())
    return BayesReadout(edges=edges, log_lik=log_lik, log_prior=log_prior)


def predict_bayes(model: BayesReadout, y: np.ndarray) -> np.ndarray:
    """(n,) terrain of each time step with the largest posterior (eq. 5.8)."""
    idx = _bins(model.edges, np.asarray(y, np.float64))
    score = np.broadcast_to(model.log_prior, (len(idx), model.log_prior.size)).copy()
    for i in range(idx.shape[1]):
        score += model.log_lik[i][idx[:, i]]
    return np.argmax(score, axis=1)
