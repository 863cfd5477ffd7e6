"""Claims decided on an unvalidated model (issue 53 item 5).

Chapters 3, 4 and 6 are decided on the simulated Oncilla. Where the profile's results hold
the model's validation (``model/validation``, ``thesis validate oncilla``,
:mod:`thesis.modelcheck.validation`) and some of its targets V1-V6 failed, every claim
whose required results come from those chapters (``requires`` entries under ``ch3/``,
``ch4/`` or ``ch6/``; §8.1's summaries of them included) carries a flag beside its verdict:
the verdict was decided on an unvalidated model, with the failed targets and their numbers.
The verdict itself is not changed: the flag says what it may describe (the simulator, not
the thesis's robot). All of these claims rest on the model's speeds and falls (the
quantities V1-V5 check) and on its gait families' ranking (V5), so every failed target is
listed for each of them.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

#: Result key of the Oncilla's validation.
VALIDATION_KEY = "model/validation"
#: Result prefixes of the chapters decided on the simulated Oncilla.
ONCILLA_RESULTS = ("ch3/", "ch4/", "ch6/")
#: Reading shown beside a flagged verdict.
UNVALIDATED = "decided on an unvalidated model"


def failed_targets(results: Mapping) -> list[dict] | None:
    """The failed validation targets of ``results[VALIDATION_KEY]`` as
    ``[{"target": "V2", "text": <its numbers>}, ...]``; None when the validation was not
    run (then nothing is flagged)."""
    ds = results.get(VALIDATION_KEY)
    if ds is None:
        return None
    return [{"target": str(t), "text": str(txt)}
            for t, p, txt in zip(ds["target"].values, ds["target_passed"].values,
                                 ds["target_text"].values) if not int(p)]


def rests_on_oncilla(requires: Iterable[str]) -> bool:
    """True if any required result comes from chapter 3, 4 or 6."""
    return any(str(r).startswith(ONCILLA_RESULTS) for r in requires)


def flag(requires: Iterable[str], results: Mapping, status: str = "") -> dict:
    """The fields a claim's verdict gains (empty when none): ``model_validation`` with
    ``unvalidated`` (True), ``reading`` (:data:`UNVALIDATED`) and ``failed_targets``,
    where the claim rests on the Oncilla and a validation target failed; or
    ``unvalidated`` False with no failed target where the validation passed. A claim
    that was not decided (``status`` ``"not_run"``) gains nothing."""
    if status == "not_run" or not rests_on_oncilla(requires):
        return {}
    failed = failed_targets(results)
    if failed is None:
        return {}
    if not failed:
        return {"model_validation": {"unvalidated": False, "failed_targets": []}}
    return {"model_validation": {"unvalidated": True, "reading": UNVALIDATED,
                                 "failed_targets": failed}}


def text(claim: Mapping) -> str:
    """The flag in words for the report ("" when the claim carries none or passed)."""
    mv = claim.get("model_validation") or {}
    if not mv.get("unvalidated"):
        return ""
    names = ", ".join(f["target"] for f in mv.get("failed_targets", []))
    return f"{UNVALIDATED} (failed: {names}; thesis validate oncilla)"
