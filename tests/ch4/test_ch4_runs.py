"""One condition of chapter 4's protocol end to end at a tiny size: the flat source run,
the transfer run with softer front legs, the safety-thread comparison and the derived
artifacts, with the layouts thesis.claims.ch4 reads; a NaN, in a generation or a
re-evaluation, stops a run with its condition, seed and generation and nothing is
written."""

from __future__ import annotations

import logging

import jax
import numpy as np
import pytest
import xarray as xr

from thesis import cli
from thesis.config import load_config
from thesis.errors import SimulationDiverged
from thesis.gaits import conditions as C
from thesis.gaits import runner as R
from thesis.ch4 import transfer_artifacts as TA
from thesis.ch4 import transfer_runs as TR
from thesis.optim import pso
from thesis.runctx import RunContext
from thesis.store import check_result

pytestmark = pytest.mark.slow

TINY = {"ch4": {
    "seeds": [0, 1, 2],
    "protocol": {"settle": 0.1, "transition_seconds": 0.1, "run_seconds": 0.3},
    "pso": {"particles": 2, "generations": 2},
    "reeval": {"repeats": 2},
    "fig4_6": {"top": 3},
    "fig4_3": {"random_examples": 1, "samples": 12},
}}


@pytest.fixture(scope="module", autouse=True)
def standard_promotion():
    """The gait commands run under standard promotion (see tests/gaits/conftest.py)."""
    with jax.numpy_dtype_promotion("standard"), jax.numpy_rank_promotion("allow"):
        yield


@pytest.fixture(scope="module")
def tiny(tmp_path_factory, standard_promotion):
    cfg = load_config("smoke", overrides=TINY)
    tmp = tmp_path_factory.mktemp("ch4")

    def ctx(key, inputs=None):
        return RunContext(key=key, profile="smoke", config=cfg["ch4"], full_config=cfg,
                          inputs=inputs or {}, output=tmp / "x.nc",
                          log=logging.getLogger("test"))

    flat = TR.flat(ctx("ch4/flat"))
    path = tmp / "flat.nc"
    flat.to_netcdf(path, engine="h5netcdf")
    soft = TR.transfer_compliant(ctx("ch4/transfer_compliant", {"flat": path}))
    soft_path = tmp / "transfer_compliant.nc"
    soft.to_netcdf(soft_path, engine="h5netcdf")
    return cfg, ctx, flat, soft, {"flat": path, "transfer_compliant": soft_path}


def test_flat_run_keeps_every_particle(tiny):
    cfg, _, flat, _, _ = tiny
    check_result(flat)
    assert flat["position"].dims == ("seed", "generation", "particle", "parameter")
    assert flat["position"].shape == (3, 2, 2, 12)
    assert list(flat["parameter"].values)[:6] == ["f", "a", "x0", "y0f", "y0r", "t_stance"]
    sc, sp, fl = flat["score"].values, flat["speed"].values, flat["fallen"].values
    np.testing.assert_allclose(sc[fl == 0], sp[fl == 0])
    assert np.all(sc[fl == 1] < -1.0)
    assert flat["reeval_speed"].shape == (3, 2)
    assert float(flat["simulated_robot_seconds"]) == pytest.approx(
        (3 * 2 * 2 + 3 * 2) * 0.5, rel=1e-6)
    assert flat["robot_seconds_per_wall_second"].attrs["measurement"] == "wall_clock"
    # the evaluated particles respect Tab. 4.1's dependent ranges
    x = flat["position"].values.reshape(-1, 12)
    np.testing.assert_allclose(TR.FAMILY.project(x), x, atol=1e-9)
    # the assistant's resets (departure ch4.fall_reset), counted per generation; the run's
    # first particle entered from its own gait and is never set back
    assert flat["reset_count"].dims == ("seed", "generation")
    np.testing.assert_array_equal(flat["reset_count"], flat["reset"].sum("particle"))
    assert set(np.unique(flat["reset"].values)) <= {0.0, 1.0}
    np.testing.assert_array_equal(flat["reset"].values[:, 0, 0], 0.0)


def test_transfer_starts_at_the_flat_runs_best_particles(tiny):
    _, _, flat, soft, _ = tiny
    check_result(soft)
    P = soft.sizes["particle"]
    imp = soft["impulse"].values
    for s in soft["seed"].values:
        best = pso.best_particles(flat["position"].sel(seed=s).values,
                                  flat["score"].sel(seed=s).values, P)
        first = soft["position"].sel(seed=s, condition="compliant", transfer=1, generation=0)
        np.testing.assert_allclose(first.values, best, atol=1e-9)
        v_tl = soft["velocity0"].sel(seed=s, condition="compliant", transfer=1).values
        assert np.all(np.abs(v_tl) <= imp + 1e-12)
        v_rand = soft["velocity0"].sel(seed=s, condition="compliant", transfer=0).values
        assert np.abs(v_rand).max() > 10 * imp.max()  # random swarms get full-range velocities
    assert soft["reeval_speed"].dims == ("seed", "condition", "transfer", "rank", "repeat")
    assert soft["reset_count"].dims == ("seed", "condition", "transfer", "generation")
    np.testing.assert_array_equal(soft["reset_count"], soft["reset"].sum("particle"))
    gen = soft["best_generation"].sel(rank=2).values
    assert np.all(gen >= 1)  # rank 2: the best after the first generation


def test_tether_comparison(tiny):
    _, ctx, flat, _, inputs = tiny
    ds = TR.tether(ctx("ch4/tether", {"flat": inputs["flat"]}))
    check_result(ds)
    assert ds["fall_fraction"].dims == ("seed", "tether", "generation")
    assert ds["reset_count"].dims == ("seed", "tether", "generation")
    np.testing.assert_array_equal(ds["reset"].sel(tether=1).values, flat["reset"].values)
    np.testing.assert_array_equal(ds["fallen"].sel(tether=1).values, flat["fallen"].values)
    assert set(np.unique(ds["fallen"].values)) <= {0.0, 1.0}
    # the thread's load: the flat run's with it, exactly none without it
    np.testing.assert_array_equal(ds["taut"].sel(tether=1).values, flat["taut"].values)
    np.testing.assert_array_equal(ds["thread_force"].sel(tether=0).values, 0.0)
    assert ds["thread_force"].attrs["units"] == "N"
    assert np.all((flat["taut"].values >= 0) & (flat["taut"].values <= 1))
    assert np.all(flat["reeval_thread_force"].values >= 0)


def test_derived_artifacts_layouts(tiny):
    _, ctx, flat, soft, inputs = tiny
    t = TA.table4_3(ctx("ch4/table4_3", inputs))
    check_result(t)
    assert t["score"].dims == ("seed", "stiffness", "transfer")
    assert float(t["euclidean_distance"].sel(stiffness="normal", transfer=0).max()) == 0.0
    assert np.isnan(t["score"].sel(stiffness="normal", transfer=1)).all()
    assert t.attrs["generations"] == 2 and t.attrs["particles"] == 2
    f = TA.fig4_7(ctx("ch4/fig4_7", {"transfer_compliant": inputs["transfer_compliant"]}))
    check_result(f)
    assert f["score"].dims == ("seed", "transfer", "generation", "particle")
    assert f["p_greater"].dims == ("seed", "generation")
    assert np.all((f["a12"].values >= 0) & (f["a12"].values <= 1))
    np.testing.assert_array_equal(f["reset_count"].values, soft["reset_count"].sel(
        condition="compliant").transpose("seed", "transfer", "generation").values)
    ss = TA.fig4_10(ctx("ch4/fig4_10", {"transfer_compliant": inputs["transfer_compliant"]}))
    check_result(ss)
    assert list(ss["condition"].values) == ["compliant"]
    assert np.all(ss["search_space_size"].values > 0)
    loci = TA.fig4_3(ctx("ch4/fig4_3", {"flat": inputs["flat"]}))
    check_result(loci)
    assert list(loci["example"].values) == ["random_1", "optimised"]
    r = np.hypot(loci["x"].values, loci["y"].values)  # hip-foot distance [mm]
    # within each leg's reach: fore 100-167 mm, hind ~90-182 mm (leg_geometry)
    fore, hind = r[:, :, 0], r[:, :, 1]  # dims (seed, example, foot, sample)
    assert np.all((fore > 99.9) & (fore < 167.1))
    assert np.all((hind > 89.5) & (hind < 182.1))
    assert np.all(loci["x"].values > 0)  # below the hip


def test_nan_stops_with_condition_seed_and_generation_and_writes_nothing(tiny, monkeypatch,
                                                                         tmp_path):
    cfg = tiny[0]
    real = C.condition_model

    def broken(c, name):
        model, state = real(c, name)
        return model.replace(gravity=model.gravity * np.float32(np.nan)), state

    monkeypatch.setattr(C, "condition_model", broken)
    out = tmp_path / "flat.nc"
    with pytest.raises(SimulationDiverged) as err:
        cli.run_experiment("ch4/flat", "smoke", output=out, overrides=TINY)
    assert err.value.experiment == "ch4/flat:flat" and err.value.step == 0
    assert err.value.seed in cfg["ch4"]["seeds"]
    assert not out.exists()
    assert not list(tmp_path.iterdir())


def test_a_non_finite_re_evaluation_stops_with_its_run_seed_and_step(tiny, monkeypatch):
    """The best particles' re-evaluations stop the run like a generation does: the last
    re-evaluated row is the random arm's (transfer=0) rank-2 best of the last seed."""
    cfg, ctx, _, _, inputs = tiny
    real = TR.evaluate_particles

    def last_reeval_diverges(model, state, c, p_from, p_to, **kw):
        terms = real(model, state, c, p_from, p_to, **kw)
        if p_from is p_to:  # a re-evaluation from standstill in the particle's own pose
            terms["finite"] = terms["finite"].copy()
            terms["finite"][len(p_to) - 1] = False
        return terms

    monkeypatch.setattr(TR, "evaluate_particles", last_reeval_diverges)
    with pytest.raises(SimulationDiverged, match="particle 11, repeat 1") as err:
        TR.transfer_compliant(ctx("ch4/transfer_compliant", {"flat": inputs["flat"]}))
    assert err.value.experiment == "ch4/transfer_compliant:compliant/transfer=0/reeval"
    assert err.value.seed == cfg["ch4"]["seeds"][-1]
    assert err.value.step == TINY["ch4"]["pso"]["generations"]


def test_corrupt_flat_input_is_named(tiny, tmp_path):
    _, ctx, _, _, _ = tiny
    bad = tmp_path / "flat.nc"
    bad.write_text("not a netcdf file")
    with pytest.raises(ValueError, match="flat"):
        TA.fig4_3(ctx("ch4/fig4_3", {"flat": bad}))
    xr.Dataset({"x": ("seed", [0.0])}, coords={"seed": [7]}).to_netcdf(
        tmp_path / "other.nc", engine="h5netcdf")
    with pytest.raises(ValueError, match="lacks seeds"):
        TR.transfer_compliant(ctx("ch4/transfer_compliant", {"flat": tmp_path / "other.nc"}))


def test_pebbles_end_to_end_and_the_field_is_touched(tiny, tmp_path):
    """The pebbly condition at a tiny size: both arms, every particle, Tab. 4.4 and
    Fig. 4.8; and the pebbles carry the robot (the same standing gait stands higher on
    the strip than on the bare floor, by different amounts at different starts)."""
    cfg, ctx, _, _, inputs = tiny
    peb = TR.transfer_pebbly(ctx("ch4/transfer_pebbly", {"flat": inputs["flat"]}))
    check_result(peb)
    assert list(peb["condition"].values) == ["pebbly"]
    assert peb["score"].shape == (3, 1, 2, 2, 2)
    assert np.isfinite(peb["speed"].values).all()
    assert peb.attrs["pebble_count"] > 1000
    path = tmp_path / "transfer_pebbly.nc"
    peb.to_netcdf(path, engine="h5netcdf")
    t44 = TA.table4_4(ctx("ch4/table4_4", {"flat": inputs["flat"], "transfer_pebbly": path}))
    assert set(t44["terrain"].values) == {"normal", "pebbly"}
    assert np.isfinite(t44["speed"].sel(terrain="pebbly").values).all()
    f48 = TA.fig4_8(ctx("ch4/fig4_8", {"transfer_pebbly": path}))
    check_result(f48)
    assert f48["p_greater"].dims == ("seed", "generation")
    assert f48["fisher_two_sided"].dims == ("seed",)

    c = ctx("x").config
    flat_m, s0 = C.condition_model(c, "flat")
    peb_m, s1 = C.condition_model(c, "pebbly", 0)
    lo, hi = C.start_range(c, "pebbly", 0.4)
    fw = np.linspace(lo, hi, 3)
    p = np.tile(0.5 * (TR.FAMILY.lower + TR.FAMILY.upper), (3, 1)).astype(np.float32)
    fn = R.gait_command_fn(TR.FAMILY, 0.1, 0.1)
    z = []
    for m, s in ((flat_m, s0), (peb_m, s1)):
        sim = R.simulate(m, s, fn, dict(p_from=p, p_to=p), 0.4, chunk=None, forward=fw)
        z.append(sim["pos"][:, -10:, R.O.trunk_index(m), 2].mean(axis=1))
        # set down among the pebbles, no robot is thrown up (trunk within 3 cm of its start)
        assert not R.exploded(m, sim).any()
        assert sim["pos"][:, :, R.O.trunk_index(m), 2].max() < float(s.pos[0, 2]) + 0.03
    assert np.ptp(z[0]) < 1e-4  # the bare floor is the same everywhere
    assert (z[1] - z[0]).max() > 1e-3  # standing on pebbles lifts the trunk
    assert np.ptp(z[1]) > 1e-4  # and by how much depends on where it stands
