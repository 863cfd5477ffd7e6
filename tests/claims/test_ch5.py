"""Chapter-5 claims decided on synthetic table5_3-5_6 and fig5_3 datasets: each claim once
with numbers that support it (reproduced) and once with numbers that contradict it."""

from __future__ import annotations

import sys

import numpy as np
import xarray as xr

from thesis import claims

SEL = ["useful", "reduced", "minimal", "leg", "agt", "imu", "joints", "touch"]
DIMS = [55, 21, 18, 12, 10, 9, 8, 4]
TERR = ["F", "S", "L", "C", "R"]
#: Seeds of the synthetic datasets. The comparisons decided by rules 4 and 6 "above" pass
#: each seed's classifier-failure flag (rule 3b): with no failure seen among n seeds the
#: failure rate may still be 1 - 0.0125^(1/n) (58 % at 5 seeds, 4 % at 100) and a failed
#: seed's difference as low as -100 points, so differences of 4-11 points decide only
#: from about 200 seeds; what 5 seeds give is in test_flagged_comparisons_need_seeds.
SEEDS = 200


def _noise(shape, seed=0, sd=0.5):
    return sd * np.random.default_rng(seed).standard_normal(shape)


#: The synthetic test sets' majority-class share [percent] (ours: 44-48 %).
MAJORITY = 30.0


def _baselines(ds, share=MAJORITY, dims=("seed", "split"), coords=("train", "test")):
    """``ds`` with the baselines every ch5 artifact carries (train sets are balanced)."""
    seeds = ds.sizes["seed"]
    vals = np.tile([20.0, share], (seeds, 1)) if coords == ("train", "test") else \
        np.full((seeds, len(coords)), share)
    ds["majority_share"] = (dims, vals + _noise(vals.shape, 9, 0.2), {"units": "percent"})
    ds["chance"] = ((), 20.0, {"units": "percent"})
    return ds


def table5_3(lr=None, rc=None, train_gain=15.0, share=MAJORITY):
    lr = np.array(lr if lr is not None else [72, 64, 67, 63, 66, 44, 48, 58], float)
    rc = np.array(rc if rc is not None else [76, 79, 81, 81, 82, 72, 74, 85], float)
    test = np.stack([lr, rc], -1)[None] + _noise((SEEDS, 8, 2), 1)
    acc = np.stack([test + train_gain, test], -1)
    ds = xr.Dataset(coords={"seed": np.arange(SEEDS), "selection": SEL, "method": ["lr", "rc"],
                            "split": ["train", "test"]})
    ds["accuracy"] = (("seed", "selection", "method", "split"), acc, {"units": "percent"})
    ds["dimensions"] = ("selection", DIMS, {"units": "1"})
    return _baselines(ds, share)


def table5_4(elm_touch=74.0, rc_touch=85.0, elm_min=80.0, rc_min=81.0, lr=(58.0, 67.0),
             share=MAJORITY):
    nodes = [25, 50, 100, 200]
    acc = np.zeros((SEEDS, 2, 2, 4, 2))
    for gi, (e, r) in enumerate(((elm_touch, rc_touch), (elm_min, rc_min))):
        acc[:, gi, 0, :, 1] = e
        acc[:, gi, 1, :, 1] = r
    acc[..., 1] += _noise(acc[..., 1].shape, 2)
    acc[..., 0] = acc[..., 1] + 10
    ds = xr.Dataset(coords={"seed": np.arange(SEEDS), "selection": ["touch", "minimal"],
                            "method": ["elm", "rc"], "nodes": nodes,
                            "split": ["train", "test"]})
    ds["accuracy"] = (("seed", "selection", "method", "nodes", "split"), acc,
                      {"units": "percent"})
    lr_acc = np.zeros((SEEDS, 2, 2))
    lr_acc[..., 1] = np.array(lr)[None] + _noise((SEEDS, 2), 3)
    lr_acc[..., 0] = lr_acc[..., 1] + 5
    ds["lr_accuracy"] = (("seed", "selection", "split"), lr_acc, {"units": "percent"})
    return _baselines(ds, share)


def table5_5(sfa2=35.0, rc_sfa=55.0, train_gain=20.0, share=MAJORITY):
    test = np.stack([np.full(8, sfa2), np.full(8, rc_sfa)], -1)[None] + _noise((SEEDS, 8, 2), 4)
    acc = np.stack([test + train_gain, test], -1)
    ds = xr.Dataset(coords={"seed": np.arange(SEEDS), "selection": SEL,
                            "method": ["sfa2", "rc_sfa"], "split": ["train", "test"]})
    ds["accuracy"] = (("seed", "selection", "method", "split"), acc, {"units": "percent"})
    return _baselines(ds, share)


def table5_6(elm_sfa=70.0, rc_sfa=70.5, share=35.0):
    acc = np.zeros((SEEDS, 2, 3, 2))
    acc[:, 0, :, 1], acc[:, 1, :, 1] = elm_sfa, rc_sfa
    acc[..., 1] += _noise(acc[..., 1].shape, 5)
    acc[..., 0] = acc[..., 1] + 12
    ds = xr.Dataset(coords={"seed": np.arange(SEEDS), "method": ["elm_sfa", "rc_sfa"],
                            "nodes": [50, 100, 200], "split": ["train", "test"]})
    ds["accuracy"] = (("seed", "method", "nodes", "split"), acc, {"units": "percent"})
    ds["sfa2_accuracy"] = (("seed", "split"), np.tile([60.0, 38.0], (SEEDS, 1)),
                           {"units": "percent"})
    return _baselines(ds, share)


def fig5_3(freq_recall=80.0, gait_recall=30.0):
    recall = np.full((SEEDS, 2, 5), np.nan)
    # F (2 training trials) fails, C (3) is not scored; S, L, R (5) are: baseline 100/3
    recall[:, 0, :] = [5.0, freq_recall, freq_recall - 5, 10.0, freq_recall + 2]
    recall[:, 1, :3] = [5.0, gait_recall, gait_recall + 5]
    recall += _noise(recall.shape, 6)
    ds = xr.Dataset(coords={"seed": np.arange(SEEDS), "test": ["frequency", "gait"],
                            "true": TERR})
    ds["recall"] = (("seed", "test", "true"), recall, {"units": "percent"})
    ds["train_trials"] = (("seed", "true"), np.tile([2, 5, 5, 3, 5], (SEEDS, 1)), {"units": "1"})
    ds.attrs["min_train_trials"] = 5
    return _baselines(ds, 50.0, dims=("seed", "test"), coords=("frequency", "gait"))


def check(claim_id, **results):
    return claims.get(claim_id).check({f"ch5/{k}": v for k, v in results.items()})


def test_thesis_like_numbers_reproduce_every_claim():
    r = dict(table5_3=table5_3(), table5_4=table5_4(), table5_5=table5_5(),
             table5_6=table5_6(), fig5_3=fig5_3())
    for cid in ("ch5.limited_sensor_selection_suffices", "ch5.nonlinearity_needed",
                "ch5.reservoir_beats_quadratic_expansion",
                "ch5.reservoir_better_with_few_sensors",
                "ch5.rc_and_elm_equal_with_enough_inputs",
                "ch5.recurrence_no_difference_unsupervised", "ch5.tactile_sensors_important",
                "ch5.generalises_to_frequencies_not_gaits", "ch5.rc_touch_best_overall",
                "ch5.lr_improves_with_dimensionality", "ch5.train_test_gap",
                "ch5.single_gait_unsupervised_better"):
        v = check(cid, **r)
        assert v.status == "reproduced", (cid, v.detail)
    v = claims.get("ch8.ch5_memory_important").check({f"ch5/{k}": d for k, d in r.items()})
    assert v.status == "reproduced"


def test_limited_selection_contradicted():
    t = table5_3(rc=[90, 79, 70, 81, 82, 72, 74, 85])
    assert check("ch5.limited_sensor_selection_suffices", table5_3=t).status == "not_reproduced"


def test_nonlinearity_contradicted_by_small_gap():
    v = check("ch5.nonlinearity_needed", table5_3=table5_3(), table5_4=table5_4(lr=(75, 77)))
    assert v.status != "reproduced"
    v = check("ch5.nonlinearity_needed", table5_3=table5_3(rc=[60] * 8), table5_4=table5_4())
    assert v.status == "not_reproduced"


def test_quadratic_claim_contradicted():
    v = check("ch5.reservoir_beats_quadratic_expansion", table5_5=table5_5(sfa2=50, rc_sfa=40))
    assert v.status == "not_reproduced"


def test_few_sensors_and_memory_contradicted():
    t = table5_4(elm_touch=86, rc_touch=80)
    assert check("ch5.reservoir_better_with_few_sensors", table5_4=t).status == "not_reproduced"
    v = claims.get("ch8.ch5_memory_important").check({"ch5/table5_4": t})
    assert v.status == "not_reproduced"


def test_equivalence_claims_contradicted():
    t = table5_4(elm_min=70, rc_min=81)
    assert check("ch5.rc_and_elm_equal_with_enough_inputs", table5_4=t).status == "not_reproduced"
    t6 = table5_6(elm_sfa=60, rc_sfa=72)
    assert check("ch5.recurrence_no_difference_unsupervised",
                 table5_6=t6).status == "not_reproduced"


def test_tactile_and_touch_best_contradicted():
    t = table5_3(lr=[72, 64, 67, 45, 40, 60, 62, 58], rc=[76, 79, 81, 70, 70, 80, 80, 75])
    assert check("ch5.tactile_sensors_important", table5_3=t).status == "not_reproduced"
    assert check("ch5.rc_touch_best_overall", table5_3=t).status == "not_reproduced"


def test_dimensionality_contradicted():
    t = table5_3(lr=[40, 45, 48, 50, 55, 58, 60, 70])
    assert check("ch5.lr_improves_with_dimensionality", table5_3=t).status == "not_reproduced"


def test_a_gap_of_one_point_is_no_gap():
    """"There is a gap between the performance on the train set and the test set": the
    thesis's gaps are 6.5-20 points; a 1-point difference is within what this chapter
    calls virtually the same (before, any train > test passed)."""
    v = check("ch5.train_test_gap", table5_3=table5_3(train_gain=1.0),
              table5_5=table5_5(train_gain=1.0))
    assert v.status == "not_reproduced", v.detail


def test_nonlinearity_needed_is_read_without_the_ten_point_figure():
    """§5.5's "linear regression performed badly ... the importance of adding
    non-linearities": ELM and RC beat LR (5-8 points here); §5.4.1.2's "over 10% more
    misclassifications" is not this sentence's (before, a gap below 10 points failed)."""
    v = check("ch5.nonlinearity_needed", table5_3=table5_3(),
              table5_4=table5_4(elm_touch=66.0, rc_touch=66.0, elm_min=72.0, rc_min=72.0))
    assert v.status == "reproduced", v.detail


def test_train_test_gap_contradicted():
    v = check("ch5.train_test_gap", table5_3=table5_3(train_gain=-5), table5_5=table5_5())
    assert v.status == "not_reproduced"


def test_generalisation_contradicted_and_needs_training_data():
    assert check("ch5.generalises_to_frequencies_not_gaits",
                 fig5_3=fig5_3(freq_recall=20, gait_recall=70)).status == "not_reproduced"
    f = fig5_3()
    f["train_trials"][:] = 1  # no terrain has enough training trials: nothing to score
    assert check("ch5.generalises_to_frequencies_not_gaits", fig5_3=f).status == "inconclusive"


def test_single_gait_contradicted():
    v = check("ch5.single_gait_unsupervised_better", table5_5=table5_5(rc_sfa=80),
              table5_6=table5_6())
    assert v.status == "not_reproduced"


def test_missing_datasets_are_not_run():
    assert check("ch5.train_test_gap", table5_3=table5_3()).status == "not_run"


def test_too_small_a_profile_is_inconclusive_whatever_the_numbers():
    r = dict(table5_3=table5_3(), table5_4=table5_4(), table5_5=table5_5(),
             table5_6=table5_6(), fig5_3=fig5_3())
    for ds in r.values():
        ds.attrs["cma_generations"] = 1
    r["fig5_3"].attrs["min_train_trials"] = 1
    for cid in ("ch5.limited_sensor_selection_suffices", "ch5.nonlinearity_needed",
                "ch5.reservoir_beats_quadratic_expansion", "ch5.train_test_gap",
                "ch5.generalises_to_frequencies_not_gaits",
                "ch5.single_gait_unsupervised_better"):
        v = check(cid, **r)
        assert v.status == "inconclusive", (cid, v.detail)
        assert "cannot test" in v.detail
    small = table5_4()
    small = small.sel(nodes=[25, 50])  # no 100-node layer (the smoke profile's case)
    for cid in ("ch5.reservoir_better_with_few_sensors",
                "ch5.rc_and_elm_equal_with_enough_inputs"):
        v = check(cid, table5_4=small)
        assert v.status == "inconclusive" and "100-node" in v.detail, (cid, v.detail)
    v = claims.get("ch8.ch5_memory_important").check({"ch5/table5_4": small})
    assert v.status == "inconclusive"


# ---------------------------------------------------------------- baselines
AT_BASELINE = 44.0  # every method scores the test set's majority-class share


def test_methods_at_the_majority_share_decide_nothing():
    """The issue's case: every method sits at the baseline, so "a limited selection
    suffices", "RC and ELM are equal", "recurrence makes no difference" and the train/test
    gap must not be reproduced however the methods compare."""
    flat = [AT_BASELINE] * 8
    r = dict(table5_3=table5_3(lr=flat, rc=flat, share=AT_BASELINE),
             table5_4=table5_4(AT_BASELINE, AT_BASELINE, AT_BASELINE, AT_BASELINE,
                               share=AT_BASELINE),
             table5_5=table5_5(AT_BASELINE, AT_BASELINE, share=AT_BASELINE),
             table5_6=table5_6(AT_BASELINE, AT_BASELINE, share=AT_BASELINE))
    for cid in ("ch5.limited_sensor_selection_suffices",
                "ch5.rc_and_elm_equal_with_enough_inputs",
                "ch5.recurrence_no_difference_unsupervised"):
        v = check(cid, **r)
        assert v.status == "inconclusive", (cid, v.detail)
        assert "majority-class share" in v.detail, (cid, v.detail)


def test_a_comparison_below_the_baseline_is_not_reproduced_but_reported():
    v = check("ch5.reservoir_better_with_few_sensors",
              table5_4=table5_4(elm_touch=30.0, rc_touch=40.0, share=AT_BASELINE))
    assert v.status == "inconclusive" and "rc do(es) not beat" in v.detail
    assert v.measured["rc_over_baseline.advantage_ci_high"] < 0
    assert v.measured["chance"] == 20.0
    # the same comparison above the baseline reproduces, the baseline in the detail
    v = check("ch5.reservoir_better_with_few_sensors", table5_4=table5_4())
    assert v.status == "reproduced" and "chance 20 %" in v.detail


def test_frequency_recall_against_a_constant_classifiers_mean_recall():
    ds = fig5_3()
    ds["train_trials"][:] = np.tile([2, 5, 3, 3, 3], (SEEDS, 1))  # S alone is scored
    v = check("ch5.generalises_to_frequencies_not_gaits", fig5_3=ds)
    assert v.status == "inconclusive"
    assert v.measured["frequencies_beat_gaits.baseline_mean"] == 100.0


def test_datasets_without_baselines_do_not_decide():
    v = check("ch5.rc_touch_best_overall", table5_3=table5_3().drop_vars("majority_share"))
    assert v.status == "not_run" and "majority_share" in v.detail
    assert all(any(r.endswith(":majority_share") for r in c.reads)
               for c in claims.CLAIMS if c.chapter == 5)


def test_majority_share_of_a_set():
    from thesis.ch5.experiments import majority_share
    from thesis.ch5.protocol import Segment

    terrain = np.array([0, 0, 1, 2])
    segs = [Segment(0, 0, 300), Segment(1, 0, 140), Segment(2, 0, 60), Segment(3, 0, 100)]
    assert majority_share(segs, terrain, 5) == 100.0 * 440 / 600
    assert np.isnan(majority_share([], terrain, 5))


def test_the_baseline_gate_holds_in_both_directions():
    """The issue's case: RC at 22 % and ELM at 26 %, both under the 33 % majority share: a
    comparison between methods that both fail to classify is inconclusive, not "not
    reproduced". When the favoured side does classify, "not reproduced" stands."""
    both_fail = table5_4(elm_touch=26.0, rc_touch=22.0, share=33.0)
    for cid in ("ch5.reservoir_better_with_few_sensors", "ch8.ch5_memory_important"):
        v = claims.get(cid).check({"ch5/table5_4": both_fail})
        assert v.status == "inconclusive" and "none of rc, elm beats" in v.detail, cid
    elm_works = table5_4(elm_touch=80.0, rc_touch=22.0, share=33.0)
    assert check("ch5.reservoir_better_with_few_sensors",
                 table5_4=elm_works).status == "not_reproduced"
    low = table5_5(sfa2=28.0, rc_sfa=24.0, share=33.0)
    assert check("ch5.reservoir_beats_quadratic_expansion",
                 table5_5=low).status == "inconclusive"


def test_train_test_gap_is_measured_against_the_majority_share():
    """Train far above the majority share and test near it is the largest gap, not an
    inconclusive one; a train accuracy that does not beat the train set's majority share
    decides nothing."""
    near = [MAJORITY] * 8
    big_gap = dict(table5_3=table5_3(lr=near, rc=near, train_gain=60.0),
                   table5_5=table5_5(sfa2=MAJORITY, rc_sfa=MAJORITY, train_gain=60.0))
    v = check("ch5.train_test_gap", **big_gap)
    assert v.status == "reproduced", v.detail
    untrained = dict(table5_3=table5_3(lr=[10.0] * 8, rc=[10.0] * 8, train_gain=5.0),
                     table5_5=table5_5(sfa2=10.0, rc_sfa=10.0, train_gain=5.0))
    assert check("ch5.train_test_gap", **untrained).status == "inconclusive"


def test_drastic_needs_a_margin_not_just_a_positive_difference():
    """"Drastic better performance" / "memory is important": RC 2 points above ELM on touch
    (well within the chapter's 5-point "virtually the same") is not drastic."""
    slight = table5_4(elm_touch=83.0, rc_touch=85.0)
    for cid in ("ch5.reservoir_better_with_few_sensors", "ch8.ch5_memory_important"):
        v = claims.get(cid).check({"ch5/table5_4": slight})
        assert v.status == "not_reproduced", (cid, v.detail)
        assert v.measured["bound"] == 5.0


def test_generalisation_to_gaits_must_be_poor():
    """"Not very effective at generalizing to unseen gaits" cannot hold at 80 % gait recall
    (two terrains scored on gaits: a constant classifier has 50 %, half-way to 100 % is
    75 %), even when the frequency recall is higher still."""
    v = check("ch5.generalises_to_frequencies_not_gaits",
              fig5_3=fig5_3(freq_recall=95.0, gait_recall=80.0))
    assert v.status == "not_reproduced", v.detail
    np.testing.assert_allclose(v.measured["gaits_not_very_effective.halfway_mean"], 75.0)


def _touch_draw(rng, seeds: int, fail_rate: float, flag: bool) -> dict:
    """Tab. 5.4 with RC - ELM on touch at +8 points on seeds whose RC works and -7 where
    it failed (``fail_rate`` of seeds: its train accuracy at the train set's majority
    share, 20 %): the issue's second mode, mean 5 points at a rate of 1/5. ``flag``
    False records no train majority share (no failure indicator)."""
    ds = table5_4(elm_touch=74.0, rc_touch=82.0)
    failed = rng.random(seeds) < fail_rate
    rc_test = ds["accuracy"].loc[{"selection": "touch", "method": "rc", "split": "test"}]
    elm_test = ds["accuracy"].loc[{"selection": "touch", "method": "elm", "split": "test"}]
    rc_test = elm_test + np.where(failed, -7.0, 8.0)[:, None] \
        + 0.5 * rng.standard_normal(rc_test.shape)
    ds["accuracy"].loc[{"selection": "touch", "method": "rc", "split": "test"}] = rc_test
    ds["accuracy"].loc[{"selection": "touch", "method": "rc", "split": "train"}] = np.where(
        failed[:, None], 20.0, rc_test + 10.0)
    if not flag:
        ds["majority_share"].loc[{"split": "train"}] = np.nan
    return {"table5_4": ds}


def test_flagged_comparisons_need_seeds(monkeypatch):
    """At 5 seeds, thesis-like numbers with no classifier failure seen leave the
    comparisons of rules 4 and 6 "above" inconclusive (rule 3b: up to 58 % of seeds may
    still fail unseen); the rule-5 comparisons, which hold their level under a second
    mode, still decide. Without a train majority share (no indicator) the flagged claim
    is decided as before."""
    monkeypatch.setattr(sys.modules[__name__], "SEEDS", 5)
    r = dict(table5_3=table5_3(), table5_4=table5_4(), table5_5=table5_5(),
             table5_6=table5_6(), fig5_3=fig5_3())
    for cid in ("ch5.reservoir_better_with_few_sensors", "ch5.nonlinearity_needed",
                "ch5.limited_sensor_selection_suffices", "ch5.tactile_sensors_important"):
        v = check(cid, **r)
        assert v.status == "inconclusive" and "rule 3b" in v.statistic, cid
    assert check("ch5.rc_and_elm_equal_with_enough_inputs", **r).status == "reproduced"
    plain = _touch_draw(np.random.default_rng(0), 5, 0.0, flag=False)
    assert check("ch5.reservoir_better_with_few_sensors", **plain).status == "reproduced"


def test_a_classifier_failure_mode_is_flagged(monkeypatch):
    """The issue's probe through the claim's own check: 20 % of 5 seeds with RC at a
    second mode (RC - ELM = -7 points, the rest +8; the mean on the 5-point bound of
    "drastic"). Without the indicator "RC drastically better" is reproduced in about a
    third of draws (nominal 2.5 %); with each seed's flag (RC's train accuracy not above
    the train set's majority share) in none."""
    monkeypatch.setattr(sys.modules[__name__], "SEEDS", 5)
    rng = np.random.default_rng(11)
    reps = 120
    rate = {flag: np.mean([check("ch5.reservoir_better_with_few_sensors",
                                 **_touch_draw(rng, 5, 0.2, flag)).status == "reproduced"
                           for _ in range(reps)]) for flag in (False, True)}
    assert rate[False] > 0.15, rate
    assert rate[True] <= 0.025, rate
