"""Tab. 7.1 peers: the same quadruped and controllers in MuJoCo MJX (and MuJoCo C).

``thesis bench mjx`` -> ``results/<profile>/ch7/table7_1_peers.nc``. The robot is the
MJCF written from our engine's quadruped (:mod:`thesis.ch7.quadruped_mjcf`), the
controllers are the bias-free MLPs of :mod:`thesis.ch7.bench_engine` (same sizes,
same 73 sensor channels -- here MuJoCo's ``jointpos``/``jointvel``/``framezaxis`` (or
``accelerometer``, config ``imu``)/``gyro``/``velocimeter`` sensors -- plus the 8-unit
memory), the servo targets go
through the engine's servo law (:func:`quadruped_mjcf.servo_ctrl`) into velocity
actuators. The timed quantity is the same: the torso's x displacement after
``simulated_seconds`` for a batch, forward only and with the gradient w.r.t. all
controller parameters (``jax.value_and_grad`` through ``lax.scan`` of ``mjx.step``).
Gradient cells run MJX's solver for one iteration (``mjx_solver_iterations``: more
iterations are a ``while_loop``, which reverse mode cannot differentiate); forward cells
for ``mjx_forward_solver_iterations``. A cell whose rollout or gradient is not finite is
recorded as such (``distance_finite``, ``gradient_finite``) and the report leaves it out
of every comparison.

Engines (dim ``engine``): ``mjx`` (JAX, float32, batch split over host devices like
ours) and ``mujoco_c`` (forward only: the closed loop steps all robots one step at a
time with ``mujoco.rollout.Rollout`` on a thread pool of ``jax.device_count()``
threads, the MLP in numpy float32 between steps). MuJoCo is the optional extra
``bench``: ``uv sync --extra bench``.
"""

from __future__ import annotations

import statistics
import time

import jax
import jax.numpy as jnp
import numpy as np

from thesis.ch7 import bench_engine as be
from thesis.ch7.quadruped_mjcf import model_to_mjcf, servo_ctrl

__all__ = ["require_mujoco", "mjx_setup", "mjx_distance_fn", "mujoco_c_forward",
           "table7_1_peers"]


def require_mujoco():
    """Import and return ``(mujoco, mujoco.mjx)``; a clear error naming the extra if absent."""
    try:
        import mujoco
        from mujoco import mjx
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise RuntimeError(
            "thesis bench mjx needs MuJoCo and MJX, the optional extra 'bench' "
            "(mujoco==3.17.0, mujoco-mjx==3.17.0): run `uv sync --locked --extra bench` "
            f"(import failed: {e})") from e
    return mujoco, mjx


def mjx_setup(model, state0, cfg):
    """``(mj_model, servo constants dict)`` of the engine model written as MJCF."""
    mujoco, _ = require_mujoco()
    xml = model_to_mjcf(model, state0, imu_bodies=be.sensor_bodies(model), imu=str(cfg["imu"]),
                        servo_kv=float(cfg["mjx_servo_kv"]),
                        solver_iterations=int(cfg["mjx_solver_iterations"]),
                        ls_iterations=int(cfg["mjx_ls_iterations"]))
    mm = mujoco.MjModel.from_xml_string(xml)
    joints = [model.joint_names[int(model.dof_joint[int(d)])] for d in model.servo_dof]
    qadr = np.asarray([mm.jnt_qposadr[mujoco.mj_name2id(mm, mujoco.mjtObj.mjOBJ_JOINT, j)]
                       for j in joints], np.int32)
    servo = {k: np.asarray(getattr(model, f"servo_{k}"), np.float32) for k in
             ("gain", "max_velocity", "lo", "hi", "deadband")}
    servo["kind"] = np.asarray(model.servo_kind, np.int32)
    servo["qadr"] = qadr
    return mm, servo


def _ctrl(servo, q, y):
    return servo_ctrl(q, y, servo["gain"], servo["max_velocity"], servo["lo"], servo["hi"],
                      servo["deadband"], servo["kind"])


def mjx_distance_fn(mm, servo, n_servo: int, n_memory: int, n_steps: int, *, remat: bool):
    """``f(weights, qvel0 (nv,)) -> torso x displacement`` [m] of one MJX rollout."""
    _, mjx = require_mujoco()
    mx = mjx.put_model(mm)
    d0 = mjx.forward(mx, mjx.make_data(mx))
    qadr = servo["qadr"]

    def f(weights, qvel0):
        d = mjx.forward(mx, d0.replace(qvel=qvel0))

        def body(carry, _):
            d, mem = carry
            y = be.apply_controller(weights, jnp.concatenate([d.sensordata, mem]))
            d = mjx.step(mx, d.replace(ctrl=_ctrl(servo, d.qpos[qadr], y[:n_servo])))
            return (d, jnp.tanh(y[n_servo:n_servo + n_memory])), None

        if remat:
            body = jax.checkpoint(body)
        (dt_, _), _ = jax.lax.scan(body, (d, jnp.zeros((n_memory,), jnp.float32)), None,
                                   length=n_steps)
        return dt_.qpos[0] - d0.qpos[0]

    return f


def mujoco_c_forward(mm, servo, weights, qvel0, n_servo, n_memory, n_steps, nthread):
    """Closed-loop MuJoCo C rollouts of a batch; returns (seconds, distances (B,))."""
    mujoco, _ = require_mujoco()
    from mujoco import rollout

    w = [np.asarray(x, np.float32).T for x in weights]  # (n_in, n_out) for a row batch
    batch = qvel0.shape[0]
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    datas = [mujoco.MjData(mm) for _ in range(max(1, nthread))]
    d = datas[0]
    states, sens = [], []
    for b in range(batch):
        mujoco.mj_resetData(mm, d)
        d.qvel[:] = qvel0[b]
        mujoco.mj_forward(mm, d)
        st = np.empty(mujoco.mj_stateSize(mm, spec))
        mujoco.mj_getState(mm, d, st, spec)
        states.append(st)
        sens.append(d.sensordata.copy())
    state, sensordata = np.stack(states), np.stack(sens).astype(np.float32)
    x0 = state[:, 1 + 0].copy()  # state = [time, qpos, ...]: qpos[0] is torso x
    mem = np.zeros((batch, n_memory), np.float32)
    t0 = time.perf_counter()
    with rollout.Rollout(nthread=nthread if batch > 1 else 0) as r:
        for _ in range(n_steps):
            x = np.concatenate([sensordata, mem], axis=1)
            for k in w[:-1]:
                x = np.maximum(x @ k, 0.0)
            y = x @ w[-1]
            mem = np.tanh(y[:, n_servo:n_servo + n_memory])
            q = state[:, 1 + servo["qadr"]].astype(np.float32)
            ctrl = _ctrl(servo, q, y[:, :n_servo])
            st, sd = r.rollout(mm, datas, state, ctrl[:, None, :].astype(np.float64),
                               nstep=1)
            state, sensordata = st[:, -1], sd[:, -1].astype(np.float32)
    seconds = time.perf_counter() - t0
    return seconds, state[:, 1] - x0


def table7_1_peers(ctx):
    """``thesis bench mjx``: Tab. 7.1's grid in MJX (and MuJoCo C forward).

    Dims ``engine`` (mjx, mujoco_c), ``device``, ``batch``, ``n_params``, ``gradient``;
    variables as ``ch7/table7_1`` (``seconds`` per 10 simulated seconds, ...).
    """
    import xarray as xr

    mujoco, _ = require_mujoco()
    cfg = ctx.full_config["physics"]["bench"]
    model, state0 = be.quadruped()
    dt = float(model.dt)
    n_steps = int(round(cfg["simulated_seconds"] / dt))
    n_mem, n_servo = int(cfg["memory_units"]), model.n_servo
    mm, servo = mjx_setup(model, state0, cfg)
    mm_fwd, _ = mjx_setup(model, state0, dict(
        cfg, mjx_solver_iterations=int(cfg["mjx_forward_solver_iterations"])))
    n_sensors = int(mm.nsensordata)
    sizes = [be.controller_sizes(n_sensors, n_servo, n_mem, h) for h in cfg["hidden_layers"]]
    k_w, k_s = jax.random.split(be._key(ctx))
    # gradient cells: the differentiable single solver iteration; forward cells: MJX's
    # iterated solver (while_loop, no reverse mode), which keeps this robot finite
    dist_fns = {True: mjx_distance_fn(mm, servo, n_servo, n_mem, n_steps,
                                      remat=bool(cfg["remat"])),
                False: mjx_distance_fn(mm_fwd, servo, n_servo, n_mem, n_steps,
                                       remat=bool(cfg["remat"]))}

    def qvel_batch(batch):
        dv = float(cfg["initial_velocity_std"]) * jax.random.normal(k_s, (batch, 1, 3))
        q = np.zeros((batch, mm.nv), np.float32)
        q[:, :2] = np.asarray(dv)[:, 0, :2]
        return q

    def run_mjx(devices, batch, size, gradient):
        fn, rep, shard, n_dev = be.build_bench_fn(dist_fns[bool(gradient)], devices, batch,
                                                  gradient)
        with jax.default_device(devices[0]):
            weights = be.init_controller(k_w, size, output_gain=float(cfg["output_gain"]))
        weights = jax.device_put(weights, rep)
        qv = jax.device_put(jnp.asarray(qvel_batch(batch)), shard)
        ctx.log.info("table7_1_peers: mjx %s batch %d, %d params, gradient %d",
                     devices[0].platform, batch, be.count_params(size), gradient)
        comp, runs, out, mem = be.time_compiled(fn, (weights, qv), cfg["repeats"])
        dists = np.asarray(out[0] if gradient else out)
        fin, norm = be.grad_stats(out[1]) if gradient else (np.nan, np.nan)
        ctx.log.info("table7_1_peers:   -> runs %s s, compile %.1f s, grad finite %s, norm %.3g",
                     [round(r, 3) for r in runs], comp, fin, norm)
        return dict(seconds=statistics.median(runs), compile_seconds=comp,
                    peak_memory_bytes=mem * n_dev, gradient_finite=fin, gradient_norm=norm,
                    distance_finite=float(np.all(np.isfinite(dists))), n_devices=n_dev)

    mm_c, _ = mjx_setup(model, state0, dict(
        cfg, mjx_solver_iterations=int(cfg["mujoco_c_solver_iterations"])))

    def run_c(devices, batch, size, gradient):
        if gradient:
            return dict(seconds=np.nan)
        weights = be.init_controller(k_w, size, output_gain=float(cfg["output_gain"]))
        nthread = min(jax.device_count("cpu"), batch)
        runs, dists = [], None
        for _ in range(int(cfg["repeats"])):
            s, dists = mujoco_c_forward(mm_c, servo, weights, qvel_batch(batch), n_servo,
                                        n_mem, n_steps, nthread)
            runs.append(s)
        return dict(seconds=statistics.median(runs), compile_seconds=0.0,
                    distance_finite=float(np.all(np.isfinite(dists))), n_devices=nthread)

    plats = be.platforms(bool(cfg["gpu"]))
    parts = [be.grid_dataset(run_mjx, plats, cfg["batches"], sizes, n_steps, dt)]
    engines = ["mjx"]
    if cfg["mujoco_c"]:
        parts.append(be.grid_dataset(run_c, plats[:1], cfg["batches"], sizes, n_steps, dt))
        engines.append("mujoco_c")
    ds = xr.concat(parts, dim=xr.DataArray(engines, dims="engine", name="engine"),
                   join="outer")
    ds["engine"].attrs.update(units="1", long_name="peer engine")
    ds.attrs.update(
        thesis_ref="Tab. 7.1 (peers on the same machine)", seeds=[0], model=model.name, dt=dt,
        n_steps=n_steps, simulated_seconds=n_steps * dt, repeats=int(cfg["repeats"]),
        mujoco_version=mujoco.__version__, mjx_solver_iterations=int(cfg["mjx_solver_iterations"]),
        mjx_forward_solver_iterations=int(cfg["mjx_forward_solver_iterations"]),
        mjx_ls_iterations=int(cfg["mjx_ls_iterations"]), servo_kv=float(cfg["mjx_servo_kv"]),
        integrator="implicitfast", grad_decay=1.0, grad_clip="none (raw Jacobian)",
        imu=str(cfg["imu"]), output_gain=float(cfg["output_gain"]),
        remat=int(bool(cfg["remat"])), controller_layers=[str(s) for s in sizes],
        mujoco_c_solver_iterations=int(cfg["mujoco_c_solver_iterations"]),
        mujoco_c="forward only, closed loop stepped by mujoco.rollout.Rollout one step at a "
                 "time on a thread pool, MLP in numpy; compile_seconds 0",
        loss="sum over the batch of the torso's x displacement after n_steps [m]",
    )
    return ds
