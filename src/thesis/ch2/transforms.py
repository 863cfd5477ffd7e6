"""Spatial transform layers behind one interface (thesis §2.5, approaches 1-4).

Every transform maps ``(images (B, N, N), params (B, P), out_size M) -> (B, M, M)`` and
declares its number of parameters P and the parameter vector of the identity transform
(the localisation network's last dense layer starts at W = 0, b = identity, as in the
recurrent spatial transformer code, docs/sources.md#rstn-training). A network takes the transform by
name.

Coordinates are normalised as in Jaderberg et al.'s spatial transformer (the thesis's
[4], [5]): the output grid is ``u, v = linspace(-1, 1, M)`` and a source coordinate
``x_n`` in [-1, 1] is input pixel ``(x_n + 1) (N - 1) / 2`` (corners aligned). Then

- ``bilinear`` (6 parameters, approach 1): ``(x_n, y_n) = A (u, v, 1)``, A = params as a
  row-major 2 x 3 matrix, identity ``[1, 0, 0, 0, 1, 0]``; bilinear interpolation.
- ``bilinear_no_skew`` (4 parameters, approach 2): ``(θ, s, t_x, t_y)``,
  ``A = [[s cos θ, -s sin θ, t_x], [s sin θ, s cos θ, t_y]]``; bilinear interpolation.
- ``chirp_z`` (4 parameters, approach 3): the same ``(θ, s, t_x, t_y)`` and the same
  sample points as ``bilinear_no_skew``, resampled with the chirp-Z layer
  (:mod:`thesis.ch2.czt`): x0 = t_x (N-1)/2, y0 = t_y (N-1)/2, Δ = s (N-1)/(M-1),
  with §2.4's low-pass down-sampling.
- ``none`` (0 parameters, approach 4): no transform and no down-sampling; the image is
  passed through unchanged (its output size is N whatever M is asked).

Bilinear samples outside the image read zero: each of the four neighbours is fetched with
an explicit validity mask and ``mode="fill"`` (JAX gathers otherwise clamp silently,
JAX's Common Gotchas, "Out-of-bounds indexing"), so there is no border replication. The
chirp-Z layer is periodic by construction (its interpolant is the periodic band-limited one).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import jax.numpy as jnp
from jax import Array

from thesis.ch2.czt import chirpz_resample

__all__ = [
    "Transform",
    "TRANSFORMS",
    "affine_grid",
    "bilinear_sample",
    "no_skew_to_affine",
    "get_transform",
    "inside_fraction",
]


def affine_grid(theta: Array, n: int, m: int) -> tuple[Array, Array]:
    """Source pixel coordinates of an M x M output grid under affine matrices.

    Args:
        theta: (B, 2, 3) affine matrices in normalised coordinates.
        n: input size N; m: output size M (>= 2).

    Returns:
        x, y: (B, M, M) source coordinates in input pixels (x = column, y = row).
    """
    g = jnp.linspace(-1.0, 1.0, m, dtype=theta.dtype)
    v, u = jnp.meshgrid(g, g, indexing="ij")  # v: row, u: column
    ones = jnp.ones_like(u)
    grid = jnp.stack([u, v, ones], axis=0).reshape(3, m * m)
    src = jnp.einsum("bij,jk->bik", theta, grid)  # (B, 2, M*M)
    scale = (n - 1) / 2.0
    x = (src[:, 0] + 1.0) * scale
    y = (src[:, 1] + 1.0) * scale
    return x.reshape(-1, m, m), y.reshape(-1, m, m)


def bilinear_sample(images: Array, x: Array, y: Array) -> Array:
    """Bilinear interpolation of images at (x, y); samples outside the image read zero.

    Args:
        images: (B, N, N) images.
        x, y: (B, M, M) sample coordinates in input pixels (column, row).

    Returns:
        (B, M, M) interpolated values (image units).
    """
    b, n, _ = images.shape
    flat = images.reshape(b, n * n)
    x0 = jnp.floor(x)
    y0 = jnp.floor(y)
    wx1 = x - x0
    wy1 = y - y0
    out = jnp.zeros_like(x)
    for dy, wy in ((0, 1.0 - wy1), (1, wy1)):
        for dx, wx in ((0, 1.0 - wx1), (1, wx1)):
            xi = (x0 + dx).astype(jnp.int32)
            yi = (y0 + dy).astype(jnp.int32)
            valid = (xi >= 0) & (xi <= n - 1) & (yi >= 0) & (yi <= n - 1)
            idx = jnp.where(valid, yi * n + xi, n * n)  # n*n is out of range -> fill
            vals = jnp.take_along_axis(
                flat, idx.reshape(b, -1), axis=1, mode="fill", fill_value=0
            ).reshape(x.shape)
            out = out + jnp.where(valid, vals, 0.0) * wx * wy
    return out


def no_skew_to_affine(params: Array) -> Array:
    """(B, 4) parameters (θ [rad], s, t_x, t_y) -> (B, 2, 3) affine matrices (rotation,
    isotropic scale and translation, no skew)."""
    th, s, tx, ty = (params[:, i] for i in range(4))
    c, si = s * jnp.cos(th), s * jnp.sin(th)
    return jnp.stack([jnp.stack([c, -si, tx], -1), jnp.stack([si, c, ty], -1)], axis=1)


def _bilinear(images, params, out_size):
    n = images.shape[-1]
    x, y = affine_grid(params.reshape(-1, 2, 3), n, out_size)
    return bilinear_sample(images, x, y)


def _bilinear_no_skew(images, params, out_size):
    n = images.shape[-1]
    x, y = affine_grid(no_skew_to_affine(params), n, out_size)
    return bilinear_sample(images, x, y)


def _chirp_z(images, params, out_size, output="abs"):
    n = images.shape[-1]
    half = (n - 1) / 2.0
    th, s, tx, ty = (params[:, i] for i in range(4))
    return chirpz_resample(
        images, tx * half, ty * half, th, s * (n - 1) / (out_size - 1), out_size=out_size,
        output=output,
    )


def _chirp_z_crops(images, params, out_size, output="abs"):
    """T chirp-Z crops of each image from one spectrum per image: params (B, T, 4) ->
    (B T, M, M) sample-major (:meth:`Transform.crops`)."""
    b, t, _ = params.shape
    n = images.shape[-1]
    half = (n - 1) / 2.0
    th, s, tx, ty = (params.reshape(b * t, 4)[:, i] for i in range(4))
    return chirpz_resample(
        images, tx * half, ty * half, th, s * (n - 1) / (out_size - 1), out_size=out_size,
        output=output, crops_per_image=t,
    )


def _none(images, params, out_size):
    return images


@dataclass(frozen=True)
class Transform:
    """A spatial transform layer: ``apply(images (B,N,N), params (B,P), M) -> (B,M',M')``.

    Attributes:
        name: registry name.
        n_params: P, number of parameters produced by the localisation network.
        identity: the P parameters of the identity transform (bias initialisation).
        apply: the layer function.
        downsamples: False for ``none`` (output size is always N).
        apply_crops: ``(images (B,N,N), params (B,T,P), M) -> (B T, M', M')``, several
            crops per image sharing per-image work (:meth:`crops`); None = ``apply`` on
            the repeated images.
    """

    name: str
    n_params: int
    identity: tuple[float, ...]
    apply: Callable[..., Array]
    downsamples: bool = True
    apply_crops: Callable[..., Array] | None = None

    def out_size(self, n: int, d: int) -> int:
        """Output side for input side n and down-sampling factor d (N // d, or N for none)."""
        return n // d if self.downsamples else n

    def __call__(self, images: Array, params: Array, out_size: int) -> Array:
        return self.apply(images, params, out_size)

    def crops(self, images: Array, params: Array, out_size: int) -> Array:
        """T crops of every image (RNN-SPN's one transform per digit, §2.5).

        Args:
            images: (B, N, N); params: (B, T, P) (crop t of image b uses params[b, t]).

        Returns:
            (B * T, M, M) sample-major (crop t of image b at b * T + t), each equal to
            ``self(images[b:b+1], params[b, t:t+1], out_size)``.
        """
        if self.apply_crops is not None:
            return self.apply_crops(images, params, out_size)
        b, t, _ = params.shape
        return self.apply(jnp.repeat(images, t, axis=0), params.reshape(b * t, -1), out_size)


TRANSFORMS: dict[str, Transform] = {
    "bilinear": Transform("bilinear", 6, (1.0, 0.0, 0.0, 0.0, 1.0, 0.0), _bilinear),
    "bilinear_no_skew": Transform("bilinear_no_skew", 4, (0.0, 1.0, 0.0, 0.0), _bilinear_no_skew),
    "chirp_z": Transform("chirp_z", 4, (0.0, 1.0, 0.0, 0.0), _chirp_z,
                         apply_crops=_chirp_z_crops),
    "none": Transform("none", 0, (), _none, downsamples=False),
}


def inside_fraction(transform: Transform, params: Array, n: int, m: int) -> Array:
    """Fraction of the M x M output grid whose source point lies on the N x N canvas.

    A diagnostic of the localisation network (§2.5): bilinear samples outside the canvas
    read zero, so a transform whose grid has left the canvas yields an empty image and
    zero gradients for the localisation network. For ``chirp_z`` the same sample points
    are used (the layer itself is periodic, so points outside wrap around instead).

    Args:
        transform: a layer with parameters (not ``none``).
        params: (B, P) transform parameters.
        n: input side N; m: output side M.

    Returns:
        (B,) fraction in [0, 1].
    """
    if transform.n_params == 6:
        theta = params.reshape(-1, 2, 3)
    elif transform.n_params == 4:
        theta = no_skew_to_affine(params)
    else:
        raise ValueError(f"transform {transform.name!r} has no sampling grid")
    x, y = affine_grid(theta, n, m)
    inside = (x >= 0) & (x <= n - 1) & (y >= 0) & (y <= n - 1)
    return jnp.mean(inside.astype(params.dtype), axis=(1, 2))


def get_transform(name: str, chirpz_output: str = "abs") -> Transform:
    """The transform called ``name`` (keys of :data:`TRANSFORMS`); ``chirpz_output`` picks
    the chirp-Z layer's output ("abs" as Alg. 2.1 line 8, or "real")."""
    if name not in TRANSFORMS:
        raise KeyError(f"unknown transform {name!r}; choose from {sorted(TRANSFORMS)}")
    t = TRANSFORMS[name]
    if name == "chirp_z" and chirpz_output != "abs":
        return Transform(t.name, t.n_params, t.identity,
                         lambda i, p, m: _chirp_z(i, p, m, output=chirpz_output),
                         apply_crops=lambda i, p, m: _chirp_z_crops(i, p, m,
                                                                    output=chirpz_output))
    return t
