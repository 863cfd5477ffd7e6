"""Rendering strips of frames of a learned behaviour with the engine's camera (§7.3.3).

The quadruped model has no camera, so :func:`with_tracking_camera` returns a copy of a
model with one world-fixed camera added through ``Model.replace`` (the camera fields of
the engine contract); :func:`render_strip` moves that camera along with a body between
frames (a tracking shot) and renders with ``thesis.physics.render``.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics import render

__all__ = ["with_tracking_camera", "render_strip", "to_uint8"]

#: Camera frame (columns: x right, y down, z forward) looking along world +y, z up.
LOOK_ALONG_Y = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]]).T


def with_tracking_camera(model, pixels, *, focal_length=0.03, sensor_width=0.036,
                         name="tracker"):
    """Copy of ``model`` whose only camera is a world camera looking along +y.

    Args:
        pixels: (width, height) [pixels]; the sensor keeps that aspect ratio.
        focal_length, sensor_width: pinhole parameters [m].
    """
    w, h = int(pixels[0]), int(pixels[1])
    dt = model.body_mass.dtype
    return model.replace(
        camera_names=(name,), camera_body=np.array([-1], np.int32),
        camera_pixels=((w, h),),
        camera_pos=jnp.zeros((1, 3), dt), camera_rot=jnp.asarray(LOOK_ALONG_Y, dt)[None],
        camera_focal=jnp.asarray([focal_length], dt),
        camera_sensor=jnp.asarray([[sensor_width, sensor_width * h / w]], dt))


def render_strip(model, state0, positions, rotations, body: int, offset):
    """Render one frame per pose, the camera following ``body``'s x coordinate.

    Args:
        model: a model with a camera at index 0 (e.g. :func:`with_tracking_camera`).
        state0: a state of the model (its other fields are kept).
        positions: (F, n_body, 3) body positions [m]; rotations: (F, n_body, 3, 3).
        body: index of the tracked body.
        offset: (3,) camera position relative to (x_body, 0, 0) [m].
    Returns:
        (F, H, W, 3) float images in [0, 1].
    """
    offset = jnp.asarray(offset, positions.dtype)

    def one(pos, rot):
        cam = jnp.array([pos[body, 0], 0.0, 0.0], pos.dtype) + offset
        m = model.replace(camera_pos=cam[None])
        return render(m, state0.replace(pos=pos, rot=rot), 0)
    return jax.jit(jax.vmap(one))(jnp.asarray(positions), jnp.asarray(rotations))


def to_uint8(images) -> np.ndarray:
    """Float images in [0, 1] -> uint8 0-255."""
    return np.clip(np.round(np.asarray(images, float) * 255.0), 0, 255).astype(np.uint8)
