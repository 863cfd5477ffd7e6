"""Experiment functions of chapter 6 (registered in :mod:`thesis.registry`).

``teacher`` runs the open-loop teachers through the protocol (the fixed ones of the config,
or a screen of chapter 3's optima, input ``table3_1``); every other simulation reads its
choice (input ``teacher``) and trains and tests a sweep of
controller configurations over the profile's seeds (:func:`thesis.ch6.sweep.run`):

=================  ====================================================================
``trot``           H = 50, B = 5 (§6.5, Fig. 6.4); with the same controller the
                   phase-1-only ablation (§6.4) and the sweep of the motors-off duration
``walk``           the walk with H = 50, B = 12 and 30-s stages, and with the trot's
                   settings (H = 50, B = 5, 10-s stages) as the control (§6.5)
``linear_feedback`` no hidden layer: x_rls = [x; 1] (§6.3.1)
``minimal_hidden`` B = 0, a sweep of H (§6.5 "H = 128 ± 32")
``minimal_buffer`` H = 12, a sweep of B (§6.5 "B ... at least 16")
``minimal_training`` H = 250, B = 0, a sweep of the stage length (§6.5 "1.18 s")
=================  ====================================================================

``fig6_4`` and ``fig6_5`` extract the right hind leg's joint-space trajectories of the
trot and the walk; ``fig6_6`` joins the training MSE, N and outcome of every run with
10-s stages (``trot``, ``linear_feedback``, ``minimal_hidden``, ``minimal_buffer``) and
the MSE curves of Fig. 6.6. Sizes, grids and thresholds come from the ``ch6`` section.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from thesis.ch6 import criteria as K
from thesis.ch6 import protocol as PR
from thesis.ch6 import sweep as S
from thesis.ch6 import teacher as TE
from thesis.ch6 import loop
from thesis.ch6 import twins
from thesis.gaits import trajectories as T

Condition = S.Condition


def _stage(cfg) -> float:
    return float(cfg["protocol"]["stage_seconds"])


def _off(cfg) -> float:
    return float(cfg["protocol"]["power_off"])


def _hb(h: int, b: int) -> str:
    return f"h{int(h)}_b{int(b)}"


# ------------------------------------------------------------------ teacher screen
def teacher(ctx) -> xr.Dataset:
    """The teacher screen of :mod:`thesis.ch6.teacher` (§6.4): every candidate (the
    fixed teachers, or chapter 3's optima) open loop through its gait's protocol; the
    chosen trot and walk teachers."""
    cfg = ctx.config
    tc, wc = cfg["teacher"], cfg["walk"]
    freq = float(tc["frequency"])
    table = xr.load_dataset(ctx.input("table3_1")) if tc["source"] == "screen" else None
    cands, teachers, conditions = [], {}, []
    for gait in TE.GAITS:
        offsets = T.TROT_PHASE if gait == "trot" else tuple(wc["phase_offsets"])
        duty = None if gait == "trot" else float(wc["duty"])
        stage = _stage(cfg) if gait == "trot" else float(wc["stage_seconds"])
        if table is None:  # the configured teacher, screened as a check
            fam_name, p = TE.fixed_params(tc["fixed"][gait], gait, freq, duty)
            found = [(f"{gait}/{fam_name}/fixed", fam_name, -1, np.nan, p)]
        else:
            found = [(f"{gait}/{fam_name}/seed{int(s)}/stride{float(scale):g}", fam_name,
                      int(s), float(scale),
                      TE.candidate_params(table, fam_name, s, freq, float(scale), duty))
                     for fam_name in tc["families"] for s in table["seed"].values
                     for scale in tc["stride_scales"]]
        for key, fam_name, s, scale, p in found:
            teachers[key] = (TE.family(fam_name, offsets), p, freq)
            conditions.append(Condition(key, key, 1, 0, stage, stage, _off(cfg)))
            cands.append((gait, fam_name, s, scale, p))
    model, state = S.model_of(cfg)
    dt = S.controller_dt(cfg)
    runs, labels, scheds, _, n = S.build_runs(conditions, [0], teachers, cfg, ctx.root_seed,
                                              open_loop=True)
    k_runs, rel = len(runs), S.perturbation(cfg)
    if rel > 0:  # the perturbed twins of the screen (thesis.ch6.twins)
        t_runs, t_labels, *_ = S.build_runs(conditions, [0], teachers, cfg, ctx.root_seed,
                                            open_loop=True, perturb=rel)
        runs, labels = runs + t_runs, labels + t_labels
    rec, timing = loop.simulate(model, state, runs, int(cfg["control"]["substeps"]),
                                experiment=ctx.key, labels=labels)
    ctx.log.info("ch6 teacher screen: %d candidates x %d steps, compile %.1f s, rollout "
                 "%.1f s", len(runs), n, timing["compile_seconds"], timing["rollout_seconds"])
    crit = cfg["criteria"]
    names = []  # the union of the candidates' families' parameters, in family order
    for fam_name in dict.fromkeys(c[1] for c in cands):
        names += [n for n in TE.PARAM_NAMES[fam_name] if n not in names]
    k_all = len(cands)
    res = {k: np.full(k_all, np.nan) for k in
           ("fallen", "up_seconds", "speed", "rec_down", "rec_speed", "passed")}
    params = np.full((k_all, len(names)), np.nan)
    for i, ((gait, fam_name, s, scale, p), sch) in enumerate(zip(cands, scheds)):
        m = screen_metrics(rec["trunk_pos"][i], rec["trunk_up"][i], sch, dt, crit)
        for k in res:
            res[k][i] = m[k]
        for j, name in enumerate(TE.PARAM_NAMES[fam_name]):
            params[i, names.index(name)] = p[j]
    twin = {k: np.full(k_all, np.nan) for k in res}
    if rel > 0:
        for i, sch in enumerate(scheds):
            m = screen_metrics(rec["trunk_pos"][k_runs + i], rec["trunk_up"][k_runs + i], sch,
                               dt, crit)
            for k in twin:
                twin[k][i] = m[k]
    gaits = [c[0] for c in cands]
    chosen, chosen_twin = {}, {}
    for gait in TE.GAITS:
        idx = np.array([i for i in range(k_all) if gaits[i] == gait])
        chosen[gait] = int(idx[TE.choose(res["passed"][idx], res["up_seconds"][idx],
                                          res["speed"][idx])])
        chosen_twin[gait] = (int(idx[TE.choose(twin["passed"][idx], twin["up_seconds"][idx],
                                               twin["speed"][idx])]) if rel > 0 else -1)
    cd = ("candidate",)
    g_idx = [chosen[g] for g in TE.GAITS]
    ds = xr.Dataset(
        dict(candidate_gait=(cd, np.array(gaits), dict(units="1", long_name="gait")),
             candidate_family=(cd, np.array([c[1] for c in cands]), dict(
                 units="1", long_name="foot-locus family of chapter 3")),
             candidate_source_seed=(cd, np.array([c[2] for c in cands]), dict(
                 units="1", long_name="chapter 3 seed whose optimum the candidate is (-1: "
                                      "the fixed teacher of teacher.fixed)")),
             candidate_stride_scale=(cd, np.array([c[3] for c in cands]), dict(
                 units="1", long_name="factor applied to the optimum's stride a (NaN: the "
                                      "fixed teacher)")),
             candidate_params=(("candidate", "parameter"), params, dict(
                 units="mixed (thesis units: Hz, mm, 1)", long_name="gait parameters")),
             **{f"candidate_{k}": (cd, v, dict(units=u, long_name=ln)) for k, (u, ln) in {
                 "fallen": ("1", "1 if the robot fell before the motors were switched off"),
                 "up_seconds": ("s", "time upright from the normalisation phase on"),
                 "speed": ("m s-1", "forward speed in the running window"),
                 "rec_down": ("1", "1 if down or tipped in the recovery window"),
                 "rec_speed": ("m s-1", "forward speed in the recovery window"),
                 "passed": ("1", "1 if up until power-off and walking after power-on"),
             }.items() for v in [res[k]]},
             chosen=(("gait",), np.array(g_idx), dict(
                 units="1", long_name="index of the chosen candidate")),
             candidate_passed_perturbed=(cd, twin["passed"], dict(
                 units="1", long_name="passed, the candidate's perturbed twin (NaN: no "
                                      "twins, ch6.perturbation.relative = 0)")),
             candidate_speed_perturbed=(cd, twin["speed"], dict(
                 units="m s-1", long_name="running-window speed, the perturbed twin")),
             chosen_perturbed=(("gait",), np.array([chosen_twin[g] for g in TE.GAITS]), dict(
                 units="1", long_name="index of the candidate the screen chooses from the "
                                      "perturbed twins (-1: no twins)")),
             teacher_family=(("gait",), np.array([cands[i][1] for i in g_idx]), dict(
                 units="1", long_name="family of the chosen teacher")),
             teacher_params=(("gait", "parameter"), params[g_idx], dict(
                 units="mixed (thesis units: Hz, mm, 1)", long_name="the teacher's parameters")),
             teacher_speed=(("gait",), res["speed"][g_idx], dict(
                 units="m s-1", long_name="the teacher's open-loop speed, running window")),
             teacher_passed=(("gait",), res["passed"][g_idx], dict(
                 units="1", long_name="1 if the chosen teacher passed the screen")),
             n_passed=(("gait",), np.array([np.nansum(res["passed"][[i for i in range(k_all)
                                                                     if gaits[i] == g]])
                                           for g in TE.GAITS]), dict(
                 units="1", long_name="candidates that passed the screen")),
             phase_offsets=(("gait", "leg"), np.array(
                 [T.TROT_PHASE, tuple(wc["phase_offsets"])], float), dict(
                 units="1", long_name="phase offset of each leg [cycles]")),
             robot_seconds=((), len(runs) * n * dt, dict(
                 units="s", long_name="simulated robot time (every run for the longest "
                                      "schedule)")),
             robot_seconds_per_wall_second=((), len(runs) * n * dt
                                            / timing["rollout_seconds"], dict(
                 units="1", measurement="wall_clock",
                 long_name="simulated robot-seconds per wall-second of the rollout"))),
        coords=dict(candidate=[c.name for c in conditions], parameter=names,
                    gait=list(TE.GAITS), leg=["LF", "RF", "LH", "RH"]))
    ds.attrs.update(thesis_ref="§6.4", teacher_source=tc["source"],
                    # the chapter 3 seeds screened, or the one run seed of the fixed teachers
                    seeds=[0] if table is None else [int(s) for s in table["seed"].values],
                    perturbation_relative=rel,
                    frequency=tc["frequency"], stride_scales=list(tc["stride_scales"]),
                    walk_duty=wc["duty"])
    return ds


def screen_metrics(trunk_pos, trunk_up, schedule: PR.Schedule, dt: float, crit) -> dict:
    """Open-loop screen of one candidate: fallen before power-off, seconds upright from
    the normalisation on, speed in the running window, down or speed in the recovery
    window, passed (see :mod:`thesis.ch6.teacher`)."""
    b = schedule.bounds()
    a, e = PR.n_steps(b["normalisation"][0], dt), PR.n_steps(b["off"][0], dt)
    z, up = trunk_pos[a:e, 2], trunk_up[a:e]
    bad = (z < crit["fall_height"]) | (up < K.MIN_UP) | (z > K.EXPLODED_HEIGHT)
    down = K.fallen(trunk_pos[a:e], trunk_up[a:e], crit["fall_height"], dt)
    up_s = (int(np.argmax(bad)) if bad.any() else len(bad)) * dt
    run = PR.window(schedule, "running", dt, last=crit["window"])
    rec = PR.window(schedule, "recovery", dt, skip=crit["recovery_within"])
    rec_down = K.fallen(trunk_pos[rec], trunk_up[rec], crit["fall_height"], dt)
    rec_speed = K.forward_speed(trunk_pos[rec], dt)
    passed = (not down) and (not rec_down) and rec_speed > crit["min_speed"]
    return dict(fallen=float(down), up_seconds=up_s,
                speed=K.forward_speed(trunk_pos[run], dt), rec_down=float(rec_down),
                rec_speed=rec_speed, passed=float(passed))


# ------------------------------------------------------------------ controller sweeps
def trot(ctx) -> xr.Dataset:
    """§6.5 / Fig. 6.4: the trot with H = 50, B = 5 (``ch6.trot``, role ``base``); with the
    same controller and seeds, trained by the first stage only (§6.4, role
    ``phase1_only``: the running stage follows the first stage) and with the motors off
    for each duration of ``ch6.power_off.seconds`` other than the protocol's (role
    ``power_off``; the thesis does not state the duration). One batch: the variants share
    the base's hidden layers and training noise seed by seed."""
    cfg = ctx.config
    c, st, off = cfg["trot"], _stage(cfg), _off(cfg)
    name = _hb(c["hidden"], c["buffer"])
    conds = [Condition(name, "trot", c["hidden"], c["buffer"], st, st, off),
             Condition(name + "_phase1_only", "trot", c["hidden"], c["buffer"], st, 0.0, off,
                       role="phase1_only")]
    conds += [Condition(f"{name}_off{float(t):g}s", "trot", c["hidden"], c["buffer"], st, st,
                        float(t), role="power_off")
              for t in cfg["power_off"]["seconds"] if abs(float(t) - off) > 1e-9]
    return S.run(ctx, conds, thesis_ref="§6.5, §6.4, Fig. 6.4", joint_space=True)


def walk(ctx) -> xr.Dataset:
    """§6.5 / Fig. 6.5: the walk with H = 50, B = 12 and longer stages, and the walk with
    the trot's settings as the control (``ch6.walk``)."""
    w = ctx.config["walk"]
    c = w["control"]
    conds = [Condition("walk_" + _hb(w["hidden"], w["buffer"]), "walk", w["hidden"],
                       w["buffer"], w["stage_seconds"], w["stage_seconds"], _off(ctx.config)),
             Condition("trot_settings_" + _hb(c["hidden"], c["buffer"]), "walk", c["hidden"],
                       c["buffer"], c["stage_seconds"], c["stage_seconds"], _off(ctx.config))]
    return S.run(ctx, conds, thesis_ref="§6.5, Fig. 6.5", joint_space=True)


def linear_feedback(ctx) -> xr.Dataset:
    """§6.3.1: linear feedback, x_rls = [x; 1] (no hidden layer, no buffer)."""
    st = _stage(ctx.config)
    cond = Condition("linear", "trot", 0, 0, st, st, _off(ctx.config), linear=True)
    return S.run(ctx, [cond], thesis_ref="§6.3.1")


def minimal_hidden(ctx) -> xr.Dataset:
    """§6.5: B = 0 and a sweep of H (``ch6.minimal_hidden``)."""
    c, st = ctx.config["minimal_hidden"], _stage(ctx.config)
    conds = [Condition(_hb(h, c["buffer"]), "trot", h, c["buffer"], st, st, _off(ctx.config))
             for h in c["hidden"]]
    return S.run(ctx, conds, thesis_ref="§6.5")


def minimal_buffer(ctx) -> xr.Dataset:
    """§6.5: H = 12 and a sweep of B (``ch6.minimal_buffer``)."""
    c, st = ctx.config["minimal_buffer"], _stage(ctx.config)
    conds = [Condition(_hb(c["hidden"], b), "trot", c["hidden"], b, st, st, _off(ctx.config))
             for b in c["buffer"]]
    return S.run(ctx, conds, thesis_ref="§6.5")


def minimal_training(ctx) -> xr.Dataset:
    """§6.5: H = 250, B = 0 and a sweep of the stage length (``ch6.minimal_training``)."""
    c = ctx.config["minimal_training"]
    conds = [Condition(f"stage{float(t):g}s", "trot", c["hidden"], c["buffer"], t, t,
                       _off(ctx.config)) for t in c["stage_seconds"]]
    return S.run(ctx, conds, thesis_ref="§6.5")


# ------------------------------------------------------------------ figures from results
_JOINT_SPACE = ("rh_teacher", "rh_learned", "success", "outcome", "n_signals", "hidden",
                "buffer", "gait_period", "role")


def _with_twins(src: xr.Dataset, names) -> list[str]:
    """``names`` and, where ``src`` has them, their perturbed twins and ``flipped``
    (:mod:`thesis.ch6.twins`), so a figure's claims can be decided on both."""
    extra = [n + twins.SUFFIX for n in names if n + twins.SUFFIX in src]
    return list(names) + extra + (["flipped"] if extra and "flipped" in src else [])


def _joint_space(ctx, name: str, ref: str, base_only: bool) -> xr.Dataset:
    src = xr.load_dataset(ctx.input(name))
    if base_only:
        src = src.isel(config=np.flatnonzero(src["role"].values == "base"))
    ds = src[_with_twins(src, _JOINT_SPACE)]
    ds.attrs = {k: v for k, v in src.attrs.items() if k.startswith("teacher_")
                or k in ("controller_dt",)}
    ds.attrs.update(thesis_ref=ref, seeds=[int(s) for s in src["seed"].values], source=name)
    return twins.tolerances(ds)


def fig6_4(ctx) -> xr.Dataset:
    """Fig. 6.4: the right hind leg in joint space, teacher and learned trot (from
    ``trot``)."""
    return _joint_space(ctx, "trot", "Fig. 6.4", base_only=True)


def fig6_5(ctx) -> xr.Dataset:
    """Fig. 6.5 (printed as a second "Fig. 6.4"): the same for the walk (from ``walk``)."""
    return _joint_space(ctx, "walk", "Fig. 6.5", base_only=False)


#: Sources of Fig. 6.6's table of runs: the sweeps with the profile's stage length.
FIG6_6_SOURCES = ("linear_feedback", "trot", "minimal_hidden", "minimal_buffer")


def fig6_6(ctx) -> xr.Dataset:
    """Fig. 6.6 and §6.6: training MSE, N and outcome of every run with the profile's
    stage length (the trot's ablation and power-off variants left out: they train like
    its base), and the MSE curves of the configured settings (``ch6.fig6_6.curves``:
    the thesis's "without time window", "reduced number of hidden neurons" and "failed
    ... not enough signals")."""
    src = {n: xr.load_dataset(ctx.input(n)) for n in FIG6_6_SOURCES}
    parts = []
    for n, ds in src.items():
        ds = ds.isel(config=np.flatnonzero(ds["role"].values == "base"))
        part = ds[_with_twins(ds, ("train_mse", "end_mse", "success", "outcome", "hidden",
                                   "buffer", "n_signals", "mse_curve"))]
        part = part.assign_coords(config=[f"{n}/{c}" for c in ds["config"].values])
        parts.append(part.rename(config="setting"))
    table = xr.concat(parts, dim="setting", join="outer")
    setting = list(table["setting"].values)
    curves = ctx.config["fig6_6"]["curves"]
    names = []
    for c in curves:
        key = f"{c['source']}/{c['config']}"
        if key not in setting:
            raise KeyError(f"ch6.fig6_6.curves: {key!r} is not a setting of "
                           f"{', '.join(FIG6_6_SOURCES)}; have {setting}")
        names.append(key)
    out = table
    for name in ("mse_curve", "mse_curve" + twins.SUFFIX):
        if name not in table:
            continue
        curve = table[name].sel(setting=names).rename(setting="curve")
        out = out.drop_vars(name)
        out[name.replace("mse_curve", "curve_mse")] = curve.assign_attrs(table[name].attrs)
    out["curve_kind"] = (("curve",), np.array([c["kind"] for c in curves]), dict(
        units="1", long_name="kind of curve of Fig. 6.6"))
    out["source"] = (("setting",), np.array([s.split("/")[0] for s in setting]), dict(
        units="1", long_name="experiment the run comes from"))
    for v in ("hidden", "buffer", "n_signals"):
        out[v] = out[v].astype(float)
    out["train_time"].attrs.update(units="s", long_name="time since the first training stage")
    out.attrs = {k: v for k, v in src["trot"].attrs.items()
                 if k.startswith(("protocol_", "criteria_"))}
    out.attrs.update(thesis_ref="Fig. 6.6, §6.6", seeds=[int(s) for s in out["seed"].values])
    return twins.tolerances(out)
