"""A tiny run of every ch3 experiment returns the layout thesis.claims.ch3 documents."""

import logging

import jax
import numpy as np
import pytest

from thesis.config import load_config
from thesis.gaits import experiments as E
from thesis.runctx import RunContext
from thesis.store import check_result

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module", autouse=True)
def standard_promotion():
    """thesis.gaits.leg._grid_init is not clean under the strict dtype and rank
    promotion of tests/conftest.py (int32 arange + Python float; (16,16,2) - (2,));
    the gait commands run under standard promotion here."""
    with jax.numpy_dtype_promotion("standard"), jax.numpy_rank_promotion("allow"):
        yield


@pytest.fixture(scope="module")
def tiny(tmp_path_factory, standard_promotion):
    over = {"ch3": {
        "seeds": [0, 1],
        "protocol": {"settle": 0.1},
        "pso": {g: {"particles": 2, "generations": 2, "run_seconds": 0.3,
                    "transition_seconds": 0.1} for g in ("sine", "half_ellipse", "spline")},
        "sweep": {"frequencies": [1.0, 2.0], "run_seconds": 0.3, "transition_seconds": 0.1},
        "robustness": {"perturbations": 2, "run_seconds": 0.3, "transition_seconds": 0.1},
        "turning": {"run_seconds": 0.6, "transition_seconds": 0.1},
        "tracking": {"run_seconds": 0.3, "transition_seconds": 0.1},
    }}
    cfg = load_config("smoke", overrides=over)
    tmp = tmp_path_factory.mktemp("ch3")

    def ctx(key, inputs=None):
        return RunContext(key=key, profile="smoke", config=cfg["ch3"], full_config=cfg,
                          inputs=inputs or {}, output=tmp / "x.nc",
                          log=logging.getLogger("test"))

    t31 = E.table3_1(ctx("ch3/table3_1"))
    path = tmp / "table3_1.nc"
    t31.to_netcdf(path, engine="h5netcdf")
    return ctx, t31, {"table3_1": path}


def test_table3_1_layout(tiny):
    _, ds, _ = tiny
    check_result(ds)
    assert list(ds["gait"].values) == ["sine", "half_ellipse", "spline"]
    assert list(ds["seed"].values) == [0, 1]
    for name in ("x0", "y0_fore", "y0_hind", "a", "b_fore", "b_hind", "t_stance_f", "f",
                 "l0_fore", "l1_fore", "l0_hind", "l1_hind", "l2", "l3"):
        assert name in ds["parameter"].values
    he = ds["value"].sel(gait="half_ellipse")
    assert np.isfinite(he.sel(parameter="a").values).all()
    assert np.isnan(he.sel(parameter="l2").values).all()
    assert ds["best_fitness"].sizes["generation"] == 2
    assert float(ds["robot_seconds_per_wall_second"]) > 0


def test_fig3_4_layout(tiny):
    ctx, _, inputs = tiny
    ds = E.fig3_4(ctx("ch3/fig3_4", inputs))
    check_result(ds)
    assert ds["speed"].dims == ("gait", "frequency", "seed")
    assert list(ds["frequency"].values) == [1.0, 2.0]
    assert ds["speed"].attrs["units"] == "m s-1"
    assert np.isnan(ds["theoretical_speed"].sel(gait="sine")).all()
    th = ds["theoretical_speed"].sel(gait="half_ellipse").values
    assert np.all(th[1] >= th[0])  # 2 a f / duty grows with f
    assert float(ds["wall_seconds"]) > 0


def test_robustness_layout(tiny):
    ctx, _, inputs = tiny
    ds = E.robustness(ctx("ch3/robustness", inputs))
    check_result(ds)
    fr = ds["fraction_walking"]
    assert set(fr.dims) == {"gait", "seed"}
    assert ((fr >= 0) & (fr <= 1)).all()


def test_table3_2_layout(tiny):
    ctx, _, inputs = tiny
    ds = E.table3_2(ctx("ch3/table3_2", inputs))
    check_result(ds)
    assert list(ds["strategy"].values) == ["step_size", "step_speed",
                                           "step_size_constant_speed", "torque", "scapulae"]
    for v in ("speed", "angular_speed", "turning_radius", "stable"):
        assert ds[v].dims == ("strategy", "seed")
    assert set(np.unique(ds["stable"].values)) <= {0.0, 1.0}


def test_fig3_5_layout(tiny):
    ctx, _, inputs = tiny
    ds = E.fig3_5(ctx("ch3/fig3_5", inputs))
    check_result(ds)
    assert list(ds["strategy"].values) == ["step_size", "scapulae"]
    assert ds["lateral_position"].dims == ("strategy", "seed", "time")
    # starts at the configured offset from the LED line
    assert np.allclose(ds["lateral_position"].isel(time=0), 0.2, atol=0.02)
