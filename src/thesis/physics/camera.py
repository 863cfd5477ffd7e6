"""Differentiable pinhole camera of the engine (thesis §7.3.3.1, docs/sources.md#tpx-camera).

A camera is a pinhole at ``pos`` with orientation ``rot`` (world = pos + rot @ camera-frame
point). Camera frame: x right, y down, z forward (the camera looks along +z). The sensor
of ``sensor_size = (w, h)`` metres lies at ``focal_length`` in front of the pinhole (the
virtual, non-inverted image plane) and is divided into ``pixels = (px_w, px_h)`` pixels;
one ray is cast through every pixel centre (docs/sources.md#tpx-camera). Images are (H, W, 3) =
(px_h, px_w, 3), row 0 at the top, column 0 on the left.

Pixel coordinates (:func:`project` / :func:`project_points`) are (column, row) in pixel
units with integer values at pixel centres, so the pixel ``image[i, j]`` is centred at
(j, i) and the image spans [-0.5, px_w - 0.5] x [-0.5, px_h - 0.5].

:func:`render` reads the Model/State fields of the engine API contract: the world pose of
a visual geom is its body pose composed with the geom offset (body -1 = world), and so is
the camera's. Body poses follow world_point = state.pos + state.rot @ local_point.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics.raycast import SKY_COLOR, Scene, _einsum, cast

__all__ = [
    "camera_rays",
    "project",
    "camera_pose",
    "scene_from_model",
    "render",
    "render_batch",
    "project_points",
]

# GeomType values of the engine contract (thesis.physics.types.GeomType).
_SPHERE, _BOX, _PLANE = 0, 1, 2

#: Texture period of a plane when the model does not give one [m per texture repeat].
DEFAULT_PLANE_TILE = 1.0


def _sensor_coords(focal_length, sensor_size, pixels, dtype):
    px_w, px_h = int(pixels[0]), int(pixels[1])
    sensor = jnp.asarray(sensor_size, dtype)
    xs = ((jnp.arange(px_w, dtype=dtype) + 0.5) / px_w - 0.5) * sensor[0]
    ys = ((jnp.arange(px_h, dtype=dtype) + 0.5) / px_h - 0.5) * sensor[1]
    return xs, ys


def camera_rays(pos, rot, focal_length, sensor_size, pixels):
    """One world-frame ray per pixel centre of a pinhole camera (docs/sources.md#tpx-camera).

    Args:
        pos: (3,) pinhole position, world frame [m].
        rot: (3, 3) camera orientation; columns are the camera x (right), y (down) and
            z (forward) axes in world coordinates.
        focal_length: scalar distance pinhole - image plane [m].
        sensor_size: (w, h) sensor size [m].
        pixels: static (px_w, px_h) pixel counts.

    Returns:
        origins (H, W, 3) (all equal to ``pos``) and unit directions (H, W, 3), with
        H = px_h, W = px_w.
    """
    pos = jnp.asarray(pos)
    dtype = pos.dtype if jnp.issubdtype(pos.dtype, jnp.floating) else jnp.float32
    pos = pos.astype(dtype)
    rot = jnp.asarray(rot, dtype)
    xs, ys = _sensor_coords(focal_length, sensor_size, pixels, dtype)
    f = jnp.asarray(focal_length, dtype)
    h, w = ys.shape[0], xs.shape[0]
    local = jnp.stack(
        [jnp.broadcast_to(xs[None, :], (h, w)), jnp.broadcast_to(ys[:, None], (h, w)),
         jnp.broadcast_to(f, (h, w))], axis=-1)
    local = local / jnp.linalg.norm(local, axis=-1, keepdims=True)  # f > 0: never zero
    dirs = _einsum("ij,hwj->hwi", rot, local)
    origins = jnp.broadcast_to(pos, dirs.shape)
    return origins, dirs


def project(pos, rot, focal_length, sensor_size, pixels, points, z_min=1e-6):
    """Pinhole projection of world points to pixel coordinates (docs/sources.md#tpx-camera).

    Args:
        pos, rot, focal_length, sensor_size, pixels: the camera, as in :func:`camera_rays`.
        points: (N, 3) world points [m].
        z_min: depth below which a point counts as not in front of the camera [m].

    Returns:
        uv (N, 2) pixel coordinates (column, row), pixel centres at integers (see module
        docstring), and in_front (N,) bool (depth > z_min). Points behind the camera get
        finite (meaningless) coordinates and finite gradients.
    """
    points = jnp.asarray(points)
    dtype = points.dtype if jnp.issubdtype(points.dtype, jnp.floating) else jnp.float32
    points = points.astype(dtype)
    pc = _einsum("nk,kj->nj", points - jnp.asarray(pos, dtype)[None, :],
                 jnp.asarray(rot, dtype))  # rot^T (p - pos)
    z = pc[:, 2]
    in_front = z > z_min
    inv_z = jnp.where(in_front, 1.0 / jnp.where(in_front, z, 1.0), 0.0)
    f = jnp.asarray(focal_length, dtype)
    sensor = jnp.asarray(sensor_size, dtype)
    px = jnp.asarray([pixels[0], pixels[1]], dtype)
    xy = f * pc[:, :2] * inv_z[:, None]  # sensor coordinates [m]
    uv = (xy / sensor[None, :] + 0.5) * px[None, :] - 0.5
    return uv, in_front


# --------------------------------------------------------------------------- Model/State


def _camera_index(model, camera) -> int:
    if isinstance(camera, str):
        return list(model.camera_names).index(camera)
    return int(camera)


def _compose(body_pos, body_rot, bodies, local_pos, local_rot):
    """World pose of frames attached to ``bodies`` (static ints, -1 = world)."""
    bodies = np.asarray(bodies, np.int64)
    if bodies.size == 0 or np.all(bodies < 0):
        return local_pos, local_rot
    idx = np.maximum(bodies, 0)
    bpos, brot = body_pos[idx], body_rot[idx]
    wpos = bpos + _einsum("nij,nj->ni", brot, local_pos)
    wrot = _einsum("nij,njk->nik", brot, local_rot)
    world = jnp.asarray(bodies < 0)
    return (jnp.where(world[:, None], local_pos, wpos),
            jnp.where(world[:, None, None], local_rot, wrot))


def camera_pose(model, state, camera):
    """World pose (pos (3,), rot (3, 3)) of camera ``camera`` (name or index)."""
    c = _camera_index(model, camera)
    pos, rot = _compose(state.pos, state.rot, model.camera_body[c:c + 1],
                        model.camera_pos[c:c + 1], model.camera_rot[c:c + 1])
    return pos[0], rot[0]


def scene_from_model(model, state, background=SKY_COLOR) -> Scene:
    """World-frame :class:`Scene` of the model's visual geoms in ``state``.

    Geom world pose = body pose composed with the geom offset (``geom_body`` -1 = world).
    Plane texture period: ``geom_size[g, :2]`` where positive, else
    :data:`DEFAULT_PLANE_TILE` metres per repeat.
    """
    gtype = np.asarray(model.geom_type).astype(np.int64)
    gbody = np.asarray(model.geom_body).astype(np.int64)
    gtex = np.asarray(model.geom_texture).astype(np.int64)
    pos, rot = _compose(state.pos, state.rot, gbody, model.geom_pos, model.geom_rot)
    size, color = model.geom_size, model.geom_color
    dtype = pos.dtype

    def sel(kind):
        return np.nonzero(gtype == kind)[0]

    s, b, p = sel(_SPHERE), sel(_BOX), sel(_PLANE)
    tile = size[p, :2]
    tile = jnp.where(tile > 0, tile, DEFAULT_PLANE_TILE)
    textures = model.textures
    if textures is None or np.ndim(textures) != 4:
        textures = jnp.zeros((0, 1, 1, 3), dtype)
    return Scene(
        sphere_pos=pos[s], sphere_radius=size[s, 0], sphere_rot=rot[s], sphere_color=color[s],
        box_pos=pos[b], box_rot=rot[b], box_half=size[b], box_color=color[b],
        plane_pos=pos[p], plane_rot=rot[p], plane_color=color[p], plane_tile=tile,
        textures=jnp.asarray(textures, dtype), background=jnp.asarray(background, dtype),
        sphere_texture=tuple(int(i) for i in gtex[s]),
        box_texture=tuple(int(i) for i in gtex[b]),
        plane_texture=tuple(int(i) for i in gtex[p]),
    )


def render(model, state, camera, background=SKY_COLOR) -> jax.Array:
    """Image (px_h, px_w, 3) seen by camera ``camera`` (name or index) in ``state``.

    The differentiable camera of thesis §7.3.3.1: :func:`camera_rays` at the camera's
    world pose, cast against :func:`scene_from_model` with :func:`~thesis.physics.raycast.cast`.
    Differentiable w.r.t. the state (body poses) and the model's geometry, colours and
    textures; jit/vmap friendly (``camera`` and the model topology are static).
    """
    c = _camera_index(model, camera)
    pos, rot = camera_pose(model, state, c)
    origins, dirs = camera_rays(pos, rot, model.camera_focal[c], model.camera_sensor[c],
                                model.camera_pixels[c])
    return cast(origins, dirs, scene_from_model(model, state, background))


def render_batch(model, states, camera, background=SKY_COLOR) -> jax.Array:
    """:func:`render` vmapped over a batch of states (leading axis): (B, px_h, px_w, 3)."""
    return jax.vmap(lambda s: render(model, s, camera, background))(states)


def project_points(model, state, camera, points, z_min=1e-6):
    """Pixel coordinates (N, 2) and in-front mask (N,) of world ``points`` (N, 3) in camera
    ``camera`` (name or index); see :func:`project` (e.g. the infrared LED seen by the
    1024 x 768 onboard camera of thesis ch. 3).
    """
    c = _camera_index(model, camera)
    pos, rot = camera_pose(model, state, c)
    return project(pos, rot, model.camera_focal[c], model.camera_sensor[c],
                   model.camera_pixels[c], points, z_min)
