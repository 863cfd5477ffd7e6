"""Kinematics of the Oncilla's three-segment pantographic leg (§3.2.1, §3.3.1.2, §4.5).

Frames and conventions (engine convention, SI units):

* Hip frame: origin on the hip axis, ``x`` forward, ``y`` left, ``z`` up. The thesis
  writes foot positions as (horizontal y, vertical x) with x the *depth* below the hip
  (Tab. 4.1: "x0: vertical distance of the hip to the trajectory's center"); here that
  is ``(x_here, z_here) = (y_thesis, -x_thesis)``.
* ``hip`` [rad]: angle of the proximal segment (femur) from the downward vertical,
  positive when it points forward. ``knee`` [rad]: the inner knee angle ψ between
  femur and tibia (π would be a straight leg). Both grow when "the leg is moved to the
  front or the knee is extended", the encoder convention of Fig. 6.4.
* ``scapula`` [rad]: ab/adduction of the leg plane about the body's x axis through the
  hip, positive = abduction (foot moves outward); ``side`` = +1 for left legs, -1 for
  right legs.

Pantograph: the femur (hip→knee, ``femur``), the tibia (knee→heel, ``tibia``) and the
foot segment (heel→toe, ``foot``) with a parallel link that keeps the foot segment
parallel to the femur (Cheetah-cub lineage, Spröwitz et al. 2013, docs/sources.md#oncilla-legs).
The knee points forward (cat-like,
"loosely inspired by the legs of a cat", §3.2.1), so the tibia leans back::

    foot = (femur + foot) u(hip) + tibia u(hip + knee - π),   u(φ) = (sin φ, -cos φ)

The thesis (§3.3.1.2) had no algebraic inverse for the real cable-driven leg and solved
it numerically; :func:`inverse` does the same (damped Gauss-Newton with joint-limit
projection, fixed iterations, jit/vmap/grad-safe). For this rigid-pantograph model a
closed form *does* exist (two-link equivalent); :func:`inverse_closed_form` is kept as a
test oracle only.

Reachable area = image of the joint-limit box under :func:`forward`. Targets outside it
(e.g. a half ellipse "higher than strictly possible", §3.3.1.2, or splines "limited to
the range of the actuators", §4.2) are mapped by the projected solver to joint commands
at the limits, which reproduces the "dent" of §3.3.1.2.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics.models.leg_geometry import (  # noqa: F401  (public names of this module)
    IS_FORE,
    JOINTS,
    LEGS,
    KNEE_RANGE_HIND_RATIO,
    R_MAX,
    R_MAX_HIND,
    R_MIN,
    SIDES,
    LegGeometry,
    knee_angle_for_reach,
    leg_geometries,
    oncilla_geometry,
    oncilla_hind_geometry,
)


def forward(geom: LegGeometry, hip, knee) -> jnp.ndarray:
    """Sagittal forward kinematics.

    Args:
        geom: leg geometry.
        hip, knee: joint angles [rad], broadcastable arrays of shape (...).

    Returns:
        (..., 2) foot position (x forward, z up) in the hip frame [m].
    """
    hip = jnp.asarray(hip)
    knee = jnp.asarray(knee)
    a = geom.femur + geom.foot
    b = geom.tibia
    t2 = hip + knee - jnp.pi
    x = a * jnp.sin(hip) + b * jnp.sin(t2)
    z = -(a * jnp.cos(hip) + b * jnp.cos(t2))
    return jnp.stack(jnp.broadcast_arrays(x, z), axis=-1)


def forward3d(geom: LegGeometry, scapula, hip, knee, side) -> jnp.ndarray:
    """Forward kinematics including scapula ab/adduction.

    Args:
        scapula, hip, knee: joint angles [rad], broadcastable (...).
        side: +1 (left leg) or -1 (right leg), broadcastable.

    Returns:
        (..., 3) foot position (x, y, z) in the hip frame [m]; the leg plane is rotated
        about the x axis through the hip by ``scapula`` towards the outside.
    """
    p = forward(geom, hip, knee)
    depth = -p[..., 1]
    s = jnp.asarray(scapula)
    y = jnp.asarray(side) * depth * jnp.sin(s)
    z = -depth * jnp.cos(s)
    x, y, z = jnp.broadcast_arrays(p[..., 0], y, z)
    return jnp.stack([x, y, z], axis=-1)


def _fk_q(geom: LegGeometry, q: jnp.ndarray) -> jnp.ndarray:
    return forward(geom, q[0], q[1])


def _grid_init(geom: LegGeometry, target: jnp.ndarray, n: int) -> jnp.ndarray:
    """Nearest point of an n×n joint grid (coarse global start for the local solver)."""
    u = (jnp.arange(n, dtype=target.dtype) + 0.5) / n
    hips = geom.hip_min + u * (geom.hip_max - geom.hip_min)
    knees = geom.knee_min + u * (geom.knee_max - geom.knee_min)
    H, K = jnp.meshgrid(hips, knees, indexing="ij")
    P = forward(geom, H, K)
    d2 = jnp.sum((P - target[None, None, :]) ** 2, axis=-1).reshape(-1)
    i = jnp.argmin(d2)
    q0 = jnp.stack([H.reshape(-1)[i], K.reshape(-1)[i]])
    return jax.lax.stop_gradient(q0)


def _solve2(H: jnp.ndarray, g: jnp.ndarray) -> jnp.ndarray:
    """Solve the 2×2 system H x = g in closed form (H symmetric positive definite)."""
    det = H[0, 0] * H[1, 1] - H[0, 1] * H[1, 0]
    return jnp.stack([H[1, 1] * g[0] - H[0, 1] * g[1], H[0, 0] * g[1] - H[1, 0] * g[0]]) / det


def _solve_one(geom: LegGeometry, target: jnp.ndarray, n_iter: int, grid: int,
               damping: float) -> jnp.ndarray:
    lo, hi = geom.lower.astype(target.dtype), geom.upper.astype(target.dtype)
    q0 = _grid_init(geom, target, grid).astype(target.dtype)
    jac = jax.jacfwd(lambda q: _fk_q(geom, q))
    eye = jnp.eye(2, dtype=target.dtype)

    def body(_, q):
        r = _fk_q(geom, q) - target
        J = jac(q)
        JtJ = J.T @ J
        mu = damping * (jnp.trace(JtJ) + 1e-12)
        dq = -_solve2(JtJ + mu * eye, J.T @ r)
        # active set: joints whose full step leaves the box are put on their limit and
        # the step of the free joints is re-solved on the linearised residual
        q_full = q + dq
        active = (q_full < lo) | (q_full > hi)
        free = (~active).astype(q.dtype)
        d_act = jnp.where(active, jnp.clip(q_full, lo, hi) - q, 0.0)
        r2 = r + J @ d_act
        H = free[:, None] * JtJ * free[None, :] + jnp.diag(1.0 - free) + mu * eye
        d_free = -_solve2(H, free * (J.T @ r2))
        return jnp.clip(q + d_act + d_free, lo, hi)

    return jax.lax.fori_loop(0, n_iter, body, q0)


def inverse(geom: LegGeometry, foot_xz, *, n_iter: int = 12, grid: int = 16,
            damping: float = 1e-4) -> jnp.ndarray:
    """Numerical sagittal inverse kinematics (§3.3.1.2: solved numerically).

    A coarse ``grid``×``grid`` search over the joint box gives the start; then
    ``n_iter`` Levenberg-Marquardt (damped Gauss-Newton) steps, each followed by
    an active-set projection onto the joint limits (a joint whose step would leave its
    range is put on the limit and the other joint's step is re-solved). Inside the reachable area
    this converges to the exact solution; outside, to joint commands at the limits whose foot
    position is (close to) the nearest reachable point. Fixed iteration count: jit- and vmap-able,
    and differentiable with respect to the target and the geometry.

    Args:
        geom: leg geometry.
        foot_xz: (..., 2) target foot positions (x forward, z up) in the hip frame [m].

    Returns:
        (..., 2) joint angles (hip, knee) [rad], inside the joint limits.
    """
    p = jnp.asarray(foot_xz)
    if not jnp.issubdtype(p.dtype, jnp.floating):
        p = p.astype(jnp.float32)
    q = _inverse_flat(geom, p.reshape(-1, 2), n_iter, grid, float(damping))
    return q.reshape(p.shape)


@functools.partial(jax.jit, static_argnums=(2, 3, 4))
def _inverse_flat(geom: LegGeometry, flat: jnp.ndarray, n_iter: int, grid: int,
                  damping: float) -> jnp.ndarray:
    return jax.vmap(lambda t: _solve_one(geom, t, n_iter, grid, damping))(flat)


def inverse3d(geom: LegGeometry, foot_xyz, side, **kw) -> jnp.ndarray:
    """Inverse kinematics including the scapula.

    The scapula angle is closed form (rotation of the leg plane about the x axis),
    clipped to its limits; the sagittal part uses :func:`inverse` on the foot's position
    in the rotated leg plane.

    Args:
        foot_xyz: (..., 3) target foot positions in the hip frame [m].
        side: +1 (left) / -1 (right), broadcastable to (...).

    Returns:
        (..., 3) joint angles (scapula, hip, knee) [rad].
    """
    p = jnp.asarray(foot_xyz)
    lateral = jnp.asarray(side) * p[..., 1]
    scap = jnp.clip(jnp.arctan2(lateral, -p[..., 2]), geom.scapula_min, geom.scapula_max)
    depth = jnp.sqrt(p[..., 1] ** 2 + p[..., 2] ** 2 + 1e-20)
    q = inverse(geom, jnp.stack([p[..., 0], -depth], axis=-1), **kw)
    scap = jnp.broadcast_to(scap, q.shape[:-1])
    return jnp.concatenate([scap[..., None], q], axis=-1)


def inverse_legs(legs, foot_xyz, **kw) -> jnp.ndarray:
    """Inverse kinematics of the four legs, each with its own geometry.

    Legs that share one geometry object (the Oncilla's fore pair and its hind pair,
    :func:`~thesis.physics.models.leg_geometry.leg_geometries`) are solved in one
    :func:`inverse3d` call.

    Args:
        legs: 4 :class:`LegGeometry` in LEGS order.
        foot_xyz: (..., 4, 3) target foot positions, each in its leg's hip frame [m].

    Returns:
        (..., 4, 3) joint angles (scapula, hip, knee) [rad] per leg, LEGS order.
    """
    p = jnp.asarray(foot_xyz)
    groups: dict[int, list[int]] = {}
    for i, g in enumerate(legs):
        groups.setdefault(id(g), []).append(i)
    out = [None] * len(legs)
    for idx in groups.values():
        q = inverse3d(legs[idx[0]], p[..., idx, :],
                      jnp.asarray([SIDES[i] for i in idx], p.dtype), **kw)
        for j, i in enumerate(idx):
            out[i] = q[..., j, :]
    return jnp.stack(out, axis=-2)


def inverse_closed_form(geom: LegGeometry, foot_xz) -> jnp.ndarray:
    """Closed-form inverse of the rigid-pantograph model (test oracle, no clipping).

    Returns (..., 2) (hip, knee) [rad]; NaN where |foot| is outside the two-link reach.
    """
    p = jnp.asarray(foot_xz)
    a, b = geom.femur + geom.foot, geom.tibia
    r2 = jnp.sum(p**2, axis=-1)
    r = jnp.sqrt(r2)
    knee = jnp.arccos((a * a + b * b - r2) / (2 * a * b))
    phi = jnp.arctan2(p[..., 0], -p[..., 1])  # foot direction from the downward vertical
    delta = jnp.arccos((a * a + r2 - b * b) / (2 * a * r))  # femur leads the foot ray
    return jnp.stack([phi + delta, knee], axis=-1)


def reachable(geom: LegGeometry, points, tol: float = 1e-4, **kw) -> jnp.ndarray:
    """Mask of the sagittal foot positions inside the reachable area.

    Args:
        points: (..., 2) foot positions (x, z) in the hip frame [m].
        tol: accepted distance [m] between the target and the foot position of the
            (limit-projected) inverse kinematics.

    Returns:
        (...,) boolean mask.
    """
    p = jnp.asarray(points)
    q = inverse(geom, p, **kw)
    err = jnp.linalg.norm(forward(geom, q[..., 0], q[..., 1]) - p, axis=-1)
    return err <= tol


def reach_boundary(geom: LegGeometry, n_per_edge: int = 200) -> np.ndarray:
    """Closed polygon of the reachable area's boundary (sagittal plane).

    The forward map is one-to-one on the joint box (the knee never straightens), so the
    image of the box's boundary is the boundary of the reachable area.

    Returns:
        (4 n_per_edge, 2) foot positions [m], counter-clockwise around the box:
        knee at flexion stop (hip rising), hip at its maximum (knee opening), knee at
        the extension stop (hip falling), hip at its minimum (knee closing).
    """
    u = np.linspace(0.0, 1.0, n_per_edge, endpoint=False)
    h0, h1 = float(geom.hip_min), float(geom.hip_max)
    k0, k1 = float(geom.knee_min), float(geom.knee_max)
    hips = np.concatenate([h0 + u * (h1 - h0), np.full_like(u, h1), h1 - u * (h1 - h0),
                           np.full_like(u, h0)])
    knees = np.concatenate([np.full_like(u, k0), k0 + u * (k1 - k0), np.full_like(u, k1),
                            k1 - u * (k1 - k0)])
    return np.asarray(forward(geom, hips, knees), dtype=np.float64)


def horizontal_extent(geom: LegGeometry, depth, n_per_edge: int = 2000) -> np.ndarray:
    """Horizontal extent of the reachable area at given depths below the hip.

    Args:
        depth: (...,) depth(s) below the hip [m] (thesis x0).

    Returns:
        (..., 2) the (x_min, x_max) [m] of the reachable points at that depth (the
        outermost crossings of the boundary polygon; NaN where the line misses the
        area). Over the x0 range of Tab. 4.1 the slice is one interval.
    """
    poly = reach_boundary(geom, n_per_edge)
    p0, p1 = poly, np.roll(poly, -1, axis=0)
    d = np.asarray(depth, dtype=np.float64)
    zc = -d.reshape(-1, 1)
    z0, z1 = p0[None, :, 1], p1[None, :, 1]
    cross = (z0 - zc) * (z1 - zc) <= 0.0
    t = np.where(z1 != z0, (zc - z0) / np.where(z1 != z0, z1 - z0, 1.0), 0.0)
    x = p0[None, :, 0] + t * (p1[None, :, 0] - p0[None, :, 0])
    xmin = np.where(cross, x, np.inf).min(axis=1)
    xmax = np.where(cross, x, -np.inf).max(axis=1)
    out = np.stack([xmin, xmax], axis=-1)
    out[~np.isfinite(out).all(axis=1)] = np.nan
    return out.reshape(d.shape + (2,))
