"""``thesis validate oncilla --only fit`` (registry ``model/fit``): the fit of the simulated
Oncilla's unsourced values to the fitted side of the declared split, run exactly as
:mod:`thesis.modelcheck.split` declares it (docs/architecture.md#engine-rules).

What it fits (:data:`thesis.modelcheck.split.PARAMETERS`, bounds and start values there):
the foot plate's length and width [m] (docs/sources.md#oncilla-feet), the knee's extension
spring [N m/rad] (docs/sources.md#oncilla-knee-spring) and the hip and knee drives'
stiffness [N m/rad] (docs/sources.md#oncilla-drives). The values derived from them
(:data:`~thesis.modelcheck.split.DERIVED`) follow: the toe sits ``foot_length / 2 + 4 mm``
behind the plate's front edge (``toe_offset``) and ``drive_damping = drive_stiffness / 50``
[N m s/rad]. ``LEG_OFFSET`` (the legs' plane outboard of the scapula axes [m]) is a module
constant of :mod:`thesis.physics.models.oncilla` that the trunk's inertia, the hips and the
validation's hip-frame measurements all read, so it is not a model argument: the fit holds
it at its start value (:data:`HELD`; the dataset's ``held`` marks it) and the split keeps
``wired=False`` for it.

The procedure (:data:`thesis.modelcheck.split.PROCEDURE`):

* **Physics**: ``ch4.model`` as the chapters run it (dt, sweeps, sweep order,
  relaxations), with ``feet='plate'`` and the values above (:func:`build_model`),
  untethered.
* **Cases**: Tab. 3.1a (half ellipse) and Tab. 3.1b (spline) at 1.5 Hz (§3.3.1.3,
  §3.3.3), their other parameters as published; the validation's protocol
  (:mod:`thesis.modelcheck.validation`: flat floor, ``ch4.protocol``'s settle and fall
  height, the 1-s self-transition, a window of ``seconds``) from ``starts`` perturbed
  starts with the validation's kicks (stream ``model/validation/starts``), the same kicks
  at every point. ``starts`` and ``seconds`` are ``physics.oncilla_validation``'s unless
  ``physics.oncilla_fit`` sets them (the smoke profile does, to stay small).
* **Objective** (:func:`objective`): per case the squared log speed error
  ``(ln(v / v_pub))^2`` (:func:`squared_log_error`), v the case's speed
  (:func:`thesis.modelcheck.targets.gait_speed`: the mean over the starts that stayed up);
  for Tab. 3.1a the error is to the nearer of the thesis's two speeds (0.27 and 0.30 m/s)
  and 0 between them; Tab. 3.1b's is to its 1.5 Hz speed. Plus
  ``PROCEDURE["fall_penalty"]`` (0.25) per fallen start of either case. A case without a
  speed (fewer than half its starts up) costs ``PROCEDURE["undefined_cost"]`` (4.0) in
  place of its error; so does a case whose speed is not positive, whose log error does not
  exist (a choice: the procedure does not name that case).
* **Initial points** (:func:`design`): the start values and ``design_points - 1`` points
  of a Latin hypercube (:class:`scipy.stats.qmc.LatinHypercube`, stream
  ``model/calibration/design`` of the root seed) in the unit cube of the bounds: lengths
  and widths linear, the spring and the stiffness in log (:data:`SCALES`).
* **Optimiser** (:func:`search`): every initial point is evaluated; then
  :func:`scipy.optimize.minimize` (``method="Nelder-Mead"``, its own default simplex and
  tolerances, the unit cube as its bounds and every point clipped to it) from each of the
  best ``local_starts`` initial points (ties: the earlier), each stopped after
  ``local_evaluations`` evaluations at most (a budget this module enforces: Nelder-Mead's
  own ``maxfev`` is checked once per iteration only). The fit is the lowest objective of
  every evaluation, ties to the earliest.
* **Report**: the fit's values and objective, each case's speed and falls there, and per
  parameter whether it ended at a bound: within :data:`AT_BOUND` (2 %) of the bounds'
  range, in the parameter's own units, of its low (-1) or high (+1) bound, else 0.

Reads only the fitted side of the split: V1's two speeds
(:func:`thesis.modelcheck.targets.v1_speeds`), Tab. 3.1b's 1.5 Hz speed
(:func:`thesis.modelcheck.targets.v2_fitted_speed`), the frequency and Tab. 3.1's gaits
(tests/modelcheck/test_fit.py checks it as tests/modelcheck/test_split.py checks the
knee-spring calibration). The rollout is an argument of :func:`fit`, so that the procedure
runs on a known response in the tests.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import xarray as xr
from scipy import optimize
from scipy.stats import qmc

from thesis import seeding, store
from thesis.gaits import conditions as C
from thesis.modelcheck import checks as M
from thesis.modelcheck.calibration import MATCH_TOLERANCE
from thesis.modelcheck import split as S
from thesis.modelcheck import targets as TG
from thesis.modelcheck import validation as V
from thesis.physics.models.oncilla import (DRIVE_DAMPING_RATIO, LEG_OFFSET, TOE_BEHIND_CENTRE,
                                           oncilla)
from thesis.physics.models.oncilla_config import oncilla_kwargs

#: Stream of the Latin hypercube (:data:`thesis.modelcheck.split.PROCEDURE`).
DESIGN_STREAM = "model/calibration/design"
#: How each parameter maps onto the unit cube: lengths and widths linear, the spring and
#: the stiffness in log (PROCEDURE's initial points).
SCALES = {"foot_length": "linear", "foot_width": "linear", "knee_spring": "log",
          "drive_stiffness": "log", "LEG_OFFSET": "linear"}
#: Parameters held at their start value: no model argument sets them (module docstring).
HELD = ("LEG_OFFSET",)
#: Share of a parameter's range within which its fitted value counts as at a bound.
AT_BOUND = 0.02
#: ``units`` of a variable along ``parameter``: each row in its parameter's unit.
_MIXED = "see parameter_unit"


def configured(model_cfg: dict, params=None) -> dict[str, float]:
    """The value each parameter has in a ``ch4.model`` config section (its key; a held
    parameter: the model's module constant), for the fit's dataset to show beside the fit
    whether the chapters run it."""
    constants = {"LEG_OFFSET": LEG_OFFSET}
    return {p.name: float(model_cfg[p.name] if p.wired else constants[p.name])
            for p in (S.PARAMETERS if params is None else params)}


def free(params=None) -> tuple[S.Parameter, ...]:
    """The parameters the fit varies (all but :data:`HELD`)."""
    return tuple(p for p in (params or S.PARAMETERS) if p.name not in HELD)


def _ends(p: S.Parameter) -> tuple[float, float]:
    if SCALES[p.name] == "log":
        return math.log(p.low), math.log(p.high)
    return p.low, p.high


def to_unit(params, values) -> np.ndarray:
    """(..., P) positions in the unit cube of the bounds of ``params`` of ``values`` (..., P)
    in the parameters' units (:data:`SCALES`)."""
    x = np.asarray(values, np.float64)
    out = np.empty_like(x)
    for i, p in enumerate(params):
        lo, hi = _ends(p)
        v = np.log(x[..., i]) if SCALES[p.name] == "log" else x[..., i]
        out[..., i] = (v - lo) / (hi - lo)
    return out


def from_unit(params, u) -> np.ndarray:
    """(..., P) values in the parameters' units of unit-cube positions ``u`` (..., P),
    clipped to the cube first."""
    u = np.clip(np.asarray(u, np.float64), 0.0, 1.0)
    out = np.empty_like(u)
    for i, p in enumerate(params):
        lo, hi = _ends(p)
        v = lo + u[..., i] * (hi - lo)
        out[..., i] = np.exp(v) if SCALES[p.name] == "log" else v
    return out


def design(root_seed: int, points: int, params=None) -> np.ndarray:
    """(points, P) initial points in the unit cube of the free parameters: the start values
    first, then ``points - 1`` of a Latin hypercube drawn from stream
    :data:`DESIGN_STREAM` of ``root_seed``."""
    params = free(params)
    start = to_unit(params, [p.start for p in params])[None]
    if points <= 1:
        return start[:points]
    lhs = qmc.LatinHypercube(d=len(params), rng=seeding.rng(root_seed, DESIGN_STREAM))
    return np.concatenate([start, lhs.random(points - 1)])


def squared_log_error(v: float, lo: float, hi: float) -> float:
    """``(ln(v / v_pub))^2`` with v_pub the nearer of ``lo`` and ``hi`` [m/s], 0 for
    ``lo <= v <= hi``; NaN where ``v`` is NaN or not positive (no log error)."""
    if not (np.isfinite(v) and v > 0):
        return float("nan")
    if v < lo:
        return math.log(v / lo) ** 2
    if v > hi:
        return math.log(v / hi) ** 2
    return 0.0


def objective(speeds, fallen, bands, fall_penalty: float = S.PROCEDURE["fall_penalty"],
              undefined_cost: float = S.PROCEDURE["undefined_cost"]) -> dict:
    """The procedure's objective of one evaluation.

    Args:
        speeds, fallen: (C, S) window speed [m/s] and fall (bool) of each case's starts.
        bands: C (low, high) published speeds [m/s] per case (low == high: one speed).
        fall_penalty: cost per fallen start. undefined_cost: cost of a case without a speed.

    Returns:
        dict: ``total``; (C,) ``speed`` (the case's speed, NaN: fewer than half up),
        ``error`` (squared log error, NaN where undefined), ``cost`` (the error or
        ``undefined_cost``), ``falls`` (fallen starts).
    """
    speeds = np.asarray(speeds, np.float64)
    fallen = np.asarray(fallen, bool)
    v = np.array([TG.gait_speed(s, f) for s, f in zip(speeds, fallen)])
    err = np.array([squared_log_error(x, *b) for x, b in zip(v, bands)])
    cost = np.where(np.isfinite(err), err, float(undefined_cost))
    falls = fallen.sum(axis=1)
    total = float(cost.sum() + float(fall_penalty) * falls.sum())
    return dict(total=total, speed=v, error=err, cost=cost, falls=falls)


class _Budget(Exception):
    """A local start has spent its evaluations."""


def search(f: Callable[[np.ndarray], float], initial, local_starts: int,
           local_evaluations: int) -> dict:
    """The optimiser of the procedure on the unit cube.

    Args:
        f: unit-cube point (P,) (already clipped) -> objective.
        initial: (N, P) initial points (:func:`design`).
        local_starts: Nelder-Mead runs, from the best initial points (ties: the earlier).
        local_evaluations: most evaluations of each run.

    Returns:
        dict: ``points`` (E, P) every evaluation's point in order, ``values`` (E,),
        ``phase`` (E,) 0 for an initial point, k for the k-th local start, ``origin``
        (local_starts,) index of the initial point each run began at, ``best`` the index
        of the lowest value (the earliest on a tie).
    """
    points, values, phase = [], [], []

    def evaluate(u, k: int) -> float:
        u = np.clip(np.asarray(u, np.float64), 0.0, 1.0)
        val = float(f(u))
        points.append(u)
        values.append(val)
        phase.append(k)
        return val

    initial = np.atleast_2d(np.asarray(initial, np.float64))
    for u in initial:
        evaluate(u, 0)
    origin = np.argsort(np.asarray(values), kind="stable")[:int(local_starts)]
    d = initial.shape[1]
    for k, i in enumerate(origin, start=1):
        spent = [0]

        def g(u, k=k, spent=spent):
            if spent[0] >= int(local_evaluations):
                raise _Budget
            spent[0] += 1
            return evaluate(u, k)

        if int(local_evaluations) <= 0:
            continue
        try:
            optimize.minimize(g, initial[i], method="Nelder-Mead", bounds=[(0.0, 1.0)] * d,
                              options=dict(maxfev=int(local_evaluations)))
        except _Budget:
            pass
    vals = np.asarray(values)
    return dict(points=np.asarray(points).reshape(-1, d), values=vals,
                phase=np.asarray(phase, np.int16), origin=np.asarray(origin, np.int64),
                best=int(np.argmin(vals)))


def at_bound(params, values) -> np.ndarray:
    """(P,) -1 where a value lies within :data:`AT_BOUND` of its range from its low bound,
    +1 from its high bound, else 0."""
    out = np.zeros(len(params), np.int8)
    for i, (p, x) in enumerate(zip(params, values)):
        tol = AT_BOUND * (p.high - p.low)
        out[i] = -1 if x - p.low <= tol else (1 if p.high - x <= tol else 0)
    return out


def cases() -> list[dict]:
    """The procedure's cases (:func:`thesis.modelcheck.validation.case` dicts), read from
    Tab. 3.1 alone."""
    gaits = {g.name: g for g in TG.tab3_1_gaits()}
    return [V.case(gaits[name], f) for name, f in S.PROCEDURE["cases"]]


def bands() -> dict[str, tuple[float, float]]:
    """{gait name: (low, high) [m/s]}: Tab. 3.1a's two published speeds at 1.5 Hz, Tab.
    3.1b's one (low == high)."""
    lo, hi = TG.v1_speeds()
    v = TG.v2_fitted_speed()
    return {"tab3_1a": (min(lo, hi), max(lo, hi)), "tab3_1b": (v, v)}


def values_of(params, unit) -> dict[str, float]:
    """{name: value} of every declared parameter at the free parameters' unit-cube point
    ``unit`` (the held ones at their start; a coordinate that is exactly its start's
    position gives the start itself, so that the design's first point runs the current
    values bit for bit)."""
    fr = free(params)
    u = np.asarray(unit, np.float64)
    x = from_unit(fr, u)
    home = to_unit(fr, [p.start for p in fr])
    out = {p.name: float(p.start) for p in params}
    out.update({p.name: float(p.start if u[i] == home[i] else x[i])
                for i, p in enumerate(fr)})
    return out


def build_model(ch4: dict, values: dict):
    """(Model, State) of ``ch4.model`` with the plate feet and ``values`` (and their
    derived values, split.DERIVED: the model places the toe on the plate itself and
    :func:`oncilla_kwargs` the drives' damping), untethered."""
    wired = {p.name: float(values[p.name]) for p in S.PARAMETERS if p.wired}
    model, state = oncilla(**oncilla_kwargs({**ch4["model"], "feet": "plate", **wired},
                                            ch4.get("tether")))
    return C.untethered(model), state


def simulator(full: dict, *, settle: float, seconds: float, fall_height: float,
              batch: int) -> Callable:
    """The real rollout: ``(values, cases, kicks) -> dict`` of (C, S) ``speed``, ``fallen``
    and ``wall`` [s] (:func:`thesis.modelcheck.validation.measure_cases` on
    :func:`build_model`); its last model is kept in ``.model``."""
    def rollout(values, cs, kicks):
        model, state = build_model(full["ch4"], values)
        rollout.model = model
        return V.measure_cases(model, state, cs, kicks, settle=settle, seconds=seconds,
                               fall_height=fall_height, batch=batch)

    rollout.model = None
    return rollout


def fit(ctx, rollout: Callable | None = None) -> xr.Dataset:
    """``model/fit``: the procedure of the module docstring on the profile's ``ch4.model``
    (Tab. 3.1a and 3.1b at 1.5 Hz; §3.3.1.2-3, §3.3.3).

    Args:
        ctx: the run context (``full_config``, ``root_seed``, ``log``).
        rollout: ``(values {name: value}, cases, kicks (S, 3)) -> dict`` of (C, S)
            ``speed`` [m/s] and ``fallen`` and ``wall`` [s]; default :func:`simulator`.
    """
    full = ctx.full_config
    fcfg = full["physics"]["oncilla_fit"]
    vcfg = full["physics"]["oncilla_validation"]
    pr = full["ch4"]["protocol"]
    settle, fall_height = float(pr["settle"]), float(pr["fall_height"])
    n_starts = int(vcfg["starts"] if fcfg["starts"] is None else fcfg["starts"])
    seconds = float(vcfg["seconds"] if fcfg["seconds"] is None else fcfg["seconds"])
    real = rollout is None
    if real:
        # each case is one compiled call of its starts: a batch wider than them pads it
        rollout = simulator(full, settle=settle, seconds=seconds, fall_height=fall_height,
                            batch=min(int(vcfg["batch"]), n_starts))
    params = S.PARAMETERS
    fr = free(params)
    cs = cases()
    bd = bands()
    case_bands = [bd[c["gait"]] for c in cs]
    kicks = V.start_kicks(ctx.root_seed, n_starts, float(vcfg["start_velocity"]))
    fall_penalty = float(S.PROCEDURE["fall_penalty"])
    undefined_cost = float(S.PROCEDURE["undefined_cost"])
    records: list[dict] = []
    wall = [0.0]

    def evaluate(u) -> float:
        values = values_of(params, u)
        m = rollout(values, cs, kicks)
        wall[0] += float(m.get("wall", 0.0))
        speeds = np.asarray(m["speed"], np.float64).reshape(len(cs), n_starts)
        fallen = np.asarray(m["fallen"], bool).reshape(len(cs), n_starts)
        o = objective(speeds, fallen, case_bands, fall_penalty, undefined_cost)
        records.append(dict(values=values, speeds=speeds, fallen=fallen, **o))
        ctx.log.info("fit %d: %s -> %.4g (%s m/s, falls %s)", len(records),
                     ", ".join(f"{k} {v:.4g}" for k, v in values.items()), o["total"],
                     np.round(o["speed"], 3).tolist(), o["falls"].tolist())
        return o["total"]

    init = design(ctx.root_seed, int(fcfg["design_points"]), params)
    res = search(evaluate, init, int(fcfg["local_starts"]), int(fcfg["local_evaluations"]))
    b = res["best"]
    best = records[b]
    fit_values = np.array([best["values"][p.name] for p in params])
    bound = at_bound(params, fit_values)
    ctx.log.info("fit: evaluation %d of %d, objective %.4g, %s", b + 1, len(records),
                 best["total"], ", ".join(f"{p.name} {x:.4g}{' (at a bound)' if k else ''}"
                                          for p, x, k in zip(params, fit_values, bound)))
    conf_of = configured(full["ch4"]["model"], params)
    conf = np.array([conf_of[p.name] for p in params])
    a = V._a
    E, EC, ECS = ("evaluation",), ("evaluation", "case"), ("evaluation", "case", "start")
    P, Cd = ("parameter",), ("case",)
    rec = lambda name, dtype=np.float64: np.asarray([r[name] for r in records], dtype)  # noqa: E731
    data = dict(
        objective=(E, res["values"], a("1", "the procedure's objective of each evaluation")),
        phase=(E, res["phase"], a("1", "0: an initial point of the design; k: the k-th "
                                       "Nelder-Mead start")),
        unit_point=(("evaluation", "free_parameter"), res["points"], a(
            "1", "each evaluation's point in the unit cube of the free parameters' bounds "
                 "(log for knee_spring and drive_stiffness)")),
        case_speed=(EC, rec("speed"), a("m s-1", "the case's speed: mean over the starts "
                                                 "that stayed up (NaN: fewer than half)")),
        case_error=(EC, rec("error"), a("1", "squared log speed error to the published "
                                             "speed(s) (NaN: no speed)")),
        case_cost=(EC, rec("cost"), a("1", "the case's share of the objective before the "
                                           "fall penalty (its error or undefined_cost)")),
        case_falls=(EC, rec("falls", np.int16), a("1", "fallen starts of the case")),
        start_speed=(ECS, rec("speeds"), a("m s-1", "window speed of each start")),
        start_fallen=(ECS, rec("fallen", np.int8), a("1", "1 if the start fell")),
        case_target_low=(Cd, np.array([x[0] for x in case_bands]), a(
            "m s-1", "the lower published speed of the case (Tab. 3.1a: 0 error from here "
                     "to case_target_high)")),
        case_target_high=(Cd, np.array([x[1] for x in case_bands]), a(
            "m s-1", "the higher published speed of the case")),
        parameter_low=(P, np.array([p.low for p in params]), a(
            _MIXED, "low bound, in the parameter's unit")),
        parameter_high=(P, np.array([p.high for p in params]), a(
            _MIXED, "high bound, in the parameter's unit")),
        parameter_start=(P, np.array([p.start for p in params]), a(
            _MIXED, "start value (the model's current value; the design's first "
                              "point)")),
        held=(P, np.array([p.name in HELD for p in params], np.int8), a(
            "1", "1 if the fit holds the parameter at its start (no model argument sets "
                 "it)")),
        fit_value=(P, fit_values, a(_MIXED, "the fit's value, in the parameter's "
                                                      "unit")),
        fit_at_bound=(P, bound, a("1", f"-1 / +1 if the fit lies within {AT_BOUND:.0%} of "
                                       "the range of its low / high bound, else 0")),
        fit_evaluation=((), b, a("1", "index of the fit's evaluation (lowest objective, "
                                      "the earliest on a tie)")),
        fit_objective=((), float(best["total"]), a("1", "the fit's objective")),
        fit_case_speed=(Cd, best["speed"], a("m s-1", "each case's speed at the fit")),
        fit_case_falls=(Cd, np.asarray(best["falls"], np.int16), a(
            "1", "fallen starts of each case at the fit")),
        local_start_origin=(("local_start",), res["origin"], a(
            "1", "the design evaluation each Nelder-Mead start began at")),
        configured=(P, conf, a(_MIXED, "the value ch4.model holds (a held parameter: the "
                                       "model's constant), in the parameter's unit")),
        configured_matches_fit=(P, np.array(
            [abs(c - f) <= MATCH_TOLERANCE * abs(f) for c, f in zip(conf, fit_values)],
            np.int8), a("1", f"1 if the configured value is within {MATCH_TOLERANCE:.0%} of "
                             "the fit")),
        fit_toe_offset=((), best["values"]["foot_length"] / 2 + TOE_BEHIND_CENTRE, a(
            "m", "derived: the plate's reach forward of the toe, foot_length / 2 + 4 mm")),
        fit_drive_damping=((), best["values"]["drive_stiffness"] / DRIVE_DAMPING_RATIO, a(
            "N m s rad-1", "derived: drive_stiffness / 50 s-1")),
        rollout_wall_seconds=((), wall[0], a("s", "wall time of the rollouts, compilation "
                                                  "included", **store.WALL_CLOCK)),
    )
    for p in params:
        data[f"evaluation_{p.name}"] = (E, np.array([r["values"][p.name] for r in records]),
                                        a(p.unit, f"{p.name} of each evaluation"))
        data[f"fit_{p.name}"] = ((), float(best["values"][p.name]), a(
            p.unit, f"the fit's {p.name}" + (" (held at its start)" if p.name in HELD
                                              else "")))
    ds = xr.Dataset(data, coords=dict(
        parameter=[p.name for p in params], free_parameter=[p.name for p in fr],
        case=[c["gait"] for c in cs], start=np.arange(n_starts),
        evaluation=np.arange(len(records)),
        local_start=np.arange(1, len(res["origin"]) + 1)))
    ds = ds.assign_coords(parameter_unit=("parameter", [p.unit for p in params]))
    ds["parameter_unit"].attrs.update(units="1", long_name="unit of each parameter's values")
    for name, long in (("parameter", "declared parameter (split.PARAMETERS)"),
                       ("free_parameter", "parameter the fit varies"),
                       ("case", "published gait at 1.5 Hz"), ("start", "perturbed start"),
                       ("evaluation", "evaluation, in order"),
                       ("local_start", "Nelder-Mead start")):
        ds[name].attrs.update(units="1", long_name=long)
    model = getattr(rollout, "model", None)
    ds.attrs.update(
        title="Fit of the simulated Oncilla's unsourced values to the fitted side of the "
              "split",
        thesis_ref="Tab. 3.1a, Tab. 3.1b, §3.3.1.2-3, §3.3.3",
        seeds=[int(ctx.root_seed)], settle=settle, transition=M.SELF_TRANSITION,
        seconds=seconds, fall_height=fall_height, untethered=1, floor="flat", feet="plate",
        frequency=S.FIT_FREQUENCY, starts=n_starts,
        design_points=int(fcfg["design_points"]), local_starts=int(fcfg["local_starts"]),
        local_evaluations=int(fcfg["local_evaluations"]), fall_penalty=fall_penalty,
        undefined_cost=undefined_cost, at_bound=AT_BOUND, design_stream=DESIGN_STREAM,
        held_parameters=list(HELD),
        held_reason="LEG_OFFSET is a module constant of thesis.physics.models.oncilla "
                    "(hips, trunk inertia, the validation's hip frames), not a model "
                    "argument: held at its start value",
        simulated=int(real), model_code_sha256=M.model_code_sha256(),
        configured_feet=str(full["ch4"]["model"].get("feet", "sphere")))
    if model is not None:
        ds.attrs.update(dt=float(model.dt), solver_iterations=int(model.solver_iterations),
                        sweep_order=str(model.sweep_order),
                        relaxation=float(model.relaxation),
                        contact_relaxation=("none" if model.contact_relaxation is None
                                            else float(model.contact_relaxation)))
    return ds
