"""The five turning strategies of §3.3.2 and the LED-tracking P-controller of §3.3.3.

All strategies start from a straight half-ellipse gait (``EllipseGait`` parameters, the
PSO optimum run at the turning frequency) and change it on one side or per leg; turning
is commanded to the **left** (positive yaw), so the "inner" side is the left one (legs
LF, LH). Per-leg parameters are (P, 4) arrays whose columns follow ``leg.LEGS``; the
ellipse family's ``foot_targets`` broadcasts over them.

1. ``step_size`` (§3.3.2.1): inner-side step size a reduced to ``reduced_a`` mm,
   t_stance unchanged.
2. ``step_speed`` (§3.3.2.2): inner-side stance slowed (duty raised to
   ``slow_duty``), a unchanged.
3. ``step_size_constant_speed`` (§3.3.2.3): inner a reduced as in 1, and the inner duty
   scaled by the same ratio so that the stance speed 2 a f / duty is unchanged.
4. ``torque`` (§3.3.2.4): inner hip and knee servo torque limits scaled by
   ``torque_scale`` (a model change), gait unchanged.
5. ``scapulae`` (§3.3.2.5): the loci rotated about the vertical by +yaw (fore legs) and
   -yaw (hind legs), ``yaw`` up to 20 degrees: four-wheel steering through the scapulae.
"""

from __future__ import annotations

import functools

import jax.numpy as jnp
import numpy as np

from thesis.gaits import leg as L
from thesis.gaits import trajectories as T

STRATEGIES = ("step_size", "step_speed", "step_size_constant_speed", "torque", "scapulae")
#: Legs on the inner (left) side of a left turn.
INNER = np.array([s > 0 for s in L.SIDES])
FORE = np.array(L.IS_FORE)


def per_leg(params) -> np.ndarray:
    """(P,) gait parameters -> (P, 4) per-leg columns."""
    return np.repeat(np.asarray(params, np.float64)[:, None], 4, axis=1)


def strategy_params(family: T.EllipseGait, params, strategy: str, *, reduced_a: float,
                    slow_duty: float, yaw_deg: float):
    """Per-leg parameters (P, 4) and per-leg locus yaw (4,) [rad] of a turning strategy.

    ``torque`` returns the straight gait (its change is in the model, see
    :func:`torque_limits`)."""
    p = per_leg(params)
    ia, idu = family.index("a"), family.index("duty")
    yaw = np.zeros(4)
    if strategy in ("step_size", "step_size_constant_speed"):
        a0 = p[ia, 0]
        a1 = min(reduced_a, a0)
        p[ia, INNER] = a1
        if strategy == "step_size_constant_speed":
            p[idu, INNER] = p[idu, INNER] * a1 / max(a0, 1e-9)
    elif strategy == "step_speed":
        p[idu, INNER] = slow_duty
    elif strategy == "scapulae":
        yaw = np.where(FORE, 1.0, -1.0) * np.deg2rad(yaw_deg)
    elif strategy != "torque":
        raise ValueError(f"unknown strategy {strategy!r}; known: {STRATEGIES}")
    return p, yaw


def torque_limits(model, torque_scale: float):
    """Servo torque limits (12,) with the inner (left) hips and knees scaled (§3.3.2.4)."""
    lim = np.asarray(model.servo_max_torque, np.float64).copy()
    for i, name in enumerate(model.servo_names):
        leg, joint = name.split("_")
        if leg in ("LF", "LH") and joint in ("hip", "knee"):
            lim[i] *= torque_scale
    return lim


def _blend(w, a, b):
    return (1.0 - w) * a + w * b


@functools.lru_cache(maxsize=8)
def turning_command_fn(family: T.EllipseGait, settle: float, t_transition: float):
    """Command function for per-leg gaits: memory ``p_from``/``p_to`` (P, 4), ``yaw``
    (4,). Frequency is common to all legs; parameters and yaw blend linearly over the
    transition (§3.2.5; the phase runs at the common frequency)."""

    def fn(mem, t, sens):
        w = jnp.clip((t - settle) / t_transition, 0.0, 1.0)
        params = _blend(w, mem["p_from"], mem["p_to"])
        f = params[family.index("f"), 0]
        phase = f * jnp.maximum(t - settle, 0.0)
        targets = family.foot_targets(params, phase, w * mem["yaw"])
        return family.inverse(targets).reshape(12)

    return fn


@functools.lru_cache(maxsize=8)
def tracking_command_fn(family: T.EllipseGait, settle: float,
                        t_transition: float, led_distance: float, led_height: float,
                        camera_focal_px: float, trunk: int, camera_x: float):
    """P-controller on the LED's bearing (§3.3.3) for ``step_size`` or ``scapulae``
    turning (memory ``scapulae``: 0 or 1, so both run in one batch).

    The bearing beta [rad] of the LED seen by the onboard camera (from its pixel column,
    ``camera_focal_px`` = focal length in pixels) drives the turning command
    u = clip(gain * beta, -1, 1) (memory ``gain``): for step size the inner side's a
    shrinks by |u| (a_inner = a - |u| (a - reduced_a), the side chosen by the sign of u);
    for scapulae the loci turn by u * yaw_max (fore +, hind -). Memory: ``params``
    (P,), ``gain``, ``reduced_a``, ``yaw_max`` [rad], ``scapulae`` (0 or 1).
    """
    ia = family.index("a")

    def fn(mem, t, sens):
        pos, rot = sens["body_pos"][trunk], sens["body_rot"][trunk]
        cam = pos + rot[:, 0] * camera_x
        led = jnp.stack([pos[0] + led_distance, 0.0 * pos[0], 0.0 * pos[0] + led_height])
        d = rot.T @ (led - cam)  # LED in the trunk frame (x forward, y left)
        col = -camera_focal_px * d[1] / jnp.maximum(d[0], 1e-3)  # pixels right of centre
        beta = jnp.arctan2(-col, camera_focal_px)  # + = LED to the left
        w = jnp.clip((t - settle) / t_transition, 0.0, 1.0)
        u = w * jnp.clip(mem["gain"] * beta, -1.0, 1.0)
        p = jnp.repeat(mem["params"][:, None], 4, axis=1)
        scap = mem["scapulae"]
        a0 = mem["params"][ia]
        cut = (1.0 - scap) * jnp.abs(u) * (a0 - jnp.minimum(mem["reduced_a"], a0))
        left = jnp.asarray(INNER)
        a = jnp.where(left, a0 - cut * (u > 0), a0 - cut * (u < 0))
        p = p.at[ia].set(a)
        yaw = scap * jnp.where(jnp.asarray(FORE), 1.0, -1.0) * u * mem["yaw_max"]
        f = mem["params"][family.index("f")]
        phase = f * jnp.maximum(t - settle, 0.0)
        targets = family.foot_targets(p, phase, yaw)
        return family.inverse(targets).reshape(12)

    return fn
