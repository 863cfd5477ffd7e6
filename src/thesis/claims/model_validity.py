"""Claims decided on an unvalidated model (docs/architecture.md#engine-rules).

Chapters 3, 4 and 6 are decided on the simulated Oncilla. Where the profile's results hold
the model's validation (``model/validation``, ``thesis validate oncilla``,
:mod:`thesis.modelcheck.validation`) and some of its targets V1-V6 failed, every claim
whose required results come from those chapters (``requires`` entries under ``ch3/``,
``ch4/`` or ``ch6/``; §8.1's summaries of them included) carries a flag beside its verdict:
the verdict was decided on an unvalidated model, with the failed targets and their numbers.
The verdict itself is not changed: the flag says what it may describe (the simulator, not
the thesis's robot). All of these claims rest on the model's speeds and falls (the
quantities V1-V5 check) and on its gait families' ranking (V5), so every failed target is
listed for each of them. A claim whose required results come from chapter 4's pebble runs
(:data:`PEBBLE_RESULTS`) rests on the robot walking the pebble field as well: where V7
(Tab. 4.4's pebble optima on that field, ``model/pebbles``,
:mod:`thesis.modelcheck.pebbles`) failed, it is listed for those claims alone. A model
whose convergence table (``model/convergence``, :mod:`thesis.modelcheck.convergence_rule`)
decides "not converged" is not validated either: its speeds and falls change with the time
step or the solver sweeps, so the table's failed settings are listed beside the failed
targets (as "convergence"). An inconclusive table does not make a claim unvalidated, but it
does not validate it either: the record names it (``convergence_inconclusive``) and the
report says so beside the verdict. A table written before the three-valued rule (no
``verdict``) is not read. Chapter 5's claims rest on the simulated Puppy II's recordings
(``requires`` under ``ch5/``): where its convergence table (``model/puppy_convergence``,
:mod:`thesis.modelcheck.puppy_convergence`) decides "not converged", they carry the same
flag with that table as the failed target ("Puppy II convergence"), and an inconclusive one
is named as the Oncilla's is. They carry it too where the Puppy II's terrain check
(``model/puppy_heldout``, ``thesis bench puppy-heldout``,
:mod:`thesis.modelcheck.puppy_heldout`) shows that the recordings lack what the real
robot's had: the terrain carrying across gaits (§5.3-5.4), failed ("Puppy II terrains
across gaits") when the reservoir's held-out-gait test (Test A) fails *and* the linear
discriminant beside it does not beat the held-out majority share either, i.e. the
channels hold no terrain that crosses gaits, which no classifier can find; where the
discriminant does beat it, the reservoir's failure is the method's, a finding of the
chapter, and nothing is flagged. The terrains being separable within one gait x
frequency (Test B) is the second target ("Puppy II terrains within a gait").

Claims on a calibration target. The knee spring is fitted to V1, Tab.
3.1a's speed (:mod:`thesis.modelcheck.calibration`), and the fit of the unsourced values
(:mod:`thesis.modelcheck.fit`) to the whole fitted side of the split (V1 and Tab. 3.1b's
speed at 1.5 Hz, :func:`thesis.modelcheck.split.paper_keys`); a claim whose thesis numbers
include a fitted number and that rests on the Oncilla is marked where the profile's results
hold the fit (its fitted side) or else the calibration (V1): the model was made to walk
that number, so matching it is no evidence.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from thesis.modelcheck import convergence_rule as CR
from thesis.modelcheck import split as SPLIT
from thesis.modelcheck.targets import V1_PAPER_KEYS

#: Result key of the Oncilla's validation.
VALIDATION_KEY = "model/validation"
#: Result prefixes of the chapters decided on the simulated Oncilla.
ONCILLA_RESULTS = ("ch3/", "ch4/", "ch6/")
#: Reading shown beside a flagged verdict.
UNVALIDATED = "decided on an unvalidated model"
#: Result key of the Oncilla's convergence table.
CONVERGENCE_KEY = "model/convergence"
#: Result key of the Puppy II's convergence table.
PUPPY_CONVERGENCE_KEY = "model/puppy_convergence"
#: Result prefixes of the chapter decided on the simulated Puppy II.
PUPPY_RESULTS = ("ch5/",)
#: Failed-target name of the Puppy II's convergence table.
PUPPY_TARGET = "Puppy II convergence"
#: Result key of the Puppy II's terrain check (held-out gait and within a cell).
PUPPY_HELDOUT_KEY = "model/puppy_heldout"
#: Failed-target name of its held-out-gait test when no terrain crosses the gaits.
PUPPY_ACROSS_TARGET = "Puppy II terrains across gaits"
#: Failed-target name of its within-cell test.
PUPPY_WITHIN_TARGET = "Puppy II terrains within a gait"
#: The command that remakes each failed target's result (the Oncilla's otherwise).
REMAKE = {PUPPY_TARGET: "thesis validate puppy",
          PUPPY_ACROSS_TARGET: "thesis bench puppy-heldout",
          PUPPY_WITHIN_TARGET: "thesis bench puppy-heldout"}
#: Result key of the pebble field's target V7.
PEBBLES_KEY = "model/pebbles"
#: Results made from chapter 4's pebble runs (transfer_pebbly and what is made from it).
PEBBLE_RESULTS = ("ch4/transfer_pebbly", "ch4/table4_4", "ch4/fig4_8")
#: Result key of the knee spring's calibration.
CALIBRATION_KEY = "model/calibration"
FIT_KEY = "model/fit"
#: Reading shown beside a verdict whose model's convergence table is inconclusive.
INCONCLUSIVE_CONVERGENCE = "model's convergence in dt and sweeps not shown (inconclusive)"
#: Reading shown beside a verdict whose thesis number is the calibration's target.
CALIBRATION_TARGET = "its thesis number is a calibration target"


def failed_targets(results: Mapping, conv: dict | None) -> list[dict] | None:
    """The failed validation targets of ``results[VALIDATION_KEY]`` as
    ``[{"target": "V2", "text": <its numbers>}, ...]``, followed by ``conv`` (the Oncilla's
    convergence table as :func:`convergence_failure` gives it) where that table decided
    "not converged"; None when neither was run (then nothing is flagged)."""
    ds = results.get(VALIDATION_KEY)
    if ds is None and conv is None:
        return None
    failed = [] if ds is None else _failed_rows(ds)
    return failed + ([conv] if conv and conv["failed"] else [])


def _failed_rows(ds) -> list[dict]:
    """``[{"target": ..., "text": ...}]`` of the targets a validation dataset (``target``,
    ``target_passed``, ``target_text``) records as failed."""
    return [{"target": str(t), "text": str(txt)}
            for t, p, txt in zip(ds["target"].values, ds["target_passed"].values,
                                 ds["target_text"].values) if not int(p)]


def convergence_failure(results: Mapping, key: str, target: str) -> dict | None:
    """The verdict of the convergence table ``results[key]`` as a target entry:
    ``{"target": target, "failed": bool, "text": <each setting's verdict, fall-rate change
    and largest speed change>}``; None when the table was not run or predates the
    three-valued rule."""
    ds = results.get(key)
    if ds is None or "verdict" not in ds:
        return None
    def falls(r) -> str:
        if "case_fall_rate_change" in ds:  # the rule decides each case's fall rate
            return (f"largest case fall-rate change "
                    f"{100 * float(ds['case_fall_rate_change'].sel(refined=r).max()):.1f} points")
        return f"fall rate {100 * float(ds['fall_rate_change'].sel(refined=r)):.1f} points"

    text = "; ".join(
        f"{r}: {ds['verdict'].sel(refined=r).values} ({falls(r)}, largest speed "
        f"change {100 * float(ds['max_speed_change'].sel(refined=r)):.0f} %)"
        for r in ds["refined"].values)
    verdict = CR.overall(ds["verdict"].values)
    return {"target": target, "failed": verdict == CR.NOT_CONVERGED, "verdict": verdict,
            "text": text}


def terrain_failures(results: Mapping) -> list[dict] | None:
    """The failed targets of the Puppy II's terrain check ``results[PUPPY_HELDOUT_KEY]``
    (module docstring) as ``[{"target": ..., "text": ...}]``, empty when both hold; None
    when the check was not run."""
    ds = results.get(PUPPY_HELDOUT_KEY)
    if ds is None:
        return None
    out = []
    lda, maj = float(ds["pooled_lda_accuracy"]), float(ds["pooled_majority_share"])
    if not bool(ds["pooled_passed"]) and lda <= maj:
        out.append({"target": PUPPY_ACROSS_TARGET, "text": (
            f"{ds.attrs['test_a']}; the linear discriminant scores {lda:.1f} % against the "
            f"held-out majority share {maj:.1f} %: no terrain in the "
            f"{ds.attrs.get('selection', 'touch')} channels crosses gaits")})
    if not bool(ds["within_passed"]):
        out.append({"target": PUPPY_WITHIN_TARGET, "text": str(ds.attrs["test_b"])})
    return out


def pebble_failures(results: Mapping) -> list[dict] | None:
    """V7 of ``results[PEBBLES_KEY]`` as ``[{"target": "V7", "text": ...}]`` where it
    failed, empty where it passed; None when the check was not run."""
    ds = results.get(PEBBLES_KEY)
    return None if ds is None else _failed_rows(ds)


def rests_on_pebbles(requires: Iterable[str]) -> bool:
    """True if any required result comes from chapter 4's pebble runs."""
    return any(str(r) in PEBBLE_RESULTS for r in requires)


def rests_on_oncilla(requires: Iterable[str]) -> bool:
    """True if any required result comes from chapter 3, 4 or 6."""
    return any(str(r).startswith(ONCILLA_RESULTS) for r in requires)


def calibration_mark(paper_keys: Iterable[str], results: Mapping) -> dict | None:
    """The calibration-target record of a claim with ``paper_keys``: ``keys`` (its fitted
    keys), ``source`` (the result that fitted them), ``fitted_knee_spring`` [N m/rad],
    ``configured_matches_fit`` and ``reading`` (:data:`CALIBRATION_TARGET`). With the fit
    (:data:`FIT_KEY`) the fitted keys are the split's fitted side, else with the
    calibration V1's; None when no key is fitted or neither was run."""
    fit = results.get(FIT_KEY)
    if fit is not None:
        keys = sorted(set(paper_keys) & SPLIT.paper_keys(SPLIT.FITTED))
        if not keys:
            return None
        return {"keys": keys, "reading": CALIBRATION_TARGET, "source": FIT_KEY,
                "fitted_knee_spring": float(fit["fit_knee_spring"]),
                "configured_matches_fit": bool(fit["configured_matches_fit"].all())}
    keys = sorted(set(paper_keys) & set(V1_PAPER_KEYS))
    ds = results.get(CALIBRATION_KEY)
    if not keys or ds is None:
        return None
    return {"keys": keys, "reading": CALIBRATION_TARGET, "source": CALIBRATION_KEY,
            "fitted_knee_spring": float(ds["fitted_knee_spring"]),
            "configured_matches_fit": bool(int(ds["configured_matches_fit"]))}


def flag(requires: Iterable[str], results: Mapping, status: str = "",
         paper_keys: Iterable[str] = ()) -> dict:
    """The fields a claim's verdict gains (empty when none): ``model_validation`` with
    ``unvalidated`` (True), ``reading`` (:data:`UNVALIDATED`) and ``failed_targets``,
    where the claim rests on the Oncilla and a validation target failed; or
    ``unvalidated`` False with no failed target where the validation passed (V7 counts
    only for a claim on the pebble runs, :func:`rests_on_pebbles`); and
    ``calibration_target`` (:func:`calibration_mark`) where its thesis numbers include
    the calibration's target. A claim on chapter 5's recordings gains ``model_validation``
    from the Puppy II's convergence table and terrain check (:func:`terrain_failures`)
    alone. A claim that was not decided (``status`` ``"not_run"``) gains nothing."""
    if status == "not_run":
        return {}
    if any(str(r).startswith(PUPPY_RESULTS) for r in requires) \
            and not rests_on_oncilla(requires):
        conv = convergence_failure(results, PUPPY_CONVERGENCE_KEY, PUPPY_TARGET)
        terrain = terrain_failures(results)
        if conv is None and terrain is None:
            return {}
        failed = ([conv] if conv is not None and conv["failed"] else []) + (terrain or [])
        return {"model_validation": _record(failed, conv)}
    if not rests_on_oncilla(requires):
        return {}
    out = {}
    mark = calibration_mark(paper_keys, results)
    if mark is not None:
        out["calibration_target"] = mark
    conv = convergence_failure(results, CONVERGENCE_KEY, "convergence")
    failed = failed_targets(results, conv)
    pebbles = pebble_failures(results) if rests_on_pebbles(requires) else None
    if pebbles is not None:
        failed = (failed or []) + pebbles
    if failed is None:
        return out
    out["model_validation"] = _record(failed, conv)
    return out


def _record(failed: list[dict], conv: dict | None = None) -> dict:
    """``model_validation`` of a claim: unvalidated (with :data:`UNVALIDATED`) when any
    target failed, else a passed validation with no failed target; either gains
    ``convergence_inconclusive`` (the table's target entry) when the convergence table
    ``conv`` (:func:`convergence_failure`) is inconclusive."""
    rec = {"unvalidated": False, "failed_targets": []} if not failed else {
        "unvalidated": True, "reading": UNVALIDATED, "failed_targets": failed}
    if conv is not None and conv["verdict"] == CR.INCONCLUSIVE:
        rec["convergence_inconclusive"] = conv
    return rec


def text(claim: Mapping) -> str:
    """The flags in words for the report ("" when the claim carries none, or only a
    passed validation)."""
    parts = []
    mv = claim.get("model_validation") or {}
    if mv.get("unvalidated"):
        failed = mv.get("failed_targets", [])
        names = ", ".join(f["target"] for f in failed)
        cmds = ", ".join(dict.fromkeys(REMAKE.get(f["target"], "thesis validate oncilla")
                                       for f in failed))
        parts.append(f"{UNVALIDATED} (failed: {names}; {cmds})")
    unsure = mv.get("convergence_inconclusive")
    if unsure:
        robot = "puppy" if unsure["target"] == PUPPY_TARGET else "oncilla"
        parts.append(f"{INCONCLUSIVE_CONVERGENCE} ({unsure['text']}; thesis validate {robot})")
    ct = claim.get("calibration_target")
    if ct:
        if ct.get("source") == FIT_KEY:
            parts.append(f"{CALIBRATION_TARGET} ({', '.join(ct['keys'])}: the feet, knee "
                         f"spring and drives were fitted to it, model/fit; knee spring "
                         f"{ct['fitted_knee_spring']:.4g} N m/rad)")
        else:
            parts.append(f"{CALIBRATION_TARGET} (V1, Tab. 3.1a's speed: the knee spring was "
                         f"fitted to it, {ct['fitted_knee_spring']:.4g} N m/rad)")
    return "; ".join(parts)
