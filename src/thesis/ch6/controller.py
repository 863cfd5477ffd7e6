"""The embodied controller of §6.3: a fixed random tanh layer (ELM), a delay buffer and a
linear readout trained online by recursive least squares (Fig. 6.3).

Signals, per controller step of Δt (§6.3.2-6.3.3):

* ``x`` (8,): the normalised hip and knee encoders;
* ``x_nl = tanh(W_hidden x + w_bias)`` (H,): the hidden layer, W_hidden and w_bias drawn
  from the standard normal distribution and never trained (:func:`draw_hidden`);
* ``x_rls = [x_nl(t); x_nl(t - Δt); ...; x_nl(t - B Δt); 1]`` (N,), N = (B + 1) H + 1
  (:func:`push_buffer`, :func:`features`);
* ``y_hat = W_rls x_rls`` (12,), W_rls learned by RLS with P(0) = I, W(0) = 0 and no
  forgetting factor (:func:`rls_init`, :func:`rls_update`).

Padding, so that a sweep over H and B compiles once: the hidden layer has ``H_max`` rows
and the buffer ``S = B_max + 1`` slots; a run masks the hidden units beyond its H
(``hidden_mask``) and the slots beyond its B + 1 (``slot_mask``). A masked entry of
``x_rls`` is exactly 0, so RLS never moves the padded rows and columns of P (they stay
those of the identity) or the padded columns of W (they stay 0): the learned outputs are
those of the unpadded controller (tested). The same mechanism gives the linear feedback
of §6.3.1 (``identity=True``: ``x_nl`` is ``x`` itself, no hidden layer).

All functions are pure ``jnp`` for one run (``jax.vmap`` over runs), except
:func:`draw_hidden` (NumPy, host side).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

#: Number of encoder inputs (hip and knee of four legs, §6.2).
N_INPUTS = 8
#: Number of motor outputs (scapula, hip and knee of four legs, §6.5 "12 independent
#: outputs").
N_OUTPUTS = 12


def draw_hidden(rng: np.random.Generator, n_hidden: int, n_inputs: int = N_INPUTS):
    """Random hidden layer of §6.3.3: W_hidden (n_hidden, n_inputs) and w_bias (n_hidden,).

    Both standard normal ("we initialize all elements in the matrix W_hidden and the
    vector w_bias by sampling them from the standard normal distribution"). Row k is drawn
    after rows 0 .. k-1, so the first H rows of a draw of ``n_hidden`` >= H units equal a
    draw of H units from the same generator state: configurations of a sweep over H share
    their first units (common random numbers, tested).
    """
    wb = rng.standard_normal((int(n_hidden), int(n_inputs) + 1))
    return wb[:, :n_inputs], wb[:, n_inputs]


def hidden_layer(x, w_hidden, w_bias, hidden_mask, identity):
    """``x_nl`` (H_max,) of §6.3.3 for normalised inputs ``x`` (8,).

    ``hidden_mask`` (H_max,) is 1 for the run's H units and 0 for padding; ``identity``
    (scalar bool) replaces the layer by ``x`` itself (the first 8 entries; the linear
    feedback of §6.3.1, which needs H_max >= 8 and a mask of 8 ones).
    """
    pre = w_hidden @ x + w_bias
    h, n = w_bias.shape[0], x.shape[0]
    x_pad = jnp.concatenate([x, jnp.zeros((h - n,), x.dtype)]) if h >= n else x[:h]
    return jnp.where(identity, x_pad, jnp.tanh(pre)) * hidden_mask


def push_buffer(buffer, x_nl):
    """Delay buffer (S, H_max) after pushing ``x_nl``: row j holds x_nl(t - j Δt)."""
    return jnp.concatenate([x_nl[None], buffer[:-1]], axis=0)


def features(buffer, slot_mask):
    """``x_rls`` (S H_max + 1,): the masked buffer, flattened slot by slot, and a constant 1
    (the bias, §6.3.2 "we add a constant signal to the inputs")."""
    flat = (buffer * slot_mask[:, None]).reshape(-1)
    return jnp.concatenate([flat, jnp.ones((1,), flat.dtype)])


def n_signals(n_hidden: int, n_buffer: int) -> int:
    """N = (B + 1) H + 1: the number of signals the RLS readout receives (§6.4)."""
    return (int(n_buffer) + 1) * int(n_hidden) + 1


def rls_init(n_features: int, n_outputs: int = N_OUTPUTS, dtype=jnp.float32):
    """(W (n_outputs, n_features) = 0, P (n_features, n_features) = I) of §6.3.2."""
    return jnp.zeros((n_outputs, n_features), dtype), jnp.eye(n_features, dtype=dtype)


def rls_update(w, p, x, y):
    """One RLS step of §6.3.2 without forgetting factor.

    ``L = P x / (1 + x^T P x)``, ``P <- P - P x x^T P / (1 + x^T P x)``,
    ``e = y - W x`` (a priori), ``W <- W + e L^T``.

    P stays exactly symmetric in floating point: with u = P x and v = u / sqrt(1 + x^T u)
    the update is P - v v^T, whose (i, j) and (j, i) entries are the same product.

    Args:
        w: (M, N) readout; p: (N, N) inverse correlation ("precision") matrix.
        x: (N,) features; y: (M,) targets.
    Returns:
        (w, p, e): updated readout and matrix and the a priori error e (M,).
    """
    u = p @ x
    denom = 1.0 + x @ u
    e = y - w @ x
    gain = u / denom
    v = u / jnp.sqrt(denom)
    return w + jnp.outer(e, gain), p - jnp.outer(v, v), e
