"""Smooth transitions between consecutive gaits (§3.2.5).

"For this transition we change the phase velocity smoothly, while linearly
interpolating between the other parameters of the gait as well." During a transition of
duration T (1 s in §3.3.1.2–3, 2 s between the 4 s trials of §4.5) from parameters p to
q, at τ ∈ [0, T] after its start, with w = τ / T:

* phase velocity  f(τ) = f_p + (f_q - f_p) S(w),  S(w) = 3w² - 2w³ (smoothstep, so the
  phase velocity and its rate are continuous at both ends); the phase is its integral,
  φ(τ) = φ0 + f_p τ + (f_q - f_p) T (w³ - w⁴/2), in closed form;
* every other parameter  (1 - w) p + w q  (linear).

The commands are ``family.commands_at_phase(params(τ), φ(τ))``, so they are continuous
in time whenever both gaits' commands are. All functions are pure jnp (jit/vmap-able);
``family`` is any object of :mod:`thesis.gaits.trajectories`.
"""

from __future__ import annotations

import jax.numpy as jnp


def smoothstep(w):
    """S(w) = 3w² - 2w³ for w in [0, 1] (the §3.2.5 blend; also the settle easing of
    :func:`thesis.gaits.runner.protocol_commands`)."""
    return w * w * (3.0 - 2.0 * w)


def _smoothstep_integral(w):
    """∫_0^w S(u) du for the smoothstep S."""
    return w**3 - 0.5 * w**4


def transition_state(family, p_from, p_to, tau, duration, phase0=0.0):
    """Parameters and phase at ``tau`` seconds into a transition (§3.2.5).

    Args:
        family: a gait family (needs ``index("f")``).
        p_from, p_to: (P,) parameter vectors of the outgoing and incoming gait.
        tau: time since the transition started [s]; before it (tau < 0) the outgoing
            gait runs unchanged, after ``duration`` the incoming gait runs at its own
            frequency.
        duration: transition length T [s].
        phase0: gait phase at the start of the transition [cycles].

    Returns:
        (params (P,), phase [cycles]).
    """
    p_from, p_to = jnp.asarray(p_from), jnp.asarray(p_to)
    i = family.index("f")
    f0, f1 = p_from[i], p_to[i]
    tau_raw = jnp.asarray(tau, dtype=p_from.dtype)
    tau = jnp.maximum(tau_raw, 0.0)
    w = jnp.clip(tau / duration, 0.0, 1.0)
    params = (1.0 - w) * p_from + w * p_to
    params = params.at[i].set(f0 + (f1 - f0) * smoothstep(w))
    phase_in = f0 * jnp.minimum(tau, duration) + (f1 - f0) * duration * _smoothstep_integral(w)
    phase = phase0 + phase_in + f1 * jnp.maximum(tau - duration, 0.0)
    phase = phase + f0 * jnp.minimum(tau_raw, 0.0)  # before the start: gait p_from runs
    return params, phase


def transition_commands(family, p_from, p_to, tau, duration, phase0=0.0):
    """(12,) joint commands [rad] at ``tau`` seconds into a transition (see
    :func:`transition_state`)."""
    params, phase = transition_state(family, p_from, p_to, tau, duration, phase0)
    return family.commands_at_phase(params, phase)


def schedule_state(family, params_seq, t, t_gait, t_transition, phase0=0.0):
    """Parameters and phase of the treadmill protocol: gaits run one after another.

    Gait k runs alone during [k D, k D + t_gait] with D = t_gait + t_transition, then
    blends into gait k + 1 during the next ``t_transition`` seconds (§3.2.5; e.g.
    t_gait = 4 s, t_transition = 2 s in §4.5). The last gait keeps running.

    Args:
        params_seq: (K, P) parameter vectors in evaluation order.
        t: time since the start of the first gait [s] (scalar).
        t_gait, t_transition: durations [s] (Python floats).
        phase0: phase at t = 0 [cycles].

    Returns:
        (params (P,), phase [cycles]).
    """
    ps = jnp.asarray(params_seq)
    K = ps.shape[0]
    i = family.index("f")
    f = ps[:, i]
    D = t_gait + t_transition
    # phase gained over each full segment k (steady + transition into k+1)
    seg = f[:-1] * t_gait + 0.5 * (f[:-1] + f[1:]) * t_transition
    start = phase0 + jnp.concatenate([jnp.zeros(1, ps.dtype), jnp.cumsum(seg)])  # (K,)
    t = jnp.asarray(t, dtype=ps.dtype)
    k = jnp.clip(jnp.floor(t / D).astype(jnp.int32), 0, K - 1)
    tk = t - k * D
    k_next = jnp.minimum(k + 1, K - 1)
    last = k == K - 1
    tau = jnp.where(last, 0.0, tk - t_gait)
    params, phase_tr = transition_state(family, ps[k], ps[k_next], tau, t_transition,
                                        start[k] + f[k] * t_gait)
    steady = (tk <= t_gait) | last
    phase = jnp.where(steady, start[k] + f[k] * tk, phase_tr)
    params = jnp.where(steady, ps[k], params)
    return params, phase


def schedule_commands(family, params_seq, t, t_gait, t_transition, phase0=0.0):
    """(12,) joint commands [rad] at time ``t`` of the protocol of :func:`schedule_state`."""
    params, phase = schedule_state(family, params_seq, t, t_gait, t_transition, phase0)
    return family.commands_at_phase(params, phase)
