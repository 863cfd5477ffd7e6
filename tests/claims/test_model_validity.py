"""Claims decided on an unvalidated model (thesis.claims.model_validity): the flag is
attached exactly to the claims resting on chapters 3, 4 and 6 when a validation target
failed, lists the failed targets, and is shown beside the verdict in the report."""

from __future__ import annotations

import numpy as np
import xarray as xr

from thesis.claims import CLAIMS, evaluate, model_validity as MV
from thesis.report import verdicts as V


def _validation(passed):
    targets = ["V1", "V2", "V3", "V4", "V5", "V6"]
    return xr.Dataset(dict(
        target_passed=(("target",), np.array(passed, np.int8)),
        target_text=(("target",), np.array([f"{t} numbers" for t in targets]))),
        coords=dict(target=targets))


def test_flag_only_on_oncilla_claims_and_only_when_a_target_failed():
    failed = {"model/validation": _validation([1, 0, 0, 1, 1, 1])}
    f = MV.flag(["ch3/table3_1"], failed)["model_validation"]
    assert f["unvalidated"] and [x["target"] for x in f["failed_targets"]] == ["V2", "V3"]
    assert f["failed_targets"][0]["text"] == "V2 numbers"
    assert MV.flag(["ch7/ball"], failed) == {}
    assert MV.flag(["ch6/trot", "ch7/ball"], failed)["model_validation"]["unvalidated"]
    assert MV.flag(["ch4/flat"], {}) == {}  # validation not run: no flag
    assert MV.flag(["ch4/flat"], failed, "not_run") == {}  # nothing decided: no flag
    ok = {"model/validation": _validation([1] * 6)}
    assert MV.flag(["ch4/flat"], ok) == {"model_validation": {"unvalidated": False,
                                                              "failed_targets": []}}


def _convergence(verdicts):
    refined = ["dt/2", "2x sweeps"]
    return xr.Dataset(dict(
        verdict=(("refined",), np.array(verdicts)),
        fall_rate_change=(("refined",), np.array([0.15, 0.02])),
        max_speed_change=(("refined",), np.array([0.5, 0.2]))), coords=dict(refined=refined))


def test_a_model_not_converged_in_dt_is_unvalidated_an_inconclusive_table_is_named():
    ok = {"model/validation": _validation([1] * 6)}
    bad = {**ok, "model/convergence": _convergence(["not converged", "inconclusive"])}
    f = MV.flag(["ch3/table3_1"], bad)["model_validation"]
    assert f["unvalidated"] and [x["target"] for x in f["failed_targets"]] == ["convergence"]
    assert "dt/2: not converged (fall rate 15.0 points" in f["failed_targets"][0]["text"]
    assert "failed: convergence;" in MV.text({"model_validation": f})
    unsure = {**ok, "model/convergence": _convergence(["inconclusive", "converged"])}
    f = MV.flag(["ch3/table3_1"], unsure)["model_validation"]
    assert not f["unvalidated"] and f["failed_targets"] == []
    assert f["convergence_inconclusive"]["verdict"] == "inconclusive"
    assert MV.text({"model_validation": f}).startswith(MV.INCONCLUSIVE_CONVERGENCE)
    assert "thesis validate oncilla" in MV.text({"model_validation": f})
    assert "convergence_inconclusive" not in MV.flag(["ch3/table3_1"], ok)["model_validation"]
    old_table = {**ok, "model/convergence": xr.Dataset(dict(converged=(("refined",), [0, 0])))}
    assert not MV.flag(["ch3/table3_1"], old_table)["model_validation"]["unvalidated"]
    only_conv = {"model/convergence": _convergence(["not converged", "converged"])}
    assert MV.flag(["ch6/trot"], only_conv)["model_validation"]["unvalidated"]


def test_chapter5_claims_are_flagged_by_the_puppy_s_convergence_table():
    bad = {"model/puppy_convergence": _convergence(["not converged", "not converged"]),
           "model/validation": _validation([0] * 6)}
    f = MV.flag(["ch5/table5_3"], bad)["model_validation"]
    assert f["unvalidated"] and [x["target"] for x in f["failed_targets"]] \
        == ["Puppy II convergence"]  # the Oncilla's targets are not chapter 5's
    assert "thesis validate puppy" in MV.text({"model_validation": f})
    assert "convergence_inconclusive" not in f
    unsure = {"model/puppy_convergence": _convergence(["inconclusive", "converged"])}
    f = MV.flag(["ch5/table5_3"], unsure)["model_validation"]
    assert not f["unvalidated"] and f["failed_targets"] == []
    assert f["convergence_inconclusive"]["target"] == "Puppy II convergence"
    assert "thesis validate puppy" in MV.text({"model_validation": f})
    converged = {"model/puppy_convergence": _convergence(["converged", "converged"])}
    assert MV.flag(["ch5/table5_3"], converged) == {"model_validation": {
        "unvalidated": False, "failed_targets": []}}
    assert MV.text(MV.flag(["ch5/table5_3"], converged)) == ""
    assert MV.flag(["ch5/table5_3"], {}) == {}
    assert MV.flag(["ch7/ball"], bad) == {}


def _heldout(rc_passed, lda, within_passed, majority=45.0):
    return xr.Dataset(dict(
        pooled_passed=((), rc_passed), pooled_lda_accuracy=((), lda),
        pooled_majority_share=((), majority), within_passed=((), within_passed)),
        attrs=dict(test_a="Test A: FAIL", test_b="Test B: FAIL", selection="touch"))


def test_chapter5_claims_are_flagged_when_no_terrain_crosses_the_gaits():
    converged = {"model/puppy_convergence": _convergence(["converged", "converged"])}
    # neither the reservoir nor the linear discriminant beats the majority: the model's
    no_signal = {**converged, "model/puppy_heldout": _heldout(False, 40.0, True)}
    f = MV.flag(["ch5/table5_3"], no_signal)["model_validation"]
    assert f["unvalidated"]
    assert [x["target"] for x in f["failed_targets"]] == ["Puppy II terrains across gaits"]
    assert "40.0 % against the held-out majority share 45.0 %" in f["failed_targets"][0]["text"]
    assert "thesis bench puppy-heldout" in MV.text({"model_validation": f})
    assert "thesis validate oncilla" not in MV.text({"model_validation": f})
    # the discriminant finds it where the reservoir does not: the method's failure, no flag
    method = {**converged, "model/puppy_heldout": _heldout(False, 60.0, True)}
    assert not MV.flag(["ch5/table5_3"], method)["model_validation"]["unvalidated"]
    passed = {**converged, "model/puppy_heldout": _heldout(True, 40.0, True)}
    assert not MV.flag(["ch5/table5_3"], passed)["model_validation"]["unvalidated"]
    within = {"model/puppy_heldout": _heldout(True, 60.0, False)}  # without the table too
    f = MV.flag(["ch5/table5_3"], within)["model_validation"]
    assert [x["target"] for x in f["failed_targets"]] == ["Puppy II terrains within a gait"]
    both = {"model/puppy_convergence": _convergence(["not converged", "converged"]),
            "model/puppy_heldout": _heldout(False, 40.0, False)}
    f = MV.flag(["ch5/table5_3"], both)["model_validation"]
    assert len(f["failed_targets"]) == 3
    text = MV.text({"model_validation": f})
    assert "thesis validate puppy, thesis bench puppy-heldout)" in text
    assert MV.flag(["ch3/table3_1"], no_signal) == {}  # the Oncilla's claims: not read
    verdict = {"status": "inconclusive", "requires": ["ch5/table5_3"],
               **MV.flag(["ch5/table5_3"], no_signal)}
    from thesis.claims import kinds
    assert kinds.classify(verdict)["kind"] == "model failed validation"


def test_every_ch3_ch4_ch6_claim_is_flagged_and_shown_beside_its_verdict():
    results = {"model/validation": _validation([0, 1, 1, 1, 1, 1])}
    oncilla = [c for c in CLAIMS if MV.rests_on_oncilla(c.requires)]
    assert {c.chapter for c in oncilla} >= {3, 4, 6}
    others = [c for c in CLAIMS if not MV.rests_on_oncilla(c.requires)]
    out = evaluate(oncilla[0], results)
    assert out["status"] == "not_run" and "model_validation" not in out
    out = {**out, "status": "not_reproduced",
           **MV.flag(oncilla[0].requires, results, "not_reproduced")}
    assert out["model_validation"]["unvalidated"]
    assert "decided on an unvalidated model (failed: V1" in MV.text(out)
    assert "model_validation" not in evaluate(others[0], results)
    assert MV.UNVALIDATED in V.claims_html([out])
    assert any(MV.UNVALIDATED in line for line in V.summary_lines([out], out["chapter"]))
    plain = {**out, "model_validation": {"unvalidated": False, "failed_targets": []}}
    assert MV.UNVALIDATED not in V.claims_html([plain])


def _pebbles(passed):
    return xr.Dataset(dict(
        target_passed=(("target",), np.array([passed], np.int8)),
        target_text=(("target",), np.array(["V7 numbers"]))), coords=dict(target=["V7"]))


def test_the_pebble_target_flags_the_claims_on_the_pebble_runs_alone():
    ok = {"model/validation": _validation([1] * 6)}
    bad = {**ok, "model/pebbles": _pebbles(0)}
    for key in MV.PEBBLE_RESULTS:
        f = MV.flag([key], bad)["model_validation"]
        assert f["unvalidated"] and f["failed_targets"] == [{"target": "V7",
                                                             "text": "V7 numbers"}]
    assert not MV.flag(["ch4/fig4_5"], bad)["model_validation"]["unvalidated"]
    assert not MV.flag(["ch4/table4_4"], {**ok, "model/pebbles": _pebbles(1)})[
        "model_validation"]["unvalidated"]
    # the pebble check alone (no flat-ground validation) still flags a pebble claim
    only = MV.flag(["ch4/fig4_8"], {"model/pebbles": _pebbles(0)})["model_validation"]
    assert [x["target"] for x in only["failed_targets"]] == ["V7"]
    assert MV.flag(["ch4/fig4_5"], {"model/pebbles": _pebbles(0)}) == {}
    assert "failed: V7; thesis validate oncilla" in MV.text({"model_validation": only})
    # every chapter-4 claim on the pebble runs reads it, and no claim of another chapter
    # but §8.1's summaries of chapter 4 does
    on = [c for c in CLAIMS if MV.rests_on_pebbles(c.requires)]
    assert {c.id for c in on} >= {"ch4.transfer_not_significant_on_pebbles",
                                  "ch4.pebbles_head_start_lost"}
    assert all(c.id.startswith("ch4.") or c.chapter == 8 for c in on)
