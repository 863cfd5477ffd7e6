"""CMA-ES over each method's hyper-parameters (thesis §5.2.5).

"To optimize the parameters of the different techniques described above, we use
CMA-ES" (N. Hansen's implementation: pycma, through :mod:`thesis.optim.cmaes`) with the
population size lambda = floor(4 + 3 ln M) for M parameters. The search runs in the unit
cube [0, 1]^M (initial mean 0.5, step size ``sigma0``) and :func:`decode` maps a point to
the parameters through the ranges of the profile (``ch5.search``): ``pca_rate`` linear,
``leak`` and ``input_scaling`` log-uniform, ``spectral_radius`` linear. The objective is
the mean validation accuracy of the threefold cross-validation (maximised); the search
stops after a fixed number of generations (the profile's budget).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np

from thesis.optim import cmaes

__all__ = ["popsize", "decode", "tune"]

#: How each hyper-parameter maps [0, 1] onto its range.
LOG_PARAMS = ("leak", "input_scaling")


def popsize(n_params: int) -> int:
    """lambda = floor(4 + 3 ln M) (§5.2.5)."""
    return int(math.floor(4 + 3 * math.log(n_params)))


def decode(x, names, ranges: Mapping[str, tuple[float, float]]) -> dict[str, float]:
    """Map a point of the unit cube to named parameters (see module docstring)."""
    out = {}
    for v, name in zip(np.clip(np.asarray(x, float), 0.0, 1.0), names):
        lo, hi = (float(b) for b in ranges[name])
        if name in LOG_PARAMS:
            out[name] = float(10 ** (math.log10(lo) + v * (math.log10(hi) - math.log10(lo))))
        else:
            out[name] = float(lo + v * (hi - lo))
    return out


def tune(objective: Callable[[dict], float], names, ranges, *, seed: int, generations: int,
         sigma0: float = 0.3) -> dict:
    """Maximise ``objective(params)`` with CMA-ES.

    Returns:
        dict with ``best`` (parameters), ``best_score``, ``scores`` (generations, lambda),
        ``evaluations`` and ``popsize``.
    """
    names = tuple(names)
    lam = popsize(len(names))
    if len(names) < 2:
        raise ValueError("CMA-ES needs at least two parameters")
    state = cmaes.cmaes_init(seed, np.full(len(names), 0.5), sigma0, np.zeros(len(names)),
                             np.ones(len(names)), popsize=lam)
    best, best_score, scores = None, -np.inf, []
    for _ in range(int(generations)):
        xs = cmaes.ask(state)
        f = np.array([objective(decode(x, names, ranges)) for x in xs], float)
        scores.append(f)
        i = int(np.nanargmax(np.where(np.isfinite(f), f, -np.inf)))
        if f[i] > best_score:
            best, best_score = decode(xs[i], names, ranges), float(f[i])
        state = cmaes.tell(state, f)
    return dict(best=best, best_score=best_score, scores=np.array(scores),
                evaluations=int(generations) * lam, popsize=lam)
