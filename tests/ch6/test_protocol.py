"""The phases of §6.4 as per-step signals."""

from __future__ import annotations

import numpy as np

from thesis.ch6 import protocol as PR

SCH = PR.Schedule(settle=0.5, normalisation=5.0, stage1=10.0, stage2=10.0, running=30.0,
                  off=1.0, recovery=10.0)
DT = 0.0082


def test_bounds_follow_the_thesis_order():
    b = SCH.bounds()
    assert b["normalisation"] == (0.5, 5.5)
    assert b["stage1"] == (5.5, 15.5) and b["stage2"] == (15.5, 25.5)
    assert b["running"] == (25.5, 55.5) and b["off"] == (55.5, 56.5)
    assert SCH.total == 66.5


def test_signals_of_each_phase():
    n = PR.n_steps(SCH.total, DT)
    s = PR.signals(SCH, DT, n)
    t = np.arange(n) * DT
    at = lambda sec: int(round(sec / DT))  # noqa: E731
    assert s["stats"][at(1.0)] == 1 and s["stats"][at(0.2)] == 0 and s["stats"][at(6.0)] == 0
    assert s["learn"][at(5.6)] == 1 and s["learn"][at(25.4)] == 1 and s["learn"][at(25.6)] == 0
    assert s["share"][at(15.0)] == 1.0 and s["share"][at(26.0)] == 0.0
    np.testing.assert_allclose(s["share"][at(20.5)], 0.5, atol=DT / 10 + 1e-6)  # linear ramp
    ramp = s["share"][(t > 15.6) & (t < 25.4)]
    assert np.all(np.diff(ramp) < 0)
    assert s["torque"][at(56.0)] == 0 and s["torque"][at(55.0)] == 1 and s["torque"][at(57.0)] == 1
    assert abs((s["torque"] == 0).sum() - 1.0 / DT) <= 1  # 1 s of motors off


def test_phase1_only_and_open_loop():
    p1 = PR.Schedule(**{**SCH.__dict__, "stage2": 0.0})
    n = PR.n_steps(p1.total, DT)
    s = PR.signals(p1, DT, n)
    at = lambda sec: int(round(sec / DT))  # noqa: E731
    assert s["share"][at(15.4)] == 1.0 and s["share"][at(15.6)] == 0.0  # no mixing stage
    assert s["learn"][at(15.6)] == 0
    o = PR.signals(SCH, DT, PR.n_steps(SCH.total, DT), open_loop=True)
    assert np.all(o["share"] == 1) and np.all(o["learn"] == 0)
    assert o["torque"].min() == 0  # the power-off test still happens


def test_windows():
    w = PR.window(SCH, "running", DT, last=10.0)
    assert abs(w.start * DT - 45.5) < DT and abs(w.stop * DT - 55.5) < DT
    r = PR.window(SCH, "recovery", DT, skip=5.0)
    assert abs(r.start * DT - 61.5) < DT and abs(r.stop * DT - 66.5) < DT
    f = PR.window(SCH, "stage1", DT)
    assert abs(f.start * DT - 5.5) < DT and abs(f.stop * DT - 15.5) < DT
