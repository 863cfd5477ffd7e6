"""A sweep of controller configurations x seeds through the §6.4 protocol, as one dataset.

A :class:`Condition` is one controller configuration and protocol variant (H, B, stage
lengths, power-off duration, gait); :func:`run` trains and tests every condition for
every seed of the profile in one batched simulation (:func:`thesis.ch6.loop.simulate`)
and evaluates each run with :mod:`thesis.ch6.criteria`.

Random streams (:mod:`thesis.seeding`), common to all conditions and experiments of a
seed: ``"ch6/hidden"`` gives the hidden weights (a configuration with H units uses the
first H units of the seed's draw, :func:`thesis.ch6.controller.draw_hidden`) and
``"ch6/noise"`` the training input noise, so that conditions differ only by what they
vary.

Dataset layout (dims ``config``, ``seed``; see :func:`run`): per run the outcome and the
metrics of the criteria, the training MSE and the MSE curve over training time; per
config H, B, N, the stage and power-off lengths; the simulation rate (wall clock).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.ch6 import controller as C
from thesis.ch6 import criteria as K
from thesis.ch6 import loop
from thesis.ch6 import protocol as PR
from thesis.ch6 import teacher as TE
from thesis.ch6 import twins
from thesis.physics.models.oncilla_config import oncilla_from_config

#: Per-run metrics stored (criteria.evaluate keys) -> (units, long_name).
METRICS = {
    "success": ("1", "1 if stable for the running stage and back in gait after power-on"),
    "stable_running": ("1", "1 if upright, amplitude and period criteria met while running"),
    "recovered": ("1", "1 if the gait returned after the motors were powered back on"),
    "fallen": ("1", "1 if the robot fell between the first training stage and power-off"),
    "amplitude": ("1", "mean std(output) / std(teacher) over hip and knee, running window"),
    "frequency": ("Hz", "dominant frequency of the hip and knee outputs, running window"),
    "teacher_frequency": ("Hz", "dominant frequency of the teacher's hip and knee commands"),
    "autocorrelation": ("1", "output autocorrelation at one teacher period, running window"),
    "speed": ("m s-1", "forward speed of the trunk, running window"),
    "rec_amplitude": ("1", "amplitude ratio in the recovery window"),
    "rec_frequency": ("Hz", "dominant output frequency in the recovery window"),
    "rec_autocorrelation": ("1", "output autocorrelation at one period, recovery window"),
    "rec_speed": ("m s-1", "forward speed of the trunk in the recovery window"),
    "rec_down": ("1", "1 if the trunk was down or tipped in the recovery window"),
}


@dataclasses.dataclass(frozen=True)
class Condition:
    """One controller configuration and protocol variant.

    Attributes:
        name: coordinate value in the dataset, e.g. ``"h50_b5"``.
        gait: key of the condition's teacher in the ``teachers`` mapping: ``"trot"`` or
            ``"walk"`` (the teacher screen uses one key per candidate).
        hidden: H, hidden tanh units (ignored with ``linear``).
        buffer: B, delay-buffer length in controller steps.
        stage1, stage2: training stage lengths [s] (``stage2 = 0``: phase 1 only).
        off: motors-off duration of the power-off test [s].
        linear: linear feedback of §6.3.1 (no hidden layer: x_rls = [x; 1]).
        role: what the condition is within its experiment (``"base"``; the trot
            experiment also has ``"phase1_only"`` and ``"power_off"``).
    """

    name: str
    gait: str
    hidden: int
    buffer: int
    stage1: float
    stage2: float
    off: float
    linear: bool = False
    role: str = "base"

    @property
    def n_signals(self) -> int:
        """N, the number of signals the RLS readout receives ((B + 1) H + 1)."""
        return C.n_signals(C.N_INPUTS if self.linear else self.hidden, self.buffer)

    @property
    def width(self) -> int:
        """Rows of the hidden layer this condition needs (8 for linear feedback)."""
        return C.N_INPUTS if self.linear else int(self.hidden)


def schedule_of(cond: Condition, protocol: dict) -> PR.Schedule:
    """The :class:`thesis.ch6.protocol.Schedule` of a condition under ``ch6.protocol``."""
    return PR.Schedule(settle=protocol["settle"], normalisation=protocol["normalisation"],
                       stage1=cond.stage1, stage2=cond.stage2, running=protocol["running"],
                       off=cond.off, recovery=protocol["recovery"])


def controller_dt(cfg: dict) -> float:
    """Controller period Δt [s] = ``control.substeps`` x ``model.dt``."""
    return int(cfg["control"]["substeps"]) * float(cfg["model"]["dt"])


def model_of(cfg: dict):
    """(Model, State) of the configured Oncilla (``ch6.model``: step, sweeps, the fitted
    knee spring, the constraint softness [Hz] and the solver's warm start, relaxation and
    sweep order and contact relaxation; by default chapters 3 and 4's robot;
    :func:`thesis.physics.models.oncilla_config.oncilla_from_config`)."""
    return oncilla_from_config(cfg["model"])


def teachers_from(ds: xr.Dataset) -> dict[str, tuple]:
    """{gait: (family object, params (P,), frequency [Hz])} from a ``ch6/teacher`` dataset."""
    out = {}
    for gait in TE.GAITS:
        name = str(ds["teacher_family"].sel(gait=gait).values)
        row = ds["teacher_params"].sel(gait=gait)
        params = np.array([float(row.sel(parameter=n)) for n in TE.PARAM_NAMES[name]])
        offsets = tuple(float(x) for x in ds["phase_offsets"].sel(gait=gait).values)
        fam = TE.family(name, offsets)
        out[gait] = (fam, params, float(params[fam.index("f")]))
    return out


def _moving_average(x, n: int):
    if n <= 1:
        return x
    k = np.ones(n) / n
    return np.convolve(x, k, mode="same") / np.convolve(np.ones_like(x), k, mode="same")


def build_runs(conditions, seeds, teachers, cfg, root_seed: int, *, open_loop=False,
               perturb: float = 0.0):
    """Per-run inputs of :func:`thesis.ch6.loop.simulate` for conditions x seeds.

    ``perturb`` > 0 gives the perturbed twins of the runs (:mod:`thesis.ch6.twins`):
    the same inputs, the initial body positions perturbed at that relative size by the
    seed's stream ``"ch6/perturb"`` (the same perturbation for every condition of a seed).

    Returns (runs, labels, schedules, tables, n_steps) where ``tables`` maps a gait to its
    (n_steps, 12) teacher command table.
    """
    dt = controller_dt(cfg)
    scheds = [schedule_of(c, cfg["protocol"]) for c in conditions]
    n = max(PR.n_steps(s.total, dt) for s in scheds)
    h_max = max(c.width for c in conditions)
    slots = max(c.buffer for c in conditions) + 1
    tables = {g: TE.command_table(fam, p, n, dt, cfg["protocol"]["settle"])
              for g, (fam, p, _) in teachers.items()
              if any(c.gait == g for c in conditions)}
    hidden = {s: C.draw_hidden(seeding.rng(root_seed, "ch6/hidden", s), h_max) for s in seeds}
    runs, labels = [], []
    for c, sch in zip(conditions, scheds):
        sig = PR.signals(sch, dt, n, open_loop=open_loop)
        for s in seeds:
            wh, wb = hidden[s]
            runs.append(dict(
                teacher=tables[c.gait], **sig, w_hidden=wh, w_bias=wb,
                hidden_mask=(np.arange(h_max) < c.width).astype(np.float32),
                slot_mask=(np.arange(slots) < c.buffer + 1).astype(np.float32),
                identity=c.linear, noise_std=float(cfg["control"]["input_noise"]),
                noise_seed=seeding.int_seed(root_seed, "ch6/noise", s),
                perturb=float(perturb), perturb_seed=seeding.int_seed(root_seed, "ch6/perturb",
                                                                      s),
                **sensing(cfg), sensing_seed=seeding.int_seed(root_seed, "ch6/sensing", s)))
            labels.append((c.name if perturb == 0 else f"{c.name} (perturbed twin)", s))
    return runs, labels, scheds, tables, n


def commands_sent(rec, runs, i):
    """(T, 12) motor commands of run ``i``: teacher's share of the teacher, the rest the
    controller's a priori output."""
    share = np.asarray(runs[i]["share"])[:, None]
    return share * runs[i]["teacher"] + (1.0 - share) * rec["y_hat"][i]


def sensing(cfg: dict) -> dict:
    """Per-run sensing inputs of :func:`thesis.ch6.loop.pack_runs` from
    ``ch6.control``: the period's relative jitter and the encoders' read noise and
    resolution [rad] (the noise is given in counts of ``encoder_counts`` per revolution)."""
    c = cfg["control"]
    step = 2.0 * np.pi / float(c["encoder_counts"]) if c["encoder_counts"] else 0.0
    return dict(jitter=float(c["jitter"]), encoder_noise=float(c["encoder_noise"]) * step,
                encoder_resolution=step)


def perturbation(cfg: dict) -> float:
    """Relative size of the twins' initial-state perturbation (``ch6.perturbation``; 0:
    no twins)."""
    return float(cfg["perturbation"]["relative"])


def run(ctx, conditions: list[Condition], *, thesis_ref: str,
        joint_space: bool = False) -> xr.Dataset:
    """Train and test every condition for every seed; the dataset of outcomes and metrics.

    With ``ch6.perturbation.relative`` > 0 every run also runs as its perturbed twin in
    the same batch, and the dataset carries the twins' values, the flips and the
    regression policy of :func:`thesis.ch6.twins.attach`.

    Args:
        ctx: run context (``ch6`` config, ``teacher`` input).
        conditions: the sweep's conditions (names unique).
        thesis_ref: the thesis figure or section the dataset reproduces.
        joint_space: also store the right hind leg's hip and knee encoders in the first
            ``record.joint_space_seconds`` of the first training stage and the last ones
            of the running stage (Fig. 6.4 / 6.5).
    """
    cfg, seeds = ctx.config, list(ctx.config["seeds"])
    teachers = teachers_from(xr.load_dataset(ctx.input("teacher")))
    model, state = model_of(cfg)
    dt = controller_dt(cfg)
    runs, labels, scheds, tables, n = build_runs(conditions, seeds, teachers, cfg,
                                                 ctx.root_seed)
    rel = perturbation(cfg)
    k = len(runs)
    if rel > 0:
        twin_runs, twin_labels, *_ = build_runs(conditions, seeds, teachers, cfg,
                                                ctx.root_seed, perturb=rel)
        runs, labels = runs + twin_runs, labels + twin_labels
    rec, timing = loop.simulate(model, state, runs, int(cfg["control"]["substeps"]),
                                experiment=ctx.key, labels=labels)
    ctx.log.info("ch6 %s: %d runs x %d steps, compile %.1f s, rollout %.1f s", ctx.key,
                 len(runs), n, timing["compile_seconds"], timing["rollout_seconds"])
    ds = evaluate({key: v[:k] for key, v in rec.items()}, runs[:k], conditions, seeds,
                  scheds, teachers, cfg, timing, thesis_ref=thesis_ref,
                  joint_space=joint_space)
    if rel <= 0:
        return ds
    twin = evaluate({key: v[k:] for key, v in rec.items()}, runs[k:], conditions, seeds,
                    scheds, teachers, cfg, timing, thesis_ref=thesis_ref,
                    joint_space=joint_space)
    out = twins.attach(ds, twin, rel)
    for name in ("robot_seconds", "robot_seconds_per_wall_second"):  # twins simulated too
        out[name] = out[name].copy(data=out[name].values * len(runs) / k)
    return out


def evaluate(rec, runs, conditions, seeds, scheds, teachers, cfg, timing, *, thesis_ref: str,
             joint_space: bool = False) -> xr.Dataset:
    """The sweep's dataset from the recordings of :func:`thesis.ch6.loop.simulate`."""
    dt = controller_dt(cfg)
    crit, record = cfg["criteria"], cfg["record"]
    hk = list(loop.HIP_KNEE)
    nc, ns = len(conditions), len(seeds)
    metrics = {k: np.full((nc, ns), np.nan) for k in METRICS}
    outcome = np.empty((nc, ns), dtype=object)
    train_mse = np.full((nc, ns), np.nan)
    end_mse = np.full((nc, ns), np.nan)
    stride = max(1, int(round(record["mse_interval"] / dt)))
    t_train = max(c.stage1 + c.stage2 for c in conditions)
    n_curve = PR.n_steps(t_train, dt * stride)
    curve = np.full((nc, ns, n_curve), np.nan)
    n_js = PR.n_steps(record["joint_space_seconds"], dt)
    n_per = max((w.stop - w.start) // int(round(1.0 / teachers[c.gait][2] / dt))
                for c, sch in zip(conditions, scheds) for w in [PR.window(sch, "running", dt)])
    amp_curve = np.full((nc, ns, n_per), np.nan)
    multiplier = np.full((nc, ns), np.nan)
    js_teacher = np.full((nc, ns, n_js, 2), np.nan)
    js_learned = np.full((nc, ns, n_js, 2), np.nan)
    rh = [loop.ENCODERS.index("RH_hip"), loop.ENCODERS.index("RH_knee")]
    i = 0
    for ci, (c, sch) in enumerate(zip(conditions, scheds)):
        period = 1.0 / teachers[c.gait][2]
        for si in range(ns):
            cmd = commands_sent(rec, runs, i)
            m = K.evaluate(cmd[:, hk], runs[i]["teacher"][:, hk], rec["trunk_pos"][i],
                           rec["trunk_up"][i], sch, dt, period, crit)
            for k in METRICS:
                metrics[k][ci, si] = m[k]
            outcome[ci, si] = m["outcome"]
            run_w = PR.window(sch, "running", dt)
            amps = K.amplitude_by_period(cmd[run_w][:, hk], runs[i]["teacher"][run_w][:, hk],
                                         int(round(period / dt)))
            amp_curve[ci, si, :len(amps)] = amps
            multiplier[ci, si] = K.cycle_multiplier(amps)
            err = ((runs[i]["teacher"] - rec["y_hat"][i]) ** 2).mean(axis=1)  # a priori
            tr = PR.window(sch, "stage1", dt, skip=0.0)
            half = PR.window(sch, "stage1", dt, last=0.5 * c.stage1)
            train_mse[ci, si] = err[half].mean()
            b = sch.bounds()
            t0, t1 = PR.n_steps(b["stage1"][0], dt), PR.n_steps(b["stage2"][1], dt)
            end_mse[ci, si] = err[max(t0, t1 - int(round(period / dt))):t1].mean()
            smooth = _moving_average(err[t0:t1], int(round(period / dt)))[::stride]
            curve[ci, si, :len(smooth)] = smooth[:n_curve]
            if joint_space:
                enc = rec["encoders"][i][:, rh]
                a = tr.start
                seg = enc[a:min(a + n_js, tr.stop)]
                js_teacher[ci, si, :len(seg)] = seg
                run_w = PR.window(sch, "running", dt, last=record["joint_space_seconds"])
                seg = enc[run_w][-n_js:]
                js_learned[ci, si, :len(seg)] = seg
            i += 1
    dims = ("config", "seed")
    data = {k: (dims, v, dict(units=u, long_name=ln)) for k, (u, ln) in METRICS.items()
            for v in [metrics[k]]}
    data.update(
        outcome=(dims, outcome.astype(str), dict(
            units="1", long_name="outcome of the run: " + ", ".join(K.OUTCOMES))),
        train_mse=(dims, train_mse, dict(
            units="rad2", long_name="mean a priori MSE of the 12 outputs over the second "
                                    "half of the first training stage (teacher driving)")),
        end_mse=(dims, end_mse, dict(
            units="rad2", long_name="mean a priori MSE over the last gait period of "
                                    "training")),
        running_amplitude=(("config", "seed", "running_period"), amp_curve, dict(
            units="1", long_name="amplitude ratio (mean std(output) / std(teacher) over hip "
                                 "and knee) in each teacher period of the running stage")),
        cycle_multiplier=(dims, multiplier, dict(
            units="1", long_name="per-period growth factor of the running stage's amplitude "
                                 "(exp of the slope of its log): < 1 the oscillation decays "
                                 "towards a fixed point, ~1 it is sustained")),
        mse_curve=(("config", "seed", "train_time"), curve, dict(
            units="rad2", long_name="a priori MSE of the 12 outputs during training, "
                                    "moving average over one gait period (Fig. 6.6)")),
        role=(("config",), np.array([c.role for c in conditions]), dict(
            units="1", long_name="role of the configuration in its experiment")),
        hidden=(("config",), np.array([0 if c.linear else c.hidden for c in conditions]),
                dict(units="1", long_name="H, hidden tanh units (0: linear feedback)")),
        buffer=(("config",), np.array([c.buffer for c in conditions]),
                dict(units="1", long_name="B, delay-buffer length in controller steps")),
        n_signals=(("config",), np.array([c.n_signals for c in conditions]),
                   dict(units="1", long_name="N = (B + 1) H + 1 signals fed to RLS")),
        stage1_seconds=(("config",), np.array([c.stage1 for c in conditions]),
                        dict(units="s", long_name="first training stage length")),
        stage2_seconds=(("config",), np.array([c.stage2 for c in conditions]),
                        dict(units="s", long_name="second training stage length")),
        off_seconds=(("config",), np.array([c.off for c in conditions]),
                     dict(units="s", long_name="motors-off duration of the power-off test")),
        gait_period=(("config",), np.array([1.0 / teachers[c.gait][2] for c in conditions]),
                     dict(units="s", long_name="the teacher's gait period")),
    )
    robot_s = float(len(runs) * np.asarray(runs[0]["share"]).shape[0] * dt)  # all simulated
    wall = dict(units="s", measurement="wall_clock")
    data.update(
        robot_seconds=((), robot_s, dict(
            units="s", long_name="simulated robot time (every run for the longest schedule)")),
        compile_wall_seconds=((), timing["compile_seconds"], dict(
            wall, long_name="wall time to compile the batched closed loop")),
        rollout_wall_seconds=((), timing["rollout_seconds"], dict(
            wall, long_name="wall time of the batched closed-loop rollout")),
        robot_seconds_per_wall_second=((), robot_s / timing["rollout_seconds"], dict(
            units="1", measurement="wall_clock",
            long_name="simulated robot-seconds per wall-second of the rollout "
                      "(controller, RLS and physics; compilation excluded)")),
    )
    coords = dict(config=[c.name for c in conditions], seed=seeds,
                  train_time=np.arange(n_curve) * stride * dt)
    if joint_space:
        jdims = ("config", "seed", "sample", "joint")
        data.update(
            rh_teacher=(jdims, js_teacher, dict(
                units="rad", long_name="right hind hip and knee encoders, first seconds of "
                                       "the first training stage (teacher driving)")),
            rh_learned=(jdims, js_learned, dict(
                units="rad", long_name="right hind hip and knee encoders, last seconds of "
                                       "the running stage (learned controller)")))
        coords.update(sample=np.arange(n_js), joint=["hip", "knee"])
    ds = xr.Dataset(data, coords=coords)
    ds["train_time"].attrs.update(units="s", long_name="time since the first training stage")
    for gait, (fam, p, f) in teachers.items():
        ds.attrs[f"teacher_{gait}_params"] = p.tolist()
        ds.attrs[f"teacher_{gait}_family"] = type(fam).__name__
    ds.attrs.update(thesis_ref=thesis_ref, seeds=seeds, controller_dt=dt,
                    **{f"criteria_{k}": v for k, v in crit.items()},
                    **{f"protocol_{k}": v for k, v in cfg["protocol"].items()})
    return ds
