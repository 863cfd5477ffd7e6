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


def _soft_model(dt, **kw):
    b = Builder("soft", dt=dt, **kw)
    b.add_plane("floor", (0, 0, 1), 0.0)
    b.add_box("a", (0.1, 0.1, 0.1), (0, 0, 0.5))
    b.add_box("c", (0.1, 0.1, 0.1), (0.2, 0, 0.5))
    b.add_hinge("h", "a", "c", (0.1, 0, 0.5), (0, 1, 0), limits=(-0.5, 0.5))
    b.add_contact_sphere("a", 0.05)
    return b.build(jnp.float32)[0]


def test_default_softness_is_physical_not_per_step():
    """The builder's default joint, limit and contact softness are constants [Hz] that do
    not change with dt: 100, 100 and 25 Hz, i.e. 1/dt and 0.25/dt at the default 10-ms
    step; a model may state its own."""
    from thesis.physics import builder

    for dt in (0.01, 0.0025, 0.001):
        m = _soft_model(dt)
        np.testing.assert_allclose(m.joint_hz, builder.JOINT_HZ)
        np.testing.assert_allclose(m.limit_hz, builder.LIMIT_HZ)
        np.testing.assert_allclose(m.material_hz[0], builder.CONTACT_HZ)
    assert (builder.JOINT_HZ, builder.LIMIT_HZ, builder.CONTACT_HZ) == (100.0, 100.0, 25.0)
    m = _soft_model(0.001, joint_hz=300.0, limit_hz=200.0, contact_hz=40.0)
    np.testing.assert_allclose([m.joint_hz[0], m.limit_hz[0], m.material_hz[0]],
                               [300.0, 200.0, 40.0])


def test_robots_state_the_softness_they_had_at_their_step():
    """Every robot keeps the softness it had at its own step under the former per-step
    rule, whatever dt it is built with: the Oncilla 400 / 100 Hz (2.5 ms), Puppy II
    200 / 50 Hz (5 ms), the 10-ms robots the builder's 100 / 25 Hz."""
    import importlib

    O = importlib.import_module("thesis.physics.models.oncilla")
    P = importlib.import_module("thesis.physics.models.puppy")

    for dt in (0.0025, 0.00125):
        m, _ = O.oncilla(dt=dt)
        np.testing.assert_allclose(np.unique(np.asarray(m.joint_hz)), [400.0])
        np.testing.assert_allclose(np.unique(np.asarray(m.limit_hz)), [400.0])
        np.testing.assert_allclose(np.unique(np.asarray(m.material_hz)), [100.0])
    m, _ = P.puppy(dt=0.0025)
    np.testing.assert_allclose(np.unique(np.asarray(m.joint_hz)), [200.0])
    np.testing.assert_allclose(np.unique(np.asarray(m.material_hz)), [50.0])
    m, _ = quadruped(dt=0.005)
    np.testing.assert_allclose(np.unique(np.asarray(m.joint_hz)), [100.0])
    np.testing.assert_allclose(np.unique(np.asarray(m.material_hz)), [25.0])
