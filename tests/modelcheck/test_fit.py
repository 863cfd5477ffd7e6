"""The fit of the Oncilla's unsourced values (thesis.modelcheck.fit, ``thesis validate
oncilla --only fit``): the declared procedure of thesis.modelcheck.split on a known
response (stubbed rollouts), its design, its objective on hand-computed numbers, and that
it reads only the fitted side of the split. No test runs the model."""

from __future__ import annotations

import logging
import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.stats import qmc

from thesis import registry, seeding, store
from thesis.config import load_config
from thesis.modelcheck import fit as F
from thesis.modelcheck import split as S

from .test_split import guard  # noqa: F401  (the judged-side guard fixture)

#: The free parameters' optimum of the stub response (inside every bound).
OPTIMUM = dict(foot_length=0.081, foot_width=0.033, knee_spring=4.0, drive_stiffness=14.0)


def _ctx(overrides=None):
    sizes = dict(design_points=8, local_starts=2, local_evaluations=150, starts=2,
                 seconds=0.3)
    config = load_config("smoke", overrides={"physics": {"oncilla_fit": {
        **sizes, **(overrides or {})}}})
    return SimpleNamespace(full_config=config, root_seed=int(config["root_seed"]),
                           key="model/fit", log=logging.getLogger("test"))


def _stub(optimum=OPTIMUM, falls=None):
    """A rollout whose speed is a smooth function of the parameters: both cases walk their
    published speed (Tab. 3.1a 0.285, Tab. 3.1b 0.41 m/s) at ``optimum`` and slower away
    from it (a Gaussian bump in the unit cube); ``falls(values)`` -> (C, S) fallen."""
    calls = []
    fr = F.free()
    centre = F.to_unit(fr, [optimum[p.name] for p in fr])

    def rollout(values, cs, kicks):
        calls.append(dict(values))
        u = F.to_unit(fr, [values[p.name] for p in fr])
        bump = math.exp(-4.0 * float(((u - centre) ** 2).sum()))
        peak = np.array([0.285, 0.41])[:len(cs)]
        speed = np.repeat((peak * bump)[:, None], len(kicks), axis=1)
        fallen = np.zeros_like(speed, bool) if falls is None else falls(values)
        return dict(speed=speed, fallen=fallen, wall=0.0)

    rollout.calls = calls
    return rollout


def test_the_procedure_finds_the_minimum_of_a_known_response_and_records_it():
    stub = _stub()
    ds = F.fit(_ctx(), rollout=stub)
    store.check_result(ds)  # units and long_name on every variable
    n = ds.sizes["evaluation"]
    assert n == len(stub.calls) <= 8 + 2 * 150
    assert list(ds["phase"].values[:8]) == [0] * 8 and set(ds["phase"].values[8:]) <= {1, 2}
    # the fit is the lowest objective of every evaluation, ties to the earliest
    assert int(ds["fit_evaluation"]) == int(np.argmin(ds["objective"].values))
    assert float(ds["fit_objective"]) == pytest.approx(float(ds["objective"].min()))
    assert float(ds["fit_objective"]) < 1e-5
    for name, want in OPTIMUM.items():
        assert float(ds[f"fit_{name}"]) == pytest.approx(want, rel=0.03), name
    assert float(ds["fit_LEG_OFFSET"]) == 0.031 and int(ds["held"].sel(parameter="LEG_OFFSET"))
    assert {c["LEG_OFFSET"] for c in stub.calls} == {0.031}
    assert list(ds["fit_at_bound"].values) == [0] * 5
    assert np.allclose(ds["fit_case_speed"].values, [0.285, 0.41], rtol=1e-2)
    assert list(ds["fit_case_falls"].values) == [0, 0]
    # the derived values follow the fitted ones
    assert float(ds["fit_toe_offset"]) == pytest.approx(float(ds["fit_foot_length"]) / 2
                                                        + 0.004)
    assert float(ds["fit_drive_damping"]) == pytest.approx(float(ds["fit_drive_stiffness"])
                                                           / 50)
    # each local start began at one of the best initial points, and stayed in the bounds
    best = np.argsort(ds["objective"].values[:8], kind="stable")[:2]
    assert list(ds["local_start_origin"].values) == list(best)
    for p in S.PARAMETERS:
        v = ds[f"evaluation_{p.name}"].values
        assert (v >= p.low - 1e-12).all() and (v <= p.high + 1e-12).all(), p.name


def test_a_fit_at_a_bound_is_reported_at_that_bound():
    # the optimum lies beyond the high bound of the spring and the low one of the width
    out = dict(OPTIMUM, knee_spring=40.0, foot_width=0.010)
    ds = F.fit(_ctx(), rollout=_stub(out))
    bound = dict(zip(ds["parameter"].values, ds["fit_at_bound"].values))
    assert bound == dict(foot_length=0, foot_width=-1, knee_spring=1, drive_stiffness=0,
                         LEG_OFFSET=0)
    # foot_length 60-90 mm: within 0.6 mm (2 % of 30 mm) of a bound
    assert F.at_bound(S.PARAMETERS[:1], [0.0605]).tolist() == [-1]
    assert F.at_bound(S.PARAMETERS[:1], [0.0607]).tolist() == [0]
    assert F.at_bound(S.PARAMETERS[:1], [0.0895]).tolist() == [1]
    assert F.at_bound(S.PARAMETERS[:1], [0.0893]).tolist() == [0]


def test_each_local_start_spends_at_most_its_evaluations():
    stub = _stub()
    ds = F.fit(_ctx(dict(design_points=5, local_starts=3, local_evaluations=7)), rollout=stub)
    phase = ds["phase"].values
    assert len(phase) == 5 + 3 * 7
    assert [int((phase == k).sum()) for k in (0, 1, 2, 3)] == [5, 7, 7, 7]
    ds = F.fit(_ctx(dict(design_points=3, local_starts=0)), rollout=_stub())
    assert ds.sizes["evaluation"] == 3


def test_ties_go_to_the_earliest_evaluation():
    res = F.search(lambda u: 1.0, np.full((3, 2), 0.5), local_starts=1, local_evaluations=4)
    assert res["best"] == 0 and list(res["origin"]) == [0]
    res = F.search(lambda u: 0.0 if u[0] > 0.6 else 1.0, [[0.1, 0.1], [0.9, 0.9], [0.8, 0.8]],
                   local_starts=0, local_evaluations=4)
    assert res["best"] == 1


def test_the_design_is_reproducible_and_starts_at_the_current_values():
    fr = F.free()
    a = F.design(7, 32)
    assert a.shape == (32, 4) and np.array_equal(a, F.design(7, 32))
    assert not np.array_equal(a, F.design(8, 32))
    # the first point is the model's current values, the rest the seeded hypercube
    assert np.allclose(F.from_unit(fr, a[0]), [p.start for p in fr])
    lhs = qmc.LatinHypercube(d=4, rng=seeding.rng(7, "model/calibration/design")).random(31)
    assert np.array_equal(a[1:], lhs)
    # a Latin hypercube: each of 31 strata of every axis holds exactly one point
    for j in range(4):
        assert sorted(np.floor(a[1:, j] * 31).astype(int)) == list(range(31))
    # lengths and widths linear, the spring and the stiffness in log
    x = F.from_unit(fr, [[0.5] * 4])[0]
    assert x[0] == pytest.approx(0.075) and x[1] == pytest.approx(0.039)
    assert x[2] == pytest.approx(math.sqrt(10.0)) and x[3] == pytest.approx(20.0)
    assert np.allclose(F.to_unit(fr, F.from_unit(fr, a)), a)
    # the fit's first evaluation is the current values
    stub = _stub()
    F.fit(_ctx(dict(design_points=3, local_starts=0)), rollout=stub)
    assert stub.calls[0] == {p.name: p.start for p in S.PARAMETERS}


def test_tab3_1a_costs_nothing_between_its_two_speeds_and_the_log_error_outside():
    lo, hi = 0.27, 0.30
    assert F.squared_log_error(0.27, lo, hi) == 0.0
    assert F.squared_log_error(0.285, lo, hi) == 0.0
    assert F.squared_log_error(0.30, lo, hi) == 0.0
    assert F.squared_log_error(0.20, lo, hi) == pytest.approx(math.log(0.20 / 0.27) ** 2)
    assert F.squared_log_error(0.60, lo, hi) == pytest.approx(math.log(2.0) ** 2)
    assert math.isnan(F.squared_log_error(float("nan"), lo, hi))
    assert math.isnan(F.squared_log_error(-0.1, lo, hi))
    assert F.bands() == {"tab3_1a": (0.27, 0.30), "tab3_1b": (0.41, 0.41)}


def test_the_objective_adds_the_fall_penalty_and_the_undefined_cost_by_hand():
    bands = [(0.27, 0.30), (0.41, 0.41)]
    # no fall: Tab. 3.1a inside its band (0), Tab. 3.1b at 0.205 = half its speed
    o = F.objective([[0.28, 0.29], [0.205, 0.205]], [[0, 0], [0, 0]], bands)
    assert o["total"] == pytest.approx(math.log(2.0) ** 2)  # 0.480453
    assert o["cost"].tolist() == pytest.approx([0.0, 0.480453], abs=1e-6)
    # one start of Tab. 3.1a fell: its speed is the other start's (0.24), plus 0.25
    o = F.objective([[9.0, 0.24], [0.41, 0.41]], [[1, 0], [0, 0]], bands)
    assert o["speed"].tolist() == pytest.approx([0.24, 0.41])
    assert o["total"] == pytest.approx(math.log(0.24 / 0.27) ** 2 + 0.25)  # 0.263873
    # three starts, two of Tab. 3.1b fell: fewer than half up, no speed: 4.0 + 2 x 0.25
    o = F.objective([[0.30, 0.30, 0.30], [0.5, 0.5, 0.41]], [[0, 0, 0], [1, 1, 0]], bands)
    assert math.isnan(o["speed"][1]) and math.isnan(o["error"][1])
    assert o["falls"].tolist() == [0, 2]
    assert o["total"] == pytest.approx(4.0 + 0.5)
    # every start of both fell: 2 x 4.0 + 4 x 0.25
    o = F.objective([[0.3, 0.3], [0.4, 0.4]], [[1, 1], [1, 1]], bands)
    assert o["total"] == pytest.approx(9.0)
    assert S.PROCEDURE["fall_penalty"] == 0.25 and S.PROCEDURE["undefined_cost"] == 4.0


def test_the_fit_reads_only_the_fitted_side(guard):  # noqa: F811
    """The whole procedure of model/fit, its rollouts replaced by the known response,
    under test_split's guard (every judged-side paper key forbidden)."""
    stub = _stub()
    ds = F.fit(_ctx(dict(design_points=3, local_starts=1, local_evaluations=3)), rollout=stub)
    assert stub.calls and ds.sizes["evaluation"] == 6
    read = set(guard.keys)
    assert read and not read & S.paper_keys(S.JUDGED)
    assert {"fig3_4/gait=spline/frequency=1.5/speed", *S.parts(S.FITTED, "V1")[0].paper_keys
            } >= {k for k in read if not k.startswith("table3_1/gait=")}


def test_the_fit_is_registered_configured_and_run_only_by_name():
    assert registry.resolve("model/fit") is F.fit
    assert "model/fit" not in registry.VALIDATIONS["oncilla"]
    assert registry.OPTIONAL_VALIDATIONS["oncilla"] == ("model/fit",)
    assert registry.reads("model/fit")[0] == "physics.oncilla_fit"
    d = load_config("default")["physics"]["oncilla_fit"]
    assert (d["design_points"], d["local_starts"], d["local_evaluations"]) == (
        S.PROCEDURE["design_points"], S.PROCEDURE["local_starts"],
        S.PROCEDURE["local_evaluations"])
    assert d["starts"] is None and d["seconds"] is None  # the validation's, as declared
    assert [(c["gait"], c["frequency"]) for c in F.cases()] == list(S.PROCEDURE["cases"])
    assert {p.name for p in S.PARAMETERS} == set(F.SCALES)
    assert {p.name for p in S.PARAMETERS if not p.wired} == set(F.HELD)


def test_the_dataset_shows_whether_the_chapters_run_the_fit_and_the_report_renders_it():
    from thesis.report import validation as RV

    stub = _stub()
    ds = F.fit(_ctx(dict(design_points=3, local_starts=0)), rollout=stub)
    conf = dict(zip(ds["parameter"].values, ds["configured"].values))
    cfg = _ctx().full_config["ch4"]["model"]
    assert conf == dict(foot_length=cfg["foot_length"], foot_width=cfg["foot_width"],
                        knee_spring=cfg["knee_spring"], drive_stiffness=cfg["drive_stiffness"],
                        LEG_OFFSET=0.031)
    # the design's first point is the configured values: that evaluation matches them
    match = dict(zip(ds["parameter"].values, ds["configured_matches_fit"].values))
    assert match["LEG_OFFSET"] == 1
    fit = dict(zip(ds["parameter"].values, ds["fit_value"].values))
    for name in ("foot_length", "knee_spring"):
        assert match[name] == int(abs(conf[name] - fit[name]) <= 0.01 * abs(fit[name]))
    table = RV.fit_table({"model/fit": ds})
    assert [r[0] for r in table.rows] == list(ds["parameter"].values)
    assert table.rows[-1][4].endswith("(held)") and table.rows[-1][5] == "—"
    assert any("(not the fit)" in r[6] for r in table.rows) == (not all(match.values()))
    assert "of 3 evaluations" in table.note.replace("evaluation 1 of 3", "of 3 evaluations") \
        or f"of {ds.sizes['evaluation']}" in table.note
    assert "feet 'sphere', not the fitted plates" in table.note  # the smoke profile's feet
    assert RV.fit_table({}).rows == [["not run"] * 7]
