"""rollout.py: vmap equals a loop, gradient decay, rematerialisation, device split."""

import os
import subprocess
import sys
import textwrap

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import batched_rollout, rollout
from thesis.physics.models import arm4, ball


def _ctrl(p, sens, mem, t):
    return p * jnp.sin(3.0 * t) * jnp.ones((4,), p.dtype) + 0.0 * sens["joint_angle"], mem


def test_vmap_equals_loop_of_single_robots():
    m, s = arm4()
    gains = jnp.asarray([0.2, -0.4, 0.7])
    single = jax.jit(lambda p: rollout(m, s, _ctrl, p, 60, record=("body_pos",))[1]["body_pos"])
    batched = jax.jit(jax.vmap(single))(gains)
    for i in range(3):
        np.testing.assert_allclose(batched[i], single(gains[i]), rtol=1e-5, atol=1e-6)
    assert float(jnp.abs(batched[0] - batched[1]).max()) > 1e-3  # different robots moved


def test_batched_rollout_vmapped_chunks_equal_vmap():
    m, s = arm4()
    states = jax.tree.map(lambda x: jnp.stack([x, x]), s)
    states = states.replace(vel=states.vel.at[1, 2, 0].set(0.5))
    _, tr = batched_rollout(m, states, _ctrl, jnp.asarray(0.3), 20, chunk=None)
    ref = jax.vmap(lambda s0: rollout(m, s0, _ctrl, jnp.asarray(0.3), 20)[1])(states)
    np.testing.assert_allclose(tr["body_pos"], ref["body_pos"], rtol=1e-5, atol=1e-6)


def test_gradient_decay_is_identity_forward_and_scales_backward(x64):
    m, s = ball(height=50.0, dtype=jnp.float64)  # free flight: v_N = v_0 + N g dt
    n, alpha = 10, 0.9
    none = lambda p, sens, mem, t: (jnp.zeros((0,), jnp.float64), mem)  # noqa: E731

    def final_vz(v0, decay):
        s0 = s.replace(vel=s.vel.at[0, 2].set(v0))
        return rollout(m, s0, none, None, n, grad_decay=decay)[0].vel[0, 2]

    f = jax.jit(final_vz, static_argnums=1)
    g = jax.jit(jax.grad(final_vz), static_argnums=1)
    np.testing.assert_allclose(f(1.0, alpha), f(1.0, 1.0), rtol=0, atol=0)
    np.testing.assert_allclose(g(1.0, 1.0), 1.0, rtol=1e-12)
    np.testing.assert_allclose(g(1.0, alpha), alpha ** n, rtol=1e-12)


def test_warm_start_grad_cuts_only_the_initial_guess_path():
    m, s = arm4()
    n = 20

    def final(imp, p, wsg):
        j, r = imp
        s0 = s.replace(joint_impulse=j, row_impulse=r)
        fin, _ = rollout(m, s0, _ctrl, p, n, warm_start_grad=wsg, record=())
        return jnp.sum(fin.pos) + jnp.sum(fin.vel)

    imp0 = (s.joint_impulse + 0.1, s.row_impulse + 0.1)
    g = jax.jit(jax.value_and_grad(final, argnums=(0, 1)), static_argnums=2)
    (f1, (gi1, gp1)), (f0, (gi0, gp0)) = g(imp0, 0.3, 1.0), g(imp0, 0.3, 0.0)
    np.testing.assert_array_equal(f0, f1)  # forward unchanged
    # the last step's impulses reach the future only as the solver's initial guess
    assert max(float(jnp.abs(x).max()) for x in jax.tree.leaves(gi1)) > 1e-6
    assert all(float(jnp.abs(x).max()) == 0.0 for x in jax.tree.leaves(gi0))
    assert np.isfinite(float(gp0)) and abs(float(gp0)) > 1e-6 and float(gp0) != float(gp1)


def test_remat_gives_the_same_gradient():
    m, s = ball(height=0.5, friction=0.2)
    none = lambda p, sens, mem, t: (jnp.zeros((0,)), mem)  # noqa: E731

    def loss(vx, remat):
        s0 = s.replace(vel=s.vel.at[0, 0].set(vx))
        _, tr = rollout(m, s0, none, None, 40, remat=remat, record=("body_pos",))
        return jnp.mean(tr["body_pos"][:, 0, 0])

    g0 = jax.jit(jax.grad(lambda p: loss(p, False)))(2.0)
    g1 = jax.jit(jax.grad(lambda p: loss(p, True)))(2.0)
    assert abs(float(g0)) > 1e-2
    np.testing.assert_allclose(g1, g0, rtol=1e-5)


def test_batched_rollout_is_vmap_on_one_device():
    m, s = arm4()
    states = jax.tree.map(lambda x: jnp.stack([x, x]), s)
    states = states.replace(vel=states.vel.at[1, 2, 0].set(0.5))
    _, tr = batched_rollout(m, states, _ctrl, jnp.asarray(0.3), 20)
    ref = jax.vmap(lambda s0: rollout(m, s0, _ctrl, jnp.asarray(0.3), 20)[1])(states)
    np.testing.assert_allclose(tr["body_pos"], ref["body_pos"], rtol=1e-6, atol=1e-7)


@pytest.mark.slow
def test_batched_rollout_splits_over_two_host_devices():
    code = textwrap.dedent("""
        import jax, jax.numpy as jnp, numpy as np
        from thesis.physics import batched_rollout, rollout
        from thesis.physics.models import ball
        assert jax.device_count() == 2
        m, s = ball()
        states = jax.tree.map(lambda x: jnp.stack([x] * 4), s)
        states = states.replace(vel=states.vel.at[:, 0, 0].set(jnp.arange(4.0)))
        ctrl = lambda p, sens, mem, t: (jnp.zeros((0,)), mem)
        fin, tr = jax.jit(lambda st: batched_rollout(m, st, ctrl, None, 50))(states)
        assert len(fin.pos.sharding.device_set) == 2
        ref = jax.vmap(lambda s0: rollout(m, s0, ctrl, None, 50)[1])(states)
        np.testing.assert_allclose(tr["body_pos"], ref["body_pos"], rtol=1e-6, atol=1e-6)
        print("OK")
    """)
    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2",
               JAX_PLATFORMS="cpu")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=300)
    assert out.returncode == 0 and "OK" in out.stdout, out.stderr[-2000:]


@pytest.mark.parametrize("order", ["jacobi", "momentum"])
def test_batched_solver_matches_the_unbatched_in_value_and_gradient(order):
    """Model.batched (the solver's robots-last vmap rule) = the unbatched solver on the
    quadruped walking into ground contact (many rows per body, torso included): the value
    and its gradient w.r.t. each robot's own controller gain (vmap of grad), and the
    gradient w.r.t. parameters shared by every robot (masses, relaxation), which is summed
    over the batch. In the chapter-7 order (Jacobi) in both orders of grad and vmap; in the
    momentum order, whose restart is decided per robot, as vmap of grad (the batching rule
    of its forward and backward sweeps; grad of vmap transposes the same rule, which the
    Jacobi order checks)."""
    from thesis.physics.models import quadruped

    m, s = quadruped()
    m = m.replace(sweep_order=order)

    def ctrl(p, sens, mem, t):
        return p * jnp.sin(6.0 * t + jnp.arange(8.0)), mem

    def travel(model, mass, relax, p):
        fin, _ = rollout(model.replace(body_mass=mass, relaxation=relax), s, ctrl, p, 40,
                         record=())
        return jnp.sum(fin.pos[:, 0]) + jnp.sum(fin.vel)

    gains = jnp.asarray([0.0, 0.3, -0.5])
    both_orders = order == "jacobi"
    out = {}
    for model in (m, m.replace(batched=True)):
        inner = jax.vmap(jax.value_and_grad(
            lambda a, r, p, mm=model: travel(mm, a, r, p), (0, 1, 2)), (None, None, 0))
        val, (g_mass, g_relax, g_gain) = jax.jit(inner)(m.body_mass, m.relaxation, gains)
        shared = [(g_mass.sum(0), g_relax.sum(0))]
        if both_orders:
            outer = jax.grad(lambda a, r, mm=model: jnp.sum(
                jax.vmap(lambda p: travel(mm, a, r, p))(gains)), (0, 1))
            shared.append(jax.jit(outer)(m.body_mass, m.relaxation))
        out[model.batched] = dict(shared=shared, value=val, gain=g_gain)
    single, batched = out[False], out[True]
    assert float(jnp.abs(single["value"][1] - single["value"][0])) > 1e-3  # gains matter
    assert float(jnp.abs(single["shared"][0][0]).max()) > 1e-2  # the masses matter
    np.testing.assert_allclose(batched["value"], single["value"], rtol=1e-4, atol=1e-5)
    np.testing.assert_allclose(batched["gain"], single["gain"], rtol=1e-3, atol=1e-4)
    assert len(batched["shared"]) == (2 if both_orders else 1)
    for b_shared, s_shared in zip(batched["shared"], single["shared"]):
        for k in (0, 1):
            np.testing.assert_allclose(b_shared[k], s_shared[k], rtol=1e-3, atol=1e-4)
