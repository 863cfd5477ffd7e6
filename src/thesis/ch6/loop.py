"""The closed loop of §6.3-6.4 on the simulated Oncilla: controller, RLS and physics in one
``lax.scan`` per run, batched over runs (seeds x configurations).

One scan step is one controller period Δt (§6.2 "on average Δt ≈ 8.2 ms"):

1. read the 8 hip and knee encoders (thesis joint angles, :func:`encoder_dofs`) as the
   robot's 12-bit magnetic encoders give them (:func:`read_encoders`: Gaussian read noise,
   then quantised);
2. accumulate their mean and variance while the protocol says so (normalisation phase),
   normalise with the statistics so far, add Gaussian noise while RLS learns;
3. hidden layer, delay buffer, features, a priori output ``y_hat = W x_rls``
   (:mod:`thesis.ch6.controller`); one RLS update towards the teacher's command
   while learning;
4. motor command = teacher's share s of the teacher plus (1 - s) of ``y_hat``; the
   servos' maximal torque is scaled by the protocol's torque signal (0: motors off);
5. ``substeps`` physics steps with the command held (an inner ``lax.scan``); the period
   jitters (§6.2 "this period can vary as much as 15 %"): each controller step lasts
   ``substeps * dt * (1 + jitter u)``, u uniform in [-1, 1] from the run's sensing stream,
   by scaling that step's physics time step.

Every run of a batch has its own protocol timeline, teacher table, hidden weights and
masks (see :func:`pack_runs`), so one compiled function serves a whole sweep: the shapes
depend only on the batch size, H_max, the number of buffer slots and the number of steps.
The batch is split over the XLA host devices with ``shard_map`` (XLA runs a CPU rollout on
one core per device: docs/architecture.md#both-cores) and vmapped on each, with the
engine's batched solver (``Model.batched``).
"""

from __future__ import annotations

import functools
import importlib
import time

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, PartitionSpec as P

from thesis.ch6 import controller as C
from thesis.errors import SimulationDiverged
from thesis.gaits import leg as L
from thesis.physics import sensors as all_sensors
from thesis.physics import step
from thesis.physics.perturbation import scale_positions

O = importlib.import_module("thesis.physics.models.oncilla")

#: Order of the 8 encoders: hip and knee of LF, RF, LH, RH (``leg.LEGS``).
ENCODERS = tuple(f"{leg}_{j}" for leg in L.LEGS for j in ("hip", "knee"))
#: Indices of the hip and knee commands among the 12 outputs (``O.SERVO_NAMES`` order).
HIP_KNEE = tuple(O.SERVO_NAMES.index(n) for n in ENCODERS)
#: Floor on an encoder's standard deviation in the normalisation [rad].
MIN_STD = 1e-4
#: Recorded per step: a priori output (12), encoders (8), trunk position (3), trunk up (1).
RECORDED = ("y_hat", "encoders", "trunk_pos", "trunk_up")


def encoder_dofs(model) -> np.ndarray:
    """(8,) engine dof indices of the hip and knee encoders (:data:`ENCODERS` order).

    The hip encoder is the hip servo's coordinate (second axis of the shoulder's universal
    joint); the knee encoder is the knee motor's side of the cable, the femur -> drum
    hinge ("rotary encoders in the motors", §6.1), not the tibia behind the cable.
    """
    names = []
    for leg in L.LEGS:
        names += [f"{leg}_shoulder:1", f"{leg}_knee:0"]
    return np.array([model.dof(n) for n in names], np.int32)


def encoder_offsets() -> np.ndarray:
    """(8,) build-pose thesis angles [rad] added to the engine's joint coordinates, so the
    encoders read thesis joint angles (those the commands are given in)."""
    return np.asarray(O.build_offsets(), np.float64)[list(HIP_KNEE)]


def read_encoders(q, key, noise_std, resolution):
    """(8,) encoder readings [rad] of the true motor angles ``q`` (8,) [rad]: plus Gaussian
    read noise of ``noise_std`` [rad] from ``key``, rounded to multiples of
    ``resolution`` [rad] (one encoder count; 0: no quantisation). The Oncilla's magnetic
    encoders count 4096 per revolution (liboncilla-hw ``L1L2.cpp``,
    docs/sources.md#oncilla-encoders)."""
    q = q + noise_std * jax.random.normal(key, q.shape, q.dtype)
    safe = jnp.where(resolution > 0, resolution, 1.0)
    return jnp.where(resolution > 0, jnp.round(q / safe) * safe, q)


def perturbed(state0, relative, seed):
    """``state0`` with every body's position scaled by ``1 + relative * u``, u standard
    normal per coordinate from ``jax.random.key(seed)``
    (:func:`thesis.physics.perturbation.scale_positions`): a twin run started at the
    rounding level (``relative`` ~1e-7 is about one float32 ulp, so a coordinate moves
    by 0, 1 or a few ulp) measures how far a closed loop
    carries a last-bit difference (:mod:`thesis.ch6.twins`). ``relative = 0`` returns
    the state bit for bit."""
    return scale_positions(state0, relative, seed)


def _run_one(model, state0, run, substeps: int, n_steps: int):
    """One run: returns the per-step recordings (dict of (n_steps, ...) arrays)."""
    dofs = encoder_dofs(model)
    dtype = state0.pos.dtype
    state0 = perturbed(state0, run["perturb"].astype(dtype), run["perturb_seed"])
    offsets = jnp.asarray(encoder_offsets(), dtype)
    trunk = O.trunk_index(model)
    key = jax.random.key(run["noise_seed"])
    sensing = jax.random.key(run["sensing_seed"])
    jitter_key, encoder_key = jax.random.fold_in(sensing, 0), jax.random.fold_in(sensing, 1)
    n_feat = run["slot_mask"].shape[0] * run["hidden_mask"].shape[0] + 1
    w0, p0 = C.rls_init(n_feat, C.N_OUTPUTS, dtype)
    buf0 = jnp.zeros((run["slot_mask"].shape[0], run["hidden_mask"].shape[0]), dtype)
    stats0 = (jnp.zeros(C.N_INPUTS, dtype), jnp.zeros(C.N_INPUTS, dtype), jnp.zeros((), dtype))
    torque = model.servo_max_torque

    def body(carry, xs):
        s, w, p, buf, (ssum, ssq, cnt) = carry
        k, teacher, share, torque_k, learn, stats = xs
        q = read_encoders(all_sensors(model, s)["joint_angle"][dofs] + offsets,
                          jax.random.fold_in(encoder_key, k), run["encoder_noise"],
                          run["encoder_resolution"])
        ssum, ssq, cnt = ssum + stats * q, ssq + stats * q * q, cnt + stats
        n = jnp.maximum(cnt, 1.0)
        mean = ssum / n
        std = jnp.sqrt(jnp.maximum(ssq / n - mean * mean, MIN_STD ** 2))
        noise = jax.random.normal(jax.random.fold_in(key, k), (C.N_INPUTS,), dtype)
        x = (q - mean) / std + learn * run["noise_std"] * noise
        x_nl = C.hidden_layer(x, run["w_hidden"], run["w_bias"], run["hidden_mask"],
                              run["identity"])
        buf = C.push_buffer(buf, x_nl)
        f = C.features(buf, run["slot_mask"])
        y_hat = w @ f
        w_new, p_new, _ = C.rls_update(w, p, f, teacher)
        on = learn > 0.5
        w, p = jnp.where(on, w_new, w), jnp.where(on, p_new, p)
        cmd = share * teacher + (1.0 - share) * y_hat
        action = O.commands_to_action(cmd).astype(dtype)
        u = jax.random.uniform(jax.random.fold_in(jitter_key, k), (), dtype, -1.0, 1.0)
        m = model.replace(servo_max_torque=torque * torque_k,
                          dt=model.dt * (1.0 + run["jitter"] * u))

        def physics(st, _):
            return step(m, st, action), None

        rec = dict(y_hat=y_hat, encoders=q, trunk_pos=s.pos[trunk], trunk_up=s.rot[trunk, 2, 2])
        s, _ = jax.lax.scan(physics, s, None, length=substeps)
        return (s, w, p, buf, (ssum, ssq, cnt)), rec

    xs = (jnp.arange(n_steps), run["teacher"], run["share"], run["torque"], run["learn"],
          run["stats"])
    _, rec = jax.lax.scan(body, (state0, w0, p0, buf0, stats0), xs)
    return rec


@functools.lru_cache(maxsize=8)
def _compiled(substeps: int, n_steps: int, n_dev: int):
    """jit of the batched closed loop (cached per shape parameters)."""

    def batch(model, state0, runs):
        return jax.vmap(lambda r: _run_one(model, state0, r, substeps, n_steps))(runs)

    if n_dev > 1:
        mesh = Mesh(np.array(jax.devices()[:n_dev]), ("batch",))
        batch = jax.shard_map(batch, mesh=mesh, in_specs=(P(), P(), P("batch")),
                              out_specs=P("batch"), check_vma=False)
    return jax.jit(batch)


def pack_runs(runs: list[dict], dtype=np.float32) -> dict:
    """Stack per-run inputs into the batched pytree the rollout takes.

    Each run is a dict with ``teacher`` (T, 12) commands [rad]; ``share``, ``torque``,
    ``learn``, ``stats`` (T,) from :func:`thesis.ch6.protocol.signals`;
    ``w_hidden`` (H_max, 8), ``w_bias`` (H_max,), ``hidden_mask`` (H_max,),
    ``slot_mask`` (S,), ``identity`` (bool), ``noise_std`` (float), ``noise_seed`` (int),
    ``perturb`` (float: relative size of the initial-state perturbation, 0 for none),
    ``perturb_seed`` (int) (:func:`perturbed`), ``jitter`` (float: relative half-range of
    the controller period), ``encoder_noise`` and ``encoder_resolution`` [rad]
    (:func:`read_encoders`) and ``sensing_seed`` (int: the stream of the period's jitter
    and the encoders' read noise).
    """
    ints = {"noise_seed": np.uint32, "perturb_seed": np.uint32, "sensing_seed": np.uint32,
            "identity": np.bool_}
    out = {}
    for k in runs[0]:
        out[k] = np.stack([np.asarray(r[k]) for r in runs]).astype(ints.get(k, dtype))
    return out


def simulate(model, state0, runs: list[dict], substeps: int, *, experiment: str,
             labels: list[tuple[str, int]]):
    """Run a batch of closed-loop runs; host arrays of the recordings.

    Args:
        model, state0: the Oncilla (one model for the whole batch).
        runs: per-run inputs (see :func:`pack_runs`), all with the same number of steps.
        substeps: physics steps per controller step (Δt = substeps model.dt).
        experiment: registry key, named by :class:`SimulationDiverged`.
        labels: (condition, seed) of each run, named by :class:`SimulationDiverged`.

    Returns:
        (recordings, timing): recordings a dict of (R, T, ...) arrays (:data:`RECORDED`:
        ``y_hat`` (R, T, 12) [rad], ``encoders`` (R, T, 8) [rad], ``trunk_pos``
        (R, T, 3) [m], ``trunk_up`` (R, T)), step k recorded when the controller acts at
        t_k = k Δt; timing a dict of wall seconds, ``compile_seconds`` and
        ``rollout_seconds``.

    Raises:
        SimulationDiverged: a run's recordings are not finite; names its condition, seed
        and the first controller step with a non-finite value. Nothing is returned.
    """
    n_runs = len(runs)
    n_steps = int(np.asarray(runs[0]["share"]).shape[0])
    n_dev = jax.device_count()
    pad = (-n_runs) % n_dev if n_dev > 1 else 0
    batch = pack_runs(list(runs) + [runs[-1]] * pad)
    fn = _compiled(int(substeps), n_steps, n_dev if n_dev > 1 else 1)
    batched = model.replace(batched=True)
    t0 = time.perf_counter()
    exe = fn.lower(batched, state0, batch).compile()
    t1 = time.perf_counter()
    rec = jax.block_until_ready(exe(batched, state0, batch))
    t2 = time.perf_counter()
    rec = {k: np.asarray(v)[:n_runs] for k, v in rec.items()}
    bad = np.zeros((n_runs, n_steps), bool)
    for v in rec.values():
        bad |= ~np.isfinite(v.reshape(n_runs, n_steps, -1)).all(axis=-1)
    if bad.any():
        r = int(np.argmax(bad.any(axis=1)))
        cond, seed = labels[r]
        raise SimulationDiverged(f"{experiment}/{cond}", seed, int(np.argmax(bad[r])),
                                 what="closed-loop recording (controller step)")
    return rec, dict(compile_seconds=t1 - t0, rollout_seconds=t2 - t1)
