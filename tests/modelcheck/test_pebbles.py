"""V7's runs (thesis.modelcheck.pebbles): the starts lie on the pebble strip and repeat from
the root seed, V7 is decided on the pebble runs (not the flat ones beside them), and a
non-finite simulation stops the check before anything is written. The runs themselves are
checked on the smoke pipeline's dataset (tests/pipeline/layouts_model.py)."""

from __future__ import annotations

import logging
from types import SimpleNamespace

import numpy as np
import pytest

from thesis.config import load_config
from thesis.errors import SimulationDiverged
from thesis.gaits import conditions as C
from thesis.modelcheck import pebbles as PB
from thesis.modelcheck import targets as TG


def test_starts_lie_on_the_strip_and_repeat_from_the_root_seed():
    ch4 = load_config("default")["ch4"]
    h, x = PB.pebble_starts(ch4, 7, 3, 50)
    assert h.shape == x.shape == (3, 50)
    lo, hi = C.start_range(ch4, "pebbly", PB.TR.protocol_times(ch4)[2])
    assert np.all((x >= lo) & (x <= hi)) and np.ptp(x) > 0.5 * (hi - lo)
    assert np.all(np.abs(h) <= np.deg2rad(ch4["reeval"]["heading_deg"]))
    h2, x2 = PB.pebble_starts(ch4, 7, 3, 50)
    assert np.array_equal(h, h2) and np.array_equal(x, x2)
    assert not np.array_equal(x, PB.pebble_starts(ch4, 8, 3, 50)[1])


def _ctx(starts=4):
    cfg = load_config("smoke")
    cfg["physics"]["oncilla_pebbles"]["starts"] = starts
    return SimpleNamespace(full_config=cfg, root_seed=int(cfg["root_seed"]),
                           log=logging.getLogger("test"))


def test_v7_is_decided_on_the_pebble_runs(monkeypatch):
    """Published speeds on pebbles, every start fallen on flat ground: V7 passes; the
    reverse fails it."""
    published = np.array(list(TG.pebble_speeds().values()))

    def runs(good):
        def run_floor(ch4, root_seed, floor, params, heading, forward, timing):
            g, r = heading.shape
            up = (floor == "pebbly") == good
            assert (forward is None) == (floor == "flat")
            return dict(speed=np.repeat(published[:, None], r, 1),
                        fallen=np.full((g, r), 0.0 if up else 1.0), score=np.zeros((g, r)),
                        taut=np.zeros((g, r)), thread_force=np.zeros((g, r)))
        return run_floor

    monkeypatch.setattr(PB, "run_floor", runs(True))
    ds = PB.pebbles(_ctx())
    assert ds["target_passed"].values.tolist() == [1]
    assert ds["case_falls"].sel(floor="flat").values.tolist() == [4, 4, 4]
    assert np.isnan(ds["case_speed"].sel(floor="flat").values).all()
    monkeypatch.setattr(PB, "run_floor", runs(False))
    ds = PB.pebbles(_ctx())
    assert ds["target_passed"].values.tolist() == [0]
    assert "4 of 4 fell" in str(ds["target_text"].values[0])


def test_a_non_finite_run_stops_the_check(monkeypatch):
    def evaluate(model, state, cfg, p_from, p_to, **kw):
        n = len(p_to)
        finite = np.ones(n, bool)
        finite[n - 1] = False
        return {k: np.zeros(n) for k in PB.FIELDS} | {"finite": finite}

    monkeypatch.setattr(PB.TR, "evaluate_particles", evaluate)
    monkeypatch.setattr(PB.C, "condition_model", lambda *a: (None, None))
    with pytest.raises(SimulationDiverged, match="model/pebbles:pebbly.*particle 2, repeat 1"):
        PB.pebbles(_ctx(starts=2))
