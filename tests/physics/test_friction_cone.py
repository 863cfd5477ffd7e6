"""Coulomb friction the same in every tangential direction (departure ch7.friction_cone).

A body that slides at any angle to the world axes meets ``mu`` times its normal force,
opposite to its slip: a box on a level floor decelerates at ``mu g`` along a straight
path whatever its heading, a box on a slope made by ``terrain.incline`` slides at the
closed form ``g (sin a - mu cos a)`` straight down the slope whatever the slope's
heading, and a directional material keeps its meaning in the frame of its grain, not the
world's. A world-aligned friction pyramid fails each of these off the axes (45 deg:
``sqrt(2) mu g``; its path bends towards an axis).
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, step, terrain

from .test_friction import DT, _velocities  # (n, 3) velocity of body 0 after each step

G = 9.81
HEADINGS = (0.0, 30.0, 45.0, 90.0, 135.0)


def _box(mu=0.3, vel=(0.0, 0.0, 0.0), yaw=0.0, direction=None, coefficients=None,
         dtype=jnp.float32, lift=0.0):
    """A 1 kg box (0.4 x 0.4 x 0.1 m) on four contact spheres on a level floor.

    ``yaw`` [rad] turns the box about z (and with it a friction ``direction`` given in
    the box's frame); ``coefficients`` = (lateral, forward, backward) of a directional
    material (the spheres then carry ``direction``)."""
    b = Builder("cone", dt=DT, solver_iterations=20, relaxation=0.5)
    if coefficients is None:
        b.add_material("m", mu, 0.0, 50.0, 1.0)
    else:
        lat, fwd, bwd = coefficients
        b.add_material("m", lat, 0.0, 50.0, 1.0, friction_forward=fwd,
                       friction_backward=bwd)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    c, s = np.cos(yaw), np.sin(yaw)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    b.add_box("box", (0.4, 0.4, 0.1), (0, 0, 0.1 + lift), mass=1.0, rot=rot)
    for sx in (-0.15, 0.15):
        for sy in (-0.15, 0.15):
            b.add_contact_sphere("box", 0.05, (sx, sy, -0.05), material="m",
                                 direction=direction)
    b.set_velocity("box", vel)
    return b.build(dtype)


def _heading(deg):
    h = np.deg2rad(deg)
    return np.array([np.cos(h), np.sin(h), 0.0])


def _fit(v, direction, sl):
    """(acceleration along ``direction``, acceleration across it) [m/s^2] fitted on ``sl``."""
    t = np.arange(len(v)) * DT
    side = np.cross([0.0, 0.0, 1.0], direction)
    return (np.polyfit(t[sl], v[sl] @ direction, 1)[0],
            np.polyfit(t[sl], v[sl] @ side, 1)[0])


@pytest.mark.parametrize("heading_deg", HEADINGS)
def test_box_on_a_level_floor_decelerates_at_mu_g_along_a_straight_path(heading_deg):
    mu, speed = 0.3, 2.0
    u = _heading(heading_deg)
    m, s = _box(mu, vel=tuple(speed * u))
    v = _velocities(m, s, 120)
    sl = slice(20, 100)  # settled contact, still sliding (stops after 2 / (mu g) = 0.68 s)
    along, across = _fit(v, u, sl)
    np.testing.assert_allclose(-along, mu * G, rtol=0.02)
    assert abs(across) < 0.01 * mu * G
    # the path keeps its heading: the velocity's direction within 0.5 deg while it slides
    angle = np.degrees(np.arctan2(v[sl, 1], v[sl, 0]))
    np.testing.assert_allclose(angle, heading_deg, atol=0.5)


@pytest.mark.parametrize("heading_deg", HEADINGS)
def test_slope_at_any_heading_slides_at_the_closed_form_straight_down(heading_deg):
    """20 deg slope, mu 0.2 < tan 20 deg: a = g (sin a - mu cos a) = 1.512 m/s^2 down the
    slope, nothing across it (in the slope's frame, where the floor stays level)."""
    mu, th = 0.2, np.deg2rad(20.0)
    m, s = _box(mu)
    v = _velocities(terrain.incline(m, th, np.deg2rad(heading_deg)), s, 200)
    down = -_heading(heading_deg)  # gravity's pull along the floor
    along, across = _fit(v, down, slice(100, 200))
    np.testing.assert_allclose(along, G * (np.sin(th) - mu * np.cos(th)), rtol=0.02)
    assert abs(across) < 0.01 * along


@pytest.mark.parametrize("yaw_deg", (0.0, 30.0, 45.0, 135.0))
@pytest.mark.parametrize("sense, mu_expected", [("forward", 0.2), ("backward", 0.6),
                                                ("across", 0.4)])
def test_directional_material_is_decided_in_the_grain_frame_not_the_world(
        yaw_deg, sense, mu_expected):
    """A box whose grain (body x) is turned by ``yaw`` in the world slides along its
    grain, against it or across it: the decelerations are mu_forward, mu_backward and
    the lateral mu times g, whatever the yaw, along a straight path."""
    lat, fwd, bwd = 0.4, 0.2, 0.6
    yaw = np.deg2rad(yaw_deg)
    grain = _heading(yaw_deg)
    u = {"forward": grain, "backward": -grain,
         "across": np.cross([0.0, 0.0, 1.0], grain)}[sense]
    speed = 2.5
    m, s = _box(vel=tuple(speed * u), yaw=yaw, direction=(1.0, 0.0, 0.0),
                coefficients=(lat, fwd, bwd))
    v = _velocities(m, s, 100)
    sl = slice(20, int(0.9 * speed / (mu_expected * G) / DT))
    along, across = _fit(v, u, sl)
    np.testing.assert_allclose(-along, mu_expected * G, rtol=0.03)
    assert abs(across) < 0.02 * mu_expected * G


@pytest.mark.parametrize("angle_deg", (30.0, 60.0))
def test_directional_slide_at_an_angle_to_the_grain_follows_the_friction_ellipse(angle_deg):
    """Sliding forward at ``angle`` to the grain (grain turned 20 deg in the world): the
    friction opposes the slip (straight path) with the elliptic bound
    ``|f| = mu_n / sqrt((cos/mu_forward)^2 + (sin/mu_lateral)^2)``."""
    lat, fwd, bwd = 0.5, 0.2, 0.8
    yaw = np.deg2rad(20.0)
    u = _heading(20.0 + angle_deg)
    m, s = _box(vel=tuple(2.5 * u), yaw=yaw, direction=(1.0, 0.0, 0.0),
                coefficients=(lat, fwd, bwd))
    v = _velocities(m, s, 100)
    a = np.deg2rad(angle_deg)
    mu_eff = 1.0 / np.sqrt((np.cos(a) / fwd) ** 2 + (np.sin(a) / lat) ** 2)
    along, across = _fit(v, u, slice(20, int(0.9 * 2.5 / (mu_eff * G) / DT)))
    np.testing.assert_allclose(-along, mu_eff * G, rtol=0.03)
    assert abs(across) < 0.02 * mu_eff * G


def test_equal_directional_coefficients_are_the_isotropic_cone_at_any_angle(x64):
    """mu_forward = mu_backward = mu_lateral: the directional model slides exactly like the
    isotropic one, at 37 deg to its grain."""
    vel = tuple(2.0 * _heading(37.0))
    m_iso, s_iso = _box(0.4, vel=vel, dtype=jnp.float64)
    m_dir, s_dir = _box(vel=vel, direction=(1.0, 0.0, 0.0), coefficients=(0.4, 0.4, 0.4),
                        dtype=jnp.float64)
    assert m_dir.directional and not m_iso.directional
    np.testing.assert_allclose(_velocities(m_dir, s_dir, 120), _velocities(m_iso, s_iso, 120),
                               atol=1e-6)


@pytest.mark.parametrize("tilt", (-1e-4, 0.0, 1e-4))
def test_grain_normal_to_the_floor_is_lateral_friction_not_round_off(tilt):
    """A grain (nearly) normal to the contact plane has no forward or backward: every
    tangential slide is across it, so the lateral coefficient holds in every direction,
    whatever the sign of a tiny tilt."""
    lat, fwd, bwd = 0.4, 0.1, 0.9
    for u in (_heading(0.0), _heading(90.0), _heading(-135.0)):
        m, s = _box(vel=tuple(2.0 * u), direction=(tilt, tilt, 1.0),
                    coefficients=(lat, fwd, bwd))
        along, across = _fit(_velocities(m, s, 80), u, slice(20, 80))
        np.testing.assert_allclose(-along, lat * G, rtol=0.03)
        assert abs(across) < 0.02 * lat * G


def _final_xy(m, s, n):
    body = lambda s, _: (step(m, s, jnp.zeros((0,), s.pos.dtype)), None)  # noqa: E731
    return jax.lax.scan(body, s, None, length=n)[0].pos[0, :2]


def test_gradients_are_finite_at_rest(x64):
    """A box resting on the floor (zero slip, friction inside the cone): d(final pose) /
    d(mu, initial velocity) is finite."""
    m, s = _box(0.3, dtype=jnp.float64)

    def loss(mu, vx):
        mm = terrain.set_material(m, "m", friction=mu)
        s0 = s.replace(vel=s.vel.at[0, 0].set(vx))
        return jnp.sum(_final_xy(mm, s0, 40))

    g = jax.jit(jax.grad(loss, argnums=(0, 1)))(0.3, 0.0)
    assert all(np.isfinite(float(x)) for x in g)


def test_gradient_through_the_stick_slip_transition_matches_finite_differences(x64):
    """A box launched at 30 deg stops within the rollout (slip, then stick): the gradient of
    its resting place with respect to the launch speed and to mu equals central differences
    and points along the launch direction."""
    u = _heading(30.0)
    m, s = _box(0.3, dtype=jnp.float64)

    def final(speed, mu):
        mm = terrain.set_material(m, "m", friction=mu)
        s0 = s.replace(vel=s.vel.at[0, :2].set(speed * jnp.asarray(u[:2])))
        return _final_xy(mm, s0, 120)  # stops after ~0.27 s, rests for the rest

    f = jax.jit(final)
    jac = jax.jit(jax.jacobian(final, argnums=(0, 1)))(0.8, 0.3)
    eps = 1e-6
    fd_v = (f(0.8 + eps, 0.3) - f(0.8 - eps, 0.3)) / (2 * eps)
    fd_mu = (f(0.8, 0.3 + eps) - f(0.8, 0.3 - eps)) / (2 * eps)
    for g, fd in zip(jac, (fd_v, fd_mu)):
        g = np.asarray(g)
        assert np.all(np.isfinite(g))
        np.testing.assert_allclose(g, np.asarray(fd), rtol=1e-4, atol=1e-8)
    # the stop distance grows with speed along the launch direction only
    gv = np.asarray(jac[0])
    assert gv @ u[:2] > 0 and abs(gv @ np.array([-u[1], u[0]])) < 1e-6 * abs(gv @ u[:2])
