"""collision.py + contact rows: friction, rolling, restitution, slopes, sphere pairs."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, sensors, step

G = 9.81


def _scan(m, s, n, record=lambda s: s.pos[0]):
    f = jax.jit(lambda s: jax.lax.scan(
        lambda s, _: (step(m, s, jnp.zeros((m.n_servo,))), record(s)), s, None, length=n))
    return f(s)


def test_sliding_box_decelerates_at_mu_g():
    mu = 0.3
    b = Builder("slide", dt=0.005, solver_iterations=20)
    b.add_material("m", mu, 0.0, 50.0, 1.0)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    b.add_box("box", (0.4, 0.4, 0.1), (0, 0, 0.1))
    for x in (-0.15, 0.15):
        for y in (-0.15, 0.15):
            b.add_contact_sphere("box", 0.05, (x, y, -0.05))
    b.set_velocity("box", (2.0, 0.0, 0.0))
    m, s = b.build(jnp.float32)
    s, vx = _scan(m, s, 120, lambda s: s.vel[0, 0])
    vx = np.asarray(vx)
    t = np.arange(vx.size) * 0.005
    sl = slice(20, 100)  # settled contact, still sliding (stops at 2 / (mu g) = 0.68 s)
    decel = -np.polyfit(t[sl], vx[sl], 1)[0]
    np.testing.assert_allclose(decel, mu * G, rtol=0.02)


def test_ball_rolls_without_slipping():
    b = Builder("roll", dt=0.005, solver_iterations=4, relaxation=1.0)
    b.add_material("m", 1.0, 0.0, 50.0, 1.0)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    r = 0.5
    b.add_sphere("ball", r, (0, 0, r))
    b.add_contact_sphere("ball", r)
    b.set_velocity("ball", (3.0, 0.0, 0.0))
    m, s = b.build(jnp.float32)
    s, _ = _scan(m, s, 300)
    v, w = float(s.vel[0, 0]), float(s.angvel[0, 1])
    np.testing.assert_allclose(v, w * r, rtol=2e-3)  # v = omega r
    np.testing.assert_allclose(v, 3.0 * 5 / 7, rtol=5e-3)  # solid sphere: v0 * 5/7


def test_bounce_height_ratio_is_e_squared():
    e, r, h0 = 0.5, 0.1, 1.0
    b = Builder("bounce", dt=0.001, solver_iterations=4, relaxation=1.0,
                restitution_threshold=0.0)
    b.add_material("m", 0.0, e, 250.0, 1.0)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    b.add_sphere("ball", r, (0, 0, r + h0))
    b.add_contact_sphere("ball", r)
    m, s = b.build(jnp.float32)
    _, z = _scan(m, s, 1600, lambda s: s.pos[0, 2])
    z = np.asarray(z) - r
    first_contact = np.argmax(z < 0.0)
    apex = z[first_contact:].max()
    np.testing.assert_allclose(apex / h0, e * e, rtol=0.04)


def test_slope_rolling_and_sliding_accelerations():
    theta = np.deg2rad(20.0)
    n = (-np.sin(theta), 0.0, np.cos(theta))  # plane rising towards -x ... normal tilted
    acc = {}
    for mu in (0.0, 1.0):
        b = Builder("slope", dt=0.005, solver_iterations=4, relaxation=1.0)
        b.add_material("m", mu, 0.0, 50.0, 1.0)
        b.add_plane("slope", n, 0.0, "m")
        r = 0.2
        b.add_sphere("ball", r, np.array(n) * r)
        b.add_contact_sphere("ball", r)
        m, s = b.build(jnp.float32)
        _, v = _scan(m, s, 200, lambda s: s.vel[0])
        v = np.asarray(v)
        t = np.arange(len(v)) * 0.005
        along = v @ np.array([np.cos(theta), 0.0, np.sin(theta)])
        acc[mu] = np.polyfit(t[40:], along[40:], 1)[0]
        assert np.abs(v[40:] @ np.asarray(n)).max() < 1e-2  # stays on the plane
    np.testing.assert_allclose(-acc[0.0], G * np.sin(theta), rtol=0.01)
    np.testing.assert_allclose(-acc[1.0], 5 / 7 * G * np.sin(theta), rtol=0.01)


def test_sphere_sphere_elastic_collision_exchanges_velocities():
    b = Builder("pool", dt=0.001, gravity=(0, 0, 0), solver_iterations=8, relaxation=1.0,
                restitution_threshold=0.0)
    b.add_sphere("a", 0.1, (-0.3, 0, 0))
    b.add_sphere("b", 0.1, (0.0, 0, 0))
    ia = b.add_contact_sphere("a", 0.1)
    ib = b.add_contact_sphere("b", 0.1)
    b.add_material("elastic", 0.0, 1.0, 500.0, 1.0)
    b.add_sphere_pair(ia, ib, "elastic")
    b.set_velocity("a", (1.0, 0, 0))
    m, s = b.build(jnp.float32)
    s, _ = _scan(m, s, 300)
    np.testing.assert_allclose(np.asarray(s.vel[:, 0]), [0.0, 1.0], atol=0.02)
    np.testing.assert_allclose(float(jnp.sum(s.vel[:, 0] * m.body_mass)),
                               float(m.body_mass[0]), rtol=1e-4)


def test_torsional_friction_stops_spin_and_resting_contact_force():
    out = {}
    for tors in (0.0, 0.02):
        b = Builder("spin", dt=0.005, solver_iterations=4, relaxation=1.0)
        b.add_material("m", 0.8, 0.0, 50.0, 1.0, torsional=tors)
        b.add_plane("floor", (0, 0, 1), 0.0, "m")
        b.add_sphere("ball", 0.1, (0, 0, 0.1))
        b.add_contact_sphere("ball", 0.1)
        b.set_velocity("ball", (0, 0, 0), (0, 0, 5.0))
        m, s = b.build(jnp.float32)
        s, _ = _scan(m, s, 200)
        out[tors] = float(s.angvel[0, 2])
        force = float(sensors(m, s)["contact_force"][0])
        np.testing.assert_allclose(force, float(m.body_mass[0]) * G, rtol=1e-3)
    assert out[0.0] > 4.99
    # torque bound tors * m g against inertia 0.4 m r^2: spin decays at 25 * tors * g / 0.4
    assert out[0.02] < 0.05


def _resting_depth(mass, stiffness, damping, dt=0.005, seconds=1.0):
    """Depth [m] below the floor of a sphere of ``mass`` [kg] resting on a contact of
    ``stiffness`` [N/m] and ``damping`` [N s/m], averaged over the last 0.2 s."""
    r = 0.012
    b = Builder("rest", dt=dt, solver_iterations=20, relaxation=1.0)
    b.add_material("m", 0.6, 0.0, 50.0, 1.0, stiffness=stiffness, damping=damping)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    b.add_sphere("paw", r, (0, 0, r), mass=mass)
    b.add_contact_sphere("paw", r)
    m, s = b.build(jnp.float32)
    assert m.absolute_contact
    n = int(round(seconds / dt))
    _, z = _scan(m, s, n, lambda s: s.pos[0, 2])
    return r - float(np.mean(np.asarray(z)[-int(round(0.2 / dt)):]))


def test_contact_in_physical_units_sinks_weight_over_stiffness():
    """A material with a stiffness [N/m] is a spring in physical units: a resting sphere
    sinks m g / k whatever its mass (a relative softness would scale k with the mass),
    at a stiffness the 5-ms step does not resolve (k = 16 kN/m under 0.375 kg rings at
    33 Hz: the implicit spring stays stable)."""
    for mass, k in ((0.375, 16e3), (1.5, 16e3), (0.375, 4e3)):
        c = 2.0 * 0.1 * np.sqrt(k * mass)
        np.testing.assert_allclose(_resting_depth(mass, k, c), mass * G / k, rtol=0.03)


def test_relative_contact_model_has_no_physical_unit_rows():
    """A model whose materials have no stiffness keeps the relative softness (its rows'
    program is the one of before the option), and set_material refuses a stiffness on it."""
    from thesis.physics import set_material

    b = Builder("rel", dt=0.005)
    b.add_material("m", 0.6, 0.0, 50.0, 1.0)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    b.add_sphere("ball", 0.1, (0, 0, 0.1))
    b.add_contact_sphere("ball", 0.1)
    m, _ = b.build(jnp.float32)
    assert not m.absolute_contact
    with pytest.raises(ValueError, match="physical"):
        set_material(m, "m", stiffness=1e4)
    with pytest.raises(ValueError, match="damping only with a stiffness"):
        b.add_material("x", 0.6, 0.0, 50.0, 1.0, damping=1.0)
