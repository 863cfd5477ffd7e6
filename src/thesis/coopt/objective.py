"""The closed-loop controller and the gait objective of the co-optimisation (thesis §8.2).

Objective: chapter 7's gait objective (§7.3.3, :func:`thesis.ch7.gait.speed_fn`):
the spine's forward (x) velocity averaged over every step of an episode of fixed length,
here as a function of the controller's parameters *and* the body's
(:mod:`thesis.coopt.morphology`).

Controller (a choice, departure ``ch8.coopt_controller``): a fixed open-loop trot
(:func:`thesis.ch7.trot.trot_controller`, the parameters of ``coopt.trot``) plus
the §7.3.3 skip network (:func:`thesis.ch7.nets.skip_apply`) closing the loop. Its
16 inputs are sin and cos of 2 pi f t (the trot's frequency), the 8 servoed joint angles
[rad] (knees 1-4, hips 1-4), the spine's up axis in its own frame (IMU attitude, 3) and
its gyroscope [rad/s] times 0.1 (3). The network's output layer starts at zero
(§7.3.2's third trick), so every arm starts from the same open-loop trot on the built
body, and "the controller fixed" (the morphology-only arm) is that trot.

A perturbed start (:func:`perturb`) adds one world velocity to every body (a push of the
whole standing robot, consistent with every joint) and lifts it by a height; it is how
the speed is re-evaluated from other starts and how the analytic gradient's spread over
starts is measured.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.coopt import morphology
from thesis.ch7 import nets, trot
from thesis.physics import rollout

__all__ = ["N_INPUTS", "trot_params", "controller_fn", "init_net", "perturb", "speed_fn",
           "build"]

SPINE = "spine"
#: Inputs of the feedback network: sin, cos, 8 joint angles, spine up axis, spine gyro.
N_INPUTS = 16
_GYRO_SCALE = 0.1


def build(cfg: dict, dtype=jnp.float32):
    """(model, state0) of the co-optimised quadruped at its built body, with the profile's
    time step, solver sweeps and servo torque bound [N m] (``coopt.body``)."""
    return morphology.build_body(dt=cfg["dt"], solver_iterations=cfg["solver_iterations"],
                                 servo_max_torque=cfg["servo_torque"], dtype=dtype)


def trot_params(cfg: dict) -> np.ndarray:
    """(5,) the fixed open-loop trot (order :data:`thesis.ch7.trot.PARAMS`)."""
    return np.array([float(cfg[k]) for k in trot.PARAMS])


def controller_fn(model, trot_p):
    """``controller(net, sensors, memory, t)`` -> 8 servo targets [rad]: the open-loop trot
    ``trot_p`` plus the skip network's feedback (module docstring)."""
    base = trot.trot_controller()
    spine = model.body(SPINE)
    servo_dof = np.asarray(model.servo_dof)
    f_hz = float(trot_p[0])

    def controller(net, sens, memory, t):
        dtype = sens["body_pos"].dtype
        p = jnp.asarray(trot_p, dtype)
        open_loop, memory = base(p, sens, memory, t)
        ph = 2.0 * jnp.pi * f_hz * t
        x = jnp.concatenate([
            jnp.stack([jnp.sin(ph), jnp.cos(ph)]).astype(dtype),
            sens["joint_angle"][servo_dof], sens["imu_up"][spine],
            _GYRO_SCALE * sens["imu_gyro"][spine]])
        return open_loop + nets.skip_apply(net, x), memory
    return controller


def init_net(key, hidden, n_out=8, *, zero_output=True, output_scale=1.0,
             dtype=jnp.float32):
    """The feedback network (:func:`thesis.ch7.nets.skip_init`, ``N_INPUTS`` inputs).
    ``zero_output=False`` gives a network whose output weights are orthogonal times
    ``output_scale`` (a point with a dense gradient, for the estimator comparison)."""
    net = nets.skip_init(key, N_INPUTS, hidden, n_out, zero_output=zero_output, dtype=dtype)
    if not zero_output:
        net = {**net, "out": jax.tree.map(lambda a: a * output_scale, net["out"]),
               "skip": jax.tree.map(lambda a: a * output_scale, net["skip"])}
    return net


def perturb(state0, push, lift):
    """``state0`` with the world velocity ``push`` (3,) [m/s] added to every body and
    every body raised by ``lift`` [m] (a rigid motion of the whole robot)."""
    dtype = state0.pos.dtype
    push = jnp.asarray(push, dtype)
    vel = state0.vel + push[None, :]
    pos = state0.pos + jnp.stack([jnp.zeros((), dtype), jnp.zeros((), dtype),
                                  jnp.asarray(lift, dtype)])[None, :]
    return state0.replace(vel=vel, prev_vel=vel, pos=pos)


def speed_fn(model, state0, trot_p, n_steps: int, *, grad_decay=1.0, remat=False):
    """``(net, u, push=0, lift=0) -> mean forward spine velocity [m/s]`` over ``n_steps``.

    ``u`` (8,) are the unconstrained morphology coordinates
    (:func:`thesis.coopt.morphology.to_physical`; 0 = the built body); ``push`` (3,) [m/s]
    and ``lift`` [m] perturb the start (:func:`perturb`). ``model``/``state0`` come from
    :func:`build`. ``grad_decay`` < 1 is §7.3.2's per-step gradient decay (forward
    unchanged)."""
    spine = model.body(SPINE)
    ctrl = controller_fn(model, trot_p)
    dtype = model.body_mass.dtype

    def f(net, u, push=None, lift=0.0):
        m, s0 = morphology.apply(model, state0, morphology.to_physical(u))
        if push is not None:
            s0 = perturb(s0, push, lift)
        _, traj = rollout(m, s0, ctrl, net, n_steps, grad_decay=grad_decay, remat=remat,
                          record=("body_vel",))
        return jnp.mean(traj["body_vel"][:, spine, 0]).astype(dtype)
    return f
