"""Claims of §8.2 (perspectives) made testable: co-optimisation and analytic gradients.

The thesis proposes these experiments and never ran them; the claims are the issue's
(issue 42) hypotheses, with decision rules fixed before any result was looked at:

* co-optimisation (``coopt/arms``): paired by seed (every seed starts the three arms from
  one network), rule 4 (:func:`thesis.claims.stats.decide_beats`) on the final speed of
  the nominal start, and on the mean speed over the perturbed starts;
* analytic against estimated gradients (``coopt/gradients``): per probe point (seed) the
  rollouts a REINFORCE / ES estimate needs before its median cosine with the engine's
  gradient stays above ``cos_threshold``, for the controller's parameters (the thesis's
  parameter counts). "Orders of magnitude fewer rollouts": rule 6
  (:func:`~thesis.claims.stats.decide_threshold`) on log10 of that count above
  :data:`ORDERS` (the engine needs one rollout and its backward pass), at every horizon
  (:func:`~thesis.claims.stats.combine`). An estimator that never gets there counts with
  the budget (``rollouts_max``), a lower bound of its need;
* the chaos chapter 7 met: the engine's gradient spread over perturbed starts
  (``start_relative_spread``) grows by at least :data:`SPREAD_GROWTH` from the shortest to
  the longest horizon (rule 6 on log10 of the ratio); a horizon whose gradients were not
  finite counts as exploded (:data:`EXPLODED`).

Dataset contracts (``results/<profile>/coopt/``): ``arms``: ``final_speed`` (arm, seed)
and ``perturbed_speed`` (arm, seed, start) [m/s], arms ``controller``, ``morphology``,
``joint``. ``gradients``: ``rollouts_to_threshold`` (seed, group, horizon, estimator),
attribute ``rollouts_max``; ``start_relative_spread`` and ``start_nonfinite`` (seed,
group, variance_horizon).
"""

from __future__ import annotations

import numpy as np

from thesis.claims import stats
from thesis.claims.types import Claim, Results, Verdict, pick, variable

ARMS = "coopt/arms"
GRADS = "coopt/gradients"
#: "orders of magnitude": at least 10^2 rollouts where the engine needs one
ORDERS = 2.0
#: the analytic gradient's spread "explodes": at least tenfold from shortest to longest
SPREAD_GROWTH = 10.0
#: log10 of the growth ascribed to a horizon whose gradients were not finite
EXPLODED = 10.0

_COOPT = ("Since the automatic differentiation library does not care whether a parameter is "
          "inside the morphology of the robot or is a parameter in the controller, both can "
          "be optimized simultaneously using gradient descent.")
_GRADS = ("If we can have analytic gradients of complex models, there is probably insight to "
          "be gained by comparing those gradients to the gradient approximations found by for "
          "instance policy gradient methods.")


def _beats(results: Results, var: str, a: str, b: str) -> Verdict:
    dims = ("arm", "seed") + (("start",) if var == "perturbed_speed" else ())
    da = variable(results, ARMS, var, dims=dims)
    per = stats.per_seed(pick(da, arm=[a, b]), keep=("arm",))
    return stats.decide_beats(per.sel({"arm": a}).values, per.sel({"arm": b}).values,
                              higher_is_better=True, label_a=a, label_b=b)


def _rollouts(results: Results, estimator: str) -> Verdict:
    da = variable(results, GRADS, "rollouts_to_threshold",
                  dims=("seed", "group", "horizon", "estimator"))
    da = pick(da, group="controller", estimator=estimator)
    budget = float(results[GRADS].attrs.get("rollouts_max", np.nan))
    parts = {}
    for h in da["horizon"].values:
        n = da.sel({"horizon": h}).values.astype(float)
        reached = np.isfinite(n)
        logn = np.log10(np.where(reached, n, budget))
        v = stats.decide_threshold(logn, bound=ORDERS, below=False,
                                   label=f"log10_rollouts_h{int(h)}")
        parts[f"horizon {int(h)} steps"] = Verdict(
            v.status, {**v.measured, f"reached_h{int(h)}": int(reached.sum()),
                       f"seeds_h{int(h)}": int(n.size)}, v.statistic, v.detail)
    out = stats.combine(parts, statistic=f"rule 6 per horizon on log10 of the {estimator} "
                        f"rollouts to the cosine threshold (budget {budget:g} where never "
                        "reached), all horizons must hold")
    return out


def _finite_mean(x) -> float:
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    return float(x.mean()) if x.size else float("nan")


def _spread(results: Results) -> Verdict:
    da = variable(results, GRADS, "start_relative_spread",
                  dims=("seed", "group", "variance_horizon"))
    bad = variable(results, GRADS, "start_nonfinite",
                   dims=("seed", "group", "variance_horizon"))
    da, bad = pick(da, group="controller"), pick(bad, group="controller")
    hs = sorted(int(h) for h in da["variance_horizon"].values)
    lo, hi = hs[0], hs[-1]
    s_lo = da.sel({"variance_horizon": lo}).values
    s_hi = da.sel({"variance_horizon": hi}).values
    nonfinite = bad.sel({"variance_horizon": hi}).values > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.log10(s_hi / s_lo)
    ratio = np.where(nonfinite & ~np.isfinite(ratio), EXPLODED, ratio)
    v = stats.decide_threshold(ratio, bound=np.log10(SPREAD_GROWTH), below=False,
                               label="log10_spread_growth")
    return Verdict(v.status, {**v.measured, "shortest_horizon": lo, "longest_horizon": hi,
                              "spread_shortest_mean": _finite_mean(s_lo),
                              "spread_longest_mean": _finite_mean(s_hi),
                              "seeds_nonfinite_longest": int(nonfinite.sum())},
                   v.statistic, v.detail)


CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="ch8.coopt_joint_beats_controller_only", chapter=8, section="§8.2",
        quote=_COOPT,
        summary="Within the same budget of gradient evaluations, controller and body "
                "optimised together end faster than the controller alone on the built body "
                "(final speed from the nominal start, paired by seed, rule 4).",
        requires=(ARMS,), reads=(f"{ARMS}:final_speed",),
        fn=lambda r: _beats(r, "final_speed", "joint", "controller"),
    ),
    Claim(
        id="ch8.coopt_joint_beats_morphology_only", chapter=8, section="§8.2",
        quote=_COOPT,
        summary="Within the same budget, controller and body together end faster than the "
                "body alone under the fixed initial controller (rule 4, paired by seed).",
        requires=(ARMS,), reads=(f"{ARMS}:final_speed",),
        fn=lambda r: _beats(r, "final_speed", "joint", "morphology"),
    ),
    Claim(
        id="ch8.coopt_joint_advantage_holds_from_perturbed_starts", chapter=8, section="§8.2",
        quote=_COOPT,
        summary="The jointly optimised gaits are faster than the controller-only ones also "
                "from perturbed starts (mean over starts per seed, rule 4).",
        requires=(ARMS,), reads=(f"{ARMS}:perturbed_speed",),
        fn=lambda r: _beats(r, "perturbed_speed", "joint", "controller"),
    ),
    Claim(
        id="ch8.coopt_gradient_needs_fewer_rollouts_than_reinforce", chapter=8, section="§8.2",
        quote=_GRADS,
        summary="A REINFORCE (score-function) estimate of the controller's gradient needs at "
                "least 100 rollouts (two orders of magnitude over the engine's one) before "
                "its median cosine with the engine's gradient stays above the threshold, at "
                "every horizon (rule 6 on log10 per probe point; never reached counts as "
                "the budget).",
        requires=(GRADS,), reads=(f"{GRADS}:rollouts_to_threshold",),
        fn=lambda r: _rollouts(r, "reinforce"),
    ),
    Claim(
        id="ch8.coopt_gradient_needs_fewer_rollouts_than_es", chapter=8, section="§8.2",
        quote=_GRADS,
        summary="The same for an antithetic evolution-strategies estimate.",
        requires=(GRADS,), reads=(f"{GRADS}:rollouts_to_threshold",),
        fn=lambda r: _rollouts(r, "es"),
    ),
    Claim(
        id="ch8.coopt_analytic_gradient_spread_explodes_with_horizon", chapter=8,
        section="§8.2", quote=_GRADS,
        summary="The engine's own gradient of the controller varies over perturbed starts "
                "at least tenfold more (relative spread) at the longest horizon than at the "
                "shortest (rule 6 on log10 of the ratio per probe point).",
        requires=(GRADS,), reads=(f"{GRADS}:start_relative_spread",
                                  f"{GRADS}:start_nonfinite"),
        fn=_spread,
    ),
)
