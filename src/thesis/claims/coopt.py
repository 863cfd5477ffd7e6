"""Claims of §8.2 (perspectives) made testable: co-optimisation and analytic gradients.

The thesis proposes these experiments and never ran them; the claims are this project's
hypotheses, with decision rules fixed before any result was looked at:

* co-optimisation (``coopt/arms``): the sentence says joint optimisation *can* be done,
  a feasibility (existential) sentence, decided as existence
  (:func:`joint_optimisation_possible`); the stronger hypotheses, that the joint
  arm beats the single arms, are separate claims marked as going beyond the sentence,
  paired by seed (every seed starts the three arms from
  one network), rule 4 (:func:`thesis.claims.stats.decide_beats`) on the final speed of
  the nominal start, and on the mean speed over the perturbed starts;
* analytic against estimated gradients (``coopt/gradients``): per probe point (seed) the
  rollouts a REINFORCE / ES estimate needs before its median cosine with the engine's
  gradient stays above ``cos_threshold``, for the controller's parameters (the thesis's
  parameter counts). "Orders of magnitude fewer rollouts": rule 6
  (:func:`~thesis.claims.stats.decide_threshold`) on log10 of that count above
  :data:`ORDERS` (the engine needs one rollout and its backward pass), at every horizon
  (:func:`~thesis.claims.stats.combine`). An estimator that never gets there counts with
  the budget (``rollouts_max``), a lower bound of its need, only at probe points where
  some estimator did reach the threshold (a positive control that the engine's gradient
  is the direction estimates converge to); elsewhere the point is dropped;
* the chaos chapter 7 met: the engine's gradient spread over perturbed starts
  (``start_relative_spread``) grows by at least :data:`SPREAD_GROWTH` from the shortest to
  the longest horizon (rule 6 on log10 of the ratio); a horizon whose gradients were not
  finite counts as exploded (:data:`EXPLODED`). Exploded seeds make the per-seed values a
  mixture (finite growths and the score :data:`EXPLODED`), so they are passed as failed
  runs to rule 3b of :mod:`thesis.claims.stats`, their value the score itself: a few
  seeds without an explosion leave a high explosion rate possible, which keeps "does not
  grow tenfold" undecided.

Runs of the arms fail: an optimisation that diverged or never improved is a second mode
far below the rest, under which rule 4 says "A beats B" in up to a third of draws at 3-10
seeds (:mod:`thesis.claims.calibration`). So the joint-beats-single comparisons pass the
joint arm's failure flag per seed (:func:`failed_runs`, from the recorded training curve)
to rule 3b, with the range of the difference on a failed seed from the recorded speeds
(:func:`failed_speed_bounds`).

Dataset contracts (``results/<profile>/coopt/``): ``arms``: ``final_speed`` (arm, seed)
and ``perturbed_speed`` (arm, seed, start) [m/s], arms ``controller``, ``morphology``,
``joint``. ``gradients``: ``rollouts_to_threshold`` (seed, group, horizon, estimator),
attribute ``rollouts_max``; ``start_relative_spread`` and ``start_nonfinite`` (seed,
group, variance_horizon).
"""

from __future__ import annotations

import numpy as np

from thesis.claims import failure_ranges, stats
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


def failed_runs(results: Results, arm: str) -> np.ndarray | None:
    """Per seed, whether ``arm``'s optimisation failed (rule 3b's flag): its final speed
    is not finite (diverged) or not above the speed it started from (``speed`` at the
    first evaluation; never improved), :func:`thesis.claims.failure_ranges.never_improved`.
    None when the training curve ``speed`` is not recorded."""
    ds = results[ARMS]
    if "speed" not in ds.data_vars or "evaluation" not in ds["speed"].dims:
        return None
    curve = ds["speed"].sel({"arm": arm}).transpose("seed", "evaluation")
    final = ds["final_speed"].sel({"arm": arm}).transpose("seed")
    return failure_ranges.never_improved(curve.isel(evaluation=0).values, final.values)


def failed_speed_bounds(results: Results, arm: str, var: str) -> tuple[float, float]:
    """Range [m/s] of (``arm`` - other) ``var`` on a seed where ``arm``'s run failed: the
    failed arm between the slowest speed the experiment recorded and the fastest start
    (a run that never improved ends no faster than where it started), the other arm
    anywhere in the recorded envelope (``speed``, ``final_speed``, ``var``). The lower
    ends are the recorded envelope, not a physical bound: the model gives none."""
    ds = results[ARMS]
    lo, hi = failure_ranges.envelope(ds["speed"].values, ds["final_speed"].values,
                                     ds[var].values)
    top = float(np.nanmax(ds["speed"].isel(evaluation=0).values))
    return failure_ranges.difference_range((lo, top), (lo, hi))


def _beats(results: Results, var: str, a: str, b: str) -> Verdict:
    """Rule 4, ``a`` faster than ``b`` on ``var`` (paired by seed); rule 3b with ``a``'s
    failed runs (:func:`failed_runs`) and their range (:func:`failed_speed_bounds`) when
    the training curve is recorded (a failure of ``b`` only moves the difference towards
    the claim)."""
    dims = ("arm", "seed") + (("start",) if var == "perturbed_speed" else ())
    da = variable(results, ARMS, var, dims=dims)
    per = stats.per_seed(pick(da, arm=[a, b]), keep=("arm",))
    va, vb = per.sel({"arm": a}).values, per.sel({"arm": b}).values
    failed = failed_runs(results, a)
    kw = {}
    if failed is not None:
        kw = {"failed": failed, "failure_bounds": failure_ranges.containing(
            failed_speed_bounds(results, a, var), va - vb, failed)}
    return stats.decide_beats(va, vb, higher_is_better=True, label_a=a, label_b=b, **kw)


def _rollouts(results: Results, estimator: str) -> Verdict:
    """"Orders of magnitude fewer rollouts" for ``estimator``: rule 6 per horizon on log10
    of its rollouts to the cosine threshold, with a positive control per probe point.

    A count that never reached the threshold (NaN) is only a lower bound, and it looks the
    same whether the estimator is expensive or the engine's gradient is meaningless (no
    estimate agrees with a wrong direction). So a probe point counts only where the
    engine's gradient is *validated*: some estimator (this one or the other) reached the
    threshold there within the budget. There this estimator's count is its reached count,
    or the budget when it never got there (a lower bound in the claim's favour only when
    the gradient is shown to be right); unvalidated points are dropped. Fewer than
    :data:`~thesis.claims.stats.MIN_SEEDS` validated points at a horizon, or no finite
    budget, make that horizon inconclusive."""
    da = variable(results, GRADS, "rollouts_to_threshold",
                  dims=("seed", "group", "horizon", "estimator"))
    da = pick(da, group="controller")
    other = [str(e) for e in da["estimator"].values if str(e) != estimator]
    budget = float(results[GRADS].attrs.get("rollouts_max", np.nan))
    parts = {}
    for h in da["horizon"].values:
        at = da.sel({"horizon": h})
        n = pick(at, estimator=estimator).values.astype(float)
        reached = np.isfinite(n) & (n > 0)
        validated = reached.copy()
        for e in other:
            m = pick(at, estimator=e).values.astype(float)
            validated |= np.isfinite(m) & (m > 0)
        logn = np.where(reached, np.log10(np.where(reached, n, 1.0)),
                        np.where(validated, np.log10(budget) if budget > 0 else np.nan, np.nan))
        tag = f"h{int(h)}"
        extra = {f"reached_{tag}": int(reached.sum()), f"validated_{tag}": int(validated.sum()),
                 f"seeds_{tag}": int(n.size), "budget": budget}
        v = stats.decide_threshold(logn, bound=ORDERS, below=False,
                                   label=f"log10_rollouts_{tag}")
        if not (np.isfinite(budget) and budget > 0):
            v = stats.untestable(["no finite rollout budget (rollouts_max) to bound the "
                                  "counts that never reached the threshold"],
                                 v.measured, v.statistic)
        elif int(validated.sum()) < stats.MIN_SEEDS:
            v = Verdict("inconclusive", v.measured, v.statistic,
                        f"no positive control: at only {int(validated.sum())} of {n.size} "
                        f"probe points did any estimator reach the cosine threshold within "
                        f"{budget:g} rollouts, so a count at the budget cannot tell an "
                        "expensive estimator from a meaningless engine gradient (at least "
                        f"{stats.MIN_SEEDS} validated points are needed)")
        parts[f"horizon {int(h)} steps"] = Verdict(v.status, {**v.measured, **extra},
                                                   v.statistic, v.detail)
    return stats.combine(parts, statistic=(
        f"rule 6 per horizon on log10 of the {estimator} rollouts to the cosine threshold, "
        f"on the probe points where some estimator reached it (the engine's gradient "
        f"validated); the budget {budget:g} where {estimator} never did; all horizons must "
        "hold"))


def joint_optimisation_possible(results: Results) -> Verdict:
    """The sentence's own reading, feasibility ("both can be optimized simultaneously using
    gradient descent"), as existence (:func:`thesis.claims.stats.decide_exists`): a seed
    shows it when its joint run (controller and body updated together) ends faster than
    it started (``final_speed`` above the objective before the first update), its body
    moved from the built one (some ``final_morphology`` parameter differs from the first
    evaluation's), *and* it ends faster than its negative control, the same run along
    random directions of the gradient step's size (:func:`_random_direction`): getting
    faster with a moved body is what a random walk does too. Without the control the
    sentence is not testable (rule 11). The rate over seeds is reported beside the
    count."""
    speed = variable(results, ARMS, "speed", dims=("arm", "seed", "evaluation"))
    final = variable(results, ARMS, "final_speed", dims=("arm", "seed"))
    body = variable(results, ARMS, "morphology", dims=("arm", "seed", "evaluation", "param"))
    body_end = variable(results, ARMS, "final_morphology", dims=("arm", "seed", "param"))
    start = pick(speed, arm="joint").isel(evaluation=0).transpose("seed").values
    end = pick(final, arm="joint").transpose("seed").values
    b0 = pick(body, arm="joint").isel(evaluation=0).transpose("seed", "param").values
    b1 = pick(body_end, arm="joint").transpose("seed", "param").values
    ok = np.isfinite(start) & np.isfinite(end) & np.isfinite(b0).all(1) & np.isfinite(b1).all(1)
    moved = np.any(np.abs(b1 - b0) > 1e-6 * np.maximum(np.abs(b0), 1.0), axis=1)
    control = _random_direction(results)
    beats_control = np.ones(ok.shape, bool)
    if control is not None:
        ok &= np.isfinite(control)
        beats_control = end > control
    event = np.where(ok, (end > start) & moved & beats_control, np.nan)
    v = stats.decide_exists(event, label="joint_gd_improved_speed_and_changed_body")
    gains = np.where(ok, end - start, np.nan)
    measured = {**v.measured, "joint_start_speed_mean": _finite_mean(start),
                "joint_final_speed_mean": _finite_mean(end),
                "joint_speed_gain_mean": _finite_mean(gains),
                "seeds_body_moved": int((ok & moved).sum())}
    if control is not None:
        measured["random_direction_final_speed_mean"] = _finite_mean(control)
        return Verdict(v.status, measured, v.statistic + "; a seed counts only where the "
                       "joint run ends faster than its random-direction control of the "
                       "same step size", v.detail)
    if v.status == "reproduced":
        return stats.untestable(["the random-direction control of the same step size "
                                 "(random_direction_final_speed) was not run: a random walk "
                                 "of the parameters also ends faster with a moved body in "
                                 "most draws"], measured, v.statistic)
    return Verdict(v.status, measured, v.statistic, v.detail)


def _random_direction(results: Results) -> np.ndarray | None:
    """Per seed, the final speed [m/s] of the negative control: the joint arm updated along
    random directions with the gradient step's size (``random_direction_final_speed``,
    dims ``seed``), None where the result does not carry it."""
    if "random_direction_final_speed" not in results[ARMS].data_vars:
        return None
    return variable(results, ARMS, "random_direction_final_speed",
                    dims=("seed",)).transpose("seed").values


def _finite_mean(x) -> float:
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    return float(x.mean()) if x.size else float("nan")


def _spread(results: Results) -> Verdict:
    """The engine's gradient spread over perturbed starts grows at least
    :data:`SPREAD_GROWTH`-fold from the shortest to the longest horizon: rule 6 on the
    per-seed log10 growth [decades], a seed whose longest-horizon gradients were not finite
    scored :data:`EXPLODED` and passed as failed to rule 3b (its value that score)."""
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
    exploded = nonfinite & ~np.isfinite(ratio)
    ratio = np.where(exploded, EXPLODED, ratio)
    v = stats.decide_threshold(ratio, bound=np.log10(SPREAD_GROWTH), below=False,
                               label="log10_spread_growth", failed=exploded,
                               failure_bounds=(EXPLODED, EXPLODED))
    return Verdict(v.status, {**v.measured, "shortest_horizon": lo, "longest_horizon": hi,
                              "spread_shortest_mean": _finite_mean(s_lo),
                              "spread_longest_mean": _finite_mean(s_hi),
                              "seeds_nonfinite_longest": int(nonfinite.sum())},
                   v.statistic, v.detail)


CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="ch8.coopt_joint_optimisation_possible", chapter=8, section="§8.2",
        quote=_COOPT,
        summary="Feasibility, the sentence's form ('can be optimized'): in at least one seed "
                "the joint run (controller and body by gradient descent together) ends faster "
                "than it started and changed the body (existence, rule 10; the rate over "
                "seeds beside it).",
        requires=(ARMS,), reads=(f"{ARMS}:speed", f"{ARMS}:final_speed", f"{ARMS}:morphology",
                                 f"{ARMS}:final_morphology"),
        fn=joint_optimisation_possible,
    ),
    Claim(
        id="ch8.coopt_joint_beats_controller_only", chapter=8, section="§8.2",
        quote=_COOPT,
        summary="Beyond the sentence (this project's hypothesis; the sentence itself is "
                "ch8.coopt_joint_optimisation_possible): within the same budget of gradient "
                "evaluations, controller and body optimised together end faster than the "
                "controller alone on the built body "
                "(final speed from the nominal start, paired by seed, rule 4).",
        requires=(ARMS,), reads=(f"{ARMS}:final_speed",),
        fn=lambda r: _beats(r, "final_speed", "joint", "controller"),
    ),
    Claim(
        id="ch8.coopt_joint_beats_morphology_only", chapter=8, section="§8.2",
        quote=_COOPT,
        summary="Beyond the sentence (this project's hypothesis): within the same budget, "
                "controller and body together end faster than the "
                "body alone under the fixed initial controller (rule 4, paired by seed).",
        requires=(ARMS,), reads=(f"{ARMS}:final_speed",),
        fn=lambda r: _beats(r, "final_speed", "joint", "morphology"),
    ),
    Claim(
        id="ch8.coopt_joint_advantage_holds_from_perturbed_starts", chapter=8, section="§8.2",
        quote=_COOPT,
        summary="Beyond the sentence (this project's hypothesis): the jointly optimised gaits "
                "are faster than the controller-only ones also "
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
                "shortest (rule 6 on log10 of the ratio per probe point; a probe point "
                "whose gradients were not finite scores 10 decades and is a failed run for "
                "rule 3b).",
        requires=(GRADS,), reads=(f"{GRADS}:start_relative_spread",
                                  f"{GRADS}:start_nonfinite"),
        fn=_spread,
    ),
)
