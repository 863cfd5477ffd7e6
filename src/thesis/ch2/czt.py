"""The spatial chirp-Z transform layer (thesis §2.2-§2.4, Alg. 2.1).

An image is resampled on a rotated, scaled and translated square grid using only FFTs
and elementwise products (Bluestein's chirp-Z algorithm). The value at a sample point is
the band-limited (periodic, trigonometric) interpolant of the image, i.e. the "perfect
reconstruction" of §2.2 ("sinc interpolation").

Geometry (pixel units, rows = y, columns = x). Output pixel (i, j), i, j = 0..M-1, is
sampled at

    x_ij = c + x0 + Δ (cos θ (j - m) - sin θ (i - m))
    y_ij = c + y0 + Δ (sin θ (j - m) + cos θ (i - m)),   c = (N-1)/2,  m = (M-1)/2,

which is §2.3's (x_pq, y_pq) with the rotation centre placed at the centre of the output
grid: (x0, y0) is the offset of the crop centre from the image centre, θ the rotation
[rad], Δ the distance between neighbouring output pixels measured in input pixels.
θ = +90° gives ``np.rot90(image, 1)``.

Derivation (eq. 2.1 and §2.3's reconstruction). With F = FFT2(I) and centred frequency
vectors k = (k_y, k_x), the interpolant at the grid is
g(n) = N^-2 Σ_k F_k e^{2πi k·o/N} e^{2πi kᵀ M n}, n = (i, j), o the sample at n = 0 and
M = (Δ/N) [[cos θ, sin θ], [-sin θ, cos θ]]. Indexing the output transposed, n' = (j, i),
turns M into the symmetric M' = (Δ/N) [[sin θ, cos θ], [cos θ, -sin θ]], and with
Q(v) = vᵀ M' v (the exponent of Alg. 2.1's B) the identity
kᵀ M' n' = (Q(k) + Q(n') - Q(n' - k)) / 2 (the substitution under eq. 2.1) gives

    g = N^-2 · C ∘ ((h ∘ A) ⋆ B),  h = F ∘ P (translation phase, Alg. 2.1 line 5),
    A = e^{iπQ(k)},  B = e^{-iπQ(·)},  C = e^{iπQ(n')}.

Deviation from Alg. 2.1 as printed, on purpose: the convolution ⋆ is the *linear*
convolution of §2.3's sum. Alg. 2.1 evaluates it as an N-point circular convolution,
which wraps the (non-periodic) chirp around and is not equal to eq. 2.1; we zero-pad to
L >= K + M - 1 points (K kept frequencies), the standard Bluestein construction (Rabiner,
Schafer and Rader 1969), so that the FFT route equals the direct sum to rounding error.
Cost: O(L² log L) per image, i.e. O(n² log n) (§2.4).

Down-sampling (§2.4): "removing the higher frequencies of FFT(I) before transforming":
only the K = M central frequencies (per axis) of FFT(I) are kept (ideal low-pass at the
output's Nyquist rate for Δ = N/M), which also makes the transform cost O(M² log M).

Output: the interpolant of a real image is real; ``output="real"`` returns its real part
(which also symmetrises the Nyquist term of even sizes), ``output="abs"`` returns
|D| / N² exactly as Alg. 2.1 line 8.
"""

from __future__ import annotations

import functools

import jax.numpy as jnp
import numpy as np
from jax import Array, lax

__all__ = ["chirpz_resample", "direct_resample", "fast_len", "sample_grid"]


def fast_len(n: int) -> int:
    """Smallest 5-smooth integer >= n (a length the FFT handles fast)."""
    m = max(int(n), 1)
    while True:
        r = m
        for p in (2, 3, 5):
            while r % p == 0:
                r //= p
        if r == 1:
            return m
        m += 1


def _cis(angle: Array) -> Array:
    """exp(i angle) for a real array, built with lax.complex (no implicit dtype promotion)."""
    return lax.complex(jnp.cos(angle), jnp.sin(angle))


def _centred(k: int) -> Array:
    """Centred frequency (or index) values of an fftshift-ed axis of length k."""
    return jnp.arange(k) - k // 2


def _crop_spectrum(spec: Array, k: int) -> Array:
    """fftshift the last two axes of ``spec`` (..., N, N) and keep the central k x k block."""
    n = spec.shape[-1]
    s = jnp.fft.fftshift(spec, axes=(-2, -1))
    start = n // 2 - k // 2
    return s[..., start : start + k, start : start + k]


@functools.lru_cache(maxsize=64)
def _index_grids(k: int, m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The index vectors of Alg. 2.1 that depend on the sizes only (trace-time constants).

    Returns:
        kk (K,): centred frequencies; lag (L,): lags τ - (K - 1) + K//2, τ = 0..L-1, of
        the chirp B on the zero-padded length L = fast_len(K + M - 1) (only
        τ <= K + M - 2 is ever read); nn (M,): output indices. All float64 integers (exact).
    """
    big = fast_len(k + m - 1)
    kk = np.arange(k, dtype=np.float64) - k // 2
    lag = np.arange(big, dtype=np.float64) - (k - 1) + k // 2
    nn = np.arange(m, dtype=np.float64)
    for v in (kk, lag, nn):
        v.flags.writeable = False
    return kk, lag, nn


def sample_grid(n: int, m: int, x0, y0, theta, delta) -> tuple[Array, Array]:
    """Input-pixel coordinates (x, y) of the M x M output grid (module docstring geometry).

    Args:
        n: input size N; m: output size M.
        x0, y0, theta, delta: arrays of shape (B,) (pixels, pixels, radians, pixels).

    Returns:
        x, y: arrays (B, M, M), x_ij and y_ij in input pixels.
    """
    theta = jnp.asarray(theta)
    dt = theta.dtype if jnp.issubdtype(theta.dtype, jnp.floating) else jnp.float32
    theta = theta.astype(dt)
    c = (n - 1) / 2.0
    u = jnp.arange(m, dtype=dt) - (m - 1) / 2.0
    cos = jnp.cos(theta)[:, None, None]
    sin = jnp.sin(theta)[:, None, None]
    d = jnp.asarray(delta, dt)[:, None, None]
    uj = u[None, None, :]
    vi = u[None, :, None]
    x = c + jnp.asarray(x0, dt)[:, None, None] + d * (cos * uj - sin * vi)
    y = c + jnp.asarray(y0, dt)[:, None, None] + d * (sin * uj + cos * vi)
    return x, y


def chirpz_resample(
    images: Array,
    x0: Array,
    y0: Array,
    theta: Array,
    delta: Array,
    out_size: int | None = None,
    n_freq: int | None = None,
    output: str = "real",
    crops_per_image: int = 1,
) -> Array:
    """Resample square images on a rotated/scaled/translated grid with the chirp-Z transform.

    Implements Alg. 2.1 (thesis §2.4) with a zero-padded (exact) Bluestein convolution;
    see the module docstring for the geometry and the derivation. Batched, jit-able and
    differentiable with respect to ``images`` and the four parameters.

    Args:
        images: (B, N, N) real images (any intensity unit; the output has the same unit).
        x0, y0: (B T,) offset of the output grid's centre from the image centre [input px].
        theta: (B T,) rotation [rad].
        delta: (B T,) spacing of output pixels [input px] (Δ of §2.3).
        out_size: output size M (default N). Down-sampling by d means M = N // d.
        n_freq: number of central frequencies kept per axis before transforming
            (default ``min(M, N)``: the §2.4 down-sampling low-pass).
        output: ``"real"`` (real part of the interpolant) or ``"abs"`` (Alg. 2.1's |D|).
        crops_per_image: T, the number of grids sampled from every image: entry b T + t
            of the parameters (and of the result) is crop t of image b. The image's
            spectrum (Alg. 2.1 line 1) is computed once and shared by its T crops.

    Returns:
        (B T, M, M) resampled images.
    """
    n = images.shape[-1]
    if images.shape[-2] != n:
        raise ValueError(f"chirp-Z layer needs square images, got {images.shape}")
    m = n if out_size is None else int(out_size)
    k = min(m, n) if n_freq is None else int(n_freq)
    if not 1 <= k <= n:
        raise ValueError(f"n_freq must be in [1, {n}], got {k}")
    if output not in ("real", "abs"):
        raise ValueError(f"output must be 'real' or 'abs', got {output!r}")
    images = jnp.asarray(images)
    real_dtype = images.dtype if jnp.issubdtype(images.dtype, jnp.floating) else jnp.float32
    cplx = jnp.complex128 if real_dtype == jnp.float64 else jnp.complex64
    theta = jnp.asarray(theta, real_dtype)
    delta = jnp.asarray(delta, real_dtype)
    x0 = jnp.asarray(x0, real_dtype)
    y0 = jnp.asarray(y0, real_dtype)

    cos = jnp.cos(theta)[:, None, None]
    sin = jnp.sin(theta)[:, None, None]
    dn = (delta / n)[:, None, None]

    # sample position of output pixel (0, 0): the translation of Alg. 2.1's P
    c = (n - 1) / 2.0
    h = (m - 1) / 2.0
    ox = c + x0 + delta * (-jnp.cos(theta) * h + jnp.sin(theta) * h)
    oy = c + y0 + delta * (-jnp.sin(theta) * h - jnp.cos(theta) * h)

    spec = _crop_spectrum(jnp.fft.fft2(images.astype(real_dtype)), k).astype(cplx)
    if crops_per_image != 1:
        spec = jnp.repeat(spec, int(crops_per_image), axis=0)
    kk, lag, nn = (v.astype(real_dtype) for v in _index_grids(k, m))
    ky = kk[None, :, None]
    kx = kk[None, None, :]

    def quad(v1, v2):  # Q(v) = vᵀ M' v, v = (v1, v2) in the transposed (x-first) order
        return dn * (sin * v1**2 + 2.0 * cos * v1 * v2 - sin * v2**2)

    # h ∘ A, indexed [k_y, k_x]; the convolution runs over (k_x, k_y) -> (j, i) after the
    # transpose, so A is evaluated at v = (k_y, k_x) and the output at n' = (j, i).
    phase = 2.0 * jnp.pi * (ky * oy[:, None, None] + kx * ox[:, None, None]) / n
    a_chirp = jnp.pi * quad(ky, kx)
    u = spec * _cis(phase + a_chirp)

    big = lag.shape[0]
    b_chirp = _cis(-jnp.pi * quad(lag[None, :, None], lag[None, None, :]))
    conv = jnp.fft.ifft2(
        jnp.fft.fft2(u, s=(big, big)) * jnp.fft.fft2(b_chirp), axes=(-2, -1)
    )
    out = conv[..., k - 1 : k - 1 + m, k - 1 : k - 1 + m]
    c_chirp = _cis(jnp.pi * quad(nn[None, :, None], nn[None, None, :]))
    g = jnp.swapaxes(out * c_chirp, -1, -2) / (n * n)
    return jnp.real(g) if output == "real" else jnp.abs(g)


def direct_resample(images, x0, y0, theta, delta, out_size=None, n_freq=None, output="real"):
    """Slow reference: evaluate the band-limited interpolant directly at every sample point.

    This is eq. 2.1 with §2.3's reconstruction written as an explicit O(M² K²) sum over the
    kept centred frequencies (no chirp, no convolution), in NumPy-compatible jnp code; used
    by the tests as the oracle for :func:`chirpz_resample`. Same arguments and result.
    """
    n = images.shape[-1]
    m = n if out_size is None else int(out_size)
    k = min(m, n) if n_freq is None else int(n_freq)
    spec = _crop_spectrum(jnp.fft.fft2(images), k)
    x, y = sample_grid(n, m, jnp.asarray(x0), jnp.asarray(y0), jnp.asarray(theta), jnp.asarray(delta))
    kk = _centred(k).astype(x.dtype)
    ey = _cis(2 * jnp.pi * kk[None, None, None, :] * y[..., None] / n)  # (B,M,M,K)
    ex = _cis(2 * jnp.pi * kk[None, None, None, :] * x[..., None] / n)
    g = jnp.einsum("bpq,bijp,bijq->bij", spec, ey, ex) / (n * n)
    return jnp.real(g) if output == "real" else jnp.abs(g)
