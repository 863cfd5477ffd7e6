"""Simulation experiments of chapter 4 (registered in :mod:`thesis.registry`): the
flat-ground PSO and the transfer runs of §4.6.

``flat`` optimises the spline trot (Tab. 4.1) on flat ground from a random swarm, per
seed. ``transfer_slopes``, ``transfer_compliant`` and ``transfer_pebbly`` (input ``flat``)
optimise it again under each target condition of :mod:`thesis.gaits.conditions`, twice
per seed: with transfer (``transfer`` = 1: the flat run's best particles over all
generations with a small random impulse, §4.4, :func:`thesis.optim.transfer.transfer_init`)
and without (``transfer`` = 0: a fresh random swarm). Every evaluated particle is kept with its
speed, score and whether it fell; each run's best particles are re-evaluated.

Protocol of one evaluation (§4.5-4.6; sizes from the ``ch4`` config section): the robot
starts standing, eases into the pose of the particle evaluated before it in treadmill
order (the previous particle of the same swarm; the first particle of a run enters from
its own gait), runs that gait into the smooth §3.2.5 transition to the particle under
test, and is measured over the window. Fitness = the trunk's mean forward speed over the
window (§4.6, :func:`thesis.gaits.runner.speed_terms`). On the treadmill an assistant
stopped unstable gaits; here a robot that falls scores :data:`FALLEN_SCORE` plus the
fraction of the window it stayed up, below every robot that stays up (no upright robot
of this size reaches 1 m/s backwards), so PSO and the rank tests of §4.6 see falls as
the worst gaits, later falls better than earlier ones.

Falls are charged to the gait that fell (departure ``ch4.fall_reset``): the thesis tests
a gait over its window only, so a robot that is down when the window begins, having
entered from another gait (it fell while easing into, or walking, the previous particle's
gait, or in the transition), is set back on its feet at its start pose, as the assistant
did, eases into the gait under test again (``settle`` seconds) and is measured over the
rest of the window (:func:`window_starts`). Each evaluation records ``reset``; a robot
that falls again, in the gait under test, counts as fallen. An evaluation that entered
from its own gait (a run's first particle, the re-evaluations) is never reset: what it
walked before its window was the gait under test.

All robots of a generation, every seed and arm, run as batched simulations of a fixed
size (``seeds x particles``; smaller batches are padded and the padding discarded), so
one compiled rollout serves the whole chapter (:func:`evaluate_particles`). A robot whose
simulation is not finite, in a generation or a re-evaluation, stops the experiment with
:class:`thesis.errors.SimulationDiverged` naming its run, condition, arm, seed and
generation; nothing is written.
"""

from __future__ import annotations

import time
from collections.abc import Hashable, Sequence

import numpy as np
import xarray as xr

from thesis import seeding, store
from thesis.errors import SimulationDiverged
from thesis.gaits import conditions as C
from thesis.gaits import runner as R
from thesis.gaits import trajectories as T
from thesis.optim import pso, transfer

#: The gait family of chapter 4 (Tab. 4.1): 12 Bézier-spline parameters.
FAMILY = T.SplineGait()
#: Thesis names (Tab. 4.1-4.4 columns) of the family's parameters, in family order.
PARAMETERS = ("f", "a", "x0", "y0f", "y0r", "t_stance", "l0f", "l1f", "l0r", "l1r", "l2", "l3")
#: Score of a robot that fell at the start of its window [m/s]; one that fell later
#: scores this plus the fraction of the window it stayed up, so every fall ranks below
#: every robot that stays up.
FALLEN_SCORE = -2.0


def load_input(ctx, name: str) -> xr.Dataset:
    """The experiment's input ``name`` as a dataset; an unreadable file is named."""
    path = ctx.input(name)
    try:
        return xr.load_dataset(path, engine="h5netcdf")
    except (OSError, ValueError) as err:
        raise ValueError(f"cannot read input {name} ({path}): {err}") from err


def protocol_times(cfg) -> tuple[float, float, float]:
    """(window start, window end, simulated duration) [s] of one evaluation."""
    pr = cfg["protocol"]
    t0 = float(pr["settle"]) + float(pr["transition_seconds"])
    t1 = t0 + float(pr["run_seconds"])
    return t0, t1, t1


def window_starts(cfg, reset) -> np.ndarray:
    """(B,) start of each evaluation's window [s]: :func:`protocol_times`'s, or for a robot
    set back on its feet there (``reset`` (B,) bool) ``settle`` seconds later, once it has
    eased into the gait under test again (its window is that much shorter; at least one
    command period, so that its first pose is one after the reset)."""
    t0 = protocol_times(cfg)[0]
    ease = max(float(cfg["protocol"]["settle"]), R.COMMAND_PERIOD)
    return np.where(np.asarray(reset, bool), t0 + ease, t0)


def score_of(terms) -> np.ndarray:
    """(B,) §4.6 score: the window speed [m/s], or FALLEN_SCORE + upright fraction."""
    return np.where(terms["fallen"], FALLEN_SCORE + terms["upright"], terms["speed"])


class Timing:
    """Simulated robot-seconds, wall and CPU seconds of the batched rollouts of a run;
    the first call of each compiled shape (which includes compilation) is kept apart."""

    def __init__(self):
        self.robot_seconds = 0.0  # simulated, real robots only (no padding)
        self.wall = 0.0
        self.cpu = 0.0
        self.steady_robot_seconds = 0.0  # calls after the first: no compilation
        self.steady_wall = 0.0
        self.steady_cpu = 0.0
        self.calls = 0

    def add(self, robot_seconds: float, wall: float, cpu: float) -> None:
        self.robot_seconds += robot_seconds
        self.wall += wall
        self.cpu += cpu
        if self.calls > 0:
            self.steady_robot_seconds += robot_seconds
            self.steady_wall += wall
            self.steady_cpu += cpu
        self.calls += 1

    def variables(self) -> dict:
        """Dataset variables; wall-clock ones carry ``measurement="wall_clock"``."""
        clock = dict(store.WALL_CLOCK)
        rate = self.steady_robot_seconds / self.steady_wall if self.steady_wall > 0 else np.nan
        cpu_rate = self.steady_robot_seconds / self.steady_cpu if self.steady_cpu > 0 else np.nan
        return {
            "simulated_robot_seconds": ((), self.robot_seconds, dict(
                units="s", long_name="simulated robot time of every evaluation of this "
                                     "experiment (padding robots excluded)")),
            "rollout_wall_seconds": ((), self.wall, dict(
                units="s", long_name="wall time of the batched rollouts, with compilation",
                **clock)),
            "rollout_cpu_seconds": ((), self.cpu, dict(
                units="s", long_name="CPU time (all threads) of the batched rollouts, with "
                                     "compilation", **clock)),
            "robot_seconds_per_wall_second": ((), rate, dict(
                units="1", long_name="simulated robot-seconds per wall-second of the batched "
                                     "rollouts after each shape's first (compiling) call",
                **clock)),
            "robot_seconds_per_cpu_second": ((), cpu_rate, dict(
                units="1", long_name="simulated robot-seconds per CPU-second (all threads) of "
                                     "the same rollouts; about half the rate a quiet "
                                     "2-core machine reaches per wall-second", **clock)),
        }


def evaluate_particles(model, state, cfg, p_from, p_to, *, unit: int, timing: Timing,
                       heading=None, forward=None) -> dict:
    """Simulate one evaluation (:func:`protocol_times`) of each particle.

    Args:
        model, state: the Oncilla under the condition (:mod:`thesis.gaits.conditions`).
        cfg: the ``ch4`` config section.
        p_from, p_to: (n, 12) the particle evaluated before (treadmill order) and the
            particle under test, in the family's units.
        unit: robots per batched simulation; the particles run in batches of ``unit``,
            the last one padded with copies of its first robot.
        timing: accumulates the simulated and measured time.
        heading: optional (n,) initial headings [rad].
        forward: optional (n,) initial positions along x [m] (where on a strip of pebbles
            the evaluation starts).

    Returns:
        dict of (n,) arrays: :func:`thesis.gaits.runner.speed_terms`,
        :func:`thesis.gaits.conditions.thread_load` (both over each robot's window,
        :func:`window_starts`), ``reset`` (bool: set back on its feet at the window's
        start, see the module docstring) and ``score``.
    """
    p_from = np.asarray(p_from, np.float64)
    p_to = np.asarray(p_to, np.float64)
    n = len(p_to)
    settle = float(cfg["protocol"]["settle"])
    t_tr = float(cfg["protocol"]["transition_seconds"])
    fall_height = float(cfg["protocol"]["fall_height"])
    t0, t1, dur = protocol_times(cfg)
    if t1 - t0 <= max(settle, R.COMMAND_PERIOD):
        raise ValueError(f"ch4.protocol.run_seconds ({t1 - t0} s) must exceed settle "
                         f"({settle} s): a robot set back on its feet eases in for that long")
    entered = np.any(p_from != p_to, axis=1)  # from another gait: the assistant may reset
    fn = R.gait_command_fn(FAMILY, settle, t_tr)
    parts = []
    for start in range(0, n, unit):
        idx = np.arange(start, min(start + unit, n))
        pad = np.concatenate([idx, np.full(unit - len(idx), idx[0])])
        mem = dict(p_from=p_from[pad].astype(np.float32), p_to=p_to[pad].astype(np.float32))
        h = None if heading is None else np.asarray(heading, np.float64)[pad]
        fw = None if forward is None else np.asarray(forward, np.float64)[pad]
        c0 = time.process_time()
        sim = R.simulate(model, state, fn, mem, dur, heading=h, chunk=None, forward=fw,
                         reset_at=t0, fall_height=fall_height, may_reset=entered[pad])
        timing.add(len(idx) * dur, sim["wall"], time.process_time() - c0)
        ts = window_starts(cfg, sim["reset"])
        terms = R.speed_terms(model, sim, ts, fall_height, t1)
        terms.update(C.thread_load(model, sim, ts, t1), reset=sim["reset"])
        parts.append({k: v[:len(idx)] for k, v in terms.items()})
    out = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    out["score"] = score_of(out)
    return out


class GenerationRecorder:
    """Evaluates the generations of several lock-step swarms (the ``evaluate`` of
    :func:`thesis.optim.transfer.run_lockstep`) and keeps every particle's terms.

    Each swarm's particles are evaluated in treadmill order: a particle enters from the
    one before it, the first of a generation from the last of the previous generation and
    the first of the run from its own gait. ``starts`` (optional) gives each generation's
    evaluations their start positions along x (a pebble strip, :func:`start_sampler`).
    """

    FIELDS = ("speed", "score", "fallen", "upright", "exploded", "taut", "thread_force",
              "reset")

    def __init__(self, model, state, cfg, keys: Sequence[Hashable], *, unit: int,
                 timing: Timing, label, starts=None):
        self.model, self.state, self.cfg = model, state, cfg
        self.starts = starts  # optional (gen, n) -> (n,) start positions along x [m]
        self.keys = list(keys)
        self.unit = unit
        self.timing = timing
        self.label = label  # key -> (experiment label, seed) for error messages
        self.prev: dict = {}
        self.records = {k: {f: [] for f in self.FIELDS} for k in self.keys}

    def __call__(self, gen: int, xs: dict) -> dict:
        p_from, p_to, owner = [], [], []
        for k in self.keys:
            x = np.asarray(xs[k], np.float64)
            first = x[:1] if k not in self.prev else self.prev[k][None]
            p_from.append(np.concatenate([first, x[:-1]]))
            p_to.append(x)
            owner += [k] * len(x)
        p_to = np.concatenate(p_to)
        forward = None if self.starts is None else self.starts(gen, len(p_to))
        terms = evaluate_particles(self.model, self.state, self.cfg, np.concatenate(p_from),
                                   p_to, unit=self.unit, timing=self.timing, forward=forward)
        owner = np.array([self.keys.index(k) for k in owner])
        scores = {}
        for i, k in enumerate(self.keys):
            sel = owner == i
            if not terms["finite"][sel].all():
                what, seed = self.label(k)
                bad = int(np.flatnonzero(~terms["finite"][sel])[0])
                raise SimulationDiverged(what, seed, gen,
                                         f"pose of particle {bad} in generation {gen}")
            for f in self.FIELDS:
                self.records[k][f].append(np.asarray(terms[f][sel], np.float64))
            self.prev[k] = np.asarray(xs[k], np.float64)[-1]
            scores[k] = terms["score"][sel]
        return scores

    def stacked(self, key, field: str) -> np.ndarray:
        """(G, n) values of ``field`` for swarm ``key``."""
        return np.stack(self.records[key][field])


def start_sampler(cfg, root_seed: int, name: str, duration: float):
    """``(gen, n) -> (n,)`` start positions along x [m] of the evaluations of condition
    ``name``, uniform over :func:`thesis.gaits.conditions.start_range` from the stream
    ``ch4/<name>/start`` (one draw per generation, in order), or None where the floor is
    the same everywhere. Every evaluation thus meets its own stretch of pebbles, as each
    particle met another arrangement on the treadmill (§4.6.3)."""
    rng_range = C.start_range(cfg, name, duration)
    if rng_range is None:
        return None
    lo, hi = rng_range

    def starts(gen: int, n: int) -> np.ndarray:
        return seeding.rng(root_seed, f"ch4/{name}/start", int(gen)).uniform(lo, hi, n)
    return starts


def swarm_options(cfg) -> dict:
    """PSO coefficients of the ``ch4`` config section (§4.3)."""
    c = cfg["pso"]
    return dict(omega=float(c["omega"]), phi_p=float(c["phi_p"]), phi_g=float(c["phi_g"]))


def best_indices(score: np.ndarray, first_generation: int = 0) -> tuple[int, int]:
    """(generation, particle) of the best score at or after ``first_generation``."""
    s = np.where(np.isnan(score), -np.inf, score).copy()
    s[:first_generation] = -np.inf
    g, i = np.unravel_index(int(np.argmax(s)), s.shape)
    return int(g), int(i)


def reeval_headings(cfg, root_seed: int, name: str, seed: int, m: int) -> np.ndarray:
    """(m, repeats) initial headings [rad] of the re-evaluations of ``m`` particles of one
    seed: U(-h, h), h = ``reeval.heading_deg``, from the stream ``name`` of that seed."""
    rc = cfg["reeval"]
    rng = seeding.rng(root_seed, name, seed)
    return np.deg2rad(float(rc["heading_deg"])) * rng.uniform(-1.0, 1.0,
                                                             (m, int(rc["repeats"])))


#: What :func:`reevaluate` keeps of each re-evaluation.
REEVAL_FIELDS = ("speed", "score", "fallen", "taut", "thread_force")


def reevaluate(model, state, cfg, particles, headings, *, unit: int, timing: Timing,
               label, step: int, forward=None) -> dict:
    """Re-evaluate particles from standstill, ``reeval.repeats`` times each.

    Each repeat starts standing in the particle's own pose (``p_from`` = ``p_to``) with
    its own initial heading.

    Args:
        particles: (m, 12) parameter vectors.
        headings: (m, repeats) initial headings [rad] (:func:`reeval_headings`).
        label: ``row -> (experiment, seed)`` naming the run of particle ``row`` (m rows).
        step: the optimisation step the re-evaluation follows (its generation count).
        forward: optional (m, repeats) start positions along x [m] (a pebble strip).

    Returns:
        dict of (m, repeats) ``speed``, ``score``, ``fallen``, ``taut``,
        ``thread_force``.

    Raises:
        SimulationDiverged: a repeat's recorded pose was not finite (no result is written).
    """
    headings = np.asarray(headings, np.float64)
    reps = headings.shape[1]
    p = np.repeat(np.asarray(particles, np.float64), reps, axis=0)
    fw = None if forward is None else np.asarray(forward, np.float64).reshape(-1)
    terms = evaluate_particles(model, state, cfg, p, p, unit=unit, timing=timing,
                               heading=headings.reshape(-1), forward=fw)
    if not terms["finite"].all():
        bad = int(np.flatnonzero(~terms["finite"])[0])
        what, seed = label(bad // reps)
        raise SimulationDiverged(what, seed, step, f"a recorded pose of the re-evaluation of "
                                                   f"particle {bad // reps}, repeat {bad % reps}")
    return {k: np.asarray(terms[k], np.float64).reshape(-1, reps) for k in REEVAL_FIELDS}


def _param_coords() -> dict:
    return dict(parameter=list(PARAMETERS))


def _common_vars(ds: xr.Dataset) -> None:
    ds["parameter_unit"] = ("parameter", list(FAMILY.units),
                            dict(units="1", long_name="unit of the parameter"))
    ds["lower"] = ("parameter", FAMILY.lower, dict(
        units="mixed (see parameter_unit)", long_name="lower bound of the search box"))
    ds["upper"] = ("parameter", FAMILY.upper, dict(
        units="mixed (see parameter_unit)",
        long_name="upper bound of the search box (a <= a_max(x0) and the y0 range are "
                  "enforced by the family's projection)"))


def _size_attrs(cfg) -> dict:
    pr, ps = cfg["protocol"], cfg["pso"]
    return dict(particles=int(ps["particles"]), generations=int(ps["generations"]),
                run_seconds=float(pr["run_seconds"]),
                transition_seconds=float(pr["transition_seconds"]),
                settle_seconds=float(pr["settle"]), omega=float(ps["omega"]),
                phi_p=float(ps["phi_p"]), phi_g=float(ps["phi_g"]),
                fallen_score=FALLEN_SCORE, reeval_repeats=int(cfg["reeval"]["repeats"]),
                reeval_heading_deg=float(cfg["reeval"]["heading_deg"]))


_UNITS_MIXED = "mixed (see parameter_unit)"
_SCORE_LONG = ("§4.6 score: window speed, or for a fallen robot -2 + the fraction of the "
               "window it stayed up")


def _particle_vars(dims, pos, fields) -> dict:
    """Every evaluated particle of a run: position (dims + parameter) and its outcome (dims)."""
    return dict(
        position=(dims + ("parameter",), pos, dict(
            units=_UNITS_MIXED, long_name="evaluated particle (spline parameters)")),
        speed=(dims, fields["speed"], dict(
            units="m s-1", long_name="mean forward speed of the trunk over the window")),
        score=(dims, fields["score"], dict(units="m s-1", long_name=_SCORE_LONG)),
        fallen=(dims, fields["fallen"], dict(units="1", long_name="1 if the robot fell")),
        upright=(dims, fields["upright"], dict(
            units="1", long_name="fraction of the window before the first fall")),
        exploded=(dims, fields["exploded"], dict(
            units="1", long_name="1 if the simulation went unphysical (counted fallen)")),
        **_reset_vars(dims, fields["reset"]),
        **_thread_vars(dims, fields))


def _reset_vars(dims, reset) -> dict:
    """The assistant's resets (departure ch4.fall_reset): per evaluation (dims end with
    'particle') and their number per generation (dims without 'particle')."""
    reset = np.asarray(reset, float)
    return dict(
        reset=(dims, reset, dict(
            units="1", long_name="1 if the robot was down when its window began, having "
                                 "entered from another gait, and was set back on its feet "
                                 "at its start pose (not counted as a fall)")),
        reset_count=(dims[:-1], reset.sum(axis=-1), dict(
            units="1", long_name="evaluations of the generation whose robot was set back "
                                 "on its feet at the start of its window")))


def _thread_vars(dims, fields) -> dict:
    """The safety threads' load over the window (:func:`thesis.gaits.conditions.thread_load`)."""
    return dict(
        taut=(dims, fields["taut"], dict(
            units="1", long_name="fraction of the window with a safety thread taut")),
        thread_force=(dims, fields["thread_force"], dict(
            units="N", long_name="window mean of the safety threads' tension (estimated "
                                 "from the 10-ms poses)")))


def _reeval_vars(dims, re) -> dict:
    """The best particles re-evaluated from standstill (dims end with 'repeat')."""
    what = "of the best particle re-evaluated from standstill"
    return dict(
        reeval_speed=(dims, re["speed"], dict(units="m s-1", long_name=f"speed {what}")),
        reeval_score=(dims, re["score"], dict(units="m s-1", long_name=f"score {what}")),
        reeval_fallen=(dims, np.asarray(re["fallen"], float), dict(
            units="1", long_name="1 if the re-evaluated best particle fell")),
        **{f"reeval_{k}": v for k, v in _thread_vars(dims, re).items()})


def flat(ctx) -> xr.Dataset:
    """Flat-ground PSO from a random swarm, per seed (§4.6.1: "We start by optimizing a
    gait on a flat terrain using PSO"): every particle, and the best one re-evaluated."""
    cfg = ctx.config
    seeds = [int(s) for s in cfg["seeds"]]
    P, G = int(cfg["pso"]["particles"]), int(cfg["pso"]["generations"])
    model, state = C.condition_model(cfg, "flat")
    timing = Timing()
    unit = len(seeds) * P
    swarms = {s: pso.pso_init(seeding.rng(ctx.root_seed, "ch4/flat", s), P, FAMILY.lower,
                              FAMILY.upper, project=FAMILY.project, **swarm_options(cfg))
              for s in seeds}
    rec = GenerationRecorder(model, state, cfg, seeds, unit=unit, timing=timing,
                             label=lambda s: ("ch4/flat:flat", s))
    hist = transfer.run_lockstep(swarms, _logged(rec, ctx, "flat"), G, project=FAMILY.project)
    pos = np.stack([hist[s].positions for s in seeds])  # (S, G, P, d)
    fields = {f: np.stack([rec.stacked(s, f) for s in seeds]) for f in rec.FIELDS}
    best = [best_indices(fields["score"][i]) for i in range(len(seeds))]
    best_pos = np.stack([pos[i, g, k] for i, (g, k) in enumerate(best)])
    heads = np.concatenate([reeval_headings(cfg, ctx.root_seed, "ch4/flat/reeval", s, 1)
                            for s in seeds])
    re = reevaluate(model, state, cfg, best_pos, heads, unit=unit, timing=timing, step=G,
                    label=lambda row: ("ch4/flat:flat/reeval", seeds[row]))
    dims = ("seed", "generation", "particle")
    ds = xr.Dataset(
        dict(**_particle_vars(dims, pos, fields),
             best_generation=(("seed",), np.array([g for g, _ in best], float), dict(
                 units="1", long_name="generation of the best particle over all generations")),
             best_particle=(("seed",), np.array([k for _, k in best], float), dict(
                 units="1", long_name="index of the best particle in its generation")),
             **_reeval_vars(("seed", "repeat"), re)),
        coords=dict(seed=seeds, generation=np.arange(G), particle=np.arange(P),
                    repeat=np.arange(int(cfg["reeval"]["repeats"])), **_param_coords()))
    _common_vars(ds)
    for k, v in timing.variables().items():
        ds[k] = v
    ds.attrs.update(thesis_ref="§4.6.1 (flat source run)", seeds=seeds, condition="flat",
                    **_size_attrs(cfg))
    return ds


def _logged(rec: GenerationRecorder, ctx, what: str):
    def evaluate(gen, xs):
        scores = rec(gen, xs)
        ctx.log.info("ch4 %s generation %d: best score %.3f, fallen %.0f %%, set back %d",
                     what, gen, max(float(np.max(v)) for v in scores.values()),
                     100 * np.mean([rec.records[k]["fallen"][-1] for k in rec.keys]),
                     int(sum(rec.records[k]["reset"][-1].sum() for k in rec.keys)))
        return scores
    return evaluate


def transfer_conditions(ctx, names: Sequence[str]) -> xr.Dataset:
    """Both arms of every condition in ``names`` per seed (§4.6): with the flat run's
    best particles transferred (§4.4) and from a random swarm; every particle kept, each
    arm's best particle (``rank`` 1) and its best after the first generation (``rank``
    2, Tab. 4.4's "excluding the transferred particles") re-evaluated."""
    cfg = ctx.config
    seeds = [int(s) for s in cfg["seeds"]]
    P, G = int(cfg["pso"]["particles"]), int(cfg["pso"]["generations"])
    src = load_input(ctx, "flat")
    missing = [s for s in seeds if s not in src["seed"].values]
    if missing or src.sizes["particle"] < P:
        raise ValueError(f"input flat ({ctx.input('flat')}) lacks seeds {missing} or has "
                         f"fewer than {P} particles per generation; rerun ch4/flat")
    imp = transfer.impulse_scale(FAMILY.lower, FAMILY.upper,
                                 float(cfg["transfer"]["impulse_divisor"]))
    timing = Timing()
    unit = len(seeds) * P
    arms = (0, 1)
    shape = (len(seeds), len(names), len(arms))
    pos = np.zeros(shape + (G, P, len(PARAMETERS)))
    vel0 = np.zeros(shape + (P, len(PARAMETERS)))
    fields = {f: np.zeros(shape + (G, P)) for f in GenerationRecorder.FIELDS}
    best_pos = np.zeros(shape + (2, len(PARAMETERS)))
    best_gen = np.zeros(shape + (2,))
    best_k = np.zeros(shape + (2,))
    reps = int(cfg["reeval"]["repeats"])
    re = {k: np.zeros(shape + (2, reps)) for k in REEVAL_FIELDS}
    for ci, name in enumerate(names):
        model, state = C.condition_model(cfg, name, ctx.root_seed)
        starts = start_sampler(cfg, ctx.root_seed, name, protocol_times(cfg)[2])
        swarms = {}
        for s in seeds:
            sp, sf = src["position"].sel(seed=s).values, src["score"].sel(seed=s).values
            swarms[(s, 1)] = transfer.transfer_init(
                seeding.rng(ctx.root_seed, f"ch4/{name}/transfer", s), sp, sf, P,
                FAMILY.lower, FAMILY.upper, impulse=imp, project=FAMILY.project,
                **swarm_options(cfg))
            swarms[(s, 0)] = pso.pso_init(
                seeding.rng(ctx.root_seed, f"ch4/{name}/random", s), P, FAMILY.lower,
                FAMILY.upper, project=FAMILY.project, **swarm_options(cfg))
        keys = [(s, t) for t in (1, 0) for s in seeds]  # one batch per arm
        rec = GenerationRecorder(model, state, cfg, keys, unit=unit, timing=timing,
                                 label=lambda k, n=name: (f"{ctx.key}:{n}/transfer={k[1]}",
                                                          k[0]), starts=starts)
        for (s, t) in keys:
            vel0[seeds.index(s), ci, t] = swarms[(s, t)].v
        hist = transfer.run_lockstep(swarms, _logged(rec, ctx, name), G,
                                     project=FAMILY.project)
        todo, heads = [], []
        for (s, t) in keys:
            i = seeds.index(s)
            pos[i, ci, t] = hist[(s, t)].positions
            for f in rec.FIELDS:
                fields[f][i, ci, t] = rec.stacked((s, t), f)
            for r, first in enumerate((0, min(1, G - 1))):
                g, k = best_indices(fields["score"][i, ci, t], first)
                best_pos[i, ci, t, r] = pos[i, ci, t, g, k]
                best_gen[i, ci, t, r], best_k[i, ci, t, r] = g, k
                todo.append((i, t, r))
            heads.append(reeval_headings(cfg, ctx.root_seed, f"ch4/{name}/reeval/transfer={t}",
                                         s, 2))
        heads = np.concatenate(heads)
        fw = None if starts is None else starts(G, heads.size).reshape(heads.shape)
        out = reevaluate(model, state, cfg, np.stack([best_pos[i, ci, t, r] for i, t, r in todo]),
                         heads, unit=unit, timing=timing, forward=fw, step=G,
                         label=lambda row, n=name: (f"{ctx.key}:{n}/transfer={todo[row][1]}"
                                                    "/reeval", seeds[todo[row][0]]))
        for j, (i, t, r) in enumerate(todo):
            for k in re:
                re[k][i, ci, t, r] = out[k][j]
    dims = ("seed", "condition", "transfer", "generation", "particle")
    bdims = ("seed", "condition", "transfer", "rank")
    ds = xr.Dataset(
        dict(**_particle_vars(dims, pos, fields),
             velocity0=(("seed", "condition", "transfer", "particle", "parameter"), vel0, dict(
                 units=_UNITS_MIXED, long_name="initial PSO velocity (the transferred "
                                               "particles' random impulse, §4.4)")),
             best_position=(bdims + ("parameter",), best_pos, dict(
                 units=_UNITS_MIXED, long_name="best particle (rank 1: over all generations; "
                                               "rank 2: after the first generation)")),
             best_generation=(bdims, best_gen, dict(
                 units="1", long_name="generation of the best particle")),
             best_particle=(bdims, best_k, dict(
                 units="1", long_name="index of the best particle in its generation")),
             **_reeval_vars(bdims + ("repeat",), re)),
        coords=dict(seed=seeds, condition=list(names), transfer=list(arms),
                    generation=np.arange(G), particle=np.arange(P), rank=[1, 2],
                    repeat=np.arange(reps), **_param_coords()))
    ds["transfer"].attrs.update(units="1", long_name="1: transferred swarm; 0: random swarm")
    _common_vars(ds)
    ds["impulse"] = ("parameter", imp, dict(
        units=_UNITS_MIXED, long_name="scale of the transferred particles' random initial "
                                      "velocity r * impulse, r ~ U(-1, 1)"))
    for k, v in timing.variables().items():
        ds[k] = v
    ds.attrs.update(thesis_ref="§4.6", seeds=seeds,
                    impulse_divisor=float(cfg["transfer"]["impulse_divisor"]),
                    **_size_attrs(cfg))
    return ds


def transfer_slopes(ctx) -> xr.Dataset:
    """§4.6.1: transfer from flat ground to each slope of ``conditions.grades``."""
    return transfer_conditions(ctx, [C.grade_name(g) for g in ctx.config["conditions"]["grades"]])


def transfer_compliant(ctx) -> xr.Dataset:
    """§4.6.2: transfer from the normal robot to one with softer front legs."""
    return transfer_conditions(ctx, ["compliant"])


def transfer_pebbly(ctx) -> xr.Dataset:
    """§4.6.3: transfer from flat ground to a floor covered in ~1 cm pebbles (the sphere
    field of :func:`thesis.gaits.conditions.pebble_layout`; each evaluation starts at its
    own random place on the strip)."""
    ds = transfer_conditions(ctx, ["pebbly"])
    centres, r = C.pebble_layout(ctx.config, ctx.root_seed)
    pc = ctx.config["pebbles"]
    ds.attrs.update(pebble_count=int(len(centres)), pebble_diameter=2 * r,
                    pebble_coverage=float(pc["coverage"]),
                    pebble_strip_length=float(pc["strip_length"]),
                    pebble_strip_width=float(pc["strip_width"]), pebble_k=int(pc["k"]))
    return ds


def treadmill_predecessors(positions: np.ndarray) -> np.ndarray:
    """(G, P, d) -> (G, P, d): the particle each evaluation entered from, in treadmill
    order (the previous particle of the run; the run's first particle from itself)."""
    flat = positions.reshape(-1, positions.shape[-1])
    prev = np.concatenate([flat[:1], flat[:-1]])
    return prev.reshape(positions.shape)


def tether(ctx) -> xr.Dataset:
    """The safety thread's effect (§4.5): every evaluation of the flat run (which ran with
    the thread) simulated again without it, entered from the same previous particle; the
    fraction of fallen evaluations per generation with and without the thread, and how
    much the thread carried each evaluation (0 without it)."""
    cfg = ctx.config
    flat_ds = load_input(ctx, "flat")
    seeds = [int(s) for s in flat_ds["seed"].values]
    pos = flat_ds["position"].values  # (S, G, P, d)
    S, G, P, _ = pos.shape
    model, state = C.condition_model(cfg, "flat")
    if not model.tether_names:
        raise ValueError("ch4/tether needs the tethered Oncilla (config ch4.tether)")
    bare = C.untethered(model)
    timing = Timing()
    p_from = np.stack([treadmill_predecessors(pos[i]) for i in range(S)])
    terms = evaluate_particles(bare, state, cfg, p_from.reshape(-1, pos.shape[-1]),
                               pos.reshape(-1, pos.shape[-1]), unit=S * P, timing=timing)
    if not terms["finite"].all():
        bad = int(np.flatnonzero(~terms["finite"])[0])
        i, g = np.unravel_index(bad // P, (S, G))
        raise SimulationDiverged("ch4/tether:flat/no_tether", seeds[i], g,
                                 f"pose of particle {bad % P} in generation {g}")
    shape = (S, G, P)
    fallen = np.stack([terms["fallen"].reshape(shape).astype(float),
                       flat_ds["fallen"].values], axis=1)  # tether 0, 1
    speed = np.stack([terms["speed"].reshape(shape), flat_ds["speed"].values], axis=1)
    score = np.stack([terms["score"].reshape(shape), flat_ds["score"].values], axis=1)
    taut = np.stack([terms["taut"].reshape(shape), flat_ds["taut"].values], axis=1)
    force = np.stack([terms["thread_force"].reshape(shape), flat_ds["thread_force"].values],
                     axis=1)
    # a flat run written before the assistant's resets has none recorded: unknown, not 0
    flat_reset = flat_ds["reset"].values if "reset" in flat_ds else np.full(shape, np.nan)
    reset = np.stack([terms["reset"].reshape(shape).astype(float), flat_reset], axis=1)
    dims = ("seed", "tether", "generation", "particle")
    ds = xr.Dataset(
        dict(fallen=(dims, fallen, dict(units="1", long_name="1 if the robot fell")),
             speed=(dims, speed, dict(units="m s-1", long_name="mean forward speed over the "
                                                             "window")),
             score=(dims, score, dict(units="m s-1", long_name=_SCORE_LONG)),
             fall_fraction=(dims[:3], fallen.mean(axis=-1), dict(
                 units="1", long_name="fraction of fallen evaluations per generation")),
             **_reset_vars(dims, reset),
             **_thread_vars(dims, dict(taut=taut, thread_force=force))),
        coords=dict(seed=seeds, tether=[0, 1], generation=np.arange(G), particle=np.arange(P)))
    ds["tether"].attrs.update(units="1", long_name="1: with the safety thread (the flat run); "
                                                   "0: the same evaluations without it")
    for k, v in timing.variables().items():
        ds[k] = v
    t = cfg["tether"]
    ds.attrs.update(thesis_ref="§4.5 (safety thread)", seeds=seeds,
                    **{f"tether_{k}": float(v) for k, v in t.items()},
                    **{k: flat_ds.attrs[k] for k in ("particles", "generations", "run_seconds",
                                                     "transition_seconds") if k in flat_ds.attrs})
    return ds
