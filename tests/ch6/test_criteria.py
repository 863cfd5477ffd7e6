"""Success criteria and outcomes of a run (§6.4), on synthetic recordings."""

from __future__ import annotations

import numpy as np
import pytest

from thesis.ch6 import criteria as K
from thesis.ch6 import protocol as PR

DT = 0.0082
F = 1.7
CRIT = dict(fall_height=0.08, window=10.0, amplitude_min=0.5, amplitude_max=2.0,
            frequency_tolerance=0.1, autocorrelation_min=0.5, recovery_within=5.0,
            min_speed=0.05)
SCH = PR.Schedule(settle=0.5, normalisation=5.0, stage1=10.0, stage2=10.0, running=30.0,
                  off=1.0, recovery=10.0)
N = PR.n_steps(SCH.total, DT)
T = np.arange(N) * DT


def _gait(t, amp=1.0, f=F):
    """(T, 8) hip and knee signals: a fundamental and a second harmonic per joint."""
    return np.stack([amp * (0.3 * np.sin(2 * np.pi * f * t + k)
                            + 0.1 * np.sin(4 * np.pi * f * t + 2 * k)) for k in range(8)], 1)


def _run(output=None, height=0.15, up=1.0, speed=0.2):
    teacher = _gait(T)
    out = teacher.copy() if output is None else output
    pos = np.zeros((N, 3))
    pos[:, 0] = speed * T
    pos[:, 2] = height
    return out, teacher, pos, np.full(N, up)


def _eval(out, teacher, pos, up):
    return K.evaluate(out, teacher, pos, up, SCH, DT, 1 / F, CRIT)


def test_a_copy_of_the_teacher_is_stable():
    m = _eval(*_run())
    assert m["outcome"] == "stable" and m["success"] == 1.0
    assert m["amplitude"] == pytest.approx(1.0)
    assert m["frequency"] == pytest.approx(F, rel=0.02)
    assert m["autocorrelation"] > 0.95 and m["speed"] == pytest.approx(0.2, rel=1e-6)


def test_output_that_dies_out():
    out, teacher, pos, up = _run()
    run0 = PR.n_steps(SCH.bounds()["running"][0], DT)
    out[run0:] *= np.exp(-(T[run0:] - T[run0]))[:, None]
    assert _eval(out, teacher, pos, up)["outcome"] == "dies_out"


@pytest.mark.parametrize("kind", ["noise", "wrong_frequency", "too_large"])
def test_erratic_output(kind):
    out, teacher, pos, up = _run()
    rng = np.random.default_rng(0)
    if kind == "noise":
        out = rng.standard_normal(out.shape) * teacher.std(0)
    elif kind == "wrong_frequency":
        out = _gait(T, f=1.3 * F)
    else:
        out = 3.0 * out
    m = _eval(out, teacher, pos, up)
    assert m["outcome"] == "erratic" and m["success"] == 0.0


def test_no_return_after_power_on():
    out, teacher, pos, up = _run()
    off0 = PR.n_steps(SCH.bounds()["off"][0], DT)
    out[off0:] = out[off0]  # a fixed point after the power-off
    m = _eval(out, teacher, pos, up)
    assert m["outcome"] == "no_return" and m["stable_running"] == 1.0 and m["recovered"] == 0.0
    out, teacher, pos, up = _run()
    pos[off0:, 0] = pos[off0, 0]  # gait back, but no forward speed
    assert _eval(out, teacher, pos, up)["outcome"] == "no_return"
    out, teacher, pos, up = _run()
    pos[off0:, 2] = 0.05  # stays lying on the floor
    assert _eval(out, teacher, pos, up)["outcome"] == "no_return"


def test_fallen_during_running_but_not_during_power_off():
    out, teacher, pos, up = _run()
    b = SCH.bounds()
    k = PR.n_steps(b["running"][0] + 3.0, DT)
    up[k:] = -1.0
    assert _eval(out, teacher, pos, up)["outcome"] == "fallen"
    out, teacher, pos, up = _run()
    off = PR.window(SCH, "off", DT)
    pos[off, 2] = 0.05  # lying down while the motors are off is not a fall
    assert _eval(out, teacher, pos, up)["outcome"] == "stable"


def test_helpers():
    x = _gait(np.arange(1220) * DT)
    assert K.autocorrelation(x, int(round(1 / F / DT))) > 0.95
    assert K.autocorrelation(np.ones((100, 2)), 10) == 0.0
    assert K.dominant_frequency(x, DT) == pytest.approx(F, rel=0.02)
    assert K.fallen(np.array([[0, 0, 0.15], [0, 0, 0.9]]), np.ones(2), 0.08, DT)  # exploded
    assert not K.fallen(np.array([[0, 0, 0.15], [0.001, 0, 0.15]]), np.ones(2), 0.08, DT)


def test_cycle_multiplier_reads_the_decay_per_period():
    """A teacher sine and an output whose amplitude shrinks by 0.8 per period: the
    per-period amplitudes fall geometrically and the multiplier is 0.8; a sustained
    oscillation gives 1; an output at rest is floored, not log(0)."""
    n, k = 40, 12
    t = np.arange(n * k)
    teacher = np.sin(2 * np.pi * t / n)[:, None] * np.ones((1, 3))
    decay = 0.8 ** (t / n)
    amps = K.amplitude_by_period(teacher * decay[:, None], teacher, n)
    assert amps.shape == (k,)
    np.testing.assert_allclose(amps[1:] / amps[:-1], 0.8, rtol=1e-3)
    assert K.cycle_multiplier(amps) == pytest.approx(0.8, rel=1e-3)
    assert K.cycle_multiplier(K.amplitude_by_period(teacher, teacher, n)) == pytest.approx(1.0)
    rest = K.amplitude_by_period(np.zeros_like(teacher), teacher, n)
    assert K.cycle_multiplier(rest) == pytest.approx(1.0)  # at the floor throughout
    assert np.isnan(K.cycle_multiplier(amps[:1]))
