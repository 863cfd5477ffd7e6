"""puppy_contact.py (thesis bench puppy-contact): the Puppy II's paw contact per terrain
against the sourced contact values."""

import copy
import logging
from types import SimpleNamespace

import numpy as np
import pytest

from thesis import config, registry, store
from thesis.modelcheck import puppy_contact as PC
from thesis.physics.models import puppy as P


def _ctx(**bench):
    full = copy.deepcopy(config.load_config("smoke"))
    full["physics"]["puppy_contact"].update(bench)
    return SimpleNamespace(full_config=full, key="model/puppy_contact",
                           log=logging.getLogger("test"), root_seed=int(full["root_seed"]))


def test_puppy_contact_is_registered_with_its_config():
    assert registry.BENCHMARKS["puppy-contact"] == "model/puppy_contact"
    assert registry.resolve("model/puppy_contact") is PC.puppy_contact
    cfg = config.load_config("default")["physics"]["puppy_contact"]
    # every gait and frequency of Tab. 5.1 by default
    from thesis.ch5.recordings import FREQUENCIES, TAB5_1
    cells = {(g, f) for (g, _), counts in TAB5_1.items()
             for f, n in zip(FREQUENCIES, counts) if n}
    assert {(g["gait"], g["frequency"]) for g in cfg["gaits"]} == cells
    assert cfg["tolerance"] == 0.25 and cfg["terrains"] is None


def test_check_widens_the_sourced_range_by_the_tolerance_and_names_missing_sources():
    got = PC.check([0.7, 0.8, 1.26, 1.24, 5.0, 0.1, np.nan], [1.0, 1.0, np.nan, np.nan, 1.0,
                                                              np.nan, 1.0],
                   [1.0, 1.0, 1.0, 1.0, np.nan, np.nan, 2.0], 0.25)
    assert got.tolist() == ["fail", "pass", "fail", "pass", "pass", "no source", "fail"]


def test_sourced_touchdown_times_follow_the_quarter_period_of_the_sources():
    """docs/sources.md §5.3: 8.6-25 kN/m under m / 4 ring at 24-41 Hz, peaking 10-6 ms
    after touchdown; a stiffer contact peaks sooner."""
    src = PC.sourced_ranges(["F", "S", "C"], P.MASS)
    lo, hi = src["time_to_peak"][0]
    assert lo == pytest.approx(6.1, abs=0.05) and hi == pytest.approx(10.4, abs=0.05)
    assert np.allclose(src["rise_time"][0], src["time_to_peak"][0] * 0.649, atol=1e-3)
    assert np.isnan(src["time_to_peak"][1, 1]) and np.isnan(src["indentation"][2]).all()
    assert src["stiffness"][2].tolist()[1] == 25.0


def test_touchdown_reads_the_first_peak_and_its_rise_from_a_step_series():
    dt = 0.005
    # released 1 mm above the floor, falling 0.5 mm per step: touches at half the
    # second step; force 0, 0, 2, 8, 10, 6 N
    depth = np.array([-0.5, 0.0, 0.5, 1.0, 1.2, 1.1]) * 1e-3
    force = np.array([0.0, 0.0, 2.0, 8.0, 10.0, 6.0])
    peak, to_peak, rise, t_touch, steps = PC.touchdown(force, depth, dt, 0.05, -1e-3)
    assert t_touch == pytest.approx(2 * dt)
    assert peak == 10.0 and to_peak == pytest.approx(3 * dt) and steps == 3
    # 10 % (1 N) at half of step 3's rise, 90 % (9 N) half-way from 8 to 10 N
    assert rise == pytest.approx((4.5 - 2.5) * dt)
    # a jump to the peak within one step: 0.8 dt, flagged by its single step
    jump = PC.touchdown(np.array([0.0, 0.0, 10.0, 4.0]), depth[:4], dt, 0.05, -1e-3)
    assert jump[2] == pytest.approx(0.8 * dt) and jump[4] == 1
    assert np.isnan(PC.touchdown(force * 0, depth - 1.0, dt, 0.05, -1.0)[0])


@pytest.fixture(scope="module")
def tiny():
    """The bench on foil (the stiffest contact, 14.7 kN/m) and Styrofoam (4.1 kN/m), one
    short bound."""
    return PC.puppy_contact(_ctx(terrains=["F", "S"],
                                 gaits=[{"gait": "bound_right", "frequency": 1.0}],
                                 settle=1.0, average=0.25, warmup=1.0, gait_seconds=1.0))


def test_bench_layout_units_and_physics_on_two_terrains(tiny):
    """The layout and units, the weight carried by the paws at rest within 1 %, the foam
    indenting more than the foil, by the ratio of their stiffnesses (a contact in N/m
    sinks F / k whatever the paw's mass)."""
    ds = tiny
    store.check_result(ds)  # units and long names on every variable
    assert list(ds["terrain"].values) == ["F", "S"]
    assert list(ds["paw"].values) == list(P.LEGS)
    assert ds.sizes == {"terrain": 2, "paw": 4, "gait": 1, "bound": 2}
    units = {"indentation": "mm", "normal_force": "N", "implied_stiffness": "kN/m",
             "rise_time": "ms", "time_to_peak": "ms", "off_ground_share": "1",
             "knee_stance_range": "rad", "indentation_source": "mm"}
    for name, unit in units.items():
        assert ds[name].attrs["units"] == unit, name
    assert ds["off_ground_share"].dims == ("terrain", "gait", "paw")
    assert ds["indentation_source"].attrs["source"] == "docs/sources.md#ch5-terrain-contact"
    weight = P.MASS * 9.81
    total = ds["normal_force"].sum("paw")
    assert np.allclose(total, weight, rtol=0.01), total.values
    assert np.allclose(ds["total_normal_force"], weight, rtol=0.01)
    d = ds["indentation"]
    assert (d > 0).all()
    assert float(d.sel(terrain="S").min()) > float(d.sel(terrain="F").max())
    k = ds["implied_stiffness"]
    assert np.allclose(k, ds["normal_force"] / d)
    assert float(k.sel(terrain="S").max()) < float(k.sel(terrain="F").min())
    rise, peak = ds["rise_time"], ds["time_to_peak"]
    assert np.isfinite(rise).all() and (rise > 0).all() and (rise <= peak).all()
    ter = config.load_config("smoke")["ch5"]["terrains"]
    ratio = float(d.sel(terrain="S").mean()) / float(d.sel(terrain="F").mean())
    assert ratio == pytest.approx(ter["F"]["stiffness"] / ter["S"]["stiffness"], rel=0.05)
    off = ds["off_ground_share"]
    assert ((off >= 0) & (off <= 1)).all()
    assert set(np.unique(ds["indentation_check"])) <= {"pass", "fail", "no source"}
    unresolved = ds["rise_time_check"] == "unresolved"
    assert (unresolved == (ds["rise_steps"] <= 1)).all()
    assert ds["off_ground_share"].attrs["check"].startswith("no source")
    assert not ds["turned_over"].any()


def test_report_tables_read_the_dataset_and_say_not_run_without_it(tiny):
    from thesis.report import puppy_contact as R
    from thesis.report.chapters import model as chapter

    terr, gaits = R.tables({R.KEY: tiny})
    assert [r[0] for r in terr.rows] == ["F", "S"]
    d = tiny.sel(terrain="S")
    assert terr.rows[1][1].startswith(f"{float(d['indentation'].mean()):.2f} (0.58-1.34; ")
    k = float(tiny["implied_stiffness"].sel(terrain="F").mean())
    word = "pass" if 8.6 * 0.75 <= k <= 25 * 1.25 else "fail"
    assert terr.rows[0][2] == f"{k:.2f} (8.60-25.00; {word})"
    assert [R._range(r) for r in ((np.nan, 25.0), (0.22, np.nan), (np.nan, np.nan))] == [
        "<= 25.00", ">= 0.22", "no source"]
    assert R._verdict(["pass", "fail", "pass", "pass"]) == "3 of 4 pass"
    assert gaits.rows[0][0] == "bound_right 1 Hz" and len(gaits.columns) == 5
    assert tiny.attrs["unloading"] in gaits.note
    empty = R.tables({})
    assert all(t.rows[0][0] == "not run" for t in empty)
    assert {"puppy_contact", "puppy_contact_gaits"} <= {t.id for t in chapter.tables({})}
