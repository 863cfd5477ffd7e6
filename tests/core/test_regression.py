"""Regression references: tolerances per variable, exactly the wall-clock values skipped."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from thesis import regression, store
from thesis.config import load_config
from thesis.store import WALL_CLOCK

from ..ch2_chance import CHANCE_ERROR, better_than_chance


def _ds(err=(0.1, 0.2), secs=(1.0, 2.0), sim=(3.0, 4.0)):
    return xr.Dataset(
        {"test_error": xr.DataArray(np.array(err), dims="seed",
                                    attrs={"units": "1", "long_name": "error"}),
         "wall_seconds": xr.DataArray(np.array(secs), dims="seed",
                                      attrs={"units": "s", "long_name": "time",
                                             **WALL_CLOCK}),
         "time_to_up_s": xr.DataArray(np.array(sim), dims="seed",
                                      attrs={"units": "s", "long_name": "simulated time"})},
        coords={"seed": [0, 1]}, attrs={"thesis_ref": "Tab. 2.2"})


def test_identical_result_matches_its_reference():
    ref = json.loads(json.dumps(regression.to_reference(_ds())))
    assert regression.compare(_ds(), ref) == []


def test_value_change_beyond_tolerance_is_reported():
    ref = regression.to_reference(_ds())
    problems = regression.compare(_ds(err=(0.1, 0.25)), ref)
    assert len(problems) == 1 and "test_error" in problems[0]


def test_change_within_tolerance_passes():
    ref = regression.to_reference(_ds())
    assert regression.compare(_ds(err=(0.1, 0.2 * (1 + 1e-5))), ref) == []


def test_wall_time_is_recorded_but_not_compared():
    ref = regression.to_reference(_ds())
    assert ref["variables"]["wall_seconds"]["compare"] is False
    assert regression.compare(_ds(secs=(50.0, 60.0)), ref) == []


def test_a_text_rendering_of_compared_numbers_is_recorded_but_not_compared():
    """A text that renders numbers the dataset holds (attribute ``renders``) flips at a
    rounding boundary where the number passes its tolerance (-0.0775 m/s written "-0.077"
    on one host, "-0.078" on another): it is recorded, not compared; the number is."""
    def ds(speed):
        text = np.array([f"{v:.3f} m/s" for v in speed])
        return xr.Dataset({"speed": xr.DataArray(np.array(speed), dims="seed"),
                           "text": xr.DataArray(text, dims="seed", attrs={"renders": "speed"})},
                          coords={"seed": [0, 1]})
    ref = json.loads(json.dumps(regression.to_reference(ds([-0.07750001, 0.3]))))
    assert ref["variables"]["text"]["compare"] is False
    assert ref["variables"]["text"]["values"] == ["-0.078 m/s", "0.300 m/s"]
    assert regression.compare(ds([-0.07749999, 0.3]), ref) == []  # "-0.077 m/s"
    problems = regression.compare(ds([-0.09, 0.3]), ref)
    assert len(problems) == 1 and "'speed'" in problems[0]
    unmarked = ds([-0.07749999, 0.3])
    del unmarked["text"].attrs["renders"]  # as recorded before the marker: a stale reference
    assert any("stale reference" in p for p in regression.compare(unmarked, ref))


def test_changed_labels_are_reported_not_raised():
    """A text variable (e.g. a fate per seed) that changes is a reported difference."""
    def ds(fate):
        return xr.Dataset({"fate": xr.DataArray(np.array(fate), dims="seed")},
                          coords={"seed": [0, 1]})
    ref = json.loads(json.dumps(regression.to_reference(ds(["settles", "dies_out"]))))
    assert regression.compare(ds(["settles", "dies_out"]), ref) == []
    problems = regression.compare(ds(["settles", "settles"]), ref)
    assert len(problems) == 1 and "'fate' labels differ" in problems[0]


def test_missing_and_new_variables_and_shape_changes_are_reported():
    ref = regression.to_reference(_ds())
    ds = _ds().rename({"test_error": "error"})
    problems = regression.compare(ds, ref)
    assert any("'test_error' missing" in p for p in problems)
    assert any("'error' is new" in p for p in problems)


def test_simulated_seconds_are_compared_like_any_number():
    ref = regression.to_reference(_ds())
    assert ref["variables"]["time_to_up_s"]["compare"] is True
    problems = regression.compare(_ds(sim=(3.0, 4.5)), ref)
    assert len(problems) == 1 and "time_to_up_s" in problems[0]


def test_skipping_follows_the_marker_not_units_or_names():
    ds = _ds()
    ds["wall_seconds"].attrs.pop("measurement")  # a name and unit that look like wall time
    ref = regression.to_reference(ds)
    assert ref["variables"]["wall_seconds"]["compare"] is True
    changed = _ds(secs=(50.0, 60.0))
    changed["wall_seconds"].attrs.pop("measurement")
    assert any("wall_seconds" in p for p in regression.compare(changed, ref))
    assert not regression.is_wall_clock(ds["wall_seconds"])
    assert regression.is_wall_clock(_ds()["wall_seconds"])


def test_stale_reference_policy_is_reported():
    ref = regression.to_reference(_ds())
    ref["variables"]["time_to_up_s"]["compare"] = False  # as recorded before the marker
    problems = regression.compare(_ds(sim=(3.0, 4.5)), ref)
    assert any("stale reference" in p for p in problems)
    assert any("differs beyond" in p and "time_to_up_s" in p for p in problems)


def test_per_variable_override():
    def widened(**kw):
        ds = _ds(**kw)
        ds["test_error"].attrs["regression_rtol"] = 0.5
        return ds
    ref = regression.to_reference(widened())
    assert regression.compare(widened(err=(0.1, 0.25)), ref) == []
    assert regression.compare(widened(err=(0.1, 0.35)), ref) != []


def test_write_references_reports_changes(tmp_path):
    assert regression.write_references({"ch2/table2_2": _ds()}, tmp_path) == [
        "ch2/table2_2: new reference"]
    lines = regression.write_references({"ch2/table2_2": _ds(err=(0.3, 0.2))}, tmp_path)
    assert any("test_error" in line for line in lines)
    assert (tmp_path / "ch2" / "table2_2.json").exists()


REFERENCES = Path(__file__).resolve().parents[1] / "regression" / "smoke"
#: Every committed reference file: the canonical ones and those of other host classes.
REFERENCE_FILES = sorted(REFERENCES.glob("*/*.json")) + sorted(
    REFERENCES.parent.glob(f"{REFERENCES.name}-*/*/*.json"))


def _numeric(values):
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        return None
    return a[np.isfinite(a)]


def test_committed_tolerances_are_narrower_than_the_spread_of_their_quantity():
    """A tolerance of its own (wider than the rounding guard) must not cover every value
    the quantity takes in its reference, or the comparison checks nothing."""
    assert REFERENCE_FILES, REFERENCES
    widened = 0
    for path in REFERENCE_FILES:
        for name, spec in json.loads(path.read_text())["variables"].items():
            default = (spec["rtol"], spec["atol"]) == (regression.DEFAULT_RTOL,
                                                       regression.DEFAULT_ATOL)
            if not spec["compare"] or default or "over" in spec or "chaos" in spec:
                continue  # a chaotic variable's tolerance is measured: the tests below
            widened += 1
            v = _numeric(spec["values"])
            assert v is not None and v.size > 1, f"{path.name}:{name} has no spread"
            band = spec["atol"] + spec["rtol"] * np.abs(v).max()
            spread = v.max() - v.min()
            assert band < spread, f"{path.name}:{name}: tolerance {band:.3g} >= spread {spread:.3g}"


def test_committed_chaotic_tolerances_are_what_their_twins_measured():
    """A variable compared through its mean over seeds carries the tolerance its perturbed
    twins give (recomputed here from the reference's own values), never a typed one; the
    ch6 sweeps are such results."""
    chaotic = 0
    for path in REFERENCE_FILES:
        variables = json.loads(path.read_text())["variables"]
        if "outcome_perturbed" not in variables:
            continue
        for name, spec in variables.items():
            if "over" not in spec:
                continue
            chaotic += 1
            base = name.removesuffix("_perturbed")
            pair = base if base + "_perturbed" in variables and base != "flipped" else "outcome"
            n = np.asarray(spec["values"], dtype=object).shape[spec["dims"].index(spec["over"])]
            want = regression.chaos_tolerance(variables[pair]["values"],
                                              variables[pair + "_perturbed"]["values"], n)
            assert spec["atol"] == pytest.approx(want), f"{path.name}:{name}"
    assert chaotic >= 10


def test_committed_references_skip_only_wall_clock_like_variables():
    """Every skipped reference variable is one the code marks as wall-clock, or a text
    rendering of numbers compared on their own (``renders``): the names here are the
    marked ones (a new skip must be a new marked measurement)."""
    marked = {"seconds", "seconds_runs", "exponent_n2logn", "exponent_n", "train_seconds",
              "wall_seconds", "trot_wall_seconds", "robot_seconds_per_wall_second",
              "compile_seconds", "ms_per_robot_step", "peak_memory_bytes",
              "rollout_wall_seconds", "rollout_cpu_seconds", "robot_seconds_per_cpu_second",
              "compile_wall_seconds", "followup_rollout_wall_seconds", "target_text"}
    for path in REFERENCE_FILES:
        for name, spec in json.loads(path.read_text())["variables"].items():
            if not spec["compare"]:
                assert name in marked, f"{path.parent.name}/{path.name}: {name} skipped"


def test_every_host_class_reference_has_a_canonical_one():
    """A host class's own reference replaces a canonical one; it never adds a result."""
    own = [p for p in REFERENCE_FILES if p.parent.parent != REFERENCES]
    for path in own:
        assert (REFERENCES / path.parent.name / path.name).exists(), path
        host = path.parent.parent.name.removeprefix(f"{REFERENCES.name}-")
        assert regression.host_root(REFERENCES, host) == path.parent.parent


def test_ch2_smoke_references_are_better_than_chance():
    """Every cell of each committed smoke Tab. 2.2 learned (one-sided binomial test against
    0.9, the error of a model that learned nothing): a reference rewritten from models that
    learned nothing (e.g. shuffled labels) cannot be committed. Where the error rates are
    chaotic (their twins move a single smoke run by more than its distance to chance), a
    run at chance is told by the smoke run's own binomial test
    (``tests/pipeline/test_smoke.py::test_smoke_ch2_models_learn``), not by the
    regression; where they are not, the tolerance must tell it."""
    paths = [p for p in REFERENCE_FILES if p.parent.name == "ch2" and p.name == "table2_2.json"]
    assert paths
    n_test = int(load_config("smoke")["ch2"]["data"]["n_test"])
    for path in paths:
        ref = json.loads(path.read_text())
        err = np.asarray(ref["variables"]["test_error"]["values"], dtype=float)
        assert np.isfinite(err).all(), path
        assert better_than_chance(err, n_test).all(), (path, err.ravel().tolist())
        spec = ref["variables"]["test_error"]
        if "chaos" not in spec:
            assert CHANCE_ERROR - err.max() > spec["atol"]  # a chance-level run differs


def test_host_class_from_machine_and_flags():
    assert regression.host_class("x86_64", {"avx2", "fma", "avx512f"}) == "avx512"
    assert regression.host_class("AMD64", {"avx2", "fma"}) == "avx2"
    assert regression.host_class("x86_64", {"sse4_2"}) == "x86-64"
    assert regression.host_class("arm64", set()) == "arm64"


def test_reference_of_a_host_class_replaces_the_canonical_one(tmp_path):
    root = tmp_path / "smoke"
    regression.write_references({"ch6/trot": _ds(), "ch3/table3_1": _ds()}, root)
    regression.write_references({"ch6/trot": _ds(err=(0.5, 0.6))}, tmp_path / "smoke-avx512")
    assert regression.reference_file(root, "ch6/trot", "avx512") == \
        tmp_path / "smoke-avx512" / "ch6" / "trot.json"
    assert regression.reference_file(root, "ch3/table3_1", "avx512") == \
        root / "ch3" / "table3_1.json"
    assert regression.reference_file(root, "ch6/trot", "avx2") == root / "ch6" / "trot.json"


def test_update_rewrites_the_canonical_references_and_names_the_host_classes(tmp_path):
    root = tmp_path / "smoke"
    regression.write_references({"ch6/trot": _ds()}, root)
    regression.write_references({"ch6/trot": _ds(err=(0.5, 0.6))}, tmp_path / "smoke-avx512")
    lines = regression.update_references({"ch6/trot": _ds(err=(0.3, 0.2))}, root,
                                         {"perturbed": {}})
    ref = json.loads((root / "ch6" / "trot.json").read_text())
    assert ref["variables"]["test_error"]["values"] == [0.3, 0.2]
    assert "chaos" not in ref["variables"]["test_error"]  # no twin: deterministic
    assert any("no perturbed twin of ch6/trot" in x for x in lines)
    assert any("avx512 hosts" in x and "kept" in x for x in lines)


# ------------------------------------------------------------ twin-measured chaos ---
def test_a_variable_its_twins_reproduce_is_deterministic():
    ds = _ds()
    assert regression.measure_sensitivity(ds["test_error"], {"perturbed": ds["test_error"]}) \
        is None
    ref = regression.to_reference(ds, {"perturbed": _ds(err=(0.1, 0.2 * (1 + 1e-6)))})
    assert "chaos" not in ref["variables"]["test_error"]
    assert regression.compare(_ds(err=(0.1, 0.21)), ref) != []  # still tight


def test_a_chaotic_variable_is_compared_through_its_mean_over_seeds_within_its_twins():
    twin = _ds(err=(0.3, 0.1))  # each seed moved by 0.2 / 0.1
    chaos = regression.measure_sensitivity(_ds()["test_error"],
                                           {"perturbed": twin["test_error"],
                                            "native": _ds()["test_error"]})
    rms = np.sqrt((0.2 ** 2 + 0.1 ** 2) / 2)
    assert chaos["over"] == "seed" and chaos["n"] == 2
    assert chaos["twins"] == pytest.approx({"perturbed": rms, "native": 0.0})
    assert chaos["atol"] == pytest.approx(regression.CHAOS_Z * rms / np.sqrt(2))
    ref = json.loads(json.dumps(regression.to_reference(_ds(), {"perturbed": twin})))
    assert ref["variables"]["test_error"]["chaos"]["atol"] == pytest.approx(
        regression.CHAOS_Z * rms / np.sqrt(2))
    assert "chaos" not in ref["variables"]["time_to_up_s"]  # its twin reproduced it
    # the runs swap (mean kept): no difference; a mean moved beyond the tolerance: one
    assert regression.compare(_ds(err=(0.2, 0.1)), ref) == []
    shifted = 0.15 + chaos["atol"] * 1.5
    problems = regression.compare(_ds(err=(shifted, shifted)), ref)
    assert len(problems) == 1 and "chaotic" in problems[0] and "test_error" in problems[0]


def test_a_chaotic_variable_without_runs_is_compared_through_its_overall_mean():
    def traj(v):
        return xr.Dataset({"yaw": xr.DataArray(np.asarray(v, float), dims="time",
                                               attrs={"units": "rad", "long_name": "yaw"})})
    base, twin = traj([0.0, 0.1, 0.2, 0.3]), traj([0.0, 0.1, 0.25, 0.2])
    ref = regression.to_reference(base, {"native": twin})
    chaos = ref["variables"]["yaw"]["chaos"]
    assert chaos["over"] is None and chaos["n"] == 1
    assert regression.compare(traj([0.0, 0.1, 0.3, 0.2]), ref) == []  # same mean
    assert regression.compare(traj([0.5, 0.6, 0.7, 0.8]), ref) != []


def test_chaotic_labels_are_compared_through_their_shares():
    def ds(fate):
        return xr.Dataset({"fate": xr.DataArray(np.array(fate), dims="seed")},
                          coords={"seed": np.arange(len(fate))})
    base = ["up"] * 30 + ["down"] * 10
    twin = ["down"] * 2 + ["up"] * 28 + ["up"] * 2 + ["down"] * 8  # 4 of 40 flipped
    ref = json.loads(json.dumps(regression.to_reference(ds(base), {"perturbed": ds(twin)})))
    chaos = ref["variables"]["fate"]["chaos"]
    assert chaos["twins"]["perturbed"] == pytest.approx(np.sqrt(4 / 40))
    assert chaos["atol"] == pytest.approx(regression.CHAOS_Z * np.sqrt(4 / 40) / np.sqrt(40))
    assert regression.compare(ds(base[::-1]), ref) == []  # same shares, other seeds
    assert regression.compare(ds(["up"] * 40), ref) != []  # a quarter of the runs moved


def test_a_twin_of_another_shape_is_refused():
    other = _ds().isel(seed=[0])
    with pytest.raises(ValueError, match="another configuration"):
        regression.to_reference(_ds(), {"perturbed": other})


def test_committed_chaotic_tolerances_are_what_their_recorded_twins_measured():
    """Every chaotic reference variable's tolerance is recomputed from the twin
    differences it records (never typed), its statistic averages over runs where the
    result has them, and at least one twin moved it."""
    chaotic = 0
    for path in REFERENCE_FILES:
        for name, spec in json.loads(path.read_text())["variables"].items():
            if "chaos" not in spec:
                continue
            chaotic += 1
            c = spec["chaos"]
            assert c["twins"] and max(c["twins"].values()) > 0, f"{path}:{name}"
            want = regression.chaos_tolerance_from_rms(max(c["twins"].values()), c["n"], c["z"])
            assert c["atol"] == pytest.approx(want), f"{path}:{name}"
            assert c["z"] == regression.CHAOS_Z
            if "seed" in spec["dims"] and c["over"] == "seed":
                seeds = json.loads(path.read_text())["coords"]["seed"]
                assert c["n"] == len(seeds), f"{path}:{name}"
            elif "seed" not in spec["dims"]:
                assert c["n"] == 1, f"{path}:{name}"
    assert chaotic >= 10


def test_another_hosts_measurement_is_carried_over_and_a_reference_is_a_twin(tmp_path):
    """A twin measured on another host (its references, read back as a result) stays
    recorded when the references are rewritten on a host that only has its own twins."""
    root, other = tmp_path / "smoke", tmp_path / "other"
    regression.write_references({"ch2/table2_2": _ds(err=(0.3, 0.1))}, other)
    back = regression.host_twin(other, ["ch2/table2_2", "ch9/none"])
    assert list(back) == ["ch2/table2_2"]
    assert regression.compare(back["ch2/table2_2"],
                              json.loads((other / "ch2" / "table2_2.json").read_text())) == []
    regression.write_references({"ch2/table2_2": _ds()}, root, {"host-x": back})
    first = json.loads((root / "ch2" / "table2_2.json").read_text())
    assert set(first["variables"]["test_error"]["chaos"]["twins"]) == {"host-x"}
    regression.write_references({"ch2/table2_2": _ds()}, root, {"perturbed": {"ch2/table2_2": _ds()}})
    again = json.loads((root / "ch2" / "table2_2.json").read_text())
    chaos = again["variables"]["test_error"]["chaos"]
    assert chaos["twins"]["perturbed"] == 0.0
    assert chaos["twins"]["host-x"] == first["variables"]["test_error"]["chaos"]["twins"]["host-x"]
    assert chaos["atol"] == pytest.approx(first["variables"]["test_error"]["chaos"]["atol"])
    # another shape: the old measurement no longer applies
    regression.write_references({"ch2/table2_2": _ds().isel(seed=[0])}, root)
    last = json.loads((root / "ch2" / "table2_2.json").read_text())
    assert "chaos" not in last["variables"]["test_error"]


def test_a_censored_mean_on_one_side_counts_the_quantitys_largest_magnitude():
    """A chaotic count that is NaN (never reached) in every run on one side differs by the
    quantity's largest magnitude, as its twins' differences were measured: within a
    tolerance that covers that it passes, beyond it it fails."""
    def ds(v):
        return xr.Dataset({"n": xr.DataArray(np.asarray(v, float), dims=("seed", "k"),
                                             attrs={"units": "1", "long_name": "count"})},
                          coords={"seed": [0]})
    base = ds([[20.0, 100.0]])
    ref = regression.to_reference(base, {"perturbed": ds([[20.0, np.nan]])})
    assert ref["variables"]["n"]["chaos"]["atol"] == pytest.approx(
        regression.CHAOS_Z * 100.0)
    assert regression.compare(ds([[20.0, np.nan]]), ref) == []
    ref["variables"]["n"]["chaos"]["atol"] = 50.0  # a tolerance below the flip's size
    assert regression.compare(ds([[20.0, np.nan]]), ref) != []


def test_infinite_values_survive_the_reference():
    """A value that is inf in the result (a ratio to zero) is inf in the reference too, so
    the result compares equal to it, and a finite value in its place differs."""
    def ds(v):
        return xr.Dataset({"r": xr.DataArray(np.asarray(v, float), dims="case",
                                             attrs={"units": "1", "long_name": "ratio"})})
    ref = json.loads(json.dumps(regression.to_reference(ds([1.0, np.inf, np.nan]))))
    assert ref["variables"]["r"]["values"][1] == np.inf
    assert regression.compare(ds([1.0, np.inf, np.nan]), ref) == []
    assert regression.compare(ds([1.0, 5.0, np.nan]), ref) != []


def test_a_twin_run_is_measured_against_the_references_as_they_are(tmp_path):
    """``python -m thesis.regression twin``: another host's results become a twin of the
    committed references without a new smoke run: the values and coordinates stay, a
    variable that host moved becomes chaotic with the tolerance it measured, the
    measurements already recorded are carried, and a recorded measurement named in
    ``--forget`` (no twin at all) is dropped."""
    root = tmp_path / "smoke"
    regression.write_references({"ch2/table2_2": _ds()}, root,
                                {"perturbed": {"ch2/table2_2": _ds(sim=(3.0, 4.2))},
                                 "bogus": {"ch2/table2_2": _ds(sim=(3.0, 4.1))}})
    path = root / "ch2" / "table2_2.json"
    before = json.loads(path.read_text())
    assert "chaos" not in before["variables"]["test_error"]
    host = tmp_path / "host" / "smoke" / "ch2"
    host.mkdir(parents=True)
    store.write_dataset(_ds(err=(0.1, 0.2 * 1.01)).assign_attrs(seeds=[0, 1]),
                        host / "table2_2.nc", profile="smoke", experiment="ch2/table2_2",
                        config_slice={}, started=store.now(), wall_seconds=1.0)
    assert regression.main(["twin", "smoke", str(root), "--twin-run",
                            f"host-x={tmp_path / 'host' / 'smoke'}",
                            "--forget", "bogus:ch2/"]) == 0
    after = json.loads(path.read_text())
    assert after["coords"] == before["coords"]
    for name, spec in after["variables"].items():
        assert spec["values"] == before["variables"][name]["values"]
    err = after["variables"]["test_error"]["chaos"]
    assert err["twins"] == pytest.approx({"host-x": 0.002 / np.sqrt(2)})
    assert regression.compare(_ds(err=(0.1, 0.2 * 1.01)), after) == []
    assert regression.compare(_ds(err=(0.1, 0.3)), after) != []  # still fails a real change
    sim = after["variables"]["time_to_up_s"]["chaos"]
    # carried, and measured again by the new twin (no move); the bogus one forgotten
    assert sim["twins"] == pytest.approx({"perturbed": 0.2 / np.sqrt(2), "host-x": 0.0})
    assert sim["atol"] == pytest.approx(
        regression.chaos_tolerance_from_rms(0.2 / np.sqrt(2), 2))
