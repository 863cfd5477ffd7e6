"""kinematics.py: joint coordinates of hinge, universal, ball and slider joints."""

import jax.numpy as jnp
import numpy as np

from thesis.physics import Builder, sensors
from thesis.physics.math import rodrigues


def _rot(axis, angle):
    return np.asarray(rodrigues(jnp.asarray(np.asarray(axis, float) * angle)))


def _model(kind):
    b = Builder("k")
    b.add_box("a", (0.2, 0.2, 0.2), (0, 0, 0))
    b.add_box("b", (0.2, 0.2, 0.2), (0, 0, -0.5))
    if kind == "hinge":
        b.add_hinge("j", "a", "b", (0, 0, 0), (0, 1, 0))
    elif kind == "universal":
        b.add_universal("j", "a", "b", (0, 0, 0), (1, 0, 0), (0, 1, 0))
    elif kind == "ball":
        b.add_ball("j", "a", "b", (0, 0, 0))
    else:
        b.add_slider("j", "a", "b", (1, 0, 0))
    return b.build(jnp.float32)


def _pose(s, rot_b):
    anchor_b = np.array([0.0, 0.0, 0.5])  # anchor seen from b's centre at build
    pos_b = -rot_b @ anchor_b
    return s.replace(pos=s.pos.at[1].set(jnp.asarray(pos_b, jnp.float32)),
                     rot=s.rot.at[1].set(jnp.asarray(rot_b, jnp.float32)))


def test_hinge_angle_and_velocity():
    m, s = _model("hinge")
    s = _pose(s, _rot((0, 1, 0), 0.7))
    s = s.replace(angvel=s.angvel.at[1].set(jnp.asarray([0.0, 1.5, 0.0])))
    sen = sensors(m, s)
    np.testing.assert_allclose(sen["joint_angle"], [0.7], atol=1e-5)
    np.testing.assert_allclose(sen["joint_velocity"], [1.5], atol=1e-5)


def test_universal_angles():
    m, s = _model("universal")
    a, bb = 0.4, -0.9
    s = _pose(s, _rot((1, 0, 0), a) @ _rot((0, 1, 0), bb))
    np.testing.assert_allclose(sensors(m, s)["joint_angle"], [a, bb], atol=1e-5)


def test_ball_rotation_vector():
    m, s = _model("ball")
    phi = np.array([0.3, -0.5, 0.2])
    s = _pose(s, _rot(phi / np.linalg.norm(phi), np.linalg.norm(phi)))
    np.testing.assert_allclose(sensors(m, s)["joint_angle"], phi, atol=1e-5)


def test_slider_displacement():
    m, s = _model("slider")
    s = s.replace(pos=s.pos.at[1, 0].set(0.25), vel=s.vel.at[1, 0].set(-0.5))
    sen = sensors(m, s)
    np.testing.assert_allclose(sen["joint_angle"], [0.25], atol=1e-6)
    np.testing.assert_allclose(sen["joint_velocity"], [-0.5], atol=1e-6)
