"""``thesis bench solver`` (registry ``model/solver``): how many solver sweeps the Oncilla
and the Puppy II need, per sweep order, against the direct solution of the same step.

States. Each model is built at its chapter's configuration (the Oncilla of ``ch4.model``,
the Puppy II of ``ch5.model``) in float64 and walks a published gait from its build
pose: the Oncilla each gait of ``oncilla_gaits`` (Tab. 3.1a's half ellipse, Tab. 3.1b's
spline; :func:`thesis.modelcheck.targets.published_gaits`) under the ch4 protocol
(``ch4.protocol.settle``, then the 1-s self-transition of
:data:`thesis.modelcheck.checks.SELF_TRANSITION`), the Puppy II each of ``puppy_gaits``
(:func:`thesis.ch5.gaits.commands` at its frequency on the model's default floor).
At each of ``times`` [s] the state and the step's servo commands are saved; nothing is
random (no seed is drawn) and nothing is read from outside the run.

Problems. A saved state's step, up to its solve (:func:`thesis.physics.step.solver_problem`,
warm start included), is solved by every order of ``orders`` (sweep order, relaxation,
contact relaxation, relaxation of the other scalar rows, momentum) at every sweep count
of ``sweeps``, and by the ``reference`` settings at ``reference.sweeps``: many sweeps in
float64, whose natural residual (:func:`thesis.physics.solver.solve`, ``report``) is
recorded beside it and is at round-off where the reference has converged. All orders
share the reference's fixed point (the projected updates' fixed point does not depend on
the relaxation or the order), so the reference is the direct solution of the step's LCP.

Measure. The relative error of a solve is the kinetic-energy norm of its velocity error
over that of the constraints' whole velocity change,
``||v - v*||_M / ||v* - v0||_M`` with ``||u||_M^2 = sum_b m_b |u_b|^2 + w_b . I_b w_b``
(the bodies' masses and world inertias). ``sweeps_to`` is the fewest sweeps of the
``sweeps`` ladder at which every saved state of a model is within a target of
``targets`` (NaN: not within the ladder).
"""

from __future__ import annotations

import importlib

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from thesis.gaits import runner as R
from thesis.gaits import trajectories as T
from thesis.modelcheck import checks as M
from thesis.modelcheck import targets as TG
from thesis.physics.models.oncilla_config import oncilla_kwargs
from thesis.physics.solver_settings import solver_fields

O = importlib.import_module("thesis.physics.models.oncilla")
S = importlib.import_module("thesis.physics.step")

__all__ = ["solver", "oncilla_states", "puppy_states", "relative_errors", "solve_ladder"]

#: The models of the bench, in dataset order.
MODELS = ("oncilla", "puppy")


def _solver_kwargs(order: dict) -> dict:
    """Model fields of one ``orders`` / ``reference`` entry (float64 states); an entry
    without a contact or row relaxation takes the blocks' (None), not the model's."""
    return solver_fields({"contact_relaxation": None, "row_relaxation": None, **order},
                         jnp.float64)


def _march(model, state, action_at, times):
    """[(state, action)] at each of ``times`` [s]: the model stepped from ``state`` with
    the servo actions ``action_at(t)``, and the action of the step that follows."""
    def body(s, _):
        return S.step(model, s, action_at(s.time)), None

    run = jax.jit(lambda s, n: jax.lax.scan(body, s, None, length=n)[0], static_argnums=1)
    out, k = [], 0
    for t in times:
        n = int(round(float(t) / float(model.dt))) - k
        if n < 0:
            raise ValueError(f"solver bench: times must increase, got {times}")
        state = run(state, n) if n else state
        k += n
        out.append((state, action_at(state.time)))
    return out


def oncilla_states(model_cfg: dict, gait: str, times, settle: float):
    """(model, [(state, action)]): the Oncilla of ``model_cfg`` (a ``ch4.model`` section,
    every key of it: feet, drives and solver, :func:`oncilla_kwargs`) in float64 walking
    the published gait ``gait`` (a :func:`published_gaits` name) under the ch4 protocol
    (``settle`` [s], then the self-transition), saved at ``times`` [s] (module
    docstring)."""
    model, state = O.oncilla(**oncilla_kwargs(model_cfg), dtype=jnp.float64)
    g = {x.name: x for x in TG.published_gaits()}[gait]
    family = T.FAMILIES[g.family]()
    fn = M.command_fn(float(settle), M.SELF_TRANSITION, family)
    p = jnp.asarray(np.asarray(g.params, np.float64))
    mem = dict(p_from=p, p_to=p, stand=jnp.zeros((), jnp.float64))

    def action_at(t):
        return O.commands_to_action(fn(mem, R.command_time(t), None)).astype(jnp.float64)

    return model, _march(model, state, action_at, times)


def puppy_states(ch5: dict, gait: str, frequency: float, times):
    """(model, [(state, action)]): the Puppy II of ``ch5["model"]`` in float64 walking
    ``gait`` at ``frequency`` [Hz] (:func:`thesis.ch5.gaits.commands` with
    ``ch5["gaits"]``, held per sample of ``ch5["recordings"]["sample_rate"]``), saved
    at ``times`` [s]."""
    from thesis.ch5 import gaits as G

    pup = importlib.import_module("thesis.physics.models.puppy")
    mc = ch5["model"]
    model, state = pup.puppy(dt=float(mc["dt"]), solver_iterations=int(mc["solver_iterations"]),
                             skin_ratio=float(mc["skin_ratio"]), dtype=jnp.float64)
    rate = float(ch5["recordings"]["sample_rate"])
    n = int(np.ceil(max(times) * rate)) + 2
    # a deterministic gait: the generator is not drawn from (only the random gait is)
    cmds = jnp.asarray(G.commands(gait, float(frequency), n, rate, ch5["gaits"],
                                  np.random.default_rng(0)), jnp.float64)

    def action_at(t):
        k = jnp.floor(t * rate + 1e-6).astype(jnp.int32)
        return cmds[jnp.clip(k, 0, n - 1)]

    return model, _march(model, state, action_at, times)


def _problems(model, saved):
    """The saved states' solver problems, stacked on a leading axis: (arrays, statics)
    with ``arrays`` the traced inputs of :func:`thesis.physics.solver.solve` and
    ``statics`` its static index arrays (one set for all states); and the stacked
    (K, n_body, 3, 3) body rotations."""
    probs = [S.solver_problem(model, s, a) for s, a in saved]
    keys = [k for k in S.SOLVER_ARGS]
    static = {k: {kk: vv for kk, vv in probs[0][k].items() if not isinstance(vv, jax.Array)}
              for k in keys if isinstance(probs[0][k], dict)}

    def arrays(p):
        return {k: ({kk: vv for kk, vv in p[k].items() if isinstance(vv, jax.Array)}
                    if isinstance(p[k], dict) else p[k]) for k in keys}

    stacked = jax.tree.map(lambda *x: jnp.stack(x), *[arrays(p) for p in probs])
    rot = np.stack([np.asarray(s.rot, np.float64) for s, _ in saved])
    return stacked, static, rot


def solve_ladder(model, stacked, static, sweeps) -> tuple[np.ndarray, np.ndarray]:
    """Velocities (len(sweeps), K, n_body + 1, 6) and relative residuals
    (len(sweeps), K) of the K stacked problems solved by ``model``'s solver at each
    sweep count of ``sweeps``."""
    from thesis.physics import solver

    def one(arr, mk):
        p = {k: ({**v, **static[k]} if k in static else v) for k, v in arr.items()}
        v, _, _, res = solver.solve(mk, *(p[k] for k in S.SOLVER_ARGS), report=True)
        return v, res

    vs, rs = [], []
    for k in sweeps:
        mk = model.replace(solver_iterations=int(k))
        v, r = jax.jit(jax.vmap(lambda a: one(a, mk)))(stacked)
        vs.append(np.asarray(v))
        rs.append(np.asarray(r))
    return np.stack(vs), np.stack(rs)


def relative_errors(model, rot, v, v_ref, v0) -> np.ndarray:
    """``||v - v_ref||_M / ||v_ref - v0||_M`` (module docstring) of velocities ``v``
    (..., K, n_body + 1, 6) against ``v_ref`` and ``v0`` (K, n_body + 1, 6); ``rot``
    (K, n_body, 3, 3)."""
    nb = model.n_body
    mass = np.asarray(model.body_mass, np.float64)
    inertia = np.einsum("kbij,bjl,kbml->kbim", rot, np.asarray(model.body_inertia, np.float64),
                        rot)

    def norm(u):
        u = np.asarray(u, np.float64)[..., :nb, :]
        lin = np.sum(mass * np.sum(u[..., :3] ** 2, -1), -1)
        ang = np.einsum("...bi,...bij,...bj->...", u[..., 3:], inertia, u[..., 3:])
        return np.sqrt(lin + ang)

    return norm(v - v_ref) / np.maximum(norm(v_ref - v0), 1e-300)


def _sweeps_to(err: np.ndarray, sweeps, target: float) -> float:
    """Fewest sweeps of the ladder at which every state's error is <= target (NaN)."""
    ok = np.all(err <= target, axis=-1)
    return float(np.asarray(sweeps)[ok.argmax()]) if ok.any() else np.nan


def solver(ctx) -> xr.Dataset:
    """``thesis bench solver`` (registry ``model/solver``; module docstring): relative
    errors of every sweep order at every sweep count of ``physics.solver_bench`` on
    saved Oncilla and Puppy II states, and the sweeps each order needs to reach each
    target.

    Returns a dataset with dims ``model``, ``order``, ``sweeps``, ``state`` (saved
    states, padded with NaN where a model has fewer) and ``target``.
    """
    full = ctx.full_config
    cfg = full["physics"]["solver_bench"]
    times = [float(t) for t in cfg["times"]]
    sweeps = [int(k) for k in cfg["sweeps"]]
    targets = [float(t) for t in cfg["targets"]]
    orders = list(cfg["orders"])
    names = [str(o["name"]) for o in orders]
    ref_cfg = cfg["reference"]
    settle = float(full["ch4"]["protocol"]["settle"])
    with jax.enable_x64(True):  # float64 states and solves, restored after
        per_model = {}
        for name in MODELS:
            saved, model, labels = [], None, []
            if name == "oncilla":
                for gait in cfg["oncilla_gaits"]:
                    model, st = oncilla_states(full["ch4"]["model"], str(gait), times, settle)
                    saved += st
                    labels += [f"{gait} t={t:g}" for t in times]
            else:
                for g in cfg["puppy_gaits"]:
                    model, st = puppy_states(full["ch5"], str(g["gait"]), float(g["frequency"]),
                                             times)
                    saved += st
                    labels += [f"{g['gait']} {float(g['frequency']):g} Hz t={t:g}"
                               for t in times]
            stacked, static, rot = _problems(model, saved)
            v_ref, res_ref = solve_ladder(model.replace(**_solver_kwargs(ref_cfg)), stacked,
                                          static, [int(ref_cfg["sweeps"])])
            v_ref, res_ref = v_ref[0], res_ref[0]
            v0 = np.asarray(stacked["v0"])
            err, res = [], []
            for o in orders:
                v, r = solve_ladder(model.replace(**_solver_kwargs(o)), stacked, static, sweeps)
                err.append(relative_errors(model, rot, v, v_ref, v0))
                res.append(r)
            per_model[name] = dict(err=np.stack(err), res=np.stack(res), ref=res_ref,
                                   labels=labels)
            ctx.log.info("solver bench: %s, %d states, reference residual <= %.1e", name,
                         len(saved), float(res_ref.max()))
    n_state = max(len(d["labels"]) for d in per_model.values())

    def pad(x, axis=-1):
        width = [(0, 0)] * x.ndim
        width[axis] = (0, n_state - x.shape[axis])
        return np.pad(x.astype(np.float64), width, constant_values=np.nan)

    err = np.stack([pad(per_model[m]["err"]) for m in MODELS])  # model, order, sweeps, state
    res = np.stack([pad(per_model[m]["res"]) for m in MODELS])
    ref = np.stack([pad(per_model[m]["ref"]) for m in MODELS])
    to = np.array([[[_sweeps_to(per_model[m]["err"][i], sweeps, t) for t in targets]
                    for i in range(len(orders))] for m in MODELS])
    labels = np.array([[*per_model[m]["labels"], *[""] * (n_state - len(per_model[m]["labels"]))]
                       for m in MODELS])
    ds = xr.Dataset(
        {
            "relative_error": (("model", "order", "sweeps", "state"), err, dict(
                units="1", long_name="kinetic-energy norm of the velocity error over that of "
                "the constraints' velocity change, against the reference solution")),
            "residual": (("model", "order", "sweeps", "state"), res, dict(
                units="1", long_name="relative natural residual the solve reports")),
            "reference_residual": (("model", "state"), ref, dict(
                units="1", long_name="relative natural residual of the reference solution")),
            "sweeps_to": (("model", "order", "target"), to, dict(
                units="1", long_name="fewest sweeps of the ladder at which every saved "
                "state is within the target (NaN: not within the ladder)")),
            "state_label": (("model", "state"), labels, dict(
                units="1", long_name="gait and time of the saved state")),
        },
        coords=dict(model=list(MODELS), order=names, sweeps=sweeps,
                    state=np.arange(n_state), target=targets),
        attrs=dict(title="Solver sweeps to a relative error, per sweep order, on saved "
                   "Oncilla and Puppy II states",
                   thesis_ref="engine benchmark (thesis.physics.solver); §3.2, §5.3",
                   seeds=[], dtype="float64", times=times,
                   reference=f"{ref_cfg['sweep_order']} at relaxation "
                   f"{float(ref_cfg['relaxation']):g}, {int(ref_cfg['sweeps'])} sweeps",
                   orders="; ".join(f"{o['name']}: " + ", ".join(
                       f"{k}={o[k]}" for k in o if k != "name") for o in orders)))
    for m in MODELS:
        for i, o in enumerate(names):
            ctx.log.info("solver bench: %s %s sweeps to %s: %s", m, o, targets,
                         to[MODELS.index(m), i].tolist())
    return ds
