"""Closed-loop rollouts: the robot and its controller unrolled over time (thesis §7.3, Fig. 7.2).

``rollout`` scans ``step`` with ``lax.scan`` (one compiled body, any number of steps),
feeding the controller the sensors of the current state; it is a pure function, so
``jax.jit``, ``jax.vmap`` (batches of robots) and ``jax.grad`` (BPTT w.r.t. controller
parameters, the initial state or model parameters, eq. 7.2-7.3) apply directly.
Two tricks of §7.3.2 / docs/sources.md#tpx-experiments are built in:

* ``grad_decay`` = alpha < 1: identity in the forward pass, but the gradient flowing back
  through each time step's state is multiplied by alpha (the original's ``MulGrad``),
  implemented as ``alpha x + (1 - alpha) stop_gradient(x)``;
* ``warm_start_grad`` < 1 scales the gradient through the solver's warm start only
  (forward unchanged; :func:`thesis.physics.step`);
* ``remat=True``: ``jax.checkpoint`` on the scan body, so the backward pass stores one
  state per step instead of every intermediate of the solver (memory O(steps * state)).

``batched_rollout`` runs a batch of initial states (and optionally memories), robot by
robot or in vmapped chunks, and, when more than one XLA host device exists
(``--xla_force_host_platform_device_count``, XLA runs one core per device,
docs/architecture.md#both-cores here), splits the batch across the devices with ``jax.shard_map``.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, PartitionSpec as P

from thesis.physics.math import decay_gradient
from thesis.physics.perturbation import at_start
from thesis.physics.sensors import sensors as all_sensors
from thesis.physics.step import step
from thesis.physics.types import Model, State

__all__ = ["rollout", "batched_rollout", "decay_gradient"]


def rollout(model: Model, state0: State, controller, params, n_steps: int, *,
            memory0=None, grad_decay=1.0, warm_start_grad=1.0, remat=False,
            record=("body_pos",)):
    """Simulate ``n_steps`` steps under a closed-loop controller.

    Args:
        model, state0: the model and initial state.
        controller: ``(params, sensors: dict, memory, t) -> (action (n_servo,), memory)``,
            with ``t`` the simulated time [s] of the current state and ``sensors`` the dict
            of :func:`thesis.physics.sensors`.
        params: controller parameters (any pytree).
        n_steps: static number of steps.
        memory0: initial controller memory (any pytree; None allowed).
        grad_decay: per-step gradient decay alpha (1.0: exact BPTT), thesis §7.3.2.
        warm_start_grad: fraction of the gradient that flows through the solver's warm
            start (see :func:`thesis.physics.step`; 1.0: exact).
        remat: checkpoint the scan body (less memory for long gradients).
        record: names of sensors (see ``sensors``) and/or ``"action"`` to record.
    Returns:
        ``(final_state, trajectory)``; ``trajectory[name]`` has shape (n_steps, ...) and
        holds the value *after* each step (``"action"``: the command applied in it).

    Under a process-wide perturbation (``thesis --perturb``) the rollout starts from
    :func:`thesis.physics.perturbation.at_start` of ``state0``; without one, from
    ``state0`` itself.
    """
    record = tuple(record)
    state0 = at_start(state0)

    def body(carry, _):
        s, mem = carry
        action, mem = controller(params, all_sensors(model, s), mem, s.time)
        s = step(model, s, action, warm_start_grad=warm_start_grad)
        if not (isinstance(grad_decay, (int, float)) and grad_decay == 1.0):
            s = decay_gradient(s, grad_decay)
        sens = all_sensors(model, s)  # only the recorded entries survive compilation
        out = {k: (action if k == "action" else sens[k]) for k in record}
        return (s, mem), out

    if remat:
        body = jax.checkpoint(body)
    (final, _), traj = jax.lax.scan(body, (state0, memory0), None, length=int(n_steps))
    return final, traj


def batched_rollout(model: Model, states0: State, controller, params, n_steps: int, *,
                    memory0=None, batch_memory=False, chunk=1, per_robot=None, **kwargs):
    """``rollout`` over a batch of initial states (leading axis B), sharing ``params``.

    With ``jax.device_count() > 1`` and B divisible by the device count, the batch is
    split across the host devices (``shard_map`` over a 1-D mesh ``"batch"``). On each
    device the robots run ``chunk`` at a time (``jax.lax.map`` over chunks of a
    ``jax.vmap``); ``chunk=None`` vmaps the whole local batch. Vmapped chunks run the
    solver's batched variant (``Model.batched``). The default ``chunk=1`` is a sequential
    map, kept so that existing results stay bit-for-bit; with the profile's XLA flags
    (``thesis.jaxsetup.xla_flags``) ``chunk=None`` is the faster choice on CPU too
    (64 robots on one core, engine alone, per robot-step: Tab. 7.1 quadruped 93 vs 128 us,
    Oncilla 159 vs 213 us). ``memory0`` is shared
    unless ``batch_memory=True``. Returns ``(final_states, trajectories)`` with a leading
    batch axis; results equal ``jax.vmap(rollout)`` up to float round-off.

    ``per_robot`` gives robots their own values of model leaves: a dict from a traced
    ``Model`` field name (e.g. ``"gravity"``, ``"material_friction"``, the sphere field's
    ``"field_centre"``) to an array with a leading batch axis B and the leaf's shape
    after it. Each robot then runs ``model.replace(**its_values)``; the topology stays
    shared, so one compilation serves the whole batch (terrain as data,
    ``thesis.physics.terrain``). Fields not named stay shared.
    """
    mem_axis = 0 if batch_memory else None
    if chunk != 1:  # vmapped: the solver's batched variant (Model.batched)
        model = model.replace(batched=True)
    batch = jax.tree.leaves(states0)[0].shape[0]
    if per_robot:
        return _per_robot_rollout(model, states0, controller, params, n_steps,
                                  _check_per_robot(model, per_robot, batch), memory0,
                                  batch_memory, chunk, kwargs)

    def one(s, mm):
        return rollout(model, s, controller, params, n_steps, memory0=mm, **kwargs)

    # lax.map's batch_size reshapes with -1, which fails on zero-size leaves (a model
    # without joints has a (B, 0, 6) impulse array): chunk=1 uses a plain map instead
    size = None if chunk == 1 else chunk

    def run(s0, mem):
        if chunk is None:
            return jax.vmap(one, in_axes=(0, mem_axis))(s0, mem)
        if batch_memory:
            return jax.lax.map(lambda sm: one(*sm), (s0, mem), batch_size=size)
        return jax.lax.map(lambda s: one(s, mem), s0, batch_size=size)

    n_dev = jax.device_count()
    if n_dev > 1 and batch % n_dev == 0:
        mesh = Mesh(np.array(jax.devices()), ("batch",))
        mem_spec = P("batch") if batch_memory else P()
        sharded = jax.shard_map(run, mesh=mesh, in_specs=(P("batch"), mem_spec),
                                out_specs=P("batch"), check_vma=False)
        return sharded(states0, memory0)
    return run(states0, memory0)


def _check_per_robot(model: Model, per_robot: dict, batch: int) -> dict:
    """Validate ``per_robot`` (see :func:`batched_rollout`): traced Model fields with a
    leading batch axis and the leaf's shape; returns the dict with ``jax.Array`` values."""
    out = {}
    for name, value in per_robot.items():
        if name in Model._STATIC or not hasattr(model, name):
            raise ValueError(f"per_robot: {name!r} is not a traced Model field (static "
                             "topology cannot differ between the robots of one batch)")
        leaf = getattr(model, name)
        value = jnp.asarray(value, leaf.dtype)
        if value.shape != (batch,) + tuple(leaf.shape):
            raise ValueError(f"per_robot[{name!r}]: shape {value.shape}, expected "
                             f"{(batch,) + tuple(leaf.shape)} (batch {batch}, then the leaf)")
        out[name] = value
    return out


def _per_robot_rollout(model, states0, controller, params, n_steps, leaves, memory0,
                       batch_memory, chunk, kwargs):
    """:func:`batched_rollout` with per-robot model leaves ``leaves`` (checked dict)."""

    def one(s, mm, lv):
        return rollout(model.replace(**lv), s, controller, params, n_steps, memory0=mm,
                       **kwargs)

    size = None if chunk == 1 else chunk

    def run(s0, mem, lv):
        if chunk is None:
            return jax.vmap(one, in_axes=(0, 0 if batch_memory else None, 0))(s0, mem, lv)
        if batch_memory:
            return jax.lax.map(lambda x: one(*x), (s0, mem, lv), batch_size=size)
        return jax.lax.map(lambda x: one(x[0], mem, x[1]), (s0, lv), batch_size=size)

    n_dev = jax.device_count()
    batch = jax.tree.leaves(states0)[0].shape[0]
    if n_dev > 1 and batch % n_dev == 0:
        mesh = Mesh(np.array(jax.devices()), ("batch",))
        mem_spec = P("batch") if batch_memory else P()
        sharded = jax.shard_map(run, mesh=mesh, in_specs=(P("batch"), mem_spec, P("batch")),
                                out_specs=P("batch"), check_vma=False)
        return sharded(states0, memory0, leaves)
    return run(states0, memory0, leaves)
