"""Tests of the bilinear spatial transformers and the shared transform interface."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from jax import enable_x64
from jax.test_util import check_grads

from thesis.ch2.transforms import (
    TRANSFORMS,
    affine_grid,
    bilinear_sample,
    get_transform,
    no_skew_to_affine,
)


@pytest.mark.parametrize("name", ["bilinear", "bilinear_no_skew", "chirp_z", "none"])
def test_identity_parameters_return_image(name):
    rng = np.random.default_rng(0)
    img = jnp.asarray(rng.random((2, 16, 16)), jnp.float32)
    t = get_transform(name)
    p = jnp.tile(jnp.asarray(t.identity, jnp.float32), (2, 1))
    out = jax.jit(t.apply, static_argnums=2)(img, p, 16)
    assert out.shape == (2, 16, 16)
    np.testing.assert_allclose(np.asarray(out), np.asarray(img), atol=3e-5)


def test_no_skew_and_chirp_z_sample_the_same_points():
    """A smooth image: both 4-parameter layers agree up to interpolation error."""
    n, m = 48, 24
    yy, xx = np.mgrid[0:n, 0:n]
    img = 1.0 + np.cos(2 * np.pi * (xx + 2 * yy) / n)
    p = jnp.asarray([[0.4, 0.6, 0.1, -0.2]], jnp.float32)
    a = TRANSFORMS["bilinear_no_skew"](jnp.asarray(img[None], jnp.float32), p, m)
    b = get_transform("chirp_z", "real")(jnp.asarray(img[None], jnp.float32), p, m)
    assert float(jnp.abs(a - b).max()) < 0.02


def test_bilinear_matches_manual_interpolation():
    rng = np.random.default_rng(1)
    img = rng.random((1, 8, 8))
    x = np.array([[[2.25, 5.5], [0.0, 6.75]]])
    y = np.array([[[3.5, 1.25], [7.0, 0.5]]])
    out = np.asarray(bilinear_sample(jnp.asarray(img), jnp.asarray(x), jnp.asarray(y)))
    for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)]:
        xx, yy = x[0, i, j], y[0, i, j]
        x0, y0 = int(np.floor(xx)), int(np.floor(yy))
        fx, fy = xx - x0, yy - y0
        g = lambda r, c: img[0, r, c] if 0 <= r < 8 and 0 <= c < 8 else 0.0
        ref = ((1 - fx) * (1 - fy) * g(y0, x0) + fx * (1 - fy) * g(y0, x0 + 1)
               + (1 - fx) * fy * g(y0 + 1, x0) + fx * fy * g(y0 + 1, x0 + 1))
        assert out[0, i, j] == pytest.approx(ref, abs=1e-6)


def test_out_of_range_samples_read_zero():
    img = jnp.ones((1, 10, 10))
    x = jnp.asarray([[[-3.0, 12.0, -0.5, 4.0, 9.5]]])
    y = jnp.asarray([[[4.0, 4.0, 4.0, 20.0, 2.0]]])
    out = np.asarray(bilinear_sample(img, x, y))[0, 0]
    # fully outside -> 0 (clamping would give 1); half outside -> 0.5
    np.testing.assert_allclose(out, [0.0, 0.0, 0.5, 0.0, 0.5], atol=1e-7)
    # a translation of the whole grid off the image gives an empty output
    p = jnp.asarray([[1.0, 0.0, 3.0, 0.0, 1.0, 0.0]])
    assert float(jnp.abs(TRANSFORMS["bilinear"](img, p, 10)).max()) == 0.0


def test_bilinear_translation_by_whole_pixels():
    rng = np.random.default_rng(2)
    n = 9
    img = rng.random((1, n, n))
    step = 2.0 / (n - 1)  # one pixel in normalised units
    p = jnp.asarray([[1.0, 0.0, 2 * step, 0.0, 1.0, -1 * step]])
    out = np.asarray(TRANSFORMS["bilinear"](jnp.asarray(img), p, n))[0]
    ref = np.zeros((n, n))
    ref[1:, : n - 2] = img[0, : n - 1, 2:]
    np.testing.assert_allclose(out, ref, atol=1e-6)


def test_no_skew_matrix():
    a = np.asarray(no_skew_to_affine(jnp.asarray([[np.pi / 2, 2.0, 0.3, -0.1]])))[0]
    np.testing.assert_allclose(a, [[0.0, -2.0, 0.3], [2.0, 0.0, -0.1]], atol=1e-6)
    x, y = affine_grid(jnp.asarray(a[None]), 5, 3)
    assert x.shape == (1, 3, 3)


def test_bilinear_gradients_finite_differences():
    with enable_x64():
        rng = np.random.default_rng(3)
        img = jnp.asarray(rng.random((1, 12, 12)))
        w = jnp.asarray(rng.normal(size=(1, 6, 6)))
        p6 = jnp.asarray([[0.83, 0.1, 0.05, -0.07, 0.9, 0.12]])
        p4 = jnp.asarray([[0.3, 0.71, 0.13, -0.08]])
        for name, p in (("bilinear", p6), ("bilinear_no_skew", p4), ("chirp_z", p4)):
            t = TRANSFORMS[name]
            check_grads(lambda i, q: jnp.sum(w * t(i, q, 6)), (img, p), order=1, modes=["rev"],
                        atol=1e-5, rtol=1e-5, eps=1e-6)


@pytest.mark.parametrize("output", ["abs", "real"])
@pytest.mark.parametrize("name", ["bilinear_no_skew", "chirp_z"])
def test_crops_equal_the_layer_on_repeated_images(name, output):
    """Transform.crops (RNN-SPN's T crops per canvas; the chirp-Z layer computes each
    canvas's spectrum once) equals the layer applied to the canvas repeated T times."""
    rng = np.random.default_rng(3)
    b, t_steps, n, m = 2, 3, 20, 10
    img = jnp.asarray(rng.random((b, n, n)), jnp.float32)
    p = np.column_stack([rng.uniform(-0.5, 0.5, b * t_steps), rng.uniform(0.6, 1.2, b * t_steps),
                         rng.uniform(-0.3, 0.3, (b * t_steps, 2))])
    p = jnp.asarray(p, jnp.float32).reshape(b, t_steps, 4)
    t = get_transform(name, output)
    if name == "chirp_z":
        assert t.apply_crops is not None
    crops = jax.jit(t.crops, static_argnums=2)(img, p, m)
    want = jax.jit(t.apply, static_argnums=2)(jnp.repeat(img, t_steps, axis=0),
                                              p.reshape(b * t_steps, 4), m)
    assert crops.shape == (b * t_steps, m, m)
    np.testing.assert_allclose(np.asarray(crops), np.asarray(want), rtol=1e-6, atol=1e-6)
    # sample-major: crop t of image b sits at b * T + t and differs from the other crops
    assert float(jnp.abs(crops[0] - crops[1]).max()) > 1e-3
    one = t.apply(img[1:2], p[1, 2:3], m)
    np.testing.assert_allclose(np.asarray(crops[5]), np.asarray(one[0]), rtol=1e-5, atol=1e-5)
    # the gradient with respect to the parameters flows through the shared spectrum alike
    ct = jnp.asarray(rng.standard_normal(crops.shape), jnp.float32)
    g = jax.grad(lambda p: jnp.sum(t.crops(img, p, m) * ct))(p)
    g_want = jax.grad(lambda p: jnp.sum(t.apply(jnp.repeat(img, t_steps, axis=0),
                                                p.reshape(b * t_steps, 4), m) * ct))(p)
    np.testing.assert_allclose(np.asarray(g), np.asarray(g_want), rtol=1e-5, atol=1e-5)
