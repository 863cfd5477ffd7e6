"""``thesis bench puppy-contact`` (registry ``model/puppy_contact``): the Puppy II's paw
contact on each chapter-5 terrain, measured on the current model and held against the
contact values gathered from material sources (docs/sources.md#ch5-terrain-contact).

The robot is :func:`thesis.ch5.recordings.puppy_model` (``ch5.model``'s settings), on a
flat floor of each terrain of ``ch5.terrains`` at its nominal values (no per-trial
jitter), the floor material set as the chapter's recordings set it
(:func:`thesis.ch5.recordings.terrain_model`). All runs of all terrains are one vmapped
rollout of ``max(settle + average, warmup + gait_seconds)`` simulated seconds, the hip
commands held per 50-Hz sample as in the recordings:

* **stand**: the build pose, paws touching the floor, servos holding the build pose
  (command 0). After ``settle`` seconds, the mean over ``average`` seconds of each paw's
  indentation (the paw sphere's depth below the floor plane [mm]) and normal force [N];
  their ratio is the contact's implied (secant) stiffness [kN/m].
* **drop**: the same pose released ``drop_height`` above the floor. At each paw's first
  touchdown (its sphere reaching the floor, interpolated between steps) the first force
  peak within ``impact_window`` seconds, the time from touchdown to that peak and the
  10-90 % rise time of the force (crossings interpolated linearly between the steps'
  forces; a step's force is its mean normal impulse / dt, stamped at the step's end, as
  the engine's sensor reports it). The time resolution is the model's step.
* **gaits**: each ``gaits`` entry (:func:`thesis.ch5.gaits.commands`, ``ch5.gaits``;
  the random gait's noise from stream ``model/puppy_contact/random`` of the root seed),
  from standing, measured over ``gait_seconds`` after ``warmup``: the share of steps in
  which each paw's normal force is below ``off_ground_threshold`` (off the ground), and
  the knee's angle range and largest flexion over the steps in which the paw is on the
  ground (stance). A run whose trunk turns over (up axis below
  ``ch5.recordings.fallen_up``) is flagged and measured only up to the turn-over, as the
  recordings stop a trial there (NaN if it turned over before the window).

Sources (:data:`SOURCED`): docs/sources.md §5.3 gives, for one paw's static load
m g / 4 = 3.68 N on a 12-mm silicone paw, the contact stiffness and indentation per
terrain where a source exists; the touchdown times below are derived from those
stiffnesses by that section's own formula (the paw's share m / 4 of the mass ringing on
k: f = sqrt(k / (m / 4)) / (2 pi), force peak a quarter period 1 / (4 f) after touchdown)
and, for the 10-90 % rise of a quarter sine, (asin 0.9 - asin 0.1) / (pi / 2) = 0.649 of
that time. A measured value passes when it lies within the sourced range widened by
``tolerance`` (default +-25 %) on each side that has a bound; "no source" where the
section gives none (off-ground shares and the knee's stance flexion have none).
"""

from __future__ import annotations

import importlib
import math

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from thesis import seeding
from thesis.ch5.recordings import puppy_model, terrain_model
from thesis.physics import rollout

__all__ = ["SOURCED", "simulate", "touchdown", "check", "puppy_contact"]

#: Where the sourced values are written out, with their derivations.
CITATION = "docs/sources.md#ch5-terrain-contact"
#: Rise of a quarter sine from 10 % to 90 % of its peak, as a fraction of the time to the
#: peak: (asin 0.9 - asin 0.1) / (pi / 2).
QUARTER_SINE_10_90 = (math.asin(0.9) - math.asin(0.1)) / (math.pi / 2)
_MATERIAL_KEYS = ("friction", "restitution", "stiffness", "damping_ratio")
_NAN = float("nan")

#: Per terrain, the sourced (low, high) of one paw's contact stiffness [kN/m] and static
#: indentation [mm] under m g / 4 (NaN: no bound on that side; both NaN: no source), and
#: a note on where they come from (docs/sources.md §5.3's table and its text).
SOURCED = {
    "F": dict(stiffness=(8.6, 25.0), indentation=(0.22, 0.64),
              note="blue foil on a hard floor: the silicone paw alone (Shore 30-60 A, "
              "Ruess relation, Hertz on a rigid floor): 8.6-25 kN/m, 0.22-0.64 mm"),
    "S": dict(stiffness=(2.7, 6.3), indentation=(0.58, 1.34),
              note="Styrofoam (EPS) crushes under the paw: crush indentation 0.36-0.70 mm "
              "(rigid cap at 135-70 kPa) plus the paw's own 0.22-0.64 mm; stiffness: "
              "3.68 N over that range (secant of a plastic contact)"),
    "L": dict(stiffness=(_NAN, 25.0), indentation=(0.22, _NAN),
              note="linoleum: modulus not found; only the paw's bounds (k <= 25 kN/m, "
              "d >= 0.22 mm)"),
    "C": dict(stiffness=(_NAN, 25.0), indentation=(_NAN, _NAN),
              note="corrugated cardboard: flat-crush stiffness not found; only the paw's "
              "bound k <= 25 kN/m; indentation open"),
    "R": dict(stiffness=(7.6, 24.0), indentation=(0.23, 0.72),
              note="rubber mat (Shore 60 A, 5.9 MPa) in series with the paw (Hertz): "
              "7.6-24 kN/m, 0.23-0.72 mm"),
}


def _time_to_peak_ms(stiffness_kn_m: float, mass: float) -> float:
    """Quarter period [ms] of the paw's share ``mass`` / 4 [kg] on a spring of
    ``stiffness_kn_m`` [kN/m] (docs/sources.md §5.3, "Touchdown"); NaN stays NaN."""
    if not np.isfinite(stiffness_kn_m):
        return _NAN
    f = math.sqrt(stiffness_kn_m * 1e3 / (mass / 4.0)) / (2.0 * math.pi)
    return 1e3 / (4.0 * f)


def sourced_ranges(terrains, mass: float) -> dict[str, np.ndarray]:
    """(len(terrains), 2) sourced (low, high) arrays of ``stiffness`` [kN/m],
    ``indentation`` [mm], ``time_to_peak`` and ``rise_time`` [ms] (module docstring;
    a stiffer contact peaks sooner, so a stiffness's upper bound is the time's lower
    bound). A terrain without an entry in :data:`SOURCED` has no source (NaN)."""
    out = {k: np.full((len(terrains), 2), np.nan)
           for k in ("stiffness", "indentation", "time_to_peak", "rise_time")}
    for i, t in enumerate(terrains):
        src = SOURCED.get(t)
        if src is None:
            continue
        out["stiffness"][i] = src["stiffness"]
        out["indentation"][i] = src["indentation"]
        lo_k, hi_k = src["stiffness"]
        peak = (_time_to_peak_ms(hi_k, mass), _time_to_peak_ms(lo_k, mass))
        if t == "S":  # the crush is plastic: no rise-time figure, only the paw's bound
            peak = (_time_to_peak_ms(25.0, mass), _NAN)
        out["time_to_peak"][i] = peak
        out["rise_time"][i] = np.asarray(peak) * QUARTER_SINE_10_90
    return out


def check(value, low, high, tolerance: float) -> np.ndarray:
    """"pass" / "fail" / "no source" of ``value`` against the sourced ``[low, high]``
    widened by ``tolerance`` (a fraction) on each side; a NaN bound is open, both NaN is
    "no source"; a NaN value (not measured) fails. Broadcasts; returns a str array."""
    v, lo, hi = np.broadcast_arrays(np.asarray(value, float), np.asarray(low, float),
                                    np.asarray(high, float))
    ok = ((np.isnan(lo) | (v >= lo * (1.0 - tolerance)))
          & (np.isnan(hi) | (v <= hi * (1.0 + tolerance))) & np.isfinite(v))
    return np.where(np.isnan(lo) & np.isnan(hi), "no source", np.where(ok, "pass", "fail"))


def simulate(ch5: dict, materials: np.ndarray, lifts: np.ndarray, commands: np.ndarray
             ) -> dict[str, np.ndarray]:
    """Run one batch of Puppy II robots (ch5.model settings) and record per step.

    Args:
        ch5: the ``ch5`` config section (``model``, ``recordings.sample_rate``).
        materials: (B, 4) floor material of each robot (:func:`thesis.ch5.recordings.terrain_model`).
        lifts: (B,) height [m] by which each robot's build pose is raised at release.
        commands: (B, n_samples, 4) hip commands [rad] per 50-Hz sample.
    Returns:
        dict of (B, n_steps, ...) arrays: ``force`` (4,) paw normal forces [N],
        ``depth`` (4,) paw sphere depth below the floor [m] (negative: above it),
        ``knee`` (4,) knee angles [rad] (positive = flexion), ``total`` all contact
        spheres' normal force [N], ``up`` the trunk's up axis' world z [1]; and the
        floats ``dt`` [s], the model's step, and ``slop`` [m], its contact slop (the
        depth a contact takes before its position correction starts).
    """
    pup = importlib.import_module("thesis.physics.models.puppy")
    mc = ch5["model"]
    model, state0 = puppy_model(ch5)
    dt = float(mc["dt"])
    rate = float(ch5["recordings"]["sample_rate"])
    steps = int(round(1.0 / rate / dt))
    n_samples = commands.shape[1]
    paws, knees = pup.paw_spheres(model), pup.knee_dofs(model)
    tibias = np.array([model.body(f"{leg}_tibia") for leg in pup.LEGS])
    trunk = pup.trunk_index(model)
    dtype = state0.pos.dtype
    offset = jnp.asarray([0.0, 0.0, -pup.TIBIA / 2], dtype)  # paw centre in the tibia

    def one(mat, lift, cmds):
        m = terrain_model(model, mat, float(mc["skin_ratio"]))
        s0 = state0.replace(pos=state0.pos.at[:, 2].add(lift))

        def ctrl(_, sens, k, t):
            return cmds[jnp.minimum(k // steps, n_samples - 1)], k + 1

        _, tr = rollout(m, s0, ctrl, None, n_samples * steps, memory0=jnp.int32(0),
                        record=("contact_force", "joint_angle", "body_pos", "body_rot"))
        paw_z = (tr["body_pos"][:, tibias, 2]
                 + jnp.einsum("tbj,j->tb", tr["body_rot"][:, tibias, 2, :], offset))
        return dict(force=tr["contact_force"][:, paws], depth=pup.PAW_RADIUS - paw_z,
                    knee=tr["joint_angle"][:, knees], total=tr["contact_force"].sum(-1),
                    up=tr["body_rot"][:, trunk, 2, 2])

    run = jax.jit(jax.vmap(one))
    out = run(jnp.asarray(materials, dtype), jnp.asarray(lifts, dtype),
              jnp.asarray(commands, dtype))
    out = {k: np.asarray(v, np.float64) for k, v in out.items()}
    out["dt"] = dt
    out["slop"] = float(model.contact_slop)
    return out


def _crossing(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """First time at which ``y`` (sampled at ``t``) reaches ``level`` from below,
    interpolated linearly between samples (NaN if it never does)."""
    above = np.flatnonzero(y >= level)
    if above.size == 0:
        return _NAN
    k = int(above[0])
    if k == 0:
        return float(t[0])
    y0, y1 = y[k - 1], y[k]
    return float(t[k - 1] + (level - y0) / (y1 - y0) * (t[k] - t[k - 1]))


def touchdown(force: np.ndarray, depth: np.ndarray, dt: float, window: float,
              depth0: float) -> tuple[float, float, float, float, float]:
    """(peak force [N], time from touchdown to it [s], 10-90 % rise time [s], touchdown
    time [s], steps with force on the rising edge up to the peak) of one paw's first
    touchdown, from its per-step ``force`` [N] and sphere ``depth`` [m] (step k's values
    stamped at (k + 1) dt; module docstring) and its depth at release ``depth0`` [m]
    (< 0: above the floor). All NaN if the paw never touches the floor within the run or
    its window. With one step on the edge (the force jumps to its peak within a step)
    the rise is not resolved: 10-90 % of a one-step jump reads 0.8 dt whatever it was."""
    t = (np.arange(force.size) + 1.0) * dt
    t_touch = _crossing(np.concatenate([[0.0], t]), np.concatenate([[depth0], depth]), 0.0)
    if not np.isfinite(t_touch):
        return (_NAN,) * 5
    win = (t >= t_touch) & (t <= t_touch + window + dt)
    if not win.any():
        return (_NAN,) * 5
    k_peak = int(np.flatnonzero(win)[np.argmax(force[win])])
    peak = float(force[k_peak])
    if peak <= 0.0:
        return (_NAN,) * 5
    # rising edge: from the touchdown (force 0) to the peak
    te = np.concatenate([[t_touch], t[win & (t <= t[k_peak])]])
    fe = np.concatenate([[0.0], force[win & (t <= t[k_peak])]])
    rise = _crossing(te, fe, 0.9 * peak) - _crossing(te, fe, 0.1 * peak)
    return (peak, float(t[k_peak] - t_touch), float(rise), float(t_touch),
            float(np.sum(fe > 0.0)))


def _plan(ch5: dict, cfg: dict, root_seed: int):
    """(terrains, gaits, materials (B, 4), lifts (B,) [m], commands (B, n_samples, 4)
    [rad], index) of the bench's runs, ``index`` giving the run of each terrain's stand
    and drop (T,) and gaits (T, G) (module docstring)."""
    from thesis.ch5 import gaits as G

    rate = float(ch5["recordings"]["sample_rate"])
    seconds = max(float(cfg["settle"]) + float(cfg["average"]),
                  float(cfg["warmup"]) + float(cfg["gait_seconds"]))
    n = int(round(seconds * rate))
    terrains = list(cfg["terrains"] or ch5["terrains"])
    gaits = list(cfg["gaits"])
    gait_cmds = []
    for i, g in enumerate(gaits):
        rng = seeding.rng(root_seed, "model/puppy_contact/random", i)
        gait_cmds.append(G.commands(str(g["gait"]), float(g["frequency"]), n, rate,
                                    ch5["gaits"], rng))
    mats, lifts, cmds = [], [], []
    index = dict(stand=[], drop=[], gait=[])
    for t in terrains:
        mat = [float(ch5["terrains"][t][k]) for k in _MATERIAL_KEYS]
        for kind, lift in (("stand", 0.0), ("drop", float(cfg["drop_height"]))):
            index[kind].append(len(mats))
            mats.append(mat)
            lifts.append(lift)
            cmds.append(np.zeros((n, 4)))
        row = []
        for c in gait_cmds:
            row.append(len(mats))
            mats.append(mat)
            lifts.append(0.0)
            cmds.append(c)
        index["gait"].append(row)
    return (terrains, gaits, np.array(mats), np.array(lifts), np.array(cmds),
            {k: np.array(v, int) for k, v in index.items()})


def puppy_contact(ctx) -> xr.Dataset:
    """``thesis bench puppy-contact`` (registry ``model/puppy_contact``; module
    docstring): static indentation, touchdown rise and per-gait paw unloading and knee
    stance flexion of the current Puppy II on each ch5 terrain, against the sourced
    contact values.

    Returns a dataset with dims ``terrain``, ``paw`` (LF, RF, LH, RH), ``gait`` (one per
    ``gaits`` entry; coords ``gait_name``, ``frequency``) and ``bound`` (low, high).
    """
    pup = importlib.import_module("thesis.physics.models.puppy")
    full = ctx.full_config
    ch5, cfg = full["ch5"], full["physics"]["puppy_contact"]
    tol = float(cfg["tolerance"])
    thr = float(cfg["off_ground_threshold"])
    terrains, gaits, mats, lifts, cmds, index = _plan(ch5, cfg, ctx.root_seed)
    ctx.log.info("puppy contact: %d terrains x (stand, drop, %d gaits), %d robots, %.1f s",
                 len(terrains), len(gaits), len(mats),
                 cmds.shape[1] / float(ch5["recordings"]["sample_rate"]))
    sim = simulate(ch5, mats, lifts, cmds)
    dt = sim["dt"]
    n_t, n_p, n_g = len(terrains), len(pup.LEGS), len(gaits)

    # stand: mean over the averaging window after settling
    a0 = int(round(float(cfg["settle"]) / dt))
    a1 = a0 + int(round(float(cfg["average"]) / dt))
    st = index["stand"]
    depth = sim["depth"][st, a0:a1].mean(1) * 1e3  # (terrain, paw) [mm]
    force = sim["force"][st, a0:a1].mean(1)
    total = sim["total"][st, a0:a1].mean(1)
    knee_static = sim["knee"][st, a0:a1].mean(1)
    with np.errstate(divide="ignore", invalid="ignore"):
        stiff = np.where(depth > 0, force / depth, np.nan)  # N/mm = kN/m
        beyond = depth - sim["slop"] * 1e3
        stiff_beyond = np.where(beyond > 0, force / beyond, np.nan)

    # drop: first touchdown per paw
    td = np.array([[touchdown(sim["force"][r, :, p], sim["depth"][r, :, p], dt,
                              float(cfg["impact_window"]), -float(lifts[r]))
                    for p in range(n_p)]
                   for r in index["drop"]])  # (terrain, paw, 4)

    # gaits: the measured window, up to the step before the trunk turns over (the
    # recordings stop a trial there too)
    g0 = int(round(float(cfg["warmup"]) / dt))
    g1 = g0 + int(round(float(cfg["gait_seconds"]) / dt))
    gi = index["gait"]  # (terrain, gait)
    upright = np.cumprod(sim["up"][gi, :g1] >= float(ch5["recordings"]["fallen_up"]),
                         axis=2).astype(bool)  # (terrain, gait, time)
    turned = ~upright[..., -1]
    valid = upright[..., g0:g1, None]
    f = sim["force"][gi, g0:g1]  # (terrain, gait, time, paw)
    q = sim["knee"][gi, g0:g1]
    n_valid = valid.sum(2)
    with np.errstate(invalid="ignore"):
        off = np.where(n_valid > 0, ((f < thr) & valid).sum(2) / n_valid, np.nan)
    stance = (f >= thr) & valid
    q_st_max = np.where(stance, q, -np.inf).max(2)
    q_st_min = np.where(stance, q, np.inf).min(2)
    has = stance.any(2)
    knee_range = np.where(has, q_st_max - q_st_min, np.nan)
    knee_max = np.where(has, q_st_max, np.nan)
    measured = valid[..., 0].sum(2) * dt  # (terrain, gait) [s]

    src = sourced_ranges(terrains, pup.MASS)

    def chk(value, key, resolved=True):
        lo, hi = src[key][:, 0], src[key][:, 1]
        out = check(value, lo[:, None], hi[:, None], tol)
        return np.where((out != "no source") & ~np.asarray(resolved), "unresolved", out)

    resolved = td[..., 4] > 1  # more than one step on the rising edge

    unload = (off > 0).any(2)  # (terrain, gait): some paw leaves the ground
    never = [f"{g['gait']} {float(g['frequency']):g} Hz" for j, g in enumerate(gaits)
             if not unload[:, j].any()]
    unload_note = ("The paws never unload (normal force below the threshold) on any "
                   "terrain in: " + ", ".join(never) if never else
                   "In every gait some paw unloads on some terrain")
    ranges = ("bound", ["low", "high"])
    no_src = ("no source: docs/sources.md §5.3 gives no value (Tab. 5.1 and §5.3.1 "
              "give no gait kinematics)")
    ds = xr.Dataset(
        {
            "indentation": (("terrain", "paw"), depth, dict(
                units="mm", long_name="paw sphere's depth below the floor, standing "
                "(paw and floor together; includes the engine's contact slop)")),
            "normal_force": (("terrain", "paw"), force, dict(
                units="N", long_name="paw's normal force, standing")),
            "total_normal_force": (("terrain",), total, dict(
                units="N", long_name="all contact spheres' normal force, standing "
                f"(weight m g = {pup.MASS * 9.81:.3f} N)")),
            "knee_static": (("terrain", "paw"), knee_static, dict(
                units="rad", long_name="knee angle standing (positive = flexion)")),
            "implied_stiffness": (("terrain", "paw"), stiff, dict(
                units="kN/m", long_name="normal force over indentation, standing")),
            "implied_stiffness_beyond_slop": (("terrain", "paw"), stiff_beyond, dict(
                units="kN/m", long_name="normal force over the indentation beyond the "
                "engine's contact slop (the soft row's own spring)")),
            "peak_force": (("terrain", "paw"), td[..., 0], dict(
                units="N", long_name="first force peak after touchdown, drop")),
            "time_to_peak": (("terrain", "paw"), td[..., 1] * 1e3, dict(
                units="ms", long_name="time from touchdown to the first force peak, drop")),
            "rise_time": (("terrain", "paw"), td[..., 2] * 1e3, dict(
                units="ms", long_name="10-90 % rise time of the normal force at "
                "touchdown, drop")),
            "off_ground_share": (("terrain", "gait", "paw"), off, dict(
                units="1", long_name="share of steps with the paw's normal force below "
                "the off-ground threshold", check=no_src)),
            "knee_stance_range": (("terrain", "gait", "paw"), knee_range, dict(
                units="rad", long_name="knee angle range over the paw's stance steps",
                check=no_src)),
            "knee_stance_max": (("terrain", "gait", "paw"), knee_max, dict(
                units="rad", long_name="largest knee flexion over the paw's stance steps",
                check=no_src)),
            "paws_unload": (("terrain", "gait"), unload, dict(
                units="1", long_name="some paw is off the ground in the measured window")),
            "turned_over": (("terrain", "gait"), turned, dict(
                units="1", long_name="the trunk's up axis fell below ch5.recordings."
                "fallen_up before the window's end")),
            "measured_seconds": (("terrain", "gait"), measured, dict(
                units="s", long_name="length of the measured window up to a turn-over")),
            "stiffness_source": (("terrain",) + (ranges[0],), src["stiffness"], dict(
                units="kN/m", source=CITATION, long_name="sourced one-paw contact "
                "stiffness (NaN: no bound)")),
            "indentation_source": (("terrain", ranges[0]), src["indentation"], dict(
                units="mm", source=CITATION, long_name="sourced static indentation under "
                "m g / 4 (NaN: no bound)")),
            "time_to_peak_source": (("terrain", ranges[0]), src["time_to_peak"], dict(
                units="ms", source=CITATION, long_name="touchdown to force peak, a quarter "
                "period of m / 4 on the sourced stiffness (NaN: no bound)")),
            "rise_time_source": (("terrain", ranges[0]), src["rise_time"], dict(
                units="ms", source=CITATION, long_name="10-90 % rise of a quarter sine "
                f"({QUARTER_SINE_10_90:.3f} of the time to peak; NaN: no bound)")),
            "source_note": (("terrain",), np.array([SOURCED[t]["note"] if t in SOURCED
                                                    else "no source" for t in terrains]),
                            dict(units="1", source=CITATION,
                                 long_name="where the terrain's sourced values come from")),
            "indentation_check": (("terrain", "paw"), chk(depth, "indentation"), dict(
                units="1", long_name=f"indentation within +-{tol:.0%} of the sourced range")),
            "stiffness_check": (("terrain", "paw"), chk(stiff, "stiffness"), dict(
                units="1", long_name=f"implied stiffness within +-{tol:.0%} of the sourced "
                "range")),
            "rise_steps": (("terrain", "paw"), td[..., 4], dict(
                units="1", long_name="steps with force on the rising edge up to the peak "
                "(1: the force jumps within a step, the rise is not resolved)")),
            "time_to_peak_check": (("terrain", "paw"),
                                   chk(td[..., 1] * 1e3, "time_to_peak", resolved), dict(
                units="1", long_name=f"time to peak within +-{tol:.0%} of the sourced range "
                "('unresolved': the force jumps to its peak within one step)")),
            "rise_time_check": (("terrain", "paw"), chk(td[..., 2] * 1e3, "rise_time",
                                                        resolved), dict(
                units="1", long_name=f"rise time within +-{tol:.0%} of the sourced range "
                "('unresolved': the force jumps to its peak within one step)")),
        },
        coords=dict(terrain=terrains, paw=list(pup.LEGS), bound=ranges[1],
                    gait=[f"{g['gait']} {float(g['frequency']):g} Hz" for g in gaits],
                    gait_name=("gait", [str(g["gait"]) for g in gaits],
                               dict(units="1", long_name="gait (thesis.ch5.gaits)")),
                    frequency=("gait", np.array([float(g["frequency"]) for g in gaits]),
                               dict(units="Hz", long_name="gait frequency (random: "
                                    "cut-off)"))),
        attrs=dict(title="Puppy II paw contact per terrain: static indentation, touchdown "
                   "rise, paw unloading and knee stance flexion per gait",
                   thesis_ref="§5.3.1 (Puppy II, terrains, Tab. 5.1); model check",
                   source=CITATION, dt_s=dt, contact_slop_m=sim["slop"],
                   static_load_n=pup.MASS * 9.81 / 4, tolerance=tol,
                   off_ground_threshold_n=thr, unloading=unload_note,
                   seeds=[int(ctx.root_seed)]))
    for i, t in enumerate(terrains):
        ctx.log.info("puppy contact %s: indentation %.2f mm, %.2f kN/m, rise %.1f ms, "
                     "peak after %.1f ms (sourced: %s)", t, float(depth[i].mean()),
                     float(np.nanmean(stiff[i])), float(np.nanmean(td[i, :, 2])) * 1e3,
                     float(np.nanmean(td[i, :, 1])) * 1e3,
                     SOURCED[t]["note"] if t in SOURCED else "no source")
    ctx.log.info("puppy contact: %s", unload_note)
    return ds
