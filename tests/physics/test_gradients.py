"""Gradients through the engine: float64 finite differences and NaN-free edge cases."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, rollout, step
from thesis.physics.models import arm4, ball


def _fd(f, x, eps=1e-6):
    return (f(x + eps) - f(x - eps)) / (2 * eps)


def test_finite_differences_through_sliding_contact(x64):
    m, s = ball(height=0.5, velocity=(2.0, 0.0, 0.0), friction=0.1, dtype=jnp.float64,
                solver_iterations=2)
    none = lambda p, sens, mem, t: (jnp.zeros((0,), jnp.float64), mem)  # noqa: E731

    def final_x(vx, mu):
        mm = m.replace(material_friction=m.material_friction.at[:].set(mu))
        s0 = s.replace(vel=s.vel.at[0, 0].set(vx))
        return rollout(mm, s0, none, None, 40)[0].pos[0, 0]

    f = jax.jit(final_x)
    gv, gmu = jax.jit(jax.grad(final_x, argnums=(0, 1)))(2.0, 0.1)
    np.testing.assert_allclose(gv, _fd(lambda v: f(v, 0.1), 2.0), rtol=1e-6)
    np.testing.assert_allclose(gmu, _fd(lambda u: f(2.0, u), 0.1), rtol=1e-6)
    assert gmu < 0  # more friction, shorter slide


def _arm_effector_x(m, s):
    """``(p, scale) -> x`` [m]: the arm's end effector x after 20 steps of fixed servo
    commands ``p`` times a pattern, with every body mass scaled by ``scale``."""
    ctrl = lambda p, sens, mem, t: (p * jnp.asarray([1.0, 0.5, -1.0, 0.8]), mem)  # noqa

    def effector_x(p, scale):
        mm = m.replace(body_mass=m.body_mass * scale)
        return rollout(mm, s, ctrl, p, 20)[0].pos[4, 0]

    return effector_x


@pytest.mark.slow
def test_finite_differences_through_servos_and_morphology(x64):
    m, s = arm4(dtype=jnp.float64, solver_iterations=5, servo_deadband=0.0)
    effector_x = _arm_effector_x(m, s)
    f = jax.jit(effector_x)
    # p small enough that gain * error stays below the velocity limit (smooth stretch)
    gp, gs = jax.jit(jax.grad(effector_x, argnums=(0, 1)))(0.02, 1.0)
    assert abs(float(gp)) > 1e-3 and abs(float(gs)) > 1e-6
    np.testing.assert_allclose(gp, _fd(lambda p: f(p, 1.0), 0.02), rtol=1e-5)
    np.testing.assert_allclose(gs, _fd(lambda c: f(0.02, c), 1.0), rtol=1e-4)


def _all_finite(tree):
    return all(bool(jnp.all(jnp.isfinite(x))) for x in jax.tree.leaves(tree))


@pytest.mark.slow
def test_no_nan_gradients_at_contact_onset_and_zero_relative_velocity():
    # exactly touching (gap 0), at rest (zero relative velocity, friction inside the cone)
    m, s = ball(height=0.5)

    def loss(s0):
        s1 = jax.lax.fori_loop(0, 20, lambda i, x: step(m, x, jnp.zeros((0,))), s0)
        return s1.pos[0, 2] + s1.pos[0, 0] + jnp.sum(s1.angvel)

    g = jax.jit(jax.grad(loss))(s)  # jit: one compilation instead of op-by-op dispatch
    assert _all_finite(g)
    gm = jax.jit(jax.grad(lambda mm: jax.lax.fori_loop(
        0, 20, lambda i, x: step(mm, x, jnp.zeros((0,))), s).pos[0, 0]))(m)
    assert _all_finite(gm)


@pytest.mark.slow
def test_no_nan_gradients_for_coincident_spheres_and_zero_spin():
    b = Builder("overlap", gravity=(0, 0, 0))
    b.add_sphere("a", 0.1, (0, 0, 0))
    b.add_sphere("b", 0.1, (0, 0, 0))  # same centre: the normal is undefined
    b.add_sphere_pair(b.add_contact_sphere("a", 0.1), b.add_contact_sphere("b", 0.1))
    m, s = b.build(jnp.float32)
    g = jax.jit(jax.grad(lambda s0: jnp.sum(step(m, step(m, s0, jnp.zeros((0,))),
                                                 jnp.zeros((0,))).pos ** 2)))(s)
    assert _all_finite(g)


def test_servo_command_gradient_at_zero_error_without_dead_band():
    """A zero-output policy starts with commands equal to the joint angles (§7.3.2): with
    no dead band the servo must act there, so the gradient w.r.t. the command is not zero;
    with a dead band it is zero by construction."""

    def effector_x(cmd, deadband):
        m, s = arm4(solver_iterations=5, servo_deadband=deadband)
        ctrl = lambda p, sens, mem, t: (jnp.zeros((4,)) + p, mem)  # noqa: E731
        return rollout(m, s, ctrl, cmd, 1)[0].pos[4, 0]

    grad = jax.jit(jax.grad(effector_x), static_argnums=1)
    g0 = grad(0.0, 0.0)
    g_band = grad(0.0, 0.01)
    assert np.isfinite(g0) and abs(float(g0)) > 1e-6
    assert float(g_band) == 0.0


def _momentum(m):
    """``m`` with the momentum sweep order (solver module docstring, Momentum)."""
    return m.replace(sweep_order="momentum", momentum=0.85,
                     relaxation=jnp.asarray(0.6, m.body_mass.dtype))


@pytest.mark.slow
def test_finite_differences_through_the_momentum_order(x64):
    """Gradients through the extrapolated, projected and restarted sweeps match central
    finite differences: a servo command and a mass scale of the arm (joints, servos),
    and the launch speed and friction of a sliding ball (contact rows only)."""
    m, s = arm4(dtype=jnp.float64, solver_iterations=10, servo_deadband=0.0)
    effector_x = _arm_effector_x(_momentum(m), s)
    f = jax.jit(effector_x)
    gp, gs = jax.jit(jax.grad(effector_x, argnums=(0, 1)))(0.02, 1.0)
    fd_p, fd_s = _fd(lambda p: f(p, 1.0), 0.02), _fd(lambda c: f(0.02, c), 1.0)
    assert abs(float(gp)) > 1e-3 and abs(float(gs)) > 1e-6
    np.testing.assert_allclose(gp, fd_p, rtol=1e-2)
    np.testing.assert_allclose(gs, fd_s, rtol=1e-2)

    mb, sb = ball(height=0.5, velocity=(2.0, 0.0, 0.0), friction=0.1, dtype=jnp.float64,
                  solver_iterations=5)
    mb = _momentum(mb)
    none = lambda p, sens, mem, t: (jnp.zeros((0,), jnp.float64), mem)  # noqa: E731

    def final_x(vx, mu):
        mm = mb.replace(material_friction=mb.material_friction.at[:].set(mu))
        return rollout(mm, sb.replace(vel=sb.vel.at[0, 0].set(vx)), none, None, 40)[0].pos[0, 0]

    g = jax.jit(final_x)
    gv, gmu = jax.jit(jax.grad(final_x, argnums=(0, 1)))(2.0, 0.1)
    print(float(gv), float(gmu))
    np.testing.assert_allclose(gv, _fd(lambda v: g(v, 0.1), 2.0), rtol=1e-2)
    np.testing.assert_allclose(gmu, _fd(lambda u: g(2.0, u), 0.1), rtol=1e-2)
    assert gmu < 0


@pytest.mark.slow
def test_momentum_order_gradient_is_finite_over_a_ten_second_rollout():
    """The arm swinging for 10 s (1,000 steps) with the momentum order: the gradient of
    its final effector position w.r.t. the command amplitude and the masses is finite."""
    m, s = arm4(solver_iterations=10, servo_deadband=0.0)
    m = _momentum(m)

    def ctrl(p, sens, mem, t):
        return p * jnp.sin(2.0 * jnp.pi * 0.5 * t) * jnp.asarray([1.0, 0.5, -1.0, 0.8]), mem

    def loss(p, scale):
        mm = m.replace(body_mass=m.body_mass * scale)
        return jnp.sum(rollout(mm, s, ctrl, p, 1000)[0].pos[4])

    g = jax.jit(jax.grad(loss, argnums=(0, 1)))(0.3, 1.0)
    print(g)
    assert _all_finite(g) and abs(float(g[0])) > 0
