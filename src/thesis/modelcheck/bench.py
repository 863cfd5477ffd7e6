"""``thesis bench oncilla`` (registry ``model/oncilla``): the model-level checks of
:mod:`thesis.modelcheck.checks` on the current Oncilla, written as one dataset
(``results/<profile>/model/oncilla.nc``; ``--output`` for a second model beside it).

Runs, all on one compiled rollout of ``settle + seconds`` simulated seconds (the ch4
protocol's ``settle``, then ``seconds`` of gait or standing):

* one robot standing (build pose held): the standing pose at the end;
* per push impulse J of ``pushes`` [N s], a robot standing and one trotting the nominal
  gait, the trunk's velocity changed by J / m_trunk sideways (+y) ``push_time`` seconds
  after ``settle``;
* one robot trotting the nominal gait unpushed (encoder information);
* ``gaits`` random Tab. 4.1 trots from standstill (stream ``model/oncilla/gaits`` of the
  root seed).

Sizes from the ``physics.oncilla_model`` config section; the model (time step, solver)
and the protocol (``settle``, ``fall_height``) from ``ch4.model`` and ``ch4.protocol``,
so the checks measure the Oncilla chapter 4 runs, untethered.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from thesis import seeding, store
from thesis.gaits import conditions as C
from thesis.gaits import leg as L
from thesis.modelcheck import checks as M
from thesis.gaits import runner as R

#: Parameters binned against, with their ranges (Tab. 4.1; a up to a_max(126 mm)).
BINNED = ("a", "x0", "f", "a_fraction")


def _edges(name: str, bins: int) -> np.ndarray:
    fam = M.FAMILY
    lo, hi = {"a": (0.0, float(fam.upper[fam.index("a")])),
              "x0": (float(fam.lower[fam.index("x0")]), float(fam.upper[fam.index("x0")])),
              "f": (float(fam.lower[fam.index("f")]), float(fam.upper[fam.index("f")])),
              "a_fraction": (0.0, 1.0)}[name]
    return np.linspace(lo, hi, int(bins) + 1)


def plan_runs(cfg: dict, root_seed: int, trunk_mass: float, settle: float) -> tuple[dict, dict]:
    """(runs, index) of the bench: the per-run arrays of
    :func:`thesis.modelcheck.checks.simulate_runs` and the run indices of each group
    (``stand``, ``push_standing``, ``push_trotting``, ``nominal``, ``gaits``)."""
    pushes = np.asarray(cfg["pushes"], np.float64)
    n_push, n_gait = len(pushes), int(cfg["gaits"])
    gaits = M.sample_gaits(seeding.rng(root_seed, "model/oncilla/gaits", 0), n_gait)
    nominal = M.nominal_gait()
    t_push = settle + float(cfg["push_time"])
    p = np.concatenate([nominal[None], np.tile(nominal, (2 * n_push + 1, 1)), gaits])
    stand = np.zeros(len(p))
    stand[:1 + n_push] = 1.0
    kick = np.zeros((len(p), 3))
    kick[1:1 + 2 * n_push, 1] = np.tile(pushes, 2) / trunk_mass
    kick_time = np.full(len(p), np.inf)
    kick_time[1:1 + 2 * n_push] = t_push
    first = 2 + 2 * n_push
    index = dict(stand=np.array([0]), push_standing=np.arange(1, 1 + n_push),
                 push_trotting=np.arange(1 + n_push, 1 + 2 * n_push),
                 nominal=np.array([1 + 2 * n_push]), gaits=np.arange(first, first + n_gait))
    return dict(p=p, stand=stand, kick=kick, kick_time=kick_time), index


def gait_phase(p, t, settle: float) -> np.ndarray:
    """(R, K) gait phase [cycles] of the command held over each 10-ms period ending at
    ``t`` (K,) [s] for spline trots ``p`` (R, 12): f (t_cmd - settle), the gait starting
    at phase 0 when the settle ends (:func:`thesis.gaits.runner.protocol_commands`)."""
    f = np.asarray(p, np.float64)[:, M.FAMILY.index("f")]
    t_cmd = np.asarray(t, np.float64) - R.COMMAND_PERIOD
    return f[:, None] * (t_cmd[None] - settle)


def _push_terms(model, sim, t_push: float, fall_height: float):
    """(fell before the push, fell after it, largest trunk tilt after it [rad], largest
    scapula deflection from its command after it, while upright [rad]) per run."""
    before = R.speed_terms(model, sim, 0.0, fall_height, t_push)["fallen"]
    after = R.speed_terms(model, sim, t_push, fall_height)["fallen"]
    trunk = M.O.trunk_index(model)
    w = R.window(sim["t"], t_push, sim["t"][-1], len(after))
    tilt = np.arccos(np.clip(sim["rot"][:, :, trunk, 2, 2], -1.0, 1.0))
    max_tilt = np.where(w, tilt, 0.0).max(1)
    up = M.upright_mask(model, sim, fall_height, t_push)
    dev = np.abs(sim["q"][..., M.scapula_dofs(model)]
                 - sim["cmd"][..., list(M.SCAPULA_COMMANDS)]).max(-1)
    deflection = np.where(up.any(1), np.where(up, dev, 0.0).max(1), np.nan)
    return before, after, max_tilt, deflection


def oncilla(ctx) -> xr.Dataset:
    """``thesis bench oncilla``: standing pose, fall rate of random Tab. 4.1 trots against
    a, x0, f, lateral push recovery and the encoders' information (module docstring;
    :mod:`thesis.modelcheck.checks`)."""
    full = ctx.full_config
    cfg = full["physics"]["oncilla_model"]
    ch4 = full["ch4"]
    pr = ch4["protocol"]
    settle = float(pr["settle"])
    fall_height = float(pr["fall_height"])
    seconds = float(cfg["seconds"])
    if not 0.0 < float(cfg["push_time"]) < seconds:
        raise ValueError(f"physics.oncilla_model.push_time ({cfg['push_time']} s) must lie "
                         f"inside seconds ({seconds} s)")
    model, state = C.base_model(ch4)
    model = C.untethered(model)
    trunk = M.O.trunk_index(model)
    runs, ix = plan_runs(cfg, ctx.root_seed, float(np.asarray(model.body_mass)[trunk]), settle)
    sim = M.simulate_runs(model, state, runs, duration=settle + seconds, settle=settle,
                          t_transition=M.SELF_TRANSITION, batch=int(cfg["batch"]))
    ctx.log.info("oncilla model checks: %d runs x %.2f s in %.1f s", len(runs["p"]),
                 settle + seconds, sim["wall"])
    fam = M.FAMILY

    # standing
    st = M.standing(model, state, sim, int(ix["stand"][0]))
    # random gaits
    g = M.select(sim, ix["gaits"])
    terms = R.speed_terms(model, g, 0.0, fall_height)
    kind = M.fall_kind(model, g, fall_height)
    down_t = np.where(terms["fallen"], terms["upright"] * g["t"][-1], np.nan)
    gp = runs["p"][ix["gaits"]]
    values = dict(a=gp[:, fam.index("a")], x0=gp[:, fam.index("x0")], f=gp[:, fam.index("f")])
    values["a_fraction"] = values["a"] / np.maximum(fam.a_max(values["x0"]), 1e-9)
    bins = {n: M.fall_rate_bins(values[n], terms["fallen"], _edges(n, cfg["bins"]))
            for n in BINNED}
    # pushes
    t_push = settle + float(cfg["push_time"])
    push = {pos: _push_terms(model, M.select(sim, ix[f"push_{pos}"]), t_push, fall_height)
            for pos in M.POSTURES}
    # encoders
    t_enc = settle + float(cfg["encoder_warmup"])
    nom = M.select(sim, ix["nominal"])
    enc_nom = M.encoder_information(model, nom, M.upright_mask(model, nom, fall_height, t_enc),
                                    gait_phase(runs["p"][ix["nominal"]], sim["t"], settle))
    enc = M.encoder_information(model, g, M.upright_mask(model, g, fall_height, t_enc),
                                gait_phase(gp, sim["t"], settle))
    need = int(round(float(cfg["encoder_min_seconds"]) / R.COMMAND_PERIOD))
    used = enc["samples"] >= need
    nominal_kind = M.fall_kind(model, nom, fall_height)[0]

    def a(units, long_name, **extra):
        return dict(units=units, long_name=long_name, **extra)

    J, G = ("joint",), ("gait",)
    data = dict(
        stand_trunk_height=((), st["trunk_height"], a("m", "settled trunk-centre height, "
                                                            "standing")),
        nominal_trunk_height=((), st["nominal_trunk_height"], a(
            "m", "kinematic trunk-centre height of the build pose (toes BUILD_DEPTH below "
                 "the hips, resting on the floor)")),
        stand_com_height=((), st["com_height"], a("m", "settled centre-of-mass height, "
                                                        "standing")),
        nominal_com_height=((), st["nominal_com_height"], a(
            "m", "centre-of-mass height of the build pose")),
        stand_toe=(("leg", "axis"), st["toe"], a("m", "settled toe-sphere centre in the "
                                                      "hip frame (trunk axes), standing")),
        nominal_toe=(("leg", "axis"), st["nominal_toe"], a("m", "nominal toe position in "
                                                                "the hip frame")),
        stand_trunk_tilt=((), st["trunk_tilt"], a("rad", "trunk up axis from the vertical, "
                                                         "standing")),
        stand_knee_fold=(("leg",), st["knee_fold"], a(
            "rad", "tibia folded beyond the cable (knee spring compression), standing")),
        stand_scapula=(("leg",), st["scapula"], a("rad", "scapula angle, standing")),
        gait_params=(("gait", "parameter"), gp, a("mixed (Tab. 4.1 units: Hz, mm, 1)",
                                                  "random Tab. 4.1 spline trot")),
        gait_a_fraction=(G, values["a_fraction"], a("1", "a / a_max(x0)")),
        fallen=(G, terms["fallen"].astype(np.int8), a("1", "1 if the trot from standstill "
                                                           "fell (ch3/ch4 criterion)")),
        fall_time=(G, down_t, a("s", "time of the first fall from the start (NaN: "
                                     "stayed up)")),
        fall_kind=(G, np.array([M.FALL_KINDS[k] for k in kind]), a(
            "1", "how the run first fell: " + ", ".join(M.FALL_KINDS))),
        speed=(G, terms["speed"], a("m s-1", "mean forward trunk speed from the start")),
        fall_rate=((), float(terms["fallen"].mean()), a("1", "fraction of the random "
                                                             "trots that fell")),
        roll_fall_rate=((), float((kind == M.FALL_KINDS.index("roll")).mean()), a(
            "1", "fraction of the random trots that fell by rolling over sideways")),
        push_fell_before=(("posture", "push"),
                          np.stack([push[p][0] for p in M.POSTURES]).astype(np.int8),
                          a("1", "1 if down before the push landed")),
        push_fallen=(("posture", "push"),
                     np.stack([push[p][1] for p in M.POSTURES]).astype(np.int8),
                     a("1", "1 if down at any time after the push (not recovered)")),
        push_max_tilt=(("posture", "push"), np.stack([push[p][2] for p in M.POSTURES]),
                       a("rad", "largest trunk tilt after the push")),
        push_scapula_deflection=(("posture", "push"),
                                 np.stack([push[p][3] for p in M.POSTURES]),
                                 a("rad", "largest scapula deviation from its command after "
                                          "the push while upright")),
        nominal_params=(("parameter",), runs["p"][ix["nominal"][0]], a(
            "mixed (Tab. 4.1 units)", "nominal trot (pushes while trotting, encoders)")),
        nominal_fall_kind=((), M.FALL_KINDS[nominal_kind], a("1", "fall of the unpushed "
                                                                  "nominal trot")),
        encoder_samples_nominal=((), int(enc_nom["samples"][0]), a(
            "1", "10-ms samples of the nominal trot in the encoder regressions")),
        encoder_gaits_used=((), int(used.sum()), a(
            "1", "random trots upright long enough for the encoder regressions")),
        encoder_samples=(G, enc["samples"], a("1", "10-ms samples in the encoder "
                                                   "regressions")),
    )
    enc_long = dict(r2_forces="R^2 of encoder minus command on the 12 toe contact forces",
                    r2_command="R^2 of encoder minus command on the joint's command over "
                               f"the last {M.COMMAND_LAGS} periods",
                    r2_both="R^2 of encoder minus command on the command's last "
                            f"{M.COMMAND_LAGS} periods and the toe contact forces",
                    r2_forces_given_command="share of the variance the command leaves "
                                            "unexplained that the toe contact forces explain",
                    r2_forces_beyond_phase="R^2 of the cycle-to-cycle part of encoder minus "
                                           "command on that of the toe contact forces",
                    error_rms="RMS of encoder minus command")
    for k, ln in enc_long.items():
        units = "rad" if k == "error_rms" else "1"
        data[f"encoder_{k}_nominal"] = (J, enc_nom[k][0], a(units, ln + ", nominal trot"))
        data[f"encoder_{k}"] = (("gait", "joint"), enc[k], a(units, ln + ", per random trot"))
        with warnings.catch_warnings():  # an all-NaN column: mean of empty slice
            warnings.simplefilter("ignore", RuntimeWarning)
            mean = np.nanmean(np.where(used[:, None], enc[k], np.nan), axis=0)
        data[f"encoder_{k}_mean"] = (J, mean, a(units, ln + ", mean over the random trots "
                                                       "used"))
    coords = dict(gait=np.arange(len(gp)), parameter=list(fam.names), joint=list(M.ENCODERS),
                  leg=list(L.LEGS), axis=["x", "y", "z"], posture=list(M.POSTURES),
                  push=np.asarray(cfg["pushes"], np.float64))
    for n in BINNED:
        b = bins[n]
        dim = f"{n}_bin"
        coords[dim] = b["centre"]
        unit = "1" if n == "a_fraction" else dict(zip(fam.names, fam.units))[n]
        data[f"fall_rate_by_{n}"] = ((dim,), b["rate"], a("1", f"fall rate of the random "
                                                               f"trots per {n} bin"))
        data[f"falls_by_{n}"] = ((dim,), b["falls"], a("1", f"fallen trots per {n} bin"))
        data[f"gaits_by_{n}"] = ((dim,), b["n"], a("1", f"trots per {n} bin"))
        data[f"{n}_bin_edges"] = ((f"{n}_edge",), _edges(n, cfg["bins"]), a(unit, f"{n} bin "
                                                                                  "edges"))
    data["rollout_wall_seconds"] = ((), sim["wall"], a("s", "wall time of the rollouts, "
                                                            "compilation included",
                                                       **store.WALL_CLOCK))
    ds = xr.Dataset(data, coords=coords)
    ds["push"].attrs.update(units="N s", long_name="lateral impulse on the trunk (+y)")
    for n in BINNED:
        ds[f"{n}_bin"].attrs.update(units="1" if n == "a_fraction" else
                                    dict(zip(fam.names, fam.units))[n],
                                    long_name=f"{n} bin centre")
    ds.attrs.update(
        title="Model-level checks of the simulated Oncilla",
        thesis_ref="Tab. 4.1, §4.5-4.6 (random trots, fall criterion); §3.2.1 (standing); "
                   "§6.1-6.2 (encoders)",
        model_label=str(cfg["label"]), model_code_sha256=M.model_code_sha256(),
        seeds=[int(ctx.root_seed)], gaits=int(cfg["gaits"]), seconds=seconds,
        settle=settle, push_time=float(cfg["push_time"]), fall_height=fall_height,
        encoder_warmup=float(cfg["encoder_warmup"]),
        encoder_min_seconds=float(cfg["encoder_min_seconds"]),
        phase_harmonics=M.PHASE_HARMONICS, command_lags=M.COMMAND_LAGS,
        untethered=1, floor="flat", trunk_mass=float(np.asarray(model.body_mass)[trunk]))
    return ds

