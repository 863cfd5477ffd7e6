"""terrain.py: slopes by rotated gravity, floor materials as leaves, per-robot terrains."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, batched_rollout, rollout, step, terrain

G = 9.81


def _block(normal=(0.0, 0.0, 1.0), mu=0.2, dtype=jnp.float32, lift=0.002):
    """A 1 kg box on four contact spheres, ``lift`` [m] above the plane with ``normal``
    through the origin (dropped, so that no contact sits exactly at zero gap, where
    round-off decides whether it is active), floor material ``"floor"``."""
    n = np.asarray(normal, np.float64)
    n /= np.linalg.norm(n)
    x = np.cross([0.0, 1.0, 0.0], n)  # slope direction in the x-z plane (normal about y)
    x /= np.linalg.norm(x)
    rot = np.stack([x, np.cross(n, x), n], axis=1)
    b = Builder("block", dt=0.005, solver_iterations=20, relaxation=0.5)
    b.add_material("floor", mu, 0.0, 50.0, 1.0)
    b.add_plane("floor", n, 0.0, "floor")
    b.add_box("box", (0.2, 0.2, 0.1), rot @ np.array([0.0, 0.0, 0.1 + lift]), rot=rot, mass=1.0)
    for sx in (-0.08, 0.08):
        for sy in (-0.08, 0.08):
            b.add_contact_sphere("box", 0.05, (sx, sy, -0.05))
    return b.build(dtype)


def _scan(m, s, n):
    def body(s, _):
        s = step(m, s, jnp.zeros((0,), s.pos.dtype))
        return s, (s.pos[0], s.vel[0])
    return jax.lax.scan(body, s, None, length=n)[1]


def test_incline_is_the_tilted_plane_seen_in_its_own_frame(x64):
    """Gravity rotated by theta on a level floor = the floor tilted by theta under vertical
    gravity, in the slope's frame (the stand-in of terrain.incline)."""
    theta = np.deg2rad(25.0)
    n = (-np.sin(theta), 0.0, np.cos(theta))  # the plane rises towards +x
    m_tilt, s_tilt = _block(n, dtype=jnp.float64)
    m_flat, s_flat = _block(dtype=jnp.float64)
    m_flat = terrain.incline(m_flat, theta)
    pos_t, vel_t = jax.jit(lambda s: _scan(m_tilt, s, 200))(s_tilt)
    pos_f, vel_f = jax.jit(lambda s: _scan(m_flat, s, 200))(s_flat)
    x = np.array([np.cos(theta), 0.0, np.sin(theta)])
    frame = np.stack([x, [0.0, 1.0, 0.0], n])  # world -> slope coordinates
    np.testing.assert_allclose(np.asarray(pos_t) @ frame.T, pos_f, atol=1e-9)
    np.testing.assert_allclose(np.asarray(vel_t) @ frame.T, vel_f, atol=1e-9)
    # mu = 0.2 < tan 25 deg: slides down (towards -x) at g (sin - mu cos)
    acc = np.polyfit(np.arange(100, 200) * 0.005, np.asarray(vel_f)[100:, 0], 1)[0]
    np.testing.assert_allclose(acc, -G * (np.sin(theta) - 0.2 * np.cos(theta)), rtol=0.01)


def test_one_compiled_rollout_serves_two_terrains():
    m, s = _block(mu=0.5)
    traces = []

    def run(model):
        traces.append(1)
        return _scan(model, s, 150)[1][:, 0]

    f = jax.jit(run)
    flat = np.asarray(f(m))
    steep = np.asarray(f(terrain.set_material(terrain.incline(m, np.deg2rad(30.0)),
                                              "floor", friction=0.2)))
    assert len(traces) == 1  # the second terrain reused the compiled rollout
    assert np.abs(flat).max() < 1e-3  # level floor: the block stays
    acc = np.polyfit(np.arange(75, 150) * 0.005, steep[75:], 1)[0]
    th = np.deg2rad(30.0)
    np.testing.assert_allclose(acc, -G * (np.sin(th) - 0.2 * np.cos(th)), rtol=0.01)
    # tan 30 deg = 0.577 > 0.5 > tan 25 deg: with the floor's own friction it slides at
    # 30 deg but sticks at 25 deg
    # (the 20-sweep parallel solver leaves a creep of a few mm/s on the slope, against
    # the metres per second of the sliding block)
    stick = np.asarray(f(terrain.incline(m, np.deg2rad(25.0))))
    assert np.abs(stick[75:]).max() < 0.01
    assert len(traces) == 1


def test_incline_grade_and_magnitude():
    m, _ = _block()
    a = terrain.grade_angle(0.09)
    np.testing.assert_allclose(np.rad2deg(a), 5.14, atol=0.005)  # §4.6.1 "a 5.14° slope"
    np.testing.assert_allclose(np.rad2deg(terrain.grade_angle(0.18)), 10.2, atol=0.005)
    g = np.asarray(terrain.incline(m, a, heading=np.pi / 2).gravity)
    np.testing.assert_allclose(np.linalg.norm(g), G, rtol=1e-6)
    np.testing.assert_allclose(g, G * np.array([0.0, -np.sin(a), -np.cos(a)]), atol=1e-5)
    np.testing.assert_allclose(np.asarray(terrain.incline(m, 0.0).gravity), [0, 0, -G],
                               atol=1e-6)


def test_set_material_changes_only_the_named_material_and_checks_its_input():
    m, _ = _block()
    m2 = terrain.set_material(m, "floor", friction=0.9, restitution=0.3)
    i = m.material_names.index("floor")
    assert float(m2.material_friction[i]) == pytest.approx(0.9)
    assert float(m2.material_restitution[i]) == pytest.approx(0.3)
    others = np.array([k for k in range(len(m.material_names)) if k != i])
    np.testing.assert_array_equal(m2.material_friction[others], m.material_friction[others])
    with pytest.raises(KeyError, match="no material 'ice'"):
        terrain.set_material(m, "ice", friction=0.1)
    with pytest.raises(TypeError, match="unknown parameter"):
        terrain.set_material(m, "floor", grip=0.1)
    with pytest.raises(ValueError, match="torsional"):
        terrain.set_material(m, "floor", torsional=0.01)


def test_oncilla_floor_is_a_named_material_of_every_contact():
    from thesis.physics.models import oncilla

    m, _ = oncilla()
    floor = m.material_names.index("floor")
    assert set(np.asarray(m.pair_material).tolist()) == {floor}
    assert float(m.material_friction[floor]) == pytest.approx(0.8)


def test_per_robot_terrains_in_one_batched_rollout():
    """Two robots of one batch on two terrains (gravity and floor friction per robot)
    equal two single rollouts on those terrains."""
    m, s = _block(mu=0.5)
    th = np.deg2rad(30.0)
    terrains = [m, terrain.set_material(terrain.incline(m, th), "floor", friction=0.2)]
    none = lambda p, sens, mem, t: (jnp.zeros((0,)), mem)  # noqa: E731
    states = jax.tree.map(lambda x: jnp.stack([x, x]), s)
    per_robot = {k: jnp.stack([getattr(t, k) for t in terrains])
                 for k in ("gravity", "material_friction")}
    for chunk in (1, None):
        _, tr = jax.jit(lambda st, pr: batched_rollout(
            m, st, none, None, 100, per_robot=pr, chunk=chunk, record=("body_vel",)))(
            states, per_robot)
        for i, t in enumerate(terrains):
            _, single = jax.jit(lambda st, t=t: rollout(t, st, none, None, 100,
                                                        record=("body_vel",)))(s)
            np.testing.assert_allclose(tr["body_vel"][i], single["body_vel"], atol=1e-5)
    assert float(jnp.abs(tr["body_vel"][1]).max()) > 0.5  # the sloped robot slid
    with pytest.raises(ValueError, match="not a traced Model field"):
        batched_rollout(m, states, none, None, 3, per_robot={"pair_material": jnp.zeros(2)})
    with pytest.raises(ValueError, match="expected"):
        batched_rollout(m, states, none, None, 3, per_robot={"gravity": jnp.zeros((3, 3))})
