"""Rule 8 of :mod:`thesis.claims.stats`: timings and ratios are measurements, not seeded
outcomes: a median against a bound, "roughly a factor F" as a band.
"""

from __future__ import annotations

import numpy as np

from thesis.claims.levels import ROUGHLY
from thesis.claims.types import Verdict


def decide_measurement(value: float, *, bound: float, below: bool, label: str) -> Verdict:
    """Decide a timing-like measurement (median over repeats) against ``bound`` (rule 8)."""
    side = "below" if below else "above"
    statistic = f"{label} (median over repeats, a measurement without interval) {side} {bound:g}"
    measured = {label: value, "bound": bound}
    if not np.isfinite(value):
        return Verdict("inconclusive", measured, statistic, f"{label} is not finite")
    ok = value < bound if below else value > bound
    return Verdict("reproduced" if ok else "not_reproduced", measured, statistic,
                   f"{label} = {value:.3g} is {'' if ok else 'not '}{side} {bound:g}")


def decide_roughly(values, *, factor: float, label: str) -> Verdict:
    """Decide "roughly a factor ``factor``" from measured ratios ``values`` (rule 8).

    Reproduced when every finite ratio lies in ``[factor / ROUGHLY, factor * ROUGHLY]``;
    not_reproduced when their geometric mean lies outside it; inconclusive when the mean is
    inside but some ratios are not.
    """
    x = np.asarray(values, float).ravel()
    x = x[np.isfinite(x) & (x > 0)]
    lo, hi = factor / ROUGHLY, factor * ROUGHLY
    gmean = float(np.exp(np.log(x).mean())) if x.size else float("nan")
    statistic = (f"{label}: every measured ratio (no interval) within roughly a factor "
                 f"{factor:g}, i.e. [{lo:g}, {hi:g}]")
    measured = {f"{label}_gmean": gmean, f"{label}_min": float(x.min()) if x.size else np.nan,
                f"{label}_max": float(x.max()) if x.size else np.nan, "band_low": lo,
                "band_high": hi, "n_configurations": float(x.size)}
    if not x.size:
        return Verdict("inconclusive", measured, statistic, f"no finite {label}")
    inside = (x >= lo) & (x <= hi)
    if inside.all():
        return Verdict("reproduced", measured, statistic,
                       f"every {label} ({x.min():.3g} to {x.max():.3g}) is in [{lo:g}, {hi:g}]")
    if not lo <= gmean <= hi:
        return Verdict("not_reproduced", measured, statistic,
                       f"geometric mean {gmean:.3g} is outside [{lo:g}, {hi:g}]")
    return Verdict("inconclusive", measured, statistic,
                   f"geometric mean {gmean:.3g} is in the band but {int((~inside).sum())} of "
                   f"{x.size} ratios are not")
