"""Projected block-Jacobi solver of the velocity-level LCP (thesis §7.2;
docs/sources.md#tpx-step item 5).

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

Sweep order (``model.sweep_order``). ``"jacobi"`` (the default, every model of chapters 5
and 7): blocks and rows all update from the same velocities. ``"blocks_first"`` (the
Oncilla's of chapters 3, 4 and 6): the joint blocks update first, then every scalar row
from the velocities the new block impulses give (Gauss-Seidel between the two groups,
Jacobi within each); each group's impulses are scattered to the bodies once per sweep, as
in ``"jacobi"``. A joint's servo and limit rows act on the same two bodies as its block;
updated from the same velocities, block and row each correct the same residual and
overshoot, which only a small relaxation damps. On the Oncilla (a light leg on a universal
joint under a 4-kg trunk) that left the scapula servo rows 20-30 % from their solution
after 120 sweeps at relaxation 0.3; blocks first, at relaxation 1.0, 120 sweeps bring
every row group within 3 % (``thesis.physics.models.oncilla``, Solver;
``tests/physics/test_solver.py``).

Momentum (``sweep_order="momentum"``, ``model.momentum`` = beta, ``model.momentum_restart``).
Blocks-first sweeps converge linearly and slowly on the Oncilla (the error falls about
10x per 115 sweeps): every scalar row is updated with the effective mass of its two
bodies, not of the mechanism behind them, so a toe's tangential force reaches the trunk
about one joint per sweep. The momentum order runs the same blocks-first sweep T, but
from extrapolated impulses (Nesterov's scheme on the fixed-point map, as in accelerated
projected Gauss-Seidel / APGD solvers): ``x_{k+1} = T(y_k)``, ``y_{k+1} = P(x_{k+1} +
beta (x_{k+1} - x_k))`` with P the rows' projection (bounds, friction cone) applied
after the extrapolation. The joint blocks are not projected, so the velocity change of
their extrapolated impulses is extrapolated in the same way and carried from sweep to
sweep, not scattered again: a sweep still scatters each group once. On a mode of T
with eigenvalue mu the extrapolation turns the rate mu into about sqrt(mu beta) near mu
= 1 (a slow mode is sped up) but makes a mode with mu < -1/(1 + 2 beta) diverge (the
roots of z^2 - mu (1 + beta) z + mu beta). Blocks first at relaxation 1 has modes at mu
of about -0.96 on the Oncilla, carried by the joint blocks (the blocks of one leg's
chain update in parallel and overshoot); a relaxation w maps mu to 1 - w (1 - mu), so
the blocks need w below about (1 + 1/(1 + 2 beta)) / 1.96, 0.70 at beta 0.85 (0.7
diverges). Its slowest modes (mu about 0.98) lie on the joint blocks and the contacts;
the joints' scalar rows (servo, limit, spring) carry neither, and they take their own,
larger factor (``model.row_relaxation``), divided by the number of rows of their joint
coordinate that can act in this step (an idle limit has both bounds at 0): such rows
share one Jacobian, so n of them updated in parallel overshoot n-fold (a mode at 1 - n w,
as k contacts on one body), which the extrapolation turns into divergence (the Puppy
II's knee spring and its engaged limit, undivided, diverge above about 0.65). On the saved
states of ``thesis bench solver`` of the Oncilla with point feet at 2.5 ms
(``tests/modelcheck/test_solver_bench.py``), with the rows at the blocks' factor no setting
reaches 1e-2 in 40 sweeps; with rows 0.8, blocks 0.65, contacts 0.5 and beta 0.85 every
state is within 1e-2 of the direct solution in 40 sweeps and 1e-4 in 120 (blocks first: 240
and 480), and the Puppy II's in 60 and 120. On the chapters' Oncilla (foot plates, 0.625 ms;
the default bench) the same settings are within 1e-2 in 20 sweeps on all six states (blocks
first 60, Jacobi 160) and within 1e-4 in 30-160 on five; the sixth (Tab. 3.1b's spline at
1.5 s) keeps a slow mode that no order removes: 2.9e-3 at 120 sweeps, 9.6e-4 at 480 (blocks
first 4.1e-3 and 3.3e-3).

With ``momentum_restart`` a sweep whose update ``x_{k+1} - y_k`` points against the last
change ``x_{k+1} - x_k`` (a negative inner product in the metric of the softened Delassus
diagonal D, per robot) does not extrapolate: the momentum has overshot (the gradient
scheme of adaptive restart, O'Donoghue and Candes 2015). The test is a ``jnp.where``,
so the sweeps stay branch-free, of static count and differentiable (piecewise, like the
projections). The returned impulses are ``x``, projected; the fixed point is that of the
other orders.

Contact relaxation (``model.contact_relaxation``; None by default, the contact rows then
use ``model.relaxation``). The contact rows of one sweep update in parallel from the same
velocities in either order, so k contacts pressing on one light body (a toe on a pebble
field touches the floor and up to ``field_k`` pebbles) each correct the same residual and
together overshoot about k-fold: at relaxation 1.0 such a foot's contacts diverge. A
separate factor for the contact rows (normals, friction, torsion) under-relaxes them alone
and leaves the joints' servo, limit and spring rows at ``model.relaxation``, or at
``model.row_relaxation`` where that is set (Momentum); the joint blocks always take
``model.relaxation``.

Friction cone. The two friction rows of a contact are projected together (:func:`cone`):
their impulse pair is scaled radially onto the disc of radius ``mu lambda_n`` (the
exact, nearest-point projection for isotropic Coulomb friction, as in projected
Gauss-Seidel solvers and MuJoCo's elliptic cones), or, for a directional material, onto
the ellipse with the semi-axes of its grain frame, scaled in that ellipse's own metric.
At a fixed point of the sweeps the friction impulse is then anti-parallel to the slip
(``lambda = c (lambda - m v)`` with ``c`` in (0, 1) forces ``lambda`` along ``-v``), with
the magnitude the ellipse allows in that direction: the coaxial elliptic friction law,
not the maximal-dissipation one, whose force is not opposite to the slip. Trade-off:
the alternative, a pyramid turned to the current slip direction, keeps the per-row box
but needs the slip direction, which is undefined and non-differentiable at rest; the
radial scaling is a handful of elementwise ops per contact, continuous everywhere, and
its square root is only taken where the pair lies outside the cone (``r > mu lambda_n
>= 0``), so gradients stay finite at zero slip.
Warm starting scales last step's impulses by ``model.warm_start``.

Per iteration the work is: gather the velocities of each row's two bodies, one batched
6x6 mat-vec for the joint blocks, elementwise ops for the scalar rows, and one
scatter-add (segment sum) of impulses back to bodies. Everything constant within the
step (effective masses, block inverses, M^-1 J^T) is computed once before the loop.

Known limits (measured, see the engine report): convergence of the parallel block updates
is linear and slow on closed loops and long chains of similar masses (a 4-link chain with
a weld needs ~400 sweeps for 1e-4 accuracy, see ``tests/physics/test_solver.py``);
20 sweeps leave visible joint drift in violent motions (< 2 cm on a falling 3-link chain,
not growing).

Batches of robots (``Model.batched``, Tab. 7.1 at batch 128). Under ``jax.vmap`` every
array gets the robots as its first axis, and each of the sweeps' tiny reductions (over
3-6 entries) becomes a strided loop per robot; a vmapped scatter-add is slower still. A
batched model therefore gives :func:`solve` its own ``jax.vmap`` rule
(``jax.custom_batching.custom_vmap``, :func:`_solve_batch_last`): the solver's inputs are
moved to robots-*last*, and the same per-step preparation and sweeps (written for a
leading row axis and any trailing batch axes) run once over the batch with contiguous
loops over robots; the impulses go back to bodies by a scatter-add over the leading body
axis, whose rows are contiguous runs of 6 x robots values. Together with XLA's own
reductions instead of YNNPACK fusions (``thesis.jaxsetup.xla_flags``), one sweep over 64
quadrupeds on one core costs about a quarter of the plain ``jax.vmap`` of the
robots-first code. A ``custom_vjp`` around it keeps reverse-mode gradients available in
either order of ``jax.grad`` and ``jax.vmap`` (:func:`_batched_solver`). One robot runs
the same code without batch axes.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics.math import inv3, inv_spd, mm, mmt
from thesis.physics.types import Model

__all__ = ["cone", "inverse_mass", "solve"]


def inverse_mass(m: Model, rot_ext):
    """(inv_mass (n_body+1,), inv_inertia_world (n_body+1, 3, 3)); the world gets zeros."""
    dtype = rot_ext.dtype
    inv_m = jnp.concatenate([1.0 / m.body_mass, jnp.zeros((1,), dtype)])
    inv_ib = inv3(m.body_inertia)
    inv_ib = jnp.concatenate([inv_ib, jnp.zeros((1, 3, 3), dtype)])
    inv_iw = mmt(mm(rot_ext, inv_ib), rot_ext)
    return inv_m, inv_iw


def _apply_minv(j, inv_m, inv_iw, axis):
    """M^-1 J^T of rows ``j`` whose 6 entries (linear, angular) lie on ``axis``.

    ``inv_m`` and ``inv_iw`` (3x3 on axes ``axis``, ``axis + 1``) are broadcast against
    ``j`` with size-1 axes before ``axis``; axes after the row's entries are batch axes.
    """
    pre = (slice(None),) * axis
    lin = j[pre + (slice(0, 3),)] * inv_m[pre + (None,)]
    ang = jnp.sum(inv_iw * j[pre + (None, slice(3, 6))], axis=axis + 1)
    return jnp.concatenate([lin, ang], axis)


_ROW_KEYS = ("ja", "jb", "bias", "gamma", "cfm_abs", "lo", "hi", "fric", "fric_lo")
_BLOCK_KEYS = ("ja", "jb", "bias", "gamma")


def _prepare(mask, idx, v0, inv_m, inv_iw, blocks, rows, cone_rows=None):
    """Everything constant within the step's sweeps.

    For one robot, or for a batch with the robots on trailing axes (every array then has
    shape (rows, ..., *B) and ``v0.ndim - 2`` trailing axes; :func:`_solve_batch_last`).

    Args:
        mask: (n_joint, 6) static 0/1 rows of each joint block. idx: static body indices
            ``ba, bb, ra, rb`` of the blocks and rows. cone_rows: static ``(first, n)``
            of the friction rows (``constraint.scalar_rows``' ``cone``) or None. Others
            as in :func:`solve`.
    Returns:
        dict of arrays with a leading row axis: ``v0``; joint blocks ``mask`` (the static
        mask with the batch axes), ``ja``, ``jb``,
        ``wa``, ``wb`` (M^-1 J^T), ``a_inv`` (inverse of the softened 6x6 block),
        ``bias_j``, ``cfm_j``, ``d_j`` (the softened block's diagonal, 0 on unused
        rows); scalar rows ``rja``, ``rjb``, ``wra``, ``wrb``, ``m_c``
        (effective mass), ``cfm``, ``bias``, ``lo``, ``hi``, ``fric`` and, for
        directional friction, ``fric_lo``.
    """
    dtype = v0.dtype
    ba, bb, ra, rb = idx
    extra = (1,) * (v0.ndim - 2)  # trailing batch axes (robots-last layout)
    mask = jnp.asarray(mask, dtype).reshape(mask.shape + extra)
    ja, jb = blocks["ja"], blocks["jb"]  # (n_joint, 6 rows, 6 entries, *B)
    wa = _apply_minv(ja, inv_m[ba][:, None], inv_iw[ba][:, None], 2)
    wb = _apply_minv(jb, inv_m[bb][:, None], inv_iw[bb][:, None], 2)
    a_blk = (jnp.sum(ja[:, :, None] * wa[:, None], axis=3)
             + jnp.sum(jb[:, :, None] * wb[:, None], axis=3))
    diag = jnp.stack([a_blk[:, k, k] for k in range(6)], axis=1)
    cfm_blk = blocks["gamma"] * diag * mask
    eye = jnp.eye(6, dtype=dtype).reshape((1, 6, 6) + extra)
    a_soft = a_blk + eye * (cfm_blk + (1.0 - mask))[:, None]
    wra = _apply_minv(rows["ja"], inv_m[ra], inv_iw[ra], 1)
    wrb = _apply_minv(rows["jb"], inv_m[rb], inv_iw[rb], 1)
    d = jnp.sum(rows["ja"] * wra, axis=1) + jnp.sum(rows["jb"] * wrb, axis=1)
    cfm = rows["gamma"] * d + rows["cfm_abs"]
    m_c = 1.0 / jnp.maximum(d + cfm, 1e-12)
    if cone_rows is not None:
        # one effective mass for both friction rows of a contact (the mean of their
        # diagonals): with a different one per row the fixed point of the projected
        # update, lambda = s (lambda - diag(m1, m2) v), turns the friction away from the
        # slip v towards the row of larger mass; with a common one it opposes the slip
        first, n = cone_rows
        t1, t2 = slice(first, first + n), slice(first + n, first + 2 * n)
        pair = 2.0 / jnp.maximum(d[t1] + cfm[t1] + d[t2] + cfm[t2], 1e-12)
        m_c = jnp.concatenate([m_c[:first], pair, pair, m_c[first + 2 * n:]])
    out = dict(v0=v0, mask=mask, ja=ja, jb=jb, wa=wa, wb=wb, a_inv=inv_spd(a_soft, axis=1),
               bias_j=blocks["bias"], cfm_j=cfm_blk, d_j=(diag + cfm_blk) * mask,
               rja=rows["ja"], rjb=rows["jb"],
               wra=wra, wrb=wrb, m_c=m_c, cfm=cfm,
               bias=rows["bias"], lo=rows["lo"], hi=rows["hi"], fric=rows["fric"])
    if "fric_lo" in rows:  # directional friction (static)
        out["fric_lo"] = rows["fric_lo"]
    return out


def cone(a, b, lam_n, mu1, mu2):
    """Project tangential impulses onto the friction cone of their normal impulse.

    ``(a / mu1)^2 + (b / mu2)^2 <= lam_n^2`` by radial scaling of the pair (module
    docstring, "Friction cone"); ``mu1 == mu2`` is the isotropic disc
    ``|(a, b)| <= mu lambda_n``. A zero coefficient forces its impulse to zero.

    Args:
        a, b: impulses of the contacts' ``t1`` and ``t2`` rows [N s] (n, *B).
        lam_n: their normal impulses, >= 0 (n, *B). mu1, mu2: semi-axes along ``t1``
            and ``t2`` (n, *B), >= 0.
    Returns:
        (a, b) projected.
    """
    pos1, pos2 = mu1 > 0, mu2 > 0
    u = jnp.where(pos1, a / jnp.where(pos1, mu1, 1.0), 0.0)
    w = jnp.where(pos2, b / jnp.where(pos2, mu2, 1.0), 0.0)
    r2 = u * u + w * w
    over = r2 > lam_n * lam_n  # implies r2 > 0: the root below never sees zero
    scale = jnp.where(over, lam_n / jnp.sqrt(jnp.where(over, r2, 1.0)), 1.0)
    return jnp.where(pos1, a * scale, 0.0), jnp.where(pos2, b * scale, 0.0)


def _sweeps(m: Model, idx, fric_idx, relax, c, lam_joint0, lam_row0, report=False):
    """The static number of block-Jacobi sweeps and the final velocities.

    Written for arrays with a leading row axis and any number of *trailing* batch axes
    (none for one robot): every reduction names its axis from the front, so the batched
    solver (:func:`_solve_batch_last`) runs the same code with the robots as the last,
    contiguous axis, where XLA's loops vectorise over robots.

    Args:
        idx: static ``ba, bb, ra, rb``; fric_idx: static row bookkeeping
            ``(ref, is_fric, cone, dof)`` of ``constraint.scalar_rows`` (``dof`` None
            where the rows have none).
        relax: relaxation factor (scalar or (*B,)); the contact rows take
            ``m.contact_relaxation`` and the other scalar rows ``m.row_relaxation``
            instead where they are set. c: dict of :func:`_prepare`.
        lam_joint0 (n_joint, 6, *B), lam_row0 (n_rows, *B): warm start.
        report: also return the final relative residual (:func:`solve`).
    Returns:
        (v (n_body + 1, 6, *B), lam_joint, lam_row), and with ``report`` the relative
        residual (*B).
    """
    ba, bb, ra, rb = idx
    ref, is_fric, cone_rows, row_dof = fric_idx
    v0 = c["v0"]
    nb1, dtype, extra = v0.shape[0], v0.dtype, v0.ndim - 2
    mask = c["mask"]
    relax = jnp.asarray(relax, dtype)
    relax_j, relax_r = relax.reshape((1, 1) + relax.shape), relax.reshape((1,) + relax.shape)
    # the contacts' rows are the last ones: normals, t1, t2 (and torsion) from here on
    n_rows = c["bias"].shape[0]
    is_contact = (np.arange(n_rows) >= cone_rows[0] - cone_rows[1] if cone_rows is not None
                  else np.zeros(n_rows, bool)).reshape((n_rows,) + (1,) * relax.ndim)
    if m.row_relaxation is not None:
        relax_rows = jnp.asarray(m.row_relaxation, dtype)
        if row_dof is not None and np.any(row_dof >= 0):
            # divided by the rows of the same joint coordinate that can act this step
            # (bounds not both zero: an idle limit is clamped to 0): they share one
            # Jacobian and overshoot together (module docstring, Momentum)
            same = ((row_dof[:, None] == row_dof[None, :]) & (row_dof[:, None] >= 0))
            acts = (c["hi"] > c["lo"]).astype(dtype)
            n_act = jnp.tensordot(jnp.asarray(same, dtype), acts, axes=1)
            relax_rows = relax_rows / jnp.maximum(n_act, 1.0)
        relax_r = jnp.where(is_contact, relax_r, relax_rows)
    if m.contact_relaxation is not None and cone_rows is not None:
        relax_r = jnp.where(is_contact, jnp.asarray(m.contact_relaxation, dtype), relax_r)
    seg = np.concatenate([ba, bb, ra, rb]).astype(np.int32)
    seg_j, seg_r = seg[:len(ba) + len(bb)], seg[len(ba) + len(bb):]

    def bmv(a, x):  # (n, r, k, *B), (n, k, *B) -> (n, r, *B)
        return jnp.sum(a * x[:, None], axis=2)

    def velocities(lj, lr):
        dv = jnp.concatenate([
            jnp.sum(c["wa"] * lj[:, :, None], axis=1), jnp.sum(c["wb"] * lj[:, :, None], axis=1),
            c["wra"] * lr[:, None], c["wrb"] * lr[:, None]])
        # a scatter-add over the leading (body) axis: robots-last, each added row is a
        # contiguous run of 6 x robots values
        return v0 + jax.ops.segment_sum(dv, seg, num_segments=nb1)

    def dv_joints(lj):  # the joint blocks' velocity change (blocks_first)
        dv = jnp.concatenate([jnp.sum(c["wa"] * lj[:, :, None], axis=1),
                              jnp.sum(c["wb"] * lj[:, :, None], axis=1)])
        return jax.ops.segment_sum(dv, seg_j, num_segments=nb1)

    def dv_rows(lr):  # the scalar rows' velocity change (blocks_first)
        dv = jnp.concatenate([c["wra"] * lr[:, None], c["wrb"] * lr[:, None]])
        return jax.ops.segment_sum(dv, seg_r, num_segments=nb1)

    def project(lr):
        lr = jnp.clip(lr, c["lo"], c["hi"])
        if np.any(is_fric):  # torsion: a box of fric x the normal impulse (static branch)
            bound = c["fric"] * lr[ref]
            lr = jnp.where(is_fric.reshape(is_fric.shape + (1,) * extra),
                           jnp.clip(lr, -bound, bound), lr)
        if cone_rows is None:
            return lr
        first, n = cone_rows
        t1, t2 = slice(first, first + n), slice(first + n, first + 2 * n)
        a, b = lr[t1], lr[t2]
        mu1 = c["fric"][t1]
        if "fric_lo" in c:  # directional: the grain's forward / backward semi-axis
            mu1 = jnp.where(a > 0, mu1, c["fric_lo"][t1])
        a, b = cone(a, b, lr[first - n:first], mu1, c["fric"][t2])
        return jnp.concatenate([lr[:first], a, b, lr[first + 2 * n:]])

    def block_update(lj, v):
        jv_j = bmv(c["ja"], v[ba]) + bmv(c["jb"], v[bb])
        res_j = (jv_j + c["bias_j"] + c["cfm_j"] * lj) * mask
        return lj - relax_j * bmv(c["a_inv"], res_j)

    def row_update(lr, v):
        jv_r = jnp.sum(c["rja"] * v[ra], axis=1) + jnp.sum(c["rjb"] * v[rb], axis=1)
        return project(lr - relax_r * c["m_c"] * (jv_r + c["bias"] + c["cfm"] * lr))

    def sweep(_, carry):
        lj, lr = carry
        v = velocities(lj, lr)
        return block_update(lj, v), row_update(lr, v)

    def sweep_blocks_first(_, carry):
        # carries the blocks' velocity change, so that a sweep scatters each group once
        lj, lr, v_joints = carry
        v_rows = dv_rows(lr)
        lj = block_update(lj, v0 + v_joints + v_rows)
        v_joints = dv_joints(lj)
        return lj, row_update(lr, v0 + v_joints + v_rows), v_joints

    def dot(aj, ar, bj, br):  # D-inner product of block and row impulses, per robot: (*B)
        return (jnp.sum(c["d_j"] * aj * bj, axis=(0, 1))
                + jnp.sum(ar * br / c["m_c"], axis=0))

    beta = float(m.momentum)

    def sweep_momentum(_, carry):
        # x: the last sweep's impulses (projected); y: their extrapolation, from which
        # this sweep starts; dv_x, dv_y: the blocks' velocity changes of x and y (linear
        # in the unprojected block impulses, so y's is extrapolated, not scattered)
        xj, xr, yj, yr, dv_x, dv_y = carry
        v_rows = dv_rows(yr)
        xj1 = block_update(yj, v0 + dv_y + v_rows)
        dv1 = dv_joints(xj1)
        xr1 = row_update(yr, v0 + dv1 + v_rows)
        # restart: this sweep's update turned against the last change of x
        turned = dot(xj1 - yj, xr1 - yr, xj1 - xj, xr1 - xr) < 0
        b = jnp.where(turned, 0.0, beta) if m.momentum_restart else beta
        b = jnp.asarray(b, dtype)
        bj, br = b.reshape((1, 1) + b.shape), b.reshape((1,) + b.shape)
        yj = xj1 + bj * (xj1 - xj)
        dv_y = dv1 + bj * (dv1 - dv_x)
        yr = project(xr1 + br * (xr1 - xr))
        return xj1, xr1, yj, yr, dv1, dv_y

    lam = (lam_joint0 * mask, project(lam_row0))
    if m.sweep_order == "blocks_first":
        lj, lr, _ = jax.lax.fori_loop(0, m.solver_iterations, sweep_blocks_first,
                                      lam + (dv_joints(lam[0]),))
    elif m.sweep_order == "momentum":
        dv0 = dv_joints(lam[0])
        lj, lr = jax.lax.fori_loop(0, m.solver_iterations, sweep_momentum,
                                   lam + lam + (dv0, dv0))[:2]
    else:
        lj, lr = jax.lax.fori_loop(0, m.solver_iterations, sweep, lam)
    v = velocities(lj, lr)
    if not report:
        return v, lj, lr
    # the natural residual of the final impulses: one exact block step and one projected
    # row step at relaxation 1 from them, measured in the D-norm, relative to the impulses
    jv_j = bmv(c["ja"], v[ba]) + bmv(c["jb"], v[bb])
    r_j = bmv(c["a_inv"], (jv_j + c["bias_j"] + c["cfm_j"] * lj) * mask)
    jv_r = jnp.sum(c["rja"] * v[ra], axis=1) + jnp.sum(c["rjb"] * v[rb], axis=1)
    r_r = lr - project(lr - c["m_c"] * (jv_r + c["bias"] + c["cfm"] * lr))
    tiny = jnp.asarray(jnp.finfo(dtype).tiny, dtype)
    rel = jnp.sqrt(dot(r_j, r_r, r_j, r_r) / jnp.maximum(dot(lj, lr, lj, lr), tiny))
    return v, lj, lr, rel


def solve(m: Model, v0, inv_m, inv_iw, blocks, rows, lam_joint0, lam_row0, *,
          report=False):
    """Solve for post-step velocities and impulses.

    Args:
        v0: (n_body + 1, 6) velocities after external forces (world row zero).
        inv_m, inv_iw: from :func:`inverse_mass`.
        blocks: dict ``ja``, ``jb`` (n_joint, 6, 6), ``bias`` (n_joint, 6),
            ``gamma`` (n_joint, 6) relative softness, with static ``body_a``/``body_b``.
        rows: dict from ``constraint.scalar_rows``.
        lam_joint0 (n_joint, 6), lam_row0 (n_rows,): warm-start impulses [N s].
        report: (static) also return the final relative residual, a debug output of one
            robot (not available with ``m.batched``): the natural residual of the final
            impulses (one exact block step and one projected row step at relaxation 1
            from them), relative to the impulses, both in the norm of the softened
            Delassus diagonal D (sum of D_ii lambda_i^2, an energy); 0 at the solution.
    Returns:
        (v, lam_joint, lam_row): final velocities (n_body + 1, 6) and impulses; with
        ``report`` a fourth entry, the relative residual ().

    With ``m.batched`` the function carries a custom ``jax.vmap`` rule
    (:func:`_solve_batch_last`); otherwise it is the plain single-robot solver.
    """
    idx = (blocks["body_a"], blocks["body_b"], rows["body_a"], rows["body_b"])
    fric_idx = (rows["ref"], rows["is_fric"], rows["cone"], rows.get("dof"))
    blk = {k: blocks[k] for k in _BLOCK_KEYS}
    row = {k: rows[k] for k in _ROW_KEYS if k in rows}

    def single(relax, v0_, inv_m_, inv_iw_, blk_, row_, lj0, lr0):
        c = _prepare(m.joint_row_mask, idx, v0_, inv_m_, inv_iw_, blk_, row_, fric_idx[2])
        return _sweeps(m, idx, fric_idx, relax, c, lj0, lr0, report)

    args = (m.relaxation, v0, inv_m, inv_iw, blk, row, lam_joint0, lam_row0)
    if report and m.batched:
        raise ValueError("the solver's residual report is for one robot (batched=False)")
    if not m.batched:
        return single(*args)
    return _batched_solver(m, idx, fric_idx, single)(*args)


def _batched_solver(m: Model, idx, fric_idx, single):
    """``single`` with the robots-last ``jax.vmap`` rule, in value and in gradient.

    ``jax.custom_batching.custom_vmap`` gives the rule (:func:`_solve_batch_last`), but
    JAX cannot linearise a ``custom_vmap`` that is differentiated *before* it is batched
    (``jax.vmap(jax.grad(...))``: "Linearization failed to produce known values").
    So the function is a ``custom_vjp`` whose forward and backward passes are each a
    ``custom_vmap``: neither is ever differentiated by JAX, and both get the robots-last
    rule in either order of ``vmap`` and ``grad``. The backward pass recomputes the
    solve from its inputs (its residuals) and pulls the cotangents back through it.
    Forward-mode differentiation (``jax.jvp``) of a batched model is not available.
    """
    def rule(fn):
        return lambda size, in_batched, *a: _solve_batch_last(
            m, idx, fric_idx, size, in_batched, a, fn)

    value = jax.custom_batching.custom_vmap(single)
    value.def_vmap(rule(None))

    def pullback(args, ct):
        return jax.vjp(single, *args)[1](ct)

    back = jax.custom_batching.custom_vmap(pullback)
    back.def_vmap(rule("vjp"))

    f = jax.custom_vjp(value)
    f.defvjp(lambda *a: (value(*a), a), back)
    return f


def _solve_batch_last(m: Model, idx, fric_idx, size, in_batched, args, mode=None):
    """``jax.vmap`` rule of the batched solver: the robots moved to the last axis.

    ``args`` are :func:`solve`'s traced inputs (robots first where ``in_batched``; the
    others are broadcast to ``size`` robots). ``mode=None``: the solve, returned robots
    first; ``mode="vjp"``: ``args = (inputs, cotangents of the outputs)`` and the rule
    returns the cotangents of the inputs (the solve is recomputed and pulled back).
    With 64 Tab. 7.1 quadrupeds on one core the sweeps and the per-step preparation cost
    roughly a quarter and a half of their vmapped robots-first versions.
    """
    def front(x, b):
        return x if b else jnp.broadcast_to(x, (size, *jnp.shape(x)))

    last = lambda x: jnp.moveaxis(x, 0, -1)  # noqa: E731
    first = lambda x: jnp.moveaxis(x, -1, 0)  # noqa: E731

    def solve_last(*a):
        """The batch's solve on robots-first inputs; outputs robots-last."""
        relax, v0, inv_m, inv_iw, blk, row, lj0, lr0 = jax.tree.map(last, a)
        c = _prepare(m.joint_row_mask, idx, v0, inv_m, inv_iw, blk, row, fric_idx[2])
        return _sweeps(m, idx, fric_idx, relax, c, lj0, lr0)

    if mode is None:
        args = jax.tree.map(front, tuple(args), tuple(in_batched))
        return jax.tree.map(first, solve_last(*args)), (True, True, True)
    (args, ct), (args_b, ct_b) = args, in_batched
    args = jax.tree.map(front, tuple(args), tuple(args_b))
    ct = jax.tree.map(front, tuple(ct), tuple(ct_b))
    _, pull = jax.vjp(solve_last, *args)
    grads = pull(jax.tree.map(last, ct))
    return grads, jax.tree.map(lambda _: True, grads)
