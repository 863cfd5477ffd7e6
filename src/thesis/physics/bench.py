"""``thesis bench field``: what a static sphere field costs the simulated Oncilla.

The requirement: a field of 10,000 pebbles, each contact sphere checking its K = 2
nearest, slows the Oncilla by at most 1.3x (pebbles listed as sphere pairs would add rows
for every pebble). This benchmark measures the Oncilla's
simulated robot-seconds per wall-second on the level floor and on a pebble strip, same
robots, same open-loop gait, same batch (the ch3/ch4 rollout: ``batched_rollout`` split
over the profile's host devices, one robot at a time per device).

Workload (fixed here, not tuned to the result): the Oncilla of
:func:`thesis.physics.models.oncilla.oncilla` with its default settings, driven by an
open-loop trot of sinusoidal hip and knee commands about the build pose (1.5 Hz, hip
+-0.25 rad, knee +-0.3 rad, diagonal legs in phase), a different phase per robot so the
batch does not move in lockstep. Pebbles: ``physics.sphere_field.pebbles`` spheres of
``radius`` resting on the floor (centre z = radius), spread over lanes of
``lane_width`` centred at ``lanes`` (y) along ``strip_length`` metres of x starting
0.5 m behind the robot, at the points of a two-dimensional additive-recurrence (R2,
golden-ratio) sequence: evenly spread without a random stream, the same layout in every
profile. Conditions: ``none`` (the model every chapter used, no field), and one per
entry of ``query`` -- ``all`` (toes and trunk bumpers collide with the pebbles) and
``toes`` (only the four toe spheres do).

Timing: each condition's rollout is compiled first (compile time recorded separately)
and run once untimed, then the conditions run in turn ``repeats`` times (interleaved, so that load from other
processes falls on all of them alike) and the median wall time per condition is
reported, with ``block_until_ready``; the process's CPU time (all threads) is recorded
beside it, since on a shared machine other processes' load inflates wall times more
than the CPU time the rollout itself needs.
"""

from __future__ import annotations

import importlib
import statistics
import time

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics.rollout import batched_rollout

# the module (the models package re-exports the constructor under the same name)
oncilla_mod = importlib.import_module("thesis.physics.models.oncilla")

__all__ = ["pebble_strip", "sphere_field"]

#: The benchmark's open-loop trot: frequency [Hz], hip and knee amplitudes [rad].
GAIT = (1.5, 0.25, 0.3)


def pebble_strip(n, radius, length, lanes, lane_width, x0=-0.5):
    """(n, 3) centres of ``n`` spheres of ``radius`` [m] resting on the floor z = 0 over
    lanes of ``lane_width`` [m] centred at y = ``lanes`` [m], from x = ``x0`` over
    ``length`` [m]: the points of the R2 additive-recurrence sequence (quasi-random,
    deterministic), lane by lane in turn."""
    g = 1.32471795724474602596  # plastic number: R2 sequence constants 1/g, 1/g^2
    i = np.arange(int(n), dtype=np.float64) + 1.0
    u = np.mod(0.5 + i / g, 1.0)
    v = np.mod(0.5 + i / (g * g), 1.0)
    lanes = np.asarray(lanes, np.float64).reshape(-1)
    y = lanes[np.arange(int(n)) % lanes.size] + (v - 0.5) * lane_width
    return np.stack([x0 + u * length, y, np.full_like(u, radius)], axis=1)


def _controller(model):
    f, a_hip, a_knee = GAIT
    build = jnp.asarray(oncilla_mod.build_offsets(), jnp.float32)
    trot = jnp.asarray([0.0, 0.5, 0.5, 0.0], jnp.float32)  # LF, RF, LH, RH

    def ctrl(_, sens, phase, t):
        ph = 2.0 * jnp.pi * (f * t + trot + phase)
        joints = jnp.stack([jnp.zeros_like(ph), a_hip * jnp.sin(ph),
                            a_knee * jnp.sin(ph + 0.5 * jnp.pi)], axis=1).reshape(-1)
        cmd = oncilla_mod.commands_to_action(build + joints.astype(build.dtype))
        return cmd.astype(sens["body_pos"].dtype), phase

    return ctrl


def _rollout_fn(model, n_steps):
    ctrl = _controller(model)

    def run(states, phases):
        final, _ = batched_rollout(model, states, ctrl, None, n_steps, memory0=phases,
                                   batch_memory=True, record=())
        return final.pos[:, model.body("trunk")]

    return jax.jit(run)


def sphere_field(ctx):
    """``thesis bench field`` (registry ``physics/sphere_field``): the Oncilla's
    robot-seconds per wall-second without and with a pebble field (module docstring).

    Reads ``physics.sphere_field``. Returns a dataset with dim ``condition`` (``none``,
    then the ``query`` entries) and the rate, wall and compile times (wall-clock
    measurements), the slowdown against ``none``, the solver's scalar rows, and the
    trunk's final forward position and height (means over the batch) as a sanity record.
    Raises ``thesis.errors.SimulationDiverged`` if a rollout ends non-finite.
    """
    import xarray as xr

    cfg = ctx.full_config["physics"]["sphere_field"]
    batch, seconds = int(cfg["batch"]), float(cfg["simulated_seconds"])
    centres = pebble_strip(cfg["pebbles"], cfg["radius"], cfg["strip_length"], cfg["lanes"],
                           cfg["lane_width"])
    conditions = ["none", *cfg["query"]]
    runs, rows = {}, {}
    for cond in conditions:
        field = None if cond == "none" else dict(
            centres=centres, radii=float(cfg["radius"]), k=int(cfg["k"]), spheres=cond)
        model, state = oncilla_mod.oncilla(field=field)
        n_steps = int(round(seconds / float(model.dt)))
        states = jax.tree.map(lambda x: jnp.broadcast_to(x, (batch,) + x.shape), state)
        phases = jnp.arange(batch, dtype=jnp.float32) / batch
        fn = _rollout_fn(model, n_steps)
        t0 = time.perf_counter()
        compiled = fn.lower(states, phases).compile()
        runs[cond] = dict(fn=compiled, args=(states, phases), compile=time.perf_counter() - t0,
                          walls=[], cpus=[], steps=n_steps)
        rows[cond] = model.n_rows
        ctx.log.info("field bench: %s compiled in %.1f s (%d scalar rows)", cond,
                     runs[cond]["compile"], model.n_rows)
    for cond in conditions:  # one untimed run each: first-run allocation out of the timing
        jax.block_until_ready(runs[cond]["fn"](*runs[cond]["args"]))
    for _ in range(int(cfg["repeats"])):
        for cond in conditions:
            r = runs[cond]
            t0, c0 = time.perf_counter(), time.process_time()
            r["out"] = np.asarray(jax.block_until_ready(r["fn"](*r["args"])))
            r["walls"].append(time.perf_counter() - t0)
            r["cpus"].append(time.process_time() - c0)
    for cond in conditions:
        if not np.all(np.isfinite(runs[cond]["out"])):
            from thesis.errors import SimulationDiverged

            raise SimulationDiverged(ctx.key, 0, runs[cond]["steps"],
                                     f"final trunk position, condition {cond}")
    wall = np.array([statistics.median(runs[c]["walls"]) for c in conditions])
    cpu = np.array([statistics.median(runs[c]["cpus"]) for c in conditions])
    rate = batch * seconds / wall
    def var(values, units, name, wall_clock=False):
        attrs = dict(units=units, long_name=name)
        if wall_clock:
            attrs["measurement"] = "wall_clock"
        return ("condition", np.asarray(values), attrs)

    out = [runs[c]["out"] for c in conditions]
    ds = xr.Dataset(
        {
            "robot_seconds_per_wall_second": var(
                rate, "1", "simulated robot-seconds per wall-second", True),
            "wall_seconds": var(wall, "s", "median wall time of the timed rollouts", True),
            "compile_seconds": var([runs[c]["compile"] for c in conditions], "s",
                                   "compilation time of the rollout", True),
            "slowdown": var(rate[0] / rate, "1", "wall time relative to no field", True),
            "cpu_seconds": var(cpu, "s", "median process CPU time of the timed rollouts "
                               "(all threads; less sensitive to other processes' load)", True),
            "cpu_slowdown": var(cpu / cpu[0], "1", "CPU time relative to no field", True),
            "scalar_rows": var([rows[c] for c in conditions], "1",
                               "scalar constraint rows per robot and step"),
            "final_x": var([o[:, 0].mean() for o in out], "m",
                           "trunk's final forward position, mean over the batch"),
            "final_height": var([o[:, 2].mean() for o in out], "m",
                                "trunk's final height, mean over the batch"),
        },
        coords={"condition": conditions},
        attrs=dict(title="Static sphere field: cost on the simulated Oncilla",
                   thesis_ref="engine benchmark; §4.6 pebbles",
                   seeds=[0], layout="R2 quasi-random sequence (no random stream)",
                   pebbles=int(cfg["pebbles"]), k=int(cfg["k"]), batch=batch,
                   simulated_seconds=seconds, repeats=int(cfg["repeats"]),
                   host_devices=int(jax.device_count())))
    for cond, w in zip(conditions, wall):
        ctx.log.info("field bench: %s %.2f s -> %.1f robot-s/s", cond, w, batch * seconds / w)
    return ds
