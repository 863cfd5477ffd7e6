"""Neural-network controllers of chapter 7 (§7.3.2, §7.3.3, §7.3.3.1), as plain JAX pytrees.

Three controllers, all with a zero-output initial policy (§7.3.2, third trick: "our
controllers are initialized such that they only output zeros at the start"):

* :func:`mlp_init` / :func:`mlp_apply`: dense ReLU network with identity outputs
  (arm, §7.3.2.1: 1-128-128-4 = 17 284 parameters; §7.3.2.2: 3-1024-1024-1024-4 =
  2 107 396 parameters).
* :func:`skip_init` / :func:`skip_apply`: the gait network of §7.3.3: two ReLU layers and
  a linear output layer that reads both the top hidden layer and the inputs. The output
  is the sum of two dense maps, each with its own bias (hidden -> out and input -> out),
  which is what gives the thesis's 17 952 parameters for 2-128-128-8 (one shared bias
  would give 17 944).
* :func:`convnet_init` / :func:`convnet_apply`: a pixel controller for the cart-pole
  (§7.3.3.1): 3x3 convolutions (ReLU, "SAME"), 2x2 max pooling after every
  ``pool_every`` convolutions, then dense ReLU layers and a linear output.

Hidden weights are orthogonal (the original code's initialiser, docs/sources.md#tpx-experiments)
with the ReLU gain sqrt(2); biases start at zero; output layers start at exactly zero. A parameter
pytree is a list of ``{"w": (n_in, n_out), "b": (n_out,)}`` layers (plus named sub-trees for the
skip and conv networks).
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp

__all__ = [
    "n_params", "mlp_init", "mlp_apply", "skip_init", "skip_apply", "convnet_init",
    "convnet_apply",
]

_RELU_GAIN = math.sqrt(2.0)


def n_params(params) -> int:
    """Number of scalar parameters of a pytree."""
    return int(sum(int(x.size) for x in jax.tree.leaves(params)))


def _dense(key, n_in, n_out, zero, dtype):
    if zero:
        w = jnp.zeros((n_in, n_out), dtype)
    else:
        w = jax.nn.initializers.orthogonal(_RELU_GAIN)(key, (n_in, n_out), dtype)
    return {"w": w, "b": jnp.zeros((n_out,), dtype)}


def mlp_init(key, sizes, *, zero_output=True, dtype=jnp.float32):
    """Dense network with layer widths ``sizes = (n_in, h1, ..., n_out)``.

    Args:
        key: JAX PRNG key.
        sizes: widths, input first, output last (at least two entries).
        zero_output: initialise the output layer (weights and bias) at zero, so the
            initial policy outputs exactly zero (§7.3.2).
    Returns:
        list of ``{"w": (n_in, n_out), "b": (n_out,)}``, one per layer.
    """
    sizes = [int(s) for s in sizes]
    if len(sizes) < 2:
        raise ValueError(f"an MLP needs an input and an output width, got {sizes}")
    keys = jax.random.split(key, len(sizes) - 1)
    layers = []
    for i, (k, a, b) in enumerate(zip(keys, sizes[:-1], sizes[1:])):
        last = i == len(sizes) - 2
        layers.append(_dense(k, a, b, zero_output and last, dtype))
    return layers


def _affine(x, layer):
    """``x @ w + b`` for any number of leading axes (explicit broadcast of ``b``)."""
    b = layer["b"].reshape((1,) * (x.ndim - 1) + layer["b"].shape)
    return x @ layer["w"] + b


def mlp_apply(params, x):
    """Forward pass: ReLU hidden layers, identity output. ``x``: (..., n_in) -> (..., n_out)."""
    for layer in params[:-1]:
        x = jax.nn.relu(_affine(x, layer))
    return _affine(x, params[-1])


def skip_init(key, n_in, hidden, n_out, *, zero_output=True, dtype=jnp.float32):
    """Gait controller of §7.3.3: ReLU ``hidden`` layers, linear output fed by the top hidden
    layer and by the inputs (skip connection), output layer zero-initialised.

    Returns:
        ``{"hidden": [layers], "out": {"w": (h_last, n_out), "b"}, "skip": {"w": (n_in,
        n_out), "b"}}``.
    """
    hidden = [int(h) for h in hidden]
    k_h, k_o, k_s = jax.random.split(key, 3)
    sizes = [int(n_in), *hidden]
    keys = jax.random.split(k_h, max(len(hidden), 1))
    layers = [_dense(k, a, b, False, dtype) for k, a, b in zip(keys, sizes[:-1], sizes[1:])]
    return {"hidden": layers,
            "out": _dense(k_o, sizes[-1], int(n_out), zero_output, dtype),
            "skip": _dense(k_s, int(n_in), int(n_out), zero_output, dtype)}


def skip_apply(params, x):
    """``(..., n_in) -> (..., n_out)``: out(h_top) + skip(x), both linear."""
    h = x
    for layer in params["hidden"]:
        h = jax.nn.relu(_affine(h, layer))
    return _affine(h, params["out"]) + _affine(x, params["skip"])


def _conv_out_hw(h, w, n_conv, pool_every):
    n_pool = n_conv // pool_every if pool_every > 0 else 0
    for _ in range(n_pool):
        h, w = h // 2, w // 2
    return h, w


def convnet_init(key, image_hw, in_channels, conv_channels, pool_every, hidden, n_out, *,
                 zero_output=True, dtype=jnp.float32):
    """Pixel controller of §7.3.3.1 (memoryless; the inputs are stacked frames).

    Args:
        key: PRNG key.
        image_hw: (H, W) of the input images [pixels].
        in_channels: channels of the input (3 colours x number of stacked frames).
        conv_channels: output channels of each 3x3 convolution (may be empty: then the
            network is an MLP on the flattened pixels).
        pool_every: 2x2 max pooling after every this many convolutions (0: never).
        hidden: widths of the dense ReLU layers after the convolutions.
        n_out: number of outputs (zero-initialised).
    Returns:
        ``{"conv": [{"w": (3, 3, c_in, c_out), "b"}], "dense": [mlp layers]}``.
    """
    h, w = int(image_hw[0]), int(image_hw[1])
    conv_channels = [int(c) for c in conv_channels]
    keys = jax.random.split(key, len(conv_channels) + 1)
    conv, c_in = [], int(in_channels)
    for k, c in zip(keys[:-1], conv_channels):
        fan = jax.nn.initializers.orthogonal(_RELU_GAIN)(k, (9 * c_in, c), dtype)
        conv.append({"w": fan.reshape(3, 3, c_in, c), "b": jnp.zeros((c,), dtype)})
        c_in = c
    ho, wo = _conv_out_hw(h, w, len(conv_channels), int(pool_every))
    if ho < 1 or wo < 1:
        raise ValueError(f"image {h}x{w} is too small for {len(conv_channels)} convolutions "
                         f"with pooling every {pool_every}")
    dense = mlp_init(keys[-1], [ho * wo * c_in, *hidden, n_out], zero_output=zero_output,
                     dtype=dtype)
    return {"conv": conv, "dense": dense}


def convnet_apply(params, images, pool_every):
    """``images`` (H, W, C) -> (n_out,). Pixel values are centred (minus 0.5) first, as in
    the original code (docs/sources.md#tpx-experiments)."""
    x = images[None] - 0.5
    for i, layer in enumerate(params["conv"]):
        x = jax.lax.conv_general_dilated(x, layer["w"], (1, 1), "SAME",
                                         dimension_numbers=("NHWC", "HWIO", "NHWC"))
        x = jax.nn.relu(x + layer["b"].reshape(1, 1, 1, -1))
        if pool_every > 0 and (i + 1) % pool_every == 0:
            x = jax.lax.reduce_window(x, -jnp.inf, jax.lax.max, (1, 2, 2, 1), (1, 2, 2, 1),
                                      "VALID")
    return mlp_apply(params["dense"], x.reshape(-1))
