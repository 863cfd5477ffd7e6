"""Morphology as parameters (thesis §8.2).

* The builder construction of the co-optimised body is the chapter-7 quadruped (leaf by
  leaf) plus its knee springs.
* :func:`thesis.coopt.morphology.apply` writes every leaf a parameter reaches exactly as
  the builder would build that body (random bodies within the bounds).
* One compiled rollout serves every body (no retrace per value).
* Gradients of a closed-loop rollout with respect to each kind of morphological leaf
  (segment lengths, foot radius, hip placement, mass, spring stiffness and rest angle)
  match float64 central differences on a short rollout (40 steps).
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.coopt import morphology as M
from thesis.coopt import objective as O
from thesis.physics import rollout
from thesis.physics.models import quadruped

#: Leaves a morphological parameter reaches (checked against the builder).
LEAVES = ("body_mass", "body_inertia", "joint_anchor1", "joint_anchor2", "csphere_radius",
          "csphere_offset", "geom_size", "geom_pos", "joint_frame1", "joint_frame2",
          "joint_rel_rot", "jspring_k", "jspring_rest", "jspring_c")
TROT = np.array([1.5, 0.2, 0.2, 0.0, -0.4])


def test_built_body_is_the_chapter7_quadruped(x64):
    m0, s0 = quadruped(dtype=jnp.float64, servo_max_torque=20.0)
    m1, s1 = M.build_body(dtype=jnp.float64, servo_max_torque=20.0)
    assert m1.body_names == m0.body_names and m1.joint_names == m0.joint_names
    assert m1.servo_names == m0.servo_names
    np.testing.assert_array_equal(m1.csphere_body, m0.csphere_body)
    for name in LEAVES[:-3] + ("servo_max_torque", "servo_lo", "servo_hi", "dt"):
        np.testing.assert_allclose(getattr(m1, name), getattr(m0, name), atol=1e-12,
                                   err_msg=name)
    np.testing.assert_allclose(s1.pos, s0.pos, atol=1e-12)
    # the only addition: one spring row per knee
    assert m1.n_rows - m0.n_rows == 4
    assert [m1.dof_names[d] for d in m1.jspring_dof] == [f"knee{i}:0" for i in range(1, 5)]
    np.testing.assert_allclose(M.to_physical(jnp.zeros(8)), M.built_values(), rtol=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_apply_matches_the_builder(x64, seed):
    rng = np.random.default_rng(seed)
    lo = np.array([p.lo for p in M.PARAMS])
    hi = np.array([p.hi for p in M.PARAMS])
    values = lo + (hi - lo) * rng.uniform(0.02, 0.98, size=lo.shape)
    base, s_base = M.build_body(dtype=jnp.float64)
    want, s_want = M.build_body(values, dtype=jnp.float64)
    got, s_got = M.apply(base, s_base, jnp.asarray(values))
    for name in LEAVES:
        np.testing.assert_allclose(getattr(got, name), getattr(want, name), atol=1e-12,
                                   err_msg=name)
    np.testing.assert_allclose(s_got.pos, s_want.pos, atol=1e-12)
    # the body really changed (the test would pass trivially otherwise)
    assert not np.allclose(got.body_mass, base.body_mass)
    # round trip through the unconstrained coordinates
    np.testing.assert_allclose(M.to_physical(M.to_unconstrained(jnp.asarray(values))), values,
                               rtol=1e-10)


def test_one_compilation_serves_every_body():
    model, s0 = M.build_body(servo_max_torque=20.0)
    f = O.speed_fn(model, s0, TROT, 5)
    net = O.init_net(jax.random.PRNGKey(0), [4])
    traces = []

    def counted(u):
        traces.append(1)
        return f(net, u)

    g = jax.jit(counted)
    a = float(g(jnp.asarray(np.zeros(8), jnp.float32)))
    b = float(g(jnp.asarray(np.full(8, 0.7), jnp.float32)))
    assert len(traces) == 1 and a != b


@functools.lru_cache(maxsize=None)
def _problem(n_steps: int):
    """(f, grad f) of a 40-step closed-loop rollout as a function of the physical values."""
    model, s0 = M.build_body(dtype=jnp.float64, servo_max_torque=20.0)
    ctrl = O.controller_fn(model, TROT)
    net = O.init_net(jax.random.PRNGKey(0), [8], zero_output=False, output_scale=0.1,
                     dtype=jnp.float64)
    spine = model.body("spine")

    def f(values):
        m, s = M.apply(model, s0, values)
        fin, tr = rollout(m, s, ctrl, net, n_steps, record=("body_vel",))
        return (jnp.mean(tr["body_vel"][:, spine, 0]) + fin.pos[spine, 2]
                + 0.1 * jnp.sum(fin.pos[:, 0]))
    return jax.jit(f), jax.jit(jax.grad(f))


@pytest.mark.parametrize("name", M.NAMES)
def test_gradient_matches_central_differences(x64, name):
    f, grad = _problem(40)
    i = M.NAMES.index(name)
    p = M.PARAMS[i]
    v0 = jnp.asarray(M.built_values())
    g = float(grad(v0)[i])
    h = 1e-5 * (p.hi - p.lo)
    e = jnp.zeros(8, jnp.float64).at[i].set(h)
    fd = float((f(v0 + e) - f(v0 - e)) / (2 * h))
    assert abs(g) > 1e-4, (name, g)  # the parameter reaches the rollout
    assert g == pytest.approx(fd, rel=2e-5, abs=1e-8), (name, g, fd)
