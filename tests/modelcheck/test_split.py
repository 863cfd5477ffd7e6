"""The declared split of the published Oncilla measurements (thesis.modelcheck.split): it is
disjoint, covers every sub-target of V1-V6 and every published number the targets read,
and the calibration reads only what the split puts on its fitted side."""

from __future__ import annotations

import ast
import inspect
import logging
import math
from types import SimpleNamespace

import numpy as np
import pytest

from thesis import paper
from thesis.config import load_config
from thesis.modelcheck import calibration as CAL
from thesis.modelcheck import fit as FIT
from thesis.modelcheck import split as S
from thesis.modelcheck import targets as TG
from thesis.modelcheck import validation as V

#: Prefixes of the paper keys of published gait parameter vectors (Tab. 3.1, Tab. 4.2-4.4):
#: the gaits run, inputs of the fit and of the validation alike, not measurements.
_GAIT_INPUTS = ("table3_1/gait=", "table4_2/", "table4_3/", "table4_4/")


def _is_gait_input(key: str) -> bool:
    return key.startswith(_GAIT_INPUTS) and not key.endswith("/speed")


class _Reads:
    """Records the paper keys read through ``paper.get``; raises on the forbidden ones and
    on any table or selection (a table hands out its measurements with its inputs)."""

    def __init__(self, forbidden=frozenset()):
        self.keys: list[str] = []
        self.forbidden = forbidden
        self._get = paper.get

    def get(self, key):
        if key in self.forbidden:
            raise AssertionError(f"read the validation-only measurement {key!r}")
        self.keys.append(key)
        return self._get(key)

    @staticmethod
    def table(*a, **k):
        raise AssertionError(f"read a whole table {a}")

    select = table


@pytest.fixture
def guard(monkeypatch):
    """The paper with every judged-side key forbidden."""
    reads = _Reads(S.paper_keys(S.JUDGED))
    monkeypatch.setattr(paper, "get", reads.get)
    monkeypatch.setattr(paper, "table", reads.table)
    monkeypatch.setattr(paper, "select", reads.select)
    return reads


def test_every_paper_key_of_the_split_exists_and_the_sides_are_disjoint():
    ids = [p.id for p in S.PARTS]
    assert len(ids) == len(set(ids))
    for p in S.PARTS:
        for k in p.paper_keys:
            paper.get(k)
        assert p.source and p.what and p.gaits, p.id
    assert S.paper_keys(S.FITTED) and S.paper_keys(S.JUDGED)
    assert not S.paper_keys(S.FITTED) & S.paper_keys(S.JUDGED)
    assert S.TARGETS == TG.ALL_TARGETS
    assert {p.target for p in S.PARTS} - {None} == set(TG.ALL_TARGETS)
    gaits = {g.name for g in TG.published_gaits()}
    assert all(set(p.gaits) <= gaits for p in S.PARTS)


@pytest.mark.parametrize("profile", ["smoke", "default"])
def test_every_sub_target_of_every_run_lies_on_exactly_one_side(profile):
    cs = V.cases(load_config(profile)["physics"]["oncilla_validation"])
    freqs = sorted({c["frequency"] for c in cs})
    # V1: its one case, fitted on
    assert S.part_of("V1", "tab3_1a", TG.V1_FREQUENCY).side == S.FITTED
    # V2: each published speed of the spline, 1.5 Hz fitted on, the fastest judged
    for f in TG.published_speeds()["v2"]:
        want = S.FITTED if math.isclose(f, S.FIT_FREQUENCY) else S.JUDGED
        assert S.part_of("V2", "tab3_1b", f).side == want
    # V3: every run of every case (part_of raises unless exactly one part takes it)
    sides = {(c["gait"], c["frequency"]): S.part_of("V3", c["gait"], c["frequency"]).side
             for c in cs}
    fitted = {k for k, s in sides.items() if s == S.FITTED}
    assert fitted == {("tab3_1a", S.FIT_FREQUENCY), ("tab3_1b", S.FIT_FREQUENCY)}
    # V4's three rules, V5 at every frequency, V6
    assert {S.part_of("V4", sub=s).side for s in ("V4a", "V4b", "V4c")} == {S.JUDGED}
    for f in freqs:
        want = S.FITTED if math.isclose(f, S.FIT_FREQUENCY) else S.JUDGED
        assert S.part_of("V5", "tab3_1b", f).side == want
    assert S.part_of("V6", "tab3_1b", 2.6).side == S.JUDGED


def test_a_broken_split_is_found():
    with pytest.raises(LookupError):
        S.part_of("V4", "tab3_1a", 1.5)  # two sub-targets take it: name one
    with pytest.raises(LookupError):
        S.part_of("V2", "tab3_1a", 1.5)  # no part of V2 runs the half ellipse


def test_every_published_number_the_targets_read_is_declared(monkeypatch):
    reads = _Reads()
    monkeypatch.setattr(paper, "get", reads.get)
    TG.published_speeds()
    speed = {("tab3_1a", f): 0.3 for f in (0.5, 1.0, 1.5, 2.0)}
    speed.update({("tab3_1b", f): 0.4 for f in (1.5, 2.0, 2.6)})
    TG.decide(speed, {k: 0.5 for k in speed}, 0, 10, 1.0)
    measured = {k for k in reads.keys if not _is_gait_input(k)}
    assert measured
    assert measured <= S.paper_keys(S.FITTED) | S.paper_keys(S.JUDGED)


def test_the_calibration_s_target_readers_read_only_the_fitted_side(guard):
    assert CAL.target_band() == pytest.approx((0.27, 0.30))
    assert CAL.target_speed() == pytest.approx(0.285)
    assert CAL.agreement_width() == pytest.approx(0.03)
    case = CAL.v1_case()
    assert case["gait"] == "tab3_1a" and case["frequency"] == TG.V1_FREQUENCY
    read = set(guard.keys)
    assert read and not read & S.paper_keys(S.JUDGED)
    assert {k for k in read if not _is_gait_input(k)} <= S.paper_keys(S.FITTED)
    # the gaits it reads are Tab. 3.1's (the fitted side's), not Tab. 4.2-4.4's
    assert all(k.startswith("table3_1/gait=") for k in read if _is_gait_input(k))


def test_the_calibration_end_to_end_reads_only_the_fitted_side(guard, monkeypatch):
    """The whole procedure of model/calibration, its rollouts replaced by a known response
    (speed linear in log k), under the guard."""
    calls = []

    def fake_measure(full, k, case, kicks, **kw):
        calls.append(k)
        v = 0.1 + 0.1 * math.log(k)
        n = len(kicks)
        m = dict(speed=np.full((1, n), v), fallen=np.zeros((1, n), bool),
                 compression=np.zeros((1, n)), wall=0.0)
        model = SimpleNamespace(dt=0.0025, solver_iterations=120, sweep_order="blocks_first",
                                relaxation=1.0, contact_relaxation=0.3)
        return m, model

    monkeypatch.setattr(CAL, "_measure", fake_measure)
    config = load_config("smoke")
    ctx = SimpleNamespace(full_config=config, root_seed=int(config["root_seed"]),
                          key="model/calibration", log=logging.getLogger("test"))
    ds = CAL.calibration(ctx)
    assert calls and int(ds["fit_holds"]) == 1
    assert not set(guard.keys) & S.paper_keys(S.JUDGED)


@pytest.mark.parametrize("module", [CAL, FIT], ids=["calibration", "fit"])
def test_the_calibration_and_the_fit_call_no_reader_of_the_judged_side(module):
    """Static: the calibration's and the fit's modules name none of the targets' readers
    that read validation-only numbers or gaits (the dynamic tests see only the paths run)."""
    tree = ast.parse(inspect.getsource(module))
    used = {(n.value.id, n.attr) for n in ast.walk(tree)
            if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name)}
    forbidden = {("TG", "published_speeds"), ("TG", "decide"), ("TG", "published_gaits"),
                 ("V", "cases"), ("V", "validation"), ("V", "convergence")}
    assert not used & forbidden, sorted(used & forbidden)


def test_parameters_are_inside_their_bounds_and_cite_a_source():
    names = [p.name for p in S.PARAMETERS]
    assert len(names) == len(set(names))
    for p in S.PARAMETERS:
        assert p.low < p.high and p.low <= p.start <= p.high, p.name
        assert "docs/sources.md#" in p.bounds_from, p.name
    with pytest.raises(ValueError, match="outside"):
        S.Parameter("x", "m", 0.0, 1.0, 2.0, "docs/sources.md#oncilla-feet")
    assert set(S.PROCEDURE["cases"]) == {(g, S.FIT_FREQUENCY) for p in S.parts(S.FITTED)
                                         for g in p.gaits}
