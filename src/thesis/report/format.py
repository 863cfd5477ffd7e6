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
