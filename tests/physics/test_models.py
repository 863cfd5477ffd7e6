"""models/: each model builds and steps; the quadruped stands; cameras and masses."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import GeomType, rollout, sensors
from thesis.physics.models import MODELS, cartpole, quadruped


def _zero(m):
    return lambda p, sens, mem, t: (jnp.zeros((m.n_servo,)), mem)


@pytest.mark.parametrize("name", ["ball", "arm4", "cartpole"])
def test_model_builds_and_steps(name):
    m, s = MODELS[name]()
    fin, tr = jax.jit(lambda s: rollout(m, s, _zero(m), None, 100,
                                        record=("body_pos", "joint_angle")))(s)
    assert np.all(np.isfinite(np.asarray(tr["body_pos"])))
    assert all(np.all(np.isfinite(np.asarray(x))) for x in sensors(m, fin).values())
    assert tr["body_pos"].shape == (100, m.n_body, 3)


def test_quadruped_stands_for_two_seconds():
    m, s = quadruped()
    assert m.n_body == 17 and m.n_servo == 8
    fin, tr = jax.jit(lambda s: rollout(m, s, _zero(m), None, 200,
                                        record=("body_pos", "body_rot", "contact_force")))(s)
    pos = np.asarray(tr["body_pos"])
    spine = m.body("spine")
    feet = [m.body(f"foot{i}") for i in range(1, 5)]
    assert np.all(np.isfinite(pos))
    assert pos[:, spine, 2].min() > 0.35  # started at 0.40: the legs hold it up
    assert pos[:, feet, 2].min() > 0.05 - 0.02  # feet do not sink through the floor
    up = np.asarray(tr["body_rot"])[-1, spine][:, 2]
    assert up[2] > 0.99  # upright
    force = np.asarray(tr["contact_force"])[-1]
    np.testing.assert_allclose(force[4:].sum(), float(jnp.sum(m.body_mass)) * 9.81, rtol=0.02)


def test_cartpole_camera_and_geometry_fields():
    m, s = cartpole(pixels=(72, 24))
    assert m.camera_names == ("front_camera",) and m.camera_pixels == ((72, 24),)
    np.testing.assert_allclose(m.camera_sensor[0], [0.036, 0.012])
    np.testing.assert_allclose(m.camera_focal[0], 0.018)
    rot = np.asarray(m.camera_rot[0])
    np.testing.assert_allclose(rot[:, 2], [0, -1, 0], atol=1e-6)  # looks along -y
    np.testing.assert_allclose(rot.T @ rot, np.eye(3), atol=1e-6)
    assert list(m.geom_type).count(GeomType.PLANE) == 1 and m.n_pair == 0
    assert m.textures.shape[0] == 2 and (m.geom_texture >= 0).sum() == 2
