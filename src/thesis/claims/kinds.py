"""Why a verdict is inconclusive, in one of a few kinds, so that a reader sees what more
compute would buy.

Every *inconclusive* verdict of :func:`thesis.claims.evaluate` carries
``inconclusive_kind`` (:func:`classify`), one of :data:`KINDS`:

- ``"model failed validation"``: the claim rests on a simulated robot whose validation
  failed a target (named, :mod:`thesis.claims.model_validity`); more seeds of that model
  decide nothing about the thesis's robot;
- ``"not testable at this profile's scale"``: the profile runs a smaller budget, network,
  batch or duration than the thesis (rule 11 of :mod:`thesis.claims.stats`); the paper
  profile may test it;
- ``"needs about N seeds"``: at the measured effect and spread, the rule's test reaches
  80 % power (:data:`POWER`) at about N seeds (:func:`seeds_needed`), and N is within the
  paper profile's seed count for the results the claim reads;
- ``"ambiguous at any seed count the paper profile has"``: N exceeds the paper profile's
  seed count, the measured effect is nil (no seed count decides it), or the verdict's
  numbers give no effect to size (N is then absent).

N is estimated per part of the verdict (each set of measured numbers a rule writes: a
mean with its interval and seed count; a count of seeds with the event) and the largest
is kept, since every part must be decided. For a mean: the t interval's half-width gives
the per-seed spread s, the effect d is the distance of the mean from the rule's bound
(0 for "A beats B", the bound of rule 6, the margin minus |mean| for rule 5), and N is the
smallest n with t(0.975, n-1) + t(0.8, n-1) <= d sqrt(n) / s (the one-sided t test at
2.5 % with 80 % power). For a count: the smallest n at which the exact binomial test of
the rule (rule 10's majority, rule 7, existence against runs passing by chance) reaches
80 % power at the measured rate. These are estimates at the measured effect, which is
itself uncertain: a planning number, not a promise.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping

import numpy as np
from scipy import stats as sps

from thesis.claims import stats

#: The kinds of an inconclusive verdict.
KINDS = ("needs more seeds", "model failed validation", "not testable at this profile's scale",
         "ambiguous at any seed count the paper profile has")
#: Power at which the seed count is sized.
POWER = 0.8
#: Largest seed count searched (beyond it: no seed count the profiles run decides it).
MAX_SEEDS = 1000


def _t_seeds(d: float, s: float) -> float:
    """Smallest n with t(1 - ONE_SIDED, n-1) + t(POWER, n-1) <= d sqrt(n) / s; inf when
    ``d`` is not positive or nothing up to :data:`MAX_SEEDS` reaches it."""
    if not (np.isfinite(d) and np.isfinite(s)) or d <= 0:
        return math.inf
    if s <= 0:
        return float(stats.MIN_SEEDS)
    for n in range(stats.MIN_SEEDS, MAX_SEEDS + 1):
        need = sps.t.ppf(1 - stats.ONE_SIDED, n - 1) + sps.t.ppf(POWER, n - 1)
        if need * s / np.sqrt(n) <= d:
            return float(n)
    return math.inf


def _count_seeds(rate: float, reaches) -> float:
    """Smallest n at which ``reaches(n, rate)`` (the probability that the rule decides
    with n seeds at true rate ``rate``) is at least :data:`POWER`; inf if none is."""
    if not np.isfinite(rate):
        return math.inf
    for n in range(stats.MIN_SEEDS, MAX_SEEDS + 1):
        if reaches(n, rate) >= POWER:
            return float(n)
    return math.inf


def _majority_power(n: int, rate: float) -> float:
    """Probability that the exact binomial test against 1/2 decides either way with n
    seeds at true rate ``rate`` (the side the rate is on)."""
    ks = np.arange(n + 1)
    if rate >= 0.5:
        hit = sps.binom.sf(ks - 1, n, 0.5) <= stats.ONE_SIDED
    else:
        hit = sps.binom.cdf(ks, n, 0.5) <= stats.ONE_SIDED
    return float(sps.binom.pmf(ks[hit], n, rate).sum())


def _exists_power(replicated: bool):
    """The probability that existence is shown with n seeds at a true rate of counted
    events (:func:`thesis.claims.stats.exists_needs`)."""
    def power(n: int, rate: float) -> float:
        need = stats.exists_needs(n, replicated=replicated)
        return float(sps.binom.sf(need - 1, n, rate)) if need <= n else 0.0
    return power


def _groups(measured: Mapping[str, object]) -> dict[str, dict[str, float]]:
    """Measured numbers by part: ``"part.name"`` -> group ``"part"``, key ``"name"``."""
    out: dict[str, dict[str, float]] = {}
    for k, v in measured.items():
        if not isinstance(v, (int, float)) or isinstance(v, bool):
            continue
        group, _, name = str(k).rpartition(".")
        out.setdefault(group, {})[name] = float(v)
    return out


def _part_seeds(m: Mapping[str, float]) -> float | None:
    """N for one part's numbers (None when they size nothing), at least the fewest seeds
    its rule decides at (``seeds_needed_unflagged``: rule 9's "not worse" without a
    failure flag)."""
    floor = m.get("seeds_needed_unflagged")
    n = _effect_seeds(m)
    if floor is None:
        return n
    return float(floor) if n is None else max(float(floor), n)


def _effect_seeds(m: Mapping[str, float]) -> float | None:
    """N at which one part's measured effect and spread would decide (None: nothing)."""
    n = m.get("n_seeds")
    lows = [k[:-len("_ci_low")] for k in m if k.endswith("_ci_low")
            and not k.startswith("rate")]
    for label in lows:
        mean, lo, hi = (m.get(f"{label}_{x}") for x in ("mean", "ci_low", "ci_high"))
        if mean is None or lo is None or hi is None or not n or n < 2:
            continue
        if not (np.isfinite(lo) and np.isfinite(hi)):
            return math.inf  # a failure rate still unbounded: more seeds, many
        s = (hi - lo) / 2.0 * np.sqrt(n) / sps.t.ppf(1 - stats.ONE_SIDED, n - 1)
        if "margin" in m:
            d = m["margin"] - abs(mean)
        else:
            d = abs(mean - m.get("bound", 0.0))
        return _t_seeds(d, s)
    if n and "n_seeds_counted" in m:  # existence, events repeated by their twin
        return _count_seeds(m["n_seeds_counted"] / n,
                            _exists_power(bool(m.get("replicated", 0.0))))
    if n and "p_most" in m:  # rule 10's majority and rule 7
        k = m.get("n_success")
        if k is None:
            k = next((v for key, v in m.items() if key.startswith("n_seeds_")
                      and key != "n_seeds_failed"), None)
        if k is not None:
            return _count_seeds(k / n, _majority_power)
    return None


def seeds_needed(measured: Mapping[str, object]) -> float | None:
    """About how many seeds the verdict's rules need at the measured effects: the largest
    over its parts (inf: none up to :data:`MAX_SEEDS`; None: nothing to size)."""
    found = [x for x in (_part_seeds(g) for g in _groups(measured).values()) if x is not None]
    return max(found) if found else None


@functools.lru_cache(maxsize=1)
def _paper_config() -> dict:
    from thesis.config import load_config

    return load_config("paper")


def _seeds_at(cfg: dict, path: str) -> int | None:
    """The seed count the config holds at dotted ``path`` (a ``seeds`` list there or in
    the section it names), None when none: a list at ``path`` that is not a ``seeds``
    list (the grades ``ch4.conditions.grades`` names, coopt's hidden widths) counts
    nothing."""
    node = cfg
    for part in path.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    if isinstance(node, dict):
        node = node.get("seeds")
    elif path.rpartition(".")[2] != "seeds":
        return None
    return len(node) if isinstance(node, (list, tuple)) else None


def paper_seeds(requires) -> int | None:
    """The paper profile's seed count for the results a claim reads (the smallest over
    them): the ``seeds`` of the config sections each result's experiment reads
    (:func:`thesis.registry.reads`; ``ch7/pendulum_pixels`` reads ``ch7.pendulum``), else
    of its chapter's section; None when none is known."""
    from thesis import registry

    cfg, counts = _paper_config(), []
    for key in requires:
        try:
            paths = registry.reads(str(key))
        except (KeyError, ValueError):
            paths = ()
        found = [n for n in (_seeds_at(cfg, p) for p in paths) if n is not None]
        if not found:
            n = _seeds_at(cfg, str(key).partition("/")[0])
            found = [n] if n is not None else []
        counts.extend(found[:1])
    return min(counts) if counts else None


def classify(verdict: Mapping[str, object]) -> dict | None:
    """``{"kind", "why", "seeds_needed", "paper_seeds"}`` for an inconclusive verdict of
    :func:`thesis.claims.evaluate` (None for any other status); ``kind`` is
    ``"needs about N seeds"`` with N filled in, or another of :data:`KINDS`."""
    if verdict.get("status") != "inconclusive":
        return None
    paper = paper_seeds(verdict.get("requires", ()))
    mv = verdict.get("model_validation")
    if isinstance(mv, Mapping) and mv.get("unvalidated"):
        names = [str(t.get("target") or t.get("name") or t.get("key") or t)
                 if isinstance(t, Mapping) else str(t) for t in mv.get("failed_targets", [])]
        return {"kind": "model failed validation", "why": "failed targets: " + ", ".join(names),
                "seeds_needed": None, "paper_seeds": paper}
    detail = str(verdict.get("detail", ""))
    if "not testable" in detail:
        return {"kind": "not testable at this profile's scale", "why": detail,
                "seeds_needed": None, "paper_seeds": paper}
    n_now = verdict.get("measured", {}).get("n_seeds")
    need = seeds_needed(verdict.get("measured", {}))
    if need is not None and np.isfinite(need) and isinstance(n_now, (int, float)):
        need = max(need, float(n_now) + 1.0)
    if need is not None and np.isfinite(need) and (paper is None or need <= paper):
        n = int(need)
        return {"kind": f"needs about {n} seeds", "why": "power 80 % at the measured effect",
                "seeds_needed": n, "paper_seeds": paper}
    why = ("no effect to size in its numbers" if need is None else
           "the measured effect is nil or the failure rate unbounded" if not np.isfinite(need)
           else f"about {int(need)} seeds at the measured effect, more than the paper "
                f"profile's {paper}")
    return {"kind": "ambiguous at any seed count the paper profile has", "why": why,
            "seeds_needed": int(need) if need is not None and np.isfinite(need) else None,
            "paper_seeds": paper}


def kind_of(entry: Mapping[str, object]) -> str:
    """The kind of ``entry``'s ``inconclusive_kind`` as counted per chapter ("needs more
    seeds" for every "needs about N seeds"); "" when it has none."""
    k = entry.get("inconclusive_kind")
    if not isinstance(k, Mapping):
        return ""
    kind = str(k.get("kind", ""))
    return "needs more seeds" if kind.startswith("needs about") else kind
