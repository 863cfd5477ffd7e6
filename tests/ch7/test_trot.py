"""The open-loop trot family and its grid search (thesis.ch7.trot, §7.3.3)."""

import jax.numpy as jnp
import numpy as np

from thesis.ch7 import trot
from thesis.physics.models import quadruped


def test_grid_is_the_product_in_parameter_order():
    cfg = {"frequency_hz": [1.0, 2.0], "hip_amplitude": [0.1, 0.2, 0.3], "knee_amplitude": [0.0],
           "knee_phase": [0.0, 1.0], "knee_offset": [0.4]}
    g = trot.grid(cfg)
    assert g.shape == (2 * 3 * 1 * 2 * 1, 5)
    np.testing.assert_array_equal(g[0], [1.0, 0.1, 0.0, 0.0, 0.4])
    np.testing.assert_array_equal(sorted(set(g[:, 1])), [0.1, 0.2, 0.3])


def test_diagonal_legs_move_together_and_the_pairs_in_antiphase():
    ctrl = trot.trot_controller()
    p = jnp.array([1.5, 0.4, 0.3, 0.5, -0.2])
    for t in (0.05, 0.21, 0.4):
        u, _ = ctrl(p, None, None, t)
        knee, hip = np.asarray(u[:4]), np.asarray(u[4:])
        assert abs(hip[0] - hip[3]) < 1e-6 and abs(knee[0] - knee[3]) < 1e-6  # legs 1, 4
        assert abs(hip[1] - hip[2]) < 1e-6 and abs(knee[1] - knee[2]) < 1e-6  # legs 2, 3
        np.testing.assert_allclose(hip[1], -hip[0], atol=1e-6)  # half a period apart
        np.testing.assert_allclose(knee[0] + knee[1], 2 * -0.2, atol=1e-6)  # about c_k
    w = 2 * np.pi * 1.5 * 0.21
    u, _ = ctrl(p, None, None, 0.21)
    np.testing.assert_allclose(float(u[4]), 0.4 * np.sin(w), rtol=1e-5)
    np.testing.assert_allclose(float(u[0]), -0.2 + 0.3 * np.sin(w + 0.5), rtol=1e-5)


def test_search_in_chunks_equals_one_batch_and_standing_still_does_not_move():
    model, s0 = quadruped()
    spine = model.body("spine")
    params = np.array([[1.5, 0.0, 0.0, 0.0, 0.0],  # zero amplitudes: the robot stands
                       [1.5, 0.4, 0.4, 1.5708, -0.4],
                       [2.0, 0.6, 0.2, 0.0, 0.4]])
    v1, u1 = trot.search(model, s0, 30, spine, params, chunk=2)  # a padded last chunk
    v3, u3 = trot.search(model, s0, 30, spine, params, chunk=3)
    np.testing.assert_allclose(v1, v3, rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(u1, u3, rtol=1e-5, atol=1e-7)
    assert abs(v1[0]) < 0.02 and u1[0] > 0.99
    assert np.all(u1 <= 1.0 + 1e-6) and np.any(np.abs(v1[1:]) > abs(v1[0]))
