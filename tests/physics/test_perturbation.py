"""perturbation.py: rounding-level twins are identity when off, move a start by about one
ulp when on, and reach every rollout and random starting point under the process-wide size."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import perturbation, rollout
from thesis.physics.models import arm4


def _ctrl(p, sens, mem, t):
    return p * jnp.sin(3.0 * t) * jnp.ones((4,), p.dtype) + 0.0 * sens["joint_angle"], mem


def test_off_is_the_state_itself_and_the_default():
    _, s = arm4()
    assert perturbation.relative() == 0.0
    assert perturbation.at_start(s) is s
    tree = {"w": jnp.ones(3), "n": jnp.arange(2)}
    assert perturbation.perturb_tree(tree) is tree
    same = perturbation.scale_positions(s, 0.0, 5)
    np.testing.assert_array_equal(np.asarray(same.pos), np.asarray(s.pos))


def test_scale_positions_moves_by_a_few_ulp_and_depends_on_the_seed():
    _, s = arm4()
    a = np.asarray(perturbation.scale_positions(s, 1e-7, 1).pos)
    b = np.asarray(perturbation.scale_positions(s, 1e-7, 2).pos)
    pos = np.asarray(s.pos)
    ulp = np.spacing(np.abs(pos).astype(np.float32))
    moved = np.abs(a - pos)
    assert (moved > 0).any()
    assert (moved <= 8 * ulp).all()  # |u| < 8 for every coordinate of this small state
    assert not np.array_equal(a, b)


def test_scope_sets_and_restores_and_rejects_sizes_out_of_range():
    _, s = arm4()
    with perturbation.scope(1e-7):
        assert perturbation.relative() == 1e-7
        moved = perturbation.at_start(s)
        assert not np.array_equal(np.asarray(moved.pos), np.asarray(s.pos))
        np.testing.assert_allclose(moved.pos, s.pos, rtol=1e-6, atol=0)
    assert perturbation.relative() == 0.0
    with pytest.raises(ValueError, match="allowed values: 0"):
        perturbation.set_relative(0.5)
    with pytest.raises(ValueError, match="allowed values"):
        with perturbation.scope(-1e-7):
            pass
    assert perturbation.relative() == 0.0


def test_rollout_starts_from_the_perturbed_state_under_the_scope():
    m, s = arm4()
    p = jnp.asarray(0.4)
    run = lambda: rollout(m, s, _ctrl, p, 50)[0].pos  # noqa: E731 (traced per call)
    plain, again = run(), run()
    np.testing.assert_array_equal(np.asarray(plain), np.asarray(again))
    with perturbation.scope(1e-7):
        twin = run()
        start = rollout(m, s, _ctrl, p, 0)[0].pos  # zero steps: the start it used
    assert not np.array_equal(np.asarray(twin), np.asarray(plain))
    np.testing.assert_allclose(twin, plain, rtol=1e-4, atol=1e-5)
    np.testing.assert_array_equal(
        np.asarray(start),
        np.asarray(perturbation.scale_positions(s, 1e-7, perturbation.SEED).pos))


def test_perturb_tree_moves_floating_leaves_only():
    tree = {"w": jnp.linspace(-1.0, 1.0, 50), "n": jnp.arange(5), "b": jnp.zeros(4)}
    with perturbation.scope(1e-6):
        out = perturbation.perturb_tree(tree, seed=3)
        again = perturbation.perturb_tree(tree, seed=3)
    np.testing.assert_array_equal(np.asarray(out["n"]), np.asarray(tree["n"]))
    np.testing.assert_array_equal(np.asarray(out["b"]), np.zeros(4))  # relative: 0 stays 0
    w, w0 = np.asarray(out["w"]), np.asarray(tree["w"])
    assert not np.array_equal(w, w0)
    np.testing.assert_allclose(w, w0, rtol=1e-5, atol=0)
    np.testing.assert_array_equal(w, np.asarray(again["w"]))
    assert jax.tree_util.tree_structure(out) == jax.tree_util.tree_structure(tree)
