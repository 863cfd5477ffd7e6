"""The pendulum-cart system of thesis §7.3.3.1, seen by a camera (Fig. 7.4).

From [TPX] ``robotmodel/pendulum.json`` (docs/sources.md#tpx-pendulum): sled box 0.15^3 m at (0, 0,
0.3) on a slider to the world along x with a linear position servo (command = sled x [m], within +-1
m, gain 15 1/s); bar box 0.07 x 0.1 x 0.6 m at the origin hinged to the sled at z 0.3 about y; "top"
box 0.15^3 m at z -0.3 fixed to the bar (the pole hangs down at start); density 1000 kg/m^3; dt 0.01
s, 20 solver iterations, warm start 0; the builder's physical softness (joints 100 Hz, contacts 25
Hz, independent of dt). Camera ``front_camera`` at (0, 2, 0.3) looking along -y (the JSON's
quaternion turns the original's x-looking camera by 90 deg about z), 288 x 96 px (thesis Fig. 7.4),
sensor 0.036 x 0.012 m, focal length 0.018 m; a textured backdrop plane at y = -1. The JSON gives no
force limit for the sled servo (unbounded here by default) and textures from
photographs we do not have: the textures here are procedural (deterministic stripes and
checkers), which keeps rendering and its gradients meaningful.
"""

from __future__ import annotations

import numpy as np
import jax.numpy as jnp

from thesis.physics.builder import Builder

#: Camera frame (columns x right, y down, z forward) looking along world -y.
CAMERA_ROT = np.array([[-1.0, 0, 0], [0, 0, -1.0], [0, -1.0, 0]]).T


def _textures(size=64):
    u = (np.arange(size) + 0.5) / size
    uu, vv = np.meshgrid(u, u)
    checker = ((np.floor(uu * 8) + np.floor(vv * 8)) % 2)[..., None]
    back = 0.35 + 0.3 * checker * np.array([0.9, 0.8, 0.6]) + 0.1 * np.array([0.2, 0.3, 0.5])
    stripes = 0.5 + 0.4 * np.sin(2 * np.pi * 4 * vv)[..., None] * np.array([1.0, 0.3, 0.1])
    stripes = np.clip(stripes, 0, 1)
    return np.clip(back, 0, 1), stripes


def cartpole(*, dt=0.01, solver_iterations=20, warm_start=0.0, servo_gain=15.0,
             servo_max_force=np.inf, rail_range=1.0, pixels=(288, 96),
             sensor_size=(0.036, 0.012), focal_length=0.018, gravity=(0.0, 0.0, -9.81),
             texture_size=64, dtype=jnp.float32):
    """Build the cart-pole; returns ``(Model, State)``. One servo: sled x target [m]."""
    b = Builder("cartpole", dt=dt, solver_iterations=solver_iterations,
                warm_start=warm_start, gravity=gravity)
    back, stripes = _textures(texture_size)
    b.add_texture("background", back)
    b.add_texture("stripes", stripes)
    b.add_plane("background", (0, 1, 0), -1.0, texture="background", collide=False)
    b.add_box("sled", (0.15, 0.15, 0.15), (0, 0, 0.3), color=(0.2, 0.4, 0.9))
    b.add_box("bar", (0.07, 0.1, 0.6), (0, 0, 0.0), color=(0.9, 0.9, 0.9), texture="stripes")
    b.add_box("top", (0.15, 0.15, 0.15), (0, 0, -0.3), color=(0.9, 0.2, 0.2))
    b.add_slider("rail", "world", "sled", (1, 0, 0))
    b.add_hinge("bottom", "sled", "bar", (0, 0, 0.3), (0, 1, 0))
    b.add_fixed("top", "bar", "top", (0, 0, -0.3))
    b.add_position_servo("rail", servo_gain, servo_max_force, np.inf,
                         command_range=(-rail_range, rail_range), name="rail")
    b.add_camera("front_camera", "world", (0, 2, 0.3), CAMERA_ROT, focal_length,
                 sensor_size, pixels)
    return b.build(dtype)
