"""``thesis validate oncilla`` (registry ``model/validation``, ``model/convergence``): the
simulated Oncilla on the thesis's own published gaits, decided against the validation
targets V1-V6 of :mod:`thesis.modelcheck.targets` (docs/architecture.md#engine-rules).

Protocol (every run; the one of ``thesis bench oncilla``, :mod:`thesis.modelcheck.checks`):
untethered, flat floor, the ch4 model (``ch4.model``: time step, solver sweeps); the
robot starts standing, eases into the gait's pose over ``ch4.protocol.settle`` seconds,
enters the gait from itself over :data:`thesis.modelcheck.checks.SELF_TRANSITION` (1 s,
§3.2.5) and is measured over the next ``seconds`` (the window). Each published gait of
the flat ground (Tab. 3.1a, Tab. 3.1b, Tab. 4.2's flat optimum) runs at the profile's
``frequencies`` (its other parameters as published) and at its own published frequency,
each from ``starts`` perturbed starts: at the first command period the trunk's velocity
changes by a random vector (each axis normal with ``start_velocity`` [m/s] standard
deviation, stream ``model/validation/starts`` of the root seed; start ``s`` gets the same
vector in every case, so that cases and time steps are compared on equal starts).

Measured per run (window samples before the first fall, :func:`measure`): mean forward
speed, fall (the ch3/ch4 criterion, any time from the start), largest roll and pitch of
the trunk, stance compression (the commanded hip-to-toe length in stance, by forward
kinematics of the commanded joint angles, minus the simulated one; stance = the leg's
commanded phase inside its duty), the scapulae's largest deviation from their
commands, and per leg the share of its stance spent on the knee motor's extension stop or
with the cable taut (:func:`stance_at_stops`: where the stiff limit rows, not the knee's
spring, carry the leg). Every published optimum's foot path (Tab. 3.1, Tab. 4.2-4.4) is
recorded inside or outside the model's reach (:func:`reach`). V1-V6 are decided on these numbers
(:func:`thesis.modelcheck.targets.decide`).

``model/convergence`` measures the same runs three times, from ``convergence_starts``
perturbed starts per case (the first ``starts`` of them are the validation's): at the
model's dt, at dt / 2, and at dt with twice the solver sweeps (the physical softness of
:mod:`thesis.physics.builder` does not change with dt, so the three simulate one robot).
Each case's speed over its runs that stayed up must move by at most
``convergence_speed_tolerance`` (3 %: a step that has converged moves a gait that stays up by
no more) and each case's fall rate by at most 15 percentage points, decided per case and
three-valued on intervals that carry the starts' sampling spread
(:mod:`thesis.modelcheck.convergence_rule`): converged, not converged or inconclusive, with
the starts per case that would decide each undecided case. Beside them, each setting records
the legs' stance on the stops, so that the table shows whether the cases that move are those
whose legs the stop rows carry, and V1-V6 decided on its first ``starts`` starts (the
validation's instrument at each setting).
"""

from __future__ import annotations

import math
import warnings

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from thesis import seeding, store
from thesis.gaits import conditions as C
from thesis.gaits import leg as L
from thesis.gaits import runner as R
from thesis.gaits import trajectories as T
from thesis.modelcheck import checks as M
from thesis.modelcheck import convergence_rule as CR
from thesis.modelcheck import targets as TG

#: Settings of the convergence table: (name, dt factor, sweeps factor).
SETTINGS = (("dt", 1.0, 1), ("dt/2", 0.5, 1), ("2x sweeps", 1.0, 2))
#: Phases per cycle at which a foot path is drawn for the reach record.
REACH_SAMPLES = 100


def _family(name: str):
    return T.FAMILIES[name]()


def cases(cfg: dict) -> list[dict]:
    """The (gait, frequency) cases of the instrument: each flat-ground published gait at
    every frequency of ``cfg["frequencies"]`` and at its own; dicts with ``gait``
    (name), ``family``, ``frequency`` [Hz], ``params`` (P,)."""
    out = []
    for g in TG.published_gaits():
        if not g.flat:
            continue
        own = g.params[_family(g.family).index("f")]
        for f in sorted({float(x) for x in cfg["frequencies"]} | {float(own)}):
            out.append(case(g, f))
    return out


def case(gait: TG.PublishedGait, frequency: float) -> dict:
    """One case of :func:`cases`: the published ``gait`` at ``frequency`` [Hz], its other
    parameters as published."""
    p = np.array(gait.params, np.float64)
    p[_family(gait.family).index("f")] = float(frequency)
    return dict(gait=gait.name, family=gait.family, frequency=float(frequency), params=p)


def start_kicks(root_seed: int, starts: int, sigma: float) -> np.ndarray:
    """(starts, 3) trunk velocity changes [m/s] of the perturbed starts."""
    rng = seeding.rng(root_seed, "model/validation/starts", 0)
    return rng.normal(0.0, float(sigma), size=(int(starts), 3))


def trunk_angles(rot) -> tuple[np.ndarray, np.ndarray]:
    """Roll and pitch [rad] of trunk rotations ``rot`` (..., 3, 3) (world from body):
    roll about the trunk's long axis (+ = left side up), pitch (+ = nose down)."""
    r = np.asarray(rot, np.float64)
    roll = np.arctan2(r[..., 2, 1], r[..., 2, 2])
    pitch = np.arcsin(np.clip(-r[..., 2, 0], -1.0, 1.0))
    return roll, pitch


def toe_in_hip_frames(model, sim) -> np.ndarray:
    """(R, K, 4, 3) toe-sphere centres in each hip's frame (trunk axes, origin at the
    hip) [m] at every sample of a :func:`thesis.modelcheck.checks.simulate_runs` result."""
    trunk = M.O.trunk_index(model)
    toes = np.asarray(M.O.toe_spheres())
    body = np.asarray(model.csphere_body)[toes]
    off = np.asarray(model.csphere_offset, np.float64)[toes]
    pos = sim["pos"].astype(np.float64)
    rot = sim["rot"].astype(np.float64)
    world = pos[:, :, body] + np.einsum("rknij,nj->rkni", rot[:, :, body], off)
    rel = world - pos[:, :, trunk][:, :, None]
    return np.einsum("rkni,rkij->rknj", rel, rot[:, :, trunk]) - np.asarray(M.O.HIPS)


def commanded_toes(family, cmd) -> np.ndarray:
    """(R, K, 4, 3) hip-frame toe positions [m] of the commanded joint angles ``cmd``
    (R, K, 12) (forward kinematics of each leg's geometry: what the servos are asked)."""
    c = np.asarray(cmd, np.float64).reshape(cmd.shape[:2] + (4, 3))
    out = []
    for i, (geom, side) in enumerate(zip(family.legs, L.SIDES)):
        out.append(np.asarray(L.forward3d(geom, c[..., i, 0], c[..., i, 1], c[..., i, 2],
                                          side)))
    return np.stack(out, axis=2)


def measure(model, state, family, params, kicks, *, settle: float, seconds: float,
            fall_height: float, batch: int) -> dict:
    """Run ``params`` (N, P) of ``family`` from each of the perturbed starts ``kicks``
    (S, 3) and measure them (module docstring).

    Returns:
        dict of (N, S) arrays: ``speed`` [m/s] (window), ``fallen`` (bool, from the
        start), ``fall_time`` [s] (NaN: up), ``roll_max``, ``pitch_max`` [rad] (largest
        |angle| in the window while up), ``compression`` [m] (mean commanded minus
        simulated hip-to-toe length in stance while up), ``length_commanded`` [m],
        ``scapula_max_dev`` [rad] (largest |scapula - command| in the window while up),
        ``scapula_min``, ``scapula_max`` [rad] (scapula angle range in the window);
        (N, S, 4) per leg, the share of its stance samples while up on a stop
        (:func:`stance_at_stops`: ``knee_stop``, ``cable_taut``); and ``wall`` [s].
    """
    params = np.asarray(params, np.float64)
    n, s = len(params), len(kicks)
    p = np.repeat(params, s, axis=0)
    runs = dict(p=p, stand=np.zeros(len(p)), kick=np.tile(kicks, (n, 1)),
                kick_time=np.zeros(len(p)))
    t0 = settle + M.SELF_TRANSITION
    sim = M.simulate_runs(model, state, runs, duration=t0 + seconds, settle=settle,
                          t_transition=M.SELF_TRANSITION, batch=batch, family=family)
    whole = R.speed_terms(model, sim, 0.0, fall_height)
    win = R.speed_terms(model, sim, t0, fall_height)
    up = M.upright_mask(model, sim, fall_height, t0)
    trunk = M.O.trunk_index(model)
    roll, pitch = trunk_angles(sim["rot"][:, :, trunk])

    def wmax(x):
        with np.errstate(invalid="ignore"):
            return np.where(up.any(1), np.where(up, np.abs(x), 0.0).max(1), np.nan)

    scap = sim["q"][..., M.scapula_dofs(model)].astype(np.float64)
    dev = np.abs(scap - sim["cmd"][..., list(M.SCAPULA_COMMANDS)]).max(-1)
    big = np.where(up[..., None], scap, np.nan)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: fallen runs
        s_min, s_max = np.nanmin(big, axis=(1, 2)), np.nanmax(big, axis=(1, 2))
    # stance compression
    f = p[:, family.index("f")]
    duty = p[:, family.index("duty")]
    phase = f[:, None] * (sim["t"][None] - R.COMMAND_PERIOD - settle)
    legs = np.mod(phase[..., None] + np.asarray(family.phase_offsets), 1.0)
    stance = (legs < duty[:, None, None]) & up[..., None]
    length = np.linalg.norm(toe_in_hip_frames(model, sim), axis=-1)
    want = np.linalg.norm(commanded_toes(family, sim["cmd"]), axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cnt = stance.sum((1, 2))
        comp = np.where(cnt > 0, np.where(stance, want - length, 0.0).sum((1, 2))
                        / np.maximum(cnt, 1), np.nan)
        lcmd = np.where(cnt > 0, np.where(stance, want, 0.0).sum((1, 2))
                        / np.maximum(cnt, 1), np.nan)
    fall_t = np.where(whole["fallen"], whole["upright"] * sim["t"][-1], np.nan)
    out = dict(speed=win["speed"], fallen=whole["fallen"], fall_time=fall_t,
               roll_max=wmax(roll), pitch_max=wmax(pitch), compression=comp,
               length_commanded=lcmd, scapula_max_dev=wmax(dev), scapula_min=s_min,
               scapula_max=s_max)
    out = {k: np.asarray(v).reshape(n, s) for k, v in out.items()}
    for k, v in stance_at_stops(model, sim["q"], stance).items():
        out[k] = v.reshape(n, s, len(L.LEGS))
    out["wall"] = sim["wall"]
    return out


#: Angle [rad] within which a joint counts as on its stop (:func:`stance_at_stops`).
STOP_TOLERANCE = 0.01
#: The stops of :func:`stance_at_stops`: record name -> (joint of each leg, its stop).
STOPS = {"knee_stop": ("knee", "extension stop of the knee motor (femur-drum hinge)"),
         "cable_taut": ("cable", "taut cable (drum-tibia hinge on its opening stop)")}


def stance_at_stops(model, q, stance) -> dict:
    """Share of each leg's stance samples in which a joint sits on its upper stop: the
    knee motor's drum on its extension stop (``knee_stop``) and the cable taut
    (``cable_taut``: the tibia opened as far as the cable lets it, so the leg carries its
    load on the stop rows rather than on the knee's extension spring; §3.2.1, Fig. 3.1b).

    Legs whose stance targets lie beyond reach are commanded onto the extension stop
    (:func:`thesis.gaits.leg.inverse` projects them there), and a straight leg under
    the body's weight is held by those stiff rows; the convergence table records where
    that happens at each dt and sweep count.

    Args:
        model: the Oncilla; q: (R, K, n_dof) joint coordinates [rad] of
            :func:`thesis.modelcheck.checks.simulate_runs`; stance: (R, K, 4) bool, the
            samples counted (a leg's commanded stance while the robot is up).

    Returns:
        {name: (R, 4) fraction of the leg's counted samples within
        :data:`STOP_TOLERANCE` of (or beyond) the stop, NaN without any} per
        :data:`STOPS` name, legs in LEGS order.
    """
    lim_dof = np.asarray(model.limit_dof)
    hi = np.asarray(model.limit_hi, np.float64)
    cnt = stance.sum(1)
    out = {}
    for name, (joint, _) in STOPS.items():
        dofs = [model.dof(f"{leg}_{joint}:0") for leg in L.LEGS]
        top = np.array([hi[np.flatnonzero(lim_dof == d)[0]] for d in dofs])
        on = np.asarray(q[..., dofs], np.float64) >= top - STOP_TOLERANCE
        with np.errstate(invalid="ignore", divide="ignore"):
            out[name] = np.where(cnt > 0, (on & stance).sum(1) / np.maximum(cnt, 1), np.nan)
    return out


def measure_cases(model, state, cs: list[dict], kicks, *, settle, seconds, fall_height,
                  batch) -> dict:
    """:func:`measure` of every case of :func:`cases` (one compiled rollout per family);
    (C, S) arrays in case order, ``wall`` summed."""
    out: dict = {}
    wall = 0.0
    order = []
    for fam_name in sorted({c["family"] for c in cs}):
        idx = [i for i, c in enumerate(cs) if c["family"] == fam_name]
        m = measure(model, state, _family(fam_name), np.stack([cs[i]["params"] for i in idx]),
                    kicks, settle=settle, seconds=seconds, fall_height=fall_height,
                    batch=batch)
        wall += m.pop("wall")
        order += idx
        for k, v in m.items():
            out.setdefault(k, []).append(v)
    inv = np.argsort(order)
    res = {k: np.concatenate(v)[inv] for k, v in out.items()}
    res["wall"] = wall
    return res


#: Parts of a foot path in the reach record.
PATH_PARTS = ("cycle", "stance", "swing")


def reach(family_name: str, params, samples: int = REACH_SAMPLES) -> np.ndarray:
    """(3, 4) fraction of the foot targets of ``params`` (family order) that lie outside
    each leg's reachable area (columns LEGS order, fore and hind geometries; a target
    more than 1 mm from the nearest reachable point), over the whole cycle, its stance
    and its swing (rows :data:`PATH_PARTS`), drawn at ``samples`` phases; the sine family
    draws no foot path (NaN)."""
    fam = _family(family_name)
    if not hasattr(fam, "foot_targets"):
        return np.full((len(PATH_PARTS), 4), np.nan)
    ph = jnp.arange(samples) / samples
    tg = np.asarray(jax.vmap(lambda x: fam.foot_targets(jnp.asarray(params), x))(ph))
    legs = np.mod(np.asarray(ph)[:, None] + np.asarray(fam.phase_offsets)[None, :], 1.0)
    stance = legs < float(np.asarray(params)[fam.index("duty")])
    out = np.full((len(PATH_PARTS), 4), np.nan)
    for i, geom in enumerate(fam.legs):
        sag = np.stack([tg[:, i, 0], tg[:, i, 2]], axis=-1)
        outside = ~np.asarray(L.reachable(geom, sag, tol=1e-3))
        for k, m in enumerate((np.ones(samples, bool), stance[:, i], ~stance[:, i])):
            if m.any():
                out[k, i] = float(outside[m].mean())
    return out


def _setup(ctx):
    full = ctx.full_config
    cfg = full["physics"]["oncilla_validation"]
    pr = full["ch4"]["protocol"]
    return full, cfg, float(pr["settle"]), float(pr["fall_height"])


def _model(ch4: dict, dt_factor: float = 1.0, sweeps: int = 1):
    m = dict(ch4["model"])
    m["dt"] = float(m["dt"]) * dt_factor
    m["solver_iterations"] = int(m["solver_iterations"]) * int(sweeps)
    model, state = C.base_model({**ch4, "model": m})
    return C.untethered(model), state


def _a(units, long_name, **extra):
    return dict(units=units, long_name=long_name, **extra)


def _case_speeds(cs, m) -> tuple[dict, dict]:
    speed, theory = {}, {}
    for i, c in enumerate(cs):
        key = (c["gait"], c["frequency"])
        speed[key] = TG.gait_speed(m["speed"][i], m["fallen"][i])
        theory[key] = float(_family(c["family"]).speed(c["params"]))
    return speed, theory


def _unit_of(key: str) -> str:
    if key.startswith("speed") or key.endswith("Hz") and "frequencies" not in key:
        return "m s-1"
    if key.endswith("_deg"):
        return "degree"
    return "1"


def decide_targets(cs: list[dict], m: dict, starts: int | None = None):
    """V1-V6 (:func:`thesis.modelcheck.targets.decide`) from the measurements ``m`` of
    :func:`measure_cases` on the cases ``cs`` (every one a flat-ground published gait),
    over their first ``starts`` starts (None: all).

    Returns:
        (speed, theory, decided): {(gait, frequency): speed [m/s]}, the families'
        theoretical speeds [m/s] and the targets' verdicts.
    """
    n = slice(None) if starts is None else slice(0, int(starts))
    m = {k: np.asarray(m[k])[:, n] for k in ("speed", "fallen", "scapula_max_dev")}
    speed, theory = _case_speeds(cs, m)
    dev_deg = math.degrees(float(np.nanmax(m["scapula_max_dev"]))) \
        if np.isfinite(m["scapula_max_dev"]).any() else float("nan")
    decided = TG.decide(speed, theory, int(m["fallen"].sum()), int(m["fallen"].size),
                        dev_deg)
    return speed, theory, decided


def validation(ctx) -> xr.Dataset:
    """``thesis validate oncilla``: the published gaits on the model and V1-V6 (module
    docstring; Tab. 3.1, Fig. 3.4, §3.3.1, Tab. 4.2)."""
    full, cfg, settle, fall_height = _setup(ctx)
    cs = cases(cfg)
    kicks = start_kicks(ctx.root_seed, cfg["starts"], cfg["start_velocity"])
    model, state = _model(full["ch4"])
    m = measure_cases(model, state, cs, kicks, settle=settle, seconds=float(cfg["seconds"]),
                      fall_height=fall_height, batch=int(cfg["batch"]))
    ctx.log.info("oncilla validation: %d cases x %d starts in %.1f s", len(cs), len(kicks),
                 m["wall"])
    speed, theory, decided = decide_targets(cs, m)
    ds = dataset(cs, kicks, m, speed, theory, decided)
    ds.attrs.update(
        title="Validation of the simulated Oncilla on the thesis's published gaits",
        thesis_ref="Tab. 3.1, Fig. 3.4, §3.3.1, §3.3.3, Tab. 4.2-4.4",
        seeds=[int(ctx.root_seed)], settle=settle, transition=M.SELF_TRANSITION,
        seconds=float(cfg["seconds"]), fall_height=fall_height, untethered=1, floor="flat",
        dt=float(model.dt), solver_iterations=int(model.solver_iterations),
        model_code_sha256=M.model_code_sha256(),
        targets_passed=",".join(k for k, v in decided.items() if v["passed"]),
        targets_failed=",".join(k for k, v in decided.items() if not v["passed"]))
    ds["rollout_wall_seconds"] = ((), float(m["wall"]), _a(
        "s", "wall time of the rollouts, compilation included", **store.WALL_CLOCK))
    return ds


def dataset(cs, kicks, m, speed, theory, decided) -> xr.Dataset:
    """The validation dataset of :func:`validation` (cases x starts, reach, targets)."""
    CS = ("case", "start")
    keys = [(c["gait"], c["frequency"]) for c in cs]
    data = dict(
        speed=(CS, m["speed"], _a("m s-1", "mean forward trunk speed over the window")),
        fallen=(CS, m["fallen"].astype(np.int8), _a("1", "1 if the run fell (ch3/ch4 "
                                                         "criterion, from the start)")),
        fall_time=(CS, m["fall_time"], _a("s", "time of the first fall (NaN: stayed up)")),
        roll_max=(CS, m["roll_max"], _a("rad", "largest |trunk roll| in the window while up")),
        pitch_max=(CS, m["pitch_max"], _a("rad", "largest |trunk pitch| in the window while "
                                                 "up")),
        stance_compression=(CS, m["compression"], _a(
            "m", "commanded minus simulated hip-to-toe length in stance (mean over legs and "
                 "stance samples while up)")),
        stance_length_commanded=(CS, m["length_commanded"], _a(
            "m", "commanded hip-to-toe length in stance (forward kinematics of the "
                 "commands)")),
        scapula_max_deviation=(CS, m["scapula_max_dev"], _a(
            "rad", "largest |scapula angle - command| over the four legs in the window while "
                   "up")),
        scapula_min=(CS, m["scapula_min"], _a("rad", "smallest scapula angle in the window "
                                                    "while up")),
        scapula_max=(CS, m["scapula_max"], _a("rad", "largest scapula angle in the window "
                                                    "while up")),
        start_kick=(("start", "axis"), kicks, _a("m s-1", "trunk velocity change at the "
                                                          "first command period")),
        case_speed=(("case",), np.array([speed[k] for k in keys]), _a(
            "m s-1", "speed of the case: mean over the starts that stayed up (NaN: fewer "
                     "than half)")),
        theoretical_speed=(("case",), np.array([theory[k] for k in keys]), _a(
            "m s-1", "theoretical speed 2 a f / duty (Fig. 3.4)")),
        case_falls=(("case",), m["fallen"].sum(1).astype(np.int64), _a("1", "fallen starts")),
        **_stop_variables(("case", "start", "leg"), m,
                          "share of the leg's stance samples while up"),
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        data["speed_share"] = (("case",), data["case_speed"][1] / data["theoretical_speed"][1],
                               _a("1", "case speed / theoretical speed"))
    gaits = TG.published_gaits()
    data["reach_outside"] = (("published", "path_part", "leg"),
                             np.stack([reach(g.family, g.params) for g in gaits]),
                             _a("1", "fraction of the published foot path outside the leg's "
                                     "reachable area (one cycle, its stance, its swing)"))
    data["published_flat"] = (("published",), np.array([g.flat for g in gaits], np.int8),
                              _a("1", "1 if the thesis ran the gait on flat ground"))
    data["target_passed"] = (("target",), np.array([decided[t]["passed"] for t in TG.TARGETS],
                                                   np.int8),
                             _a("1", "1 if the validation target passed"))
    data["target_text"] = (("target",), np.array([decided[t]["text"] for t in TG.TARGETS]),
                           _a("1", "the target's numbers beside its bounds",
                              renders="target_passed and the targets' measured variables"))
    for t in TG.TARGETS:
        for k, v in {**decided[t]["measured"], **decided[t]["bounds"]}.items():
            name = f"{t}_{k}".replace(".", "p")
            data[name] = ((), float(v), _a(_unit_of(k), f"{t}: {k}"))
    coords = dict(case=np.arange(len(cs)), start=np.arange(len(kicks)), axis=["x", "y", "z"],
                  case_gait=("case", [c["gait"] for c in cs]),
                  case_frequency=("case", np.array([c["frequency"] for c in cs])),
                  case_family=("case", [c["family"] for c in cs]),
                  published=[g.name for g in gaits],
                  published_source=("published", [g.source for g in gaits]),
                  published_family=("published", [g.family for g in gaits]),
                  leg=list(L.LEGS), target=list(TG.TARGETS), path_part=list(PATH_PARTS))
    ds = xr.Dataset(data, coords=coords)
    ds["case_frequency"].attrs.update(units="Hz", long_name="gait frequency of the case")
    for name, long_name in (("case_gait", "published gait of the case"),
                            ("case_family", "gait family of the case"),
                            ("published_source", "thesis table of the published gait"),
                            ("published_family", "gait family of the published gait")):
        ds[name].attrs.update(units="1", long_name=long_name)
    return ds


def _stop_variables(dims: tuple, m: dict, share: str) -> dict:
    """The :data:`STOPS` records of ``m`` as dataset variables ``stance_<name>``."""
    return {f"stance_{k}": (dims, np.asarray(m[k]), _a(
                "1", f"{share} with the {what} (within {STOP_TOLERANCE} rad)"))
            for k, (_, what) in STOPS.items()}


def settings_variables(speeds, fells, case, n_cases: int, dts, sweeps, walls, *,
                       speed_tol: float = CR.SPEED_TOLERANCE) -> tuple[dict, np.ndarray]:
    """The dataset variables of a convergence table over :data:`SETTINGS` (the Oncilla's
    and the Puppy II's, :mod:`thesis.modelcheck.puppy_convergence`), decided by
    :func:`thesis.modelcheck.convergence_rule.compare_runs`.

    Args:
        speeds, fells: (G, N) each run's speed [m/s] and whether it fell, per setting.
        case: (N,) int, each run's case; n_cases: the number of cases.
        dts [s], sweeps, walls [s]: (G,) each setting's step, solver sweeps and wall time.
        speed_tol: the table's tolerance of a case's relative speed change.

    Returns:
        ({name: (dims, values, attrs)}, verdicts (G-1,) str).
    """
    res = CR.compare_runs(speeds, fells, case, n_cases, speed_tol=speed_tol)
    S, SC, R_, RC = ("setting",), ("setting", "case"), ("refined",), ("refined", "case")
    tol_s, tol_f, tol_c = speed_tol, CR.FALL_TOLERANCE, CR.CASE_FALL_TOLERANCE
    level = f"{1 - CR.ALPHA:.0%}"
    data = dict(
        case_speed=(SC, res["case_speed"], _a(
            "m s-1", f"speed of the case (mean over the runs that stayed up; NaN: fewer than "
                     f"{CR.MIN_UP_RUNS})")),
        case_speed_se=(SC, res["case_speed_se"], _a(
            "m s-1", "standard error of the case's speed over its runs that stayed up")),
        fall_rate=(SC, res["fall_rate"], _a("1", "fraction of the case's runs that fell")),
        total_fall_rate=(S, res["total_fall_rate"], _a("1", "fraction of all runs that fell")),
        dt=(S, np.array(dts, np.float64), _a("s", "physics time step")),
        solver_iterations=(S, np.array(sweeps), _a("1", "solver sweeps per step")),
        **_interval_variables("speed_change", RC, res, "relative speed change",
                              "|speed - speed at dt| / speed at dt (inf: defined at one "
                              "setting only)", "delta method", level),
        max_speed_change=(R_, _nanmax_rows(res["speed_change"]), _a(
            "1", "largest relative speed change (inf: a case whose speed is defined at one "
                 "setting only)")),
        **_interval_variables("case_fall_rate_change", RC, res, "case's fall-rate change",
                              "|the case's fall rate - its fall rate at dt|",
                              "Agresti-Caffo", level),
        **_interval_variables("fall_rate_change", R_, res, "fall-rate change",
                              "|fall rate over all runs - fall rate over all runs at dt|",
                              "Agresti-Caffo", level),
        starts_to_decide=(RC, res["starts_to_decide"], _a(
            "1", "runs per case at which the case's speed and fall rate would both decide, "
                 "were their changes and spreads what these runs show (a projection; "
                 "thesis.modelcheck.convergence_rule.starts_to_decide)")),
        quantities=(R_, res["quantities"], _a(
            "1", "quantities tested (cases with a speed at both settings, and each case's "
                 "fall rate)")),
        verdict=(R_, res["verdict"], _a(
            "1", f"converged: every interval within {tol_s:.0%} (each case's speed) and "
                 f"{tol_c * 100:.0f} points (each case's fall rate); not converged: one "
                 f"beyond; else inconclusive (thesis.modelcheck.convergence_rule; the fall "
                 f"rate over all runs is recorded against {tol_f * 100:.0f} points, not "
                 "decided)")),
        rollout_wall_seconds=(S, np.array(walls, np.float64), _a(
            "s", "wall time of the rollouts, compilation included", **store.WALL_CLOCK)),
    )
    return data, res["verdict"]


def _interval_variables(name: str, dims: tuple, res: dict, what: str, long_name: str,
                        method: str, level: str) -> dict:
    """A change's variables in a convergence table: its size ``name``, its standard error
    ``name_se``, the upper end of its ``level`` interval ``name_upper`` and the lower end of
    its Bonferroni interval ``name_lower_k`` (all of |change|, fractions)."""
    return {
        name: (dims, res[name], _a("1", long_name)),
        f"{name}_se": (dims, res[f"{name}_se"], _a("1", f"standard error of the {what} "
                                                        f"({method})")),
        f"{name}_upper": (dims, res[f"{name}_upper"], _a(
            "1", f"upper end of the {level} interval of |{what}|")),
        f"{name}_lower_k": (dims, res[f"{name}_lower_k"], _a(
            "1", f"lower end of the Bonferroni interval of |{what}|")),
    }


def _nanmax_rows(x) -> np.ndarray:
    """(R,) each row's largest value ignoring NaN (NaN for a row of NaN)."""
    x = np.asarray(x, float)
    return np.array([np.max(r[~np.isnan(r)]) if (~np.isnan(r)).any() else np.nan for r in x])


def verdict_attrs(verdicts, speed_tol: float = CR.SPEED_TOLERANCE) -> dict:
    """The attributes every convergence table records about its rule and its verdict."""
    return dict(speed_tolerance=float(speed_tol), fall_tolerance=CR.FALL_TOLERANCE,
                case_fall_tolerance=CR.CASE_FALL_TOLERANCE, alpha=CR.ALPHA,
                min_up_runs=CR.MIN_UP_RUNS, verdict=CR.overall(verdicts))


def convergence(ctx) -> xr.Dataset:
    """``model/convergence``: the validation quantities at dt, dt / 2 and dt with twice the
    sweeps, and whether each case's speed moves <= ``convergence_speed_tolerance`` (3 %)
    and its fall rate <= 15 points, decided three-valued (module docstring); V1-V6
    decided at each setting on the validation's starts (``target_passed``, ``target_text``
    over setting x target)."""
    full, cfg, settle, fall_height = _setup(ctx)
    cs = cases(cfg)
    kicks = start_kicks(ctx.root_seed, cfg["convergence_starts"], cfg["start_velocity"])
    speeds, fells, scap, walls, dts, sweeps, targets = [], [], [], [], [], [], []
    stops = {k: [] for k in STOPS}
    n_val = min(int(cfg["starts"]), len(kicks))
    for name, fdt, fsw in SETTINGS:
        model, state = _model(full["ch4"], fdt, fsw)
        m = measure_cases(model, state, cs, kicks, settle=settle,
                          seconds=float(cfg["seconds"]), fall_height=fall_height,
                          batch=int(cfg["batch"]))
        ctx.log.info("convergence %s: %d runs in %.1f s", name, m["speed"].size, m["wall"])
        targets.append(decide_targets(cs, m, n_val)[2])
        speeds.append(m["speed"].ravel())
        fells.append(m["fallen"].ravel())
        with warnings.catch_warnings():  # a case whose every start fell: NaN
            warnings.simplefilter("ignore", RuntimeWarning)
            scap.append(np.nanmax(m["scapula_max_dev"], axis=1))
            for k in STOPS:
                stops[k].append(np.nanmean(m[k], axis=1))
        walls.append(m["wall"])
        dts.append(float(model.dt))
        sweeps.append(int(model.solver_iterations))
    case = np.repeat(np.arange(len(cs)), len(kicks))
    tol = float(cfg["convergence_speed_tolerance"])
    data, verdicts = settings_variables(np.asarray(speeds), np.asarray(fells), case, len(cs),
                                        dts, sweeps, walls, speed_tol=tol)
    data["scapula_max_deviation"] = (("setting", "case"), np.asarray(scap), _a(
        "rad", "largest scapula deviation from its command in the window while up"))
    data.update(_stop_variables(("setting", "case", "leg"), stops,
                                "mean over the starts of the share of the leg's stance "
                                "samples while up"))
    data["target_passed"] = (("setting", "target"), np.array(
        [[d[t]["passed"] for t in TG.TARGETS] for d in targets], np.int8), _a(
        "1", f"1 if the validation target passed at the setting (V1-V6 on the first {n_val} "
             "starts of every case, the validation's own)"))
    data["target_text"] = (("setting", "target"), np.array(
        [[d[t]["text"] for t in TG.TARGETS] for d in targets]), _a(
        "1", "the target's numbers beside its bounds at the setting",
        renders="target_passed, case_speed, fall_rate, scapula_max_deviation"))
    coords = dict(setting=[s[0] for s in SETTINGS], refined=[s[0] for s in SETTINGS[1:]],
                  case=np.arange(len(cs)), leg=list(L.LEGS), target=list(TG.TARGETS),
                  case_gait=("case", [c["gait"] for c in cs]),
                  case_frequency=("case", np.array([c["frequency"] for c in cs])))
    ds = xr.Dataset(data, coords=coords)
    ds["case_frequency"].attrs.update(units="Hz", long_name="gait frequency of the case")
    ds["case_gait"].attrs.update(units="1", long_name="published gait of the case")
    ds.attrs.update(
        title="Convergence of the simulated Oncilla's validation quantities in dt and sweeps",
        thesis_ref="Tab. 3.1, Fig. 3.4, Tab. 4.2 (the published gaits of the validation)",
        seeds=[int(ctx.root_seed)], settle=settle, seconds=float(cfg["seconds"]),
        fall_height=fall_height, starts=len(kicks), target_starts=n_val,
        model_code_sha256=M.model_code_sha256(), **verdict_attrs(verdicts, tol))
    return ds
