"""Thesis-shaped synthetic results at a chosen seed count, per claim: the finding at its
published size (the chapters' test fixtures, whose means are the thesis's numbers) and
the finding reversed. Used by ``test_decidability.py``."""

from __future__ import annotations

from . import test_ch2 as c2
from . import test_ch3 as c3
from . import test_ch6 as c6
from . import test_ch7 as c7

G = c2.GOOD
REVERSED_CH2 = {"bilinear": 0.078, "bilinear_no_skew": 0.078, "chirp_z": 0.078, "none": 0.030}


def _t32(n: int, changes: dict | None = None, **kw):
    ds = c3.table3_2(seeds=n, **kw)
    for (var, strategy), value in (changes or {}).items():
        ds[var].loc[{"strategy": strategy}] = value
    return {"ch3/table3_2": ds}


def _share(n: int, rate: float) -> int:
    return int(round(rate * n))


def _ch6(key: str, names, rates, n: int, **kw):
    """A chapter-6 sweep with each config's success in a share ``rates`` of ``n`` seeds
    (twins repeating each run)."""
    return {f"ch6/{key}": c6.sweep(names, c6.rows(*(_share(n, r) for r in rates), seeds=n),
                                  **kw)}


STAGES = c6.STAGES
HS = c6.HS


def _ch2(means, n, **kw):
    return {"ch2/table2_2": c2.table2_2(means, seeds=n, **kw)}


#: claim id -> (finding at its published size, reversed finding), each a function of the
#: number of seeds returning the results the claim reads.
CASES = {
    "ch2.spatial_transformers_beat_plain": (lambda n: _ch2(G, n),
                                            lambda n: _ch2(REVERSED_CH2, n)),
    "ch2.recurrent_beats_feedforward": (lambda n: _ch2(G, n, rnn_gain=0.005),
                                        lambda n: _ch2(G, n, rnn_gain=-0.005)),
    "ch2.chirpz_similar_to_bilinear_no_skew": (lambda n: _ch2(G, n),
                                               lambda n: _ch2({**G, "chirp_z": 0.06}, n)),
    "ch2.chirpz_reaches_1_8_percent": (lambda n: _ch2({**G, "chirp_z": 0.018}, n),
                                       lambda n: _ch2({**G, "chirp_z": 0.037}, n)),
    "ch3.half_ellipse_beats_sine_at_high_speed": (
        lambda n: {"ch3/fig3_4": c3.fig3_4(seeds=n)},
        lambda n: {"ch3/fig3_4": c3.fig3_4(seeds=n, sine_knee=10.0, ellipse_gain=0.1)}),
    "ch3.spline_fastest": (lambda n: {"ch3/fig3_4": c3.fig3_4(seeds=n)},
                           lambda n: {"ch3/fig3_4": c3.fig3_4(seeds=n, ellipse_gain=0.3)}),
    "ch3.half_ellipse_most_robust": (
        lambda n: {"ch3/robustness": c3.robustness([0.2, 0.9, 0.6], seeds=n)},
        lambda n: {"ch3/robustness": c3.robustness([0.9, 0.3, 0.6], seeds=n)}),
    "ch3.scapulae_needed_for_fast_turning": (lambda n: _t32(n),
                                             lambda n: _t32(n, scap_speed=0.03)),
    "ch3.scapulae_maintain_speed": (lambda n: _t32(n), lambda n: _t32(n, scap_speed=0.03)),
    "ch3.turning_without_scapulae_possible": (
        lambda n: _t32(n), lambda n: _t32(n, {("stable", "step_size"): 0.0})),
    # chapter 6 at the thesis's finding: the trot controller works (every seed), phase 1
    # alone fails, a two-period stage works, linear feedback fails; reversed: the opposite
    "ch6.trot_h50_b5_stable": (lambda n: _ch6("trot", ["h50_b5"], [1.0], n),
                               lambda n: _ch6("trot", ["h50_b5"], [0.0], n)),
    "ch6.phase1_only_fails": (
        lambda n: _ch6("trot", ["h50_b5", "h50_b5_phase1_only"], [1.0, 0.0], n,
                       role=["base", "phase1_only"]),
        lambda n: _ch6("trot", ["h50_b5", "h50_b5_phase1_only"], [1.0, 1.0], n,
                       role=["base", "phase1_only"])),
    "ch6.learns_in_a_couple_of_strides": (
        lambda n: _ch6("minimal_training", [f"stage{x:g}s" for x in STAGES],
                       [0.0, 1.0, 1.0, 1.0, 1.0], n, hidden=[250] * 5, buffer=[0] * 5,
                       stage=STAGES),
        lambda n: _ch6("minimal_training", [f"stage{x:g}s" for x in STAGES],
                       [0.0, 0.0, 1.0, 1.0, 1.0], n, hidden=[250] * 5, buffer=[0] * 5,
                       stage=STAGES)),
    "ch6.linear_feedback_insufficient": (
        lambda n: {**_ch6("linear_feedback", ["linear"], [0.0], n, hidden=[0], buffer=[0]),
                   **_ch6("trot", ["h50_b5"], [1.0], n)},
        lambda n: {**_ch6("linear_feedback", ["linear"], [1.0], n, hidden=[0], buffer=[0]),
                   **_ch6("trot", ["h50_b5"], [1.0], n)}),
    "ch6.memoryless_feedback_trots": (
        lambda n: _ch6("minimal_hidden", [f"h{h}_b0" for h in HS],
                       [0, 0, 0.2, 0.8, 1, 1, 1], n, hidden=HS, buffer=[0] * 7),
        lambda n: _ch6("minimal_hidden", [f"h{h}_b0" for h in HS], [0] * 7, n, hidden=HS,
                       buffer=[0] * 7)),
    "ch7.arm_fixed_point_learned_quickly": (
        lambda n: {"ch7/arm_fixed": c7.curve("evaluation", 300, final=0.002, start=0.5,
                                             seeds=n, **c7.ARM1_THESIS)},
        lambda n: {"ch7/arm_fixed": c7.curve("evaluation", 400, final=0.05, start=0.5,
                                             seeds=n, **c7.ARM1_THESIS)}),
    "ch7.scales_to_millions_of_parameters": (
        lambda n: {"ch7/arm_random": c7.curve("update", 3000, final=0.01, start=0.5,
                                              tau=400.0, seeds=n, **c7.ARM2_THESIS)},
        lambda n: {"ch7/arm_random": c7.curve("update", 6000, final=0.2, start=0.5,
                                              tau=400.0, seeds=n, **c7.ARM2_THESIS)}),
}
CASES["ch8.ch6_stable_trot_in_few_periods_without_memory"] = CASES[
    "ch6.learns_in_a_couple_of_strides"]


def _pend(n: int, found: bool):
    held = [40] * n if found else [None] * n
    up = [58.0] * n if found else [0.0] * n
    to_up = [2.0] * n if found else [float("nan")] * n
    return {"ch7/pendulum_pixels": c7._pendulum(held, up, to_up)}


CASES["ch8.ch7_pendulum_from_pixels"] = (lambda n: _pend(n, True), lambda n: _pend(n, False))
CASES["ch7.vision_control_learned_through_camera"] = CASES["ch8.ch7_pendulum_from_pixels"]
CASES["ch8.ch7_gait_in_500_evaluations"] = (
    lambda n: {"ch7/quadruped_gait": c7.gait(0.75, upright=[1.0] * n, seeds=n)},
    lambda n: {"ch7/quadruped_gait": c7.gait(0.3, upright=[1.0] * n, seeds=n)})
