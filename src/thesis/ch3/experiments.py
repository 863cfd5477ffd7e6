"""Experiment functions of chapter 3 (registered in :mod:`thesis.registry`).

``table3_1`` optimises the three trot families with PSO (§3.3.1; the sine gait, tuned by
hand in the thesis, is optimised with the same PSO here) and stores the optimum per seed
(the pipeline runs each seed as a job of its own, ``table3_1_part``, and joins them);
``fig3_4``, ``robustness``, ``table3_2`` and ``fig3_5`` read those optima (input
``table3_1``). Dataset layouts are those of :mod:`thesis.claims.ch3`. Every size comes
from the ``ch3`` config section; simulated robot time is recorded so profiles can be
compared.
"""

from __future__ import annotations

import importlib

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.errors import SimulationDiverged
from thesis.gaits import runner as R
from thesis.gaits import trajectories as T
from thesis.ch3 import turning as TU
from thesis.optim import pso
from thesis.physics.models.oncilla_config import oncilla_from_config
from thesis.store import WALL_CLOCK
# the module (the package re-exports the constructor under the same name)
O = importlib.import_module("thesis.physics.models.oncilla")

#: Dataset gait name -> family object (one instance each, so compiled functions are reused).
FAMILIES = {"sine": T.SineGait(), "half_ellipse": T.EllipseGait(), "spline": T.SplineGait()}
GAITS = tuple(FAMILIES)


def param_label(name: str) -> str:
    """Parameter name used in ``table3_1`` (the thesis's ``t_stance f`` for ``duty``)."""
    return "t_stance_f" if name == "duty" else name


def model_of(cfg):
    """(Model, State) of the configured Oncilla (``model``: dt, sweeps, the fitted knee
    spring, the solver's warm start, relaxation, sweep order and contact relaxation;
    :func:`thesis.physics.models.oncilla_config.oncilla_from_config`)."""
    return oncilla_from_config(cfg["model"])


#: Length of the padded parameter vectors of a mixed batch (the sine family has 13).
PMAX = max(len(f.names) for f in FAMILIES.values())


def pad(p) -> np.ndarray:
    """(..., P) parameters -> (..., PMAX), zero padded."""
    p = np.asarray(p, np.float64)
    out = np.zeros(p.shape[:-1] + (PMAX,))
    out[..., :p.shape[-1]] = p
    return out


def _mixed_fn(mem, t, sens):
    """Commands of a robot of any family: memory ``family`` (int index into GAITS),
    ``p_from``/``p_to`` (PMAX,), ``settle`` and ``t_transition`` [s]."""
    import jax

    def branch(fam):
        n = len(fam.names)
        return lambda m: R.protocol_commands(
            fam, m["p_from"][:n], m["p_to"][:n], t, m["settle"], m["t_transition"])

    return jax.lax.switch(mem["family"], [branch(FAMILIES[g]) for g in GAITS], mem)


def evaluate_gaits(cfg, gait, p_from, p_to, t_run, t_transition):
    """Simulate a batch of gaits, each entered from ``p_from`` (§3.2.5); eq. 3.3 terms.

    Args:
        gait: family name per robot (B,) or one name for all.
        p_from, p_to: (B, P) parameters (P of each robot's family; rows may be padded).
        t_run, t_transition: (B,) or scalar evaluation window / transition [s]. One
            batched simulation runs all robots for the longest settle + transition + run;
            each robot is measured over its own window.

    Returns (terms dict of (B,) arrays, simulation dict).
    """
    model, state = model_of(cfg)
    pr = cfg["protocol"]
    B = len(p_to)
    gaits = [gait] * B if isinstance(gait, str) else list(gait)
    t_run = np.broadcast_to(np.asarray(t_run, np.float64), (B,))
    t_tr = np.broadcast_to(np.asarray(t_transition, np.float64), (B,))
    mem = dict(family=np.asarray([GAITS.index(g) for g in gaits], np.int32),
               p_from=np.stack([pad(r) for r in p_from]).astype(np.float32),
               p_to=np.stack([pad(r) for r in p_to]).astype(np.float32),
               settle=np.full(B, pr["settle"], np.float32),
               t_transition=t_tr.astype(np.float32))
    t_start = pr["settle"] + t_tr
    dur = float(np.max(t_start + t_run))
    sim = R.simulate(model, state, _mixed_fn, mem, dur)
    if not np.isfinite(sim["pos"]).any(axis=(1, 2, 3)).any():
        raise SimulationDiverged(f"ch3/{gaits[0]}", -1, -1)
    freq = np.array([float(np.asarray(p_to[i])[FAMILIES[g].index("f")])
                     for i, g in enumerate(gaits)])
    period = 1.0 / np.maximum(freq, 1e-3)
    terms = R.fitness_terms(model, sim, t_start, pr["led_distance"], pr["led_height"],
                            pr["fall_height"], period=period, t_end=t_start + t_run)
    return terms, sim


def optimise(cfg, seed: int, root_seed: int, log=None, timing=None):
    """PSO of every gait family for one seed (§3.3.1.2-3): each generation of all three
    swarms is simulated in one batched rollout. Returns {gait: (History, n_exploded,
    fallen)} with ``fallen`` (generations, particles) bool, the evaluations whose robot
    fell (as ch4 records them); appends (robot-seconds, wall-seconds) of every generation
    after the first to ``timing``."""
    timing = [] if timing is None else timing
    states, xs, fs, prev, n_bad, falls = {}, {}, {}, {}, {}, {}
    for g in GAITS:
        c, fam = cfg["pso"][g], FAMILIES[g]
        rng = seeding.rng(root_seed, f"ch3/table3_1/{g}", seed)
        states[g] = pso.pso_init(rng, int(c["particles"]), fam.lower, fam.upper,
                                 project=fam.project)
        xs[g], fs[g], prev[g], n_bad[g], falls[g] = [], [], None, 0, []
    n_gen = max(int(cfg["pso"][g]["generations"]) for g in GAITS)
    for gen in range(n_gen):
        live = [g for g in GAITS if gen < int(cfg["pso"][g]["generations"])]
        names, p_from, p_to, t_run, t_tr = [], [], [], [], []
        for g in live:
            x = pso.ask(states[g])
            c = cfg["pso"][g]
            first = x[:1] if prev[g] is None else prev[g][None]
            p_from += list(np.concatenate([first, x[:-1]]))  # previous particle (§3.2.5)
            p_to += list(x)
            names += [g] * len(x)
            t_run += [c["run_seconds"]] * len(x)
            t_tr += [c["transition_seconds"]] * len(x)
        terms, sim = evaluate_gaits(cfg, names, p_from, p_to, t_run, t_tr)
        if gen > 0:  # generation 0 includes compilation
            timing.append((sim["robot_seconds"], sim["wall"]))
        k = 0
        for g in live:
            n = int(cfg["pso"][g]["particles"])
            f = terms["fitness"][k:k + n]
            n_bad[g] += int(terms["exploded"][k:k + n].sum())
            falls[g].append(np.asarray(terms["fallen"][k:k + n], bool))
            x = pso.ask(states[g])
            xs[g].append(x)
            fs[g].append(f)
            prev[g] = x[-1]
            states[g] = pso.tell(states[g], f, project=FAMILIES[g].project)
            k += n
            if log:
                log.info("ch3 PSO seed %d gen %d %s best %.3f", seed, gen, g, np.max(f))
    return {g: (pso.history_from(xs[g], fs[g]), n_bad[g], np.stack(falls[g])) for g in GAITS}


def table3_1(ctx) -> xr.Dataset:
    """Tab. 3.1: PSO-optimised parameters of every trot family, per seed (§3.3.1).

    Inputs: ``part_seed<s>`` for every seed of ``ch3.seeds`` (each a :func:`table3_1_part`
    of that one seed, one job each), joined along ``seed``; without inputs every seed is
    optimised here, one after another. A seed's optimum is the same either way: its swarm's
    stream (``ch3/table3_1/<gait>`` of the seed) and its evaluations involve no other seed.
    Layout: :func:`table3_1_part` over every seed.
    """
    seeds = [int(s) for s in ctx.config["seeds"]]
    if not any(name.startswith("part_seed") for name in ctx.inputs):
        return table3_1_part(ctx)
    parts = []
    for s in seeds:
        with xr.open_dataset(ctx.input(f"part_seed{s}"), engine="h5netcdf") as f:
            part = f.load()
        if [int(x) for x in part["seed"].values] != [s]:
            raise ValueError(f"ch3/table3_1: input part_seed{s} holds seeds "
                             f"{part['seed'].values.tolist()}, not [{s}]")
        parts.append(part)
    # the simulation rate is each job's own wall clock: their robot-seconds over their time
    rate = [float(p["robot_seconds_per_wall_second"]) for p in parts]
    rate_attrs = dict(parts[0]["robot_seconds_per_wall_second"].attrs)
    ds = xr.concat([p.drop_vars("robot_seconds_per_wall_second") for p in parts], dim="seed",
                   data_vars="minimal", coords="minimal", compat="equals",
                   combine_attrs="override")
    ds["robot_seconds_per_wall_second"] = ((), float(np.nanmedian(rate)), dict(
        rate_attrs, long_name=rate_attrs.get("long_name", "") + " (median over the seeds' "
                                                                "jobs)"))
    ds.attrs["seeds"] = seeds
    return ds


def table3_1_part(ctx) -> xr.Dataset:
    """Tab. 3.1 for the seeds of ``ch3.seeds`` (the pipeline runs one seed per job): every
    trot family's PSO optimum, best fitness per generation, falls and unphysical
    evaluations (§3.3.1).

    Variables: value (gait, parameter, seed) [the parameter's unit], best_fitness (gait,
    seed, generation), fallen (gait, seed, generation, particle), n_exploded (gait, seed),
    parameter_unit (parameter), robot_seconds_per_wall_second (wall clock).
    """
    cfg = ctx.config
    seeds = list(cfg["seeds"])
    names = []
    for g in GAITS:
        names += [param_label(n) for n in FAMILIES[g].names if param_label(n) not in names]
    n_gen = max(int(cfg["pso"][g]["generations"]) for g in GAITS)
    value = np.full((len(GAITS), len(names), len(seeds)), np.nan)
    best = np.full((len(GAITS), len(seeds), n_gen), np.nan)
    n_bad = np.zeros((len(GAITS), len(seeds)))
    n_part = max(int(cfg["pso"][g]["particles"]) for g in GAITS)
    fallen = np.full((len(GAITS), len(seeds), n_gen, n_part), np.nan)
    timing = []
    for si, s in enumerate(seeds):
        runs = optimise(cfg, s, ctx.root_seed, ctx.log, timing)
        for gi, g in enumerate(GAITS):
            h, n_bad[gi, si], fell = runs[g]
            fallen[gi, si, :fell.shape[0], :fell.shape[1]] = fell
            for pi, n in enumerate(FAMILIES[g].names):
                value[gi, names.index(param_label(n)), si] = h.best_position[pi]
            best[gi, si, :len(h.best_fitness)] = h.best_fitness
    ds = xr.Dataset(
        dict(value=(("gait", "parameter", "seed"), value,
                    dict(units="mixed (see parameter_unit)", long_name="optimised parameter")),
             best_fitness=(("gait", "seed", "generation"), best,
                           dict(units="1", long_name="best eq. 3.3 fitness so far")),
             fallen=(("gait", "seed", "generation", "particle"), fallen, dict(
                 units="1", long_name="1 if the robot fell in its evaluation (trunk below "
                                      "ch3.protocol.fall_height or tilted over); NaN where "
                                      "a family has fewer particles or generations")),
             n_exploded=(("gait", "seed"), n_bad, dict(
                 units="1", long_name="evaluations whose simulation went unphysical "
                                      "(fitness -inf)"))),
        coords=dict(gait=list(GAITS), parameter=names, seed=seeds,
                    generation=np.arange(n_gen), particle=np.arange(n_part)))
    units = {}
    for g in GAITS:
        for n, u in zip(FAMILIES[g].names, FAMILIES[g].units):
            units[param_label(n)] = u
    rs, ws = np.sum([t[0] for t in timing]), np.sum([t[1] for t in timing])
    ds["robot_seconds_per_wall_second"] = ((), rs / ws if ws > 0 else np.nan, dict(
        units="1", long_name="simulated robot-seconds per wall-second of the batched PSO "
                             "generations (generations after the first, no compilation)",
        **WALL_CLOCK))
    ds["parameter_unit"] = ("parameter", [units[n] for n in names],
                            dict(units="1", long_name="unit of the parameter"))
    for g in GAITS:
        c = cfg["pso"][g]
        for k in ("particles", "generations", "run_seconds", "transition_seconds"):
            ds.attrs[f"pso_{g}_{k}"] = c[k]
    ds.attrs.update(thesis_ref="Tab. 3.1", seeds=seeds)
    return ds


def best_params(table: xr.Dataset, gait: str, seed) -> np.ndarray:
    """(P,) optimised parameters of ``gait`` for ``seed`` from a ``table3_1`` dataset."""
    fam = FAMILIES[gait]
    v = table["value"].sel(gait=gait, seed=seed)
    return np.array([float(v.sel(parameter=param_label(n))) for n in fam.names])


def _load_table(ctx) -> xr.Dataset:
    return xr.load_dataset(ctx.input("table3_1"))


def fig3_4(ctx) -> xr.Dataset:
    """Fig. 3.4: speed against gait frequency for the three families, with the
    theoretical foot-speed line; also the simulation rate (robot-s per wall-s)."""
    cfg, table = ctx.config, _load_table(ctx)
    sw = cfg["sweep"]
    freqs = [float(f) for f in sw["frequencies"]]
    seeds = list(cfg["seeds"])
    shape = (len(GAITS), len(freqs), len(seeds))
    names, p_from, p_to = [], [], []
    for g in GAITS:
        fam = FAMILIES[g]
        for f in freqs:
            for s in seeds:
                p0 = best_params(table, g, s)
                p1 = p0.copy()
                p1[fam.index("f")] = f
                names.append(g)
                p_from.append(p0)
                p_to.append(p1)
    terms, sim = evaluate_gaits(cfg, names, p_from, p_to, float(sw["run_seconds"]),
                                float(sw["transition_seconds"]))
    speed = terms["speed"].reshape(shape)
    fallen = terms["fallen"].reshape(shape).astype(float)
    theo = np.array([np.nan if g == "sine" else float(FAMILIES[g].speed(p))
                     for g, p in zip(names, p_to)]).reshape(shape)
    dims = ("gait", "frequency", "seed")
    ds = xr.Dataset(
        dict(speed=(dims, speed, dict(units="m s-1", long_name="forward speed of the trunk")),
             theoretical_speed=(dims, theo, dict(
                 units="m s-1", long_name="theoretical speed 2 a f / duty (foot speed in stance)")),
             fallen=(dims, fallen, dict(units="1", long_name="1 if the robot fell")),
             wall_seconds=((), sim["wall"], dict(
                 units="s", long_name="wall time of the batched sweep (with compilation)",
                 **WALL_CLOCK))),
        coords=dict(gait=list(GAITS), frequency=freqs, seed=seeds))
    ds.attrs.update(thesis_ref="Fig. 3.4", seeds=seeds, run_seconds=sw["run_seconds"],
                    batch_per_call=len(names))
    return ds


def robustness(ctx) -> xr.Dataset:
    """§3.3.1.1 / abstract: fraction of small random parameter perturbations of each
    optimised gait under which the robot still walks (not fallen, speed above
    ``min_speed``). A perturbation moves every parameter by U(-scale, scale) of its
    range and is projected on the family's feasible set."""
    cfg, table = ctx.config, _load_table(ctx)
    rc = cfg["robustness"]
    seeds = list(cfg["seeds"])
    n = int(rc["perturbations"])
    names, p_from, p_to = [], [], []
    for g in GAITS:
        fam = FAMILIES[g]
        for s in seeds:
            p0 = best_params(table, g, s)
            rng = seeding.rng(ctx.root_seed, f"ch3/robustness/{g}", s)
            d = rng.uniform(-1, 1, (n, p0.size)) * rc["scale"] * (fam.upper - fam.lower)
            p_to += list(fam.project(p0[None] + d))
            p_from += [p0] * n
            names += [g] * n
    terms, _ = evaluate_gaits(cfg, names, p_from, p_to, float(rc["run_seconds"]),
                              float(rc["transition_seconds"]))
    walks = (~terms["fallen"]) & (terms["speed"] > rc["min_speed"])
    frac = walks.reshape(len(GAITS), len(seeds), n).mean(axis=2)
    spd = terms["speed"].reshape(len(GAITS), len(seeds), n)
    ds = xr.Dataset(
        dict(fraction_walking=(("gait", "seed"), frac, dict(
                 units="1", long_name="fraction of perturbed gaits that still walk")),
             perturbed_speed=(("gait", "seed", "perturbation"), spd, dict(
                 units="m s-1", long_name="speed of each perturbed gait"))),
        coords=dict(gait=list(GAITS), seed=seeds, perturbation=np.arange(n)))
    ds.attrs.update(thesis_ref="§3.3.1.1", seeds=seeds, scale=rc["scale"],
                    min_speed=rc["min_speed"])
    return ds


def _turn_memory(cfg, table, seeds, strategies):
    fam = FAMILIES["half_ellipse"]
    tc = cfg["turning"]
    p_from, p_to, yaws = [], [], []
    for strategy in strategies:
        for s in seeds:
            p0 = best_params(table, "half_ellipse", s)
            p0[fam.index("f")] = tc["frequency"]
            p, yaw = TU.strategy_params(fam, p0, strategy, reduced_a=tc["reduced_a"],
                                        slow_duty=tc["slow_duty"], yaw_deg=tc["yaw_deg"])
            p_from.append(TU.per_leg(p0))
            p_to.append(p)
            yaws.append(yaw)
    return dict(p_from=np.asarray(p_from, np.float32), p_to=np.asarray(p_to, np.float32),
                yaw=np.asarray(yaws, np.float32))


def turning_metrics(model, sim, t_start: float, fall_height: float):
    """Speed [m/s], signed angular speed [deg/s] (+ = left, the commanded side), turning
    radius [m] (circle fit to the trunk centre) and fallen flag, per robot, over
    t > ``t_start``."""
    trunk = O.trunk_index(model)
    w = sim["t"] > t_start + 1e-9
    tp = sim["pos"][:, w, trunk]
    rot = sim["rot"][:, w, trunk]
    span = sim["t"][w][-1] - sim["t"][w][0]
    step = np.linalg.norm(np.diff(tp[:, :, :2], axis=1), axis=-1).sum(axis=1)
    yaw = R.yaw_of(rot)
    ang = np.degrees(yaw[:, -1] - yaw[:, 0]) / span
    bad = R.exploded(model, sim)
    radius = np.array([R.fit_circle(p[:, :2])[1] if ok else np.nan
                       for p, ok in zip(tp, ~bad)])
    fallen = (tp[..., 2].min(axis=1) < fall_height) | (rot[:, :, 2, 2].min(axis=1) < 0.5) | bad
    ang = np.where(bad, np.nan, ang)
    speed = np.where(bad, np.nan, step / span)
    return speed, ang, radius, fallen


def table3_2(ctx) -> xr.Dataset:
    """Tab. 3.2 and §3.3.2: the five turning strategies on the optimised half-ellipse gait
    at the turning frequency; speed, signed angular speed, turning radius, stability."""
    cfg, table = ctx.config, _load_table(ctx)
    tc, pr = cfg["turning"], cfg["protocol"]
    seeds = list(cfg["seeds"])
    model, state = model_of(cfg)
    fam = FAMILIES["half_ellipse"]
    fn = TU.turning_command_fn(fam, float(pr["settle"]), float(tc["transition_seconds"]))
    t_start = pr["settle"] + tc["transition_seconds"]
    dur = t_start + tc["run_seconds"]
    S = len(seeds)
    shape = (len(TU.STRATEGIES), S)
    out = {k: np.full(shape, np.nan) for k in ("speed", "angular_speed", "turning_radius")}
    fallen = np.zeros(shape, bool)
    # one batch: the four gait-changing strategies and the straight gait ("torque"
    # parameters = the unchanged gait); then the torque strategy on the weakened model,
    # padded to the same batch so the compiled rollout is reused
    plain = [s for s in TU.STRATEGIES if s != "torque"] + ["torque"]
    mem = _turn_memory(cfg, table, seeds, plain)
    sim = R.simulate(model, state, fn, mem, dur)
    v, a, r, f = turning_metrics(model, sim, t_start, pr["fall_height"])
    for k, st in enumerate(plain[:-1]):
        i = TU.STRATEGIES.index(st)
        sl = slice(k * S, (k + 1) * S)
        out["speed"][i], out["angular_speed"][i], out["turning_radius"][i] = v[sl], a[sl], r[sl]
        fallen[i] = f[sl]
    v0, a0 = v[-S:], a[-S:]
    weak = model.replace(servo_max_torque=np.asarray(
        TU.torque_limits(model, tc["torque_scale"]), np.float32))
    mem = _turn_memory(cfg, table, seeds, ["torque"] * len(plain))
    sim = R.simulate(weak, state, fn, mem, dur)
    i = TU.STRATEGIES.index("torque")
    res = turning_metrics(weak, sim, t_start, pr["fall_height"])
    out["speed"][i], out["angular_speed"][i], out["turning_radius"][i], fallen[i] = \
        (x[:S] for x in res)
    stable = (~fallen) & (out["angular_speed"] >= tc["min_angular_speed"])
    dims = ("strategy", "seed")
    ds = xr.Dataset(
        dict(speed=(dims, out["speed"], dict(units="m s-1", long_name="speed of the trunk centre")),
             angular_speed=(dims, out["angular_speed"], dict(
                 units="degree s-1", long_name="yaw rate, + in the commanded direction")),
             turning_radius=(dims, out["turning_radius"], dict(
                 units="m", long_name="radius of the circle fitted to the trunk centre")),
             stable=(dims, stable.astype(float), dict(
                 units="1", long_name="1 if upright and turning at >= min_angular_speed")),
             fallen=(dims, fallen.astype(float), dict(units="1", long_name="1 if the robot fell")),
             forward_speed=(("seed",), v0, dict(
                 units="m s-1", long_name="speed of the same gait walking straight")),
             forward_angular_speed=(("seed",), a0, dict(
                 units="degree s-1", long_name="yaw drift of the straight gait"))),
        coords=dict(strategy=list(TU.STRATEGIES), seed=seeds))
    ds.attrs.update(thesis_ref="Tab. 3.2", seeds=seeds,
                    **{f"turning_{k}": v for k, v in tc.items()})
    return ds


def fig3_5(ctx) -> xr.Dataset:
    """Fig. 3.5: lateral-shift tracking of the LED with a P-controller on its bearing,
    by step size and by scapulae (§3.3.3). The robot starts ``lateral_offset`` beside the
    treadmill's centre line, facing forward; the set point is the centre line."""
    cfg, table = ctx.config, _load_table(ctx)
    kc, tc, pr = cfg["tracking"], cfg["turning"], cfg["protocol"]
    seeds = list(cfg["seeds"])
    model, state = model_of(cfg)
    fam = FAMILIES["half_ellipse"]
    trunk = O.trunk_index(model)
    c = model.camera_names.index("onboard")
    f_px = float(model.camera_focal[c]) / float(model.camera_sensor[c][0]) * model.camera_pixels[c][0]
    cam_x = float(model.camera_pos[c][0])
    strategies = ("step_size", "scapulae")
    dur = pr["settle"] + kc["transition_seconds"] + kc["run_seconds"]
    fn = TU.tracking_command_fn(fam, float(pr["settle"]), float(kc["transition_seconds"]),
                                float(pr["led_distance"]), float(pr["led_height"]), f_px,
                                trunk, cam_x)
    ps = []
    for s in seeds:
        p0 = best_params(table, "half_ellipse", s)
        p0[fam.index("f")] = tc["frequency"]
        ps.append(p0)
    n, k = len(seeds), len(strategies)
    mem = dict(params=np.asarray(ps * k, np.float32),
               gain=np.repeat([kc[f"gain_{st}"] for st in strategies], n).astype(np.float32),
               reduced_a=np.full(n * k, tc["reduced_a"], np.float32),
               yaw_max=np.full(n * k, np.deg2rad(tc["yaw_deg"]), np.float32),
               scapulae=np.repeat([st == "scapulae" for st in strategies], n).astype(np.float32))
    sim = R.simulate(model, state, fn, mem, dur, lateral=np.full(n * k, kc["lateral_offset"]))
    bad = R.exploded(model, sim).reshape(k, n)
    lat = sim["pos"][:, :, trunk, 1].reshape(k, n, -1)
    yaw = np.degrees(R.yaw_of(sim["rot"][:, :, trunk])).reshape(k, n, -1)
    t = sim["t"]
    dims = ("strategy", "seed", "time")
    ds = xr.Dataset(
        dict(lateral_position=(dims, np.asarray(lat), dict(
                 units="m", long_name="lateral position of the trunk centre")),
             yaw=(dims, np.asarray(yaw), dict(units="degree", long_name="heading vs forward")),
             setpoint=((), 0.0, dict(units="m", long_name="lateral set point (LED line)")),
             exploded=(("strategy", "seed"), np.asarray(bad, float), dict(
                 units="1", long_name="1 if the simulation went unphysical"))),
        coords=dict(strategy=list(strategies), seed=seeds, time=t))
    ds["time"].attrs.update(units="s", long_name="time since start")
    ds.attrs.update(thesis_ref="Fig. 3.5", seeds=seeds,
                    gait_period=1.0 / float(tc["frequency"]),
                    tracking_start=pr["settle"] + kc["transition_seconds"],
                    **{f"tracking_{k}": v for k, v in kc.items()})
    return ds
