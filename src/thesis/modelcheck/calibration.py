"""``thesis validate oncilla --only calibration`` (registry ``model/calibration``): the
committed calibration procedure of the simulated Oncilla (issue 53 item 4).

Calibration is kept apart from validation. Only a value that no source gives may be
fitted, and only to V1 (:mod:`thesis.modelcheck.targets`); V2-V6 check the result and
nothing is changed after seeing them. The procedure, fixed before any calibration run:

* **Physics**: the model's chapter setting (``ch4.model``: dt 2.5 ms, 120 solver sweeps;
  below). The spring is varied on exactly that model.
* **Fitted value**: the knee's extension spring ``knee_spring`` [N m/rad] (preload
  unchanged). No source gives it (FACTS §5, the model's docstring); it sets the stance
  compression that §3.3.1.2 names as the reason the robot walks below the feet's
  theoretical speed.
* **Target**: V1 alone: Tab. 3.1a's half ellipse at :data:`~thesis.modelcheck.targets.V1_FREQUENCY`
  (1.5 Hz), the mean speed over ``starts`` perturbed starts (the validation's start kicks,
  stream ``model/validation/starts``), against the midpoint of the thesis's two speeds for
  it (0.27 and 0.30 m/s, :func:`target_speed`).
* **Grid**: ``physics.oncilla_calibration.grid`` (default 10, the model's former value,
  5, 3, 2, 1.5, 1). **Fit** (:func:`fit_log_linear`): speed interpolated linearly in
  log k between the two neighbouring grid points that bracket the target; where none
  bracket it, the grid point nearest the target (recorded as outside the grid).
* **Residual**: one more run at the fitted value; |its speed - target|.
* Then V2-V6 once (``model/validation``) on the fitted value at that setting.

The fitted value is what ``ch3.model.knee_spring`` and ``ch4.model.knee_spring`` hold
(config/schema.yaml); the dataset records the configured value beside the fit, and
:data:`MATCH_TOLERANCE` says when the two agree (``configured_matches_fit``). A claim whose
thesis number is V1's speed is marked as resting on a calibration target
(:mod:`thesis.claims.model_validity`).

Why 120 sweeps (the sweep ladder, the validation's protocol, 3 starts, at the former knee
spring of 10 N m/rad): Tab. 3.1a walked 0.026-0.045 / 0.24-0.30 m/s at 0.5 / 1.5 Hz with
30 sweeps, 0.142 / 0.449 with 120, 0.147 / 0.454 with 240, and 0.149 / 0.457 with 120
sweeps at dt / 2: from 120 sweeps on the speeds move by at most 5 % and the starts no
longer differ; at 30 the feet slip and the speeds are 3-5x lower. ``model/convergence``
checks the chosen setting on every published gait (three-valued, 30 starts: converged on
Tab. 3.1a's half ellipse, not converged on the spline and Tab. 4.2's optimum).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from thesis import store
from thesis.modelcheck import checks as M
from thesis.modelcheck import targets as TG
from thesis.modelcheck import validation as V

#: Largest |configured - fitted| / fitted for the configured knee spring to count as the fit
#: (the fit is written into the config to 4 significant digits).
MATCH_TOLERANCE = 0.01
#: The published gait the calibration runs (V1's).
GAIT = "tab3_1a"


def target_speed() -> float:
    """V1's calibration target [m/s]: the midpoint of the thesis's two speeds of Tab. 3.1a
    at 1.5 Hz (§3.3.1.3's 0.27, §3.3.3's 0.30: :func:`thesis.modelcheck.targets.published_speeds`)."""
    lo, hi = TG.published_speeds()["v1"]
    return 0.5 * (lo + hi)


def v1_case() -> dict:
    """The calibration's one case: Tab. 3.1a at V1's frequency (a :func:`validation.cases`
    entry: ``gait``, ``family``, ``frequency`` [Hz], ``params`` (P,))."""
    cs = [c for c in V.cases({"frequencies": [TG.V1_FREQUENCY]})
          if c["gait"] == GAIT and abs(c["frequency"] - TG.V1_FREQUENCY) < 1e-9]
    return cs[0]


def fit_log_linear(grid, speeds, target: float) -> dict:
    """The procedure's fit of the knee spring to ``target``.

    Args:
        grid: (G,) knee spring values [N m/rad] (any order, > 0).
        speeds: (G,) the gait's speed at each [m/s] (NaN: undefined, the gait fell).
        target: the speed to meet [m/s].

    Returns:
        dict ``value`` [N m/rad], ``inside`` (True where two neighbouring grid points, in
        the order of k, bracket the target and ``value`` is interpolated linearly in
        log k between them; False: the finite grid point nearest the target), ``bracket``
        (the two k, or the one nearest twice). Where several pairs bracket it (speed need
        not be monotone in k), the first from the stiffest spring down is taken.

    Raises:
        ValueError: when no grid speed is finite.
    """
    k = np.asarray(grid, np.float64)
    v = np.asarray(speeds, np.float64)
    order = np.argsort(k)[::-1]  # stiffest first: the model's former value leads
    k, v = k[order], v[order]
    if not np.isfinite(v).any():
        raise ValueError("no grid point gave a speed: every run fell")
    for i in range(len(k) - 1):
        a, b = v[i], v[i + 1]
        if np.isfinite(a) and np.isfinite(b) and min(a, b) <= target <= max(a, b):
            t = 0.0 if a == b else (target - a) / (b - a)
            lk = math.log(k[i]) + t * (math.log(k[i + 1]) - math.log(k[i]))
            return dict(value=float(math.exp(lk)), inside=True,
                        bracket=(float(k[i]), float(k[i + 1])))
    j = int(np.nanargmin(np.abs(v - target)))
    return dict(value=float(k[j]), inside=False, bracket=(float(k[j]), float(k[j])))


def _measure(full: dict, knee_spring: float, case: dict, kicks, *, settle, seconds,
             fall_height, batch) -> tuple[dict, object]:
    ch4 = full["ch4"]
    model, state = V._model({**ch4, "model": dict(ch4["model"], knee_spring=knee_spring)})
    return V.measure_cases(model, state, [case], kicks, settle=settle, seconds=seconds,
                           fall_height=fall_height, batch=batch), model


def calibration(ctx) -> xr.Dataset:
    """``model/calibration``: the procedure of the module docstring on the profile's
    ``ch4.model`` (Tab. 3.1a, §3.3.1.2-3, §3.3.3)."""
    full = ctx.full_config
    ccfg = full["physics"]["oncilla_calibration"]
    vcfg = full["physics"]["oncilla_validation"]
    pr = full["ch4"]["protocol"]
    settle, fall_height = float(pr["settle"]), float(pr["fall_height"])
    seconds, batch = float(ccfg["seconds"]), int(vcfg["batch"])
    case = v1_case()
    kicks = V.start_kicks(ctx.root_seed, int(ccfg["starts"]), float(vcfg["start_velocity"]))
    target = target_speed()
    grid = [float(k) for k in ccfg["grid"]]
    speeds, fallen, comp, walls = [], [], [], []
    model = None
    for k in grid:
        m, model = _measure(full, k, case, kicks, settle=settle, seconds=seconds,
                            fall_height=fall_height, batch=batch)
        ctx.log.info("calibration: knee_spring %.4g N m/rad: %s m/s (%.1f s)", k,
                     np.round(m["speed"][0], 3).tolist(), m["wall"])
        speeds.append(m["speed"][0])
        fallen.append(m["fallen"][0])
        comp.append(m["compression"][0])
        walls.append(m["wall"])
    gait = np.array([TG.gait_speed(s, f) for s, f in zip(speeds, fallen)])
    fit = fit_log_linear(grid, gait, target)
    r, _ = _measure(full, fit["value"], case, kicks, settle=settle, seconds=seconds,
                    fall_height=fall_height, batch=batch)
    walls.append(r["wall"])
    res_speed = TG.gait_speed(r["speed"][0], r["fallen"][0])
    configured = float(full["ch4"]["model"]["knee_spring"])
    matches = abs(configured - fit["value"]) <= MATCH_TOLERANCE * fit["value"]
    ctx.log.info("calibration: fit %.4g N m/rad (inside grid: %s), residual run %.3f m/s "
                 "against %.3f; configured %.4g", fit["value"], fit["inside"], res_speed,
                 target, configured)
    K, KS = ("knee_spring",), ("knee_spring", "start")
    a = V._a
    data = dict(
        grid_speed=(KS, np.asarray(speeds), a("m s-1", "window speed of each start")),
        grid_fallen=(KS, np.asarray(fallen).astype(np.int8), a("1", "1 if the start fell")),
        grid_gait_speed=(K, gait, a("m s-1", "the gait's speed: mean over the starts that "
                                             "stayed up (NaN: fewer than half)")),
        grid_compression=(KS, np.asarray(comp), a("m", "stance compression: commanded minus "
                                                       "simulated hip-to-toe length")),
        target_speed=((), target, a("m s-1", "V1's midpoint: the calibration target")),
        fitted_knee_spring=((), fit["value"], a("N m rad-1", "the procedure's fit")),
        fit_inside_grid=((), int(fit["inside"]), a("1", "1 if two grid points bracket the "
                                                        "target (interpolated fit)")),
        residual_speed=((), res_speed, a("m s-1", "the gait's speed at the fitted spring")),
        residual_start_speed=(("start",), r["speed"][0], a("m s-1", "window speed of each "
                                                                   "start at the fit")),
        residual=((), abs(res_speed - target), a("m s-1", "|speed at the fit - target|")),
        configured_knee_spring=((), configured, a("N m rad-1", "ch4.model.knee_spring: the "
                                                               "value the chapters run")),
        configured_matches_fit=((), int(matches), a(
            "1", f"1 if the configured spring is within {MATCH_TOLERANCE:.0%} of the fit")),
        rollout_wall_seconds=((), float(sum(walls)), a(
            "s", "wall time of the rollouts, compilation included", **store.WALL_CLOCK)),
    )
    ds = xr.Dataset(data, coords=dict(knee_spring=np.asarray(grid),
                                      start=np.arange(len(kicks))))
    ds["knee_spring"].attrs.update(units="N m rad-1", long_name="knee spring of the grid")
    ds.attrs.update(
        title="Calibration of the simulated Oncilla's knee spring to V1 alone",
        thesis_ref="Tab. 3.1a, §3.3.1.2-3, §3.3.3",
        seeds=[int(ctx.root_seed)], settle=settle, transition=M.SELF_TRANSITION,
        seconds=seconds, fall_height=fall_height, untethered=1, floor="flat",
        gait=GAIT, frequency=float(case["frequency"]),
        dt=float(model.dt), solver_iterations=int(model.solver_iterations),
        bracket=list(fit["bracket"]), model_code_sha256=M.model_code_sha256())
    return ds
