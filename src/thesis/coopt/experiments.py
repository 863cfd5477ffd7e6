"""The registered experiments of §8.2: ``coopt/arms`` and ``coopt/gradients``.

``coopt/arms`` (:func:`arms`): the chapter-7 quadruped (:mod:`thesis.coopt.morphology`,
at the servo torque ``coopt.body.servo_torque``) under the open-loop trot plus feedback
network of :mod:`thesis.coopt.objective`, optimised by BPTT through the engine for
chapter 7's gait objective (mean forward spine speed over ``coopt.arms.episode_s``) in
three arms with the same budget of ``coopt.arms.evaluations`` gradient evaluations each:

* ``controller``: the network only, the body fixed at the built values;
* ``morphology``: the body only, the controller fixed at its initial value (the network's
  output is zero, so the controller is the fixed open-loop trot; departure
  ``ch8.coopt_controller``); its runs are identical over seeds (nothing random is left);
* ``joint``: both at once.

Every seed starts all three arms from the same network (``seeding.key(root, "coopt/arms",
seed)``), so arms are compared paired by seed. Each group of parameters has its own Adam
with §7.3.2's clipping (the controller's ``learning_rate``, the body's
``morphology_learning_rate`` in the unconstrained coordinates); an arm's frozen group gets
a zero gradient, which leaves Adam's update exactly zero. The gradient is §7.3.2's
(per-step decay ``grad_decay``); every reported speed is the undecayed objective. All
runs are one vmapped program (one compilation). After training, every run's final
parameters (and the common initial ones) are re-evaluated from ``perturbed_starts``
perturbed starts (:func:`thesis.coopt.objective.perturb`: a push ~ N(0, push_std^2) in
x and y and a lift ~ U(0, lift_max)).

``coopt/gradients`` (:func:`gradients`): at a probe point (the built body and a feedback
network with non-zero output, ``probe_output_scale``; one per seed) and for the two
parameter groups (``controller``: the network's parameters; ``morphology``: the 8 body
coordinates), the engine's exact gradient of the speed over a horizon, beside REINFORCE
and antithetic-ES estimates (:mod:`thesis.coopt.estimators`) from 1 to ``rollouts``
rollouts, at each horizon of ``horizons_steps``: cosine and relative error per count and
block, and the rollouts each needs to reach cos > ``cos_threshold``. And the analytic
gradient's spread over ``variance_starts`` starts perturbed by ``start_push_std``, per
horizon of ``variance_horizons_steps`` (one rollout per start; the gradients of every
horizon's mean speed from one Jacobian): its norm and its cosine with the unperturbed
start's gradient.
"""

from __future__ import annotations

import time

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr
from jax.flatten_util import ravel_pytree

from thesis import seeding
from thesis.coopt import estimators as est
from thesis.coopt import morphology, objective
from thesis.ch7 import bptt, nets
from thesis.errors import SimulationDiverged
from thesis.physics import rollout
from thesis.store import WALL_CLOCK

__all__ = ["ARMS", "GROUPS", "arms", "gradients", "random_direction_steps"]

#: The three arms and which parameter groups each optimises (controller, morphology).
ARMS = {"controller": (1.0, 0.0), "morphology": (0.0, 1.0), "joint": (1.0, 1.0)}
#: The parameter groups of the gradient comparison.
GROUPS = ("controller", "morphology")


def _common_attrs(cfg: dict, model) -> dict:
    t = cfg["trot"]
    return {"servo_torque": float(cfg["body"]["servo_torque"]), "dt": float(model.dt),
            "solver_iterations": int(model.solver_iterations),
            "trot": ", ".join(f"{k}={float(t[k]):g}" for k in t),
            "network": f"{objective.N_INPUTS}-{'-'.join(map(str, cfg['hidden']))}-8 + skip",
            "morphology_units": ", ".join(f"{p.name} [{p.unit}]" for p in morphology.PARAMS)}


def _param_coords():
    p = morphology.PARAMS
    return {"param": list(morphology.NAMES),
            "param_lo": ("param", [x.lo for x in p], {"units": "various",
                                                     "long_name": "lower bound"}),
            "param_hi": ("param", [x.hi for x in p], {"units": "various",
                                                     "long_name": "upper bound"}),
            "param_built": ("param", [x.built for x in p], {
                "units": "various", "long_name": "value of the chapter-7 quadruped"}),
            "param_unit": ("param", [x.unit for x in p], {"units": "1",
                                                         "long_name": "unit of the parameter"})}


def _starts(key, n: int, push_std: float, lift_max: float):
    """(n, 3) pushes [m/s] (x, y ~ N(0, push_std^2), z 0) and (n,) lifts ~ U(0, lift_max)."""
    k1, k2 = jax.random.split(key)
    push = push_std * np.asarray(jax.random.normal(k1, (n, 3)))
    push[:, 2] = 0.0
    lift = lift_max * np.asarray(jax.random.uniform(k2, (n,)))
    return push, lift


def random_direction_steps(net, u, keys, opt_c, opt_m):
    """The negative control of the joint arm: ``net`` and body coordinates ``u`` updated
    by the same optimisers as the gradient runs, fed a random direction instead of the
    gradient at every update, so every step has the gradient run's size (Adam moves each
    coordinate by about its learning rate whatever the direction's scale) and none knows
    the objective.

    Args:
        net: one run's network parameters (pytree).
        u: (M,) body coordinates (unconstrained, :mod:`thesis.coopt.morphology`).
        keys: (E,) JAX keys, one per update: the directions, standard normal per
            coordinate, drawn from them.
        opt_c, opt_m: the controller's and the body's optimisers
            (:func:`thesis.ch7.bptt.make_optimizer`).

    Returns:
        (net, u) after the E updates.
    """
    leaves, tree = jax.tree.flatten(net)

    def step(carry, key):
        n_, u_, sc, sm = carry
        kc, km = jax.random.split(key)
        ks = jax.random.split(kc, len(leaves))
        gc = jax.tree.unflatten(tree, [jax.random.normal(k, x.shape, x.dtype)
                                       for k, x in zip(ks, jax.tree.leaves(n_))])
        gm = jax.random.normal(km, u_.shape, u_.dtype)
        dc, sc = opt_c.update(gc, sc, n_)
        dm, sm = opt_m.update(gm, sm, u_)
        return (jax.tree.map(jnp.add, n_, dc), u_ + dm, sc, sm), None

    with jax.numpy_dtype_promotion("standard"):  # optax's Adam mixes int counts and floats
        (net, u, _, _), _ = jax.lax.scan(step, (net, u, opt_c.init(net), opt_m.init(u)),
                                         keys)
    return net, u


def arms(ctx) -> xr.Dataset:
    """Experiment ``coopt/arms`` (§8.2): controller, morphology and both co-optimised.

    Dataset: dims ``arm`` (controller, morphology, joint), ``seed``, ``evaluation``,
    ``param``, ``start``. With ``random_direction_control``, also
    ``random_direction_final_speed`` (seed) [m/s]: the joint arm's negative control, the
    same number of updates along random directions (:func:`random_direction_steps`), from
    the same start, run after training so that no other variable changes. Variables:
    ``speed`` (arm, seed, evaluation) [m/s], the
    objective of the parameters before the k-th update; ``final_speed`` (arm, seed) of
    the parameters after the last; ``morphology`` (arm, seed, evaluation, param) the body
    before the k-th update and ``final_morphology`` (arm, seed, param) [units of
    ``param_unit``]; ``perturbed_speed`` (arm, seed, start) and ``initial_perturbed_speed``
    (start) [m/s]; ``skipped_updates`` (arm, seed); ``wall_seconds`` (scalar, wall clock).
    """
    cfg = ctx.config
    acfg = cfg["arms"]
    seeds = [int(s) for s in cfg["seeds"]]
    model, state0 = objective.build(cfg["body"])
    trot_p = objective.trot_params(cfg["trot"])
    n_steps = int(round(float(acfg["episode_s"]) / float(model.dt)))
    hidden = [int(h) for h in cfg["hidden"]]
    arm_names = list(ARMS)
    runs = [(a, s) for a in arm_names for s in seeds]
    R = len(runs)
    nets0 = [objective.init_net(seeding.key(ctx.root_seed, "coopt/arms", s), hidden)
             for s in seeds]
    net = jax.tree.map(lambda *x: jnp.stack(x), *[nets0[seeds.index(s)] for _, s in runs])
    net_init = net
    u = jnp.zeros((R, len(morphology.NAMES)), jnp.float32)
    mask_c = jnp.asarray([ARMS[a][0] for a, _ in runs], jnp.float32)
    mask_m = jnp.asarray([ARMS[a][1] for a, _ in runs], jnp.float32)
    opt_c = bptt.make_optimizer(acfg["learning_rate"], acfg["clip_norm"])
    opt_m = bptt.make_optimizer(acfg["morphology_learning_rate"], acfg["clip_norm"])
    st_c = jax.vmap(opt_c.init)(net)
    st_m = jax.vmap(opt_m.init)(u)
    batched = model.replace(batched=True)
    train = objective.speed_fn(batched, state0, trot_p, n_steps,
                               grad_decay=float(acfg["grad_decay"]), remat=bool(acfg["remat"]))
    # Adam minimises: the loss is minus the speed (as ch7.gait)
    vg = jax.value_and_grad(lambda n_, u_: -train(n_, u_), argnums=(0, 1))

    def update(n_, u_, sc, sm, mc, mm):
        loss, (gc, gm) = vg(n_, u_)
        speed = -loss
        gc = jax.tree.map(lambda g: g * mc, gc)
        gm = gm * mm
        ok = jnp.all(jnp.asarray([jnp.all(jnp.isfinite(x))
                                  for x in jax.tree.leaves((gc, gm))]))
        gc = jax.tree.map(lambda g: jnp.where(ok, g, 0.0), gc)
        gm = jnp.where(ok, gm, 0.0)
        dc, sc2 = opt_c.update(gc, sc, n_)
        dm, sm2 = opt_m.update(gm, sm, u_)
        keep = lambda new, old: jax.tree.map(lambda a, b: jnp.where(ok, a, b), new, old)  # noqa
        return (keep(jax.tree.map(jnp.add, n_, dc), n_), keep(u_ + dm, u_),
                keep(sc2, sc), keep(sm2, sm), speed, ok)

    step = jax.jit(jax.vmap(update))
    E = int(acfg["evaluations"])
    speeds = np.zeros((R, E))
    bodies = np.zeros((R, E, len(morphology.NAMES)))
    skipped = np.zeros(R, dtype=np.int64)
    t0 = time.perf_counter()
    for k in range(E):
        bodies[:, k] = np.asarray(morphology.to_physical(u))
        net, u, st_c, st_m, sp, ok = step(net, u, st_c, st_m, mask_c, mask_m)
        sp, ok = np.asarray(sp), np.asarray(ok)
        bad = np.flatnonzero(~np.isfinite(sp))
        if bad.size:
            raise SimulationDiverged(ctx.key, runs[bad[0]][1], k,
                                     f"arm {runs[bad[0]][0]}: gait speed")
        if acfg["nonfinite_grad"] == "raise" and not ok.all():
            i = int(np.flatnonzero(~ok)[0])
            raise SimulationDiverged(ctx.key, runs[i][1], k, f"arm {runs[i][0]}: gradient")
        skipped += ~ok
        speeds[:, k] = sp
        if k % max(1, E // 10) == 0 or k == E - 1:
            ctx.log.info("evaluation %d/%d: speed by arm %s", k + 1, E, {
                a: round(float(np.mean(sp[[i for i, r in enumerate(runs) if r[0] == a]])), 4)
                for a in arm_names})
    wall = time.perf_counter() - t0
    final_body = np.asarray(morphology.to_physical(u))
    # re-evaluation: the final parameters from the nominal and from perturbed starts
    push, lift = _starts(seeding.key(ctx.root_seed, "coopt/arms/starts", 0),
                         int(acfg["perturbed_starts"]), float(acfg["push_std"]),
                         float(acfg["lift_max"]))
    evaluate = objective.speed_fn(batched, state0, trot_p, n_steps)
    nominal = jax.jit(jax.vmap(lambda n_, u_: evaluate(n_, u_)))
    final = np.asarray(nominal(net, u))
    P = push.shape[0]
    from_starts = jax.jit(jax.vmap(jax.vmap(lambda n_, u_, p, h: evaluate(n_, u_, p, h),
                                            in_axes=(None, None, 0, 0)),
                                   in_axes=(0, 0, None, None)))
    perturbed = np.asarray(from_starts(net, u, jnp.asarray(push, jnp.float32),
                                       jnp.asarray(lift, jnp.float32)))
    # every run starts from a zero-output network on the built body: one initial gait
    init_pert = np.asarray(from_starts(jax.tree.map(lambda a: a[:1], net_init),
                                       jnp.zeros((1, u.shape[1]), jnp.float32),
                                       jnp.asarray(push, jnp.float32),
                                       jnp.asarray(lift, jnp.float32)))[0]
    if not (np.all(np.isfinite(final)) and np.all(np.isfinite(perturbed))):
        raise SimulationDiverged(ctx.key, seeds[0], E, "re-evaluation of the final gaits")
    control = None
    if bool(acfg.get("random_direction_control", False)):
        keys = jnp.stack([jax.random.split(seeding.key(
            ctx.root_seed, "coopt/arms/random_direction", s), E) for s in seeds])
        net_r, u_r = jax.jit(jax.vmap(lambda n_, u_, k: random_direction_steps(
            n_, u_, k, opt_c, opt_m)))(
            jax.tree.map(lambda *x: jnp.stack(x), *nets0),
            jnp.zeros((len(seeds), u.shape[1]), jnp.float32), keys)
        control = np.asarray(nominal(net_r, u_r))
        ctx.log.info("random-direction control, final speed: %s",
                     np.round(control, 3).tolist())
    S, A = len(seeds), len(arm_names)
    shape = lambda x: x.reshape((A, S) + x.shape[1:])  # noqa: E731  runs are arm-major
    ctx.log.info("final speed by arm: %s", {a: np.round(shape(final)[i], 3).tolist()
                                            for i, a in enumerate(arm_names)})
    ds = xr.Dataset(
        {
            "speed": (("arm", "seed", "evaluation"), shape(speeds), {
                "units": "m/s", "long_name": "mean forward spine velocity over the episode of "
                "the parameters before this evaluation's update (the objective)"}),
            "final_speed": (("arm", "seed"), shape(final), {
                "units": "m/s", "long_name": "objective of the parameters after the last "
                "update, nominal start"}),
            "morphology": (("arm", "seed", "evaluation", "param"), shape(bodies), {
                "units": "various", "long_name": "body parameters before this evaluation's "
                "update (units: param_unit)"}),
            "final_morphology": (("arm", "seed", "param"), shape(final_body), {
                "units": "various", "long_name": "body parameters after the last update "
                "(units: param_unit)"}),
            "perturbed_speed": (("arm", "seed", "start"), shape(perturbed), {
                "units": "m/s", "long_name": "objective of the final parameters from a "
                "perturbed start"}),
            "initial_perturbed_speed": (("start",), init_pert, {
                "units": "m/s", "long_name": "objective of the common initial parameters "
                "(open-loop trot, built body) from the same perturbed starts"}),
            "start_push": (("start", "axis"), push, {
                "units": "m/s", "long_name": "velocity added to every body at the start"}),
            "start_lift": (("start",), lift, {"units": "m",
                                              "long_name": "height added at the start"}),
            "skipped_updates": (("arm", "seed"), shape(skipped), {
                "units": "1", "long_name": "updates skipped for a non-finite gradient"}),
            "wall_seconds": ((), wall, {"units": "s", "long_name": "wall time of training "
                                        "after compilation (all runs)", **WALL_CLOCK}),
        },
        coords={"arm": arm_names, "seed": seeds, "axis": ["x", "y", "z"],
                "start": np.arange(P), **_param_coords()},
    )
    if control is not None:
        ds["random_direction_final_speed"] = ("seed", control, {
            "units": "m/s", "long_name": "objective after the joint arm's updates along "
            "random directions of the same step size (negative control), nominal start"})
    ds["evaluation"] = ("evaluation", np.arange(1, E + 1),
                        {"units": "1", "long_name": "gradient evaluation"})
    ds.attrs.update({
        "thesis_ref": "§8.2", "seeds": seeds, **_common_attrs(cfg, model),
        "episode_s": float(acfg["episode_s"]), "n_steps": n_steps, "evaluations": E,
        "learning_rate": float(acfg["learning_rate"]),
        "morphology_learning_rate": float(acfg["morphology_learning_rate"]),
        "grad_decay": float(acfg["grad_decay"]), "clip_norm": float(acfg["clip_norm"]),
        "n_params_controller": int(nets.n_params(nets0[0])),
        "n_params_morphology": len(morphology.NAMES),
    })
    return ds


def _nanmedian(a):
    """Median over the last axis ignoring NaN; NaN where a row has no value (no warning)."""
    a = np.asarray(a, float)
    out = np.full(a.shape[:-1], np.nan)
    ok = np.isfinite(a).any(-1)
    if ok.any():
        out[ok] = np.nanmedian(a[ok], axis=-1)
    return out


def _group_fns(model, state0, trot_p, n_steps, net0):
    """Per group: (theta0 (d,), batched returns fn ``(C, d) -> (C,)``)."""
    flat0, unravel = ravel_pytree(net0)
    u0 = jnp.zeros((len(morphology.NAMES),), jnp.float32)
    f = objective.speed_fn(model.replace(batched=True), state0, trot_p, n_steps)
    return {
        "controller": (flat0, jax.vmap(lambda th: f(unravel(th), u0))),
        "morphology": (u0, jax.vmap(lambda th: f(net0, th))),
    }


def _jacobians(model, state0, trot_p, horizons, net0, pushes):
    """Per start, the exact gradients of the mean speed over each horizon w.r.t. both
    groups: ``(controller (P, H, d_c), morphology (P, H, 8))`` (one rollout per start)."""
    spine = model.body(objective.SPINE)
    ctrl = objective.controller_fn(model, trot_p)
    n_max = int(max(horizons))
    idx = np.asarray(horizons, dtype=np.int64)
    flat0, unravel = ravel_pytree(net0)

    def speeds(th, u, push):
        m, s0 = morphology.apply(model, state0, morphology.to_physical(u))
        s0 = objective.perturb(s0, push, 0.0)
        _, tr = rollout(m, s0, ctrl, unravel(th), n_max, record=("body_vel",))
        cum = jnp.cumsum(tr["body_vel"][:, spine, 0])
        return cum[idx - 1] / jnp.asarray(idx, cum.dtype)

    jac = jax.jit(jax.jacrev(speeds, argnums=(0, 1)))
    u0 = jnp.zeros((len(morphology.NAMES),), jnp.float32)
    jc, jm = [], []
    for p in pushes:
        a, b = jac(flat0, u0, jnp.asarray(p, jnp.float32))
        jc.append(np.asarray(a))
        jm.append(np.asarray(b))
    return np.stack(jc), np.stack(jm)


def gradients(ctx) -> xr.Dataset:
    """Experiment ``coopt/gradients`` (§8.2): analytic gradients beside REINFORCE and ES.

    Dataset: dims ``seed`` (probe points), ``group`` (controller, morphology), ``horizon``
    (steps of ``horizons_steps``), ``estimator`` (reinforce, es), ``rollouts`` (log grid),
    ``block``, ``variance_horizon``, ``start``. Variables: ``cosine`` and
    ``relative_error`` (seed, group, horizon, estimator, rollouts, block) [1], NaN where
    a count has fewer blocks; ``median_cosine`` over blocks; ``rollouts_to_threshold``
    (seed, group, horizon, estimator) [1] (NaN: not reached within the budget);
    ``analytic_norm`` (seed, group, horizon) of the exact gradient [m/s per unit]; and
    over perturbed starts ``start_gradient_norm`` (seed, group, variance_horizon, start)
    and ``start_cosine`` (cosine with the unperturbed start's gradient, start 0 itself
    excluded: NaN), ``start_relative_spread`` (seed, group, variance_horizon) [1] =
    RMS over starts of |g_p - g_mean| / |g_mean|, ``start_nonfinite`` (count).
    """
    cfg = ctx.config
    gcfg = cfg["gradients"]
    seeds = [int(s) for s in gcfg["seeds"]]
    model, state0 = objective.build(cfg["body"])
    trot_p = objective.trot_params(cfg["trot"])
    hidden = [int(h) for h in cfg["hidden"]]
    horizons = [int(h) for h in gcfg["horizons_steps"]]
    n_max, chunk = int(gcfg["rollouts"]), int(gcfg["chunk"])
    if n_max % chunk:
        raise ValueError(f"coopt.gradients.rollouts ({n_max}) must be a multiple of "
                         f"coopt.gradients.chunk ({chunk})")
    repeats, sigma = int(gcfg["repeats"]), float(gcfg["sigma"])
    counts = est.log_grid(n_max)
    edges = np.union1d(est.boundaries(counts, n_max, repeats, 1),
                       est.boundaries(counts, n_max, repeats, 2))
    vh = sorted(set(int(h) for h in gcfg["variance_horizons_steps"]) | set(horizons))
    P = int(gcfg["variance_starts"])
    thr = float(gcfg["cos_threshold"])
    S, G, H, C = len(seeds), len(GROUPS), len(horizons), len(counts)
    cos = np.full((S, G, H, 2, C, repeats), np.nan)
    rel = np.full_like(cos, np.nan)
    need = np.full((S, G, H, 2), np.nan)
    an_norm = np.zeros((S, G, H))
    st_norm = np.full((S, G, len(vh), P), np.nan)
    st_cos = np.full_like(st_norm, np.nan)
    st_spread = np.full((S, G, len(vh)), np.nan)
    st_bad = np.zeros((S, G, len(vh)), dtype=np.int64)
    pushes = np.zeros((P, 3))
    pushes[1:, :2] = float(gcfg["start_push_std"]) * np.asarray(jax.random.normal(
        seeding.key(ctx.root_seed, "coopt/gradients/starts", 0), (P - 1, 2)))
    t0 = time.perf_counter()
    n_params = {}
    for si, s in enumerate(seeds):
        net0 = objective.init_net(seeding.key(ctx.root_seed, "coopt/gradients", s), hidden,
                                  zero_output=False,
                                  output_scale=float(gcfg["probe_output_scale"]))
        jc, jm = _jacobians(model, state0, trot_p, vh, net0, pushes)
        for gi, jg in enumerate((jc, jm)):
            n_params[GROUPS[gi]] = int(jg.shape[-1])
            for hi in range(len(vh)):
                g = jg[:, hi]
                fin = np.all(np.isfinite(g), axis=1)
                st_bad[si, gi, hi] = int((~fin).sum())
                st_norm[si, gi, hi] = np.where(fin, np.linalg.norm(np.where(
                    fin[:, None], g, 0.0), axis=1), np.nan)
                if fin[0]:
                    c = est.cosine(np.where(fin[:, None], g, 0.0), g[0])
                    st_cos[si, gi, hi] = np.where(fin, c, np.nan)
                    st_cos[si, gi, hi, 0] = np.nan
                if fin.sum() >= 2:
                    gf = g[fin]
                    mean = gf.mean(0)
                    st_spread[si, gi, hi] = float(np.sqrt(np.mean(np.sum(
                        (gf - mean) ** 2, 1))) / max(np.linalg.norm(mean), 1e-30))
        for hi, h in enumerate(horizons):
            for gi, (name, (theta0, ret)) in enumerate(
                    _group_fns(model, state0, trot_p, h, net0).items()):
                truth = (jc if name == "controller" else jm)[0, vh.index(h)]
                an_norm[si, gi, hi] = float(np.linalg.norm(truth))
                key = seeding.key(ctx.root_seed, f"coopt/gradients/{name}/{h}", s)
                sums = est.stream_sums(ret, theta0, sigma, key, n_max, chunk, edges)
                rf, es = est.block_estimates(sums, edges, counts, n_max, repeats, sigma)
                for ei, blocks in enumerate((rf, es)):
                    for ci, n in enumerate(counts):
                        if int(n) not in blocks:
                            continue
                        b = blocks[int(n)]
                        cos[si, gi, hi, ei, ci, :len(b)] = est.cosine(b, truth)
                        rel[si, gi, hi, ei, ci, :len(b)] = est.relative_error(b, truth)
                    med = _nanmedian(cos[si, gi, hi, ei])
                    need[si, gi, hi, ei] = est.first_above(counts, med, thr)
                ctx.log.info("seed %d %s horizon %d: |g| %.3g, rollouts to cos>%.2f: "
                             "reinforce %s, es %s", s, name, h, an_norm[si, gi, hi], thr,
                             need[si, gi, hi, 0], need[si, gi, hi, 1])
    wall = time.perf_counter() - t0
    med_cos = _nanmedian(cos)
    dims = ("seed", "group", "horizon", "estimator", "rollouts", "block")
    ds = xr.Dataset(
        {
            "cosine": (dims, cos, {"units": "1", "long_name": "cosine between an estimate "
                                   "from this many rollouts (one block) and the engine's "
                                   "exact gradient"}),
            "relative_error": (dims, rel, {"units": "1", "long_name": "|estimate - exact| / "
                                           "|exact|"}),
            "median_cosine": (dims[:-1], med_cos, {"units": "1",
                                                   "long_name": "median cosine over blocks"}),
            "rollouts_to_threshold": (dims[:4], need, {
                "units": "1", "long_name": "rollouts from which the median cosine stays above "
                "cos_threshold (NaN: not within the budget)"}),
            "analytic_norm": (dims[:3], an_norm, {
                "units": "m/s per unit", "long_name": "norm of the exact gradient"}),
            "start_gradient_norm": (("seed", "group", "variance_horizon", "start"), st_norm, {
                "units": "m/s per unit", "long_name": "norm of the exact gradient from a "
                "perturbed start (start 0 unperturbed)"}),
            "start_cosine": (("seed", "group", "variance_horizon", "start"), st_cos, {
                "units": "1", "long_name": "cosine of a perturbed start's exact gradient with "
                "the unperturbed start's"}),
            "start_relative_spread": (("seed", "group", "variance_horizon"), st_spread, {
                "units": "1", "long_name": "RMS over starts of |g - mean g| / |mean g| of the "
                "exact gradient"}),
            "start_nonfinite": (("seed", "group", "variance_horizon"), st_bad, {
                "units": "1", "long_name": "starts whose exact gradient was not finite"}),
            "start_push": (("start", "axis"), pushes, {
                "units": "m/s", "long_name": "velocity added to every body at the start"}),
            "wall_seconds": ((), wall, {"units": "s", "long_name": "wall time after "
                                        "compilation", **WALL_CLOCK}),
        },
        coords={"seed": seeds, "group": list(GROUPS), "horizon": horizons,
                "estimator": ["reinforce", "es"], "rollouts": counts.astype(np.int64),
                "block": np.arange(repeats), "variance_horizon": vh, "start": np.arange(P),
                "axis": ["x", "y", "z"]},
    )
    ds["horizon"].attrs.update({"units": "1", "long_name": "time steps of the rollout"})
    ds["variance_horizon"].attrs.update({"units": "1",
                                         "long_name": "time steps of the rollout"})
    ds.attrs.update({
        "thesis_ref": "§8.2", "seeds": seeds, **_common_attrs(cfg, model),
        "sigma": sigma, "cos_threshold": thr, "rollouts_max": n_max, "repeats": repeats,
        "probe_output_scale": float(gcfg["probe_output_scale"]),
        "start_push_std": float(gcfg["start_push_std"]),
        "n_params_controller": n_params.get("controller", 0),
        "n_params_morphology": n_params.get("morphology", 0),
    })
    return ds
