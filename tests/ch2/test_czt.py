"""Tests of the chirp-Z transform layer (thesis §2.3-§2.4, Alg. 2.1)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.signal
from jax import enable_x64
from jax.test_util import check_grads

from thesis.ch2.czt import chirpz_resample, direct_resample, fast_len, sample_grid


@pytest.fixture
def x64():
    with enable_x64():
        yield


def _eq21_oracle(image, x0, y0, theta, delta, m, k):
    """Eq. 2.1 + §2.3's reconstruction from scratch in NumPy: explicit DFT, explicit sum."""
    n = image.shape[0]
    idx = np.arange(n)
    dft = np.exp(-2j * np.pi * np.outer(idx, idx) / n)
    spec = dft @ image @ dft.T  # FFT2 by definition
    freqs = np.arange(k) - k // 2
    sel = freqs % n
    spec = spec[np.ix_(sel, sel)]
    c, h = (n - 1) / 2, (m - 1) / 2
    out = np.zeros((m, m), complex)
    for i in range(m):
        for j in range(m):
            x = c + x0 + delta * (np.cos(theta) * (j - h) - np.sin(theta) * (i - h))
            y = c + y0 + delta * (np.sin(theta) * (j - h) + np.cos(theta) * (i - h))
            out[i, j] = np.sum(
                spec * np.exp(2j * np.pi * (freqs[:, None] * y + freqs[None, :] * x) / n)
            )
    return np.real(out) / n**2


def test_fast_len():
    assert fast_len(97) == 100
    assert fast_len(7) == 8
    assert fast_len(1) == 1


def test_identity_returns_image():
    rng = np.random.default_rng(0)
    img = rng.random((3, 20, 20)).astype(np.float32)
    z = jnp.zeros(3)
    out = jax.jit(chirpz_resample)(jnp.asarray(img), z, z, z, jnp.ones(3))
    assert out.dtype == jnp.float32
    np.testing.assert_allclose(np.asarray(out), img, atol=2e-5)


def test_rot90_of_bandlimited_image(x64):
    n = 24
    yy, xx = np.mgrid[0:n, 0:n]
    img = (
        1.0
        + np.cos(2 * np.pi * 2 * xx / n + 0.3)
        + 0.5 * np.sin(2 * np.pi * (3 * yy + xx) / n)
        + 0.2 * np.cos(2 * np.pi * 5 * yy / n)
    )
    z = jnp.zeros(1)
    out = chirpz_resample(jnp.asarray(img[None]), z, z, jnp.full(1, np.pi / 2), jnp.ones(1))
    np.testing.assert_allclose(np.asarray(out[0]), np.rot90(img, 1), atol=1e-10)
    out = chirpz_resample(jnp.asarray(img[None]), z, z, jnp.full(1, -np.pi / 2), jnp.ones(1))
    np.testing.assert_allclose(np.asarray(out[0]), np.rot90(img, -1), atol=1e-10)
    # and it is not the identity (the test can fail)
    assert np.abs(np.asarray(out[0]) - img).max() > 0.1


@pytest.mark.parametrize("shift", [(3, -2), (-5, 7), (0, 11)])
def test_integer_translation_is_circular_shift(x64, shift):
    rng = np.random.default_rng(1)
    img = rng.random((1, 16, 16))
    dx, dy = shift
    out = chirpz_resample(
        jnp.asarray(img), jnp.full(1, float(dx)), jnp.full(1, float(dy)), jnp.zeros(1), jnp.ones(1)
    )
    np.testing.assert_allclose(
        np.asarray(out[0]), np.roll(img[0], (-dy, -dx), axis=(0, 1)), atol=1e-10
    )


@pytest.mark.parametrize("n,m,k", [(16, 16, 16), (15, 15, 15), (16, 8, 8), (17, 9, 9), (12, 20, 12), (16, 10, 6)])
def test_random_parameters_match_direct_eq21(x64, n, m, k):
    rng = np.random.default_rng(n * 100 + m)
    img = rng.random((2, n, n))
    x0, y0 = rng.normal(size=2) * 3, rng.normal(size=2) * 3
    theta, delta = rng.uniform(-np.pi, np.pi, 2), rng.uniform(0.4, 2.5, 2)
    fast = np.asarray(chirpz_resample(jnp.asarray(img), x0, y0, theta, delta, out_size=m, n_freq=k))
    for b in range(2):
        ref = _eq21_oracle(img[b], x0[b], y0[b], theta[b], delta[b], m, k)
        np.testing.assert_allclose(fast[b], ref, atol=1e-11)
    slow = np.asarray(direct_resample(jnp.asarray(img), x0, y0, theta, delta, out_size=m, n_freq=k))
    np.testing.assert_allclose(fast, slow, atol=1e-11)


def test_abs_output_is_modulus_of_interpolant(x64):
    rng = np.random.default_rng(5)
    img = rng.random((1, 12, 12))
    args = (jnp.asarray(img), jnp.full(1, 0.7), jnp.full(1, -1.3), jnp.full(1, 0.4), jnp.full(1, 0.8))
    a = np.asarray(chirpz_resample(*args, output="abs"))
    r = np.asarray(chirpz_resample(*args, output="real"))
    assert np.all(a >= np.abs(r) - 1e-12)
    np.testing.assert_allclose(a, np.asarray(direct_resample(*args, output="abs")), atol=1e-11)


def test_axis_aligned_case_equals_scipy_czt(x64):
    """θ = 0: along x, the layer is a 1-D CZT of the (translated) spectrum rows."""
    rng = np.random.default_rng(2)
    n, m, delta, x0 = 16, 11, 0.7, 1.9
    row = rng.random(n)
    # the image is constant along y, so only the x-axis CZT remains
    flat = np.tile(row, (n, 1))
    out = np.asarray(
        chirpz_resample(jnp.asarray(flat[None]), jnp.full(1, x0), jnp.zeros(1), jnp.zeros(1),
                        jnp.full(1, delta), out_size=m, n_freq=n)
    )[0]
    spec = np.fft.fftshift(np.fft.fft(row))
    freqs = np.arange(n) - n // 2
    ox = (n - 1) / 2 + x0 - delta * (m - 1) / 2
    xin = spec * np.exp(2j * np.pi * freqs * ox / n)
    w = np.exp(2j * np.pi * delta / n)
    ref = scipy.signal.czt(xin, m=m, w=w, a=1.0)
    ref = np.real(ref * np.exp(-2j * np.pi * (n // 2) * delta * np.arange(m) / n)) / n
    for i in range(m):
        np.testing.assert_allclose(out[i], ref, atol=1e-11)


def test_downsampling_is_perfect_for_bandlimited_image(x64):
    """§2.2: a band-limited image is reconstructed perfectly, also when down-sampling."""
    n, m = 32, 16
    f = lambda x, y: 0.5 + np.cos(2 * np.pi * (2 * x + y) / n + 0.2) + 0.3 * np.sin(2 * np.pi * 3 * y / n)
    yy, xx = np.mgrid[0:n, 0:n]
    img = f(xx, yy)[None]
    params = (jnp.full(1, 2.3), jnp.full(1, -4.1), jnp.full(1, 0.9), jnp.full(1, 1.7))
    out = np.asarray(chirpz_resample(jnp.asarray(img), *params, out_size=m))
    x, y = sample_grid(n, m, *params)
    np.testing.assert_allclose(out[0], f(np.asarray(x[0]), np.asarray(y[0])), atol=1e-10)


def test_jit_and_vmap_consistent():
    rng = np.random.default_rng(3)
    img = jnp.asarray(rng.random((4, 18, 18)), jnp.float32)
    p = [jnp.asarray(rng.normal(size=4), jnp.float32) for _ in range(3)] + [jnp.full(4, 1.2)]
    batched = jax.jit(chirpz_resample, static_argnames=("out_size",))(img, *p, out_size=9)
    single = jnp.stack(
        [chirpz_resample(img[b : b + 1], *[q[b : b + 1] for q in p], out_size=9)[0] for b in range(4)]
    )
    assert batched.shape == (4, 9, 9)
    np.testing.assert_allclose(np.asarray(batched), np.asarray(single), atol=1e-5)


def test_gradients_match_finite_differences(x64):
    rng = np.random.default_rng(4)
    img = jnp.asarray(rng.random((2, 10, 10)))
    w = jnp.asarray(rng.normal(size=(2, 7, 7)))
    params = [jnp.asarray(v) for v in (rng.normal(size=2), rng.normal(size=2),
                                       rng.uniform(-1, 1, 2), rng.uniform(0.6, 1.4, 2))]

    def loss(image, x0, y0, theta, delta):
        return jnp.sum(w * chirpz_resample(image, x0, y0, theta, delta, out_size=7))

    check_grads(loss, (img, *params), order=1, modes=["rev", "fwd"], atol=1e-6, rtol=1e-6)

    def loss_abs(image, x0, y0, theta, delta):
        return jnp.sum(w * chirpz_resample(image + 1.0, x0, y0, theta, delta, out_size=7, output="abs"))

    check_grads(loss_abs, (img, *params), order=1, modes=["rev"], atol=1e-6, rtol=1e-6)
