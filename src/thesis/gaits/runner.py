"""Batched gait evaluation on the simulated Oncilla (thesis §3.2.2-§3.2.5).

One call of :func:`simulate` runs a whole batch of robots (a PSO generation, a frequency
sweep, a set of turning strategies) in one ``batched_rollout`` of the engine. Every robot
receives its own command parameters through the rollout's per-robot controller memory;
commands are recomputed every 10 ms and held in between (§3.2.2), while the physics
runs at the model's finer ``dt``.

Evaluation protocol of one gait (§3.2.4-3.2.5, on the treadmill the gaits run one after
another; here each particle is simulated from standing):

* ``settle`` seconds easing from the build pose into the outgoing gait's pose at phase
  0 (:func:`protocol_commands`);
* a §3.2.5 transition of ``t_transition`` seconds from the outgoing gait (the previous
  particle in evaluation order, as on the treadmill) to the gait under test;
* ``t_run`` seconds of the gait under test: the evaluation window.

Optionally (chapter 4, ``reset_at`` of :func:`simulate`) the treadmill's assistant
(§4.5) stands by at the window's start: a robot that is down then, having entered from
another gait, is set back on its feet at its start pose and eases into the gait under
test again (:func:`assist`, :func:`restart_commands`).

Fitness (eq. 3.3): ``distance - sigma_x / 150 - sigma_y / 300`` with the distance walked
forward in the window [m] and sigma_x, sigma_y the standard deviations [pixels] of the
LED's position in the onboard camera's 1024 x 768 image, sampled every 10 ms (the Wii
camera's 100 Hz), obtained with the engine camera's ``project_points``.
"""

from __future__ import annotations

import importlib
import functools
import math
import time
import types

import jax
import jax.numpy as jnp
import numpy as np

from thesis.gaits import transitions
from thesis.physics import batched_rollout
from thesis.physics.camera import project_points
# the module (the package re-exports the constructor under the same name)
O = importlib.import_module("thesis.physics.models.oncilla")

#: Command period [s] (§3.2.2).
COMMAND_PERIOD = O.COMMAND_PERIOD


def command_time(t):
    """Time of the last command at or before ``t`` [s] (commands held for 10 ms)."""
    return jnp.floor(t / COMMAND_PERIOD + 1e-3) * COMMAND_PERIOD


def batch_states(state, n: int, lateral=None, heading=None, forward=None):
    """Stack ``n`` copies of ``state`` (leading batch axis); ``lateral`` (n,) shifts each
    robot sideways [m] (used by the tracking experiment); ``heading`` (n,) turns each
    robot about the vertical axis through the world origin [rad] (the robot standing at
    rest, so only positions and orientations change; used for repeated evaluations);
    ``forward`` (n,) then shifts each robot along x [m] (a start further along a strip of
    pebbles)."""
    s = jax.tree.map(lambda x: jnp.broadcast_to(x, (n,) + x.shape), state)
    if lateral is not None:
        shift = jnp.zeros((n, 1, 3), s.pos.dtype).at[:, 0, 1].set(jnp.asarray(lateral, s.pos.dtype))
        s = s.replace(pos=s.pos + shift)
    if heading is not None:
        h = jnp.asarray(heading, s.pos.dtype)
        c, sn, z, o = jnp.cos(h), jnp.sin(h), jnp.zeros_like(h), jnp.ones_like(h)
        rz = jnp.stack([jnp.stack([c, -sn, z], -1), jnp.stack([sn, c, z], -1),
                        jnp.stack([z, z, o], -1)], -2)  # (n, 3, 3)
        s = s.replace(pos=jnp.einsum("nij,nbj->nbi", rz, s.pos),
                      rot=jnp.einsum("nij,nbjk->nbik", rz, s.rot))
    if forward is not None:
        shift = jnp.zeros((n, 1, 3), s.pos.dtype).at[:, 0, 0].set(jnp.asarray(forward, s.pos.dtype))
        s = s.replace(pos=s.pos + shift)
    return s


def _command_controller(command_fn):
    """The engine controller of a command function: its commands as servo actions."""

    def controller(_, sens, memory, t):
        cmd = command_fn(memory, command_time(t), sens)
        return O.commands_to_action(cmd).astype(sens["body_pos"].dtype), memory

    return controller


def _sampled_rollout(model, states0, controller, memory, n_steps: int, stride: int, chunk):
    """(final states, pos, rot) of a batched rollout of ``n_steps``, the body poses
    sampled at the end of each command period (every ``stride`` steps)."""
    final, traj = batched_rollout(model, states0, controller, None, n_steps, memory0=memory,
                                  batch_memory=True, record=("body_pos", "body_rot"),
                                  chunk=chunk)
    sample = slice(stride - 1, None, stride)
    return final, traj["body_pos"][:, sample], traj["body_rot"][:, sample]


@functools.lru_cache(maxsize=32)
def _compiled(command_fn, n_steps: int, stride: int, chunk=1):
    """jit of a batched rollout for a given command function, length and chunking of
    the batch (``thesis.physics.batched_rollout``'s ``chunk``) (cached)."""
    controller = _command_controller(command_fn)

    def run(model, states0, memory):
        _, pos, rot = _sampled_rollout(model, states0, controller, memory, n_steps, stride,
                                       chunk)
        return pos, rot

    return jax.jit(run)


def is_down(model, state, fall_height):
    """() bool: one robot's trunk centre lower than ``fall_height`` [m] or its trunk
    tilted more than 60 degrees (up-vector z < 0.5): the fall criterion of
    :func:`speed_terms`, on a single (unbatched) engine ``State``. A non-finite pose
    is not down (its comparisons are false); :func:`exploded` catches it."""
    trunk = O.trunk_index(model)
    return (state.pos[trunk, 2] < fall_height) | (state.rot[trunk, 2, 2] < 0.5)


def assist(model, state, start, fall_height, eligible):
    """The treadmill assistant (§4.5) at the start of a window, for one robot.

    A robot that ``is_down`` and is ``eligible`` (it entered the window from another
    gait) is set back on its feet: its whole state becomes ``start`` (the evaluation's
    start pose, at rest), keeping the clock. Branch-free (``jnp.where`` on every leaf),
    so it vmaps over robots; a robot left alone keeps its state bit for bit.

    Args:
        state, start: single engine ``State`` s (same tree, no batch axis).
        fall_height: [m], see :func:`is_down`.
        eligible: () bool.

    Returns:
        (state after the check, () bool: whether the robot was set back).
    """
    reset = is_down(model, state, fall_height) & eligible
    start = start.replace(time=state.time)  # the clock runs on through the reset
    return jax.tree.map(lambda now, new: jnp.where(reset, new, now), state, start), reset


@functools.lru_cache(maxsize=32)
def _compiled_assisted(command_fn, n_steps: int, stride: int, reset_steps: int, chunk=1):
    """jit of a batched rollout like :func:`_compiled`, split at step ``reset_steps``
    (a multiple of ``stride``) where :func:`assist` checks every robot; after the check
    the controller memory carries ``restart`` (B,): the command time of the reset [s],
    inf for a robot left alone (see :func:`restart_commands`). Returns (pos, rot,
    reset (B,) bool). Cached; one compiled program per shape, as :func:`_compiled`."""

    controller = _command_controller(command_fn)

    def segment(model, states0, memory, n):
        return _sampled_rollout(model, states0, controller, memory, n, stride, chunk)

    def run(model, states0, memory, fall_height, eligible):
        mid, pos0, rot0 = segment(model, states0, memory, reset_steps)
        check = functools.partial(assist, model, fall_height=fall_height)
        after, reset = jax.vmap(check)(mid, states0, eligible=eligible)
        restart = jnp.where(reset, command_time(mid.time), jnp.inf).astype(mid.time.dtype)
        _, pos1, rot1 = segment(model, after, dict(memory, restart=restart),
                                n_steps - reset_steps)
        return (jnp.concatenate([pos0, pos1], axis=1), jnp.concatenate([rot0, rot1], axis=1),
                reset)

    return jax.jit(run)


def simulate(model, state0, command_fn, memory, duration: float, lateral=None,
             heading=None, chunk=1, forward=None, reset_at=None, fall_height=None,
             may_reset=None):
    """Simulate a batch of robots under ``command_fn``.

    Args:
        model, state0: the Oncilla (:func:`thesis.physics.models.oncilla.oncilla`).
        command_fn: hashable pure function ``(memory_i, t_cmd, sensors) -> (12,)`` thesis
            joint commands [rad] (LEGS x JOINTS order) for one robot.
        memory: pytree of per-robot command parameters, leading axis B.
        duration: simulated time [s].
        lateral: optional (B,) initial sideways offsets [m].
        heading: optional (B,) initial headings [rad] (see :func:`batch_states`).
        forward: optional (B,) initial shifts along x [m] (see :func:`batch_states`).
        chunk: robots simulated together per device (``batched_rollout``); ``None``
            vmaps the whole batch, faster for large batches; the default 1 runs robots
            one after the other (chapter 3's results are bound to it bit for bit).
        reset_at: optional time [s] (rounded to the 10-ms command grid, inside the run)
            of the assistant's check (:func:`assist`): a robot that is down then (trunk
            below ``fall_height`` [m] or tilted beyond 60 degrees) and ``may_reset``
            ((B,) bool, default all) is set back to its start pose at rest, and
            ``command_fn`` must then follow the memory's ``restart`` (see
            :func:`gait_command_fn`). ``None``: no check, the plain rollout.

    Returns:
        dict with ``pos`` (B, K, n_body, 3) and ``rot`` (B, K, n_body, 3, 3) body poses
        sampled every command period (K = duration / 10 ms), ``t`` (K,) [s], ``reset``
        (B,) bool (set back at ``reset_at``; all False without it), ``reset_at`` (the
        check's time on the command grid [s], or None), and ``wall`` the wall time of
        the call [s] and ``robot_seconds`` = B * duration.
    """
    batch = jax.tree.leaves(memory)[0].shape[0]
    stride = int(round(COMMAND_PERIOD / float(model.dt)))
    n_cmd = int(round(duration / COMMAND_PERIOD))
    states0 = batch_states(state0, batch, lateral, heading, forward)
    t0 = time.perf_counter()
    if reset_at is None:
        pos, rot = _compiled(command_fn, n_cmd * stride, stride, chunk)(model, states0, memory)
        reset = np.zeros(batch, bool)
    else:
        k = int(round(reset_at / COMMAND_PERIOD))
        if not 0 < k < n_cmd:
            raise ValueError(f"reset_at = {reset_at} s is not inside the run of {duration} s")
        fn = _compiled_assisted(command_fn, n_cmd * stride, stride, k * stride, chunk)
        eligible = np.ones(batch, bool) if may_reset is None else np.asarray(may_reset, bool)
        dtype = states0.pos.dtype
        pos, rot, reset = fn(model, states0, memory, jnp.asarray(fall_height, dtype),
                             jnp.asarray(eligible))
        reset = np.asarray(reset)
    pos = np.asarray(pos)
    wall = time.perf_counter() - t0
    rot = np.asarray(rot)
    t = (np.arange(n_cmd) + 1) * COMMAND_PERIOD
    at = None if reset_at is None else k * COMMAND_PERIOD
    return dict(pos=pos, rot=rot, t=t, reset=reset, reset_at=at, wall=wall,
                robot_seconds=batch * duration)


# ------------------------------------------------------------------- gait commands
def protocol_commands(family, p_from, p_to, t, settle, t_transition):
    """(12,) joint commands [rad] of the evaluation protocol at time ``t`` [s].

    During ``settle`` the commands ease (smoothstep) from the model's build pose into
    the outgoing gait ``p_from``'s pose at phase 0 and the robot stands there; then the
    §3.2.5 transition from ``p_from`` to ``p_to`` starts at phase 0. Without the easing
    the first command jumps from the build pose to an arbitrary gait pose: measured on
    the default profile (seed 0), 5 of 24 robots of a first PSO generation were
    thrown over within the 0.5 s settle, before the gait under test had started.
    """
    dtype = jnp.asarray(p_to).dtype
    w = jnp.clip(jnp.asarray(t, dtype) / jnp.maximum(settle, 1e-6), 0.0, 1.0)
    w = transitions.smoothstep(w)
    build = jnp.asarray(O.build_offsets(), dtype)
    pose0 = family.commands_at_phase(jnp.asarray(p_from), jnp.zeros((), dtype))
    easing = build + w * (pose0 - build)
    tau = jnp.maximum(t - settle, 0.0)
    gait = transitions.transition_commands(family, p_from, p_to, tau, t_transition)
    return jnp.where(t < settle, easing, gait)


def restart_commands(family, p_to, t, restart, settle, t_transition, cmd):
    """(12,) commands [rad] of a robot the assistant set back on its feet at ``restart``.

    From ``restart`` [s] on, the protocol starts over with the gait under test as its own
    predecessor: ``settle`` seconds easing from the build pose (the start pose it was set
    back in) into ``p_to``'s pose at phase 0, then ``p_to``'s gait (the protocol of a
    re-evaluation from standstill). Before ``restart`` (inf: never) the protocol's
    ``cmd`` are returned unchanged.
    """
    again = t >= restart
    tau = jnp.where(again, t - restart, 0.0)  # inf - inf never reaches the commands
    own = protocol_commands(family, p_to, p_to, tau, settle, t_transition)
    return jnp.where(again, own, cmd)


@functools.lru_cache(maxsize=32)
def gait_command_fn(family, settle: float, t_transition: float):
    """Command function of the evaluation protocol for a gait ``family``: memory holds
    ``p_from`` and ``p_to`` (P,) per robot (see :func:`protocol_commands`) and, after
    the assistant's check of :func:`simulate` (``reset_at``), ``restart`` () [s] (see
    :func:`restart_commands`)."""

    def fn(mem, t, sens):
        cmd = protocol_commands(family, mem["p_from"], mem["p_to"], t, settle,
                                t_transition)
        if "restart" in mem:  # the memory's structure is static under jit
            cmd = restart_commands(family, mem["p_to"], t, mem["restart"], settle,
                                   t_transition, cmd)
        return cmd

    return fn


# ------------------------------------------------------------------- measurements
def led_pixels(model, pos, rot, led_distance: float, led_height: float, lateral=0.0):
    """(..., 2) pixel position (column, row) of the LED in the onboard camera.

    Args:
        pos, rot: (..., n_body, 3) and (..., n_body, 3, 3) body poses.
    """
    trunk = O.trunk_index(model)
    lead = pos.shape[:-2]
    P = jnp.asarray(pos).reshape((-1,) + pos.shape[-2:])
    R = jnp.asarray(rot).reshape((-1,) + rot.shape[-3:])
    led = O.led_position(P[:, trunk], led_distance, led_height, lateral)

    def one(p, r, q):
        uv, _ = project_points(model, types.SimpleNamespace(pos=p, rot=r), "onboard", q[None])
        return uv[0]

    uv = jax.vmap(one)(P, R, led)
    return np.asarray(uv).reshape(lead + (2,))


def detrend(x, window: int):
    """``x`` (K, ...) minus its centred moving average over ``window`` samples (edges:
    the average over the samples available)."""
    x = np.asarray(x, np.float64)
    window = min(int(window), len(x))  # a window longer than the track: its mean
    if window <= 1 or window == len(x):
        return x - x.mean(axis=0)
    k = np.ones(window) / window
    num = np.apply_along_axis(lambda v: np.convolve(v, k, mode="same"), 0, x)
    den = np.convolve(np.ones(len(x)), k, mode="same")
    return x - num / den.reshape((-1,) + (1,) * (x.ndim - 1))


def fitness_terms(model, sim, t_start, led_distance: float, led_height: float,
                  fall_height: float, period=None, t_end=None):
    """Eq. 3.3 terms over the window t > ``t_start`` of a :func:`simulate` result.

    ``period`` (B,) [s]: gait periods. On the treadmill a light rope to an overhead rail
    "reorients" the robot along the track (§3.2.2), so the LED's image position reflects
    the body's wobble during the gait, not a slow drift of the heading. The simulated
    robot walks on an open floor without that rope, so its slow heading drift is removed
    before the standard deviations are taken: the pixel track minus its moving average
    over one gait period. ``None``: plain standard deviations.

    ``t_start`` and ``t_end`` (scalars or (B,)) bound each robot's window (``t_end``
    None: to the end of the simulation).

    A robot that falls is ranked below every robot that stays up: its fitness is
    ``FALLEN_FITNESS`` plus the fraction of the window it stayed up (so PSO still moves
    towards gaits that fall later). Eq. 3.3 presumes a robot that walks on the treadmill;
    a robot lying on its side hardly moves and keeps the LED still, so its eq. 3.3 value
    (about 0) beats every walking gait whose wobble costs more than its distance gains.
    Measured (default profile, seed 0): in the first PSO generation 22 of 24
    robots fell, and the best eq. 3.3 values of the sine and spline swarms (-0.03 and
    0.19) were robots lying on their side. An unphysical simulation scores ``-inf``.

    Returns a dict of (B,) arrays: ``distance`` [m] (trunk x displacement), ``speed``
    [m/s], ``sigma_x``, ``sigma_y`` [pixels], ``fitness`` (eq. 3.3, see above if fallen),
    ``fallen`` (bool: trunk lower than ``fall_height`` [m] or tilted more than 60
    degrees, or an unphysical simulation, see :func:`exploded`) and ``exploded``.
    """
    trunk = O.trunk_index(model)
    B = sim["pos"].shape[0]
    t = sim["t"]
    t0 = np.broadcast_to(np.asarray(t_start, np.float64), (B,))
    t1 = np.broadcast_to(np.asarray(t[-1] if t_end is None else t_end, np.float64), (B,))
    uv_all = led_pixels(model, sim["pos"], sim["rot"], led_distance, led_height)
    bad = exploded(model, sim)
    out = {k: np.zeros(B) for k in ("distance", "speed", "sigma_x", "sigma_y", "fitness")}
    fallen = np.zeros(B, bool)
    per = None if period is None else np.broadcast_to(np.asarray(period, np.float64), (B,))
    for i in range(B):
        w = (t > t0[i] + 1e-9) & (t <= t1[i] + 1e-9)
        tp = sim["pos"][i, w, trunk]
        up = sim["rot"][i, w, trunk, 2, 2]
        uv = uv_all[i, w]
        if per is not None:
            uv = detrend(uv, int(round(per[i] / COMMAND_PERIOD)))
        sx, sy = uv[:, 0].std(), uv[:, 1].std()
        dist = tp[-1, 0] - tp[0, 0]
        span = t[w][-1] - t0[i]
        with np.errstate(invalid="ignore"):
            down = (tp[:, 2] < fall_height) | (up < 0.5)
            fallen[i] = bad[i] or down.any()
        fit = dist - sx / 150.0 - sy / 300.0
        if fallen[i]:
            fit = FALLEN_FITNESS + (t[w][int(np.argmax(down))] - t0[i]) / span
        ok = np.isfinite(fit) and not bad[i]
        out["distance"][i] = dist if not bad[i] else np.nan
        out["speed"][i] = out["distance"][i] / span
        out["sigma_x"][i], out["sigma_y"][i] = sx, sy
        out["fitness"][i] = fit if ok else -np.inf
    return dict(out, fallen=fallen, exploded=bad)


def window(t, t_start, t_end, batch: int) -> np.ndarray:
    """(batch, K) mask of the samples ``t`` (K,) [s] inside each robot's window
    (``t_start``, ``t_end``], the bounds scalars or (batch,)."""
    t0 = np.broadcast_to(np.asarray(t_start, np.float64), (batch,))
    t1 = np.broadcast_to(np.asarray(t_end, np.float64), (batch,))
    return (t[None] > t0[:, None] + 1e-9) & (t[None] <= t1[:, None] + 1e-9)


def speed_terms(model, sim, t_start, fall_height: float, t_end=None):
    """Speed-only fitness terms of §4.6 over each robot's window of a :func:`simulate` result.

    "The goal of our optimization is to maximize the average robot speed, measured over a
    period of four seconds" (§4.6): the trunk's forward displacement over the window
    divided by its length. No camera terms (unlike eq. 3.3, :func:`fitness_terms`).

    Args:
        sim: a :func:`simulate` result (poses every command period).
        t_start, t_end: scalars or (B,) window bounds [s] (``t_end`` None: the end).
        fall_height: trunk-centre height [m] below which the robot counts as fallen; a
            trunk tilted more than 60 degrees (up-vector z < 0.5) counts too.

    Returns:
        dict of (B,) arrays: ``distance`` [m] (trunk x over the window), ``speed`` [m/s],
        ``fallen`` (bool: fell inside the window, or unphysical), ``upright`` [1] (the
        fraction of the window before the first fall; 1 if it never fell, 0 if it fell
        before the window or went unphysical), ``exploded`` (bool, :func:`exploded`) and
        ``finite`` (bool: every recorded pose of the robot is finite).
    """
    trunk = O.trunk_index(model)
    pos, rot, t = sim["pos"], sim["rot"], sim["t"]
    B = pos.shape[0]
    t0 = np.broadcast_to(np.asarray(t_start, np.float64), (B,))
    w = window(t, t_start, t[-1] if t_end is None else t_end, B)
    first = np.argmax(w, axis=1)
    last = w.shape[1] - 1 - np.argmax(w[:, ::-1], axis=1)
    start = np.maximum(first - 1, 0)  # the pose at the window's start (a sample at t_start)
    x = pos[:, :, trunk, 0]
    rows = np.arange(B)
    distance = x[rows, last] - x[rows, start]
    span = t[last] - np.where(first > 0, t[start], t0)
    with np.errstate(invalid="ignore"):
        down = ((pos[:, :, trunk, 2] < fall_height) | (rot[:, :, trunk, 2, 2] < 0.5)) & w
    bad = exploded(model, sim)
    finite = np.isfinite(pos).all(axis=(1, 2, 3)) & np.isfinite(rot).all(axis=(1, 2, 3, 4))
    fell = down.any(axis=1)
    t_fall = t[np.argmax(down, axis=1)]
    upright = np.where(fell, (t_fall - t0) / (t[last] - t0), 1.0)
    upright = np.where(bad, 0.0, np.clip(upright, 0.0, 1.0))
    distance = np.where(bad, np.nan, distance)
    return dict(distance=distance, speed=distance / span, fallen=fell | bad, upright=upright,
                exploded=bad, finite=finite)


#: Fitness of a robot that fell at the start of its window (eq. 3.3 of any robot that
#: stays up is far above: distances are metres, the sigma terms at most a few units).
FALLEN_FITNESS = -100.0

#: Trunk height [m] and trunk speed [m/s] that no walking 5 kg robot reaches: above
#: them the simulation has gone unphysical (engine blow-up, see the ch3 report).
EXPLODED_HEIGHT = 0.4
EXPLODED_SPEED = 10.0


def exploded(model, sim):
    """(B,) True where a robot's simulation went non-finite or unphysical (trunk above
    EXPLODED_HEIGHT or faster than EXPLODED_SPEED between two command samples; the jump
    of a robot set back to its start pose, ``sim["reset"]`` at ``sim["reset_at"]``, is
    not a speed)."""
    tp = sim["pos"][:, :, O.trunk_index(model)]
    finite = np.isfinite(sim["pos"]).all(axis=(1, 2, 3))
    with np.errstate(invalid="ignore"):
        v = np.linalg.norm(np.diff(tp, axis=1), axis=-1) / COMMAND_PERIOD
        v = np.where(_reset_jump(sim), 0.0, v)
        high = np.nanmax(tp[..., 2], axis=1) > EXPLODED_HEIGHT
        fast = np.nanmax(v, axis=1) > EXPLODED_SPEED
    return ~finite | high | fast


def _reset_jump(sim) -> np.ndarray:
    """(B, K - 1) bool: the step between two samples across which :func:`simulate` set a
    robot back to its start pose (none without ``reset_at``)."""
    B, K = sim["pos"].shape[:2]
    jump = np.zeros((B, K - 1), bool)
    if sim.get("reset_at") is not None:
        k = int(np.argmin(np.abs(sim["t"] - sim["reset_at"])))  # the sample at the check
        jump[:, k] = np.asarray(sim["reset"], bool)
    return jump


def fit_circle(xy):
    """Least-squares (Kasa) circle through points ``xy`` (N, 2) [m].

    Used for the turning radius of §3.3.3 ("fitting a circle to the measured center of
    the robot over time"). Returns (centre (2,), radius) [m]; radius inf for collinear
    points.
    """
    xy = np.asarray(xy, np.float64)
    A = np.column_stack([2 * xy[:, 0], 2 * xy[:, 1], np.ones(len(xy))])
    b = (xy ** 2).sum(axis=1)
    sol, _, rank, _ = np.linalg.lstsq(A, b, rcond=None)
    if rank < 3:  # collinear points: a straight line, no finite circle
        return np.full(2, np.nan), math.inf
    c = sol[:2]
    r2 = sol[2] + c @ c
    if not np.isfinite(r2) or r2 <= 0 or math.sqrt(r2) > 1e3:
        return c, math.inf
    return c, math.sqrt(r2)


def yaw_of(rot):
    """Heading [rad] of the trunk's x axis in the horizontal plane, unwrapped over time.

    Args: rot (..., K, 3, 3) trunk rotations. Returns (..., K)."""
    return np.unwrap(np.arctan2(rot[..., 1, 0], rot[..., 0, 0]), axis=-1)
