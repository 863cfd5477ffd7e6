"""Small, gradient-safe linear-algebra helpers of the engine (thesis §7.2).

Every function is pure, branch-free and safe to differentiate everywhere: norms use the
double-``where`` guard (JAX FAQ, "Gradients contain NaN where using ``where``"), angles
come from ``atan2`` (never ``arccos``, whose derivative is infinite at ±1,
docs/sources.md#tpx-step), and nothing divides by a quantity that can be 0. Rotation
matrices follow ``world_point = pos + rot @ local_point`` (columns = body axes in world
coordinates); the original engine stored the transpose (docs/sources.md#tpx-bodies).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

__all__ = [
    "skew",
    "vee",
    "safe_norm",
    "safe_normalize",
    "orthonormalize",
    "quat_to_rot",
    "tangent_basis",
    "inv_spd",
    "inv3",
    "rodrigues",
    "decay_gradient",
]


def skew(w):
    """Cross-product matrix [w]x of (..., 3) vectors -> (..., 3, 3), so [w]x @ v = w x v."""
    z = jnp.zeros_like(w[..., 0])
    x, y, zz = w[..., 0], w[..., 1], w[..., 2]
    return jnp.stack([
        jnp.stack([z, -zz, y], -1),
        jnp.stack([zz, z, -x], -1),
        jnp.stack([-y, x, z], -1),
    ], -2)


def vee(m):
    """Axial vector of the skew part of (..., 3, 3) matrices: vee(S - S^T) / 2."""
    return 0.5 * jnp.stack([
        m[..., 2, 1] - m[..., 1, 2],
        m[..., 0, 2] - m[..., 2, 0],
        m[..., 1, 0] - m[..., 0, 1],
    ], -1)


def safe_norm(x, axis=-1, keepdims=False, eps=1e-12):
    """Euclidean norm with a finite (zero) gradient at the origin (double-where).

    Args:
        x: (..., n) array.
    Returns:
        (...,) norm (or (..., 1) with ``keepdims``); exactly 0 where ``x`` is 0, and the
        gradient there is 0 instead of NaN.
    """
    sq = jnp.sum(x * x, axis=axis, keepdims=keepdims)
    ok = sq > eps * eps
    return jnp.where(ok, jnp.sqrt(jnp.where(ok, sq, 1.0)), 0.0)


def safe_normalize(x, fallback=None, eps=1e-12):
    """x / |x| along the last axis, ``fallback`` (default: x unchanged) where |x| ~ 0."""
    n = safe_norm(x, keepdims=True, eps=eps)
    ok = n > eps
    out = x / jnp.where(ok, n, 1.0)
    if fallback is None:
        return jnp.where(ok, out, x)
    return jnp.where(ok, out, jnp.broadcast_to(fallback, x.shape))


def orthonormalize(a, iterations=1):
    """Re-orthonormalise rotation matrices with eq. 7.1, ``A' = (3A - A A^T A) / 2``.

    One Newton-Schulz (Bjorck) step towards the nearest orthogonal matrix (thesis eq. 7.1,
    docs/sources.md#tpx-step item 6). The thesis prints the product as elementwise ``A o (A . A)``;
    the original code and the numerics use the matrix product ``A A^T A`` used here.

    Args:
        a: (..., 3, 3) nearly orthogonal matrices.
        iterations: static number of steps (model field ``reortho_iterations``).
    """
    for _ in range(int(iterations)):  # static, tiny count (1 in every shipped model)
        a = 1.5 * a - 0.5 * mm(mmt(a, a), a)
    return a


def quat_to_rot(q):
    """Unit quaternion [w, x, y, z] -> rotation matrix (numpy, used by the builder only)."""
    w, x, y, z = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def tangent_basis(n):
    """Two unit tangents (t1, t2) completing unit normals n (..., 3), branch-free.

    Duff et al. (2017), "Building an orthonormal basis, revisited"; the sign switch is a
    ``where`` on n_z, so the basis is smooth except across n_z = 0.
    """
    s = jnp.where(n[..., 2] >= 0, 1.0, -1.0).astype(n.dtype)
    a = -1.0 / (s + n[..., 2])
    b = n[..., 0] * n[..., 1] * a
    t1 = jnp.stack([1.0 + s * n[..., 0] ** 2 * a, s * b, -s * n[..., 0]], -1)
    t2 = jnp.stack([b, s + n[..., 1] ** 2 * a, -n[..., 1]], -1)
    return t1, t2


def inv_spd(a, axis=-2):
    """Inverse of small symmetric positive-definite matrices, n static (n <= 6).

    ``a`` holds the matrices on axes (``axis``, ``axis + 1``), default the last two
    ((..., n, n)); axes after them are batch axes (the batched solver's robots-last layout,
    ``thesis.physics.solver``). Unrolled Gauss-Jordan elimination without pivoting (safe
    for SPD matrices): a fixed, short sequence of vectorised ops, much faster under XLA on
    CPU than a batched LAPACK call when there are many tiny matrices (one per joint per
    robot).
    """
    ax = axis % a.ndim
    n = a.shape[ax]
    pre = (slice(None),) * ax
    eye = jnp.eye(n, dtype=a.dtype).reshape((n, n) + (1,) * (a.ndim - ax - 2))
    m = jnp.concatenate([a, jnp.broadcast_to(eye, a.shape)], axis=ax + 1)
    for k in range(n):
        row = m[pre + (k,)] / m[pre + (slice(k, k + 1), k)]
        m = m - m[pre + (slice(None), slice(k, k + 1))] * row[pre + (None,)]
        m = m.at[pre + (k,)].set(row)
    return m[pre + (slice(None), slice(n, None))]


def inv3(a):
    """Inverse of (..., 3, 3) matrices by the adjugate (no LAPACK call; fast when batched)."""
    c0 = jnp.cross(a[..., 1, :], a[..., 2, :])
    c1 = jnp.cross(a[..., 2, :], a[..., 0, :])
    c2 = jnp.cross(a[..., 0, :], a[..., 1, :])
    det = jnp.sum(a[..., 0, :] * c0, -1)
    return jnp.stack([c0, c1, c2], -1) / det[..., None, None]


# Tiny contractions as broadcast-multiply-reduce: XLA on CPU fuses these into loop
# kernels, whereas a ``dot`` on 3x3 or 6x6 operands becomes a separate library call whose
# fixed overhead dominates at these sizes.
def mv(a, x):
    """Batched matrix-vector product a @ x for (..., n, k), (..., k) -> (..., n)."""
    return jnp.sum(a * x[..., None, :], -1)


def mtv(a, x):
    """Batched a^T @ x for (..., n, k), (..., n) -> (..., k)."""
    return jnp.sum(a * x[..., :, None], -2)


def mm(a, b):
    """Batched matrix product a @ b for (..., n, k), (..., k, p) -> (..., n, p)."""
    return jnp.sum(a[..., :, :, None] * b[..., None, :, :], -2)


def mmt(a, b):
    """Batched a @ b^T for (..., n, k), (..., p, k) -> (..., n, p)."""
    return jnp.sum(a[..., :, None, :] * b[..., None, :, :], -1)


def rodrigues(phi):
    """Rotation matrices exp([phi]x) of rotation vectors phi (..., 3) (Rodrigues).

    ``I + a [phi]x + b [phi]x^2`` with a = sin(t)/t, b = (1 - cos t)/t^2, t = |phi|;
    Taylor series below t = 1e-3 keep values and gradients finite at phi = 0.
    """
    t2 = jnp.sum(phi * phi, -1)
    small = t2 < 1e-6
    t2s = jnp.where(small, 1.0, t2)
    t = jnp.sqrt(t2s)
    a = jnp.where(small, 1.0 - t2 / 6.0, jnp.sin(t) / t)
    b = jnp.where(small, 0.5 - t2 / 24.0, (1.0 - jnp.cos(t)) / t2s)
    k = skew(phi)
    eye = jnp.broadcast_to(jnp.eye(3, dtype=phi.dtype), k.shape)
    return eye + a[..., None, None] * k + b[..., None, None] * mm(k, k)


@jax.custom_vjp
def _scale_cotangent(x, alpha):
    return x


def _scale_cotangent_fwd(x, alpha):
    return x, alpha


def _scale_cotangent_bwd(alpha, g):
    return (alpha * g).astype(g.dtype), jnp.zeros_like(alpha)


_scale_cotangent.defvjp(_scale_cotangent_fwd, _scale_cotangent_bwd)


def decay_gradient(tree, alpha):
    """Identity forward (bit-exact); multiplies the cotangent of every float leaf of ``tree``
    by ``alpha`` (the original's ``MulGrad``, §7.3.2's second trick, docs/sources.md#tpx-engine).

    Applied to the state after every step, the gradient reaching step t from step t + k is
    scaled by alpha^k. ``alpha`` is a scalar (it may be traced) and receives no gradient;
    0 cuts the gradient, 1 leaves it exact.
    """
    def f(x):
        if not jnp.issubdtype(jnp.result_type(x), jnp.floating):
            return x
        return _scale_cotangent(x, jnp.asarray(alpha, jnp.result_type(x)))
    return jax.tree.map(f, tree)
