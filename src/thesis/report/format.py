"""Number formatting shared by the chapter report modules."""

from __future__ import annotations

import numpy as np

from thesis.report.model import NOT_RUN


def fmt(x, digits: int = 3) -> str:
    """A number with ``digits`` significant digits; NaN/None -> "not run"."""
    if x is None:
        return NOT_RUN
    x = float(x)
    if not np.isfinite(x):
        return "nan" if np.isnan(x) else ("inf" if x > 0 else "-inf")
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def mean_spread(values, digits: int = 3) -> str:
    """``mean ± sd (n=k)`` over the finite values (seeds) of an array."""
    v = np.asarray(values, dtype=float).ravel()
    v = v[np.isfinite(v)]
    if v.size == 0:
        return NOT_RUN
    if v.size == 1:
        return f"{fmt(v[0], digits)} (n=1)"
    return f"{fmt(v.mean(), digits)} ± {fmt(v.std(ddof=1), 2)} (n={v.size})"


def mean_interval_text(values, digits: int = 3) -> str:
    """``mean [low, high] (n=k)``: the mean over the finite values (seeds) with its 95 %
    Student t interval, the interval the claims decide on
    (:func:`thesis.claims.stats.mean_interval`); one value: ``value (n=1)``."""
    from thesis.claims import stats

    iv = stats.mean_interval(values)
    if iv.n == 0:
        return NOT_RUN
    if iv.n == 1:
        return f"{fmt(iv.mean, digits)} (n=1)"
    return f"{fmt(iv.mean, digits)} [{fmt(iv.low, digits)}, {fmt(iv.high, digits)}] (n={iv.n})"
