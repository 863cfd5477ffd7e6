"""Controllers of chapter 7: parameter counts of §7.3.2-7.3.3 and the zero initial policy."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.ch7 import nets


def test_arm_fixed_network_has_the_stated_parameter_count():
    # §7.3.2.1: 1 input, 2 x 128 ReLU, 4 outputs -> 17 284 parameters
    p = nets.mlp_init(jax.random.key(0), [1, 128, 128, 4])
    assert nets.n_params(p) == 17284


def test_arm_random_network_has_the_stated_parameter_count():
    # §7.3.2.2: 3 inputs, 3 x 1024 ReLU, 4 outputs -> 2 107 396 parameters
    p = nets.mlp_init(jax.random.key(0), [3, 1024, 1024, 1024, 4])
    assert nets.n_params(p) == 2107396


def test_gait_network_with_skip_has_the_stated_parameter_count():
    # §7.3.3: 2 inputs, 2 x 128 ReLU, 8 linear outputs fed by the top layer and the inputs
    p = nets.skip_init(jax.random.key(0), 2, [128, 128], 8)
    assert nets.n_params(p) == 17952


@pytest.mark.parametrize("seed", [0, 1])
def test_zero_output_initial_policy_outputs_exactly_zero(seed):
    key = jax.random.key(seed)
    x = jax.random.normal(jax.random.key(seed + 10), (5, 3))
    mlp = nets.mlp_init(key, [3, 16, 16, 4])
    assert np.all(np.asarray(nets.mlp_apply(mlp, x)) == 0.0)
    skip = nets.skip_init(key, 3, [16, 16], 8)
    assert np.all(np.asarray(nets.skip_apply(skip, x)) == 0.0)
    conv = nets.convnet_init(key, (8, 12), 9, [4, 4], 2, [8], 1)
    img = jax.random.uniform(jax.random.key(seed + 20), (8, 12, 9))
    assert np.all(np.asarray(nets.convnet_apply(conv, img, 2)) == 0.0)
    # the hidden layers are not zero, so the output layer gets a gradient at once
    assert float(jnp.abs(mlp[0]["w"]).sum()) > 0
    g = jax.grad(lambda p: jnp.sum(nets.mlp_apply(p, x) ** 2 + nets.mlp_apply(p, x)))(mlp)
    assert float(jnp.abs(g[-1]["w"]).sum()) > 0


def test_without_zero_output_the_policy_is_not_zero():
    x = jnp.ones((2, 3))
    mlp = nets.mlp_init(jax.random.key(0), [3, 16, 4], zero_output=False)
    assert float(jnp.abs(nets.mlp_apply(mlp, x)).sum()) > 0


def test_skip_connection_reaches_the_output():
    p = nets.skip_init(jax.random.key(0), 2, [8, 8], 3)
    p["skip"]["w"] = jnp.ones((2, 3))
    x = jnp.array([0.5, -2.0])
    np.testing.assert_allclose(np.asarray(nets.skip_apply(p, x)), np.full(3, -1.5), rtol=1e-6)


def test_convnet_rejects_an_image_too_small_for_its_pooling():
    with pytest.raises(ValueError, match="too small"):
        nets.convnet_init(jax.random.key(0), (2, 2), 3, [4, 4, 4, 4], 1, [8], 1)
