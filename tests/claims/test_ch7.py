"""Chapter-7 claims decided on synthetic ball, table7_1 and learning-curve datasets."""

from __future__ import annotations

import numpy as np
import xarray as xr

from thesis import claims


def ball(grad_iters=90.0, cma_iters=2400.0, seeds: int = 5) -> xr.Dataset:
    rng = np.random.default_rng(7)
    it = np.array([grad_iters, cma_iters])[None] * (1 + 0.05 * rng.standard_normal((seeds, 2)))
    coords = {"seed": np.arange(seeds), "method": ["gradient", "cmaes"]}
    return xr.Dataset({
        "iterations": xr.DataArray(it, dims=("seed", "method"), coords=coords,
                                   attrs={"units": "1", "long_name": "iterations"}),
        "wall_seconds": xr.DataArray(it * 0.1, dims=("seed", "method"), coords=coords,
                                     attrs={"units": "s", "long_name": "wall time"}),
    })


def table7_1(grad_factor=7.0, growth=1.0, gpu=True, gpu_single=70.0, gpu_batched=1.0,
             finite=1.0, batches=(1, 128), sizes=(1296, 1147904), simulated_seconds=10.0):
    devices = ["cpu", "gpu"] if gpu else ["cpu"]
    t = np.empty((len(devices), 2, 2, 2))
    for i, dev in enumerate(devices):
        for j, batch in enumerate(batches):
            for k in range(2):
                fwd = (1.0 * batch ** 0.9) if dev == "cpu" else (
                    gpu_single if batch == 1 else gpu_batched * batch)
                fwd = fwd / (grad_factor if dev == "gpu" else 1.0)
                t[i, j, k] = [fwd, fwd * grad_factor * (growth if k else 1.0)]
    da = xr.DataArray(t, dims=("device", "batch", "n_params", "gradient"),
                      coords={"device": devices, "batch": list(batches),
                              "n_params": list(sizes), "gradient": [0, 1]},
                      attrs={"units": "s", "long_name": "seconds per 10 model seconds"})
    ok = xr.full_like(da, finite).assign_attrs(units="1", long_name="gradient finite")
    ok.loc[dict(gradient=0)] = np.nan  # no gradient taken
    return xr.Dataset({"seconds": da, "gradient_finite": ok},
                      attrs={"simulated_seconds": simulated_seconds})


def curve(dim: str, n: int, final: float, start: float, seeds: int = 3, tau: float = 30.0,
          name: str = "distance", rising: bool = False, **attrs) -> xr.Dataset:
    steps = np.arange(1, n + 1)
    c = final + (start - final) * np.exp(-steps / tau)
    c = np.tile(c, (seeds, 1)) * (1 + 0.01 * np.arange(seeds)[:, None])
    da = xr.DataArray(c, dims=("seed", dim), coords={"seed": np.arange(seeds), dim: steps},
                      attrs={"units": "m/s" if rising else "m", "long_name": name})
    return xr.Dataset({name: da}, attrs=attrs)


#: the thesis's random-target controller size, and the gait's episode and controller
ARM1_THESIS = {"n_params": 17284, "episode_s": 8.0}
ARM2_THESIS = {"n_params": 2107396, "batch": 128, "episode_s": 8.0}
GAIT_THESIS = {"episode_s": 10.0, "n_params": 17952}


def gait(final: float, n: int = 600, upright=None, seeds: int = 3, **attrs) -> xr.Dataset:
    """The BPTT gait's speed curve; ``upright``: per-seed cos of the final gait's largest
    spine tilt (``final_upright``, with the trot's 60-degree criterion), not recorded when
    None."""
    ds = curve("evaluation", n, final=final, start=0.0, tau=80.0, name="speed", rising=True,
               seeds=seeds, **{**GAIT_THESIS, **attrs})
    if upright is not None:
        ds["final_upright"] = xr.DataArray(np.asarray(upright, float), dims=("seed",),
                                           coords={"seed": ds["seed"]}, attrs={"units": "1"})
        ds.attrs["max_tilt_deg"] = 60.0
    return ds


def check(claim_id: str, **results) -> claims.Verdict:
    return claims.get(claim_id).check({f"ch7/{k}": v for k, v in results.items()})


def test_ball():
    assert check("ch7.gradient_needs_fewer_iterations", ball=ball()).status == "reproduced"
    assert check("ch7.gradient_faster_wall_clock", ball=ball()).status == "reproduced"
    v = check("ch7.gradient_needs_fewer_iterations", ball=ball(3000.0, 2400.0))
    assert v.status == "not_reproduced"
    assert check("ch7.gradient_needs_fewer_iterations", ball=ball(seeds=2)).status == (
        "inconclusive")


def test_table7_1_thesis_like():
    ds = table7_1()
    for cid in ("ch7.gradient_costs_small_factor",
                "ch7.gradient_cost_nearly_independent_of_parameters",
                "ch7.gpu_slower_for_single_robot", "ch7.batching_accelerates_gpu",
                "ch7.gpu_speeds_up_large_batches"):
        assert check(cid, table7_1=ds).status == "reproduced", cid


def test_table7_1_contradicting():
    assert check("ch7.gradient_costs_small_factor",
                 table7_1=table7_1(grad_factor=40.0)).status == "not_reproduced"
    # "roughly a factor 10" is not "any factor below 12.5": a gradient at 1.5x is not it
    v = check("ch7.gradient_costs_small_factor", table7_1=table7_1(grad_factor=1.5))
    assert v.status == "not_reproduced" and v.measured["gradient_slowdown_gmean"] < 5
    v = check("ch7.gradient_cost_nearly_independent_of_parameters",
              table7_1=table7_1(growth=3.0))
    assert v.status == "not_reproduced" and v.measured["slowdown_growth_gmean"] > 2.9
    assert check("ch7.gpu_slower_for_single_robot",
                 table7_1=table7_1(gpu_single=0.1)).status == "not_reproduced"


def test_table7_1_timings_of_a_nan_gradient_do_not_count():
    """A table whose every gradient was NaN cannot support the cost claims, however fast;
    a single finite configuration is enough to decide them."""
    for cid in ("ch7.gradient_costs_small_factor",
                "ch7.gradient_cost_nearly_independent_of_parameters"):
        v = check(cid, table7_1=table7_1(finite=0.0))
        assert v.status == "inconclusive" and "not finite" in v.detail
    ds = table7_1(grad_factor=40.0)
    ds["gradient_finite"].loc[dict(device="cpu", batch=1, n_params=1296, gradient=1)] = 0.0
    # the contradicting timings of the other configurations still decide it
    assert check("ch7.gradient_costs_small_factor", table7_1=ds).status == "not_reproduced"
    ds = table7_1(grad_factor=40.0, finite=0.0)
    ds["gradient_finite"].loc[dict(device="cpu", batch=1, n_params=1296, gradient=1)] = 1.0
    v = check("ch7.gradient_costs_small_factor", table7_1=ds)
    assert v.status == "not_reproduced" and v.measured["n_configurations"] == 1.0


def test_table7_1_needs_the_thesis_grid():
    """A smoke-sized table (4 robots, a small controller, 1 s) cannot test Tab. 7.1."""
    small = table7_1(batches=(1, 4), sizes=(1296, 10304), simulated_seconds=1.0)
    for cid in ("ch7.gradient_costs_small_factor",
                "ch7.gradient_cost_nearly_independent_of_parameters",
                "ch7.gpu_slower_for_single_robot", "ch7.batching_accelerates_gpu",
                "ch7.gpu_speeds_up_large_batches"):
        v = check(cid, table7_1=small)
        assert v.status == "inconclusive", cid
        assert "batches [1, 4] of the thesis's [1, 128]" in v.detail
        assert "1 s simulated per rollout of the thesis's 10 s" in v.detail
    bare = table7_1()
    bare.attrs = {}
    assert "not recorded" in check("ch7.gradient_costs_small_factor", table7_1=bare).detail


def test_table7_1_without_gpu():
    ds = table7_1(gpu=False)
    v = check("ch7.batching_accelerates_gpu", table7_1=ds)
    assert v.status == "not_run" and "GPU" in v.detail
    assert check("ch7.gradient_costs_small_factor", table7_1=ds).status == "reproduced"
    nan_gpu = table7_1()
    nan_gpu["seconds"].loc[{"device": "gpu"}] = np.nan
    assert check("ch7.gpu_speeds_up_large_batches", table7_1=nan_gpu).status == "not_run"


def test_arm_budgets():
    """"Learned within N evaluations" is what the method does as a rule (rule 7: a
    majority of seeds shown, which 3 seeds cannot show: 3 of 3 at a true rate of 1/2 is
    12.5 %), so the supporting runs have 6 seeds."""
    fast = curve("evaluation", 300, final=0.002, start=0.5, seeds=6, **ARM1_THESIS)
    assert check("ch7.arm_fixed_point_learned_quickly", arm_fixed=fast).status == "reproduced"
    three = curve("evaluation", 300, final=0.002, start=0.5, **ARM1_THESIS)
    v = check("ch7.arm_fixed_point_learned_quickly", arm_fixed=three)
    assert v.status == "inconclusive" and "cannot show a majority" in v.detail
    small = curve("evaluation", 300, final=0.002, start=0.5, n_params=1252, episode_s=1.0)
    v = check("ch7.arm_fixed_point_learned_quickly", arm_fixed=small)
    assert v.status == "inconclusive" and "episode_s 1 of the thesis's 8" in v.detail
    stuck = curve("evaluation", 400, final=0.05, start=0.5, seeds=8, **ARM1_THESIS)
    v = check("ch7.arm_fixed_point_learned_quickly", arm_fixed=stuck)
    assert v.status == "not_reproduced"
    short = curve("evaluation", 50, final=0.002, start=0.5, **ARM1_THESIS)
    assert check("ch7.arm_fixed_point_learned_quickly", arm_fixed=short).status == (
        "inconclusive")
    rnd = curve("update", 3000, final=0.01, start=0.5, tau=400.0, seeds=6, **ARM2_THESIS)
    assert check("ch7.scales_to_millions_of_parameters", arm_random=rnd).status == "reproduced"
    stuck = curve("update", 6000, final=0.2, start=0.5, tau=400.0, seeds=8, **ARM2_THESIS)
    assert check("ch7.scales_to_millions_of_parameters", arm_random=stuck).status == (
        "not_reproduced")


def test_scaling_claim_reads_the_parameter_count():
    """A small controller that learns says nothing about a lot of parameters."""
    small = curve("update", 3000, final=0.01, start=0.5, tau=400.0,
                  **{**ARM2_THESIS, "n_params": 9000})
    v = check("ch7.scales_to_millions_of_parameters", arm_random=small)
    assert v.status == "inconclusive" and "9,000 parameters of the thesis's 2,107,396" in (
        v.detail)
    bare = curve("update", 3000, final=0.01, start=0.5, tau=400.0)
    v = check("ch7.scales_to_millions_of_parameters", arm_random=bare)
    assert v.status == "not_run" and "n_params" in v.detail
    few = curve("update", 3000, final=0.01, start=0.5, tau=400.0, **{**ARM2_THESIS, "batch": 8})
    v = check("ch7.scales_to_millions_of_parameters", arm_random=few)
    assert v.status == "inconclusive" and "batch 8 of the thesis's 128" in v.detail


def test_quadruped_gait():
    """A run can fail (diverge, never improve), so the speed at the budget is decided on
    rule 3b: with no failure among 3 seeds up to 77 % of runs may still fail, which keeps
    1.2 m/s from showing "above 0.8775" (inconclusive); 20 seeds show it."""
    v = check("ch7.quadruped_gait_in_500_evaluations", quadruped_gait=gait(1.2))
    assert v.status == "inconclusive" and "rule 3b" in v.statistic
    assert check("ch7.quadruped_gait_in_500_evaluations",
                 quadruped_gait=gait(1.2, seeds=20)).status == "reproduced"
    # the hand-tuned 0.7 m/s is not the sentence's 1.17 m/s (less 25 %: 0.8775)
    v = check("ch7.quadruped_gait_in_500_evaluations", quadruped_gait=gait(0.75))
    assert v.status == "not_reproduced" and v.measured["bound"] == 1.17 * 0.75
    assert check("ch8.ch7_gait_in_500_evaluations",
                 quadruped_gait=gait(0.75, upright=[1.0] * 20, seeds=20)).status == (
        "reproduced")
    slow = gait(0.3)
    assert check("ch7.quadruped_gait_in_500_evaluations", quadruped_gait=slow).status == (
        "not_reproduced")
    v = check("ch8.ch7_gait_in_500_evaluations", quadruped_gait=gait(0.3, n=100))
    assert v.status == "inconclusive" and "run ended" in v.detail


def test_quadruped_gait_needs_the_thesis_episode_and_controller():
    for claim in ("ch7.quadruped_gait_in_500_evaluations", "ch8.ch7_gait_in_500_evaluations"):
        v = check(claim, quadruped_gait=gait(1.5, episode_s=1.0))
        assert v.status == "inconclusive" and "episodes of 1 s of the thesis's 10 s" in v.detail
        v = check(claim, quadruped_gait=gait(0.01, n_params=1440))
        assert v.status == "inconclusive" and "1440 parameters" in v.detail


def _trot(speeds, upright, episode_s=10.0):
    ok = np.array(upright, np.int8)
    v = np.array(speeds, float)
    best = float(np.max(np.where(ok == 1, v, -np.inf))) if ok.any() else float("nan")
    return xr.Dataset({"trot_speed": ("trot", v), "trot_is_trot": ("trot", ok),
                       "hand_tuned_speed": ((), best), "hand_tuned_upright": ((), ok.sum())},
                      coords={"trot": np.arange(len(v))}, attrs={"episode_s": episode_s})


def test_hand_tuned_trot():
    fast = _trot([0.2, 0.75, 0.9], [1, 1, 0])  # the 0.9 m/s one fell over: not a trot
    v = check("ch7.hand_tuned_trot", quadruped_gait=fast)
    assert v.status == "reproduced" and v.measured["hand_tuned_speed"] == 0.75
    slow = _trot([0.2, 0.4, 0.9], [1, 1, 0])
    v = check("ch7.hand_tuned_trot", quadruped_gait=slow)
    assert v.status == "not_reproduced" and "3 trots (2 upright)" in v.detail
    fallen = _trot([0.2, 0.9], [0, 0])
    v = check("ch7.hand_tuned_trot", quadruped_gait=fallen)
    assert v.status == "not_reproduced" and "none of the 2" in v.detail
    old = xr.Dataset({"speed": (("seed", "evaluation"), np.zeros((1, 2)))})
    assert check("ch7.hand_tuned_trot", quadruped_gait=old).status == "not_run"
    short = _trot([0.2, 0.4], [1, 1], episode_s=1.0)  # the smoke profile's 1-s trots
    v = check("ch7.hand_tuned_trot", quadruped_gait=short)
    assert v.status == "inconclusive" and "1 s" in v.detail


def _pendulum(first_held, stays_up_s, time_to_up_s, test_s=60.0, episodes=100):
    succ = np.zeros((len(first_held), episodes))
    for i, e in enumerate(first_held):
        if e is not None:
            succ[i, e:] = 1.0
    seeds = {"seed": list(range(len(first_held)))}
    da = xr.DataArray(succ, dims=("seed", "episode"),
                      coords={**seeds, "episode": np.arange(1, episodes + 1) * 50},
                      attrs={"units": "1", "long_name": "swing-up and balance"})
    def per_seed(v):
        return xr.DataArray(np.array(v, float), dims=("seed",), coords=seeds,
                            attrs={"units": "s"})
    return xr.Dataset({"success": da, "stays_up_s": per_seed(stays_up_s),
                       "time_to_up_s": per_seed(time_to_up_s)}, attrs={"test_s": test_s})


def test_pendulum_needs_held_episodes_and_a_balancing_test_run():
    """The per-seed success of the pendulum from pixels (every seed, rule 7:
    :func:`thesis.claims.ch7.pendulum_learns`, which the existential claims count)."""
    from thesis.claims import ch7 as C7

    name = "ch7.vision_control_learned_through_camera"

    def learns(ds):
        return C7.pendulum_learns({"ch7/pendulum_pixels": ds})

    ds = _pendulum([40] * 6, [58.0, 59.0, 57.5] * 2, [2.0, 1.0, 2.5] * 2)
    v = learns(ds)
    assert v.status == "reproduced" and v.measured["episodes_to_success_median"] == 2050.0
    assert v.measured["seeds_balanced_in_test"] == 6
    never = _pendulum([None] * 3, [0.0] * 3, [np.nan] * 3)
    assert check("ch8.ch7_pendulum_from_pixels", pendulum_pixels=never).status == (
        "not_reproduced")
    # held once in training, but the final controller only swings through upright: a seed
    # that ran past the limit fails, so 6 of 6 failing is not_reproduced (a majority of
    # failures shown), 2 of 3 is not
    swings = _pendulum([40] * 6, [0.3, 0.2] * 3, [2.0, 1.0] * 3)
    v = learns(swings)
    assert v.status == "not_reproduced" and v.measured["seeds_held_in_training"] == 6
    assert v.measured["seeds_balanced_in_test"] == 0
    v = learns(_pendulum([40, 40, 40], [58.0, 0.3, 0.2], [2.0, 1.0, 2.5]))
    assert v.status == "inconclusive" and v.measured["seeds_balanced_in_test"] == 1
    # a short run whose test does not balance yet is censored, not failed
    short = _pendulum([5, 5, 5], [0.3] * 3, [1.0] * 3, test_s=10.0, episodes=10)
    assert learns(short).status == "inconclusive"
    assert check(name, pendulum_pixels=short).status == "inconclusive"
    bare = ds.copy()
    bare.attrs = {}
    v = check(name, pendulum_pixels=bare)
    assert v.status == "not_run" and "test_s" in v.detail


def test_conclusions_that_report_a_found_controller_are_existential():
    """§8.1 "we were able to find ...": existence, which without a replication of each
    seed needs more seeds than runs passing by chance at 5 % would give (2 of 3; one of
    three is what such runs give in 14 % of draws), and so does ch7's own capability
    sentence ("can be ... differentiated through, allowing ... to be learned"), read the
    same way."""
    lone = _pendulum([40, None, None], [58.0, 0.0, 0.0], [2.0, np.nan, np.nan])
    v = check("ch8.ch7_pendulum_from_pixels", pendulum_pixels=lone)
    assert v.status == "inconclusive" and "at least 2" in v.detail
    one = _pendulum([40, 40, None], [58.0, 58.0, 0.0], [2.0, 2.0, np.nan])
    v = check("ch8.ch7_pendulum_from_pixels", pendulum_pixels=one)
    assert v.status == "reproduced" and "2 of 3" in v.detail
    # "cameras can be ... differentiated through, allowing ... to be learned": a capability,
    # read as existence like §8.1's sentence (one logic per sentence form)
    assert check("ch7.vision_control_learned_through_camera",
                 pendulum_pixels=one).status == "reproduced"
    short = _pendulum([5, None, None], [9.0, 0.0, 0.0], [1.0, np.nan, np.nan], test_s=10.0,
                      episodes=10)
    assert check("ch8.ch7_pendulum_from_pixels", pendulum_pixels=short).status == (
        "inconclusive")
    slow = gait(0.3, upright=[1.0, 1.0, 1.0])
    slow["speed"][:2] = slow["speed"][:2] + 0.6  # two seeds reach 0.9 m/s
    v = check("ch8.ch7_gait_in_500_evaluations", quadruped_gait=slow)
    assert v.status == "reproduced"
    assert v.measured["n_seeds_stable_gait_at_least_hand_tuned"] == 2


def test_a_stable_gait_is_not_speed_alone():
    """§8.1 "a stable gait": fast seeds whose robot tipped over (spine tilted past the
    hand-tuned trot's criterion) do not count, and without the tilt recorded the sentence
    cannot be tested (before, speed alone reproduced it)."""
    fast = gait(1.2)
    v = check("ch8.ch7_gait_in_500_evaluations", quadruped_gait=fast)
    assert v.status == "inconclusive" and "stability" in v.detail
    tipped = gait(1.2, upright=[0.1, 0.2, 1.0])
    v = check("ch8.ch7_gait_in_500_evaluations", quadruped_gait=tipped)
    assert v.status == "inconclusive" and v.measured["n_seeds_at_least_hand_tuned_speed"] == 3
    v = check("ch8.ch7_gait_in_500_evaluations", quadruped_gait=gait(1.2, upright=[1.0] * 3))
    assert v.status == "reproduced"


def _arm_fixed(cmaes_reached, gradient_reached, n_eval=60000, n_params=17284):
    seeds = [0, 1, 2]
    reached = xr.DataArray(np.array([gradient_reached, cmaes_reached], np.int8),
                           dims=("method", "seed"),
                           coords={"method": ["gradient", "cmaes"], "seed": seeds},
                           attrs={"units": "1", "long_name": "reached 4 cm"})
    err = xr.DataArray(np.full((2, 3, n_eval), 0.5, np.float32),
                       dims=("method", "seed", "evaluation"),
                       coords={"method": ["gradient", "cmaes"], "seed": seeds,
                               "evaluation": np.arange(1, n_eval + 1)},
                       attrs={"units": "m", "long_name": "error"})
    return xr.Dataset({"reached_4cm": reached, "error": err}, attrs={"n_params": n_params})


def test_cmaes_fails_on_arm_verdicts():
    name = "ch7.cmaes_fails_on_arm"
    assert check(name, arm_fixed=_arm_fixed([0, 0, 0], [1, 1, 1])).status == "reproduced"
    assert check(name, arm_fixed=_arm_fixed([0, 0, 0], [1, 0, 1])).status == "reproduced"
    assert check(name, arm_fixed=_arm_fixed([0, 1, 0], [1, 1, 1])).status == "not_reproduced"
    # reaching 4 cm with fewer evaluations than the thesis's contradicts it all the more
    v = check(name, arm_fixed=_arm_fixed([0, 1, 0], [1, 1, 1], n_eval=200))
    assert v.status == "not_reproduced"
    assert check(name).status == "not_run"


def test_cmaes_budget_below_the_thesis_is_inconclusive():
    v = check("ch7.cmaes_fails_on_arm", arm_fixed=_arm_fixed([0, 0, 0], [1, 1, 1], n_eval=200))
    assert v.status == "inconclusive"
    assert "CMA-ES budget 200 of the thesis's 60000 evaluations" in v.detail
    # success on a smaller network does not contradict "cannot handle the sheer amount"
    v = check("ch7.cmaes_fails_on_arm",
              arm_fixed=_arm_fixed([1, 1, 1], [1, 1, 1], n_eval=60000, n_params=1252))
    assert v.status == "inconclusive" and "1252 parameters" in v.detail


def test_thesis_own_table7_1_satisfies_its_timing_claims():
    """The claims encode the thesis's statements: its own Tab. 7.1 must pass them."""
    from thesis import paper

    coords = {"device": ["cpu", "gpu"], "batch": [1, 128], "n_params": [1296, 1147904],
              "gradient": [0, 1]}
    da = xr.DataArray(np.full((2, 2, 2, 2), np.nan), dims=tuple(coords), coords=coords,
                      attrs={"units": "s", "long_name": "seconds"})
    for e in paper.select("table7_1", "seconds"):
        da.loc[e.coord_dict()] = e.value
    assert np.isfinite(da.values).all()
    # the thesis's gradients were usable (it trained with them)
    ok = xr.full_like(da, 1.0).assign_attrs(units="1", long_name="gradient finite")
    ds = xr.Dataset({"seconds": da, "gradient_finite": ok},
                    attrs={"simulated_seconds": paper.get("table7_1/simulated_seconds").value})
    for cid in ("ch7.gradient_costs_small_factor",
                "ch7.gradient_cost_nearly_independent_of_parameters",
                "ch7.gpu_slower_for_single_robot", "ch7.batching_accelerates_gpu",
                "ch7.gpu_speeds_up_large_batches"):
        assert check(cid, table7_1=ds).status == "reproduced", cid


def _censored_ball(grad, cma, grad_conv, cma_conv, grad_budget=3000, cma_budget=10000):
    seeds = list(range(len(grad)))
    it = xr.DataArray(np.array([grad, cma], float), dims=("method", "seed"),
                      coords={"method": ["gradient", "cmaes"], "seed": seeds},
                      attrs={"units": "1", "long_name": "iterations"})
    conv = xr.DataArray(np.array([grad_conv, cma_conv], np.int8), dims=("method", "seed"),
                        coords=it.coords, attrs={"units": "1", "long_name": "converged"})
    return xr.Dataset({"iterations": it, "converged": conv},
                      attrs={"gradient_max_iterations": grad_budget,
                             "cmaes_max_evaluations": cma_budget})


def test_ball_runs_that_never_converge_count_with_their_budget():
    nan = np.nan
    # gradient descent fails within 3000 on every seed, CMA-ES succeeds earlier: decided
    ds = _censored_ball([nan] * 3, [1100.0, 950.0, 1400.0], [0] * 3, [1] * 3)
    v = check("ch7.gradient_needs_fewer_iterations", ball=ds)
    assert v.status == "not_reproduced"
    assert v.measured["gradient_iterations_failed_kept"] == 3
    assert v.measured["mean_gradient_iterations"] == 3000.0  # the budget, a lower bound
    # the same failures with a budget below CMA-ES's counts tell nothing
    short = _censored_ball([nan] * 3, [1100.0, 950.0, 1400.0], [0] * 3, [1] * 3,
                           grad_budget=500)
    v = check("ch7.gradient_needs_fewer_iterations", ball=short)
    assert v.status == "inconclusive" and v.measured["n_seeds_dropped"] == 3
    # seeds where both fail are dropped: 2 informative seeds are too few
    both = _censored_ball([nan] * 3, [1100.0, nan, 1400.0], [0] * 3, [1, 0, 1])
    v = check("ch7.gradient_needs_fewer_iterations", ball=both)
    assert v.status == "inconclusive" and v.measured["n_seeds_dropped"] == 1
    # mirrored: CMA-ES fails, gradient descent succeeds early
    flip = _censored_ball([80.0, 90.0, 85.0], [nan] * 3, [1] * 3, [0] * 3)
    assert check("ch7.gradient_needs_fewer_iterations", ball=flip).status == "reproduced"


def test_censored_verdict_never_favours_a_method_with_failed_runs():
    from thesis.claims.stats import decide_fewer_censored

    # A fails on seed 0 after 200 (B needed 150 there) but wins the other seeds by far:
    # the paired mean favours A, yet A's true cost on seed 0 is unknown
    a, a_done = [200.0, 10.0, 12.0, 11.0, 13.0], [False, True, True, True, True]
    b, b_done = [150.0, 900.0, 950.0, 980.0, 940.0], [True] * 5
    v = decide_fewer_censored(a, a_done, b, b_done, label_a="a", label_b="b")
    assert v.status == "inconclusive" and v.measured["a_failed_kept"] == 1
    # without the failure, the same numbers reproduce
    v = decide_fewer_censored(a, [True] * 5, b, b_done, label_a="a", label_b="b")
    assert v.status == "reproduced"


def _bimodal_gaits(rng, seeds: int, fail_rate: float) -> xr.Dataset:
    """BPTT gait runs of which ``fail_rate`` never improve (end at their 0 m/s start) and
    the rest reach 1.097 m/s: the mean over runs at 1/5 failing is the sentence's bound
    0.8775 m/s (1.17 less 25 %)."""
    ds = gait(1.097, seeds=seeds)
    sp = ds["speed"].values * (1 + 0.01 * rng.standard_normal((seeds, 1)))
    sp[rng.random(seeds) < fail_rate] = 0.0
    ds["speed"] = (ds["speed"].dims, sp, ds["speed"].attrs)
    return ds


def test_a_gait_run_that_never_improved_is_flagged(monkeypatch):
    """20 % of 5 seeds never improve, the mean over runs on the bound: without the flag
    (rule 3) "above the bound" is said whenever the 5 seeds saw no failure (a third of
    draws); with each run's flag (rule 3b) in none."""
    from thesis.claims import ch7
    rng = np.random.default_rng(5)
    reps = 120

    def rate():
        return np.mean([check("ch7.quadruped_gait_in_500_evaluations",
                              quadruped_gait=_bimodal_gaits(rng, 5, 0.2)).status == "reproduced"
                        for _ in range(reps)])

    flagged = rate()
    monkeypatch.setattr(ch7, "_failed_gaits", lambda *a: (None, None))
    unflagged = rate()
    assert unflagged > 0.15, unflagged
    assert flagged <= 0.025, flagged
