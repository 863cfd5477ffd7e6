"""Projected block-Jacobi solver of the velocity-level LCP (thesis §7.2, FACTS §2.4 item 5).

Choice and why. The original updates every row in parallel (Jacobi) inside each of a
fixed number of iterations. A row-by-row Gauss-Seidel sweep, or a Gauss-Seidel over a
static colouring of the rows, is inherently sequential: the quadruped's torso shares a
body with ~60 rows, so a colouring needs >= 60 colours, i.e. >= 60 dependent phases per
iteration, each a handful of tiny XLA kernels -- far too slow on CPU. Plain row-Jacobi,
on the other hand, diverges on the strongly coupled rows *of one joint* (the 3 point rows
of a ball joint alone give an iteration matrix with eigenvalue -2). We therefore use
**block Jacobi**: the <= 6 equality rows of each joint are solved *exactly* together
(a 6x6 SPD inverse per joint, computed once per step), and every other row (servo, limit,
spring, contact normal, friction, torsion) is a scalar block. All blocks are updated in
parallel from the same velocities, with a relaxation factor ``model.relaxation``, then
projected on their bounds (friction bounds use the just-projected normal impulse), for a
static ``model.solver_iterations`` sweeps (``lax.fori_loop``, reverse-differentiable).
Warm starting scales last step's impulses by ``model.warm_start``.

Per iteration the work is: gather the velocities of each row's two bodies, one batched
6x6 mat-vec for the joint blocks, elementwise ops for the scalar rows, and one
scatter-add (segment sum) of impulses back to bodies. Everything constant within the
step (effective masses, block inverses, M^-1 J^T) is computed once before the loop.

Known limits (measured, see the engine report): convergence of the parallel block updates
is linear and slow on closed loops and long chains of similar masses (a 4-link chain with
a weld needs ~400 sweeps for 1e-4 accuracy, see ``tests/physics/test_solver.py``);
20 sweeps leave visible joint drift in violent motions (< 2 cm on a falling 3-link chain,
not growing). Under ``jax.vmap`` on CPU the scatter-add of the impulses becomes a slow
strided loop, so a batched model (``Model.batched``) adds them with a one-hot matrix
product instead; together with XLA's own reductions instead of YNNPACK fusions
(``thesis.jaxsetup.xla_flags``) a vmapped robot then costs ~0.6x a single one (Tab. 7.1:
80 us per robot-step per core at batch 128 against 140 us for one robot, controller
included).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics.math import inv3, inv_spd, mm, mmt, mtv, mv
from thesis.physics.types import Model

__all__ = ["inverse_mass", "solve"]


def inverse_mass(m: Model, rot_ext):
    """(inv_mass (n_body+1,), inv_inertia_world (n_body+1, 3, 3)); the world gets zeros."""
    dtype = rot_ext.dtype
    inv_m = jnp.concatenate([1.0 / m.body_mass, jnp.zeros((1,), dtype)])
    inv_ib = inv3(m.body_inertia)
    inv_ib = jnp.concatenate([inv_ib, jnp.zeros((1, 3, 3), dtype)])
    inv_iw = mmt(mm(rot_ext, inv_ib), rot_ext)
    return inv_m, inv_iw


def _apply_minv(j, inv_m, inv_iw):
    """M^-1 J^T for rows j (..., 6) of bodies with (inv_m (...,), inv_iw (..., 3, 3))."""
    lin = j[..., :3] * inv_m[..., None]
    ang = mv(inv_iw, j[..., 3:])
    return jnp.concatenate([lin, ang], -1)


def solve(m: Model, v0, inv_m, inv_iw, blocks, rows, lam_joint0, lam_row0):
    """Solve for post-step velocities and impulses.

    Args:
        v0: (n_body + 1, 6) velocities after external forces (world row zero).
        inv_m, inv_iw: from :func:`inverse_mass`.
        blocks: dict ``ja``, ``jb`` (n_joint, 6, 6), ``bias`` (n_joint, 6),
            ``gamma`` (n_joint, 6) relative softness, with static ``body_a``/``body_b``.
        rows: dict from ``constraint.scalar_rows``.
        lam_joint0 (n_joint, 6), lam_row0 (n_rows,): warm-start impulses [N s].
    Returns:
        (v, lam_joint, lam_row): final velocities (n_body + 1, 6) and impulses.
    """
    dtype = v0.dtype
    nb1 = v0.shape[0]
    w = m.relaxation
    mask = jnp.asarray(m.joint_row_mask, dtype)

    # --- joint blocks: exact block inverse of (A + C) ---
    ba, bb = blocks["body_a"], blocks["body_b"]
    wa = _apply_minv(blocks["ja"], inv_m[ba][:, None], inv_iw[ba][:, None])
    wb = _apply_minv(blocks["jb"], inv_m[bb][:, None], inv_iw[bb][:, None])
    a_blk = mmt(blocks["ja"], wa) + mmt(blocks["jb"], wb)
    diag = jnp.diagonal(a_blk, axis1=-2, axis2=-1)
    cfm_blk = blocks["gamma"] * diag * mask
    a_soft = a_blk + jnp.eye(6, dtype=dtype)[None] * (cfm_blk + (1.0 - mask))[..., None, :]
    a_inv = inv_spd(a_soft)

    # --- scalar rows ---
    ra, rb = rows["body_a"], rows["body_b"]
    wra = _apply_minv(rows["ja"], inv_m[ra], inv_iw[ra])
    wrb = _apply_minv(rows["jb"], inv_m[rb], inv_iw[rb])
    d = jnp.sum(rows["ja"] * wra, -1) + jnp.sum(rows["jb"] * wrb, -1)
    cfm = rows["gamma"] * d + rows["cfm_abs"]
    m_c = 1.0 / jnp.maximum(d + cfm, 1e-12)
    ref, is_fric = rows["ref"], rows["is_fric"]

    seg = np.concatenate([ba, bb, ra, rb]).astype(np.int32)
    if m.batched:  # one-hot product instead of a scatter-add (see Model.batched)
        onehot = np.zeros((seg.shape[0], nb1), np.float32)
        onehot[np.arange(seg.shape[0]), seg] = 1.0
        onehot = jnp.asarray(onehot, dtype)

    def velocities(lj, lr):
        dv = jnp.concatenate([
            mtv(wa, lj), mtv(wb, lj),
            wra * lr[:, None], wrb * lr[:, None]])
        if m.batched:
            return v0 + jnp.einsum("sn,sk->nk", onehot, dv)
        return v0 + jax.ops.segment_sum(dv, seg, num_segments=nb1)

    def project(lr):
        lr = jnp.clip(lr, rows["lo"], rows["hi"])
        bound = rows["fric"] * lr[ref]
        return jnp.where(is_fric, jnp.clip(lr, -bound, bound), lr)

    def sweep(_, carry):
        lj, lr = carry
        v = velocities(lj, lr)
        jv_j = mv(blocks["ja"], v[ba]) + mv(blocks["jb"], v[bb])
        res_j = (jv_j + blocks["bias"] + cfm_blk * lj) * mask
        lj = lj - w * mv(a_inv, res_j)
        jv_r = jnp.sum(rows["ja"] * v[ra], -1) + jnp.sum(rows["jb"] * v[rb], -1)
        lr = project(lr - w * m_c * (jv_r + rows["bias"] + cfm * lr))
        return lj, lr

    lam = (lam_joint0 * mask, project(lam_row0))
    lj, lr = jax.lax.fori_loop(0, m.solver_iterations, sweep, lam)
    return velocities(lj, lr), lj, lr
