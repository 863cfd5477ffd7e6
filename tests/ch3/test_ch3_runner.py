"""Fitness (eq. 3.3) terms, detrending, circle fit and turning parameters of ch. 3."""

import importlib
import numpy as np
import pytest

from thesis.gaits import runner as R
from thesis.gaits import trajectories as T
from thesis.ch3 import turning as TU
# the module (the package re-exports the constructor under the same name)
O = importlib.import_module("thesis.physics.models.oncilla")


@pytest.fixture(scope="module")
def model():
    return O.oncilla()[0]


def _poses(model, yaw_amp_deg, pitch_amp_deg, n=200, period=50):
    """Synthetic trunk poses walking forward at 0.2 m/s while yawing/pitching."""
    nb = model.n_body
    t = np.arange(n) * R.COMMAND_PERIOD
    yaw = np.radians(yaw_amp_deg) * np.sin(2 * np.pi * np.arange(n) / period)
    pit = np.radians(pitch_amp_deg) * np.sin(2 * np.pi * np.arange(n) / period)
    pos = np.zeros((1, n, nb, 3))
    pos[0, :, 0, 0] = 0.2 * t
    pos[0, :, 0, 2] = 0.16
    rot = np.tile(np.eye(3), (1, n, nb, 1, 1))
    cy, sy, cp, sp = np.cos(yaw), np.sin(yaw), np.cos(pit), np.sin(pit)
    Rz = np.stack([np.stack([cy, -sy, 0 * cy], -1), np.stack([sy, cy, 0 * cy], -1),
                   np.stack([0 * cy, 0 * cy, 1 + 0 * cy], -1)], -2)
    Ry = np.stack([np.stack([cp, 0 * cp, sp], -1), np.stack([0 * cp, 1 + 0 * cp, 0 * cp], -1),
                   np.stack([-sp, 0 * cp, cp], -1)], -2)
    rot[0, :, 0] = Rz @ Ry
    return dict(pos=pos, rot=rot, t=t + R.COMMAND_PERIOD)


def test_sigma_terms_react_to_a_wobbling_led(model):
    still = R.fitness_terms(model, _poses(model, 0, 0), 0.0, 1.5, 0.1, 0.08)
    yawing = R.fitness_terms(model, _poses(model, 3, 0), 0.0, 1.5, 0.1, 0.08)
    pitching = R.fitness_terms(model, _poses(model, 0, 3), 0.0, 1.5, 0.1, 0.08)
    assert still["sigma_x"][0] < 1e-3 and still["sigma_y"][0] < 1e-3
    # yaw moves the LED sideways in the image (sigma_x), pitch vertically (sigma_y)
    assert yawing["sigma_x"][0] > 30 and yawing["sigma_y"][0] < 5
    assert pitching["sigma_y"][0] > 30 and pitching["sigma_x"][0] < 5
    # eq. 3.3: same distance, lower fitness, by exactly sigma_x / 150 + sigma_y / 300
    assert yawing["distance"][0] == pytest.approx(still["distance"][0], abs=1e-9)
    assert yawing["fitness"][0] == pytest.approx(
        yawing["distance"][0] - yawing["sigma_x"][0] / 150 - yawing["sigma_y"][0] / 300)
    assert yawing["fitness"][0] < still["fitness"][0] - 0.2


def test_fallen_robot_ranks_below_walking_ones(model):
    """A robot that rolled onto its side and lies still (LED steady, no distance) would
    score about 0 by eq. 3.3, more than a walking gait with some wobble; it must lose."""
    walking = _poses(model, 3, 3)
    lying = _poses(model, 0, 0)
    lying["pos"][0, :, 0, 0] = 0.0
    lying["pos"][0, 50:100, 0, 2] = np.linspace(0.16, 0.05, 50)  # sinks to the floor
    lying["pos"][0, 100:, 0, 2] = 0.05
    roll = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], float)  # 90 degrees about x
    lying["rot"][0, 100:, 0] = roll
    w = R.fitness_terms(model, walking, 0.0, 1.5, 0.1, 0.08)
    f = R.fitness_terms(model, lying, 0.0, 1.5, 0.1, 0.08)
    assert not w["fallen"][0] and np.isfinite(w["fitness"][0])
    assert f["fallen"][0] and f["fitness"][0] < w["fitness"][0] - 50
    # ranked by the fraction of the 2 s window it stayed up (trunk above 0.08 m)
    k = int(np.argmax(lying["pos"][0, :, 0, 2] < 0.08))
    assert f["fitness"][0] == pytest.approx(R.FALLEN_FITNESS + lying["t"][k] / 2.0, abs=1e-9)
    # the distance is still reported (for the datasets), only the fitness is -inf
    assert f["distance"][0] == pytest.approx(0.0, abs=1e-9)


def test_led_centred_when_straight_ahead(model):
    uv = R.led_pixels(model, _poses(model, 0, 0)["pos"][:, :1], _poses(model, 0, 0)["rot"][:, :1],
                      1.5, 0.1)
    assert uv[0, 0, 0] == pytest.approx(511.5, abs=1e-3)  # horizontal centre of 1024
    assert uv[0, 0, 1] > 383.5  # LED below the camera: lower half of the image


def test_detrend_removes_slow_drift_keeps_gait_wobble():
    k = np.arange(400)
    drift = np.linspace(0, 300, 400)
    wobble = 20 * np.sin(2 * np.pi * k / 50)
    d = R.detrend(drift + wobble, 50)
    inner = d[50:-50]
    assert np.std(inner) == pytest.approx(np.std(wobble[50:-50]), rel=0.05)
    assert abs(np.mean(inner)) < 1.0


def test_circle_fit_recovers_a_known_circle():
    rng = np.random.default_rng(0)
    th = np.linspace(0.3, 2.0, 120)
    xy = np.stack([1.0 + 0.45 * np.cos(th), -2.0 + 0.45 * np.sin(th)], -1)
    xy += 1e-3 * rng.standard_normal(xy.shape)
    c, r = R.fit_circle(xy)
    assert r == pytest.approx(0.45, abs=5e-3)
    assert np.allclose(c, [1.0, -2.0], atol=1e-2)
    _, r_line = R.fit_circle(np.stack([np.linspace(0, 1, 50), np.zeros(50)], -1))
    assert r_line > 100


def test_yaw_unwraps_full_turns():
    a = np.linspace(0, 4 * np.pi, 200)
    rot = np.zeros((200, 3, 3))
    rot[:, 0, 0], rot[:, 1, 0] = np.cos(a), np.sin(a)
    assert R.yaw_of(rot)[-1] == pytest.approx(4 * np.pi, abs=1e-6)


def test_strategy_params():
    fam = T.EllipseGait()
    p0 = fam.project(np.array([140.0, 0.0, 0.0, 70.0, 20.0, 20.0, 0.5, 1.5]))
    ia, idu = fam.index("a"), fam.index("duty")
    p, yaw = TU.strategy_params(fam, p0, "step_size", reduced_a=20, slow_duty=0.7, yaw_deg=20)
    assert list(p[ia]) == [20.0, p0[ia], 20.0, p0[ia]] and not yaw.any()
    p, _ = TU.strategy_params(fam, p0, "step_size_constant_speed", reduced_a=20,
                              slow_duty=0.7, yaw_deg=20)
    v = np.asarray(fam.speed(p.T))  # stance speed 2 a f / duty per leg
    assert np.allclose(v, v[1])
    p, _ = TU.strategy_params(fam, p0, "step_speed", reduced_a=20, slow_duty=0.7, yaw_deg=20)
    assert list(p[idu]) == [0.7, 0.5, 0.7, 0.5] and np.all(p[ia] == p0[ia])
    _, yaw = TU.strategy_params(fam, p0, "scapulae", reduced_a=20, slow_duty=0.7, yaw_deg=20)
    assert np.allclose(np.degrees(yaw), [20, 20, -20, -20])


def test_torque_limits_scale_inner_hip_and_knee(model):
    lim = TU.torque_limits(model, 0.3)
    base = np.asarray(model.servo_max_torque)
    for i, name in enumerate(model.servo_names):
        leg, joint = name.split("_")
        factor = 0.3 if leg in ("LF", "LH") and joint != "scapula" else 1.0
        assert lim[i] == pytest.approx(base[i] * factor)
