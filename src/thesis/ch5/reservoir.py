"""Leaky hidden layers of chapter 5: EMA (eq. 5.2), leaky ELM (§5.2.2), leaky ESN (§5.2.3).

All three are one recursion over time, run independently on every *part* of the data
(each part starts from a zero state; thesis §5.3.1 splits the trials into parts):

* EMA, the low-pass in front of linear regression: ``x(n) = (1-a) x(n-1) + a u(n)``;
* leaky ELM: ``x(n) = (1-a) x(n-1) + a tanh(W_in u(n))``;
* leaky ESN (RC): ``x(n) = (1-a) x(n-1) + a tanh(W_res x(n-1) + W_in u(n))``.

Inputs are padded arrays ``u`` of shape (P, T, K) (P parts, T the longest part, K
inputs) with ``lengths`` (P,); outputs (P, T, N) hold garbage after each part's length,
which every consumer masks (:func:`thesis.ch5.protocol.valid_mask`). The linear
recursions run as IIR filters (``scipy.signal.lfilter``); the ESN runs a loop over time
whose batch shrinks to the parts still running (parts sorted by length), in float64,
time-major and in place. tanh is :func:`tanh` (exp-based, float64, faster than numpy's).

Weights (§5.2.2-5.2.3): ``W_in`` entries uniform on {-1, 0, 1} times the input scaling
(for the ELM and the ESN alike, so the two differ only by ``W_res``); ``W_res`` standard
normal, rescaled to spectral radius ``sigma``. No bias inside the tanh (the thesis's
equations have none; the readout has one).
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

__all__ = ["input_weights", "reservoir_weights", "tanh", "ema", "elm_states", "esn_states"]


def input_weights(rng: np.random.Generator, n_nodes: int, n_inputs: int) -> np.ndarray:
    """(n_nodes, n_inputs) unscaled input weights, i.i.d. uniform on {-1, 0, 1} (§5.2.2)."""
    return rng.integers(-1, 2, size=(int(n_nodes), int(n_inputs))).astype(np.float64)


def reservoir_weights(rng: np.random.Generator, n_nodes: int) -> np.ndarray:
    """(n_nodes, n_nodes) standard-normal recurrent weights with spectral radius 1
    (§5.2.3); multiply by sigma for spectral radius sigma."""
    w = rng.standard_normal((int(n_nodes), int(n_nodes)))
    rho = float(np.max(np.abs(np.linalg.eigvals(w))))
    return w / rho


def tanh(z: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """tanh of float64 ``z`` as 1 - 2 / (exp(2 z) + 1), into ``out`` if given (may be ``z``).

    The hidden layers' cost is mostly tanh: numpy's float64 exp is vectorised (SIMD) on
    x86-64 and its tanh is not, so this is 2-4x faster than ``np.tanh``. Absolute error
    below 1e-15 (the relative error of tiny |z| grows, the absolute one does not; every
    consumer adds the result to O(1) states); exp(2 z) overflowing to inf gives 1 exactly.
    """
    z = np.asarray(z, np.float64)
    out = np.empty_like(z) if out is None else out
    np.multiply(z, 2.0, out=out)
    with np.errstate(over="ignore", under="ignore"):
        np.exp(out, out=out)
    out += 1.0
    np.divide(-2.0, out, out=out)
    out += 1.0
    return out


def ema(u: np.ndarray, leak: float) -> np.ndarray:
    """Exponential moving average along axis 1 (time) from a zero state (eq. 5.2).

    Args:
        u: (P, T, K) inputs; leak: a in (0, 1].
    Returns:
        (P, T, K) float64.
    """
    a = float(leak)
    return lfilter([a], [1.0, a - 1.0], np.asarray(u, np.float64), axis=1)


def elm_states(u: np.ndarray, w_in: np.ndarray, leak: float) -> np.ndarray:
    """Leaky ELM hidden states (§5.2.2): EMA of ``tanh(W_in u)``.

    Args:
        u: (P, T, K) inputs; w_in: (N, K) scaled input weights; leak: a in (0, 1].
    Returns:
        (P, T, N) float64.
    """
    h = np.asarray(u, np.float64) @ np.asarray(w_in, np.float64).T
    return ema(tanh(h, out=h), leak)


def esn_states(u: np.ndarray, lengths: np.ndarray, w_in: np.ndarray, w_res: np.ndarray,
               leak: float) -> np.ndarray:
    """Leaky ESN states (§5.2.3), every part from a zero state.

    Args:
        u: (P, T, K) inputs; lengths: (P,) valid steps per part; w_in: (N, K) scaled input
            weights; w_res: (N, N) recurrent weights (already scaled to radius sigma);
            leak: a in (0, 1].
    Returns:
        (P, T, N) float64; steps at or after a part's length are zero.
    """
    u = np.asarray(u, np.float64)
    lengths = np.asarray(lengths, int)
    p, t_max, _ = u.shape
    n = w_in.shape[0]
    order = np.argsort(-lengths, kind="stable")
    # time-major drive and states: each step reads and writes contiguous (k, N) blocks
    drive = np.ascontiguousarray(
        (u[order] @ np.asarray(w_in, np.float64).T).transpose(1, 0, 2))  # (T, P, N)
    ls = lengths[order]
    a = float(leak)
    w_t = np.asarray(w_res, np.float64).T
    out = np.zeros((t_max, p, n))
    x = np.zeros((p, n))
    buf = np.empty((p, n))
    for t in range(int(ls.max()) if p else 0):
        k = int(np.sum(ls > t))  # parts still running (sorted by length)
        xk, bk = x[:k], buf[:k]  # in place: x <- (1 - a) x + a tanh(W x + W_in u)
        np.matmul(xk, w_t, out=bk)
        bk += drive[t, :k]
        tanh(bk, out=bk)
        bk *= a
        xk *= 1.0 - a
        xk += bk
        out[t, :k] = xk
    res = np.empty((p, t_max, n))
    res[order] = out.transpose(1, 0, 2)
    return res
