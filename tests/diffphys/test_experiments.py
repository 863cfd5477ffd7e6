"""A 1-iteration run of every ch7 experiment on tiny sizes: dims, variables, units.

Slow (each experiment compiles its own rollout and gradient); the layouts checked here
are the ones ``thesis.claims.ch7`` and ``thesis.report.chapters.ch7`` read.
"""

import logging

import jax
import numpy as np
import pytest

from thesis.config import load_config
from thesis.runctx import RunContext
from thesis.store import check_result

pytestmark = pytest.mark.slow

TINY = {
    "ball": {"seeds": [0], "horizon_s": 0.3, "gradient": {"max_iterations": 1},
             "cmaes": {"max_evaluations": 4, "popsize": 4}},
    "arm_fixed": {"seeds": [0], "episode_s": 0.2, "eval_window_s": 0.05, "hidden": [4],
                  "evaluations": 1, "cmaes": {"evaluations": 4, "popsize": 4}},
    "arm_random": {"seeds": [0], "episode_s": 0.2, "eval_window_s": 0.05, "hidden": [4],
                   "batch": 2, "updates": 1, "test_batch": 2, "eval_every": 1},
    "gait": {"seeds": [0], "episode_s": 0.2, "hidden": [4, 4], "evaluations": 1, "frames": 2,
             "frame_pixels": [16, 12],
             "trot": {"frequency_hz": [1.5], "hip_amplitude": [0.2, 0.4], "knee_amplitude": [0.2],
                      "knee_phase": [0.0], "knee_offset": [0.0, 0.4], "max_tilt_deg": 60.0,
                      "servo_torques": [40.0]}},
    "pendulum": {"seeds": [0], "pixels": [12, 4], "episode_s": 0.1, "episodes": 1,
                 "conv_channels": [], "hidden": [4], "hold_s": 0.05, "test_s": 0.2,
                 "frames": 2},
}


def _run(key, fn_path, section):
    cfg = load_config("smoke", overrides={"ch7": {section: TINY[section]}})
    mod, name = fn_path.split(":")
    fn = getattr(__import__(mod, fromlist=[name]), name)
    ctx = RunContext(key=key, profile="smoke", config=cfg["ch7"], full_config=cfg,
                     log=logging.getLogger("test"))
    with jax.numpy_dtype_promotion("standard"):  # optax mixes int and float internally
        ds = fn(ctx)
    check_result(ds)  # thesis_ref, seeds, units and long_name everywhere
    return ds


def _has(ds, dims_of):
    for var, dims in dims_of.items():
        assert var in ds, var
        assert ds[var].dims == dims, (var, ds[var].dims)
        assert ds[var].attrs["units"]


def test_ball_dataset_layout():
    ds = _run("ch7/ball", "thesis.diffphys.ball:ball", "ball")
    _has(ds, {"iterations": ("method", "seed"), "wall_seconds": ("method", "seed"),
              "final_position_error": ("method", "seed"),
              "final_velocity_error": ("method", "seed"),
              "gradient_loss": ("seed", "gd_iteration"),
              "cmaes_loss": ("seed", "cmaes_evaluation")})
    assert list(ds["method"].values) == ["gradient", "cmaes"]
    assert ds["wall_seconds"].attrs["units"] == "s"
    assert ds["final_position_error"].attrs["units"] == "m"
    # 1 iteration and 4 candidates cannot reach 1 cm: NaN with the flag down
    assert np.all(np.isnan(ds["iterations"].values)) and not ds["converged"].values.any()
    assert ds.sizes["gd_iteration"] == 1 and ds.sizes["cmaes_evaluation"] == 4


def test_arm_fixed_dataset_layout():
    ds = _run("ch7/arm_fixed", "thesis.diffphys.arm:arm_fixed", "arm_fixed")
    _has(ds, {"evaluations_to_4cm": ("method", "seed"), "evaluations_to_1cm": ("method", "seed"),
              "reached_4cm": ("method", "seed"), "error": ("method", "seed", "evaluation"),
              "distance": ("seed", "evaluation"),
              "best_error": ("method", "seed", "evaluation")})
    assert ds["error"].attrs["units"] == "m"
    assert ds.attrs["n_params"] == 1 * 4 + 4 + 4 * 4 + 4
    assert np.isfinite(ds["error"].sel({"method": "gradient"}).values[:, 0]).all()


def test_arm_random_dataset_layout():
    ds = _run("ch7/arm_random", "thesis.diffphys.arm:arm_random", "arm_random")
    _has(ds, {"updates_to_10cm": ("seed",), "updates_to_5cm": ("seed",),
              "distance": ("seed", "update"),
              "test_error": ("seed", "check"), "train_objective": ("seed", "update")})
    assert ds.attrs["batch"] == 2 and ds.attrs["network"] == "3-4-4"


def test_gait_dataset_layout():
    ds = _run("ch7/quadruped_gait", "thesis.diffphys.gait:gait", "gait")
    _has(ds, {"speed": ("seed", "evaluation"), "final_speed": ("seed",),
              "frames": ("frame", "row", "col", "channel")})
    assert ds["speed"].attrs["units"] == "m/s"
    # zero-output initial policy: the first evaluation is the standing robot
    assert abs(float(ds["speed"].values[0, 0])) < 0.05
    assert ds["frames"].shape == (2, 12, 16, 3) and ds["frames"].values.max() > 0
    # the hand-tuned trot search: 2 x 2 configurations, every parameter recorded
    both = ("trot_torque", "trot")
    _has(ds, {"trot_speed": both, "trot_upright": both, "trot_is_trot": both,
              "trot_hip_amplitude": ("trot",), "trot_knee_offset": ("trot",),
              "hand_tuned_speed_by_torque": ("trot_torque",)})
    assert ds.sizes["trot"] == 4 and ds["hand_tuned_speed"].attrs["units"] == "m/s"
    assert ds["trot_torque"].values.tolist() == [4.0, 40.0]  # the gait's 4 N m and the sweep
    assert sorted(set(ds["trot_hip_amplitude"].values)) == [0.2, 0.4]
    at_gait = ds.sel(trot_torque=4.0)
    up = at_gait["trot_is_trot"].values == 1
    assert up.any()  # a 0.2-s episode cannot turn the robot over
    assert float(ds["hand_tuned_speed"]) == at_gait["trot_speed"].values[up].max()
    assert int(ds["hand_tuned_upright"]) == up.sum()


def test_pendulum_dataset_layout():
    ds = _run("ch7/pendulum_pixels", "thesis.diffphys.pendulum:pendulum", "pendulum")
    _has(ds, {"episodes_to_up": ("seed",), "stays_up_s": ("seed",), "loss": ("seed", "episode"),
              "success": ("seed", "episode"),
              "frames": ("frame", "row", "col", "channel")})
    assert ds["frames"].shape == (2, 4, 12, 3)
    assert np.asarray(ds.attrs["pixels"]).tolist() == [12, 4]
