"""The tables and figures of chapter 4, derived from the simulation runs of
:mod:`thesis.ch4.transfer_runs` (registered in :mod:`thesis.registry`; inputs ``flat``
and ``transfer_<group>``). No simulation here, except the idealised foot loci of
Fig. 4.3 (inverse kinematics only).

* ``table4_2`` / ``table4_3`` / ``table4_4``: the best particle of every run (flat and
  each arm of each condition): its 12 parameters, in-run speed and score, the generation
  it was found in, its Euclidean distance to the flat run's best particle of the same
  seed after normalising every parameter to its search range (§4.6.1 "after
  normalization of the parameters"; the thesis does not say how it normalised), and its
  speed re-evaluated from standstill. Tab. 4.4 also has ``rank`` 2: the best particle
  after the first generation ("excluding the transferred particles", §4.6.3).
* ``fig4_5`` / ``fig4_7`` / ``fig4_8``: every particle's score per generation with and
  without transfer (slopes / softer front legs / pebbles), the per-generation Wilcoxon
  rank-sum p-values (transfer greater, and two-sided), the Vargha-Delaney A and the
  Fisher combination per seed (§4.6, :func:`thesis.optim.transfer.compare_generations`),
  the fraction of fallen evaluations and the number of robots set back on their feet at
  the start of their window per generation.
* ``fig4_6``: the best particles of all optimisations per inclination (§4.6.1: flat from
  the flat run, each slope from both of its arms), their means and covariances.
* ``fig4_9``: step length a and depth x0 of every particle on the steepest slope, with
  the edge a_max(x0) of the search space (§4.7).
* ``fig4_10``: the search-space size per generation, every condition and arm (§4.7,
  :func:`thesis.optim.pso.search_space_size`).
* ``fig4_3``: idealised foot trajectories of random first-generation particles and of
  the optimised flat gait (inverse kinematics, no compliance).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from thesis.gaits import conditions as C
from thesis.gaits import leg as L
from thesis.ch4.transfer_runs import FAMILY, PARAMETERS, load_input
from thesis.optim import pso, transfer

_MIXED = "mixed (see parameter_unit)"


_load = load_input


def _runs(ctx) -> xr.Dataset:
    """Every ``transfer_*`` input, concatenated along ``condition``."""
    order = ("transfer_slopes", "transfer_compliant", "transfer_pebbly")  # thesis order
    names = sorted((k for k in ctx.inputs if k.startswith("transfer_")),
                   key=lambda k: (order.index(k) if k in order else len(order), k))
    if not names:
        raise KeyError(f"experiment {ctx.key} needs at least one transfer_* input")
    parts = [_load(ctx, n) for n in names]
    keep = ["position", "score", "speed", "fallen", "best_position", "best_generation",
            "best_particle", "reeval_speed", "reeval_score", "reeval_fallen", "reeval_taut"]
    if all("reset" in p for p in parts):  # runs written before the resets lack it
        keep.append("reset")
    return xr.concat([p[keep] for p in parts], dim="condition")


#: Attributes stating a run's size, copied from the runs onto every derived artifact (the
#: claims compare them with the thesis's).
BUDGET_ATTRS = ("particles", "generations", "run_seconds", "transition_seconds")


def budget_attrs(*sources: xr.Dataset) -> dict:
    """The run-size attributes of the source runs (the smallest over the sources)."""
    out = {}
    for k in BUDGET_ATTRS:
        vals = [float(s.attrs[k]) for s in sources if k in s.attrs]
        if vals:
            out[k] = min(vals)
    return out


def normalised(x) -> np.ndarray:
    """Parameters (..., 12) mapped to their search ranges (unit box)."""
    return pso.normalise(x, FAMILY.lower, FAMILY.upper)


def distance(x, y) -> np.ndarray:
    """Euclidean distance between parameter vectors (..., 12) after normalising every
    parameter to its search range (so at most sqrt(12))."""
    return np.linalg.norm(normalised(x) - normalised(y), axis=-1)


def _flat_best(flat: xr.Dataset):
    """(S, 12) best flat particle, (S,) its speed, score, generation, (S, R) re-evaluations
    (speed, fallen, taut fraction of the safety thread)."""
    g = flat["best_generation"].values.astype(int)
    k = flat["best_particle"].values.astype(int)
    i = np.arange(len(g))
    return (flat["position"].values[i, g, k], flat["speed"].values[i, g, k],
            flat["score"].values[i, g, k], g.astype(float), flat["reeval_speed"].values,
            flat["reeval_fallen"].values, flat["reeval_taut"].values)


def _in_run(runs: xr.Dataset, cond: str, seed, t: int, rank: int):
    """Position, speed, score and generation of the stored best particle of one run."""
    at = dict(seed=seed, condition=cond, transfer=t, rank=rank)
    g, k = int(runs["best_generation"].sel(at)), int(runs["best_particle"].sel(at))
    sel = dict(seed=seed, condition=cond, transfer=t, generation=g, particle=k)
    return (runs["position"].sel(sel).values, float(runs["speed"].sel(sel)),
            float(runs["score"].sel(sel)), g)


def best_table(flat: xr.Dataset, runs: xr.Dataset, dim: str, levels, conds, ranks=(1,)):
    """The best-particle table of Tab. 4.2-4.4.

    Args:
        flat, runs: the ``flat`` and concatenated ``transfer_*`` datasets.
        dim: name of the table's row dimension (``grade``, ``stiffness``, ``terrain``).
        levels: its coordinate values; the first is the flat / normal source row.
        conds: the run condition of each level after the first.
        ranks: best particle ranks kept (1: over all generations; 2: after the first).
    """
    seeds = [int(s) for s in flat["seed"].values]
    S, Lv, T, K, P = len(seeds), len(levels), 2, len(ranks), len(PARAMETERS)
    R = flat.sizes["repeat"]
    value = np.full((S, Lv, T, K, P), np.nan)
    speed, score, gen, dist = (np.full((S, Lv, T, K), np.nan) for _ in range(4))
    rspeed, rfall, rtaut = (np.full((S, Lv, T, K, R), np.nan) for _ in range(3))
    fpos, fspeed, fscore, fgen, frs, frf, frt = _flat_best(flat)
    value[:, 0, 0, 0], speed[:, 0, 0, 0], score[:, 0, 0, 0] = fpos, fspeed, fscore
    gen[:, 0, 0, 0], rspeed[:, 0, 0, 0], rfall[:, 0, 0, 0] = fgen, frs, frf
    rtaut[:, 0, 0, 0] = frt
    dist[:, 0, 0, 0] = 0.0
    for li, cond in enumerate(conds, start=1):
        for i, s in enumerate(seeds):
            for t in (0, 1):
                for ki, r in enumerate(ranks):
                    x, v, sc, g = _in_run(runs, cond, s, t, r)
                    value[i, li, t, ki], speed[i, li, t, ki], score[i, li, t, ki] = x, v, sc
                    gen[i, li, t, ki] = g
                    dist[i, li, t, ki] = distance(x, fpos[i])
                    sel = dict(seed=s, condition=cond, transfer=t, rank=r)
                    rspeed[i, li, t, ki] = runs["reeval_speed"].sel(sel).values
                    rfall[i, li, t, ki] = runs["reeval_fallen"].sel(sel).values
                    rtaut[i, li, t, ki] = runs["reeval_taut"].sel(sel).values
    dims = ("seed", dim, "transfer", "rank")
    ds = xr.Dataset(
        dict(value=(dims + ("parameter",), value, dict(
                 units=_MIXED, long_name="parameters of the best particle (rank 1: over all "
                                         "generations; rank 2: after the first generation)")),
             speed=(dims, speed, dict(units="m s-1", long_name="in-run speed of the best "
                                                               "particle")),
             score=(dims, score, dict(units="m s-1", long_name="in-run §4.6 score of the best "
                                                               "particle (speed if it stayed up)")),
             best_generation=(dims, gen, dict(units="1", long_name="generation it was "
                                                                   "evaluated in")),
             euclidean_distance=(dims, dist, dict(
                 units="1", long_name="Euclidean distance to the flat run's best particle of "
                                      "the same seed, every parameter normalised to its range")),
             reeval_speed=(dims + ("repeat",), rspeed, dict(
                 units="m s-1", long_name="speed re-evaluated from standstill")),
             reeval_fallen=(dims + ("repeat",), rfall, dict(
                 units="1", long_name="1 if the re-evaluation fell")),
             reeval_taut=(dims + ("repeat",), rtaut, dict(
                 units="1", long_name="fraction of the re-evaluation's window with a safety "
                                      "thread taut")),
             parameter_unit=("parameter", list(FAMILY.units), dict(
                 units="1", long_name="unit of the parameter"))),
        coords={"seed": seeds, dim: list(levels), "transfer": [0, 1], "rank": list(ranks),
                "repeat": np.arange(R), "parameter": list(PARAMETERS)})
    ds["transfer"].attrs.update(units="1", long_name="1: with transfer; 0: without")
    ds.attrs.update(seeds=seeds, **budget_attrs(flat, runs))
    if len(ranks) == 1:
        ds = ds.squeeze("rank", drop=True)
    return ds


def table4_2(ctx) -> xr.Dataset:
    """Tab. 4.2: best particle per grade (0 = the flat source run) and arm."""
    grades = [float(g) for g in ctx.config["conditions"]["grades"]]
    levels = [0] + [int(g) if g.is_integer() else g for g in grades]
    ds = best_table(_load(ctx, "flat"), _runs(ctx), "grade", levels,
                    [C.grade_name(g) for g in grades])
    ds["grade"].attrs.update(units="percent", long_name="grade of the slope")
    ds.attrs.update(thesis_ref="Tab. 4.2")
    return ds


def table4_3(ctx) -> xr.Dataset:
    """Tab. 4.3: best particle with normal and with softer front legs, per arm."""
    ds = best_table(_load(ctx, "flat"), _runs(ctx), "stiffness", ["normal", "compliant"],
                    ["compliant"])
    ds.attrs.update(thesis_ref="Tab. 4.3",
                    front_spring_factor=float(ctx.config["conditions"]["front_spring_factor"]))
    return ds


def table4_4(ctx) -> xr.Dataset:
    """Tab. 4.4: best particle on normal and pebbly terrain, per arm; rank 2 is the best
    after the first generation (the thesis's second transfer row)."""
    ds = best_table(_load(ctx, "flat"), _runs(ctx), "terrain", ["normal", "pebbly"],
                    ["pebbly"], ranks=(1, 2))
    ds.attrs.update(thesis_ref="Tab. 4.4")
    return ds


def _reset_count(sub: xr.Dataset, dims) -> dict:
    """``reset_count`` (dims without 'particle'): robots set back on their feet at the
    start of their window per generation (departure ch4.fall_reset); empty for runs
    written before the resets."""
    if "reset" not in sub:
        return {}
    return dict(reset_count=(dims[:3], sub["reset"].transpose(*dims).sum("particle").values,
                             dict(units="1", long_name="evaluations of the generation whose "
                                  "robot was set back on its feet at the start of its window")))


def generation_scores(runs: xr.Dataset, cond: str, thesis_ref: str) -> xr.Dataset:
    """Per-generation scores of both arms of one condition and their comparison (§4.6)."""
    sub = runs.sel(condition=cond)
    seeds = [int(s) for s in sub["seed"].values]
    G = sub.sizes["generation"]
    out = {k: np.zeros((len(seeds), G)) for k in ("p_greater", "p_two_sided", "a12")}
    fish = {k: np.zeros(len(seeds)) for k in ("fisher_greater", "fisher_two_sided")}
    for i, s in enumerate(seeds):
        c = transfer.compare_generations(sub["score"].sel(seed=s, transfer=1).values,
                                         sub["score"].sel(seed=s, transfer=0).values)
        for k in out:
            out[k][i] = c[k]
        for k in fish:
            fish[k][i] = c[k]
    dims = ("seed", "transfer", "generation", "particle")
    ds = xr.Dataset(
        dict(score=(dims, sub["score"].transpose(*dims).values, dict(
                 units="m s-1", long_name="§4.6 score: window speed, or for a fallen robot -2 + "
                                          "the fraction of the window it stayed up")),
             speed=(dims, sub["speed"].transpose(*dims).values, dict(
                 units="m s-1", long_name="mean forward speed over the window")),
             fallen=(dims, sub["fallen"].transpose(*dims).values, dict(
                 units="1", long_name="1 if the robot fell")),
             fall_fraction=(dims[:3], sub["fallen"].transpose(*dims).mean("particle").values,
                            dict(units="1", long_name="fraction of fallen evaluations")),
             **_reset_count(sub, dims),
             p_greater=(("seed", "generation"), out["p_greater"], dict(
                 units="1", long_name="Wilcoxon rank-sum p, transfer scores greater "
                                      "(one-sided)")),
             p_two_sided=(("seed", "generation"), out["p_two_sided"], dict(
                 units="1", long_name="Wilcoxon rank-sum p, two-sided")),
             a12=(("seed", "generation"), out["a12"], dict(
                 units="1", long_name="Vargha-Delaney A: P(transfer particle outscores a "
                                      "random-swarm particle)")),
             fisher_greater=(("seed",), fish["fisher_greater"], dict(
                 units="1", long_name="Fisher combination of the one-sided p over "
                                      "generations")),
             fisher_two_sided=(("seed",), fish["fisher_two_sided"], dict(
                 units="1", long_name="Fisher combination of the two-sided p over "
                                      "generations"))),
        coords=dict(seed=seeds, transfer=[0, 1], generation=np.arange(G),
                    particle=np.arange(sub.sizes["particle"])))
    ds["transfer"].attrs.update(units="1", long_name="1: with transfer; 0: without")
    ds.attrs.update(thesis_ref=thesis_ref, seeds=seeds, condition=cond, **budget_attrs(runs))
    return ds


def fig4_5(ctx) -> xr.Dataset:
    """Fig. 4.5: particle scores per generation on each slope, with and without transfer."""
    runs = _runs(ctx)
    grades = [float(g) for g in ctx.config["conditions"]["grades"]]
    parts = [generation_scores(runs, C.grade_name(g), "Fig. 4.5") for g in grades]
    ds = xr.concat(parts, dim=xr.DataArray([int(g) if g.is_integer() else g for g in grades],
                                           dims="grade"), combine_attrs="override")
    ds["grade"].attrs.update(units="percent", long_name="grade of the slope")
    ds.attrs.pop("condition", None)
    return ds


def fig4_7(ctx) -> xr.Dataset:
    """Fig. 4.7: particle scores per generation with softer front legs."""
    return generation_scores(_runs(ctx), "compliant", "Fig. 4.7")


def fig4_8(ctx) -> xr.Dataset:
    """Fig. 4.8: particle scores per generation on pebbles."""
    return generation_scores(_runs(ctx), "pebbly", "Fig. 4.8")


def _top(pos: np.ndarray, score: np.ndarray, n: int):
    """The ``n`` best of (M, 12) positions by (M,) score, best first."""
    s = np.where(np.isnan(score), -np.inf, score)
    order = np.argsort(-s, kind="stable")[:n]
    return pos[order], score[order]


def fig4_6(ctx) -> xr.Dataset:
    """Fig. 4.6: the best particles of all optimisations per inclination, per seed
    (flat: the flat run; a slope: both of its arms), their mean and covariance."""
    flat, runs = _load(ctx, "flat"), _runs(ctx)
    grades = [float(g) for g in ctx.config["conditions"]["grades"]]
    seeds = [int(s) for s in flat["seed"].values]
    pools = []
    for s in seeds:
        row = [(flat["position"].sel(seed=s).values.reshape(-1, 12),
                flat["score"].sel(seed=s).values.ravel())]
        for g in grades:
            sub = runs.sel(seed=s, condition=C.grade_name(g))
            row.append((sub["position"].values.reshape(-1, 12), sub["score"].values.ravel()))
        pools.append(row)
    n = min(int(ctx.config["fig4_6"]["top"]), min(len(sc) for row in pools for _, sc in row))
    S, Gr, P = len(seeds), len(grades) + 1, len(PARAMETERS)
    value, score = np.zeros((S, Gr, n, P)), np.zeros((S, Gr, n))
    for i, row in enumerate(pools):
        for j, (pos, sc) in enumerate(row):
            value[i, j], score[i, j] = _top(pos, sc, n)
    mean = value.mean(axis=2)
    cen = value - mean[:, :, None]
    cov = np.einsum("sgnp,sgnq->sgpq", cen, cen) / max(n - 1, 1)
    unit = normalised(value)
    total = unit.var(axis=2, ddof=1).sum(axis=-1)
    levels = [0] + [int(g) if g.is_integer() else g for g in grades]
    ds = xr.Dataset(
        dict(value=(("seed", "grade", "top", "parameter"), value, dict(
                 units=_MIXED, long_name="the best particles of all optimisations at this "
                                         "inclination")),
             score=(("seed", "grade", "top"), score, dict(units="m s-1", long_name="their score")),
             mean=(("seed", "grade", "parameter"), mean, dict(
                 units=_MIXED, long_name="mean of the Gaussian fitted to them")),
             covariance=(("seed", "grade", "parameter", "parameter_b"), cov, dict(
                 units="mixed (product of the two parameters' units)",
                 long_name="covariance of the Gaussian fitted to them")),
             total_variance=(("seed", "grade"), total, dict(
                 units="1", long_name="sum of the variances of the parameters normalised to "
                                      "their search ranges")),
             parameter_unit=("parameter", list(FAMILY.units), dict(
                 units="1", long_name="unit of the parameter"))),
        coords=dict(seed=seeds, grade=levels, top=np.arange(n), parameter=list(PARAMETERS),
                    parameter_b=list(PARAMETERS)))
    ds["grade"].attrs.update(units="percent", long_name="grade of the slope")
    ds.attrs.update(thesis_ref="Fig. 4.6", seeds=seeds, top=n, **budget_attrs(flat, runs))
    return ds


def fig4_9(ctx) -> xr.Dataset:
    """Fig. 4.9: step length a and depth x0 of every particle on the steepest slope, with
    the search space's edge a_max(x0)."""
    runs = _runs(ctx)
    grade = max(float(g) for g in ctx.config["conditions"]["grades"])
    sub = runs.sel(condition=C.grade_name(grade))
    ia, ix = PARAMETERS.index("a"), PARAMETERS.index("x0")
    pos = sub["position"].transpose("seed", "transfer", "generation", "particle",
                                    "parameter").values
    a, x0 = pos[..., ia], pos[..., ix]
    lo, hi = FAMILY.lower[ix], FAMILY.upper[ix]
    grid = np.linspace(lo, hi, 33)
    dims = ("seed", "transfer", "generation", "particle")
    ds = xr.Dataset(
        dict(a=(dims, a, dict(units="mm", long_name="step length a")),
             x0=(dims, x0, dict(units="mm", long_name="depth x0 of the locus below the hip")),
             a_fraction=(dims, a / FAMILY.a_max(x0), dict(
                 units="1", long_name="a / a_max(x0): step length relative to the longest "
                                      "reachable one")),
             x0_fraction=(dims, (x0 - lo) / (hi - lo), dict(
                 units="1", long_name="x0 within its range (0: highest, 1: deepest)")),
             score=(dims, sub["score"].transpose(*dims).values, dict(
                 units="m s-1", long_name="§4.6 score")),
             a_max=(("x0_edge",), FAMILY.a_max(grid), dict(
                 units="mm", long_name="a_max(x0), the edge of the search space"))),
        coords=dict(seed=[int(s) for s in sub["seed"].values], transfer=[0, 1],
                    generation=sub["generation"].values, particle=sub["particle"].values,
                    x0_edge=grid))
    ds["x0_edge"].attrs.update(units="mm", long_name="x0")
    ds["transfer"].attrs.update(units="1", long_name="1: with transfer; 0: without")
    ds.attrs.update(thesis_ref="Fig. 4.9", seeds=[int(s) for s in sub["seed"].values],
                    grade=grade, **budget_attrs(runs))
    return ds


def fig4_10(ctx) -> xr.Dataset:
    """Fig. 4.10: size of the explored parameter space per generation (geometric mean of
    the principal-axis lengths in range-normalised units), every condition and arm."""
    runs = _runs(ctx)
    pos = runs["position"].transpose("seed", "condition", "transfer", "generation",
                                     "particle", "parameter").values
    size = np.zeros(pos.shape[:4])
    for idx in np.ndindex(*pos.shape[:3]):
        size[idx] = pso.search_space_size(pos[idx], FAMILY.lower, FAMILY.upper)
    seeds = [int(s) for s in runs["seed"].values]
    ds = xr.Dataset(
        dict(search_space_size=(("seed", "condition", "transfer", "generation"), size, dict(
            units="1", long_name="geometric mean of the principal-axis standard deviations "
                                 "of the generation's particles (parameters normalised to "
                                 "their ranges)"))),
        coords=dict(seed=seeds, condition=[str(c) for c in runs["condition"].values],
                    transfer=[0, 1], generation=runs["generation"].values))
    ds["transfer"].attrs.update(units="1", long_name="1: with transfer; 0: without")
    ds.attrs.update(thesis_ref="Fig. 4.10", seeds=seeds, **budget_attrs(runs))
    return ds


def foot_loci(params, samples: int) -> np.ndarray:
    """(2, samples, 2) idealised loci of a fore and a hind foot over one cycle: the
    commanded hip and knee angles (inverse kinematics limited to the joint ranges, §4.2)
    through the leg's forward kinematics; (horizontal y forward, depth x below the hip) [mm]."""
    import jax
    import jax.numpy as jnp

    phases = jnp.linspace(0.0, 1.0, samples, endpoint=False)
    q = jax.vmap(lambda ph: FAMILY.commands_at_phase(jnp.asarray(params, jnp.float32), ph))(
        phases)
    q = np.asarray(q).reshape(samples, 4, 3)
    out = []
    for leg in ("LF", "LH"):
        j = L.LEGS.index(leg)
        xz = np.asarray(L.forward(FAMILY.legs[j], q[:, j, 1], q[:, j, 2]))
        out.append(np.stack([xz[:, 0] * 1e3, -xz[:, 1] * 1e3], axis=-1))
    return np.stack(out)


def fig4_3(ctx) -> xr.Dataset:
    """Fig. 4.3: idealised foot trajectories of random particles of the flat run's first
    generation and of its best particle (inverse kinematics, no compliance)."""
    flat = _load(ctx, "flat")
    fc = ctx.config["fig4_3"]
    k = min(int(fc["random_examples"]), flat.sizes["particle"])
    n = int(fc["samples"])
    seeds = [int(s) for s in flat["seed"].values]
    best, *_ = _flat_best(flat)
    examples = [f"random_{i + 1}" for i in range(k)] + ["optimised"]
    loci = np.zeros((len(seeds), len(examples), 2, n, 2))
    for i, s in enumerate(seeds):
        parts = list(flat["position"].sel(seed=s, generation=0).values[:k]) + [best[i]]
        for j, p in enumerate(parts):
            loci[i, j] = foot_loci(p, n)
    dims = ("seed", "example", "foot", "sample")
    ds = xr.Dataset(
        dict(y=(dims, loci[..., 0], dict(units="mm", long_name="horizontal foot position "
                                                               "relative to the hip, + forward")),
             x=(dims, loci[..., 1], dict(units="mm", long_name="depth of the foot below the "
                                                               "hip"))),
        coords=dict(seed=seeds, example=examples, foot=["fore", "hind"], sample=np.arange(n)))
    ds.attrs.update(thesis_ref="Fig. 4.3", seeds=seeds)
    return ds
