"""What every decision rule shares (:mod:`thesis.claims.stats`): per-seed reduction (rule 1),
too few seeds (rule 2), an untestable sentence (rule 11), the first count that reaches a
target, and the conjunction of parts (:func:`combine`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import xarray as xr

from thesis.claims.levels import MIN_SEEDS, ONE_SIDED
from thesis.claims.types import Verdict


def per_seed(da: xr.DataArray, keep: Sequence[str] = ()) -> xr.DataArray:
    """Average every dimension except ``seed`` and ``keep`` (NaN skipped).

    A dataset without a ``seed`` dimension gives one pseudo-seed, so it counts as n = 1.
    Returns a DataArray with dims ``("seed", *keep)``.
    """
    if "seed" not in da.dims:
        da = da.expand_dims(seed=[0])
    other = [d for d in da.dims if d not in ("seed", *keep)]
    if other:
        da = da.mean(other, skipna=True)
    return da.transpose("seed", *keep)


def _too_few(n: int, measured: dict, statistic: str) -> Verdict | None:
    if n < MIN_SEEDS:
        return Verdict("inconclusive", measured, statistic,
                       f"only {n} seed(s) with values; at least {MIN_SEEDS} are needed")
    return None


def untestable(gaps: list[str], measured: dict | None = None, statistic: str = "") -> Verdict:
    """*Inconclusive* because the profile cannot test the sentence as stated (rule 11)."""
    return Verdict("inconclusive", dict(measured or {}), statistic,
                   "not testable as stated at this profile: " + "; ".join(gaps))


def first_reaching(curve: xr.DataArray, dim: str, threshold: float) -> np.ndarray:
    """Per seed, the first coordinate of ``dim`` where ``curve < threshold`` (NaN if never).

    ``curve`` has dims ``("seed", dim)``; coordinates of ``dim`` count evaluations/updates.
    """
    steps = np.asarray(curve[dim].values, dtype=float)
    below = np.asarray(curve.values < threshold)
    out = np.full(below.shape[0], np.nan)
    for i, row in enumerate(below):
        hit = np.flatnonzero(row)
        if hit.size:
            out[i] = steps[hit[0]]
    return out


def combine(parts: dict[str, Verdict], *, statistic: str = "") -> Verdict:
    """All parts must hold (rule 6's multi-part claim): reproduced if all are (an
    intersection of tests needs no correction); not_reproduced when a part contradicts
    the claim at the family level: Holm over the parts' one-sided p of their
    "not_reproduced" (``measured["p_not_reproduced"]``), whose first step is Bonferroni,
    so the smallest such p times the number of parts at most :data:`ONE_SIDED`; a
    not_reproduced part that carries no p (a count, a check's own logic) contradicts the
    whole uncorrected, as it says. Else inconclusive.

    ``not_run`` parts make the whole ``not_run``; measured numbers are prefixed by part
    name, and the whole's ``p_not_reproduced`` is the Bonferroni-adjusted smallest p.
    """
    statuses = [v.status for v in parts.values()]
    m = len(parts)
    against = {name: v.measured.get("p_not_reproduced", np.nan)
               for name, v in parts.items() if v.status == "not_reproduced"}
    ps = [float(p) for p in against.values() if isinstance(p, float) and np.isfinite(p)]
    bare = [name for name, p in against.items()
            if not (isinstance(p, float) and np.isfinite(p))]
    p_family = min(1.0, m * min(ps)) if ps else np.nan
    note = ""
    if "not_run" in statuses:
        status = "not_run"
    elif bare or (ps and p_family <= ONE_SIDED):
        status = "not_reproduced"
    elif all(s == "reproduced" for s in statuses):
        status = "reproduced"
    else:
        status = "inconclusive"
        if against:
            note = (f"{', '.join(against)} not reproduced alone, not at the family level "
                    f"(Holm over {m} parts: {m} x p = {p_family:.3g} > {ONE_SIDED:g}); ")
    measured = {f"{name}.{k}": v for name, verdict in parts.items()
                for k, v in verdict.measured.items()}
    if status == "not_reproduced" and not bare:
        measured["p_not_reproduced"] = p_family
    detail = note + "; ".join(f"{name}: {v.status} ({v.detail})" for name, v in parts.items())
    stat = statistic or "all of: " + "; ".join(
        f"{name}: {v.statistic}" for name, v in parts.items())
    if m > 1:
        stat += f" (a part contradicts the whole after Holm's correction over the {m} parts)"
    return Verdict(status, measured, stat, detail)
