"""Every claim of the thesis as a check on result datasets (chapters 2-7, §8.1 and §8.2).

Public API:

- ``CLAIMS``: all :class:`Claim` objects, chapter order; ``get(id)`` one of them;
- :func:`evaluate_all` ``(results)``: JSON-ready verdicts of every claim, with the
  published numbers each rests on, the numbers measured, and the declared departures of
  the results it reads (:mod:`thesis.claims.basis`: ``departures``, and ``reading``, e.g.
  "reproduced as stated" or "reproduced under a declared deviation");
- :class:`Verdict`, :class:`Claim`, :data:`STATUSES`; the statistics in
  :mod:`thesis.claims.stats`.

``results`` maps result keys (``"ch2/table2_2"``) to loaded datasets, as
:func:`thesis.store.load_results` returns them. Verdicts are computed from those datasets
only; a claim whose datasets are missing is ``not_run``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

from thesis import paper
from thesis.claims import (
    basis, ch2, ch3, ch4, ch5, ch6, ch7, ch8, coopt, decidability, kinds, model_validity,
    stats,
)
from thesis.claims.types import NOT_IMPLEMENTED, STATUSES, Claim, LayoutError, Verdict

#: How :meth:`Claim.check` begins the detail of a verdict whose results are absent.
MISSING = "missing datasets: "

__all__ = ["CLAIMS", "Claim", "Verdict", "STATUSES", "NOT_IMPLEMENTED", "LayoutError", "get",
           "evaluate", "evaluate_all", "mark_unreadable", "perturbed_view"]

CLAIMS: tuple[Claim, ...] = (
    *ch2.CLAIMS, *ch3.CLAIMS, *ch4.CLAIMS, *ch5.CLAIMS, *ch6.CLAIMS, *ch7.CLAIMS, *ch8.CLAIMS,
    *coopt.CLAIMS,
)

_BY_ID: dict[str, Claim] = {}
for _c in CLAIMS:
    if _c.id in _BY_ID:
        raise ValueError(f"duplicate claim id {_c.id!r}")
    _BY_ID[_c.id] = _c
del _c


def get(claim_id: str) -> Claim:
    """The claim with id ``claim_id``."""
    return _BY_ID[claim_id]


def _units(reads, results: Mapping[str, xr.Dataset]) -> dict[str, str]:
    """``"<result key>:<variable>"`` -> the variable's ``units`` attribute, for every
    variable a claim reads that is present (the report names the measured numbers' unit)."""
    out = {}
    for item in reads:
        key, _, name = item.partition(":")
        ds = results.get(key)
        if ds is not None and name in ds.variables:
            out[item] = str(ds[name].attrs.get("units", ""))
    return out


def _paper_entry(key: str) -> dict[str, object]:
    e = paper.get(key)
    return {"key": e.key, "table": e.table, "row": e.row, "column": e.column,
            "value": e.value, "unit": e.unit}


#: Suffix of a perturbed twin's variable (:mod:`thesis.ch6.twins`).
TWIN_SUFFIX = "_perturbed"


def replaced_view(results: Mapping[str, xr.Dataset],
                  runs: Mapping[str, xr.Dataset] | None = None
                  ) -> tuple[dict[str, xr.Dataset], set]:
    """(the results with each result of ``runs`` in place of the result of the same key,
    the keys replaced): the view of a profile's twin runs of one kind, perturbed
    (``results/<profile>-perturbed/``, part of :func:`perturbed_view`) or native
    (``results/<profile>-native/``: the same experiments with every CPU pin lifted,
    :func:`thesis.cpupins.native_env`). Deciding a claim on the view decides it as those
    runs would have."""
    view, keys = dict(results), set()
    for key, ds in (runs or {}).items():
        if key in results:
            view[key] = ds
            keys.add(key)
    return view, keys


def perturbed_view(results: Mapping[str, xr.Dataset],
                   twin_runs: Mapping[str, xr.Dataset] | None = None
                   ) -> tuple[dict[str, xr.Dataset], set]:
    """(the results as perturbed twin runs give them, the keys of the results that have
    twins). Two kinds of twins: a result of ``twin_runs`` (the same experiment rerun with
    ``thesis --perturb``, ``results/<profile>-perturbed/``) replaces the result of the same
    key; a dataset that carries its twins' values (``<name>_perturbed``, chapter 6's
    per-run twins, :mod:`thesis.ch6.twins`) has each variable replaced by its twin's.
    Deciding a claim on the view decides it as the twin runs would have (issue: a verdict
    is fragile when a rounding-level perturbation of the runs moves it)."""
    view, twinned = replaced_view(results, twin_runs)
    for key, ds in results.items():
        names = [n for n in ds.data_vars if n.endswith(TWIN_SUFFIX)]
        if not names or key in twinned:
            continue
        swapped = ds.copy()
        for n in names:  # both ways: on the view, the original run is the twin's twin
            swapped[n.removesuffix(TWIN_SUFFIX)] = ds[n]
            swapped[n] = ds[n.removesuffix(TWIN_SUFFIX)]
        view[key] = swapped
        twinned.add(key)
    return view, twinned


def seeds_moved(reads, results: Mapping[str, xr.Dataset]) -> dict[str, list[int]]:
    """Per variable a claim reads that carries per-run twins (``<name>_perturbed``,
    chapter 6), ``[runs whose twin moved the value, runs with both]``: fragility per
    seed, beside the verdict's own (the verdict may stay while its successes move to other
    seeds)."""
    out = {}
    for item in reads:
        key, _, name = str(item).partition(":")
        ds = results.get(key)
        if ds is None or name not in ds.data_vars or name + TWIN_SUFFIX not in ds.data_vars:
            continue
        a = np.asarray(ds[name].values, float).ravel()
        b = np.asarray(ds[name + TWIN_SUFFIX].values, float).ravel()
        if a.shape != b.shape:
            continue
        both = np.isfinite(a) & np.isfinite(b)
        out[item] = [int((both & (a != b)).sum()), int(both.sum())]
    return out


def evaluate(claim: Claim, results: Mapping[str, xr.Dataset],
             perturbed: tuple[Mapping[str, xr.Dataset], set] | None = None,
             native: tuple[Mapping[str, xr.Dataset], set] | None = None
             ) -> dict[str, object]:
    """One claim's verdict as a JSON-ready dict: claim fields, paper numbers, verdict, the
    units of the variables it reads (``units``), the units the claim declares for the
    numbers it reports (``measured_units``, :attr:`Claim.units`; empty when it reports the
    variables in their own units), the departures of the results it rests on
    (``departures``, each with ``in_effect``) and its ``reading``
    (:func:`thesis.claims.basis.reading`). Where every result the claim requires carries
    perturbed twins (``perturbed``, default :func:`perturbed_view` of ``results``), also
    ``perturbed``: the verdict decided on the twins (status, measured numbers, statistic,
    detail), and ``fragile`` (the two differ).
    Likewise, where every required result has a native twin run (``native``, a
    :func:`replaced_view` of the native runs), ``native``: the verdict decided on it, and
    ``isa_dependent``. Where a variable it reads carries per-run twins, ``seeds_moved``
    (:func:`seeds_moved`): the runs whose outcome the twin moved, per seed and not only
    through the verdict. Where the claim rests on the simulated Oncilla and the profile's
    model validation failed a target, ``model_validation``
    (:func:`thesis.claims.model_validity.flag`). An inconclusive verdict carries
    ``inconclusive_kind``: why, and what more compute would buy
    (:func:`thesis.claims.kinds.classify`)."""
    verdict = claim.check(results)
    deps = basis.claim_departures(claim.requires, results)
    out = {
        "id": claim.id, "chapter": claim.chapter, "section": claim.section,
        "quote": claim.quote, "summary": claim.summary, "requires": list(claim.requires),
        "reads": list(claim.reads), "units": _units(claim.reads, results),
        "measured_units": dict(claim.units),
        "paper": [_paper_entry(k) for k in claim.paper_keys],
        **verdict.to_dict(), "reading": basis.reading(verdict.status, deps),
        "departures": deps,
    }
    moved = seeds_moved(claim.reads, results)
    if moved:
        out["seeds_moved"] = moved
    twins = (("perturbed", "fragile", perturbed_view(results) if perturbed is None
              else perturbed), ("native", "isa_dependent", native))
    for name, flag, decided_on in twins:
        # twinned only when every input has a twin: with one input rerun and another not,
        # the "twin" verdict mixes both runs and cannot say whether the claim is fragile
        if decided_on is not None and claim.requires and set(claim.requires) <= decided_on[1]:
            other = claim.check(decided_on[0])
            out[name] = other.to_dict()
            out[flag] = other.status != verdict.status
    out.update(model_validity.flag(claim.requires, results, verdict.status,
                                   claim.paper_keys))
    kind = kinds.classify(out)
    if kind is not None:
        out["inconclusive_kind"] = kind
    sized = decidability.record(claim.id, claim.requires)
    if sized is not None:
        out["decidability"] = sized
    return out


def mark_unreadable(verdict: dict[str, object],
                    unreadable: Mapping[str, Mapping[str, str]]) -> dict[str, object]:
    """``verdict`` (of :func:`evaluate`) told why it is ``not_run`` where a result it
    requires is on disk but damaged: ``unreadable`` maps result keys to
    :meth:`thesis.errors.DamagedFileError.to_dict` records. The status stays ``not_run``
    (the claim was not decided; every consumer of :data:`STATUSES` knows it), its
    ``detail`` names each damaged file with its cause and the command that remakes it, and
    ``unreadable`` lists those records. A verdict that needs no damaged result is returned
    unchanged."""
    keys = [k for k in verdict.get("requires", ()) if k in unreadable]
    if not keys:
        return verdict
    recs = [dict(unreadable[k], key=k) for k in keys]
    detail = "unreadable result: " + "; ".join(
        f"{r['path']} ({r['cause']}; remake: {r['remake']})" for r in recs)
    before = str(verdict.get("detail", ""))
    if before.startswith(MISSING):  # the results that are absent, not damaged
        before = ", ".join(k for k in before.removeprefix(MISSING).split(", ")
                           if k not in unreadable)
        before = MISSING + before if before else ""
    if before:
        detail += "; " + before
    out = {**verdict, "status": "not_run", "reading": basis.reading("not_run", []),
           "detail": detail, "unreadable": recs}
    out.pop("inconclusive_kind", None)
    return out


def evaluate_all(results: Mapping[str, xr.Dataset], *,
                 n_resamples: int | None = None,
                 twin_runs: Mapping[str, xr.Dataset] | None = None,
                 native_runs: Mapping[str, xr.Dataset] | None = None,
                 unreadable: Mapping[str, Mapping[str, str]] | None = None
                 ) -> list[dict[str, object]]:
    """Verdicts of every claim in ``CLAIMS`` order (see :func:`evaluate`); ``twin_runs``:
    the profile's perturbed twin runs, if any were made (:func:`perturbed_view`);
    ``native_runs``: its native twin runs, if any (:func:`replaced_view`);
    ``unreadable``: result key -> record of a result file that is damaged
    (:func:`thesis.store.scan_results`): the claims that need one are ``not_run`` naming
    it (:func:`mark_unreadable`), every other claim is decided as usual.

    ``n_resamples`` (config ``report.bootstrap_resamples``) sets the resamples of
    :func:`thesis.claims.stats.bootstrap_mean`; no decision rule resamples any more (rule 3
    is the Student t interval), so it does not change a verdict.
    """
    view = perturbed_view(results, twin_runs)
    other = replaced_view(results, native_runs)
    if n_resamples is None:
        out = [evaluate(c, results, view, other) for c in CLAIMS]
    else:
        with stats.resamples(n_resamples):
            out = [evaluate(c, results, view, other) for c in CLAIMS]
    return [mark_unreadable(v, unreadable or {}) for v in out]
