"""Differentiable ray caster: spheres, boxes and planes with bilinear texture sampling.

Implements the renderer of the differentiable camera of thesis §7.3.3.1 ("This camera
uses a ray-tracing approach to find where it needs to sample from the textures, and uses
bilinear interpolation to sample from these textures, similar to the one used for the
spatial transform layer"), following the original engine's design (docs/sources.md#tpx-camera): one
ray per pixel centre, analytic ray/sphere and ray/planar-face intersections, nearest hit by minimum
ray parameter, texture coordinates from spherical angles (spheres) or face axes (box faces, planes),
bilinear sampling multiplied by the geometry colour, background colour where nothing is hit, no
lighting.

Differentiability. Which geometry a ray hits is a hard (piecewise-constant) decision; the
hit point, its texture coordinates and the bilinear sample are smooth functions of every
pose (geometry, camera), so an image is differentiable almost everywhere with non-zero
derivatives on textured surfaces. Every division and square root is guarded with the
"double where" pattern, so gradients are finite for missed rays, rays tangent to a sphere,
rays parallel to a face, and sphere poles.

Texture conventions (image row 0 = top of the texture, column 0 = left; a texture
coordinate ``u`` runs along the columns and ``v`` along the rows, both in texture
repeats; texel ``(i, j)`` has its centre at ``u = (j + 0.5) / w``, ``v = (i + 0.5) / h``):

* sphere: local direction ``q = R^T (p - c) / r``; ``u = 1/2 + atan2(q_y, q_x) / 2pi``
  (longitude, wraps), ``v = atan2(sqrt(q_x^2 + q_y^2), q_z) / pi`` (0 at the local +z
  pole, 1 at the -z pole; clamped at the poles).
* box: each of the 6 faces shows the whole texture once (clamped at the face edges), drawn
  upright and unmirrored when seen from outside: faces with a local x or y normal have
  their texture "up" along local +z, the two z faces along local +y.
* plane (point ``o``, rotation ``R``, normal = ``R[:, 2]``): ``u = (p - o).R[:, 0] / period_u``,
  ``v = -(p - o).R[:, 1] / period_v``; the texture tiles (wraps) with a period of
  ``tile`` metres per repeat along each in-plane axis, upright and unmirrored seen from
  the +normal side. Planes are visible from both sides.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

__all__ = ["Scene", "SKY_COLOR", "cast", "sample_bilinear"]

#: The original engine's default sky colour (docs/sources.md#tpx-camera): RGB (0, 191/255, 1).
SKY_COLOR = (0.0, 191.0 / 255.0, 1.0)

# |denominator| below which a ray counts as parallel to a face (direction vectors are unit).
_PARALLEL_EPS = 1e-9

# For each box face axis k: (texture-right axis, texture-up axis, sign of right for the +k face).
# right = up x normal, so that the texture is unmirrored seen from outside.
_BOX_U_AXIS = np.array([1, 0, 0])
_BOX_V_AXIS = np.array([2, 2, 1])
_BOX_U_SIGN = np.array([1.0, -1.0, 1.0])


@dataclasses.dataclass(frozen=True)
class Scene:
    """World-frame geometry seen by :func:`cast` (a JAX pytree; textures ids are static).

    Attributes:
        sphere_pos: (S, 3) sphere centres [m].
        sphere_radius: (S,) radii [m].
        sphere_rot: (S, 3, 3) rotation of the sphere's texture frame (world = R @ local).
        sphere_color: (S, 3) RGB colour in [0, 1], multiplies the texture.
        box_pos: (B, 3) box centres [m].
        box_rot: (B, 3, 3) box orientation (world = pos + R @ local).
        box_half: (B, 3) half extents along the local axes [m].
        box_color: (B, 3) RGB colour.
        plane_pos: (P, 3) a point of each plane [m] (texture origin).
        plane_rot: (P, 3, 3) plane frame; column 2 is the normal, columns 0/1 the
            texture right/up axes.
        plane_color: (P, 3) RGB colour.
        plane_tile: (P, 2) texture period along columns 0 and 1 [m per texture repeat].
        textures: (T, h, w, 3) texture images, RGB in [0, 1], row 0 at the top (T may be 0).
        background: (3,) colour of rays that hit nothing.
        sphere_texture, box_texture, plane_texture: static tuples of texture indices into
            ``textures`` (-1 = untextured, plain colour), one per geometry.
    """

    sphere_pos: jax.Array
    sphere_radius: jax.Array
    sphere_rot: jax.Array
    sphere_color: jax.Array
    box_pos: jax.Array
    box_rot: jax.Array
    box_half: jax.Array
    box_color: jax.Array
    plane_pos: jax.Array
    plane_rot: jax.Array
    plane_color: jax.Array
    plane_tile: jax.Array
    textures: jax.Array
    background: jax.Array
    sphere_texture: tuple[int, ...] = ()
    box_texture: tuple[int, ...] = ()
    plane_texture: tuple[int, ...] = ()

    def replace(self, **changes) -> "Scene":
        """Return a copy with the given fields replaced."""
        return dataclasses.replace(self, **changes)


jax.tree_util.register_dataclass(
    Scene,
    data_fields=[
        "sphere_pos", "sphere_radius", "sphere_rot", "sphere_color",
        "box_pos", "box_rot", "box_half", "box_color",
        "plane_pos", "plane_rot", "plane_color", "plane_tile",
        "textures", "background",
    ],
    meta_fields=["sphere_texture", "box_texture", "plane_texture"],
)


def _einsum(spec, *ops):
    """einsum at full float32 precision (GPUs would otherwise use TF32 for the geometry)."""
    return jnp.einsum(spec, *ops, precision=jax.lax.Precision.HIGHEST)


def _safe_div(num, den, eps=_PARALLEL_EPS):
    """num / den where |den| > eps, else 0; finite value and gradient everywhere."""
    ok = jnp.abs(den) > eps
    return jnp.where(ok, num / jnp.where(ok, den, 1.0), 0.0), ok


def _safe_atan2(y, x):
    """atan2 with a finite gradient at the origin (value 0 there)."""
    zero = (y == 0) & (x == 0)
    return jnp.where(zero, 0.0, jnp.arctan2(jnp.where(zero, 0.0, y), jnp.where(zero, 1.0, x)))


def _safe_sqrt(x):
    pos = x > 0
    return jnp.where(pos, jnp.sqrt(jnp.where(pos, x, 1.0)), 0.0)


# --------------------------------------------------------------------------- intersections
# Each returns (t (R, K), hit (R, K), u (R, K), v (R, K)) for R rays and K primitives;
# t, u, v are finite everywhere (meaningless where hit is False).


def _hit_spheres(o, d, pos, radius, rot, t_min):
    oc = o[:, None, :] - pos[None, :, :]  # (R, S, 3)
    b = _einsum("rsk,rk->rs", oc, d)
    c = jnp.sum(oc * oc, axis=-1) - radius[None, :] ** 2
    disc = b * b - c
    root = _safe_sqrt(disc)
    t_near, t_far = -b - root, -b + root
    # Nearest root in front of the ray; the far root when the origin is inside the sphere.
    t = jnp.where(t_near > t_min, t_near, t_far)
    hit = (disc > 0) & (t > t_min)
    t = jnp.where(hit, t, 0.0)
    p = oc + t[..., None] * d[:, None, :]  # hit point relative to the centre
    q = _einsum("skj,rsk->rsj", rot, p)  # local frame (R^T p), unnormalised
    u = 0.5 + _safe_atan2(q[..., 1], q[..., 0]) / (2.0 * jnp.pi)
    v = _safe_atan2(_safe_sqrt(q[..., 0] ** 2 + q[..., 1] ** 2), q[..., 2]) / jnp.pi
    return t, hit, u, v


def _hit_boxes(o, d, pos, rot, half, t_min):
    """Slab test in each box frame; the hit face is the entry face (exit face from inside)."""
    ol = _einsum("bkj,rbk->rbj", rot, o[:, None, :] - pos[None, :, :])  # (R, B, 3)
    dl = _einsum("bkj,rk->rbj", rot, d)
    h = jnp.broadcast_to(half[None], ol.shape)
    t_lo, ok = _safe_div(-h - ol, dl)
    t_hi, _ = _safe_div(h - ol, dl)
    inside_slab = jnp.abs(ol) <= h
    big = jnp.asarray(3e30, ol.dtype)
    # A ray parallel to a slab is inside it for all t or for none.
    t_in = jnp.where(ok, jnp.minimum(t_lo, t_hi), jnp.where(inside_slab, -big, big))
    t_out = jnp.where(ok, jnp.maximum(t_lo, t_hi), jnp.where(inside_slab, big, -big))
    t_enter = jnp.max(t_in, axis=-1)
    t_exit = jnp.min(t_out, axis=-1)
    k_enter = jnp.argmax(t_in, axis=-1)
    k_exit = jnp.argmin(t_out, axis=-1)
    from_outside = t_enter > t_min
    t = jnp.where(from_outside, t_enter, t_exit)
    k = jnp.where(from_outside, k_enter, k_exit)
    hit = (t_enter <= t_exit) & (t > t_min) & (t_exit < big)
    t = jnp.where(hit, t, 0.0)
    p = ol + t[..., None] * dl  # local hit point
    pk = jnp.take_along_axis(p, k[..., None], axis=-1)[..., 0]
    side = jnp.where(pk >= 0, 1.0, -1.0)
    ua, va = jnp.asarray(_BOX_U_AXIS)[k], jnp.asarray(_BOX_V_AXIS)[k]
    usign = jnp.asarray(_BOX_U_SIGN, p.dtype)[k] * side
    pu = jnp.take_along_axis(p, ua[..., None], axis=-1)[..., 0]
    pv = jnp.take_along_axis(p, va[..., None], axis=-1)[..., 0]
    hu = jnp.take_along_axis(h, ua[..., None], axis=-1)[..., 0]
    hv = jnp.take_along_axis(h, va[..., None], axis=-1)[..., 0]
    u = 0.5 * (1.0 + usign * _safe_div(pu, hu, 0.0)[0])
    v = 0.5 * (1.0 - _safe_div(pv, hv, 0.0)[0])
    return t, hit, u, v


def _hit_planes(o, d, pos, rot, tile, t_min):
    n = rot[:, :, 2]  # (P, 3)
    rel = pos[None, :, :] - o[:, None, :]  # (R, P, 3)
    t, ok = _safe_div(_einsum("rpk,pk->rp", rel, n), _einsum("rk,pk->rp", d, n))
    hit = ok & (t > t_min)
    t = jnp.where(hit, t, 0.0)
    p = t[..., None] * d[:, None, :] - rel  # hit point relative to the plane point
    u = _einsum("rpk,pk->rp", p, rot[:, :, 0]) / tile[None, :, 0]
    v = -_einsum("rpk,pk->rp", p, rot[:, :, 1]) / tile[None, :, 1]
    return t, hit, u, v


# --------------------------------------------------------------------------- texturing


def sample_bilinear(textures, tex_id, u, v, wrap_u, wrap_v):
    """Bilinearly sample ``textures[tex_id]`` at texture coordinates (u, v) (thesis §7.3.3.1:
    the interpolation of the spatial transformer, which gives the image non-zero derivatives
    with respect to the hit points).

    Args:
        textures: (T, h, w, 3) images, row 0 at the top.
        tex_id: (N,) int texture index per sample, each in [0, T).
        u, v: (N,) coordinates in texture repeats along columns / rows; texel (i, j) has
            its centre at u = (j + 0.5) / w, v = (i + 0.5) / h.
        wrap_u, wrap_v: (N,) bool; True wraps the index (periodic tiling), False clamps
            it to the edge texel.

    Returns:
        (N, 3) samples; piecewise bilinear in (u, v), differentiable w.r.t. u, v and the
        texel values (floor has zero derivative, the fractional weights carry it).
    """
    n_tex, th, tw, _ = textures.shape
    # Reduce periodic coordinates to [0, 1) first (derivative 1) so that far tiles of a
    # plane do not overflow the integer texel index.
    u = jnp.where(wrap_u, u - jnp.floor(u), u)
    v = jnp.where(wrap_v, v - jnp.floor(v), v)
    x = u * tw - 0.5
    y = v * th - 0.5
    x0f, y0f = jnp.floor(x), jnp.floor(y)
    fx, fy = x - x0f, y - y0f
    x0, y0 = x0f.astype(jnp.int32), y0f.astype(jnp.int32)

    def index(i, n, wrap):
        return jnp.where(wrap, jnp.mod(i, n), jnp.clip(i, 0, n - 1))

    cx0, cx1 = index(x0, tw, wrap_u), index(x0 + 1, tw, wrap_u)
    ry0, ry1 = index(y0, th, wrap_v), index(y0 + 1, th, wrap_v)
    flat = textures.reshape(n_tex * th * tw, 3)
    base = tex_id * (th * tw)

    def texel(r, c):
        return flat[base + r * tw + c]

    fx, fy = fx[:, None], fy[:, None]
    top = texel(ry0, cx0) * (1.0 - fx) + texel(ry0, cx1) * fx
    bottom = texel(ry1, cx0) * (1.0 - fx) + texel(ry1, cx1) * fx
    return top * (1.0 - fy) + bottom * fy


# --------------------------------------------------------------------------- cast


def cast(origins: jax.Array, dirs: jax.Array, scene: Scene, t_min: float = 1e-6) -> jax.Array:
    """Render the colour seen along each ray (thesis §7.3.3.1, docs/sources.md#tpx-camera).

    Args:
        origins: (..., 3) ray origins, world frame [m].
        dirs: (..., 3) unit ray directions, world frame.
        scene: world-frame geometry, see :class:`Scene`.
        t_min: hits closer than this along the ray are ignored [m].

    Returns:
        (..., 3) RGB: colour x bilinear texture sample of the nearest hit, or the scene's
        background colour. Branch-free; vectorised over rays x geometries.
    """
    batch_shape = origins.shape[:-1]
    o = origins.reshape(-1, 3)
    d = dirs.reshape(-1, 3)
    dtype = o.dtype
    parts = []  # (t, hit, u, v, color (K,3), tex (K,), wrap_u (K,), wrap_v (K,))
    if scene.sphere_pos.shape[0]:
        n = scene.sphere_pos.shape[0]
        parts.append((*_hit_spheres(o, d, scene.sphere_pos, scene.sphere_radius,
                                    scene.sphere_rot, t_min),
                      scene.sphere_color, scene.sphere_texture, [True] * n, [False] * n))
    if scene.box_pos.shape[0]:
        n = scene.box_pos.shape[0]
        parts.append((*_hit_boxes(o, d, scene.box_pos, scene.box_rot, scene.box_half, t_min),
                      scene.box_color, scene.box_texture, [False] * n, [False] * n))
    if scene.plane_pos.shape[0]:
        n = scene.plane_pos.shape[0]
        parts.append((*_hit_planes(o, d, scene.plane_pos, scene.plane_rot, scene.plane_tile,
                                   t_min),
                      scene.plane_color, scene.plane_texture, [True] * n, [True] * n))
    background = jnp.broadcast_to(scene.background.astype(dtype), o.shape)
    if not parts:
        return background.reshape(*batch_shape, 3)

    t = jnp.concatenate([p[0] for p in parts], axis=1)  # (R, K)
    hit = jnp.concatenate([p[1] for p in parts], axis=1)
    u = jnp.concatenate([p[2] for p in parts], axis=1)
    v = jnp.concatenate([p[3] for p in parts], axis=1)
    color = jnp.concatenate([p[4] for p in parts], axis=0)  # (K, 3)
    tex = np.concatenate([np.asarray(p[5], np.int32).reshape(-1) for p in parts])
    wrap_u = np.concatenate([np.asarray(p[6], bool) for p in parts])
    wrap_v = np.concatenate([np.asarray(p[7], bool) for p in parts])
    if tex.shape[0] != t.shape[1]:
        raise ValueError("scene texture tuples must have one entry per geometry")

    key = jnp.where(hit, t, jnp.inf)
    best = jnp.argmin(key, axis=1)  # (R,)
    any_hit = jnp.any(hit, axis=1)
    ub = jnp.take_along_axis(u, best[:, None], axis=1)[:, 0]
    vb = jnp.take_along_axis(v, best[:, None], axis=1)[:, 0]
    rgb = color[best]
    n_tex = scene.textures.shape[0]
    if n_tex and np.any(tex >= 0):
        if np.any(tex >= n_tex):
            raise ValueError(f"texture index out of range ({tex.max()} >= {n_tex})")
        tid = jnp.asarray(tex)[best]
        sample = sample_bilinear(scene.textures.astype(dtype), jnp.maximum(tid, 0), ub, vb,
                                 jnp.asarray(wrap_u)[best], jnp.asarray(wrap_v)[best])
        rgb = jnp.where((tid >= 0)[:, None], rgb * sample, rgb)
    elif np.any(tex >= 0):
        raise ValueError("a geometry has a texture but the scene has no textures")
    out = jnp.where(any_hit[:, None], rgb, background)
    return out.reshape(*batch_shape, 3)
