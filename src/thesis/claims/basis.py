"""What a verdict rests on: the declared departures of the results a claim reads.

Every result carries the records of the departures it rests on (attribute ``departures``,
written by ``thesis run``: :func:`thesis.departures.records`, with the run's config values).
Here they are joined with the current declarations (:mod:`thesis.departures`) and with the
thesis's stated setup (:func:`thesis.paper.setup`) to decide, per departure, whether it is
*in effect* in that run: a deviation is not in effect when every config path it names held
the thesis's value (e.g. the paper profile's PSO sizes); a choice always is.

A verdict is then read as "reproduced as stated" when no deviation is in effect in any
result it rests on, and "reproduced under a declared deviation" otherwise
(:func:`reading`); the same holds for the other statuses.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping

import xarray as xr

from thesis import departures as decl
from thesis import paper

#: Readings of a verdict (status + whether a declared deviation is in effect).
READINGS = (
    "reproduced as stated", "reproduced under a declared deviation",
    "not reproduced as stated", "not reproduced under a declared deviation",
    "inconclusive as stated", "inconclusive under a declared deviation", "not run",
)


def _recorded(ds: xr.Dataset) -> list[dict] | None:
    raw = ds.attrs.get(decl.ATTR)
    if raw is None:
        return None
    return json.loads(raw) if isinstance(raw, str) else list(raw)


def _run_config(ds: xr.Dataset) -> dict:
    raw = ds.attrs.get("config_json")
    try:
        return json.loads(raw) if isinstance(raw, str) else {}
    except json.JSONDecodeError:
        return {}


def _thesis_values(rec: dict) -> dict[str, list]:
    """Per config path, the thesis's stated values known for it (paper setup entries among
    the departure's paper keys, and its ``thesis_config``)."""
    out: dict[str, list] = {p: [] for p in rec["config"]}
    for k in rec.get("paper_keys", []):
        try:
            e = paper.get(k)
        except KeyError:
            continue
        if e.config in out:
            out[e.config].append(("paper", e))
    for p, v in rec.get("thesis_config", {}).items():
        if p in out:
            out[p].append(("value", v))
    return out


def is_in_effect(rec: dict) -> bool:
    """Whether a departure record is in effect in the run whose config values it holds.

    A choice always is. A deviation is not in effect only when every one of its config
    paths has a known thesis value and the run's value matches it (an unknown or
    unrecorded value counts as in effect).
    """
    if rec["kind"] != "deviation":
        return True
    if not rec["config"]:
        return True
    for path, known in _thesis_values(rec).items():
        value = rec["config"].get(path)
        if not known or value is None:
            return True
        for how, v in known:
            same = v.matches_config(value) if how == "paper" else (
                paper.config_matches(v, "value", value) if not isinstance(v, list)
                else list(v) == list(value))
            if not same:
                return True
    return False


def _paper_entries(rec: dict) -> list[dict]:
    out = []
    for k in rec.get("paper_keys", []):
        try:
            e = paper.get(k)
        except KeyError:
            out.append({"key": k, "value": None, "unit": "", "config": ""})
            continue
        out.append({"key": k, "value": e.value, "unit": e.unit, "config": e.config,
                    "config_form": e.config_form})
    return out


def result_departures(key: str, ds: xr.Dataset) -> list[dict]:
    """The departures result ``key`` rests on, each a JSON-ready record with ``in_effect``.

    Records stored with the result keep their config values (what the run used). A
    departure declared after the run is added with its config values looked up in the
    result's ``config_json`` (``recorded: false``; a value not found there is ``None``).
    """
    stored = {r["id"]: r for r in (_recorded(ds) or [])}
    current = {d.id: d for d in decl.for_result(key)}
    run_cfg = _run_config(ds)
    out = []
    for did in [*stored, *(i for i in current if i not in stored)]:
        if did in current:
            d = current[did]
            rec = {"id": d.id, "kind": d.kind, "thesis": d.thesis, "ours": d.ours,
                   "why": d.why, "paper_keys": list(d.paper_keys),
                   "thesis_config": {p: v for p, v in d.thesis_config}}
        else:
            rec = {k: stored[did][k] for k in ("id", "kind", "thesis", "ours", "why")}
            rec["paper_keys"] = list(stored[did].get("paper_keys", []))
            rec["thesis_config"] = dict(stored[did].get("thesis_config", {}))
        if did in stored:
            rec["config"] = dict(stored[did].get("config", {}))
            rec["recorded"] = True
        else:
            paths = current[did].config
            values = {}
            for p in paths:
                try:
                    values[p] = decl.config_value(run_cfg, p)
                except KeyError:
                    values[p] = None
            rec["config"] = values
            rec["recorded"] = False
        rec["in_effect"] = is_in_effect(rec)
        rec["paper"] = _paper_entries(rec)
        out.append(rec)
    return out


def claim_departures(requires: Iterable[str],
                     results: Mapping[str, xr.Dataset]) -> list[dict]:
    """Departures of every result in ``requires`` that is present, merged by id.

    Each record names the claim's ``results`` it comes from; it is ``in_effect`` when it
    is in effect in any of them (the config values are those of the first).
    """
    merged: dict[str, dict] = {}
    for key in requires:
        if key not in results:
            continue
        for rec in result_departures(key, results[key]):
            have = merged.get(rec["id"])
            if have is None:
                merged[rec["id"]] = {**rec, "results": [key]}
            else:
                have["results"].append(key)
                have["in_effect"] = have["in_effect"] or rec["in_effect"]
    return list(merged.values())


def reading(status: str, deps: Iterable[dict]) -> str:
    """``status`` read with its departures, one of :data:`READINGS`."""
    if status == "not_run":
        return "not run"
    deviated = any(d["kind"] == "deviation" and d["in_effect"] for d in deps)
    return f"{status.replace('_', ' ')} {'under a declared deviation' if deviated else 'as stated'}"
