"""constraint.py + solver: joints, limits, springs, servos against closed forms."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, sensors, step

G = 9.81


def _scan(m, s, n, record, action=None):
    a = jnp.zeros((m.n_servo,)) if action is None else action
    f = jax.jit(lambda s: jax.lax.scan(lambda s, _: (step(m, s, a), record(m, s)), s, None,
                                       length=n))
    return f(s)


def _angle(m, s):
    return sensors(m, s)["joint_angle"]


def _period(x, dt):
    up = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    frac = -x[up] / (x[up + 1] - x[up])
    return np.mean(np.diff(up + frac)) * dt


def test_small_angle_pendulum_period():
    """A rigid pendulum's period: the hinge is declared stiff (1 kHz); the builder's
    default 100-Hz hinge is a compliant pivot whose period is ~1.2 % longer whatever the
    step (test_soft_hinge_period_does_not_depend_on_dt)."""
    length, r, dt = 1.0, 0.05, 0.001
    b = Builder("pend", dt=dt, solver_iterations=10, joint_hz=1000.0)
    b.add_sphere("bob", r, (0, 0, -length), rot=None)
    b.add_hinge("pivot", "world", "bob", (0, 0, 0), (0, 1, 0))
    b.set_velocity("bob", (0.05, 0, 0), (0, -0.05, 0))  # ~3 deg amplitude
    m, s = b.build(jnp.float32)
    _, q = _scan(m, s, 5000, _angle)
    mass = float(m.body_mass[0])
    inertia = 0.4 * mass * r * r + mass * length ** 2
    expected = 2 * np.pi * np.sqrt(inertia / (mass * G * length))
    np.testing.assert_allclose(_period(np.asarray(q)[:, 0], dt), expected, rtol=5e-3)


def _pendulum_period(dt, joint_hz=None, length=1.0, r=0.05):
    b = Builder("pend", dt=dt, solver_iterations=10, joint_hz=joint_hz)
    b.add_sphere("bob", r, (0, 0, -length), rot=None)
    b.add_hinge("pivot", "world", "bob", (0, 0, 0), (0, 1, 0))
    b.set_velocity("bob", (0.05, 0, 0), (0, -0.05, 0))  # ~3 deg amplitude
    m, s = b.build(jnp.float32)
    _, q = _scan(m, s, int(round(4.5 / dt)), _angle)
    return _period(np.asarray(q)[:, 0], dt)


def test_soft_hinge_period_does_not_depend_on_dt():
    """Joint softness is physical (builder.JOINT_HZ, independent of dt): the
    default-softness pendulum has one period at 2, 1 and 0.5 ms (a softness defined per
    step would make a different pivot at each step); a stiffer declared hinge
    gives a different period, so the check can tell softness apart."""
    periods = [_pendulum_period(dt) for dt in (0.002, 0.001, 0.0005)]
    np.testing.assert_allclose(periods, periods[0], rtol=1e-3)
    assert abs(_pendulum_period(0.001, joint_hz=1000.0) - periods[0]) > 5e-3 * periods[0]


@pytest.mark.slow
def test_hinge_chain_drift_bounded_over_10k_steps():
    b = Builder("chain", dt=0.01, solver_iterations=20)
    for i in range(3):
        b.add_box(f"l{i}", (0.05, 0.05, 0.3), (0.15 + 0.3 * i, 0, 1.0),
                  rot=np.array([[0, 0, 1.0], [0, 1, 0], [-1.0, 0, 0]]))
        b.add_hinge(f"h{i}", "world" if i == 0 else f"l{i - 1}", f"l{i}",
                    (0.3 * i, 0, 1.0), (0, 1, 0))
    m, s = b.build(jnp.float32)

    def gap(m, s):
        from thesis.physics import kinematics
        pos, rot = kinematics.extend(m, s.pos, s.rot)
        fr = kinematics.joint_frames(m, pos, rot)
        return jnp.max(jnp.abs(fr["x2"] - fr["x1"]))

    s, g = _scan(m, s, 10_000, gap)
    g = np.asarray(g)
    assert np.all(np.isfinite(g))
    print("gap max first/last 1000 steps", g[:1000].max(), g[-1000:].max())
    assert g.max() < 0.02  # metres, a 3-link chain falling from horizontal
    assert g[-1000:].max() <= g[:1000].max()  # no growth over 10^4 steps
    assert float(jnp.abs(s.vel).max()) > 0.1  # still moving: drift was tested in motion


def test_joint_limit_stops_at_bound():
    b = Builder("limit", dt=0.005, solver_iterations=20)
    b.add_box("arm", (0.5, 0.05, 0.05), (0.25, 0, 0))
    b.add_hinge("h", "world", "arm", (0, 0, 0), (0, -1, 0), limits=(-0.3, 0.3))
    m, s = b.build(jnp.float32)
    s, q = _scan(m, s, 400, _angle)
    q = np.asarray(q)[:, 0]
    assert q.min() > -0.3 - 0.02
    np.testing.assert_allclose(q[-1], -0.3, atol=0.01)


def test_slider_follows_gravity_along_axis_only():
    theta = 0.4
    b = Builder("slide", dt=0.01, gravity=(0, 0, -G))
    b.add_box("sled", (0.1, 0.1, 0.1), (0, 0, 0))
    b.add_slider("rail", "world", "sled", (np.cos(theta), 0, -np.sin(theta)))
    m, s = b.build(jnp.float32)
    s, q = _scan(m, s, 100, _angle)
    t = 1.0
    np.testing.assert_allclose(float(q[-1, 0]), 0.5 * G * np.sin(theta) * t * t, rtol=0.02)
    q_end = float(sensors(m, s)["joint_angle"][0])
    off_axis = np.asarray(s.pos[0]) - q_end * np.array([np.cos(theta), 0, -np.sin(theta)])
    assert np.abs(off_axis).max() < 1e-3
    np.testing.assert_allclose(np.asarray(s.rot[0]), np.eye(3), atol=1e-4)


def test_body_spring_and_joint_spring_periods():
    k, mass, dt = 400.0, 2.0, 0.001
    b = Builder("spring", dt=dt, gravity=(0, 0, 0))
    b.add_box("m", (0.1, 0.1, 0.1), (1.1, 0, 0), mass=mass)
    b.add_slider("rail", "world", "m", (1, 0, 0))
    b.add_spring("s", "world", "m", (0, 0, 0), (1.1, 0, 0), k, 0.0, rest_length=1.0)
    m, s = b.build(jnp.float32)
    _, q = _scan(m, s, 2000, _angle)
    x = np.asarray(q)[:, 0] + 0.1
    # implicit spring: period slightly longer than 2 pi sqrt(m/k) (numerical damping)
    np.testing.assert_allclose(_period(x, dt), 2 * np.pi * np.sqrt(mass / k), rtol=0.01)

    kt = 5.0
    b = Builder("tspring", dt=dt, gravity=(0, 0, 0))
    b.add_box("w", (0.4, 0.1, 0.1), (0, 0, 0), mass=3.0)
    b.add_hinge("h", "world", "w", (0, 0, 0), (0, 0, 1))
    b.add_joint_spring("h", kt, 0.0, rest_angle=0.0)
    b.set_velocity("w", (0, 0, 0), (0, 0, 0.5))
    m, s = b.build(jnp.float32)
    _, q = _scan(m, s, 3000, _angle)
    izz = 3.0 * (0.4 ** 2 + 0.1 ** 2) / 12
    np.testing.assert_allclose(_period(np.asarray(q)[:, 0], dt), 2 * np.pi * np.sqrt(izz / kt),
                               rtol=0.01)


def _servo_model(max_torque, max_velocity, kind="position"):
    b = Builder("servo", dt=0.005, gravity=(0, 0, 0), solver_iterations=20)
    b.add_box("w", (0.6, 0.1, 0.1), (0, 0, 0), mass=2.0)
    b.add_hinge("h", "world", "w", (0, 0, 0), (0, 0, 1))
    if kind == "position":
        b.add_position_servo("h", 30.0, max_torque, max_velocity)
    else:
        b.add_velocity_servo("h", max_torque)
    return b.build(jnp.float32)


def _vel(m, s):
    return sensors(m, s)["joint_velocity"]


def test_servo_step_response_limited_by_max_velocity():
    vmax = np.deg2rad(45.0)
    m, s = _servo_model(1e3, vmax)
    s, w = _scan(m, s, 300, _vel, action=jnp.asarray([1.0]))
    w = np.asarray(w)[:, 0]
    np.testing.assert_allclose(w[5:100], vmax, rtol=1e-3)  # slewing at max velocity
    q = float(sensors(m, s)["joint_angle"][0])
    np.testing.assert_allclose(q, 1.0, atol=2e-3)  # then settles on the target


def test_servo_step_response_limited_by_max_torque():
    tau = 0.5
    m, s = _servo_model(tau, 100.0)
    _, w = _scan(m, s, 40, _vel, action=jnp.asarray([1.0]))
    w = np.asarray(w)[:, 0]
    izz = 2.0 * (0.6 ** 2 + 0.1 ** 2) / 12
    t = np.arange(40) * 0.005  # recorded before each step
    np.testing.assert_allclose(w, tau / izz * t, rtol=1e-3)  # constant acceleration tau / I


def test_velocity_servo_reaches_command():
    m, s = _servo_model(1e3, 0.0, kind="velocity")
    _, w = _scan(m, s, 20, _vel, action=jnp.asarray([2.5]))
    np.testing.assert_allclose(np.asarray(w)[-1, 0], 2.5, rtol=1e-4)


def _pd_model(stiffness, damping, max_torque, max_velocity, *, load=0.0):
    """A bar on a vertical-axis hinge with a compliant drive; ``load`` [N] pushes its tip
    sideways (a body spring to a far anchor stands in for a constant force)."""
    # a stiff hinge (200 Hz): the drive's compliance is the one under test
    b = Builder("pd", dt=0.005, gravity=(0, 0, 0), solver_iterations=40, joint_hz=200.0)
    b.add_box("w", (0.6, 0.1, 0.1), (0.3, 0, 0), mass=2.0)
    b.add_hinge("h", "world", "w", (0, 0, 0), (0, 0, 1))
    b.add_compliant_servo("h", stiffness, damping, max_torque, max_velocity)
    if load:  # weak, long spring: ~constant force along +y at the tip
        k = 1.0
        b.add_box("anchor", (0.01, 0.01, 0.01), (0.6, load / k + 1.0, 0), mass=1.0)
        b.add_fixed("fix", "world", "anchor")
        b.add_spring("push", "w", "anchor", (0.6, 0, 0), (0.6, load / k + 1.0, 0), k, 0.0,
                     rest_length=1.0)
    return b.build(jnp.float32)


def test_compliant_drive_deflects_by_load_over_stiffness():
    k, load, lever = 20.0, 2.0, 0.6
    m, s = _pd_model(k, 0.4, 100.0, 100.0, load=load)
    s, _ = _scan(m, s, 2000, _angle, action=jnp.zeros((1,)))
    q = float(sensors(m, s)["joint_angle"][0])
    torque = load * lever * np.cos(q)  # the spring's force stays ~along +y
    np.testing.assert_allclose(q, torque / k, rtol=0.03)
    assert q > 0.04  # a hard position servo would hold q = 0 (see the next test)


def test_hard_servo_under_the_same_load_holds_its_command():
    b = Builder("servo", dt=0.005, gravity=(0, 0, 0), solver_iterations=40)
    b.add_box("w", (0.6, 0.1, 0.1), (0.3, 0, 0), mass=2.0)
    b.add_hinge("h", "world", "w", (0, 0, 0), (0, 0, 1))
    b.add_position_servo("h", 50.0, 100.0, 100.0)
    b.add_box("anchor", (0.01, 0.01, 0.01), (0.6, 3.0, 0), mass=1.0)
    b.add_fixed("fix", "world", "anchor")
    b.add_spring("push", "w", "anchor", (0.6, 0, 0), (0.6, 3.0, 0), 1.0, 0.0, rest_length=1.0)
    m, s = b.build(jnp.float32)
    s, _ = _scan(m, s, 2000, _angle, action=jnp.zeros((1,)))
    assert abs(float(sensors(m, s)["joint_angle"][0])) < 1e-3


def test_compliant_drive_free_response_is_a_damped_spring():
    """Unloaded step response: the implicit PD on a rotor of inertia I has the period
    2 pi / sqrt(k / I - (c / 2I)^2) of the damped oscillator."""
    k, c = 5.0, 0.05
    m, s = _pd_model(k, c, 1e3, 1e3)
    _, q = _scan(m, s, 4000, _angle, action=jnp.asarray([0.1]))
    izz = 2.0 * (0.6 ** 2 + 0.1 ** 2) / 12 + 2.0 * 0.3 ** 2  # box about the hinge
    wd = np.sqrt(k / izz - (c / (2 * izz)) ** 2)
    np.testing.assert_allclose(_period(np.asarray(q)[:, 0] - 0.1, 0.005), 2 * np.pi / wd,
                               rtol=0.02)
    np.testing.assert_allclose(np.mean(np.asarray(q)[-1000:, 0]), 0.1, atol=1e-3)  # centre


def test_compliant_drive_is_bounded_in_torque_and_speed():
    tau, vmax = 0.5, 1.0
    m, s = _pd_model(1e3, 10.0, tau, 1e3)
    _, w = _scan(m, s, 20, _vel, action=jnp.asarray([1.0]))
    izz = 2.0 * (0.6 ** 2 + 0.1 ** 2) / 12 + 2.0 * 0.3 ** 2
    t = np.arange(20) * 0.005
    # (the first steps carry the Jacobi sweeps' error on the off-centre hinge's block)
    np.testing.assert_allclose(np.asarray(w)[3:, 0], tau / izz * t[3:], rtol=5e-3)
    m, s = _pd_model(1e3, 1.0, 1e3, vmax)
    _, w = _scan(m, s, 200, _vel, action=jnp.asarray([1.0]))
    assert float(np.max(np.asarray(w)[:, 0])) <= vmax * (1 + 1e-3)
    np.testing.assert_allclose(np.asarray(w)[60:100, 0], vmax, rtol=1e-2)  # slewing


def test_compliant_drive_needs_positive_gains():
    b = Builder("pd")
    b.add_box("w", (0.6, 0.1, 0.1), (0.3, 0, 0), mass=2.0)
    b.add_hinge("h", "world", "w", (0, 0, 0), (0, 0, 1))
    with pytest.raises(ValueError, match="stiffness and damping must be positive"):
        b.add_compliant_servo("h", 0.0, 0.1, 1.0, 1.0)
