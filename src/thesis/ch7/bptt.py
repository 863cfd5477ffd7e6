"""Training tricks of §7.3.2 for backpropagation through time, and shared helpers.

The four tricks of §7.3.2: (1) an objective averaged over every time step (done by each
experiment's loss), (2) the gradient decayed by a factor alpha < 1 per time step (the
engine's :func:`thesis.physics.decay_gradient`, the original's ``MulGrad``,
docs/sources.md#tpx-engine), (3) a zero-output initial policy (:mod:`thesis.ch7.nets`), (4) the
gradient's L2 norm clipped to 1 (:func:`make_optimizer`, ``optax.clip_by_global_norm``).

Also: :func:`check_finite` (a non-finite loss or gradient raises
:class:`thesis.errors.SimulationDiverged`), :func:`first_reach` (iterations until a
threshold is crossed), and :func:`timed` (wall time of a blocking JAX call).
"""

from __future__ import annotations

import time

import jax
import numpy as np
import optax

from thesis.errors import SimulationDiverged

__all__ = ["make_optimizer", "check_finite", "first_reach", "timed", "all_finite"]


def make_optimizer(learning_rate: float, clip_norm: float | None, *, b1: float = 0.9,
                   b2: float = 0.999, schedule=None, injectable: bool = False):
    """Adam with the gradient's global L2 norm clipped to ``clip_norm`` first (§7.3.2).

    Args:
        learning_rate: Adam step size (ignored when ``schedule`` is given).
        clip_norm: maximal global L2 norm of the gradient (None: no clipping).
        b1, b2: Adam's moment decay rates.
        schedule: optional ``optax`` schedule ``step -> learning rate``.
        injectable: make the learning rate a hyperparameter that can be set per update
            (``state.hyperparams["learning_rate"]``), for §7.3.2.2's error-scaled rate.
    """
    if injectable:
        adam = optax.inject_hyperparams(optax.adam)(learning_rate=learning_rate, b1=b1, b2=b2)
    else:
        adam = optax.adam(schedule if schedule is not None else learning_rate, b1=b1, b2=b2)
    if clip_norm is None:
        return adam
    return optax.chain(optax.clip_by_global_norm(float(clip_norm)), adam)


def all_finite(tree) -> bool:
    """True when every leaf of ``tree`` is finite (host-side check)."""
    return all(bool(np.all(np.isfinite(np.asarray(x)))) for x in jax.tree.leaves(tree))


def check_finite(tree, experiment: str, seed: int, step: int, what: str) -> None:
    """Raise :class:`SimulationDiverged` unless every value of ``tree`` is finite."""
    if not all_finite(tree):
        raise SimulationDiverged(experiment, seed, step, what)


def first_reach(values, threshold: float) -> tuple[float, bool]:
    """How many evaluations until ``values`` first drops below ``threshold``.

    Args:
        values: (n,) error after evaluation 1, 2, ..., n.
        threshold: the error to reach (strictly below).
    Returns:
        (count, reached): the 1-based index of the first value below the threshold and
        True, or (NaN, False) when it is never reached.
    """
    v = np.asarray(values, dtype=float)
    hit = np.nonzero(v < threshold)[0]
    if hit.size == 0:
        return float("nan"), False
    return float(hit[0] + 1), True


def timed(fn, *args):
    """``(result, seconds)`` of ``fn(*args)``, blocking until JAX has finished."""
    t0 = time.perf_counter()
    out = jax.block_until_ready(fn(*args))
    return out, time.perf_counter() - t0
