"""Whether a Tab. 2.2 test error is better than chance, as a one-sided binomial test.

A classifier that learned nothing errs on 9 in 10 digits (10 classes). The per-digit error
of ``n_test`` test sequences is counted conservatively over the sequences, not their
digits (the digits of one sequence share a canvas and a model state), so a cell passes
when so few errors are improbable by chance: P(X <= k | n_test, 0.9) < ``alpha``.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import binomtest

CHANCE_ERROR = 0.9
ALPHA = 1e-3


def better_than_chance(errors, n_test: int, alpha: float = ALPHA) -> np.ndarray:
    """Boolean array like ``errors`` (per-digit error rates of cells tested on ``n_test``
    sequences): True where the cell's error is significantly below :data:`CHANCE_ERROR`."""
    err = np.asarray(errors, dtype=float)
    out = np.zeros(err.shape, bool)
    for i, e in np.ndenumerate(err):
        if np.isfinite(e):
            k = int(round(e * n_test))
            out[i] = binomtest(k, n_test, CHANCE_ERROR, alternative="less").pvalue < alpha
    return out
