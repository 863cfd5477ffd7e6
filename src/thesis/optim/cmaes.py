"""CMA-ES adapter over pycma with the same batched ask/tell interface as the PSO.

The thesis names CMA-ES as the alternative it did not use (§4.3) and as the baseline of
chapter 7; this adapter lets both be run with the same batched evaluation as
:mod:`thesis.optim.pso`::

    state = cmaes_init(seed, x0, sigma0, lower, upper, popsize=20)
    x = ask(state)                 # (popsize, d), inside the bounds
    state = tell(state, fitness)   # fitness (popsize,), MAXIMISED

pycma minimises, so ``tell`` passes ``-fitness`` (NaN fitness counts as ``-inf``, i.e.
the worst). Options fixed for reproducibility (pycma's defaults are not): an explicit
``seed``, ``verbose=-9`` and ``verb_log=0`` (nothing printed, no ``outcmaes/`` files), and a fixed
``popsize`` so that every generation has the same batch shape. Bounds use pycma's
``BoundTransform`` (``bounds=[lower, upper]``), so asked points are always feasible.

The underlying ``cma.CMAEvolutionStrategy`` object is mutable: ``tell`` updates it in
place and returns the same state object (unlike the pure PSO ``tell``).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Callable

import numpy as np

from thesis.optim.pso import History, history_from


@dataclasses.dataclass
class CMAState:
    """CMA-ES state.

    Attributes:
        es: the ``cma.CMAEvolutionStrategy``.
        x: (popsize, d) the last asked generation (None until :func:`ask`).
        generation: number of ``tell`` calls so far.
    """

    es: Any
    x: np.ndarray | None = None
    generation: int = 0


def cmaes_init(
    seed: int,
    x0: Any,
    sigma0: float,
    lower: Any = None,
    upper: Any = None,
    popsize: int | None = None,
    **options: Any,
) -> CMAState:
    """Create a seeded, silent CMA-ES.

    Args:
        seed: integer seed (> 0 is used as is; 0 is mapped to 1 because pycma treats
            seed 0 as "seed from time").
        x0: (d,) initial mean; sigma0: initial step size (same units as x0).
        lower, upper: optional (d,) bounds.
        popsize: fixed population size λ (default: pycma's 4 + 3 ln d).
        **options: further ``cma.CMAOptions`` (e.g. ``CMA_diagonal``).
    """
    import cma

    opts = {"seed": int(seed) if int(seed) != 0 else 1, "verbose": -9, "verb_log": 0,
            "verb_disp": 0, "verb_filenameprefix": "", "maxiter": np.inf, "maxfevals": np.inf,
            "tolfun": 0.0, "tolx": 0.0, "tolfunhist": 0.0, "tolstagnation": np.inf}
    if lower is not None or upper is not None:
        lo = None if lower is None else list(np.asarray(lower, dtype=np.float64))
        up = None if upper is None else list(np.asarray(upper, dtype=np.float64))
        opts["bounds"] = [lo, up]
    if popsize is not None:
        opts["popsize"] = int(popsize)
    opts.update(options)
    es = cma.CMAEvolutionStrategy(list(np.asarray(x0, dtype=np.float64)), float(sigma0), opts)
    return CMAState(es=es)


def ask(state: CMAState) -> np.ndarray:
    """Ask for one generation, shape (popsize, d); asking twice re-asks a new batch."""
    state.x = np.asarray(state.es.ask(), dtype=np.float64)
    return state.x.copy()


def tell(state: CMAState, fitness: Any) -> CMAState:
    """Give the (popsize,) fitness (maximised) of the last :func:`ask`."""
    if state.x is None:
        raise RuntimeError("tell() before ask()")
    f = np.asarray(fitness, dtype=np.float64).reshape(-1)
    if f.shape[0] != state.x.shape[0]:
        raise ValueError(f"fitness must have shape ({state.x.shape[0]},), got {f.shape}")
    cost = np.where(np.isnan(f), np.inf, -f)
    state.es.tell(list(state.x), list(cost))
    state.x = None
    state.generation += 1
    return state


def run_cmaes(
    fitness_fn: Callable[[np.ndarray], Any],
    seed: int,
    x0: Any,
    sigma0: float,
    n_generations: int,
    lower: Any = None,
    upper: Any = None,
    popsize: int | None = None,
    **options: Any,
) -> tuple[History, CMAState]:
    """Run CMA-ES for ``n_generations`` batched generations.

    Args:
        fitness_fn: (popsize, d) -> (popsize,) fitness, maximised.
        seed, x0, sigma0, lower, upper, popsize, **options: as :func:`cmaes_init`.

    Returns:
        (History, final CMAState), with the same fields as the PSO history.
    """
    state = cmaes_init(seed, x0, sigma0, lower, upper, popsize, **options)
    xs, fs = [], []
    for _ in range(int(n_generations)):
        x = ask(state)
        f = np.asarray(fitness_fn(x), dtype=np.float64).reshape(-1)
        xs.append(x)
        fs.append(f)
        state = tell(state, f)
    return history_from(xs, fs), state
