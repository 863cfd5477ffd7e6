"""Sensors of a robot (thesis §7.3.1 "81 sensors, e.g. encoders and an IMU";
docs/sources.md#tpx-sensors).

``sensors(model, state)`` returns every sensor at once as named arrays; controllers pick
what they need. The accelerometer differentiates the linear velocity over the last step
(``State.prev_vel``) and, like a real IMU, measures specific force (acceleration minus
gravity) in the body frame; the gyroscope is the angular velocity in the body frame.
``imu_up`` is the world's vertical axis in the body frame, the tilt an IMU's attitude
filter reports: a smooth function of the pose, unlike the accelerometer, whose
finite difference carries every impact and makes d(reading)/d(velocity) ~ 1/dt.
Contact forces are the normal impulses the solver applied in the last step divided by dt;
tether tensions likewise.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics import kinematics
from thesis.physics.math import mtv
from thesis.physics.types import Model, State

__all__ = ["sensors", "contact_normal_force", "tether_force"]


def contact_normal_force(m: Model, state: State):
    """(n_csphere,) normal contact force on each contact sphere in the last step [N]
    (planes, listed sphere pairs and the sphere field together)."""
    if m.n_contact == 0:
        return jnp.zeros((m.n_csphere,), state.pos.dtype)
    start = m.n_rows - m.rows_per_contact * m.n_contact
    f = state.row_impulse[start:start + m.n_contact] / m.dt
    other = np.where(m.pair_is_sphere, m.pair_other, m.n_csphere)  # n_csphere = dropped
    query = np.repeat(m.field_query, m.field_k)  # field contacts: the query sphere only
    seg = np.concatenate([m.pair_sphere, query, other,
                          np.full(query.shape, m.n_csphere)]).astype(np.int32)
    return jax.ops.segment_sum(jnp.concatenate([f, f]), seg, num_segments=m.n_csphere + 1)[:-1]


def tether_force(m: Model, state: State):
    """(n_tether,) tension of each tether in the last step [N] (>= 0; 0 while slack)."""
    start = (m.n_servo + int(m.limit_dof.shape[0]) + int(m.jspring_dof.shape[0])
             + len(m.spring_names))
    return -state.row_impulse[start:start + len(m.tether_names)] / m.dt


def sensors(model: Model, state: State) -> dict:
    """All sensors of ``state``.

    Returns a dict of arrays:
        joint_angle (n_dof,) [rad or m]; joint_velocity (n_dof,) [rad/s or m/s];
        body_pos (n_body, 3) [m]; body_rot (n_body, 3, 3); body_vel (n_body, 3) [m/s];
        body_angvel (n_body, 3) [rad/s] (world frame);
        imu_acc (n_body, 3) specific force in the body frame [m/s^2] (reads +g upwards
        at rest); imu_gyro (n_body, 3) angular velocity in the body frame [rad/s];
        imu_up (n_body, 3) unit world z axis in the body frame (R^T e_z, [1]);
        contact_force (n_csphere,) normal force [N];
        tether_force (n_tether,) tension of each tether [N].
    """
    m, s = model, state
    pos, rot, vel6 = kinematics.extend(m, s.pos, s.rot, s.vel, s.angvel)
    fr = kinematics.joint_frames(m, pos, rot)
    q, qdot, _, _ = kinematics.joint_coordinates(m, fr, vel6)
    acc = (s.vel - s.prev_vel) / m.dt - m.gravity[None, :]
    return dict(
        joint_angle=q, joint_velocity=qdot, body_pos=s.pos, body_rot=s.rot,
        body_vel=s.vel, body_angvel=s.angvel,
        imu_acc=mtv(s.rot, acc),
        imu_gyro=mtv(s.rot, s.angvel),
        imu_up=s.rot[..., 2, :],
        contact_force=contact_normal_force(m, s),
        tether_force=tether_force(m, s),
    )
