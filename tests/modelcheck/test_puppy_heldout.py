"""puppy_heldout.py (thesis bench puppy-heldout): the decision logic of the held-out-gait
test on synthetic recordings, and its registration."""

import numpy as np

from thesis import config, registry
from thesis.ch5 import methods as M
from thesis.ch5.separability import start_params
from thesis.modelcheck import puppy_heldout as PH

N_TERRAINS, N_GAITS, PER_CELL, LENGTH, D = 3, 3, 2, 200, 4


def _synthetic(separable: bool, seed: int = 0):
    """Trials of 3 terrains x 3 gaits x 2 repeats on 4 channels: each gait its own
    oscillation; a separable set adds a terrain offset that is the same in every gait, a
    signal-free one adds nothing (its labels say nothing about the signals)."""
    rng = np.random.default_rng(seed)
    label, gait, freq, sig = [], [], [], []
    t = np.arange(LENGTH) / 50.0
    for g in range(N_GAITS):
        for r in range(N_TERRAINS):
            for _ in range(PER_CELL):
                x = np.sin(2 * np.pi * (g + 1) * 0.5 * t)[:, None] * (1 + g) * np.ones(D)
                x = x + rng.normal(0.0, 1.0, (LENGTH, D))
                if separable:
                    x = x + 3.0 * (r - 1)
                sig.append(x)
                label.append(r)
                gait.append(g)
                freq.append(1.0)
    signals = np.concatenate(sig)
    signals = (signals - signals.mean(0)) / signals.std(0)
    n = len(sig)
    offset = np.arange(n) * LENGTH
    return (signals, offset, np.full(n, LENGTH), np.array(label), np.array(gait),
            np.array(freq), np.arange(n))


def _run(separable: bool):
    signals, offset, length, label, gait, freq, trials = _synthetic(separable)
    ranges = {k: tuple(v) for k, v in config.load_config("smoke")["ch5"]["search"].items()
              if k != "sigma0"}
    params = start_params("rc", ranges)
    draws = [M.draw(np.random.default_rng(s), 10, D) for s in range(3)]
    a = PH.heldout_gait(signals, offset, length, label, gait, trials, np.arange(D), 50,
                        params, draws, N_TERRAINS)
    diff = 100.0 * (a["rc"].sum(1) - a["majority"].sum()) / a["n"].sum()
    b = PH.within_cell(signals, offset, length, label, gait, freq, trials, np.arange(D), 50,
                       params, draws, N_TERRAINS)
    return a, b, PH.decide(diff, 15.0, 5.0, 0.95)


def test_a_gait_independent_terrain_passes_and_a_signal_free_one_fails():
    a, b, verdict = _run(separable=True)
    assert verdict["passed"] and verdict["low"] > 15.0
    assert a["lda"].sum() / a["n"].sum() > 0.95  # the diagnostic sees it too
    assert b["rc"].sum(1).min() / b["n"].sum() > 0.7
    a, b, verdict = _run(separable=False)
    assert not verdict["passed"] and verdict["mean"] < 15.0
    assert a["lda"].sum() / a["n"].sum() < 0.6
    # the majority share of a balanced held-out set is one class's share
    assert np.all(a["majority"] * N_TERRAINS == a["n"])


def test_decide_needs_both_the_mean_and_the_lower_bound():
    assert PH.decide([20.0, 21.0, 19.0, 20.5, 19.5], 15.0, 5.0, 0.95)["passed"]
    # mean 16 but spread so wide that the lower bound falls below 5 points
    wide = PH.decide([0.0, 40.0, 2.0, 36.0, 2.0], 15.0, 5.0, 0.95)
    assert wide["mean"] >= 15.0 and wide["low"] <= 5.0 and not wide["passed"]
    assert not PH.decide([14.0, 14.5, 14.2, 14.1, 14.3], 15.0, 5.0, 0.95)["passed"]
    m, lo, hi = PH.t_interval([1.0, 2.0, 3.0], 0.95)
    assert m == 2.0 and np.isclose(hi - m, 4.302653 * 1.0 / np.sqrt(3.0), rtol=1e-6)


def test_puppy_heldout_is_registered_with_its_config():
    assert registry.BENCHMARKS["puppy-heldout"] == "model/puppy_heldout"
    assert registry.resolve("model/puppy_heldout") is PH.puppy_heldout
    cfg = config.load_config("default")["physics"]["puppy_heldout"]
    assert cfg["terrains"] == ["F", "S", "L"] and len(cfg["seeds"]) == 5
    assert (cfg["min_difference"], cfg["min_lower_bound"], cfg["min_within_cell"]) == (
        15.0, 5.0, 80.0)


def test_report_table_reads_the_verdicts_from_the_dataset():
    import xarray as xr

    from thesis.report import puppy_heldout as R
    from thesis.report.model import NOT_RUN

    assert R.table({}).rows == [[NOT_RUN] * len(R.COLUMNS)]
    g, s = ("bound_right", "random"), (0, 1)
    ds = xr.Dataset(
        dict(accuracy=(("seed", "heldout"), [[60.0, 40.0], [62.0, 38.0]]),
             majority_share=(("heldout",), [40.0, 35.0]),
             difference_mean=(("heldout",), [21.0, 4.0]),
             difference_low=(("heldout",), [8.0, -20.0]),
             difference_high=(("heldout",), [34.0, 28.0]),
             passed=(("heldout",), [True, False]), lda_accuracy=(("heldout",), [70.0, 30.0]),
             test_steps=(("heldout",), [300, 100]),
             pooled_accuracy=(("seed",), [55.0, 56.0]), pooled_majority_share=((), 38.75),
             pooled_difference_mean=((), 16.75), pooled_difference_low=((), 10.0),
             pooled_difference_high=((), 23.0), pooled_passed=((), True),
             pooled_lda_accuracy=((), 60.0),
             cell_accuracy=(("seed", "cell"), [[90.0, 70.0], [92.0, 72.0]])),
        coords=dict(seed=list(s), heldout=list(g), cell=["a", "b"]),
        attrs=dict(terrains="FSL", selection="touch", nodes=20, params="{}",
                   test_a="Test A", test_b="Test B"))
    t = R.table({R.KEY: ds})
    assert [r[0] for r in t.rows] == ["bound_right", "random", "pooled (decides)"]
    assert [r[5] for r in t.rows] == ["pass", "fail", "PASS"]
    assert t.rows[0][2] == "61.0" and t.rows[2][1] == "400" and "71.0-91.0 %" in t.note
