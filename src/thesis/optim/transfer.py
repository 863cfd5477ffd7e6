"""Transfer learning for particle swarm optimisation (thesis §4.4) and the comparison of
two optimisation runs generation by generation (§4.6).

Transfer (§4.4): "we take the best 20 particles over all generations from a previous
optimization of a similar problem ... We instead give these particles a small impulse in
a random direction in order to have them start exploring new solutions (r ∈ U(-1, 1))",
``v(0) = r``, ``x(0) = argmax(score(x̃(n)))``. :func:`transfer_init` builds that swarm
with :func:`thesis.optim.pso.best_particles` and :func:`thesis.optim.pso.pso_init`; the
personal and global bests start empty, so the new task's fitness alone steers the swarm.
The impulse is ``r * impulse`` per coordinate, ``impulse`` (d,) in the units of the
parameter vector (:func:`impulse_scale` gives a fraction of each parameter's range).

Lock-step runs (:func:`run_lockstep`): several independent swarms (seeds, arms with and
without transfer) advance one generation at a time, and each generation of all of them is
evaluated by one call, so a caller can simulate it as one batch.

Comparison (§4.6): "we compare the speed of the gaits in each generation using a
Wilcoxon rank-sum test ... Subsequently we combine the obtained p-values using Fisher's
method". :func:`compare_generations` returns the per-generation rank-sum p-values (SciPy's
Mann-Whitney U, which is the rank-sum test), the Vargha-Delaney A (the probability that a
particle of the first run outscores one of the second, ties counted half) and their
Fisher combination.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping
from typing import Any

import numpy as np
from scipy import stats as sps

from thesis.optim.pso import History, PSOState, ask, best_particles, history_from, pso_init, tell


def impulse_scale(lower: Any, upper: Any, divisor: float) -> np.ndarray:
    """(d,) impulse per coordinate: ``(upper - lower) / divisor`` (§4.4's "small impulse")."""
    lower, upper = np.asarray(lower, np.float64), np.asarray(upper, np.float64)
    if divisor <= 0:
        raise ValueError(f"impulse divisor must be > 0, got {divisor}")
    return (upper - lower) / float(divisor)


def transfer_init(key_or_rng: Any, source_positions: Any, source_fitness: Any, n: int,
                  lower: Any, upper: Any, *, impulse: Any,
                  project: Callable[[np.ndarray], np.ndarray] | None = None,
                  **options: Any) -> PSOState:
    """Swarm of the ``n`` best particles of a previous run with a random impulse (§4.4).

    Args:
        key_or_rng: seed, ``np.random.Generator`` or JAX key of the impulse draws.
        source_positions: (G, N, d) every position the previous run evaluated.
        source_fitness: (G, N) their fitness (maximised).
        n: swarm size (the number of particles transferred).
        lower, upper: (d,) box bounds of the new run.
        impulse: scalar or (d,) scale of v(0) = impulse * r, r ~ U(-1, 1)^d.
        project: feasibility map applied to the starting positions after clipping.
        **options: further :func:`thesis.optim.pso.pso_init` options (omega, phi_p,
            phi_g, v_max_fraction, per_dimension).

    Returns:
        The :class:`PSOState` whose ``x`` is the transferred generation 0, best first.
    """
    init = best_particles(source_positions, source_fitness, n)
    return pso_init(key_or_rng, n, lower, upper, init=init, velocity_scale=impulse,
                    project=project, **options)


def run_lockstep(swarms: Mapping[Hashable, PSOState],
                 evaluate: Callable[[int, dict[Hashable, np.ndarray]], Mapping[Hashable, Any]],
                 n_generations: int,
                 project: Callable[[np.ndarray], np.ndarray] | None = None,
                 ) -> dict[Hashable, History]:
    """Advance independent swarms together for ``n_generations`` generations.

    Args:
        swarms: name -> initial :class:`PSOState` (random or :func:`transfer_init`).
        evaluate: ``(generation, {name: (n, d) positions}) -> {name: (n,) fitness}``,
            called once per generation with every swarm's particles (maximised; NaN
            counts as -inf in the swarm update).
        n_generations: number of evaluated generations G.
        project: feasibility map applied after every move (as :func:`tell`).

    Returns:
        name -> :class:`History` of (G, n, d) positions and (G, n) fitness.
    """
    states = dict(swarms)
    xs: dict[Hashable, list] = {k: [] for k in states}
    fs: dict[Hashable, list] = {k: [] for k in states}
    for gen in range(int(n_generations)):
        x = {k: ask(s) for k, s in states.items()}
        f = evaluate(gen, x)
        for k in states:
            fk = np.asarray(f[k], np.float64).reshape(-1)
            xs[k].append(x[k])
            fs[k].append(fk)
            states[k] = tell(states[k], fk, project=project)
    return {k: history_from(xs[k], fs[k]) for k in states}


def vargha_delaney(a: Any, b: Any) -> float:
    """Vargha-Delaney A: P(a > b) + P(a = b)/2 for independent draws of the two samples
    (the Mann-Whitney U of ``a`` divided by its maximum). NaN if a sample is empty."""
    a, b = np.asarray(a, np.float64).ravel(), np.asarray(b, np.float64).ravel()
    a, b = a[~np.isnan(a)], b[~np.isnan(b)]
    if a.size == 0 or b.size == 0:
        return float("nan")
    gt = (a[:, None] > b[None, :]).sum()
    eq = (a[:, None] == b[None, :]).sum()
    return float((gt + 0.5 * eq) / (a.size * b.size))


def _rank_sum(a: np.ndarray, b: np.ndarray, alternative: str) -> float:
    a, b = a[~np.isnan(a)], b[~np.isnan(b)]
    if a.size == 0 or b.size == 0:
        return float("nan")
    if np.all(np.concatenate([a, b]) == a[0]):  # every value tied: no evidence either way
        return 1.0
    return float(sps.mannwhitneyu(a, b, alternative=alternative).pvalue)


def compare_generations(a: Any, b: Any) -> dict[str, Any]:
    """Compare two runs generation by generation (§4.6).

    Args:
        a, b: (G, N) fitness of every particle of run A (with transfer) and run B
            (without), generation by generation (NaN entries are ignored).

    Returns:
        dict with (G,) arrays ``p_greater`` (one-sided rank-sum p that A's particles
        outscore B's), ``p_two_sided`` and ``a12`` (Vargha-Delaney A per generation), and
        the Fisher combinations ``fisher_greater`` and ``fisher_two_sided`` (floats).
    """
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    if a.ndim != 2 or b.ndim != 2 or a.shape[0] != b.shape[0]:
        raise ValueError(f"a and b must be (G, N) with the same G, got {a.shape}, {b.shape}")
    p1 = np.array([_rank_sum(x, y, "greater") for x, y in zip(a, b)])
    p2 = np.array([_rank_sum(x, y, "two-sided") for x, y in zip(a, b)])
    a12 = np.array([vargha_delaney(x, y) for x, y in zip(a, b)])
    return dict(p_greater=p1, p_two_sided=p2, a12=a12, fisher_greater=fisher(p1),
                fisher_two_sided=fisher(p2))


def fisher(pvalues: Any) -> float:
    """Fisher's combination of independent p-values (NaN ignored; NaN if none)."""
    p = np.asarray(pvalues, np.float64).ravel()
    p = p[np.isfinite(p)]
    if p.size == 0:
        return float("nan")
    return float(sps.combine_pvalues(p, method="fisher").pvalue)
