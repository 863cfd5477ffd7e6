"""Safety tether: a tension-only spring from a body point to a carriage sliding freely
along a world rail (thesis §4.5 "a light thread to an overhead rail")."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, rollout, sensors, step

G = 9.81
RAIL_Z = 1.0


def _hanging(z0=0.6, vel=(0, 0, 0), tether=True, k=200.0, c=5.0, slack=0.3, floor=False,
             dtype=jnp.float32):
    """A 1 kg box (CoM at height ``z0``) below a rail along x at height 1 m, tethered at
    its CoM; optionally standing on a floor instead."""
    b = Builder("tethered", dt=0.002, solver_iterations=10)
    if floor:
        b.add_plane("floor", (0, 0, 1), 0.0)
    b.add_box("box", (0.1, 0.1, 0.1), (0.0, 0.0, z0), mass=1.0)
    if floor:
        for sx in (-0.04, 0.04):
            for sy in (-0.04, 0.04):
                b.add_contact_sphere("box", 0.01, (sx, sy, -0.04))
    if tether:
        b.add_tether("thread", "box", (0.0, 0.0, z0), (5.0, 0.0, RAIL_Z), (1.0, 0.0, 0.0),
                     k, c, slack)
    b.set_velocity("box", vel)
    return b.build(dtype)


def _run(m, s, n):
    none = lambda p, sens, mem, t: (jnp.zeros((0,), s.pos.dtype), mem)  # noqa: E731
    return jax.jit(lambda s: rollout(m, s, none, None, n,
                                     record=("body_pos", "body_vel", "tether_force")))(s)


def test_slack_tether_changes_nothing(x64):
    """A block sliding on a floor whose tether never tightens follows the trajectory of
    the untethered block (its row's impulse is exactly 0)."""
    kw = dict(z0=0.05, vel=(1.5, 0.4, 0.0), floor=True, slack=2.0,
              dtype=jnp.float64)
    m1, s1 = _hanging(tether=True, **kw)
    m0, s0 = _hanging(tether=False, **kw)
    _, tr1 = _run(m1, s1, 300)
    _, tr0 = _run(m0, s0, 300)
    # identical up to float64 round-off (the extra row shifts XLA's summation order, and
    # the friction cone's division and root round either way): ~100 ulp of 1 m and of
    # 1 m/s; a tether row that pulled at all would move the block by far more
    np.testing.assert_allclose(np.asarray(tr1["body_pos"]), np.asarray(tr0["body_pos"]),
                               rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(np.asarray(tr1["body_vel"]), np.asarray(tr0["body_vel"]),
                               rtol=1e-14, atol=1e-14)
    assert np.all(np.asarray(tr1["tether_force"]) == 0.0)
    assert float(tr1["body_pos"][-1, 0, 0]) > 0.2  # it did move


def test_taut_tether_holds_the_weight_at_its_spring_length():
    """Hanging from the rail: equilibrium distance slack + m g / k, tension m g."""
    k, slack = 200.0, 0.3
    m, s = _hanging(k=k, slack=slack)
    fin, tr = _run(m, s, 1500)
    z = np.asarray(tr["body_pos"])[-200:, 0, 2]
    np.testing.assert_allclose(RAIL_Z - z, slack + G / k, atol=2e-4)
    np.testing.assert_allclose(np.asarray(tr["tether_force"])[-200:, 0], G, rtol=2e-3)
    assert np.asarray(tr["tether_force"]).min() >= 0.0  # pulls, never pushes


def test_carriage_slides_freely_and_the_pull_is_perpendicular_to_the_rail():
    """Moving along the rail costs nothing (the carriage follows); a sideways swing is
    pulled back towards below the rail."""
    m, s = _hanging(z0=RAIL_Z - 0.3 - G / 200.0, vel=(0.8, 0.5, 0.0))
    fin, tr = _run(m, s, 1000)
    vel = np.asarray(tr["body_vel"])[:, 0]
    np.testing.assert_allclose(vel[:, 0], 0.8, atol=1e-4)  # no force along the rail
    y = np.asarray(tr["body_pos"])[:, 0, 1]
    assert y.max() > 0.05 and y.min() < -0.02  # swings back through the rail's plane


def test_tether_pulls_only_when_taut():
    """Thrown up towards the rail from below the slack circle: free flight (no force)
    until it falls back and the thread tightens."""
    m, s = _hanging(z0=0.75, vel=(0.0, 0.0, 1.0))  # distance 0.25 < slack 0.3
    _, tr = _run(m, s, 400)
    f = np.asarray(tr["tether_force"])[:, 0]
    z = np.asarray(tr["body_pos"])[:, 0, 2]
    free = (RAIL_Z - z) < 0.3 - 1e-3
    assert free[:50].all() and np.all(f[free] == 0.0)
    vz = np.asarray(tr["body_vel"])[:, 0, 2]
    t = (np.arange(len(vz)) + 1) * 0.002
    np.testing.assert_allclose(vz[free][:50], 1.0 - G * t[free][:50], atol=1e-5)
    assert f.max() > G  # caught by the thread


@pytest.mark.parametrize("slack", [0.3, 0.38])
def test_gradients_finite_across_tautening(x64, slack):
    """d(final height)/d(initial speed, stiffness) while the thread tightens during the
    rollout: finite, and equal to central differences."""
    m, s = _hanging(z0=0.75, dtype=jnp.float64, slack=slack)

    def final_z(v0, k):
        mm = m.replace(tether_k=m.tether_k.at[0].set(k))
        s0 = s.replace(vel=s.vel.at[0, 2].set(v0))
        body = lambda st, _: (step(mm, st, jnp.zeros((0,), jnp.float64)), None)  # noqa
        return jax.lax.scan(body, s0, None, length=250)[0].pos[0, 2]

    g = jax.jit(jax.grad(final_z, argnums=(0, 1)))(-0.5, 200.0)
    assert all(np.isfinite(float(x)) for x in g)
    f = jax.jit(final_z)
    fd_v = (f(-0.5 + 1e-6, 200.0) - f(-0.5 - 1e-6, 200.0)) / 2e-6
    fd_k = (f(-0.5, 200.0 + 1e-4) - f(-0.5, 200.0 - 1e-4)) / 2e-4
    np.testing.assert_allclose(g[0], fd_v, rtol=1e-4, atol=1e-8)
    np.testing.assert_allclose(g[1], fd_k, rtol=1e-4, atol=1e-10)


def test_tether_on_the_rail_has_finite_gradients():
    """An anchor exactly on the rail (distance 0, direction undefined) is slack and has
    finite gradients."""
    m, s = _hanging(z0=RAIL_Z)
    m = m.replace(gravity=jnp.zeros(3))
    g = jax.grad(lambda s0: jnp.sum(step(m, s0, jnp.zeros((0,))).pos ** 2))(s)
    assert all(bool(jnp.all(jnp.isfinite(x))) for x in jax.tree.leaves(g))
    assert float(sensors(m, step(m, s, jnp.zeros((0,))))["tether_force"][0]) == 0.0


def test_tethered_body_must_be_dynamic():
    b = Builder("bad")
    with pytest.raises(ValueError, match="dynamic body"):
        b.add_tether("t", "world", (0, 0, 0), (0, 0, 1), (1, 0, 0), 1.0, 0.0, 0.1)
