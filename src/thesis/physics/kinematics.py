"""Joint kinematics: world frames, joint coordinates and the Jacobians of joint rows.

Every function is vectorised over all joints or joint coordinates at once; per-type
formulas are selected with static numpy masks (``jnp.where``), never Python branches.
A Jacobian row is a pair ``(Ja, Jb)`` of (..., 6) vectors ``[linear, angular]`` acting on
the world velocities of body a (= joint body1) and body b (= body2), so that the rate of
the constrained quantity is ``Ja . v_a + Jb . v_b`` (thesis §7.2, docs/sources.md#tpx-rows).
Angles come from ``atan2`` of projections (no ``arccos``, docs/sources.md#tpx-step quirk), so they
are smooth and finite-gradient everywhere in (-pi, pi).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from thesis.physics.math import mm, mmt, mv, safe_norm, vee
from thesis.physics.types import DofKind, JointType, Model

__all__ = ["extend", "joint_frames", "joint_coordinates", "joint_rows"]


def extend(m: Model, pos, rot, vel=None, angvel=None):
    """Append the static world body (index ``n_body``) to pose/velocity arrays."""
    dt = pos.dtype
    pos = jnp.concatenate([pos, jnp.zeros((1, 3), dt)])
    rot = jnp.concatenate([rot, jnp.eye(3, dtype=dt)[None]])
    if vel is None:
        return pos, rot
    v6 = jnp.concatenate([vel, angvel], axis=-1)
    return pos, rot, jnp.concatenate([v6, jnp.zeros((1, 6), dt)])


def joint_frames(m: Model, pos, rot):
    """World-frame joint geometry from extended poses (n_body + 1 bodies).

    Returns a dict of (n_joint, ...) arrays: ``r1``/``r2`` anchor offsets from each CoM
    [m], ``x1``/``x2`` world anchors [m], ``f1``/``f2`` (n_joint, 3, 3) joint axes carried
    by body1/body2 (columns), ``rot1``/``rot2`` body rotations.
    """
    b1, b2 = m.joint_body1, m.joint_body2
    rot1, rot2 = rot[b1], rot[b2]
    r1 = mv(rot1, m.joint_anchor1)
    r2 = mv(rot2, m.joint_anchor2)
    return dict(rot1=rot1, rot2=rot2, r1=r1, r2=r2, x1=pos[b1] + r1, x2=pos[b2] + r2,
                f1=mm(rot1, m.joint_frame1), f2=mm(rot2, m.joint_frame2))


def _lin_jac(d, r1, r2):
    """Rows for ``d . (x2 - x1)`` with x_i anchored on body i: (Ja, Jb), (..., 6) each."""
    ja = jnp.concatenate([-d, -jnp.cross(r1, d)], -1)
    jb = jnp.concatenate([d, jnp.cross(r2, d)], -1)
    return ja, jb


def _ang_jac(d):
    z = jnp.zeros_like(d)
    return jnp.concatenate([z, -d], -1), jnp.concatenate([z, d], -1)


def _rotvec(e):
    """Rotation vector of rotation matrices e (..., 3, 3) (log map), safe at identity."""
    w = vee(e)
    s = safe_norm(w)
    c = 0.5 * (jnp.trace(e, axis1=-2, axis2=-1) - 1.0)
    theta = jnp.arctan2(s, c)
    small = s < 1e-6
    factor = jnp.where(small, 1.0 + s * s / 6.0, theta / jnp.where(small, 1.0, s))
    return w * factor[..., None]


def joint_coordinates(m: Model, fr, vel6):
    """Joint coordinates, their rates and Jacobian rows (angles inside servos and limits:
    docs/sources.md#tpx-step item 7).

    Args:
        fr: output of :func:`joint_frames`.
        vel6: (n_body + 1, 6) extended world velocities [linear, angular].
    Returns:
        (q, qdot, ja, jb): q (n_dof,) [rad or m]; qdot (n_dof,) [rad/s or m/s];
        ja, jb (n_dof, 6) so that qdot = ja . v[body1] + jb . v[body2].
    """
    if m.n_dof == 0:
        z = jnp.zeros((0,), vel6.dtype)
        return z, z, jnp.zeros((0, 6), vel6.dtype), jnp.zeros((0, 6), vel6.dtype)
    j = m.dof_joint
    slot = m.dof_slot
    jt = m.joint_type[j]
    f1, f2 = fr["f1"][j], fr["f2"][j]
    e1, e2, e3 = f1[..., 0], f1[..., 1], f1[..., 2]
    u2, q2 = f2[..., 1], f2[..., 2]
    # hinge / first universal coordinate: rotation of body2's e2 about e1
    ang_h = jnp.arctan2(jnp.sum(u2 * e3, -1), jnp.sum(u2 * e2, -1))
    # second universal coordinate: rotation about u2 (R = Rot(e1, a) Rot(e2, b))
    c2 = jnp.cross(e1, u2)
    ang_u = jnp.arctan2(jnp.sum(q2 * e1, -1), jnp.sum(q2 * c2, -1))
    # ball: rotation vector of body2 relative to body1, in body1's joint frame
    rv = _rotvec(mm(jnp.swapaxes(f1, -1, -2), f2))
    ang_b = jnp.take_along_axis(rv, slot[:, None], axis=-1)[:, 0]
    # slider: displacement of body2's anchor along e1
    x21 = fr["x2"][j] - fr["x1"][j]
    disp = jnp.sum(e1 * x21, -1)

    is_u2 = np.asarray((jt == JointType.UNIVERSAL) & (slot == 1))
    is_ball = np.asarray(jt == JointType.BALL)
    is_lin = np.asarray(m.dof_kind == DofKind.LINEAR)
    q = jnp.where(is_lin, disp, jnp.where(is_ball, ang_b, jnp.where(is_u2, ang_u, ang_h)))

    ball_axis = jnp.take_along_axis(f1, slot[:, None, None], axis=-1)[..., 0]
    axis = jnp.where(is_ball[:, None], ball_axis, jnp.where(is_u2[:, None], u2, e1))
    ja_a, jb_a = _ang_jac(axis)
    ja_l, jb_l = _lin_jac(e1, fr["r1"][j], fr["r2"][j])
    ja = jnp.where(is_lin[:, None], ja_l, ja_a)
    jb = jnp.where(is_lin[:, None], jb_l, jb_a)
    va = vel6[m.joint_body1[j]]
    vb = vel6[m.joint_body2[j]]
    qdot = jnp.sum(ja * va, -1) + jnp.sum(jb * vb, -1)
    return q, qdot, ja, jb


def joint_rows(m: Model, fr):
    """The 6 equality rows of every joint (3 linear, 3 angular), masked per type.

    Linear rows keep the two anchors together along body1's joint axes; angular rows lock
    the relative rotation (fixed, slider), keep the hinge axes aligned (hinge), or keep
    the two universal axes perpendicular (universal) (docs/sources.md#tpx-rows).

    Returns:
        (ja, jb, err): ja, jb (n_joint, 6, 6) rows x [linear, angular]; err (n_joint, 6)
        position error of each row [m or rad] (zero rows where masked).
    """
    f1, f2 = fr["f1"], fr["f2"]
    d_lin = jnp.swapaxes(f1, -1, -2)  # (nj, 3 rows, 3)
    x21 = fr["x2"] - fr["x1"]
    err_lin = mv(d_lin, x21)
    ja_l, jb_l = _lin_jac(d_lin, fr["r1"][:, None], fr["r2"][:, None])

    a1, a2, u2 = f1[..., 0], f2[..., 0], f2[..., 1]
    # relative-rotation error (world) of fixed / slider joints: rot2 (rot1 Q0)^T
    e_rot = vee(mmt(fr["rot2"], mm(fr["rot1"], m.joint_rel_rot)))
    err_lock = mv(d_lin, e_rot)
    err_hinge = mv(d_lin, jnp.cross(a1, a2))
    is_h = np.asarray(m.joint_type == JointType.HINGE)[:, None]
    is_u = np.asarray(m.joint_type == JointType.UNIVERSAL)[:, None]
    err_ang = jnp.where(is_h, err_hinge, err_lock)
    n_u = jnp.cross(a1, u2)
    err_u = -jnp.sum(a1 * u2, -1)
    d_ang = d_lin.at[:, 0].set(jnp.where(is_u, n_u, d_lin[:, 0]))
    err_ang = err_ang.at[:, 0].set(jnp.where(is_u[:, 0], err_u, err_ang[:, 0]))
    ja_a, jb_a = _ang_jac(d_ang)

    mask = jnp.asarray(m.joint_row_mask, f1.dtype)
    ja = jnp.concatenate([ja_l, ja_a], axis=1) * mask[..., None]
    jb = jnp.concatenate([jb_l, jb_a], axis=1) * mask[..., None]
    err = jnp.concatenate([err_lin, err_ang], axis=1) * mask
    return ja, jb, err
