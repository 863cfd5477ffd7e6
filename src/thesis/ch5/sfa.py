"""Slow feature analysis (thesis §5.2.4.1, eq. 5.3-5.6) and SFA2's quadratic expansion.

Linear SFA (Wiskott & Sejnowski's algorithm, the thesis's ref. [20]): centre the
training signals, whiten them (principal directions with a variance below
``rel_eps`` times the largest are dropped, so the reservoir's near-collinear states do
not blow up), then take the directions of smallest variance of the whitened signals'
time derivative. The outputs have zero mean (5.4), unit variance (5.5), are decorrelated
(5.6) and the first minimises <y'^2> (5.3). The derivative is the difference of
consecutive time steps *within* a part: parts are separate recordings, so a jump between
two parts is not a change in time.

SFA2 (§5.2.4): "the product of each combination of 2 different input signals alongside
the original signals" -- K inputs give K + K (K - 1) / 2 signals, no squares.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SFA", "fit_sfa", "sfa_from_moments", "quadratic_expansion", "part_differences"]


@dataclass(frozen=True)
class SFA:
    """A fitted linear SFA: ``y = (x - mean) @ w``.

    Attributes:
        mean: (D,) training mean; w: (D, n) projection; delta: (n,) <y'^2> per output on
        the training data (ascending: the first output is the slowest).
    """

    mean: np.ndarray
    w: np.ndarray
    delta: np.ndarray

    def transform(self, x: np.ndarray) -> np.ndarray:
        """(..., n) slow features of ``x`` (..., D)."""
        return (np.asarray(x, np.float64) - self.mean) @ self.w


def part_differences(x: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """(sum(lengths - 1), D) differences of consecutive valid steps within each part.

    Args:
        x: (P, T, D) padded parts; lengths: (P,).
    """
    x = np.asarray(x, np.float64)
    d = np.diff(x, axis=1)
    t = np.arange(x.shape[1] - 1)
    keep = t[None, :] < (np.asarray(lengths)[:, None] - 1)
    return d[keep]


def fit_sfa(x: np.ndarray, lengths: np.ndarray, n_components: int,
            rel_eps: float = 1e-9) -> SFA:
    """Fit linear SFA on padded parts.

    Args:
        x: (P, T, D) signals; lengths: (P,) valid steps; n_components: outputs kept.
        rel_eps: relative variance below which a whitened direction is dropped.
    With fewer usable input directions than ``n_components`` (SFA2 on a PCA of 2
    components has 3 signals), every direction is kept: fewer slow features.
    """
    x = np.asarray(x, np.float64)
    lengths = np.asarray(lengths, int)
    mask = np.arange(x.shape[1])[None, :] < lengths[:, None]
    flat = x[mask]
    mean = flat.mean(axis=0)
    centred = flat - mean
    cov = centred.T @ centred / len(centred)  # X^T X: numpy calls BLAS syrk
    d = part_differences(x, lengths)
    return sfa_from_moments(mean, cov, d.T @ d / max(len(d), 1), n_components, rel_eps)


def sfa_from_moments(mean: np.ndarray, cov: np.ndarray, dcov: np.ndarray,
                     n_components: int, rel_eps: float = 1e-9) -> SFA:
    """Linear SFA from the training moments (what :func:`fit_sfa` computes from data).

    Args:
        mean: (D,) mean; cov: (D, D) covariance of the signals; dcov: (D, D) mean of
            d d^T over the within-part differences d; n_components, rel_eps: as
            :func:`fit_sfa`.
    """
    ev, vec = np.linalg.eigh(cov)
    keep = ev > rel_eps * max(float(ev.max()), 1e-300)
    white = vec[:, keep] / np.sqrt(ev[keep])
    n_components = min(int(n_components), white.shape[1])  # fewer inputs: all of them
    # covariance of the whitened derivative, W^T (D^T D / n) W: for many inputs (SFA2)
    # one syrk over the samples instead of whitening every difference first
    wd = white.T @ dcov @ white
    dev, dvec = np.linalg.eigh(wd)
    w = white @ dvec[:, :n_components]
    return SFA(mean=np.asarray(mean, np.float64), w=w, delta=dev[:n_components])


def quadratic_expansion(x: np.ndarray) -> np.ndarray:
    """(..., K + K (K - 1) / 2): the K inputs, then x_i x_j for i < j (§5.2.4)."""
    x = np.asarray(x, np.float64)
    k = x.shape[-1]
    out = np.empty(x.shape[:-1] + (k + k * (k - 1) // 2,))
    out[..., :k] = x
    a = k
    for i in range(k - 1):  # products x_i x_j, j > i, in np.triu_indices order
        np.multiply(x[..., i:i + 1], x[..., i + 1:], out=out[..., a:a + k - 1 - i])
        a += k - 1 - i
    return out
