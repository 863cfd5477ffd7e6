"""Model-level checks of the simulated Oncilla: the measuring instrument
that decides model revisions, never a chapter's verdict.

Four measurements on the flat floor, untethered (the ch4 model of
:func:`thesis.gaits.conditions.base_model` with its thread never taut,
:func:`thesis.gaits.conditions.untethered`), all on one compiled rollout
(:func:`simulate_runs`):

* **Standing pose** (§3.2.1, §4.5): the robot holds its build pose (toes
  ``BUILD_DEPTH`` straight below the hips); settled trunk and centre-of-mass heights and
  the toes' positions in the hip frames, beside the kinematic nominal (:func:`standing`).
* **Fall rate of random Tab. 4.1 trots from standstill** (§4.2, §4.5-4.6, Tab. 4.1):
  spline trots drawn uniformly from Tab. 4.1's ranges, the dependent ones included
  (:func:`sample_gaits`), each run from standing through the ch4 evaluation protocol of
  a gait entered from itself (:func:`thesis.gaits.runner.gait_command_fn`: ``settle``
  seconds easing into the gait's pose, then the gait); fallen by the ch3/ch4 criterion
  (:func:`thesis.gaits.runner.speed_terms`: trunk below ``fall_height`` or tilted beyond
  60 degrees, or unphysical), binned against a, x0, f (:func:`fall_rate_bins`).
* **Lateral push recovery**: a sideways impulse on the trunk (+y, at its centre of
  mass) while standing and while trotting the nominal gait (:func:`nominal_gait`):
  fallen or recovered, against the impulse [N s]; with the largest deflection of the
  scapula (ab/adduction) servos from their commands after the push.
* **What the encoders carry** (§6.1-6.2: "the 8 rotary encoders on the hip and knee
  joints", "the rotary encoders in the motors"): the encoder readout of chapter 6
  (:func:`encoder_dofs`, :func:`encoder_offsets`; the hip servo's coordinate and the
  knee motor's side of the cable) minus the command the servo was given over the same
  10-ms period, regressed per joint on the four toes' contact forces (normal and both
  tangential components, :func:`toe_contact_forces`), on the joint's own command and
  command history, and on both (:func:`r_squared`); per gait, over the upright part of the
  run after a ``warmup``.

Every random draw comes from named streams of the profile's root seed
(:mod:`thesis.seeding`), independent of the model, so a revised model is measured on
the same gaits and pushes.
"""

from __future__ import annotations

import functools
import hashlib
import importlib
import inspect
import math

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, PartitionSpec as P

from thesis.gaits import leg as L
from thesis.gaits import runner as R
from thesis.gaits import trajectories as T
from thesis.physics import perturbation, step
from thesis.physics import sensors as all_sensors
from thesis.physics.models import leg_geometry as LG

O = importlib.import_module("thesis.physics.models.oncilla")

#: The gait family of Tab. 4.1 (chapter 4's spline trot).
FAMILY = T.SplineGait()
#: The 8 encoders of chapter 6 (hip and knee of LF, RF, LH, RH): the order of
#: ``thesis.ch6.loop.ENCODERS``.
ENCODERS = tuple(f"{leg}_{j}" for leg in L.LEGS for j in ("hip", "knee"))
#: Indices of the 8 encoders' commands among the 12 (``O.SERVO_NAMES`` order).
ENCODER_COMMANDS = tuple(O.SERVO_NAMES.index(n) for n in ENCODERS)
#: Indices of the 4 scapula commands among the 12.
SCAPULA_COMMANDS = tuple(O.SERVO_NAMES.index(f"{leg}_scapula") for leg in L.LEGS)
#: Regressor names of the contact-force regression: per toe (LEGS order) the force
#: along world x, y (the tangents of the level floor) and z (the normal).
FORCE_NAMES = tuple(f"{leg}_{a}" for leg in L.LEGS for a in ("fx", "fy", "fz"))
#: Codes of ``fall_kind``: how a run first met the fall criterion.
FALL_KINDS = ("none", "roll", "pitch", "low", "exploded")
#: Samples of a joint's own command (this period and the ones before) in the
#: command-only regression of :func:`encoder_information`: 40 ms.
COMMAND_LAGS = 4
#: Transition length [s] passed to the protocol's commands: every gait here is entered
#: from itself (standstill), for which the §3.2.5 transition is the gait itself whatever
#: its length (:func:`thesis.gaits.transitions.transition_state` with p_from = p_to).
SELF_TRANSITION = 1.0
#: Harmonics of the gait frequency removed by :func:`phase_residual`.
PHASE_HARMONICS = 10
#: Posture of a push run.
POSTURES = ("standing", "trotting")


# ------------------------------------------------------------------ readouts
def encoder_dofs(model) -> np.ndarray:
    """(8,) engine dof indices of the ch6 encoders (:data:`ENCODERS` order): the hip
    servo's coordinate (second axis of the shoulder's universal joint) and the knee
    motor's side of the cable (femur -> drum hinge), as
    ``thesis.ch6.loop.encoder_dofs``."""
    names = []
    for leg in L.LEGS:
        names += [f"{leg}_shoulder:1", f"{leg}_knee:0"]
    return np.array([model.dof(n) for n in names], np.int32)


def encoder_offsets() -> np.ndarray:
    """(8,) build-pose thesis angles [rad] added to the encoders' joint coordinates so
    that they read thesis joint angles (``thesis.ch6.loop.encoder_offsets``)."""
    return np.asarray(O.build_offsets(), np.float64)[list(ENCODER_COMMANDS)]


def scapula_dofs(model) -> np.ndarray:
    """(4,) engine dof indices of the scapula servos (first shoulder axis, LEGS order);
    their build-pose angle is 0, so they read thesis angles directly."""
    return np.array([model.dof(f"{leg}_shoulder:0") for leg in L.LEGS], np.int32)


def toe_contact_forces(model, state):
    """(4, 3) contact force on each toe in the last step [N]: the solver's impulses on
    the toe sphere's contact rows divided by dt, as (t1, t2, normal). On the level floor
    the tangent basis of :func:`thesis.physics.math.tangent_basis` is world x, y, so the
    columns are (fx, fy, fz) (tangential signs as the engine's rows; a linear regression
    does not depend on them). Rows: toes in LEGS order (``O.toe_spheres``)."""
    m = model
    n = m.n_contact
    start = m.n_rows - m.rows_per_contact * n
    other = np.where(m.pair_is_sphere, m.pair_other, m.n_csphere)
    query = np.repeat(m.field_query, m.field_k)
    seg = np.concatenate([m.pair_sphere, query, other,
                          np.full(query.shape, m.n_csphere)]).astype(np.int32)
    cols = []
    for r in (1, 2, 0):  # t1, t2, normal
        f = state.row_impulse[start + r * n:start + (r + 1) * n] / m.dt
        cols.append(jax.ops.segment_sum(jnp.concatenate([f, f]), seg,
                                        num_segments=m.n_csphere + 1)[:-1])
    return jnp.stack(cols, axis=-1)[np.asarray(O.toe_spheres())]


# ------------------------------------------------------------------ gaits
def sample_gaits(rng: np.random.Generator, n: int, family=FAMILY) -> np.ndarray:
    """(n, 12) spline trots drawn uniformly from Tab. 4.1's ranges, family order.

    f, x0, duty and the l_i uniform in their boxes; then, as Tab. 4.1's dependent ranges
    state, a uniform in [0, a_max(x0)] and y0 (fore and hind each) uniform in
    [y_min, y_max] of (x0, a). (The PSO's random swarm of ch4 draws a in the loosest box
    and clips it to a_max(x0), which puts a share of the particles on the a_max edge.)
    Both offsets are drawn in the fore legs' range, which the longer hind legs' range
    contains, so that models with and without the longer hind legs are measured on the
    same gaits.
    """
    u = rng.uniform(size=(int(n), len(family.names)))
    lo, hi = family.lower, family.upper
    p = lo + u * (hi - lo)
    ix0, ia = family.index("x0"), family.index("a")
    p[:, ia] = u[:, ia] * family.a_max(p[:, ix0])
    ylo, yhi = family.table.y0_range(p[:, ix0], p[:, ia])
    for name in ("y0_fore", "y0_hind"):
        i = family.index(name)
        p[:, i] = ylo + u[:, i] * np.maximum(yhi - ylo, 0.0)
    return family.project(p)


def nominal_gait(family=FAMILY) -> np.ndarray:
    """(12,) the nominal trot of the push and encoder checks: the middle of every
    Tab. 4.1 range (f 1.75 Hz, x0 142 mm, duty 0.5, l_i 35 mm), a half of a_max(x0) and
    y0 the middle of its range."""
    p = 0.5 * (family.lower + family.upper)
    ix0, ia = family.index("x0"), family.index("a")
    p[ia] = 0.5 * float(family.a_max(p[ix0]))
    ylo, yhi = family.table.y0_range(p[ix0], p[ia])
    for name in ("y0_fore", "y0_hind"):
        p[family.index(name)] = 0.5 * (float(ylo) + float(yhi))
    return family.project(p)


@functools.lru_cache(maxsize=8)
def command_fn(settle: float, t_transition: float, family=FAMILY):
    """Command function ``(memory, t, sensors) -> (12,)`` [rad]: the ch4 protocol of
    :func:`thesis.gaits.runner.gait_command_fn` for ``family`` (default the spline
    family of Tab. 4.1), or, where the memory's ``stand`` is 1, the build pose held
    (standing)."""
    gait = R.gait_command_fn(family, float(settle), float(t_transition))

    def fn(mem, t, sens):
        cmd = gait(mem, t, sens)
        build = jnp.asarray(O.build_offsets(), cmd.dtype)
        return jnp.where(mem["stand"] > 0.5, build, cmd)

    return fn


# ------------------------------------------------------------------ rollout
def _run_one(model, state0, mem, kick, k_kick, fn, n_cmd: int, stride: int):
    """One robot: ``n_cmd`` command periods of ``stride`` physics steps; before period
    ``k_kick`` the trunk's velocity changes by ``kick`` (3,) [m/s]. Records at the end of
    each period the body poses, the joint coordinates, the command held over the period
    and the toes' contact forces of its last step. Under a process-wide perturbation
    (``thesis --perturb``) the run starts from
    :func:`thesis.physics.perturbation.at_start` of ``state0``, as every rollout does."""
    trunk = O.trunk_index(model)
    state0 = perturbation.at_start(state0)

    def period(s, k):
        t = k.astype(s.pos.dtype) * R.COMMAND_PERIOD
        cmd = fn(mem, t, None).astype(s.pos.dtype)
        action = O.commands_to_action(cmd).astype(s.pos.dtype)
        dv = jnp.where(k == k_kick, 1.0, 0.0).astype(s.pos.dtype) * kick
        s = s.replace(vel=s.vel.at[trunk].add(dv))
        s, _ = jax.lax.scan(lambda st, _: (step(model, st, action), None), s, None,
                            length=stride)
        rec = dict(pos=s.pos, rot=s.rot, q=all_sensors(model, s)["joint_angle"], cmd=cmd,
                   force=toe_contact_forces(model, s))
        return s, rec

    _, rec = jax.lax.scan(period, state0, jnp.arange(n_cmd))
    return rec


@functools.lru_cache(maxsize=8)
def _compiled(settle: float, t_transition: float, n_cmd: int, stride: int, n_dev: int,
              family=FAMILY, perturbed: float = 0.0):
    """jit of a batch of :func:`_run_one` (sharded over ``n_dev`` host devices); cached per
    protocol and per process-wide perturbation size ``perturbed``, which the trace reads."""
    fn = command_fn(settle, t_transition, family)

    def batch(model, state0, mem, kick, k_kick):
        one = functools.partial(_run_one, model, state0, fn=fn, n_cmd=n_cmd, stride=stride)
        return jax.vmap(one)(mem, kick, k_kick)

    if n_dev > 1:
        mesh = Mesh(np.array(jax.devices()[:n_dev]), ("batch",))
        batch = jax.shard_map(batch, mesh=mesh, in_specs=(P(), P(), P("batch"), P("batch"),
                                                          P("batch")),
                              out_specs=P("batch"), check_vma=False)
    return jax.jit(batch)


def simulate_runs(model, state0, runs: dict, *, duration: float, settle: float,
                  t_transition: float, batch: int, family=FAMILY) -> dict:
    """Simulate R robots in compiled batches of ``batch`` (the last one padded).

    Args:
        model, state0: the Oncilla (one model for every run).
        runs: dict of per-run arrays with leading axis R: ``p`` (R, P) parameters of
            ``family`` (default the spline family, P = 12; family order), ``stand`` (R,) 1 to hold the build pose instead, ``kick``
            (R, 3) trunk velocity change [m/s], ``kick_time`` (R,) when it lands [s]
            (rounded to the 10-ms grid; inf: never).
        duration: simulated seconds of every run; settle, t_transition: the protocol [s].
        batch: robots per compiled call (a multiple of the host device count).

    Returns:
        dict of host arrays sampled every command period (K = duration / 10 ms): ``pos``
        (R, K, n_body, 3) [m], ``rot`` (R, K, n_body, 3, 3), ``q`` (R, K, n_dof) joint
        coordinates [rad], ``cmd`` (R, K, 12) thesis joint commands held over each
        period [rad], ``force`` (R, K, 4, 3) toe contact forces [N], ``t`` (K,) [s],
        ``reset`` (R,) all False and ``reset_at`` None (the fields of a
        :func:`thesis.gaits.runner.simulate` result), ``wall`` [s].
    """
    import time

    n_runs = len(runs["p"])
    n_dev = jax.device_count()
    batch = int(batch)
    if n_dev > 1 and batch % n_dev:
        batch += n_dev - batch % n_dev
    stride = int(round(R.COMMAND_PERIOD / float(model.dt)))
    n_cmd = int(round(duration / R.COMMAND_PERIOD))
    k_kick = np.where(np.isfinite(runs["kick_time"]),
                      np.round(np.nan_to_num(runs["kick_time"], posinf=0.0)
                               / R.COMMAND_PERIOD), -1).astype(np.int32)
    fn = _compiled(float(settle), float(t_transition), n_cmd, stride, n_dev, family,
                   perturbation.relative())
    dtype = np.dtype(state0.pos.dtype)
    batched = model.replace(batched=True)
    parts = []
    t0 = time.perf_counter()
    for start in range(0, n_runs, batch):
        idx = np.arange(start, min(start + batch, n_runs))
        pad = np.concatenate([idx, np.full(batch - len(idx), idx[0])])
        p = np.asarray(runs["p"], np.float64)[pad].astype(dtype)
        mem = dict(p_from=p, p_to=p, stand=np.asarray(runs["stand"], dtype)[pad])
        out = fn(batched, state0, mem, np.asarray(runs["kick"], dtype)[pad], k_kick[pad])
        parts.append({k: np.asarray(v)[:len(idx)] for k, v in out.items()})
    sim = {k: np.concatenate([q[k] for q in parts]) for k in parts[0]}
    sim.update(t=(np.arange(n_cmd) + 1) * R.COMMAND_PERIOD, reset=np.zeros(n_runs, bool),
               reset_at=None, wall=time.perf_counter() - t0)
    return sim


def select(sim: dict, idx) -> dict:
    """The runs ``idx`` of a :func:`simulate_runs` result (shared fields kept)."""
    per_run = ("pos", "rot", "q", "cmd", "force", "reset")
    return {k: (v[idx] if k in per_run else v) for k, v in sim.items()}


# ------------------------------------------------------------------ measurements
def fall_kind(model, sim, fall_height: float, t_start=0.0) -> np.ndarray:
    """(R,) index into :data:`FALL_KINDS` of how each run first met the fall criterion
    after ``t_start`` [s]: ``exploded`` (:func:`thesis.gaits.runner.exploded`), ``roll``
    or ``pitch`` (tilted beyond 60 degrees, mostly about the trunk's long or its
    lateral axis: the trunk's up axis leaning sideways or fore-aft), ``low`` (upright but
    below ``fall_height``), or ``none``."""
    trunk = O.trunk_index(model)
    pos, rot, t = sim["pos"][:, :, trunk], sim["rot"][:, :, trunk], sim["t"]
    n = pos.shape[0]
    w = R.window(t, t_start, t[-1], n)
    with np.errstate(invalid="ignore"):
        tilted = rot[..., 2, 2] < 0.5
        down = (tilted | (pos[..., 2] < fall_height)) & w
    bad = R.exploded(model, sim)
    out = np.zeros(n, np.int32)
    for i in range(n):
        if bad[i]:
            out[i] = FALL_KINDS.index("exploded")
        elif down[i].any():
            k = int(np.argmax(down[i]))
            up = rot[i, k, :, 2]  # the trunk's z axis in the world
            if tilted[i, k]:
                out[i] = FALL_KINDS.index("roll" if abs(up[1]) >= abs(up[0]) else "pitch")
            else:
                out[i] = FALL_KINDS.index("low")
    return out


def fall_rate_bins(values, fallen, edges) -> dict:
    """Fall counts of runs binned by one parameter.

    Args:
        values: (N,) the parameter of each run; fallen: (N,) bool.
        edges: (M + 1,) increasing bin edges; bin m holds edges[m] <= v < edges[m + 1],
            the last bin also v == edges[-1]; values outside are not counted.

    Returns:
        dict of (M,) arrays: ``n`` runs, ``falls`` fallen runs, ``rate`` = falls / n
        (NaN for an empty bin), ``centre`` of each bin.
    """
    v = np.asarray(values, np.float64)
    f = np.asarray(fallen, bool)
    e = np.asarray(edges, np.float64)
    m = len(e) - 1
    k = np.searchsorted(e, v, side="right") - 1
    k = np.where(v == e[-1], m - 1, k)
    inside = (k >= 0) & (k < m)
    n = np.bincount(k[inside], minlength=m).astype(np.int64)
    falls = np.bincount(k[inside], weights=f[inside].astype(float), minlength=m)
    with np.errstate(invalid="ignore", divide="ignore"):
        rate = np.where(n > 0, falls / np.maximum(n, 1), np.nan)
    return dict(n=n, falls=falls.astype(np.int64), rate=rate, centre=0.5 * (e[:-1] + e[1:]))


def r_squared(y, X) -> np.ndarray:
    """Coefficient of determination of the least-squares fit of ``y`` on ``X`` with an
    intercept: 1 - SS_res / SS_tot per column of ``y``.

    Args:
        y: (T,) or (T, J) targets; X: (T, p) regressors (p may be 0: R^2 = 0).

    Returns:
        () or (J,) R^2 (NaN for a constant target or fewer samples than p + 2).
    """
    y = np.asarray(y, np.float64)
    one = y.ndim == 1
    Y = y[:, None] if one else y
    X = np.asarray(X, np.float64).reshape(len(Y), -1)
    A = np.column_stack([np.ones(len(Y)), X])
    out = np.full(Y.shape[1], np.nan)
    if len(Y) >= A.shape[1] + 1:
        coef, *_ = np.linalg.lstsq(A, Y, rcond=None)
        res = ((Y - A @ coef) ** 2).sum(0)
        tot = ((Y - Y.mean(0)) ** 2).sum(0)
        with np.errstate(invalid="ignore", divide="ignore"):
            out = np.where(tot > 1e-12 * len(Y), 1.0 - res / tot, np.nan)
    return out[0] if one else out


def phase_residual(x, phase, harmonics: int = PHASE_HARMONICS) -> np.ndarray:
    """``x`` (T, ...) minus its least-squares fit by a Fourier series of the gait phase
    (``phase`` (T,) [cycles]; a constant and ``harmonics`` harmonics): the cycle-to-cycle
    part of a periodic gait's signal."""
    x = np.asarray(x, np.float64)
    ph = 2.0 * np.pi * np.asarray(phase, np.float64)[:, None] * np.arange(1, harmonics + 1)
    A = np.column_stack([np.ones(len(x)), np.cos(ph), np.sin(ph)])
    X = x.reshape(len(x), -1)
    coef, *_ = np.linalg.lstsq(A, X, rcond=None)
    return (X - A @ coef).reshape(x.shape)


def encoder_information(model, sim, mask, phase=None) -> dict:
    """R^2 of each encoder's deviation from its command (§6.1 encoders) per run.

    The deviation e_j = encoder_j - command_j (the command held over the same 10-ms
    period, read at its end as ch6 reads its encoders) is regressed, over the samples of
    ``mask``, on (a) the 12 toe contact forces (:data:`FORCE_NAMES`), (b) the joint's own
    command over the last :data:`COMMAND_LAGS` periods (a linear filter of the command,
    which covers a servo's lag and rate limit while it is linear), (c) both. Contact
    forces and commands are both periodic in the gait, so (a) alone also counts what the
    command explains; ``r2_forces_given_command`` = (R^2_both - R^2_command) /
    (1 - R^2_command) is the share of what the command leaves unexplained that the
    forces explain. Both still count what the gait's phase explains (the command's
    nonlinear response is periodic too); with ``phase``, ``r2_forces_beyond_phase`` is
    the R^2 of the cycle-to-cycle parts (:func:`phase_residual`) of e_j on those of the
    forces: what the encoders feel of the ground beyond the gait's rhythm.

    Args:
        sim: a :func:`simulate_runs` result (R runs, K samples); mask: (R, K) bool;
        phase: optional (R, K) gait phase of each sample's command [cycles].

    Returns:
        dict of (R, 8) arrays (NaN where a run has too few samples): ``r2_forces``,
        ``r2_command``, ``r2_both``, ``r2_forces_given_command``,
        ``r2_forces_beyond_phase`` (NaN without ``phase``) [1], ``error_rms`` [rad]
        (RMS of e_j), and ``samples`` (R,).
    """
    dofs = encoder_dofs(model)
    enc = sim["q"][..., dofs] + encoder_offsets()
    cmd = sim["cmd"][..., list(ENCODER_COMMANDS)].astype(np.float64)
    err = enc - cmd
    lagged = np.stack([np.concatenate([np.repeat(cmd[:, :1], d, axis=1),
                                       cmd[:, :cmd.shape[1] - d]], axis=1)
                       for d in range(COMMAND_LAGS)], axis=-1)  # (R, K, 8, lags)
    forces = sim["force"].reshape(sim["force"].shape[:2] + (-1,)).astype(np.float64)
    n_runs, n_enc = err.shape[0], err.shape[2]
    out = {k: np.full((n_runs, n_enc), np.nan) for k in
           ("r2_forces", "r2_command", "r2_both", "r2_forces_given_command",
            "r2_forces_beyond_phase", "error_rms")}
    samples = np.asarray(mask, bool).sum(1)
    for i in range(n_runs):
        w = np.asarray(mask[i], bool)
        if w.sum() < forces.shape[-1] + 10:
            continue
        e, F = err[i, w], forces[i, w]
        out["r2_forces"][i] = r_squared(e, F)
        out["error_rms"][i] = np.sqrt((e ** 2).mean(0))
        if phase is not None:
            ph = np.asarray(phase)[i, w]
            out["r2_forces_beyond_phase"][i] = r_squared(phase_residual(e, ph),
                                                         phase_residual(F, ph))
        for j in range(n_enc):
            own = lagged[i, w, j]
            out["r2_command"][i, j] = r_squared(e[:, j], own)
            out["r2_both"][i, j] = r_squared(e[:, j], np.column_stack([own, F]))
    with np.errstate(invalid="ignore", divide="ignore"):
        out["r2_forces_given_command"] = ((out["r2_both"] - out["r2_command"])
                                          / (1.0 - out["r2_command"]))
    out["samples"] = samples
    return out


def upright_mask(model, sim, fall_height: float, t_start: float) -> np.ndarray:
    """(R, K) bool: samples after ``t_start`` [s] and before each run's first fall
    (the criterion of :func:`thesis.gaits.runner.speed_terms`); none for an unphysical
    run."""
    trunk = O.trunk_index(model)
    pos, rot, t = sim["pos"], sim["rot"], sim["t"]
    n = pos.shape[0]
    with np.errstate(invalid="ignore"):
        down = (pos[:, :, trunk, 2] < fall_height) | (rot[:, :, trunk, 2, 2] < 0.5)
    before = np.cumsum(down, axis=1) == 0
    ok = ~R.exploded(model, sim)
    return before & (t[None] > t_start + 1e-9) & ok[:, None]


def standing(model, state0, sim, run: int = 0) -> dict:
    """Standing pose of run ``run`` of a :func:`simulate_runs` result at its last sample,
    beside the kinematic nominal (§3.2.1: toes ``O.BUILD_DEPTH`` below the hips; the
    nominal centre of mass is the build state's).

    Returns:
        dict: ``trunk_height``, ``com_height`` and their ``nominal_*`` [m]; ``toe`` (4, 3)
        toe-sphere centres in each hip's frame (trunk axes, origin at the hip) [m] and
        ``nominal_toe`` (4, 3); ``trunk_tilt`` [rad] (angle of the trunk's up axis from the
        vertical); ``knee_fold`` (4,) [rad] (tibia folded beyond the cable, the knee
        spring's compression); ``scapula`` (4,) [rad].
    """
    trunk = O.trunk_index(model)
    pos, rot = sim["pos"][run, -1].astype(np.float64), sim["rot"][run, -1].astype(np.float64)
    mass = np.asarray(model.body_mass, np.float64)
    pos0 = np.asarray(state0.pos, np.float64)
    toes = np.asarray(O.toe_spheres())
    body = np.asarray(model.csphere_body)[toes]
    off = np.asarray(model.csphere_offset, np.float64)[toes]
    world = pos[body] + np.einsum("nij,nj->ni", rot[body], off)
    rt = rot[trunk]
    hips = np.asarray(O.HIPS, np.float64)
    toe = (world - pos[trunk]) @ rt - hips  # trunk frame, relative to the hip
    q = sim["q"][run, -1].astype(np.float64)
    fold = np.array([q[model.dof(f"{leg}_cable:0")] for leg in L.LEGS])
    return dict(
        trunk_height=float(pos[trunk, 2]),
        nominal_trunk_height=float(O.BUILD_DEPTH + O.TOE_RADIUS - O.HIPS[0][2]),
        com_height=float((mass * pos[:, 2]).sum() / mass.sum()),
        nominal_com_height=float((mass * pos0[:, 2]).sum() / mass.sum()),
        toe=toe, nominal_toe=np.tile([0.0, 0.0, -O.BUILD_DEPTH], (4, 1)),
        trunk_tilt=float(math.acos(min(1.0, max(-1.0, rt[2, 2])))),
        knee_fold=fold, scapula=q[scapula_dofs(model)])


def model_code_sha256() -> str:
    """sha256 of the Oncilla model's source (``oncilla.py`` and ``leg_geometry.py``):
    which model a dataset measured."""
    h = hashlib.sha256()
    for mod in (O, LG):
        h.update(inspect.getsource(mod).encode())
    return h.hexdigest()
