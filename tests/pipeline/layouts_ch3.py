"""Layouts of the smoke profile's chapter-3 results (the ones ``thesis.claims.ch3``
documents), checked on the datasets the smoke pipeline wrote; see ``layouts_ch7``."""

from __future__ import annotations

import numpy as np

from thesis.store import check_result

#: Parameters of the three trot families of Tab. 3.1, in the dataset's ``parameter``.
FAMILY_PARAMETERS = ("x0", "y0_fore", "y0_hind", "a", "b_fore", "b_hind", "t_stance_f", "f",
                     "l0_fore", "l1_fore", "l0_hind", "l1_hind", "l2", "l3")


def table3_1(ds, cfg):
    c = cfg["ch3"]
    check_result(ds)
    assert list(ds["gait"].values) == ["sine", "half_ellipse", "spline"]
    assert list(ds["seed"].values) == c["seeds"]
    for name in FAMILY_PARAMETERS:
        assert name in ds["parameter"].values, name
    he = ds["value"].sel(gait="half_ellipse")
    assert np.isfinite(he.sel(parameter="a").values).all()
    assert np.isnan(he.sel(parameter="l2").values).all()  # a spline-only parameter
    assert ds["best_fitness"].sizes["generation"] == max(
        c["pso"][g]["generations"] for g in ("sine", "half_ellipse", "spline"))
    assert float(ds["robot_seconds_per_wall_second"]) > 0
    # falls per evaluation, as ch4 records them: 0/1 where a family ran, NaN beyond its
    # swarm size or generations
    fallen = ds["fallen"]
    assert fallen.dims == ("gait", "seed", "generation", "particle")
    for g in ("sine", "half_ellipse", "spline"):
        p = c["pso"][g]
        ran = fallen.sel(gait=g).values[:, :p["generations"], :p["particles"]]
        assert set(np.unique(ran)) <= {0.0, 1.0}
        assert np.isnan(fallen.sel(gait=g).values[:, p["generations"]:]).all()
        assert np.isnan(fallen.sel(gait=g).values[:, :, p["particles"]:]).all()


def fig3_4(ds, cfg):
    check_result(ds)
    assert ds["speed"].dims == ("gait", "frequency", "seed")
    assert list(ds["frequency"].values) == cfg["ch3"]["sweep"]["frequencies"]
    assert ds["speed"].attrs["units"] == "m s-1"
    assert np.isnan(ds["theoretical_speed"].sel(gait="sine")).all()
    th = ds["theoretical_speed"].sel(gait="half_ellipse").values
    assert np.all(np.diff(th, axis=0) >= 0)  # 2 a f / duty grows with f
    assert float(ds["wall_seconds"]) > 0


def robustness(ds, cfg):
    check_result(ds)
    fr = ds["fraction_walking"]
    assert set(fr.dims) == {"gait", "seed"}
    assert ((fr >= 0) & (fr <= 1)).all()


def table3_2(ds, cfg):
    check_result(ds)
    assert list(ds["strategy"].values) == ["step_size", "step_speed",
                                           "step_size_constant_speed", "torque", "scapulae"]
    for v in ("speed", "angular_speed", "turning_radius", "stable"):
        assert ds[v].dims == ("strategy", "seed")
    assert set(np.unique(ds["stable"].values)) <= {0.0, 1.0}


def fig3_5(ds, cfg):
    check_result(ds)
    assert list(ds["strategy"].values) == ["step_size", "scapulae"]
    assert ds["lateral_position"].dims == ("strategy", "seed", "time")
    # starts at the configured offset from the LED line
    offset = cfg["ch3"]["tracking"]["lateral_offset"]
    assert np.allclose(ds["lateral_position"].isel(time=0), offset, atol=0.02)


CHECKS = {f"ch3/{f.__name__}": f for f in (table3_1, fig3_4, robustness, table3_2, fig3_5)}
