"""Simulated Puppy II recordings: the trials of Tab. 5.1 on five terrains (§5.3.1).

Every trial is Puppy II (:mod:`thesis.physics.models.puppy`) running one gait
(:mod:`thesis.ch5.gaits`) at one frequency on one terrain for 3000-6500 samples at
50 Hz. Terrains differ *only* in the floor's contact physics -- Coulomb friction,
restitution, and the paw-floor contact as a spring-damper in physical units (stiffness
[N/m], damping ratio on the paw's share of the mass; :func:`terrain_model`), the
profile's ``ch5.terrains`` -- each parameter jittered by a uniform +-``jitter`` per trial
(the paws' directional skin takes ``ch5.model.skin_ratio`` of the friction forward), and
the 64 signals (:mod:`thesis.ch5.sensors`) carry sensor noise (``ch5.noise``; the paw
force sensors are modelled as force-sensing resistors, :func:`fsr`, ``ch5.touch``).

Terrain values (docs/sources.md#ch5-terrain-contact, departure ``ch5.terrain_materials``):
the stiffness is one paw's under its static load m g / 4 (Hertz contact of the 12 mm
silicone paw, Shore 30-60 A, in series with the floor): F 8.6-25 kN/m (the paw alone on
a hard floor), R 7.6-24 kN/m (rubber mat in series), S 2.7-6.3 kN/m (the secant of
Styrofoam's crush plus the paw's own indentation: the crush is plastic, which the
engine's elastic contact cannot be, so the secant stiffness is its declared elastic
approximation); where a range is sourced and nothing selects within it, its geometric
middle (F 14.66, R 13.51, S 4.12 kN/m). Linoleum and cardboard have only the paw's
bound (k <= 25 kN/m): their own modulus is not found, so each is the paw alone on a hard
floor (14.66 kN/m, declared: a floor compliance without a source is not invented).
Damping ratio zeta = tan(delta) / 2 from the loss factor's geometric middle: the
silicone paw's tan(delta) 0.10-0.30 (F, L, C: 0.087), SBR/NR rubber's zeta 0.05-0.125
(R: 0.079); Styrofoam 1.0 (chosen: its crush returns no energy, e ~ 0, and a critically
damped contact is the least damped that does not rebound). The energy loss of a contact
is its damping only: restitution (the engine's hard velocity target at an approaching
contact, which would replace the sourced spring at every touchdown) is 0 on every
terrain. Friction: no source measures a rubber or silicone skin on any of the five
floors, so the chosen coefficients stay (F 0.35, S 0.65, L 0.5, C 0.45, R 0.9; R's lies
in the 0.8-1.0 of rubber on a dry hard surface).
Each trial starts from standing at a random heading and position near the arena centre;
a trial stops when the robot turns over (the trunk's up axis below ``fallen_up``), as
an experimenter would stop it: without that, 9 of the 11 random-gait trials of the
default profile ended lying on the back for most of their 60-130 s.
These values were fixed from physical reasoning before any classifier ran on the
recordings and are never changed to move a score (the profile's comments give the
reasons); in simulation, class separability is a choice, so tuning it would decide the
claims.

Simulation: the floor material is a model leaf, so every trial of every terrain runs in
the same compiled rollout: a batch of trials (``batch`` robots, vmapped with per-robot
materials, split over the XLA host devices) advances ``chunk_seconds`` at a time; the
physics steps of ``ch5.model.dt`` (16 of 1.25 ms at the schema's default) make one 20 ms
sample. Per sample the accelerometer and gyroscope
are averaged over the sample's steps (a sensor's anti-aliasing); the paw forces (an FSR
is instantaneous: a point sample, docs/sources.md#ch5-touch), the joint angles and the
trunk pose are taken at its end. Trials are batched by length so
that a batch runs only as long as its longest trial.

File (``data/synthetic/puppy/<profile>.h5``, HDF5): ``signals`` (n_samples, 64)
float32, every trial end to end; per trial ``offset``, ``length``, ``terrain``
(index into attribute ``terrains``), ``gait`` (index into ``gaits``), ``frequency``
[Hz]; attributes ``names`` (the 64 signal names), ``sample_rate`` and the generating
configuration. :func:`load` checks all of it and names the file and trial at fault.
"""

from __future__ import annotations

import functools
import importlib
import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from thesis.ch5 import gaits as G
from thesis.ch5 import sensors as S

__all__ = ["TERRAINS", "TAB5_1", "RecordingError", "Recordings", "trial_table", "generate",
           "write", "load"]

#: Terrains of Tab. 5.1: blue foil, Styrofoam, linoleum, cardboard, rubber.
TERRAINS = ("F", "S", "L", "C", "R")
#: Gait frequencies of Tab. 5.1 [Hz].
FREQUENCIES = (0.25, 0.50, 0.75, 1.00, 1.25, 1.52, 1.72)
#: Tab. 5.1: (gait, terrain) -> trials per frequency (FREQUENCIES order).
TAB5_1 = {
    ("bound_right", "F"): (3, 5, 4, 2, 6, 3, 8),
    ("bound_right", "S"): (1, 2, 2, 13, 1, 2, 3),
    ("bound_right", "L"): (0, 0, 0, 9, 0, 0, 0),
    ("bound_right", "C"): (0, 0, 0, 3, 0, 0, 0),
    ("bound_right", "R"): (0, 0, 0, 5, 0, 0, 0),
    ("turn_left", "F"): (2, 4, 4, 4, 0, 0, 0),
    ("turn_left", "S"): (1, 2, 2, 4, 3, 6, 0),
    ("turn_left", "L"): (0, 0, 0, 3, 0, 0, 0),
    ("random", "F"): (0, 0, 0, 4, 0, 0, 0),
    ("random", "S"): (0, 0, 0, 3, 0, 0, 0),
    ("random", "L"): (0, 0, 0, 4, 0, 0, 0),
}
_MATERIAL_KEYS = ("friction", "restitution", "stiffness", "damping_ratio")


class RecordingError(ValueError):
    """The recordings file is missing, corrupt or does not match what is expected."""


@dataclass(frozen=True)
class Recordings:
    """Recordings in memory (see module docstring for the fields)."""

    signals: np.ndarray
    offset: np.ndarray
    length: np.ndarray
    terrain: np.ndarray
    gait: np.ndarray
    frequency: np.ndarray
    names: tuple[str, ...]
    path: str = ""
    config_json: str = "{}"
    stopped_trials: tuple[int, ...] = ()

    @property
    def n_trials(self) -> int:
        return int(self.length.size)

    def trials(self, gaits=None) -> np.ndarray:
        """Indices of the trials of the given gait names (all if None)."""
        if gaits is None:
            return np.arange(self.n_trials)
        want = [G.GAITS.index(g) for g in gaits]
        return np.flatnonzero(np.isin(self.gait, want))


def trial_table(cfg: dict, rng: np.random.Generator) -> list[dict]:
    """The trials to simulate (their planned lengths): Tab. 5.1's counts (at most
    ``max_trials_per_cell`` per cell when set; exactly ``trials_per_frequency`` per non-empty
    cell when set), each with its length drawn uniformly from the terrain's range. ``cells``
    (the Puppy II's convergence table's follow-up, not a profile key): only these ``(gait,
    terrain letter, frequency [Hz])`` cells."""
    cap = cfg["recordings"].get("max_trials_per_cell")
    exact = cfg["recordings"].get("trials_per_frequency")
    only = cfg["recordings"].get("cells")
    only = None if only is None else {(str(g), str(t), round(float(f), 6)) for g, t, f in only}
    lengths = cfg["recordings"]["samples"]
    out = []
    for (gait, terrain), counts in TAB5_1.items():
        for f, n in zip(FREQUENCIES, counts):
            if only is not None and (gait, terrain, round(float(f), 6)) not in only:
                continue
            if exact is not None:
                n = int(exact) if n else 0
            elif cap is not None:
                n = min(n, int(cap))
            lo, hi = lengths.get(terrain) or lengths["default"]
            for _ in range(n):
                out.append(dict(gait=gait, terrain=terrain, frequency=f,
                                length=int(rng.integers(int(lo), int(hi) + 1))))
    return out


# ------------------------------------------------------------------ simulation
def _puppy():
    return importlib.import_module("thesis.physics.models.puppy")


def terrain_model(model, material, skin_ratio: float):
    """``model`` with its single floor material replaced by one terrain's ``material``
    (friction, restitution, stiffness [N/m], damping ratio: a (4,) array, traced or not):
    the terrain's friction coefficient backward and sideways, the paws' skin gripping
    ``skin_ratio`` of it forward (module docstring); the contact a spring-damper of that
    stiffness with damping ``c = 2 zeta sqrt(k m_paw)`` [N s/m], ``m_paw`` the paw's share
    m / 4 of the robot's mass (the mass docs/sources.md#ch5-terrain-contact rings on k;
    its zeta = tan(delta) / 2 is the material's loss factor). ``model`` must have been
    built with a contact in physical units (:func:`puppy_model`)."""
    if not model.absolute_contact:
        raise ValueError("terrain_model: the Puppy II must be built with a contact in "
                         "physical units (thesis.ch5.recordings.puppy_model)")
    mu = material[0:1]
    k = material[2:3]
    c = paw_damping(k, material[3:4])
    return model.replace(material_friction=mu, material_friction_backward=mu,
                         material_friction_forward=float(skin_ratio) * mu,
                         material_restitution=material[1:2], material_stiffness=k,
                         material_damping=c)


def paw_damping(stiffness, damping_ratio):
    """Damping [N s/m] of a paw-floor contact of ``stiffness`` [N/m] at ``damping_ratio``:
    ``2 zeta sqrt(k m_paw)``, ``m_paw`` the paw's share m / 4 of the robot's mass
    (docs/sources.md#ch5-terrain-contact). Arrays, traced or not (a float array of one
    value for a float)."""
    import jax.numpy as jnp

    return 2.0 * damping_ratio * jnp.sqrt(stiffness * (_puppy().MASS / 4.0))


def puppy_model(ch5: dict):
    """(model, state0) of the Puppy II at ``ch5.model``'s settings with its floor contact
    in physical units (built on terrain F's stiffness and damping; every trial replaces
    the material with its terrain's, :func:`terrain_model`)."""
    mcfg = ch5["model"]
    pup = _puppy()
    f = ch5["terrains"]["F"]
    k = float(f["stiffness"])
    return pup.puppy(dt=float(mcfg["dt"]), solver_iterations=int(mcfg["solver_iterations"]),
                     skin_ratio=float(mcfg["skin_ratio"]),
                     sweep_order=str(mcfg.get("sweep_order", "jacobi")),
                     relaxation=float(mcfg.get("relaxation", 0.3)),
                     momentum=float(mcfg.get("momentum", 0.85)), contact_stiffness=k,
                     contact_damping=float(paw_damping(k, float(f["damping_ratio"]))))


@functools.lru_cache(maxsize=8)
def _chunk_fn(model_key, n_samples: int, steps: int, n_dev: int):
    """jit of one chunk for a batch: (materials, states, commands) -> (states, raw)."""
    import jax
    import jax.numpy as jnp
    from jax.sharding import Mesh, PartitionSpec as P

    from thesis.physics import rollout

    model = _MODELS[model_key].replace(batched=True)
    pup = _puppy()
    hips, knees = pup.hip_dofs(model), pup.knee_dofs(model)
    paws, trunk = pup.paw_spheres(model), pup.trunk_index(model)

    def one(mat, s0, cmds):
        m = terrain_model(model, mat, model_key[2])

        def ctrl(_, sens, k, t):
            return cmds[jnp.minimum(k // steps, n_samples - 1)].astype(s0.pos.dtype), k + 1

        final, tr = rollout(m, s0, ctrl, None, n_samples * steps, memory0=jnp.int32(0),
                            record=("joint_angle", "contact_force", "imu_acc", "imu_gyro",
                                    "body_pos", "body_rot"))

        def per_sample(x):
            return x.reshape((n_samples, steps) + x.shape[1:])

        raw = dict(
            q=per_sample(tr["joint_angle"])[:, -1][:, np.concatenate([hips, knees])],
            touch=per_sample(tr["contact_force"][:, paws])[:, -1],
            acc=per_sample(tr["imu_acc"][:, trunk]).mean(1),
            gyro=per_sample(tr["imu_gyro"][:, trunk]).mean(1),
            pos=per_sample(tr["body_pos"][:, trunk])[:, -1],
            rot=per_sample(tr["body_rot"][:, trunk])[:, -1],
        )
        return final, raw

    run = jax.vmap(one)
    if n_dev > 1:
        mesh = Mesh(np.array(jax.devices()[:n_dev]), ("batch",))
        run = jax.shard_map(run, mesh=mesh, in_specs=(P("batch"), P("batch"), P("batch")),
                            out_specs=P("batch"), check_vma=False)
    return jax.jit(run)


_MODELS: dict = {}


def _initial_states(state0, headings, offsets):
    """Stack copies of ``state0`` turned about z by ``headings`` [rad] and shifted by
    ``offsets`` (B, 2) [m] in the floor plane."""
    import jax.numpy as jnp

    c, s = np.cos(headings), np.sin(headings)
    rz = np.zeros((len(headings), 3, 3))
    rz[:, 0, 0], rz[:, 0, 1], rz[:, 1, 0], rz[:, 1, 1], rz[:, 2, 2] = c, -s, s, c, 1.0
    pos = np.einsum("bij,nj->bni", rz, np.asarray(state0.pos, np.float64))
    pos[:, :, :2] += offsets[:, None, :]
    rot = np.einsum("bij,njk->bnik", rz, np.asarray(state0.rot, np.float64))
    dtype = state0.pos.dtype
    b = len(headings)
    import jax

    tile = jax.tree.map(lambda x: jnp.broadcast_to(x, (b,) + x.shape), state0)
    return tile.replace(pos=jnp.asarray(pos, dtype), rot=jnp.asarray(rot, dtype))


def _quat(rot: np.ndarray) -> np.ndarray:
    """(..., 4) unit quaternion (w, x, y, z) with w >= 0 of rotation matrices (..., 3, 3)."""
    from scipy.spatial.transform import Rotation

    q = Rotation.from_matrix(rot.reshape(-1, 3, 3)).as_quat()  # x, y, z, w
    q = np.concatenate([q[:, 3:], q[:, :3]], axis=1)
    q *= np.where(q[:, :1] < 0, -1.0, 1.0)
    return q.reshape(rot.shape[:-2] + (4,))


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def fsr(force: np.ndarray, touch: dict, rng: np.random.Generator) -> np.ndarray:
    """(n, 4) paw force sensor readings [N] from the paws' simulated normal forces ``force``
    (n, 4) [N], each a point sample of the step that ends the 20 ms sample
    (docs/sources.md#ch5-touch: an FSR is instantaneous, the 50 Hz reading is a point
    sample). ``touch`` (profile ``ch5.touch``): an Interlink FSR 402 as the section gives
    it: nothing below the actuation force ``actuation`` [N], clipped at its ``range`` [N];
    the reading is ``hysteresis`` higher while the force falls (sample to sample) than
    while it rises, and varies by ``repeatability`` (a fraction; taken as the standard
    deviation of a Gaussian gain per sample, a chosen reading of the sheet's +-2 %)."""
    force = np.asarray(force, float)
    falling = np.diff(force, axis=0, prepend=force[:1]) < 0
    gain = (1.0 + float(touch["hysteresis"]) * falling) * (
        1.0 + rng.normal(0.0, float(touch["repeatability"]), force.shape))
    reading = np.where(force < float(touch["actuation"]), 0.0, force * gain)
    return np.clip(reading, 0.0, float(touch["range"]))


def signals_from_raw(raw: dict, cmds: np.ndarray, cfg: dict, rng: np.random.Generator,
                     sample_rate: float) -> np.ndarray:
    """(n, 64) signals of one trial (:data:`thesis.ch5.sensors.NAMES` order) from the
    simulated quantities ``raw`` (per sample) and the hip commands, with sensor noise."""
    pup = _puppy()
    noise = cfg["noise"]
    n = len(cmds)

    def nz(shape, sd):
        return rng.normal(0.0, float(sd), shape)

    touch = fsr(raw["touch"], cfg["touch"], rng) + nz((n, 4), noise["touch"])
    joints = raw["q"] + nz((n, 8), noise["joint"])
    acc = raw["acc"] + nz((n, 3), noise["accelerometer"])
    gyro = raw["gyro"] + nz((n, 3), noise["gyroscope"])
    mag = np.asarray(pup.magnetometer(raw["rot"])) + nz((n, 3), noise["magnetometer"])
    pos = raw["pos"] + nz((n, 3), noise["position"])
    head_true = np.arctan2(raw["rot"][:, 1, 0], raw["rot"][:, 0, 0])
    compass = _wrap(head_true + nz(n, noise["heading"]))
    vel_xy = np.diff(pos[:, :2], axis=0, prepend=pos[:1, :2]) * sample_rate
    fwd = np.stack([np.cos(head_true), np.sin(head_true)], 1)
    velocity = np.sum(vel_xy * fwd, 1)
    lateral = fwd[:, 0] * vel_xy[:, 1] - fwd[:, 1] * vel_xy[:, 0]
    wall = np.asarray(pup.wall_distance(raw["pos"], raw["rot"],
                                        cfg["recordings"]["arena_half_width"],
                                        cfg["recordings"]["range_max"]))
    wall = wall + nz(n, noise["wall"])

    def d(x):
        return np.diff(x, axis=0, prepend=x[:1])

    cols = {}
    for names, vals in ((S.TOUCH, touch), (S.JOINTS, joints), (S.ACC, acc), (S.GYRO, gyro),
                        (S.MAG, mag), (S.COMMANDS, cmds)):
        for i, name in enumerate(names):
            cols[name] = vals[:, i]
            cols["d_" + name] = d(vals[:, i])
    cols.update(velocity=velocity, compass=compass, wall_distance=wall,
                d_velocity=d(velocity), d_compass=_wrap(d(compass)))
    quat = _quat(raw["rot"])
    for i, a in enumerate("xyz"):
        cols[f"pos_{a}"] = pos[:, i]
    for i, a in enumerate("wxyz"):
        cols[f"quat_{a}"] = quat[:, i]
    cols["lateral_velocity"] = lateral
    cols["time"] = np.arange(n) / sample_rate
    return np.stack([cols[name] for name in S.NAMES], axis=1)


def generate(cfg: dict, root_seed: int, *, log=None, experiment: str = "ch5/puppy_recordings"
             ) -> tuple[Recordings, dict]:
    """Simulate every trial of :func:`trial_table`.

    Args:
        cfg: the ``ch5`` section of the profile; root_seed: the profile's root seed.
    Returns:
        (recordings, info) with ``info`` the wall time, robot seconds and rate.
    Raises:
        SimulationDiverged: a trial's state became non-finite (names the trial).
    """
    import jax
    import jax.numpy as jnp

    from thesis import seeding
    from thesis.errors import SimulationDiverged

    rec = cfg["recordings"]
    rate = float(rec["sample_rate"])
    mcfg = cfg["model"]
    solver = dict(sweep_order=str(mcfg.get("sweep_order", "jacobi")),
                  relaxation=float(mcfg.get("relaxation", 0.3)),
                  momentum=float(mcfg.get("momentum", 0.85)))
    model, state0 = puppy_model(cfg)
    steps = int(round(1.0 / rate / float(mcfg["dt"])))
    if abs(steps * float(mcfg["dt"]) * rate - 1.0) > 1e-9:
        raise ValueError(f"ch5.model.dt={mcfg['dt']} does not divide the sample period "
                         f"1/{rate} s")
    key = (mcfg["dt"], mcfg["solver_iterations"], mcfg["skin_ratio"], *solver.values(),
           json.dumps(cfg["terrains"]["F"], sort_keys=True))
    _MODELS[key] = model
    table = trial_table(cfg, seeding.rng(root_seed, experiment + "/trials"))
    n_dev = min(jax.device_count(), int(rec["batch"]))
    batch = max(n_dev, int(rec["batch"]) // n_dev * n_dev)
    chunk = int(round(float(rec["chunk_seconds"]) * rate))
    jitter = float(cfg["jitter"])
    order = np.argsort([-t["length"] for t in table], kind="stable")
    per_trial: dict[int, np.ndarray] = {}
    t0 = time.perf_counter()
    robot_seconds = 0.0
    for b0 in range(0, len(order), batch):
        idx = order[b0:b0 + batch]
        pad = np.concatenate([idx, np.repeat(idx[-1:], batch - len(idx))])
        rngs = [seeding.rng(root_seed, experiment + "/trial", int(i)) for i in pad]
        mats, cmds, heads, offs = [], [], [], []
        n_max = max(table[i]["length"] for i in idx)
        n_chunks = -(-n_max // chunk)
        for i, r in zip(pad, rngs):
            tr = table[i]
            base = cfg["terrains"][tr["terrain"]]
            mats.append([base[k] * (1.0 + r.uniform(-jitter, jitter)) for k in _MATERIAL_KEYS])
            c = np.zeros((n_chunks * chunk, 4))
            c[:tr["length"]] = G.commands(tr["gait"], tr["frequency"], tr["length"], rate,
                                          cfg["gaits"], r)
            cmds.append(c)
            heads.append(r.uniform(-np.pi, np.pi))
            offs.append(r.uniform(-1.0, 1.0, 2) * float(rec["initial_spread"]))
        fn = _chunk_fn(key, chunk, steps, n_dev)
        states = _initial_states(state0, np.array(heads), np.array(offs))
        mats = jnp.asarray(np.array(mats), state0.pos.dtype)
        cmds = np.array(cmds)
        raws = []
        for k in range(n_chunks):
            states, raw = fn(mats, states, jnp.asarray(cmds[:, k * chunk:(k + 1) * chunk],
                                                       state0.pos.dtype))
            raws.append({n: np.asarray(v, np.float64) for n, v in raw.items()})
        robot_seconds += batch * n_chunks * chunk / rate
        raw_all = {n: np.concatenate([r[n] for r in raws], axis=1) for n in raws[0]}
        for j, i in enumerate(idx):
            L = table[i]["length"]
            one = {n: v[j, :L] for n, v in raw_all.items()}
            bad = [n for n, v in one.items() if not np.all(np.isfinite(v))]
            if bad:
                first = min(int(np.argmax(~np.isfinite(one[n]).reshape(L, -1).all(1)))
                            for n in bad)
                raise SimulationDiverged(experiment, int(i), first * steps,
                                         f"trial {i} ({table[i]['gait']}, terrain "
                                         f"{table[i]['terrain']}, {table[i]['frequency']} Hz): "
                                         + ", ".join(bad))
            sig = signals_from_raw(one, cmds[j, :L], cfg, rngs[j], rate)
            fell = np.flatnonzero(one["rot"][:, 2, 2] < float(rec["fallen_up"]))
            if fell.size:  # the experimenter stops the trial when the robot turns over
                sig = sig[:max(int(fell[0]), 1)]
            per_trial[int(i)] = sig
        if log is not None:
            log.info("ch5 recordings: %d/%d trials, %.0f s", min(b0 + batch, len(order)),
                     len(order), time.perf_counter() - t0)
    wall = time.perf_counter() - t0
    lengths = np.array([len(per_trial[i]) for i in range(len(table))], int)
    planned = np.array([t["length"] for t in table], int)
    offset = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    recs = Recordings(
        signals=np.concatenate([per_trial[i] for i in range(len(table))]).astype(np.float32),
        offset=offset, length=lengths,
        terrain=np.array([TERRAINS.index(t["terrain"]) for t in table], int),
        gait=np.array([G.GAITS.index(t["gait"]) for t in table], int),
        frequency=np.array([t["frequency"] for t in table], float),
        names=S.NAMES)
    info = dict(wall_seconds=wall, robot_seconds=robot_seconds,
                robot_seconds_per_wall_second=robot_seconds / max(wall, 1e-9),
                planned_length=planned.tolist(),
                stopped_trials=np.flatnonzero(lengths < planned).tolist())
    return recs, info


# ------------------------------------------------------------------ file
def write(path, recs: Recordings, attrs: dict) -> None:
    """Write ``recs`` to HDF5 ``path`` (not atomic: pass a temporary path)."""
    import h5py

    with h5py.File(path, "w") as f:
        f.create_dataset("signals", data=recs.signals, compression="gzip",
                         compression_opts=4, shuffle=True)
        for name in ("offset", "length", "terrain", "gait", "frequency"):
            f.create_dataset(name, data=getattr(recs, name))
        f.attrs["names"] = json.dumps(list(recs.names))
        f.attrs["terrains"] = json.dumps(list(TERRAINS))
        f.attrs["gaits"] = json.dumps(list(G.GAITS))
        for k, v in attrs.items():
            f.attrs[k] = json.dumps(v) if isinstance(v, (dict, list, tuple)) else v


def load(path) -> Recordings:
    """Read and check recordings; every problem raises :class:`RecordingError` naming the
    file (and the trial where one is at fault)."""
    import h5py

    path = Path(path)
    if not path.exists():
        raise RecordingError(f"{path}: no such recordings file (run the ch5 "
                             "puppy_recordings rule)")
    try:
        with h5py.File(path, "r") as f:
            data = {k: np.asarray(f[k]) for k in ("signals", "offset", "length", "terrain",
                                                  "gait", "frequency")}
            names = tuple(json.loads(f.attrs["names"]))
            config_json = str(f.attrs.get("config_json", "{}"))
            stopped = tuple(json.loads(f.attrs.get("stopped_trials", "[]")))
    except (OSError, KeyError, ValueError) as err:
        raise RecordingError(f"{path}: not a valid recordings file ({err})") from err
    sig = data["signals"]
    if names != S.NAMES or sig.ndim != 2 or sig.shape[1] != len(S.NAMES):
        raise RecordingError(f"{path}: signals have shape {sig.shape} and "
                             f"{len(names)} names; expected {len(S.NAMES)} signals "
                             "named as thesis.ch5.sensors.NAMES")
    n = data["length"].size
    for k in ("offset", "terrain", "gait", "frequency"):
        if data[k].shape != (n,):
            raise RecordingError(f"{path}: {k} has shape {data[k].shape}, expected ({n},)")
    for i in range(n):
        a, L = int(data["offset"][i]), int(data["length"][i])
        if L <= 0 or a < 0 or a + L > sig.shape[0]:
            raise RecordingError(f"{path}: trial {i} spans samples [{a}, {a + L}) outside "
                                 f"the {sig.shape[0]} recorded")
        if not (0 <= data["terrain"][i] < len(TERRAINS) and 0 <= data["gait"][i] < len(G.GAITS)):
            raise RecordingError(f"{path}: trial {i} has an unknown terrain or gait index")
        bad = ~np.isfinite(sig[a:a + L])
        if bad.any():
            row, col = np.argwhere(bad)[0]
            raise RecordingError(f"{path}: trial {i} has a non-finite value in signal "
                                 f"{names[col]!r} at sample {row}")
    return Recordings(signals=sig, offset=data["offset"].astype(np.int64),
                      length=data["length"].astype(int), terrain=data["terrain"].astype(int),
                      gait=data["gait"].astype(int), frequency=data["frequency"].astype(float),
                      names=names, path=str(path), config_json=config_json,
                      stopped_trials=stopped)
