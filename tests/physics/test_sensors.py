"""sensors.py: IMU (specific force, gyroscope in the body frame), contact forces."""

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics import Builder, sensors, step
from thesis.physics.math import rodrigues

G = 9.81


def test_imu_reads_specific_force_and_body_rates():
    rot = np.asarray(rodrigues(jnp.asarray([np.pi / 2, 0.0, 0.0])))  # body z -> world -y
    b = Builder("imu", dt=0.01)
    b.add_box("free", (0.1, 0.2, 0.3), (0, 0, 5.0), rot=rot)
    b.set_velocity("free", (0, 0, 0), (0.0, 0.0, 2.0))
    b.add_box("held", (0.1, 0.1, 0.1), (1, 0, 0), rot=rot)
    b.add_fixed("weld", "world", "held")
    m, s = b.build(jnp.float32)
    s = jax.jit(lambda s: jax.lax.fori_loop(0, 50, lambda i, x: step(m, x, jnp.zeros((0,))),
                                            s))(s)
    sen = sensors(m, s)
    # free fall: no specific force; held body: +g upwards = body +y axis (rotated frame)
    np.testing.assert_allclose(sen["imu_acc"][0], [0, 0, 0], atol=1e-3)
    np.testing.assert_allclose(sen["imu_acc"][1], rot.T @ np.array([0, 0, G]), atol=1e-3)
    np.testing.assert_allclose(sen["imu_gyro"][0], np.asarray(s.rot[0]).T @ [0, 0, 2.0],
                               atol=1e-4)
    # attitude: the world's up axis in each body's frame, the held body's up = body +y
    np.testing.assert_allclose(sen["imu_up"][1], [0, 1, 0], atol=1e-6)
    np.testing.assert_allclose(sen["imu_up"][0], np.asarray(s.rot[0]).T @ [0, 0, 1.0],
                               atol=1e-6)


def test_contact_forces_share_the_weight():
    b = Builder("table", dt=0.005)
    b.add_plane("floor", (0, 0, 1), 0.0)
    b.add_box("top", (1.0, 0.5, 0.05), (0.2, 0, 0.075), mass=10.0)
    b.add_contact_sphere("top", 0.05, (-0.4, 0, -0.025))
    b.add_contact_sphere("top", 0.05, (0.4, 0, -0.025))
    m, s = b.build(jnp.float32)
    s = jax.jit(lambda s: jax.lax.fori_loop(0, 200, lambda i, x: step(m, x, jnp.zeros((0,))),
                                            s))(s)
    f = np.asarray(sensors(m, s)["contact_force"])
    np.testing.assert_allclose(f.sum(), 10.0 * G, rtol=1e-3)
    np.testing.assert_allclose(f, [5.0 * G, 5.0 * G], rtol=5e-3)  # CoM midway
