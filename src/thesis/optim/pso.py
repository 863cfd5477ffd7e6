"""Particle swarm optimisation with an ask/tell interface (thesis §3.2.3, §4.3, §4.4).

The swarm has a fixed size so that the caller can evaluate one whole generation in a
single batched (``jax.vmap``) simulation::

    state = pso_init(key, n_particles, lower, upper)
    for _ in range(n_generations):
        x = ask(state)                      # (n_particles, d)
        state = tell(state, fitness(x))     # fitness: (n_particles,), MAXIMISED

Update rule, eq. 3.1–3.2 (and its restatement in §4.3), for particle i at step n::

    v_i(n+1) = ω v_i(n) + φp r_p (p_i − x_i(n)) + φg r_g (g(n) − x_i(n))
    x_i(n+1) = x_i(n) + v_i(n+1)

with p_i the particle's best position so far, g(n) the best position found by any
particle over all past generations, and r_p, r_g ~ U(0, 1). The thesis writes r_p(n),
r_g(n) as scalars (not bold), so by default one pair is drawn per particle and update;
``per_dimension=True`` draws them per coordinate instead.

Decisions where the thesis is silent (documented, configurable):

* **Sign**: fitness is *maximised* (eq. 3.3 "This fitness is maximized"; §4.6 maximises
  speed). To minimise a cost, pass ``-cost``. NaN fitness counts as ``-inf``.
* **Initial velocities** (random init): ``v(0) ~ U(-(upper-lower), upper-lower)`` per
  coordinate, as in Pedersen (2010), "Good parameters for particle swarm optimization"
  (Hvass Labs TR HL1001), the thesis's source [15] of the default ω, φp, φg.
* **Velocity clamping**: the thesis does not mention any; Pedersen (2010) clamps each
  velocity coordinate to ``±(upper-lower)``, which we do by default
  (``v_max_fraction=1.0``; ``None`` switches it off).
* **Boundaries**: after each move, positions are clipped to the box ``[lower, upper]``;
  velocities are kept as computed (Pedersen 2010). An optional ``project`` callable
  (e.g. the dependent bounds a ≤ a_max(x0) of Tab. 4.1) is applied after clipping.
* **Transfer learning** (§4.4): ``x(0)`` = the best particles over all generations of a
  previous optimisation (:func:`best_particles`), ``v(0) = r``, ``r ~ U(-1, 1)`` per
  coordinate in the units of the parameter vector (the thesis's literal statement;
  ``velocity_scale`` rescales it if the caller optimises in other units). Their personal
  bests are *not* transferred: the old fitness belongs to another task, so p_i and g
  start from the first evaluation in the new task.

Pure NumPy; the random stream is stored in the state (PCG64 state dict), so ``tell`` is
a pure function of its inputs and a run is reproducible from its seed.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Callable

import numpy as np

#: Default inertia weight ω of eq. 3.1 (§3.2.3, after Pedersen 2010 [15]).
OMEGA = 0.6571
#: Default acceleration coefficient φp towards the personal best (eq. 3.1).
PHI_P = 1.6319
#: Default acceleration coefficient φg towards the global best (eq. 3.1).
PHI_G = 0.6239


@dataclasses.dataclass(frozen=True)
class PSOState:
    """State of a swarm between generations.

    Attributes:
        x: (n, d) current positions, to be evaluated next (returned by :func:`ask`).
        v: (n, d) current velocities.
        p: (n, d) personal best positions (equal to ``x`` before the first ``tell``).
        p_fit: (n,) personal best fitness (``-inf`` before the first ``tell``).
        g: (d,) global best position over all past generations.
        g_fit: global best fitness (``-inf`` before the first ``tell``).
        lower, upper: (d,) box bounds.
        generation: number of ``tell`` calls so far.
        rng_state: PCG64 bit-generator state (dict) for the next random draws.
        omega, phi_p, phi_g: eq. 3.1 coefficients.
        v_max: (d,) velocity clamp, or None.
        per_dimension: draw r_p, r_g per coordinate instead of per particle.
    """

    x: np.ndarray
    v: np.ndarray
    p: np.ndarray
    p_fit: np.ndarray
    g: np.ndarray
    g_fit: float
    lower: np.ndarray
    upper: np.ndarray
    generation: int
    rng_state: dict
    omega: float = OMEGA
    phi_p: float = PHI_P
    phi_g: float = PHI_G
    v_max: np.ndarray | None = None
    per_dimension: bool = False

    def replace(self, **kw: Any) -> "PSOState":
        return dataclasses.replace(self, **kw)


def make_rng(key_or_rng: Any) -> np.random.Generator:
    """A NumPy PCG64 generator from an int seed, a ``np.random.Generator`` (its state is
    copied, not consumed) or a JAX PRNG key (typed or raw uint32)."""
    if isinstance(key_or_rng, np.random.Generator):
        g = np.random.Generator(np.random.PCG64())
        g.bit_generator.state = key_or_rng.bit_generator.state
        return g
    if isinstance(key_or_rng, (int, np.integer)):
        return np.random.default_rng(int(key_or_rng))
    import jax

    k = key_or_rng
    dtype = getattr(k, "dtype", None)
    if dtype is not None and jax.dtypes.issubdtype(dtype, jax.dtypes.prng_key):
        k = jax.random.key_data(k)
    words = np.asarray(k, dtype=np.uint32).ravel()
    return np.random.default_rng(np.random.SeedSequence(words.tolist()))


def _gen(state_dict: dict) -> np.random.Generator:
    g = np.random.Generator(np.random.PCG64())
    g.bit_generator.state = state_dict
    return g


def pso_init(
    key_or_rng: Any,
    n_particles: int,
    lower: Any,
    upper: Any,
    init: Any = None,
    *,
    omega: float = OMEGA,
    phi_p: float = PHI_P,
    phi_g: float = PHI_G,
    v_max_fraction: float | None = 1.0,
    velocity_scale: Any = 1.0,
    per_dimension: bool = False,
    project: Callable[[np.ndarray], np.ndarray] | None = None,
) -> PSOState:
    """Initialise a swarm (eq. 3.1–3.2; random or transfer initialisation of §4.4).

    Args:
        key_or_rng: int seed, ``np.random.Generator`` or JAX key.
        n_particles: swarm size n (thesis: 10 in §3.3.1.2, 20 in §3.3.1.3 and §4.3).
        lower, upper: (d,) box bounds.
        init: None for random initialisation (x ~ U(lower, upper),
            v ~ U(-(upper-lower), upper-lower)); or an (n, d) array of starting
            positions (transfer learning, §4.4: use :func:`best_particles`), in which
            case v(0) = velocity_scale * r, r ~ U(-1, 1)^d.
        omega, phi_p, phi_g: eq. 3.1 coefficients (defaults from §3.2.3).
        v_max_fraction: velocity clamp as a fraction of (upper-lower); None: no clamp.
        velocity_scale: scalar or (d,) scale of the transfer impulse (1: literal §4.4).
        per_dimension: draw r_p, r_g per coordinate.
        project: optional feasibility map applied to initial positions after clipping.

    Returns:
        PSOState whose ``x`` is the first generation to evaluate.
    """
    lower = np.asarray(lower, dtype=np.float64)
    upper = np.asarray(upper, dtype=np.float64)
    if lower.shape != upper.shape or lower.ndim != 1:
        raise ValueError("lower and upper must be 1-D arrays of equal length")
    if np.any(upper < lower):
        raise ValueError("upper must be >= lower")
    d = lower.shape[0]
    rng = make_rng(key_or_rng)
    span = upper - lower
    if init is None:
        x = lower + rng.random((n_particles, d)) * span
        v = (2.0 * rng.random((n_particles, d)) - 1.0) * span
    else:
        x = np.array(init, dtype=np.float64, copy=True)
        if x.shape != (n_particles, d):
            raise ValueError(f"init must have shape {(n_particles, d)}, got {x.shape}")
        v = (2.0 * rng.random((n_particles, d)) - 1.0) * np.asarray(velocity_scale)
    x = np.clip(x, lower, upper)
    if project is not None:
        x = np.asarray(project(x), dtype=np.float64)
    v_max = None if v_max_fraction is None else float(v_max_fraction) * span
    if v_max is not None:
        v = np.clip(v, -v_max, v_max)
    return PSOState(
        x=x, v=v, p=x.copy(), p_fit=np.full(n_particles, -np.inf), g=x[0].copy(),
        g_fit=-np.inf, lower=lower, upper=upper, generation=0,
        rng_state=rng.bit_generator.state, omega=float(omega), phi_p=float(phi_p),
        phi_g=float(phi_g), v_max=v_max, per_dimension=bool(per_dimension),
    )


def ask(state: PSOState) -> np.ndarray:
    """Positions to evaluate next, shape (n, d) (a copy)."""
    return state.x.copy()


def tell(
    state: PSOState,
    fitness: Any,
    project: Callable[[np.ndarray], np.ndarray] | None = None,
) -> PSOState:
    """Record the fitness of ``ask(state)`` and move the swarm (eq. 3.1–3.2).

    Args:
        state: the swarm whose ``x`` was evaluated.
        fitness: (n,) fitness of each particle, MAXIMISED; NaN counts as -inf.
        project: optional feasibility map (n, d) -> (n, d) applied after box clipping.

    Returns:
        the new state; its ``x`` is the next generation to evaluate.
    """
    f = np.asarray(fitness, dtype=np.float64).reshape(-1)
    if f.shape[0] != state.x.shape[0]:
        raise ValueError(f"fitness must have shape ({state.x.shape[0]},), got {f.shape}")
    f = np.where(np.isnan(f), -np.inf, f)
    better = f > state.p_fit
    p = np.where(better[:, None], state.x, state.p)
    p_fit = np.where(better, f, state.p_fit)
    # personal bests only improve, so their best is the best over all past generations
    i_best = int(np.argmax(p_fit))
    g, g_fit = p[i_best].copy(), float(p_fit[i_best])

    rng = _gen(state.rng_state)
    n, d = state.x.shape
    shape = (n, d) if state.per_dimension else (n, 1)
    r_p = rng.random(shape)
    r_g = rng.random(shape)
    v = (
        state.omega * state.v
        + state.phi_p * r_p * (p - state.x)
        + state.phi_g * r_g * (g[None, :] - state.x)
    )
    if state.v_max is not None:
        v = np.clip(v, -state.v_max, state.v_max)
    x = np.clip(state.x + v, state.lower, state.upper)
    if project is not None:
        x = np.asarray(project(x), dtype=np.float64)
    return state.replace(
        x=x, v=v, p=p, p_fit=p_fit, g=g, g_fit=g_fit, generation=state.generation + 1,
        rng_state=rng.bit_generator.state,
    )


def best_particles(positions: Any, fitness: Any, n: int) -> np.ndarray:
    """The n best particles over all generations of a previous run (§4.4 transfer).

    Args:
        positions: (G, N, d) (or (M, d)) every evaluated position of a previous run.
        fitness: (G, N) (or (M,)) their fitness (maximised; NaN ranks last).

    Returns:
        (n, d) positions sorted best first: the ``init`` of :func:`pso_init`.
    """
    x = np.asarray(positions, dtype=np.float64)
    x = x.reshape(-1, x.shape[-1])
    f = np.asarray(fitness, dtype=np.float64).reshape(-1)
    if f.shape[0] != x.shape[0]:
        raise ValueError("positions and fitness disagree in size")
    if n > f.shape[0]:
        raise ValueError(f"asked for {n} particles, only {f.shape[0]} evaluated")
    f = np.where(np.isnan(f), -np.inf, f)
    order = np.argsort(-f, kind="stable")[:n]
    return x[order].copy()


@dataclasses.dataclass(frozen=True)
class History:
    """Record of an optimisation run (PSO or CMA-ES).

    Attributes:
        positions: (G, N, d) every evaluated position, per generation.
        fitness: (G, N) their fitness (maximised).
        best_fitness: (G,) best fitness found up to and including each generation.
        best_position: (d,) the best position over the whole run.
    """

    positions: np.ndarray
    fitness: np.ndarray
    best_fitness: np.ndarray
    best_position: np.ndarray


def history_from(positions: list, fitness: list) -> History:
    """Stack per-generation lists into a :class:`History`."""
    X = np.stack([np.asarray(p, dtype=np.float64) for p in positions])
    F = np.stack([np.asarray(f, dtype=np.float64).reshape(-1) for f in fitness])
    Fs = np.where(np.isnan(F), -np.inf, F)
    best = np.maximum.accumulate(Fs.max(axis=1))
    g, i = np.unravel_index(int(np.argmax(Fs)), Fs.shape)
    return History(positions=X, fitness=F, best_fitness=best, best_position=X[g, i].copy())


def run_pso(
    fitness_fn: Callable[[np.ndarray], Any],
    key_or_rng: Any,
    n_particles: int,
    n_generations: int,
    lower: Any,
    upper: Any,
    init: Any = None,
    project: Callable[[np.ndarray], np.ndarray] | None = None,
    **options: Any,
) -> tuple[History, PSOState]:
    """Run PSO for ``n_generations`` generations (one batched call per generation).

    Args:
        fitness_fn: maps an (n, d) array of positions to (n,) fitness (maximised).
        key_or_rng, n_particles, lower, upper, init, **options: as :func:`pso_init`.
        n_generations: number of evaluated generations G.
        project: optional feasibility map, applied at init and after every move.

    Returns:
        (History, final PSOState). ``History.fitness[g]`` belongs to
        ``History.positions[g]``; ``best_fitness[g]`` is the best up to generation g.
    """
    state = pso_init(key_or_rng, n_particles, lower, upper, init, project=project, **options)
    xs, fs = [], []
    for _ in range(int(n_generations)):
        x = ask(state)
        f = np.asarray(fitness_fn(x), dtype=np.float64).reshape(-1)
        xs.append(x)
        fs.append(f)
        state = tell(state, f, project=project)
    return history_from(xs, fs), state


def normalise(x: Any, lower: Any, upper: Any) -> np.ndarray:
    """Map positions (..., d) to the unit box: (x - lower) / (upper - lower)."""
    lower = np.asarray(lower, dtype=np.float64)
    span = np.asarray(upper, dtype=np.float64) - lower
    return (np.asarray(x, dtype=np.float64) - lower) / np.where(span > 0, span, 1.0)


def search_space_size(positions: Any, lower: Any, upper: Any) -> np.ndarray:
    """Size of the explored part of the parameter space per generation (Fig. 4.10).

    "the geometric mean of the lengths of the principle component axis of the particle
    parameters for each generation": here the axis lengths are the standard deviations
    along the principal components of the generation's positions, after normalising
    every parameter to the unit box (our choice; the thesis does not say how it scaled
    parameters of different units). Axes beyond the rank (n ≤ d) are left out.

    Args:
        positions: (G, N, d) or (N, d) positions.

    Returns:
        (G,) or () geometric mean axis length (dimensionless, in box units).
    """
    x = normalise(positions, lower, upper)
    single = x.ndim == 2
    x = x[None] if single else x
    out = []
    for g in x:
        c = g - g.mean(axis=0)
        sv = np.linalg.svd(c, compute_uv=False) / np.sqrt(max(g.shape[0] - 1, 1))
        sv = sv[: min(g.shape[0] - 1, g.shape[1])]
        sv = np.maximum(sv, 1e-300)
        out.append(float(np.exp(np.mean(np.log(sv)))))
    res = np.asarray(out)
    return res[0] if single else res
