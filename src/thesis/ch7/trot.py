"""The hand-tuned trot of thesis §7.3.3, as a search over open-loop trots.

Thesis §7.3.3: "With hand tuning on the robot model shown in Figure 7.3b, we were able to
obtain a trotting motion with an average forward speed of 0.7 m/s." The thesis does not
say what was tuned; we tune a standard open-loop trot by exhaustive grid search, so that
the number says what this engine's quadruped can do with a trot, independently of the
BPTT optimiser of :mod:`thesis.ch7.gait`:

* diagonal legs in phase, the two pairs half a period apart: leg phases ``p`` = (0, pi, pi,
  0) for legs 1-4 (front left, front right, rear left, rear right;
  ``thesis.physics.models.quadruped.LEGS``);
* hip target ``A_h sin(2 pi f t + p)``, knee target ``c_k + A_k sin(2 pi f t + p + phi)``
  [rad] (the servos clip commands to +-45 deg);
* the grid is the product of the configured frequencies f, hip amplitudes A_h, knee
  amplitudes A_k, knee phase lags phi and knee offsets c_k (``ch7.gait.trot``).

Each configuration is simulated for the gait's episode (10 s) from the standing robot and
scored like the gait: the spine's mean forward velocity. A configuration counts as a trot
only if the robot stays upright: the spine's up axis never tilts by more than
``ch7.gait.trot.max_tilt_deg`` from the vertical (the thesis's "upside down turtle" is
what the hand tuning avoided). The best such speed is a lower bound of what hand tuning
could reach on this model.
"""

from __future__ import annotations

import itertools

import jax
import jax.numpy as jnp
import numpy as np
from thesis.physics import rollout

__all__ = ["TROT_PHASE", "PARAMS", "grid", "trot_controller", "trot_scores", "search"]

#: Phase of legs 1-4 [rad]: diagonal pairs (1, 4) and (2, 3) half a period apart.
TROT_PHASE = (0.0, np.pi, np.pi, 0.0)
#: Names of a trot's parameters, in the order of a parameter vector.
PARAMS = ("frequency_hz", "hip_amplitude", "knee_amplitude", "knee_phase", "knee_offset")


def grid(cfg: dict) -> np.ndarray:
    """(n, 5) float array: every combination of the configured values, columns ``PARAMS``."""
    return np.array(list(itertools.product(*[[float(v) for v in cfg[k]] for k in PARAMS])),
                    dtype=np.float64).reshape(-1, len(PARAMS))


def trot_controller():
    """``controller(p, sensors, memory, t)`` -> 8 servo targets (knees 1-4, hips 1-4) [rad]
    of the open-loop trot with parameter vector ``p`` (order ``PARAMS``)."""
    phase = jnp.asarray(TROT_PHASE)

    def controller(p, sens, memory, t):
        f, a_h, a_k, phi, c_k = (p[i] for i in range(len(PARAMS)))
        w = 2.0 * jnp.pi * f * t + phase.astype(p.dtype)
        return jnp.concatenate([c_k + a_k * jnp.sin(w + phi), a_h * jnp.sin(w)]), memory
    return controller


def trot_scores(model, state0, n_steps: int, spine: int):
    """``p -> (mean forward spine velocity [m/s], min over steps of the spine's up-axis z)``.

    The second value is cos of the largest tilt of the spine from the vertical (1 upright,
    -1 on its back)."""
    ctrl = trot_controller()

    def f(p):
        _, tr = rollout(model, state0, ctrl, p, n_steps, record=("body_vel", "imu_up"))
        return jnp.mean(tr["body_vel"][:, spine, 0]), jnp.min(tr["imu_up"][:, spine, 2])
    return f


def search(model, state0, n_steps: int, spine: int, params: np.ndarray, chunk: int = 128):
    """Score every row of ``params`` ((n, 5), order ``PARAMS``) in vmapped chunks of
    ``chunk`` robots; returns ``(speed (n,) [m/s], upright (n,) [cos of max tilt])``."""
    run = jax.jit(jax.vmap(trot_scores(model, state0, n_steps, spine)))
    dtype = model.body_mass.dtype
    n = params.shape[0]
    chunk = max(1, min(chunk, n))
    speed, up = np.empty(n), np.empty(n)
    for lo in range(0, n, chunk):
        block = params[lo:lo + chunk]
        pad = np.concatenate([block, np.repeat(block[-1:], chunk - len(block), 0)])
        v, u = run(jnp.asarray(pad, dtype))
        speed[lo:lo + len(block)] = np.asarray(v)[:len(block)]
        up[lo:lo + len(block)] = np.asarray(u)[:len(block)]
    return speed, up
