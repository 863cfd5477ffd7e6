"""Learning curves of unequal length as one NaN-padded array (for the ch7 datasets)."""

from __future__ import annotations

import numpy as np


def pad_curves(curves, n: int | None = None) -> np.ndarray:
    """Stack 1-D curves into ``(len(curves), n)``, NaN after each curve's end.

    Args:
        curves: sequences of numbers (one per seed), possibly of different lengths
            (an optimisation that met its tolerance early stops early).
        n: width of the result; the longest curve's length when None.
    """
    n = max((len(c) for c in curves), default=0) if n is None else int(n)
    out = np.full((len(curves), n), np.nan)
    for i, c in enumerate(curves):
        out[i, :len(c)] = np.asarray(c, dtype=float)[:n]
    return out
