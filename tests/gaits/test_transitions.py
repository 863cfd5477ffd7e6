"""Gait transitions (§3.2.5): smooth phase velocity, linear parameters, continuity."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.gaits import trajectories as T
from thesis.gaits import transitions as X

SP = T.SplineGait()
P1 = SP.project(np.array([1.5, 50.0, 135.0, 0.0, -5.0, 0.5, 30, 20, 25, 35, 10, 5]))
P2 = SP.project(np.array([2.0, 80.0, 145.0, 5.0, -10.0, 0.6, 60, 10, 5, 60, 40, 20]))


def test_transition_state_endpoints_and_phase_velocity(x64):
    T_tr = 2.0
    p0, ph0 = X.transition_state(SP, P1, P2, 0.0, T_tr, phase0=0.3)
    np.testing.assert_allclose(p0, P1)
    assert float(ph0) == pytest.approx(0.3)
    p1, ph1 = X.transition_state(SP, P1, P2, T_tr, T_tr, phase0=0.3)
    np.testing.assert_allclose(p1, P2)
    # total phase gained = mean frequency × T (smoothstep is symmetric)
    assert float(ph1) == pytest.approx(0.3 + 0.5 * (1.5 + 2.0) * T_tr)
    # other parameters are linear in time
    pm, _ = X.transition_state(SP, P1, P2, 0.5, T_tr)
    i = [k for k in range(12) if k != SP.index("f")]
    np.testing.assert_allclose(np.asarray(pm)[i], (0.75 * P1 + 0.25 * P2)[i])
    # phase velocity equals the smoothly varying frequency, continuous at both ends
    tau = jnp.linspace(-0.5, T_tr + 0.5, 301)
    phase = jax.vmap(lambda s: X.transition_state(SP, P1, P2, s, T_tr)[1])(tau)
    freq = jax.vmap(lambda s: X.transition_state(SP, P1, P2, s, T_tr)[0][0])(tau)
    dphase = np.gradient(np.asarray(phase), np.asarray(tau))
    inner = (tau > 0.02) & (tau < T_tr - 0.02) | (tau > T_tr + 0.02)
    np.testing.assert_allclose(dphase[np.asarray(inner)], np.asarray(freq)[np.asarray(inner)],
                               rtol=1e-4)
    assert np.all(np.diff(np.asarray(freq)) >= -1e-12)
    assert np.max(np.abs(np.diff(np.asarray(freq)))) < 0.02  # no jump in phase velocity


def _max_step(c):
    return float(jnp.max(jnp.abs(jnp.diff(c, axis=0))))


def test_transition_commands_are_continuous():
    dt = 0.001
    T_tr = 1.0  # 1 s transitions of §3.3.1.2
    tau = jnp.arange(-0.3, T_tr + 0.3, dt)
    run = jax.jit(jax.vmap(lambda s: X.transition_commands(SP, jnp.asarray(P1),
                                                           jnp.asarray(P2), s, T_tr)))
    c = run(tau)
    assert bool(jnp.all(jnp.isfinite(c)))
    steady1 = jax.jit(jax.vmap(lambda t: SP.commands(jnp.asarray(P1), t)))(tau)
    steady2 = jax.jit(jax.vmap(lambda t: SP.commands(jnp.asarray(P2), t)))(tau)
    bound = 2.0 * max(_max_step(steady1), _max_step(steady2))
    assert _max_step(c) < bound
    # an abrupt switch at the same moment jumps by far more than that
    jump = float(jnp.max(jnp.abs(SP.commands_at_phase(jnp.asarray(P2), 0.0)
                                 - SP.commands_at_phase(jnp.asarray(P1), 0.0))))
    assert jump > 5 * bound
    # before the transition the commands are those of the first gait
    np.testing.assert_allclose(c[:250], steady1[:250], atol=1e-5)


def test_schedule_runs_gaits_in_sequence_continuously():
    t_gait, t_tr = 4.0, 2.0  # §4.5: 4 s per gait, 2 s transitions
    seq = np.stack([P1, P2, P1])
    t = jnp.arange(0.0, 20.0, 0.005)
    state = jax.jit(jax.vmap(lambda s: X.schedule_state(SP, jnp.asarray(seq), s, t_gait,
                                                        t_tr)))
    params, phase = state(t)
    tn = np.asarray(t)
    # inside each steady window the gait is exactly that gait, at its own frequency
    for k, p in enumerate(seq):
        lo, hi = 6.0 * k + 0.01, 6.0 * k + t_gait - 0.01 if k < 2 else 20.0
        w = (tn > lo) & (tn < hi)
        np.testing.assert_allclose(np.asarray(params)[w], np.broadcast_to(p, (w.sum(), 12)),
                                   atol=1e-5)
        dph = np.diff(np.asarray(phase)[w]) / 0.005
        np.testing.assert_allclose(dph, p[0], rtol=2e-3)
    # phase is continuous and monotone over the whole protocol
    dphase = np.diff(np.asarray(phase))
    assert np.all(dphase > 0) and np.max(dphase) < 2.0 * 0.005 * 1.01
    cmd = jax.jit(jax.vmap(lambda s: X.schedule_commands(SP, jnp.asarray(seq), s, t_gait,
                                                         t_tr)))(t)
    steady = jax.jit(jax.vmap(lambda s: SP.commands(jnp.asarray(P2), s)))(t[:2000])
    assert _max_step(cmd) < 2.5 * _max_step(steady)
