"""The 4-DoF robot arm of §7.3.2: reaching a fixed point (§7.3.2.1) and random points
(§7.3.2.2) with dense ReLU controllers trained by BPTT through the engine.

The four tricks of §7.3.2 are all used: the objective is the end-effector distance
averaged over every time step; the gradient is decayed by ``grad_decay`` per step
(``thesis.physics.rollout(grad_decay=...)``); the output layer starts at zero (the
initial policy keeps the arm still, commands = initial joint angles = 0); the gradient's
global L2 norm is clipped to ``clip_norm``.

The *error* of an episode (what the 4 cm / 1 cm and 10 cm / 5 cm thresholds are compared
with) is the end-effector distance averaged over the final ``eval_window_s`` of the
episode, like the original code's test loss (docs/sources.md#tpx-experiments); the time-averaged
objective itself cannot fall to a few cm because the arm needs time to travel to the target.

Fixed target (:func:`arm_fixed`): input = the current end-effector distance to the target
(§7.3.2.1), batch of 1, Adam; contrasted with separable CMA-ES on the same network.
Random targets (:func:`arm_random`): input = the target point, a batch of robots with
random reachable targets, Adam with the learning rate scaled by the previous mean error.
"""

from __future__ import annotations

import time

import jax
import jax.numpy as jnp
import numpy as np
import optax
import xarray as xr
from jax.flatten_util import ravel_pytree

from thesis import seeding
from thesis.ch7 import bptt, nets
from thesis.ch7.curves import pad_curves
from thesis.optim import cmaes
from thesis.physics import rollout
from thesis.physics.math import safe_norm
from thesis.physics.models import arm4
from thesis.store import WALL_CLOCK

__all__ = ["build", "servo_attrs", "episode_fn", "sample_targets", "arm_fixed", "arm_random",
           "cm_name"]

EFFECTOR = "sphere2"


def cm_name(threshold_m: float) -> str:
    """``0.04 -> "4cm"``: the suffix of ``evaluations_to_<x>`` variables."""
    return f"{round(float(threshold_m) * 100):d}cm"


def build(cfg: dict):
    """(model, state0) of the §7.3.2 arm with the profile's time step, solver iterations
    and effective servo torque (``servo_torque``, not the thesis's 30 N m: see
    ``thesis.physics.models.arm4``); no servo dead band (§7.3.2 states gain, torque and
    velocity only)."""
    return arm4(dt=cfg["dt"], solver_iterations=cfg["solver_iterations"],
                servo_max_torque=cfg["servo_torque"], servo_deadband=0.0)


def servo_attrs(cfg: dict) -> dict:
    """Dataset attributes recording the servo torque bound and solver sweeps used (the
    departure from the thesis's stated torque is declared in ``thesis.departures.ch7``
    and recorded with the result by ``thesis run``)."""
    return {
        "servo_torque_nm": float(cfg["servo_torque"]),
        "solver_iterations": int(cfg["solver_iterations"]),
    }


def episode_fn(model, state0, n_steps: int, window: int, *, inputs: str, grad_decay=1.0,
               remat=False):
    """``(params, target (3,)) -> (objective [m], error [m])`` of one episode.

    Args:
        inputs: ``"distance"`` (§7.3.2.1: the current end-effector distance to the target,
            1 input) or ``"target"`` (§7.3.2.2: the target point, 3 inputs).
        window: number of final steps whose mean distance is the error.
    Returns a function; objective = distance averaged over all steps.
    """
    ee = model.body(EFFECTOR)

    def controller(params, sens, memory, t):
        target = memory
        if inputs == "distance":
            x = safe_norm(sens["body_pos"][ee] - target)[None]
        else:
            x = target
        return nets.mlp_apply(params, x), memory

    def run(params, target):
        _, traj = rollout(model, state0, controller, params, n_steps, memory0=target,
                          grad_decay=grad_decay, remat=remat, record=("body_pos",))
        d = safe_norm(traj["body_pos"][:, ee] - target[None], axis=-1)
        return jnp.mean(d), jnp.mean(d[-window:])
    return run


def sample_targets(rng: np.random.Generator, n: int) -> np.ndarray:
    """``(n, 3)`` reachable targets [m], the original code's sampler
    (docs/sources.md#tpx-experiments): x, y uniform in [-1, 1], z in [0, 1], kept when
    x^2 + y^2 + z^2 lies in [sqrt(2)/2, 1], then z += 0.1 (the shoulder height)."""
    out = []
    while len(out) < n:
        p = rng.uniform([-1, -1, 0], [1, 1, 1], size=(4 * n, 3))
        r2 = np.sum(p * p, axis=1)
        out.extend(p[(r2 >= np.sqrt(2) / 2) & (r2 <= 1.0)])
    t = np.asarray(out[:n])
    t[:, 2] += 0.1
    return t


def _steps(cfg, model):
    dt = float(model.dt)
    return int(round(cfg["episode_s"] / dt)), max(1, int(round(cfg["eval_window_s"] / dt)))


def _gradient_fixed(run, params0, target, cfg, key, seed):
    """BPTT + Adam on ``run(params, target) -> (objective, error)`` for up to
    ``cfg["evaluations"]`` evaluations (§7.3.2.1); with ``cfg["stop_when_reached"]`` the run
    ends at the first error below every ``cfg["thresholds_m"]``. Returns (objectives,
    errors, wall seconds after the compiling first evaluation)."""
    opt = bptt.make_optimizer(cfg["learning_rate"], cfg["clip_norm"])
    stop_below = min(cfg["thresholds_m"]) if cfg.get("stop_when_reached", False) else -1.0
    vg = jax.jit(jax.value_and_grad(lambda p: run(p, target), has_aux=True))
    upd = jax.jit(lambda g, st, p: opt.update(g, st, p))
    params, st = params0, opt.init(params0)
    losses, errors, t0 = [], [], None
    for k in range(int(cfg["evaluations"])):
        (loss, err), g = vg(params)
        bptt.check_finite((loss, g), key, seed, k, "arm objective or gradient")
        if t0 is None:
            t0 = time.perf_counter()  # after the first (compiling) evaluation
        losses.append(float(loss))
        errors.append(float(err))
        if errors[-1] < stop_below:
            break
        u, st = upd(g, st, params)
        params = optax.apply_updates(params, u)
    return np.asarray(losses), np.asarray(errors), time.perf_counter() - t0


def _cmaes_fixed(run, params0, target, cfg, cma_seed, key, seed):
    ccfg = cfg["cmaes"]
    flat0, unravel = ravel_pytree(params0)
    batch = jax.jit(jax.vmap(lambda f: run(unravel(f), target)))
    state = cmaes.cmaes_init(cma_seed, np.asarray(flat0), ccfg["sigma0"],
                             popsize=ccfg["popsize"], CMA_diagonal=True)
    losses, errors, t0 = [], [], None
    while len(errors) < int(ccfg["evaluations"]):
        xs = cmaes.ask(state)
        loss, err = jax.block_until_ready(batch(jnp.asarray(xs, flat0.dtype)))
        bptt.check_finite((loss, err), key, seed, len(errors), "arm objective (CMA-ES)")
        if t0 is None:
            t0 = time.perf_counter()
        losses.extend(np.asarray(loss, float).tolist())
        errors.extend(np.asarray(err, float).tolist())
        cmaes.tell(state, -np.asarray(loss, float))
    n = int(ccfg["evaluations"])
    return np.asarray(losses[:n]), np.asarray(errors[:n]), time.perf_counter() - t0


def arm_fixed(ctx) -> xr.Dataset:
    """Experiment ``ch7/arm_fixed`` (§7.3.2.1): model evaluations until the end effector is
    within 4 cm and within 1 cm of (0.5, 0.5, 0.5) m, BPTT + Adam against CMA-ES.

    Dataset: dims ``method`` (gradient, cmaes), ``seed``, ``evaluation``; variables
    ``evaluations_to_4cm``, ``evaluations_to_1cm`` (NaN when never reached, with
    ``reached_4cm``/``reached_1cm`` = 0), ``error``, ``best_error``, ``objective``,
    ``wall_seconds``; attribute ``n_params``.
    """
    key = ctx.key
    cfg = ctx.config["arm_fixed"]
    seeds = [int(s) for s in cfg["seeds"]]
    model, state0 = build(cfg)
    n_steps, window = _steps(cfg, model)
    target = jnp.asarray(cfg["target"], state0.pos.dtype)
    run_g = episode_fn(model, state0, n_steps, window, inputs="distance",
                       grad_decay=cfg["grad_decay"], remat=cfg["remat"])
    # the CMA-ES population runs vmapped: the batched solver variant (Model.batched)
    run_f = episode_fn(model.replace(batched=True), state0, n_steps, window,
                       inputs="distance")
    sizes = [1, *cfg["hidden"], model.n_servo]
    methods = ["gradient"] + (["cmaes"] if cfg["cmaes"]["evaluations"] > 0 else [])
    res = {m: {"objective": [], "error": [], "wall": []} for m in methods}
    n_par = None
    for s in seeds:
        params0 = nets.mlp_init(seeding.key(ctx.root_seed, key, s), sizes)
        n_par = nets.n_params(params0)
        out = {"gradient": _gradient_fixed(run_g, params0, target, cfg, key, s)}
        if "cmaes" in methods:
            out["cmaes"] = _cmaes_fixed(run_f, params0, target, cfg,
                                        seeding.int_seed(ctx.root_seed, key + "/cmaes", s),
                                        key, s)
        for m in methods:
            obj, err, wall = out[m]
            res[m]["objective"].append(obj)
            res[m]["error"].append(err)
            res[m]["wall"].append(wall)
            ctx.log.info("arm_fixed seed %d %s: final error %.4f m, best %.4f m, %.1f s", s, m,
                         err[-1], np.min(err), wall)
    n_eval = max(len(e) for m in methods for e in res[m]["error"])
    dims = ("method", "seed")
    error = np.stack([pad_curves(res[m]["error"], n_eval) for m in methods])
    best = np.fmin.accumulate(np.where(np.isnan(error), np.inf, error), axis=-1)
    best = np.where(np.isnan(error), np.nan, best)
    data = {
        "distance": (("seed", "evaluation"), error[methods.index("gradient")], {
            "units": "m", "long_name": "gradient method: end-effector distance to the target "
            "(mean over the final eval_window_s) of the policy at each model evaluation"}),
        "error": (("method", "seed", "evaluation"), error, {
            "units": "m", "long_name": "end-effector distance averaged over the final "
            "eval_window_s of the episode (gradient: the current policy; cmaes: the "
            "candidate)"}),
        "best_error": (("method", "seed", "evaluation"), best, {
            "units": "m", "long_name": "lowest error so far"}),
        "objective": (("method", "seed", "evaluation"),
                      np.stack([pad_curves(res[m]["objective"], n_eval) for m in methods]), {
            "units": "m", "long_name": "objective: end-effector distance averaged over "
            "every time step"}),
        "wall_seconds": (dims, np.array([res[m]["wall"] for m in methods]), {
            "units": "s", "long_name": "wall time of the optimisation after compilation",
            **WALL_CLOCK}),
    }
    for thr in cfg["thresholds_m"]:
        name = cm_name(thr)
        hits = [[bptt.first_reach(b, thr) for b in best[i]] for i in range(len(methods))]
        data[f"evaluations_to_{name}"] = (dims, np.array([[h[0] for h in r] for r in hits]), {
            "units": "1", "long_name": f"model evaluations until the error is below "
            f"{thr} m (NaN: not within the budget)", "threshold_m": float(thr)})
        data[f"reached_{name}"] = (dims, np.array([[h[1] for h in r] for r in hits], np.int8), {
            "units": "1", "long_name": f"1 if the error fell below {thr} m within the budget"})
    ds = xr.Dataset(data, coords={"method": methods, "seed": seeds})
    ds["evaluation"] = ("evaluation", np.arange(1, n_eval + 1),
                        {"units": "1", "long_name": "model evaluation"})
    ds.attrs.update({
        "thesis_ref": "§7.3.2.1", "seeds": seeds, "n_params": int(n_par),
        "network": "-".join(str(x) for x in sizes), "episode_s": float(cfg["episode_s"]),
        "n_steps": n_steps, "eval_window_s": float(cfg["eval_window_s"]),
        "grad_decay": float(cfg["grad_decay"]), "clip_norm": float(cfg["clip_norm"]),
        "learning_rate": float(cfg["learning_rate"]),
        "gradient_evaluations": int(cfg["evaluations"]),
        "gradient_stop_when_reached": int(bool(cfg["stop_when_reached"])),
        "cmaes_evaluations": int(cfg["cmaes"]["evaluations"]),
        "cmaes_popsize": int(cfg["cmaes"]["popsize"]), "cmaes_variant": "separable (diagonal)",
        "target_m": list(map(float, cfg["target"])),
        **servo_attrs(cfg),
    })
    return ds


def arm_random(ctx) -> xr.Dataset:
    """Experiment ``ch7/arm_random`` (§7.3.2.2): update steps until the mean error over
    random targets falls below 10 cm and 5 cm.

    Each update simulates ``batch`` robots with fresh random targets (``sample_targets``)
    and applies Adam with learning rate ``lr_per_metre`` x the previous update's mean
    objective. Every ``eval_every`` updates the mean error on a fixed test batch is
    measured. Dataset: dims ``seed``, ``update``, ``check``; variables ``updates_to_10cm``,
    ``updates_to_5cm`` (NaN + ``reached_*`` = 0 when never), ``test_error`` (seed, check),
    ``train_objective`` (seed, update); sizes of the profile in the attributes.
    """
    key = ctx.key
    cfg = ctx.config["arm_random"]
    seeds = [int(s) for s in cfg["seeds"]]
    model, state0 = build(cfg)
    n_steps, window = _steps(cfg, model)
    sizes = [3, *cfg["hidden"], model.n_servo]
    n_upd, every = int(cfg["updates"]), int(cfg["eval_every"])
    checks = sorted(set(list(range(every, n_upd + 1, every)) + [n_upd]))
    dtype = state0.pos.dtype

    ee = model.body(EFFECTOR)
    bmodel = model.replace(batched=True)  # the batch of targets runs vmapped

    def controller(params, sens, memory, t):
        return nets.mlp_apply(params, memory), memory

    def batch_run(params, targets, grad_decay, remat):
        # jax.vmap of rollout, not thesis.physics.batched_rollout: with two host devices
        # its shard_map fails under jax.grad ("Context mesh ... Manual should match the
        # mesh of sharding ... Auto passed to broadcast_in_dim", rollout.py), so the batch
        # runs on one core.
        def one(target):
            return rollout(bmodel, state0, controller, params, n_steps, memory0=target,
                           grad_decay=grad_decay, remat=remat, record=("body_pos",))[1]
        traj = jax.vmap(one)(targets)
        d = safe_norm(traj["body_pos"][:, :, ee] - targets[:, None], axis=-1)  # (B, T)
        return jnp.mean(d), jnp.mean(d[:, -window:])

    def batch_loss(params, targets):
        return batch_run(params, targets, cfg["grad_decay"], cfg["remat"])

    def test_error(params, targets):
        return batch_run(params, targets, 1.0, False)[1]

    vg = jax.jit(jax.value_and_grad(batch_loss, has_aux=True))
    test = jax.jit(test_error)
    opt = bptt.make_optimizer(cfg["lr_per_metre"], cfg["clip_norm"], injectable=True)
    upd = jax.jit(lambda g, st, p: opt.update(g, st, p))
    curves, objs, dists, walls, n_par = [], [], [], [], None
    for s in seeds:
        params = nets.mlp_init(seeding.key(ctx.root_seed, key, s), sizes)
        n_par = nets.n_params(params)
        rng = seeding.rng(ctx.root_seed, key + "/targets", s)
        test_targets = jnp.asarray(sample_targets(
            seeding.rng(ctx.root_seed, key + "/test", s), int(cfg["test_batch"])), dtype)
        st = opt.init(params)
        prev, obj_curve, dist_curve, test_curve, t0 = None, [], [], [], None
        for u in range(1, n_upd + 1):
            targets = jnp.asarray(sample_targets(rng, int(cfg["batch"])), dtype)
            (obj, err), g = vg(params, targets)
            bptt.check_finite((obj, g), key, s, u, "arm objective or gradient")
            if t0 is None:
                t0 = time.perf_counter()
            obj_curve.append(float(obj))
            dist_curve.append(float(err))
            prev = float(obj) if prev is None else prev
            st[-1].hyperparams["learning_rate"] = jnp.asarray(cfg["lr_per_metre"] * prev)
            prev = float(obj)
            up, st = upd(g, st, params)
            params = optax.apply_updates(params, up)
            if u in checks:
                e = float(test(params, test_targets))
                bptt.check_finite(e, key, s, u, "arm test error")
                test_curve.append(e)
                ctx.log.info("arm_random seed %d update %d: objective %.4f m, test error "
                             "%.4f m", s, u, obj, e)
        walls.append(time.perf_counter() - t0)
        curves.append(test_curve)
        objs.append(obj_curve)
        dists.append(dist_curve)
    test_err = np.array(curves)
    data = {
        "test_error": (("seed", "check"), test_err, {
            "units": "m", "long_name": "mean over the fixed test targets of the end-effector "
            "distance averaged over the final eval_window_s"}),
        "distance": (("seed", "update"), np.array(dists), {
            "units": "m", "long_name": "training batch mean of the end-effector distance "
            "(mean over the final eval_window_s) before each update"}),
        "train_objective": (("seed", "update"), np.array(objs), {
            "units": "m", "long_name": "batch mean of the time-averaged end-effector "
            "distance (the objective) before each update"}),
        "wall_seconds": (("seed",), np.array(walls), {
            "units": "s", "long_name": "wall time of training after compilation",
            **WALL_CLOCK}),
    }
    for thr in cfg["thresholds_m"]:
        name = cm_name(thr)
        hits = [bptt.first_reach(c, thr) for c in test_err]
        upd_at = [float(checks[int(h[0]) - 1]) if h[1] else float("nan") for h in hits]
        data[f"updates_to_{name}"] = (("seed",), np.array(upd_at), {
            "units": "1", "long_name": f"update steps until the mean test error is below "
            f"{thr} m (resolution eval_every; NaN: not within the budget)",
            "threshold_m": float(thr)})
        data[f"reached_{name}"] = (("seed",), np.array([h[1] for h in hits], np.int8), {
            "units": "1", "long_name": f"1 if the mean test error fell below {thr} m"})
    ds = xr.Dataset(data, coords={"seed": seeds})
    ds["update"] = ("update", np.arange(1, n_upd + 1), {"units": "1", "long_name": "update step"})
    ds["check"] = ("check", np.array(checks), {"units": "1",
                                               "long_name": "update step after which the "
                                               "test error was measured"})
    ds.attrs.update({
        "thesis_ref": "§7.3.2.2", "seeds": seeds, "n_params": int(n_par),
        "network": "-".join(str(x) for x in sizes), "hidden": list(map(int, cfg["hidden"])),
        "batch": int(cfg["batch"]), "updates": n_upd, "test_batch": int(cfg["test_batch"]),
        "episode_s": float(cfg["episode_s"]), "n_steps": n_steps,
        "eval_window_s": float(cfg["eval_window_s"]), "grad_decay": float(cfg["grad_decay"]),
        "clip_norm": float(cfg["clip_norm"]), "lr_per_metre": float(cfg["lr_per_metre"]),
        **servo_attrs(cfg),
    })
    return ds
