"""Tab. 7.1: computing speed of the engine on the quadruped under a closed-loop controller.

Thesis §7.3.1 / Tab. 7.1: the quadruped (17 bodies, 8 servos) is simulated for 10 s by a
batch of 1 or 128 robots, each driven by a neural controller of 1,296 or 1,147,904
parameters, with and without the gradient of the distance travelled in those 10 s with
respect to all controller parameters (BPTT through all steps). We time the same grid.

Controller (the thesis gives only the two parameter counts and "81 sensors" plus the
recurrent memory h^t of Fig. 7.2 / eq. 7.3; this is our documented reading). The unique
bias-free dense networks that read 81 values and write 16 are

* ``81 -> 16``              = 81 * 16                       = 1,296 parameters;
* ``81 -> 1024 -> 1024 -> 16`` = 81*1024 + 1024*1024 + 1024*16 = 1,147,904 parameters.

16 outputs for an 8-servo robot are read as 8 servo targets [rad] plus an 8-unit memory
h^t (tanh), fed back as 8 of the 81 inputs (eq. 7.3: ``u^t, h^{t+1} = g(s^t, h^t | W)``).
The other 73 inputs are the robot's sensors (:func:`sensor_vector`): 8 joint angles and
8 joint velocities (encoders), an IMU (3 attitude + 3 gyro channels, body frame) on each
of the 9 articulated bodies (torso, 4 thighs, 4 shanks) and the torso's velocity in its
own frame (odometry). Hidden layers are ReLU; all weights orthogonal (hidden gain
sqrt 2, output gain ``output_gain``), so the robot moves and its contacts change.

The IMU's three non-gyro channels (``imu``): ``"attitude"`` (default) reads the world's up
axis in the body frame (``sensors()["imu_up"]``, what an IMU's attitude filter reports);
``"accelerometer"`` reads the specific force, which the engine differentiates from the
velocity change of the last step. Why attitude: the original engine has no accelerometer
(its sensors are positions, velocities and orientations, docs/sources.md#tpx-sensors), and the
finite-difference reading makes the exact gradient of Tab. 7.1 meaningless: its
derivative w.r.t. velocity is ~1/dt, and through the controller and the servos it closes
a loop whose tangent grows ~x1.3 per step, so the 10-s gradient overflows float32
(batch 1, 1,296 parameters, output gain 0.1: norm 9e4 after 50 steps,
1e34 after 400, NaN from 700 on; with the accelerometer's gradient cut, 8e3 after 1,000).
The second loop is the joint velocities: a servo below its torque limit turns a target
change into a joint rate change of ``servo gain`` (50 s^-1) times as much, so an output
gain above 1 / 50 also diverges in the tangent space (attitude IMU, output gain 0.1:
norm 9e23 after 600 steps, NaN from 850 on) while the forward pass stays bounded only
because the servos saturate. ``grid_dataset`` records whether every gradient is finite.

What is timed (medians of ``repeats`` runs after compilation, ``block_until_ready``):
``forward`` = the rollout returning each robot's travelled distance (torso x at the end
minus at the start); ``gradient`` = that plus d(sum of distances)/d(all parameters)
(``jax.value_and_grad`` through ``lax.scan``; per-step gradient decay ``grad_decay``,
no clipping: the raw Jacobian of the thesis). Compilation (``jit(...).lower().compile()``)
is timed separately. A batch divisible by the number of XLA devices of the platform is
split over them with ``jax.shard_map`` (one core per host device,
docs/architecture.md#both-cores).
Peak memory is XLA's buffer assignment of the compiled program
(``compiled.memory_analysis()``: arguments + outputs + temporaries - aliased bytes),
per device times the devices used; it excludes the Python process and XLA's code.
"""

from __future__ import annotations

import math
import os
import statistics
import time

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec as P

from thesis.physics.solver_settings import with_solver
from thesis.store import WALL_CLOCK

__all__ = [
    "IMU_READINGS", "controller_sizes", "count_params", "init_controller", "apply_controller",
    "sensor_bodies", "sensor_vector", "make_controller", "quadruped", "initial_states",
    "distance_fn", "build_bench_fn", "time_compiled", "grad_stats", "platforms",
    "grid_dataset", "table7_1",
]

_RELU_GAIN = math.sqrt(2.0)


# ---------------------------------------------------------------- controller ----------
def controller_sizes(n_sensors: int, n_servo: int, n_memory: int, hidden) -> list[int]:
    """Layer widths ``[n_sensors + n_memory, *hidden, n_servo + n_memory]``."""
    return [n_sensors + n_memory, *[int(h) for h in hidden], n_servo + n_memory]


def count_params(sizes) -> int:
    """Number of weights of a bias-free dense network with layer widths ``sizes``."""
    return int(sum(a * b for a, b in zip(sizes[:-1], sizes[1:])))


def init_controller(key, sizes, *, output_gain: float = 0.1, dtype=jnp.float32) -> list:
    """Bias-free dense network: a list of (n_out, n_in) weight matrices.

    Hidden layers orthogonal with ReLU gain sqrt(2); the output layer orthogonal with
    ``output_gain``. ``key`` is a JAX PRNG key. Each matrix is drawn as (n_in, n_out) and
    stored transposed: a single robot's
    step is a matrix-vector product, and XLA's CPU GEMV over contiguous rows (``W @ x``)
    beats ``x @ W`` by about a third on the 1024 x 1024 layer (1 000 products of the
    1,147,904-weight network: 0.09-0.11 s against 0.13-0.15 s).
    """
    keys = jax.random.split(key, len(sizes) - 1)
    last = len(sizes) - 2
    return [jax.nn.initializers.orthogonal(output_gain if i == last else _RELU_GAIN)(
        k, (a, b), dtype).T
        for i, (k, a, b) in enumerate(zip(keys, sizes[:-1], sizes[1:]))]


def apply_controller(weights, x):
    """ReLU hidden layers, linear output: (n_in,) -> (n_out,); weights are (n_out, n_in)."""
    for w in weights[:-1]:
        x = jax.nn.relu(w @ x)
    return weights[-1] @ x


def sensor_bodies(model) -> np.ndarray:
    """Bodies carrying an IMU: the root (no parent joint) and every servo-driven body.

    For the quadruped: torso, 4 thighs, 4 shanks (9). Raises if the model has no
    unique root body.
    """
    roots = sorted(set(range(model.n_body)) - set(int(b) for b in model.joint_body2))
    if len(roots) != 1:
        raise ValueError(f"expected one root body, found {len(roots)}: {roots}")
    driven = [int(model.joint_body2[model.dof_joint[d]]) for d in model.servo_dof]
    return np.asarray([roots[0], *driven], dtype=np.int32)


IMU_READINGS = {"attitude": "imu_up", "accelerometer": "imu_acc"}


def sensor_vector(model, sens: dict, imu: str = "attitude"):
    """The controller's sensor inputs (thesis §7.3.1), shape (2 n_servo + 6 n_imu + 3,).

    ``[joint angles of the servoed coordinates (rad), their velocities (rad/s),
    IMU reading of every IMU body in its frame (``imu="attitude"``: world up axis [1];
    ``"accelerometer"``: specific force [m/s^2]), their angular velocities (rad/s),
    torso linear velocity in the torso frame (m/s)]``; 73 values for the quadruped.
    """
    if imu not in IMU_READINGS:
        raise ValueError(f"imu must be one of {sorted(IMU_READINGS)}, got {imu!r}")
    d = model.servo_dof
    bodies = sensor_bodies(model)
    root = int(bodies[0])
    v_root = sens["body_rot"][root].T @ sens["body_vel"][root]
    return jnp.concatenate([sens["joint_angle"][d], sens["joint_velocity"][d],
                            sens[IMU_READINGS[imu]][bodies].reshape(-1),
                            sens["imu_gyro"][bodies].reshape(-1), v_root])


def make_controller(model, n_memory: int, imu: str = "attitude"):
    """Closed-loop controller for :func:`thesis.physics.rollout` (Fig. 7.2, eq. 7.3).

    ``(weights, sensors, memory (n_memory,), t) -> (servo targets (n_servo,) [rad],
    new memory)``; ``imu`` picks the IMU reading of :func:`sensor_vector`.
    """
    n_servo = model.n_servo

    def controller(weights, sens, memory, t):
        y = apply_controller(weights, jnp.concatenate([sensor_vector(model, sens, imu),
                                                       memory]))
        return y[:n_servo], jnp.tanh(y[n_servo:n_servo + n_memory])

    return controller


# ---------------------------------------------------------------- model + states ------
def quadruped(dtype=jnp.float32):
    """The engine's quadruped of Tab. 7.1 (``thesis.physics.models.quadruped``)."""
    from thesis.physics.models import quadruped as build

    return build(dtype=dtype)


def initial_states(state0, batch: int, key, velocity_std: float):
    """``batch`` copies of ``state0`` (leading axis), each robot given its own horizontal
    velocity (all bodies alike, so the joints stay consistent) ~ N(0, velocity_std^2)
    in x and y [m/s]: the robots of a batch follow different trajectories."""
    dv = velocity_std * jax.random.normal(key, (batch, 1, 3), state0.vel.dtype)
    dv = dv.at[..., 2].set(0.0)
    states = jax.tree.map(lambda x: jnp.broadcast_to(x, (batch, *x.shape)), state0)
    return states.replace(vel=states.vel + dv, prev_vel=states.prev_vel + dv)


def distance_fn(model, controller, n_steps: int, n_memory: int, *, grad_decay: float,
                remat: bool, warm_start_grad: float = 1.0):
    """``f(weights, state0) -> distance travelled by the torso along x`` [m] (one robot)."""
    from thesis.physics import rollout

    root = int(sensor_bodies(model)[0])

    def f(weights, state0):
        mem0 = jnp.zeros((n_memory,), state0.pos.dtype)
        final, _ = rollout(model, state0, controller, weights, n_steps, memory0=mem0,
                           grad_decay=grad_decay, warm_start_grad=warm_start_grad,
                           remat=remat, record=())
        return final.pos[root, 0] - state0.pos[root, 0]

    return f


def build_bench_fn(dist_one, devices, batch: int, gradient: bool):
    """A function ``(weights, states) -> distances (batch,)`` or ``(distances, grads)``,
    with its input shardings. Splits the batch over ``devices`` when it divides evenly."""
    n_dev = len(devices) if batch % len(devices) == 0 else 1
    mesh = Mesh(np.asarray(devices[:n_dev]), ("batch",))
    per_batch = jax.vmap(dist_one, in_axes=(None, 0))
    if n_dev > 1:
        # check_vma=False: carries created inside the rollout (the zero memory) are not
        # marked device-varying; the gradient of the replicated weights is still summed
        # over devices (tests/ch7/test_bench.py checks it against the unsplit vmap)
        per_batch = jax.shard_map(per_batch, mesh=mesh, in_specs=(P(), P("batch")),
                                  out_specs=P("batch"), check_vma=False)
    if gradient:
        def fn(w, s):
            (_, d), g = jax.value_and_grad(lambda w_: (lambda d_: (jnp.sum(d_), d_))(
                per_batch(w_, s)), has_aux=True)(w)
            return d, g
    else:
        fn = per_batch
    return fn, NamedSharding(mesh, P()), NamedSharding(mesh, P("batch")), n_dev


def time_compiled(fn, args, repeats: int, shardings=None):
    """Compile ``fn`` for ``args`` and run it ``repeats`` times.

    Returns ``(compile_seconds, [run seconds], last output, peak memory bytes per
    device or nan)``; each run is ``block_until_ready``'d.
    """
    t0 = time.perf_counter()
    jitted = jax.jit(fn) if shardings is None else jax.jit(fn, in_shardings=shardings)
    compiled = jitted.lower(*args).compile()
    compile_s = time.perf_counter() - t0
    mem = float("nan")
    try:
        ma = compiled.memory_analysis()
        mem = float(ma.argument_size_in_bytes + ma.output_size_in_bytes
                    + ma.temp_size_in_bytes - ma.alias_size_in_bytes)
    except Exception:  # noqa: BLE001 - not every backend reports it
        pass
    runs, out = [], None
    for _ in range(max(1, int(repeats))):
        t0 = time.perf_counter()
        out = jax.block_until_ready(compiled(*args))
        runs.append(time.perf_counter() - t0)
    return compile_s, runs, out, mem


def grad_stats(grads) -> tuple[float, float]:
    """(1.0 if every gradient entry is finite else 0.0, global L2 norm in float64)."""
    leaves = [np.asarray(x, np.float64) for x in jax.tree.leaves(grads)]
    finite = all(bool(np.all(np.isfinite(x))) for x in leaves)
    with np.errstate(over="ignore", invalid="ignore"):
        norm = float(np.sqrt(sum(float(np.sum(x * x)) for x in leaves)))
    return float(finite), norm


def platforms(want_gpu: bool) -> list[tuple[str, list]]:
    """``[("cpu", cpu devices), ("gpu", gpu devices)?]`` as JAX sees them."""
    out = [("cpu", jax.devices("cpu"))]
    if want_gpu:
        try:
            gpus = jax.devices("gpu")
        except RuntimeError:
            gpus = []
        if gpus:
            out.append(("gpu", gpus))
    return out


# ---------------------------------------------------------------- dataset -------------
_VARS = {  # name: (units, long_name)
    "seconds": ("s", "computing time per 10 simulated seconds of the whole batch (median "
                     "over repeats after compilation; measured over simulated_seconds and "
                     "scaled by 10 s / simulated_seconds)"),
    "compile_seconds": ("s", "time to trace and compile the rollout (jit lower + compile)"),
    "ms_per_robot_step": ("ms", "computing time per time step per robot"),
    "peak_memory_bytes": ("B", "XLA buffer assignment of the compiled program (arguments + "
                               "outputs + temporaries - aliased), summed over devices used"),
    "gradient_finite": ("1", "1 if every entry of the gradient is finite, 0 if not, "
                             "NaN without gradient"),
    "gradient_norm": ("1", "global L2 norm of d(sum of distances)/d(parameters) [m per "
                           "parameter unit], NaN without gradient"),
    "distance_finite": ("1", "1 if every robot's travelled distance is finite"),
    "n_devices": ("1", "XLA devices the batch was split over"),
}


#: the variables of ``_VARS`` measured by the wall clock (or by the memory in use)
_WALL = ("seconds", "compile_seconds", "ms_per_robot_step", "peak_memory_bytes")


def grid_dataset(run_cell, plats, batches, sizes, n_steps: int, dt: float):
    """Run ``run_cell(devices, batch, sizes, gradient) -> dict`` over the whole grid.

    Returns an ``xarray.Dataset`` with dims ``device`` (platform: cpu, gpu), ``batch``,
    ``n_params``, ``gradient`` (0, 1) and the variables of ``_VARS`` plus ``device_name``.
    ``seconds`` is normalised to 10 simulated seconds (``n_steps * dt``).
    """
    import xarray as xr

    n_params = [count_params(s) for s in sizes]
    shape = (len(plats), len(batches), len(sizes), 2)
    data = {k: np.full(shape, np.nan) for k in _VARS}
    scale = 10.0 / (n_steps * dt)
    for i, (_, devs) in enumerate(plats):
        for j, batch in enumerate(batches):
            for k, size in enumerate(sizes):
                for g in (0, 1):
                    cell = run_cell(devs, int(batch), size, bool(g))
                    cell["seconds"] = cell["seconds"] * scale
                    cell["ms_per_robot_step"] = 1e3 * cell["seconds"] / scale / (
                        int(batch) * n_steps)
                    for name in _VARS:
                        data[name][i, j, k, g] = cell.get(name, np.nan)
    dims = ("device", "batch", "n_params", "gradient")
    ds = xr.Dataset(
        {k: (dims, data[k], {"units": u, "long_name": ln,
                             **(WALL_CLOCK if k in _WALL else {})})
         for k, (u, ln) in _VARS.items()},
        coords={"device": [p for p, _ in plats], "batch": [int(b) for b in batches],
                "n_params": n_params, "gradient": [0, 1]})
    ds["device_name"] = ("device", [str(d[0].device_kind) for _, d in plats],
                         {"units": "1", "long_name": "device kind as reported by JAX"})
    return ds


# ---------------------------------------------------------------- experiment ----------
def table7_1(ctx):
    """``thesis bench physics``: Tab. 7.1 on the engine (see module docstring).

    Reads ``physics.bench`` of the profile (its ``solver``: the quadruped's sweep order
    and factors, {} = the model's own). Returns a dataset with dims ``device``,
    ``batch``, ``n_params``, ``gradient`` (0 = forward only, 1 = with gradient).
    """
    cfg = ctx.full_config["physics"]["bench"]
    model, state0 = quadruped()
    # null settings keep the model's own (its Jacobi sweeps of chapter 7)
    model = with_solver(model, {k: v for k, v in cfg.get("solver", {}).items() if v is not None})
    dt = float(model.dt)
    n_steps = int(round(cfg["simulated_seconds"] / dt))
    n_mem = int(cfg["memory_units"])
    imu = str(cfg["imu"])
    controller = make_controller(model, n_mem, imu)
    n_sensors = int(sensor_vector(model, _sensors0(model, state0), imu).shape[0])
    sizes = [controller_sizes(n_sensors, model.n_servo, n_mem, h) for h in cfg["hidden_layers"]]
    key = _key(ctx)
    k_w, k_s = jax.random.split(key)
    # batches > 1 run vmapped with the batched solver variant (Model.batched)
    dist = {b: distance_fn(model.replace(batched=b), controller, n_steps, n_mem,
                           grad_decay=float(cfg["grad_decay"]), remat=bool(cfg["remat"]),
                           warm_start_grad=float(cfg["warm_start_grad"]))
            for b in (False, True)}

    def run_cell(devices, batch, size, gradient):
        fn, rep, shard, n_dev = build_bench_fn(dist[batch > 1], devices, batch, gradient)
        with jax.default_device(devices[0]):
            weights = init_controller(k_w, size, output_gain=float(cfg["output_gain"]))
            states = initial_states(state0, batch, k_s, float(cfg["initial_velocity_std"]))
        weights = jax.device_put(weights, rep)
        states = jax.device_put(states, shard)
        ctx.log.info("table7_1: %s batch %d, %d params, gradient %d on %d device(s)",
                     devices[0].platform, batch, count_params(size), gradient, n_dev)
        comp, runs, out, mem = time_compiled(fn, (weights, states), cfg["repeats"])
        dists = np.asarray(out[0] if gradient else out)
        fin, norm = grad_stats(out[1]) if gradient else (float("nan"), float("nan"))
        ctx.log.info("table7_1:   -> runs %s s, compile %.1f s, grad finite %s, norm %.3g",
                     [round(r, 3) for r in runs], comp, fin, norm)
        return dict(seconds=statistics.median(runs), compile_seconds=comp,
                    peak_memory_bytes=mem * n_dev, gradient_finite=fin, gradient_norm=norm,
                    distance_finite=float(np.all(np.isfinite(dists))), n_devices=n_dev)

    ds = grid_dataset(run_cell, platforms(bool(cfg["gpu"])), cfg["batches"], sizes,
                      n_steps, dt)
    ds.attrs.update(
        thesis_ref="Tab. 7.1", seeds=[0], model=model.name, dt=dt, n_steps=n_steps,
        simulated_seconds=n_steps * dt, solver_iterations=int(model.solver_iterations),
        grad_decay=float(cfg["grad_decay"]), warm_start_grad=float(cfg["warm_start_grad"]),
        grad_clip="none (raw Jacobian, no clipping)",
        remat=int(bool(cfg["remat"])), repeats=int(cfg["repeats"]),
        controller="bias-free MLP, inputs = sensors + memory, ReLU hidden, outputs = "
                   "servo targets + tanh memory",
        controller_layers=[str(s) for s in sizes], n_sensors=n_sensors, memory_units=n_mem,
        imu=imu, output_gain=float(cfg["output_gain"]),
        peak_memory_source="jax compiled.memory_analysis(): argument+output+temp-alias "
                           "bytes per device x devices used",
        loss="sum over the batch of the torso's x displacement after n_steps [m]",
        solver_variant="batch 1: scatter-add of impulses; batch > 1: vmapped, the solver's "
                       "robots-last vmap rule (Model.batched)",
        xla_flags=os.environ.get("XLA_FLAGS", ""),
    )
    return ds


def _sensors0(model, state0):
    from thesis.physics import sensors

    return sensors(model, state0)


def _key(ctx):
    from thesis.seeding import key

    return key(ctx.root_seed, ctx.key, 0)
