"""Whether a Tab. 2.2 test error is better than chance, as a one-sided binomial test.

A classifier that learned nothing errs on 9 in 10 digits (10 classes). The per-digit error
of ``n_test`` test sequences is counted conservatively over the sequences, not their
digits (the digits of one sequence share a canvas and a model state), so a cell passes
when so few errors are improbable by chance: P(X <= k | n_test, 0.9) < ``alpha``.
"""

from __future__ import annotations

from thesis.claims.sentences import CHANCE_ERROR
from thesis.claims.sentences import better_than_chance as _better_than_chance

ALPHA = 1e-3


def better_than_chance(errors, n_test: int, alpha: float = ALPHA):
    """Boolean array like ``errors`` (per-digit error rates of cells tested on ``n_test``
    sequences): True where the cell's error is significantly below :data:`CHANCE_ERROR`
    (:func:`thesis.claims.sentences.better_than_chance` at this module's stricter level)."""
    return _better_than_chance(errors, n_test, alpha=alpha)
