"""Throwing a ball (thesis §7.2.1): gradient descent through the rollout against CMA-ES.

The 1 m ball (mu = 1.0, restitution 0.5; ``thesis.physics.models.ball``) starts above the
origin; the six parameters are its initial linear velocity v0 [m/s] and angular velocity
w0 [rad/s]. After ``horizon_s`` (5 s) it must rest at ``target_xy`` = (10, 0) on the
ground: the position error is ``|p_T - (10, 0, r)|`` [m] (r the radius: resting on the
ground) and the velocity error ``|(v_T, w_T)|`` (the norm of the 6-vector, as in the
original code's loss, docs/sources.md#tpx-experiments). Both methods minimise the original's loss
``position error + velocity error`` from the same seeded starting point and stop when
both errors are below their tolerances (0.01 m and 0.01 m/s) or the budget is spent.

* gradient descent: Adam on the BPTT gradient of the 5 s rollout (one model evaluation
  with its gradient per iteration), with the original's moment rates and piecewise
  constant learning-rate schedule (docs/sources.md#tpx-experiments, config ``ch7.ball.gradient``);
* CMA-ES (``thesis.optim.cmaes``: seeded, silent, no files), one batched forward
  evaluation per generation; its ``iterations`` are model evaluations (candidates), counted
  up to the first candidate that meets both tolerances.

Wall times exclude compilation (each jitted function is compiled once before the clock
starts; compile times are stored as attributes).

Why gradient descent can stall here (measured, float64). From seed 0 Adam
ends at v0 ~ (3.09, -0.33, -2.05), w0 ~ (-1.77, -1.93, 0): the ball is at the target
(position error < 0.03 m) but rolls at 1.93 m/s (velocity error 4.3). The gradient is
right: AD equals central differences to 5 digits in all six components
(``tests/ch7/test_ball.py``). The landscape is the obstacle:

* once the ball rolls, its speed is fixed by the angular momentum about the contact line,
  ``(m r v_x + I w_y) / (m r + I / r)``, which no later contact changes, so the velocity
  error depends on (v_x, w_y) only; to rest, the ball must land with that momentum zero;
* with mu = 1 the landing impulse removes the slip in one step, after which the horizontal
  motion no longer depends on the vertical one, and the landing time is an integer
  number of steps: the derivative w.r.t. the throw's vertical speed v_z is exactly 0
  (AD and differences with eps 1e-7 ... 1e-1 agree on the velocity error). The
  continuous-time sensitivity of the final position, ``(v_x - v_roll) dt_land/dv_z``
  (0.069 m per m/s there; the secant of p_x(T) over v_z +- 0.5, landing steps 25-31, is
  0.067, the AD derivative 0), is lost by time stepping without a time-of-impact
  correction (the DiffTaichi observation, Hu et al. 2020);
* so from a downward throw the gradient cannot raise the throw (the high-throw solutions
  CMA-ES finds, like the original's ``velocity2`` = (3.74, 0, 12, 0, 4.686, 0),
  docs/sources.md#tpx-ball: with the quirk inertia and w_y = -4.686 in our sign convention it ends
  with velocity error 0.008, position error 0.58 m here), and at a fixed landing time a resting
  solution needs ``v_x ~ 10 / t_land`` and a backspin of ``-m r v_x / I``, tens of units away while
  the schedule's steps are 0.01 after iteration 100. The quirk inertia (docs/sources.md#tpx-bodies)
  stalls the same way (seed 0: velocity error 3.97 after 200 iterations).

The time-of-impact correction (``physics.step.toi_correction``, config
``ch7.ball.toi_correction``, on by default) restores the landing-time derivative (at the
point above: AD 0.0676 m per m/s against the secant 0.068;
``tests/ch7/test_ball.py``). Measured with it (default profile, 3 seeds):
gradient descent raises the throw on seeds 0 and 2 (v_z 13.5 m/s, backspin
-16.5 / -13.5 rad/s, the family CMA-ES converges to) but still ends unconverged (loss
3.59 / 4.28 / 3.69 against 4.34 / 4.19 / 4.15 without), with a gradient norm of about 4 at
the end: the schedule's 0.01 steps after iteration 100 crawl over a loss that is bumpy
along the way to CMA-ES's solution (every change in the number of bounces is a step).
"""

from __future__ import annotations

import time

import jax
import jax.numpy as jnp
import numpy as np
import optax
import xarray as xr

from thesis import seeding
from thesis.ch7 import bptt
from thesis.ch7.curves import pad_curves
from thesis.optim import cmaes
from thesis.physics import rollout
from thesis.physics.math import safe_norm
from thesis.physics.models import ball as ball_model
from thesis.store import WALL_CLOCK

__all__ = ["build", "errors_fn", "gradient_fns", "run_gradient", "run_cmaes", "ball"]

KEY = "ch7/ball"


def build(cfg: dict):
    """(model, state0) of the ball with the profile's physics settings."""
    return ball_model(dt=cfg["dt"], solver_iterations=cfg["solver_iterations"],
                      toi_correction=bool(cfg["toi_correction"]))


def _no_control(params, sens, memory, t):
    return jnp.zeros((0,), sens["body_pos"].dtype), memory


def errors_fn(model, state0, n_steps: int, target_xy):
    """``x (6,) -> (position_error [m], velocity_error [m/s or rad/s])`` after ``n_steps``.

    ``x`` = (v0, w0) replaces the initial velocities of the single body.
    """
    radius = model.csphere_radius[0]
    target = jnp.array([target_xy[0], target_xy[1], 0.0], state0.pos.dtype)
    target = target.at[2].set(radius)

    def f(x):
        s = state0.replace(vel=x[None, :3].astype(state0.vel.dtype),
                           angvel=x[None, 3:].astype(state0.vel.dtype))
        final, _ = rollout(model, s, _no_control, None, n_steps, record=())
        pos_err = safe_norm(final.pos[0] - target)
        vel_err = safe_norm(jnp.concatenate([final.vel[0], final.angvel[0]]))
        return pos_err, vel_err
    return f


def _schedule(pairs):
    """Piecewise-constant learning rate from ``[[iteration, lr], ...]`` (0-based)."""
    pairs = sorted((int(i), float(v)) for i, v in pairs)
    if not pairs or pairs[0][0] != 0:
        raise ValueError("ch7.ball.gradient.lr_schedule must start at iteration 0")
    boundaries = {i: v / prev for (i, v), (_, prev) in zip(pairs[1:], pairs[:-1])}
    return optax.piecewise_constant_schedule(pairs[0][1], boundaries)


def gradient_fns(err, gcfg: dict):
    """Jitted ``(value_and_grad, optimizer update, optimizer)`` of the gradient method."""
    def loss(x):
        p, v = err(x)
        return p + v, (p, v)

    vg = jax.jit(jax.value_and_grad(loss, has_aux=True))
    opt = bptt.make_optimizer(0.0, gcfg["clip_norm"], b1=gcfg["beta1"], b2=gcfg["beta2"],
                              schedule=_schedule(gcfg["lr_schedule"]))
    update = jax.jit(lambda g, st, x: opt.update(g, st, x))
    return vg, update, opt


def run_gradient(fns, x0, gcfg: dict, tol_pos: float, tol_vel: float, seed: int):
    """Adam on the BPTT gradient from ``x0`` until both tolerances are met.

    Args:
        fns: :func:`gradient_fns` of the error function.

    Returns:
        dict with ``iterations`` (gradient evaluations until the evaluated point met the
        tolerances; NaN if never), ``converged``, ``wall_seconds``, ``losses``
        (per evaluation), ``pos_err``/``vel_err`` of the last evaluated point, ``x``.
    """
    vg, update, opt = fns
    x = jnp.asarray(x0, jnp.float32)
    st = opt.init(x)
    t_compile = time.perf_counter()
    jax.block_until_ready(vg(x))
    jax.block_until_ready(update(jnp.zeros_like(x), st, x))
    compile_s = time.perf_counter() - t_compile
    losses, converged, p, v = [], False, np.nan, np.nan
    t0 = time.perf_counter()
    for it in range(int(gcfg["max_iterations"])):
        (lv, (p, v)), g = vg(x)
        bptt.check_finite((lv, g), KEY, seed, it, "gradient-descent loss or gradient")
        losses.append(float(lv))
        if float(p) < tol_pos and float(v) < tol_vel:
            converged = True
            break
        upd, st = update(g, st, x)
        x = optax.apply_updates(x, upd)
    wall = time.perf_counter() - t0
    return dict(iterations=float(len(losses)) if converged else float("nan"),
                converged=converged, wall_seconds=wall, compile_seconds=compile_s,
                losses=np.asarray(losses), pos_err=float(p), vel_err=float(v),
                x=np.asarray(x))


def run_cmaes(batch, x0, ccfg: dict, tol_pos: float, tol_vel: float, cma_seed: int,
              seed: int):
    """Seeded CMA-ES from ``x0`` until a candidate meets both tolerances.

    ``batch`` is the jitted, vmapped error function ``(n, 6) -> ((n,), (n,))``.

    Returns the same fields as :func:`run_gradient`; ``losses`` is the loss of every
    evaluated candidate in order and ``iterations`` the number of candidates evaluated up
    to and including the first one that met both tolerances.
    """
    state = cmaes.cmaes_init(cma_seed, x0, ccfg["sigma0"], popsize=ccfg["popsize"])
    t_compile = time.perf_counter()
    jax.block_until_ready(batch(jnp.zeros((int(ccfg["popsize"]), 6), jnp.float32)))
    compile_s = time.perf_counter() - t_compile
    losses, converged, n_eval = [], False, 0
    best = (np.inf, np.nan, np.nan, np.asarray(x0, float))
    t0 = time.perf_counter()
    while n_eval < int(ccfg["max_evaluations"]) and not converged:
        xs = cmaes.ask(state)
        p, v = jax.block_until_ready(batch(jnp.asarray(xs, jnp.float32)))
        p, v = np.asarray(p, float), np.asarray(v, float)
        bptt.check_finite((p, v), KEY, seed, n_eval, "CMA-ES candidate loss")
        for i in range(xs.shape[0]):
            n_eval += 1
            losses.append(p[i] + v[i])
            if p[i] + v[i] < best[0]:
                best = (p[i] + v[i], p[i], v[i], xs[i])
            if p[i] < tol_pos and v[i] < tol_vel:
                converged = True
                best = (p[i] + v[i], p[i], v[i], xs[i])
                break
        if not converged:
            cmaes.tell(state, -(p + v))
    wall = time.perf_counter() - t0
    return dict(iterations=float(n_eval) if converged else float("nan"),
                converged=converged, wall_seconds=wall, compile_seconds=compile_s,
                losses=np.asarray(losses), pos_err=float(best[1]), vel_err=float(best[2]),
                x=np.asarray(best[3]))


def ball(ctx) -> xr.Dataset:
    """Experiment ``ch7/ball`` (§7.2.1): iterations and wall time of BPTT gradient descent
    and CMA-ES on the ball throw, per seed.

    Dataset: dims ``method`` (gradient, cmaes), ``seed``, ``parameter`` (6),
    ``gd_iteration``, ``cmaes_evaluation``; variables ``iterations``, ``wall_seconds``,
    ``final_position_error``, ``final_velocity_error``, ``converged``, ``start``,
    ``solution``, ``gradient_loss``, ``cmaes_loss``.
    """
    cfg = ctx.config["ball"]
    seeds = [int(s) for s in cfg["seeds"]]
    model, state0 = build(cfg)
    n_steps = int(round(cfg["horizon_s"] / float(model.dt)))
    err = errors_fn(model, state0, n_steps, cfg["target_xy"])
    tol_p, tol_v = float(cfg["tol_position_m"]), float(cfg["tol_velocity_mps"])
    gfns = gradient_fns(err, cfg["gradient"])
    # the CMA-ES population runs vmapped: the batched solver variant (Model.batched)
    batch = jax.jit(jax.vmap(errors_fn(model.replace(batched=True), state0, n_steps,
                                       cfg["target_xy"])))
    rows = {m: [] for m in ("gradient", "cmaes")}
    starts = []
    for s in seeds:
        x0 = seeding.rng(ctx.root_seed, KEY + "/start", s).normal(0.0, cfg["start_std"], 6)
        starts.append(x0)
        ctx.log.info("ball seed %d: start %s", s, np.round(x0, 3))
        rows["gradient"].append(run_gradient(gfns, x0, cfg["gradient"], tol_p, tol_v, s))
        rows["cmaes"].append(run_cmaes(batch, x0, cfg["cmaes"], tol_p, tol_v,
                                       seeding.int_seed(ctx.root_seed, KEY + "/cmaes", s), s))
        for m in rows:
            r = rows[m][-1]
            ctx.log.info("  %s: iterations %s, %.2f s, errors %.4g m / %.4g", m,
                         r["iterations"], r["wall_seconds"], r["pos_err"], r["vel_err"])
    methods = ["gradient", "cmaes"]

    def stack(field):
        return np.array([[r[field] for r in rows[m]] for m in methods], dtype=float)

    gd_curves = [r["losses"] for r in rows["gradient"]]
    cma_curves = [r["losses"] for r in rows["cmaes"]]
    dims = ("method", "seed")
    ds = xr.Dataset(
        {
            "iterations": (dims, stack("iterations"), {
                "units": "1", "long_name": "model evaluations until both tolerances are met "
                "(gradient: iterations with gradient; cmaes: candidates); NaN = not reached"}),
            "wall_seconds": (dims, stack("wall_seconds"), {
                "units": "s", "long_name": "wall time of the optimisation (compilation "
                "excluded; until convergence or the budget)", **WALL_CLOCK}),
            "final_position_error": (dims, stack("pos_err"), {
                "units": "m", "long_name": "|p_T - target| of the returned solution"}),
            "final_velocity_error": (dims, stack("vel_err"), {
                "units": "m/s", "long_name": "|(v_T, w_T)| of the returned solution "
                "(w in rad/s counted as is, as in the original loss)"}),
            "converged": (dims, stack("converged").astype(np.int8), {
                "units": "1", "long_name": "1 if both tolerances were met within the budget"}),
            "start": (("seed", "parameter"), np.array(starts), {
                "units": "m/s or rad/s", "long_name": "starting point (v0, w0) of both methods"}),
            "solution": (("method", "seed", "parameter"),
                         np.array([[r["x"] for r in rows[m]] for m in methods]), {
                "units": "m/s or rad/s", "long_name": "returned (v0, w0)"}),
            "gradient_loss": (("seed", "gd_iteration"),
                              pad_curves(gd_curves), {
                "units": "1", "long_name": "loss (position + velocity error) per gradient "
                "iteration"}),
            "cmaes_loss": (("seed", "cmaes_evaluation"),
                           pad_curves(cma_curves), {
                "units": "1", "long_name": "loss of each CMA-ES candidate in evaluation "
                "order"}),
        },
        coords={"method": methods, "seed": seeds,
                "parameter": ["vx", "vy", "vz", "wx", "wy", "wz"]},
    )
    ds["gd_iteration"] = ("gd_iteration", np.arange(1, ds.sizes["gd_iteration"] + 1),
                          {"units": "1", "long_name": "gradient iteration"})
    ds["cmaes_evaluation"] = ("cmaes_evaluation", np.arange(1, ds.sizes["cmaes_evaluation"] + 1),
                              {"units": "1", "long_name": "CMA-ES model evaluation"})
    ds.attrs.update({
        "thesis_ref": "§7.2.1", "seeds": seeds, "horizon_s": float(cfg["horizon_s"]),
        "toi_correction": int(bool(cfg["toi_correction"])),
        "n_steps": n_steps, "dt": float(model.dt), "tol_position_m": tol_p,
        "tol_velocity_mps": tol_v, "cmaes_popsize": int(cfg["cmaes"]["popsize"]),
        "gradient_compile_seconds": float(rows["gradient"][0]["compile_seconds"]),
        "cmaes_compile_seconds": float(rows["cmaes"][0]["compile_seconds"]),
        "gradient_max_iterations": int(cfg["gradient"]["max_iterations"]),
        "cmaes_max_evaluations": int(cfg["cmaes"]["max_evaluations"]),
    })
    return ds
