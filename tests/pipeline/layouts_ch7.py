"""Layouts of the smoke profile's chapter-7 results: dims, units, and the relations between
variables that ``thesis.claims.ch7`` and ``thesis.report.chapters.ch7`` rely on.

Checked on the datasets the smoke pipeline wrote (``tests/pipeline/test_smoke.py``), so
no experiment is run a second time for its layout; the numbers themselves are regressed
against ``tests/regression/smoke``. Every check takes the dataset and the smoke profile's
resolved configuration, and derives what it expects from that configuration.
"""

from __future__ import annotations

import numpy as np
import pytest

from thesis.ch7 import bench_engine as be
from thesis.ch7 import trot


def has(ds, dims_of):
    """Every named variable exists with these dims and a unit."""
    for var, dims in dims_of.items():
        assert var in ds, var
        assert ds[var].dims == dims, (var, ds[var].dims)
        assert ds[var].attrs["units"], var


def network_params(network: str) -> int:
    """Weights and biases of a dense network written as "in-h1-...-out"."""
    sizes = [int(x) for x in network.split("-")]
    return sum(a * b + b for a, b in zip(sizes[:-1], sizes[1:]))


def table7_1(ds, cfg):
    b = cfg["physics"]["bench"]
    dims = ("device", "batch", "n_params", "gradient")
    has(ds, {v: dims for v in ("seconds", "compile_seconds", "ms_per_robot_step",
                               "peak_memory_bytes", "gradient_finite", "gradient_norm")})
    assert ds["batch"].values.tolist() == b["batches"]
    assert ds["gradient"].values.tolist() == [0, 1]
    # the controllers of eq. 7.3: sensors and memory in, servo targets and memory out
    n_in = _quad_sensor_count()
    want = [be.count_params(be.controller_sizes(n_in, 8, 8, list(h)))
            for h in b["hidden_layers"]]
    assert ds["n_params"].values.tolist() == want
    assert np.all(ds["seconds"].values > 0)
    assert np.all(np.isnan(ds["gradient_norm"].sel(gradient=0).values))
    assert set(np.unique(ds["gradient_finite"].sel(gradient=1).values)) <= {0.0, 1.0}
    # ms per robot-step = seconds per 10 simulated seconds, back to the simulated
    # horizon, over batch x steps
    n_steps = ds.attrs["n_steps"]
    horizon = ds["seconds"] * ds.attrs["simulated_seconds"] / 10.0
    per = 1e3 * horizon / (ds["batch"] * n_steps)
    np.testing.assert_allclose(ds["ms_per_robot_step"].transpose(*dims).values,
                               per.transpose(*dims).values, rtol=1e-6)
    assert ds.attrs["simulated_seconds"] == pytest.approx(b["simulated_seconds"], rel=1e-6)


def _quad_sensor_count() -> int:
    """Length of the quadruped's controller sensor vector (eq. 7.3), from its shape alone
    (traced, not run: the sensors' eager ops would dispatch one by one)."""
    import jax

    from thesis.physics import sensors

    model, state = be.quadruped()
    out = jax.eval_shape(lambda s: be.sensor_vector(model, sensors(model, s)), state)
    return int(out.shape[0])


def ball(ds, cfg):
    c = cfg["ch7"]["ball"]
    has(ds, {"iterations": ("method", "seed"), "wall_seconds": ("method", "seed"),
             "final_position_error": ("method", "seed"),
             "final_velocity_error": ("method", "seed"),
             "gradient_loss": ("seed", "gd_iteration"),
             "cmaes_loss": ("seed", "cmaes_evaluation")})
    assert ds["method"].values.tolist() == ["gradient", "cmaes"]
    assert ds["seed"].values.tolist() == c["seeds"]
    assert ds["wall_seconds"].attrs["units"] == "s"
    assert ds["final_position_error"].attrs["units"] == "m"
    # iterations are counted only for converged runs, NaN otherwise
    converged = ds["converged"].values.astype(bool)
    assert np.array_equal(np.isnan(ds["iterations"].values), ~converged)
    assert ds.sizes["gd_iteration"] <= c["gradient"]["max_iterations"]
    assert np.isfinite(ds["gradient_loss"].isel(gd_iteration=0)).all()
    assert np.isfinite(ds["cmaes_loss"].isel(cmaes_evaluation=0)).all()


def arm_fixed(ds, cfg):
    c = cfg["ch7"]["arm_fixed"]
    has(ds, {"evaluations_to_4cm": ("method", "seed"), "evaluations_to_1cm": ("method", "seed"),
             "reached_4cm": ("method", "seed"), "error": ("method", "seed", "evaluation"),
             "distance": ("seed", "evaluation"),
             "best_error": ("method", "seed", "evaluation")})
    assert ds["error"].attrs["units"] == "m"
    assert ds.attrs["network"].split("-")[1:-1] == [str(h) for h in c["hidden"]]
    assert ds.attrs["n_params"] == network_params(ds.attrs["network"])
    assert np.isfinite(ds["error"].sel({"method": "gradient"}).values[:, 0]).all()
    # the best error so far never increases
    best = ds["best_error"].values
    assert np.all(np.diff(best, axis=-1)[np.isfinite(np.diff(best, axis=-1))] <= 1e-12)


def arm_random(ds, cfg):
    c = cfg["ch7"]["arm_random"]
    has(ds, {"updates_to_10cm": ("seed",), "updates_to_5cm": ("seed",),
             "distance": ("seed", "update"),
             "test_error": ("seed", "check"), "train_objective": ("seed", "update")})
    assert ds.attrs["batch"] == c["batch"]
    assert ds.attrs["network"].split("-")[1:-1] == [str(h) for h in c["hidden"]]
    assert ds.attrs["n_params"] == network_params(ds.attrs["network"])
    assert ds.sizes["update"] == c["updates"]


def quadruped_gait(ds, cfg):
    c = cfg["ch7"]["gait"]
    has(ds, {"speed": ("seed", "evaluation"), "final_speed": ("seed",),
             "frames": ("frame", "row", "col", "channel")})
    assert ds["speed"].attrs["units"] == "m/s"
    # zero-output initial policy: the first evaluation is the standing robot
    assert np.all(np.abs(ds["speed"].values[:, 0]) < 0.05)
    width, height = c["frame_pixels"]
    assert ds["frames"].shape == (c["frames"], height, width, 3)
    assert ds["frames"].values.max() > 0
    # the hand-tuned trot search: every configuration of the grid, every parameter kept
    both = ("trot_torque", "trot")
    has(ds, {"trot_speed": both, "trot_upright": both, "trot_is_trot": both,
             "trot_hip_amplitude": ("trot",), "trot_knee_offset": ("trot",),
             "hand_tuned_speed_by_torque": ("trot_torque",)})
    grid = c["trot"]
    assert ds.sizes["trot"] == len(trot.grid(grid)) and ds["hand_tuned_speed"].attrs["units"] == "m/s"
    # the gait's own torque and the sweep's, ascending
    gait_torque = float(c["servo_torque"])
    torques = sorted({gait_torque, *map(float, grid["servo_torques"])})
    assert ds["trot_torque"].values.tolist() == torques
    assert sorted(set(ds["trot_hip_amplitude"].values)) == sorted(grid["hip_amplitude"])
    at_gait = ds.sel(trot_torque=gait_torque)
    up = at_gait["trot_is_trot"].values == 1
    assert int(ds["hand_tuned_upright"]) == up.sum()
    if up.any():
        assert float(ds["hand_tuned_speed"]) == at_gait["trot_speed"].values[up].max()
    else:
        assert np.isnan(float(ds["hand_tuned_speed"]))


def pendulum_pixels(ds, cfg):
    c = cfg["ch7"]["pendulum"]
    has(ds, {"episodes_to_up": ("seed",), "stays_up_s": ("seed",), "loss": ("seed", "episode"),
             "success": ("seed", "episode"),
             "frames": ("frame", "row", "col", "channel")})
    width, height = c["pixels"]
    assert ds["frames"].shape == (c["frames"], height, width, 3)
    assert np.asarray(ds.attrs["pixels"]).tolist() == [width, height]
    assert ds.sizes["episode"] == c["episodes"]
    assert ds.attrs["n_params"] > 0


CHECKS = {"ch7/table7_1": table7_1, "ch7/ball": ball, "ch7/arm_fixed": arm_fixed,
          "ch7/arm_random": arm_random, "ch7/quadruped_gait": quadruped_gait,
          "ch7/pendulum_pixels": pendulum_pixels}
