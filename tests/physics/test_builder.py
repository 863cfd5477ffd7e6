"""builder.py / tables.py / types.py: inertias, masses, static topology, pytree behaviour."""

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics import Builder, JointType, Model, box_inertia, sphere_inertia
from thesis.physics.models import arm4, quadruped


def test_inertias():
    np.testing.assert_allclose(np.diag(box_inertia(12.0, (1.0, 2.0, 3.0))),
                               [13.0, 10.0, 5.0])
    np.testing.assert_allclose(np.diag(sphere_inertia(5.0, 2.0)), [8.0] * 3)
    np.testing.assert_allclose(np.diag(sphere_inertia(5.0, 2.0, "tpx_quirk")), [2.0] * 3)


def test_density_masses_and_model_sizes():
    m, s = quadruped()
    assert m.n_body == 17 and m.n_servo == 8 and m.n_csphere == 8
    total = float(jnp.sum(m.body_mass))
    np.testing.assert_allclose(total, 28.69, atol=0.01)  # thesis §7.3.3: 28.7 kg
    spine = float(m.body_mass[m.body("spine")])
    assert 0.70 < spine / total < 0.80  # "75% of the mass ... in its torso"
    ma, _ = arm4()
    np.testing.assert_allclose(float(jnp.sum(ma.body_mass)), 32.17, atol=0.01)  # §7.3.2
    assert list(ma.joint_type) == [JointType.HINGE] * 4 + [JointType.FIXED]


def test_model_is_a_pytree_with_static_topology():
    m, s = quadruped()
    leaves, tdef = jax.tree.flatten(m)
    assert all(isinstance(x, jax.Array) for x in leaves)
    m2 = jax.tree.unflatten(tdef, leaves)
    assert isinstance(m2, Model) and np.array_equal(m2.joint_body1, m.joint_body1)
    heavier = m.replace(body_mass=m.body_mass * 2)
    assert jax.tree.structure(heavier) == tdef
    f = jax.jit(lambda mm: jnp.sum(mm.body_mass))
    np.testing.assert_allclose(f(heavier), 2 * f(m), rtol=1e-6)


def test_joint_frames_in_body_coordinates():
    b = Builder("t")
    b.add_box("a", (1, 1, 1), (0, 0, 0))
    rot = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])  # 90 deg about z
    b.add_box("b", (1, 1, 1), (2, 0, 0), rot=rot)
    b.add_hinge("h", "a", "b", (1, 0, 0), (0, 1, 0))
    m, s = b.build(jnp.float32)
    np.testing.assert_allclose(m.joint_anchor1[0], [1, 0, 0], atol=1e-6)
    np.testing.assert_allclose(m.joint_anchor2[0], rot.T @ np.array([-1.0, 0, 0]), atol=1e-6)
    np.testing.assert_allclose(m.joint_frame2[0][:, 0], rot.T @ np.array([0.0, 1, 0]), atol=1e-6)
