"""Ranges a failed run's value can take (rule 3b's ``failure_bounds`` of
:mod:`thesis.claims.stats`), built from the ranges of the quantities it combines: a linear
combination of bounded values, a difference, and the widening that keeps what failed
runs actually recorded inside the declared range.
"""

from __future__ import annotations

import numpy as np


def linear_range(weights, top) -> tuple[float, float]:
    """Range of sum_i w_i v_i when each v_i lies in [0, top_i] (a mean, a least-squares
    slope or their difference over cells whose speeds are bounded)."""
    w, t = np.asarray(weights, float), np.asarray(top, float)
    return float(np.sum(np.minimum(w, 0.0) * t)), float(np.sum(np.maximum(w, 0.0) * t))


def difference_range(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    """Range of A - B for A in ``a`` and B in ``b``: [low A - high B, high A - low B]."""
    return a[0] - b[1], a[1] - b[0]


def containing(bounds: tuple[float, float], values, failed) -> tuple[float, float]:
    """``bounds`` widened to contain every finite value of a seed flagged in ``failed``
    (what failed runs gave lies in the range of what they can give)."""
    x = np.asarray(values, float).ravel()
    f = np.asarray(failed, bool).ravel() & np.isfinite(x)
    lo, hi = float(bounds[0]), float(bounds[1])
    if f.any():
        lo, hi = min(lo, float(x[f].min())), max(hi, float(x[f].max()))
    return lo, hi


def envelope(*arrays) -> tuple[float, float]:
    """(smallest, largest) finite value of ``arrays`` (NaN, NaN when none is finite): the
    range an experiment's recorded values span."""
    x = np.concatenate([np.asarray(a, float).ravel() for a in arrays])
    x = x[np.isfinite(x)]
    return (float(x.min()), float(x.max())) if x.size else (np.nan, np.nan)


def never_improved(start, final) -> np.ndarray:
    """Per run, whether it failed as an optimisation: its ``final`` objective is not
    finite (it diverged) or not above its ``start`` (it never improved). ``start`` and
    ``final``: (n,) [the objective's units], higher is better; a run without a finite
    start is not flagged."""
    s, f = np.asarray(start, float).ravel(), np.asarray(final, float).ravel()
    with np.errstate(invalid="ignore"):
        return np.isfinite(s) & (~np.isfinite(f) | (f <= s))
