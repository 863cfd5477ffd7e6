"""Claims of chapter 3 (trotting and turning strategies on the Oncilla).

Dataset contracts (``results/<profile>/ch3/<artifact>.nc``; a ``seed`` dim is expected,
any other extra dim is averaged):

- ``fig3_4``: dims ``seed``, ``gait`` (``"sine"``, ``"half_ellipse"``, ``"spline"``),
  ``frequency`` [Hz]; variable ``speed`` [m/s], the robot's forward speed.
- ``robustness``: dims ``seed``, ``gait`` (same names), any perturbation dims; variable
  ``fraction_walking`` [1], the fraction of perturbed parameter sets that still walk.
- ``table3_2``: dims ``seed``, ``strategy`` (``"step_size"``, ``"step_speed"``,
  ``"step_size_constant_speed"``, ``"torque"``, ``"scapulae"``: §3.3.2.1 to §3.3.2.5);
  variables ``speed`` [m/s], ``angular_speed`` [degree/s] (signed, positive in the
  commanded turning direction), ``turning_radius`` [m],
  ``stable`` [1] (1 if the strategy gives a stable turning gait, 0 otherwise).

Note: the chapter abstract calls the half-ellipse gait the fastest, while §3.3.1.3 reports
the spline gait faster (0.41 against 0.27 m/s); both statements are checked separately.
"""

from __future__ import annotations

import numpy as np

from thesis import paper
from thesis.claims import stats
from thesis.claims.types import Claim, LayoutError, Results, Verdict, pick, variable

FIG = "ch3/fig3_4"
ROB = "ch3/robustness"
TURN = "ch3/table3_2"
GAITS = ["sine", "half_ellipse", "spline"]
WORKING = ["step_size", "scapulae"]
FAILING = ["step_speed", "step_size_constant_speed", "torque"]
KNEE_KEY = "fig3_4/gait=sine/linear_up_to_frequency"


def _speed(results: Results):
    return variable(results, FIG, "speed", dims=("gait", "frequency"))


def _high_band_speed(results: Results, gaits: list[str]):
    """Per-seed mean speed over frequencies above the sine gait's knee (1 Hz): (seed, gait)."""
    knee = paper.get(KNEE_KEY).value
    sp = pick(_speed(results), gait=gaits)
    high = sp.where(sp["frequency"] > knee, drop=True)
    if high.sizes.get("frequency", 0) == 0:
        raise LayoutError(f"{FIG} has no frequency above {knee} Hz")
    return stats.per_seed(high, keep=("gait",))


def _max_speed(results: Results, gaits: list[str]):
    """Per-seed maximum speed over frequency: dims (seed, gait)."""
    sp = stats.per_seed(pick(_speed(results), gait=gaits), keep=("gait", "frequency"))
    return sp.max("frequency", skipna=True)


def _beats_each(per, winner: str, losers: list[str], higher_is_better: bool = True) -> Verdict:
    return stats.combine({
        f"{winner}_vs_{other}": stats.decide_beats(
            per.sel(gait=winner).values, per.sel(gait=other).values,
            higher_is_better=higher_is_better, label_a=winner, label_b=other)
        for other in losers})


def ellipse_beats_sine_high_speed(results: Results) -> Verdict:
    """Half-ellipse walks faster than sine above the sine gait's knee frequency."""
    return _beats_each(_high_band_speed(results, ["half_ellipse", "sine"]), "half_ellipse",
                       ["sine"])


def trajectories_beat_sine_high_speed(results: Results) -> Verdict:
    """Both foot-trajectory gaits (half ellipse, spline) beat sine above the knee frequency."""
    per = _high_band_speed(results, GAITS)
    return stats.combine({
        f"{g}_vs_sine": stats.decide_beats(per.sel(gait=g).values, per.sel(gait="sine").values,
                                           higher_is_better=True, label_a=g, label_b="sine")
        for g in ("half_ellipse", "spline")})


def sine_flattens(results: Results) -> Verdict:
    """The sine gait's speed-frequency slope is smaller above the knee than below it."""
    knee = paper.get(KNEE_KEY).value
    sp = stats.per_seed(pick(_speed(results), gait="sine"), keep=("frequency",))
    f = np.asarray(sp["frequency"].values, float)
    lo, hi = f <= knee, f >= knee
    if lo.sum() < 2 or hi.sum() < 2:
        return Verdict("inconclusive", {"n_below": float(lo.sum()), "n_above": float(hi.sum())},
                       "least-squares slopes below and above the knee",
                       f"need at least 2 frequencies on each side of {knee} Hz")

    def slopes(mask):
        out = []
        for row in sp.values:
            ok = mask & np.isfinite(row)
            out.append(np.polyfit(f[ok], row[ok], 1)[0] if ok.sum() >= 2 else np.nan)
        return np.array(out)

    return stats.decide_beats(slopes(lo), slopes(hi), higher_is_better=True,
                              label_a="slope_below_knee", label_b="slope_above_knee")


def ellipse_fastest(results: Results) -> Verdict:
    """Half ellipse reaches a higher maximum speed than sine and spline."""
    return _beats_each(_max_speed(results, GAITS), "half_ellipse", ["sine", "spline"])


def spline_fastest(results: Results) -> Verdict:
    """Spline reaches a higher maximum speed than sine and half ellipse."""
    return _beats_each(_max_speed(results, GAITS), "spline", ["sine", "half_ellipse"])


def _robust(results: Results):
    da = variable(results, ROB, "fraction_walking", dims=("gait",))
    return stats.per_seed(pick(da, gait=GAITS), keep=("gait",))


def ellipse_most_robust(results: Results) -> Verdict:
    """Half ellipse keeps walking under parameter perturbations more often than the others."""
    return _beats_each(_robust(results), "half_ellipse", ["sine", "spline"])


def sine_least_robust(results: Results) -> Verdict:
    """Sine keeps walking under perturbations less often than both trajectory gaits."""
    return _beats_each(_robust(results), "sine", ["half_ellipse", "spline"],
                       higher_is_better=False)


def _turn(results: Results, name: str):
    da = variable(results, TURN, name, dims=("strategy",))
    return stats.per_seed(pick(da, strategy=WORKING), keep=("strategy",))


def _scapulae_vs_step(results: Results, name: str, higher_is_better: bool = True) -> Verdict:
    per = _turn(results, name)
    return stats.decide_beats(per.sel(strategy="scapulae").values,
                              per.sel(strategy="step_size").values,
                              higher_is_better=higher_is_better,
                              label_a=f"scapulae_{name}", label_b=f"step_size_{name}")


def scapulae_turn_faster(results: Results) -> Verdict:
    """Scapulae turning has both higher speed and higher angular speed than step-size turning."""
    return stats.combine({"speed": _scapulae_vs_step(results, "speed"),
                          "angular_speed": _scapulae_vs_step(results, "angular_speed")})


def scapulae_keep_speed(results: Results) -> Verdict:
    """Scapulae turning keeps more forward speed than step-size turning."""
    return _scapulae_vs_step(results, "speed")


def scapulae_larger_radius(results: Results) -> Verdict:
    """Scapulae turning has a larger turning radius than step-size turning."""
    return _scapulae_vs_step(results, "turning_radius")


def turning_without_scapulae(results: Results) -> Verdict:
    """Step-size turning turns (signed angular speed > 0) but more slowly than scapulae."""
    step = _turn(results, "angular_speed").sel(strategy="step_size").values
    return stats.combine({
        "turns": stats.decide_threshold(step, bound=0.0, below=False,
                                        label="step_size_angular_speed"),
        "slower": _scapulae_vs_step(results, "angular_speed"),
    })


def other_strategies_fail(results: Results) -> Verdict:
    """The three failed strategies of §3.3.2.2-3.3.2.4 are less often stable than the two kept."""
    da = variable(results, TURN, "stable", dims=("strategy",))
    per = stats.per_seed(pick(da, strategy=WORKING + FAILING), keep=("strategy",))
    return stats.decide_beats(per.sel(strategy=WORKING).mean("strategy").values,
                              per.sel(strategy=FAILING).mean("strategy").values,
                              higher_is_better=True, label_a="stable_kept",
                              label_b="stable_failed")


def not_testable_in_simulation(results: Results) -> Verdict:
    """A claim about optimising on hardware without a model cannot be tested in simulation."""
    return Verdict("not_run", {}, "",
                   "not testable in simulation: the claim is that gaits can be optimised on the "
                   "hardware without a model, and this reproduction replaces the hardware by a "
                   "model")


_T32 = tuple(f"table3_2/strategy={s}/{v}" for s in WORKING
             for v in ("speed", "angular_speed", "turning_radius"))
_FIG = ("fig3_4/gait=spline/frequency=1.5/speed", "fig3_4/gait=sine/speed_compared",
        "fig3_4/gait=half_ellipse/speed_compared", "fig3_4/gait=spline/max_speed")
_SPEED = (f"{FIG}:speed",)

CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="ch3.half_ellipse_beats_sine_at_high_speed", chapter=3, section="§3.4",
        quote="The fact that the gait optimized with this trajectory could maintain its "
              "performance up to higher speeds, also points to favoring this approach over "
              "sine-based control signal methods.",
        summary="Half-ellipse mean speed over frequencies above 1 Hz (where the sine gait "
                "flattens) exceeds the sine gait's (rule 4).",
        paper_keys=(KNEE_KEY, "fig3_4/gait=half_ellipse/linear_up_to_frequency"),
        requires=(FIG,), reads=_SPEED, fn=ellipse_beats_sine_high_speed,
    ),
    Claim(
        id="ch3.sine_speed_flattens_above_1hz", chapter=3, section="§3.3.1.1",
        quote="This gait's velocity is proportional to the frequency up to about 1 Hz, at "
              "which point it flattens.",
        summary="Per-seed least-squares slope of sine-gait speed over frequency is larger at "
                "or below 1 Hz than at or above it (rule 4).",
        paper_keys=(KNEE_KEY,), requires=(FIG,), reads=_SPEED, fn=sine_flattens,
    ),
    Claim(
        id="ch3.half_ellipse_fastest", chapter=3, section="Ch. 3 abstract",
        quote="We found that using half ellipses as foot trajectories resulted in the fastest "
              "gaits",
        summary="Half-ellipse maximum speed over frequency exceeds both the sine and the spline "
                "gait's (rule 4 for each; both must hold).",
        paper_keys=_FIG, requires=(FIG,), reads=_SPEED, fn=ellipse_fastest,
    ),
    Claim(
        id="ch3.spline_fastest", chapter=3, section="§3.3.1.3",
        quote="it performs better than the gait based on sine-wave control signals (0.24 m/s) "
              "and the gait from our half ellipse approach (0.27 m/s).",
        summary="Spline maximum speed over frequency exceeds both the sine and the half-ellipse "
                "gait's (rule 4 for each; both must hold).",
        paper_keys=_FIG, requires=(FIG,), reads=_SPEED, fn=spline_fastest,
    ),
    Claim(
        id="ch3.half_ellipse_most_robust", chapter=3, section="Ch. 3 abstract",
        quote="as well as the highest robustness against parameter changes.",
        summary="Fraction of perturbed half-ellipse gaits still walking exceeds that of sine "
                "and of spline gaits (rule 4 for each).",
        requires=(ROB,), reads=(f"{ROB}:fraction_walking",), fn=ellipse_most_robust,
    ),
    Claim(
        id="ch3.sine_gaits_fragile", chapter=3, section="§3.3.1.1",
        quote="Furthermore, the obtained sine based gaits for the Oncilla were not robust "
              "against small parameter changes, which makes live optimisation very hard.",
        summary="Fraction of perturbed sine gaits still walking is below that of the half-"
                "ellipse and of the spline gaits (rule 4 for each).",
        requires=(ROB,), reads=(f"{ROB}:fraction_walking",), fn=sine_least_robust,
    ),
    Claim(
        id="ch3.scapulae_needed_for_fast_turning", chapter=3, section="§3.4",
        quote="Additionally, we found that scapulae are not necessary for turning, but that "
              "they are needed in order to turn with higher speeds.",
        summary="Turning with the scapulae has higher speed and higher angular speed than "
                "turning by step size (rule 4 for each).",
        paper_keys=_T32, requires=(TURN,),
        reads=(f"{TURN}:speed", f"{TURN}:angular_speed"), fn=scapulae_turn_faster,
    ),
    Claim(
        id="ch3.turning_without_scapulae_possible", chapter=3, section="§3.4",
        quote="Turning without scapulae is also possible, albeit more slowly.",
        summary="Step-size turning has a signed angular speed > 0 in the commanded direction "
                "(rule 6) and a lower one than scapulae turning (rule 4).",
        paper_keys=("table3_2/strategy=step_size/angular_speed",
                    "table3_2/strategy=scapulae/angular_speed"),
        requires=(TURN,), reads=(f"{TURN}:angular_speed",), fn=turning_without_scapulae,
    ),
    Claim(
        id="ch3.scapulae_maintain_speed", chapter=3, section="§3.4",
        quote="Using the scapulae, it is possible to maintain the robot's heading while turning "
              "and thus also its speed.",
        summary="Forward speed while turning with the scapulae exceeds that while turning by "
                "step size (rule 4).",
        paper_keys=("table3_2/strategy=step_size/speed", "table3_2/strategy=scapulae/speed",
                    "table3_2/forward_speed", "table3_2/strategy=scapulae/speed_loss"),
        requires=(TURN,), reads=(f"{TURN}:speed",), fn=scapulae_keep_speed,
    ),
    Claim(
        id="ch3.scapulae_larger_turning_radius", chapter=3, section="§3.3.3",
        quote="However, due to the faster motion, the turning radius is 36% higher compared to "
              "using a smaller step size for turning.",
        summary="Turning radius with the scapulae exceeds that with step-size turning (rule 4).",
        paper_keys=("table3_2/strategy=step_size/turning_radius",
                    "table3_2/strategy=scapulae/turning_radius",
                    "table3_2/strategy=scapulae/turning_radius_increase"),
        requires=(TURN,), reads=(f"{TURN}:turning_radius",), fn=scapulae_larger_radius,
    ),
    Claim(
        id="ch3.three_turning_strategies_fail", chapter=3, section="§3.3.2.2-§3.3.2.4",
        quote="This approach failed to work as well",
        summary="Mean 'stable' of step-speed, constant-speed step-size and torque turning is "
                "below that of step-size and scapulae turning (rule 4).",
        requires=(TURN,), reads=(f"{TURN}:stable",), fn=other_strategies_fail,
    ),
    Claim(
        id="ch3.model_free_optimisation_feasible", chapter=3, section="§3.4",
        quote="This research shows also that it is feasible to develop and optimize gaits "
              "without relying on models, using observations from nature.",
        summary="Not testable here: the reproduction optimises on a simulated model.",
        paper_keys=("sec3.3.1.2/optimisation_minutes", "sec3.3.1.3/optimisation_minutes"),
        fn=not_testable_in_simulation,
    ),
)
