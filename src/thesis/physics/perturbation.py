"""Rounding-level perturbations of simulations: how much of a result is a property of its
seed (issue: "a verdict is fragile when the perturbed rerun moves it").

A closed loop that is chaotic at the rounding level carries a last-bit difference (another
CPU's kernels, another compiler) into a different outcome: a robot that falls or not, a
PSO that keeps another particle, a classifier trained on other recordings. The measure is
a *perturbed twin*: the same computation from a start moved by about one float32 ulp.

* :func:`scale_positions` moves every body position of a state by ``relative * u``
  relative, ``u`` standard normal per coordinate from ``jax.random.key(seed)``; at
  ``relative`` ~1e-7 a coordinate moves by 0, 1 or a few ulp. Chapter 6's twin runs call
  it per run (:mod:`thesis.ch6.twins`).
* A *process-wide* relative size (:func:`set_relative`, :func:`scope`; ``thesis
  --perturb REL``) makes every :func:`thesis.physics.rollout` start from
  :func:`at_start` of its initial state, and lets a chapter perturb its other random
  starting points the same way (:func:`perturb_tree`, e.g. chapter 2's initial network
  weights). With the size 0 (the default) nothing is traced differently: results are
  bit for bit those of an unperturbed run and the compiled programs are the same.

The size is read when a function is traced, so it must be set before the process traces
anything (the command line sets it first). Every :func:`at_start` uses the same ``u`` for
a state of a given shape (key :data:`SEED`): a perturbation, not a new random stream.
"""

from __future__ import annotations

import contextlib

import jax
import jax.numpy as jnp

__all__ = ["SEED", "relative", "set_relative", "scope", "scale_positions", "at_start",
           "perturb_tree"]

#: Key of the process-wide perturbation's ``u``.
SEED = 0

#: The process-wide size: a module global, not a context variable, so that threads that
#: trace (thread pools) see it too.
_RELATIVE = [0.0]


def _check(value: float) -> float:
    value = float(value)
    if not (0.0 <= value <= 1e-3):
        raise ValueError(f"perturbation relative size = {value!r} is not allowed; "
                         "allowed values: 0 (off) to 1e-3 (rounding level is ~1e-7)")
    return value


def relative() -> float:
    """The process-wide relative size of the perturbation (0: none)."""
    return _RELATIVE[0]


def set_relative(value: float) -> None:
    """Set the process-wide relative size (0 to 1e-3) for everything traced from now on."""
    _RELATIVE[0] = _check(value)


@contextlib.contextmanager
def scope(value: float):
    """Context in which the process-wide relative size is ``value`` (tests, one-off runs)."""
    before, _RELATIVE[0] = _RELATIVE[0], _check(value)
    try:
        yield
    finally:
        _RELATIVE[0] = before


def scale_positions(state, relative_size, seed):
    """``state`` with every body's position scaled by ``1 + relative_size * u``, u standard
    normal per coordinate from ``jax.random.key(seed)`` (both may be traced).
    ``relative_size = 0`` returns the positions bit for bit."""
    u = jax.random.normal(jax.random.key(seed), state.pos.shape, state.pos.dtype)
    return state.replace(pos=state.pos + state.pos * (relative_size * u))


def at_start(state):
    """A simulation's initial state under the process-wide perturbation: ``state`` itself
    when it is 0, else :func:`scale_positions` with key :data:`SEED`."""
    r = relative()
    return state if r == 0.0 else scale_positions(state, jnp.asarray(r, state.pos.dtype), SEED)


def perturb_tree(tree, seed: int = SEED):
    """Every floating leaf ``x`` of a pytree as ``x (1 + r u)`` under the process-wide size
    ``r`` (u standard normal, one key per leaf from ``seed``); ``tree`` itself when r = 0.
    For random starting points that are not a simulation state (initial weights)."""
    r = relative()
    if r == 0.0:
        return tree
    leaves, treedef = jax.tree_util.tree_flatten(tree)
    keys = jax.random.split(jax.random.key(seed), max(len(leaves), 1))
    out = []
    for k, x in zip(keys, leaves):
        if jnp.issubdtype(jnp.result_type(x), jnp.floating):
            x = jnp.asarray(x)
            x = x + x * (jnp.asarray(r, x.dtype) * jax.random.normal(k, x.shape, x.dtype))
        out.append(x)
    return jax.tree_util.tree_unflatten(treedef, out)
