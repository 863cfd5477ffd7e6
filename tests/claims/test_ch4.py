"""Chapter-4 claims (and their §8.1 restatements) decided on synthetic datasets laid out as
thesis.ch4.transfer_artifacts writes them: each claim once on data that supports it
(reproduced) and once on data that contradicts it (anything but reproduced)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from thesis import claims

S, G, N = 5, 13, 20
#: The thesis's run size (thesis.claims.ch4.thesis_budget), stated on every dataset.
FULL = dict(particles=20, generations=13, run_seconds=4.0, transition_seconds=2.0)
PARAMS = ["f", "a", "x0", "y0f", "y0r", "t_stance", "l0f", "l1f", "l0r", "l1r", "l2", "l3"]


def _da(values, dims, coords, units="1"):
    return xr.DataArray(values, dims=dims, coords=coords,
                        attrs={"units": units, "long_name": "synthetic"})


def _scores(shift_per_gen, rng, gen0_shift=None):
    """(S, 2, G, N) scores; transfer (index 1) shifted by shift_per_gen[g]."""
    sc = rng.normal(0.2, 0.1, (S, 2, G, N))
    sc[:, 1] += np.asarray(shift_per_gen)[None, :, None]
    if gen0_shift is not None:
        sc[:, 1, 0] = rng.normal(0.2, 0.1, (S, N)) + gen0_shift
    return sc


def _run_ds(sc, **extra):
    dims = ("seed", "transfer", "generation", "particle")
    coords = dict(seed=np.arange(S), transfer=[0, 1], generation=np.arange(G),
                  particle=np.arange(N))
    return xr.Dataset({"score": _da(sc, dims, coords, "m s-1")})


def fig4_5(shift=0.1, rng=0):
    r = np.random.default_rng(rng)
    parts = [_run_ds(_scores(np.full(G, shift), r)) for _ in (9, 18)]
    return xr.concat(parts, dim=xr.DataArray([9, 18], dims="grade"))


def fig4_7(gen0=-0.1, later=0.08, rng=1):
    r = np.random.default_rng(rng)
    return _run_ds(_scores(np.full(G, later), r, gen0_shift=gen0))


def fig4_8(gen0=0.15, later=0.0, rng=2):
    r = np.random.default_rng(rng)
    return _run_ds(_scores(np.full(G, later), r, gen0_shift=gen0))


def _table(dim, levels, score, dist, ranks=None, best_gen=None):
    coords = {"seed": np.arange(S), dim: levels, "transfer": [0, 1]}
    dims = ("seed", dim, "transfer")
    if ranks is not None:
        coords["rank"] = ranks
        dims = dims + ("rank",)
    ds = xr.Dataset({"score": _da(score, dims, coords, "m s-1"),
                     "euclidean_distance": _da(dist, dims, coords)})
    if best_gen is not None:
        ds["best_generation"] = _da(best_gen, dims, coords)
    return ds


def table4_2(gain=0.1, d9=0.5, d18=0.8, rng=3):
    r = np.random.default_rng(rng)
    score = 0.5 + 0.02 * r.standard_normal((S, 3, 2))
    score[:, 1:, 1] += gain * score[:, 1:, 0]
    dist = np.zeros((S, 3, 2))
    dist[:, 1] = d9 + 0.05 * r.standard_normal((S, 2))
    dist[:, 2] = d18 + 0.05 * r.standard_normal((S, 2))
    return _table("grade", [0, 9, 18], score, dist)


def table4_3(gain=0.13, rng=4):
    r = np.random.default_rng(rng)
    score = 0.5 + 0.02 * r.standard_normal((S, 2, 2))
    score[:, 1, 1] = score[:, 1, 0] * (1 + gain + 0.005 * r.standard_normal(S))
    return _table("stiffness", ["normal", "compliant"], score, np.ones((S, 2, 2)))


def table4_4(tl_better=0.05, close=True, gen0=True, rng=5):
    r = np.random.default_rng(rng)
    score = 0.5 + 0.02 * r.standard_normal((S, 2, 2, 2))
    score[:, 1, 1] += tl_better
    dist = np.ones((S, 2, 2, 2)) + 0.05 * r.standard_normal((S, 2, 2, 2))
    dist[:, 1, 1] = (0.2 if close else 1.8) + 0.05 * r.standard_normal((S, 2))
    best_gen = np.full((S, 2, 2, 2), 5.0)
    best_gen[:, 1, 1, 0] = 0.0 if gen0 else 4.0
    return _table("terrain", ["normal", "pebbly"], score, dist, ranks=[1, 2], best_gen=best_gen)


def fig4_6(a=(95, 90, 85), t=(0.50, 0.54, 0.58), x0=(137, 140, 143), var=(0.3, 0.2, 0.1), rng=6):
    r = np.random.default_rng(rng)
    mean = np.zeros((S, 3, 12))
    for j, name in enumerate(PARAMS):
        mean[:, :, j] = 1.0
    for name, vals, sd in (("a", a, 1.0), ("t_stance", t, 0.005), ("x0", x0, 0.5)):
        j = PARAMS.index(name)
        mean[:, :, j] = np.asarray(vals)[None] + sd * r.standard_normal((S, 3))
    tv = np.asarray(var)[None] + 0.01 * r.standard_normal((S, 3))
    coords = dict(seed=np.arange(S), grade=[0, 9, 18], parameter=PARAMS)
    return xr.Dataset({"mean": _da(mean, ("seed", "grade", "parameter"), coords),
                       "total_variance": _da(tv, ("seed", "grade"),
                                             {k: coords[k] for k in ("seed", "grade")})})


def fig4_9(related=True, rng=7):
    r = np.random.default_rng(rng)
    shape = (S, 2, G, N)
    af = r.uniform(0, 1, shape)
    x0 = r.uniform(0, 1, shape)
    score = r.normal(0, 0.05, shape)
    if related:
        score += af - np.abs(x0 - 0.5)
    else:
        score += -af + np.abs(x0 - 0.5)
    dims = ("seed", "transfer", "generation", "particle")
    coords = dict(seed=np.arange(S), transfer=[0, 1], generation=np.arange(G),
                  particle=np.arange(N))
    return xr.Dataset({"a_fraction": _da(af, dims, coords), "x0_fraction": _da(x0, dims, coords),
                       "score": _da(score, dims, coords, "m s-1")})


def fig4_10(ratio=1.7, start_match=True, rng=8):
    r = np.random.default_rng(rng)
    size = np.zeros((S, 2, 2, G))
    rand = np.linspace(0.3, 0.15, G)
    size[:, :, 0] = rand[None, None] * (1 + 0.02 * r.standard_normal((S, 2, G)))
    size[:, :, 1] = size[:, :, 0] / ratio
    if start_match:
        size[:, :, 1, 0] = size[:, :, 0, -1] * (1 + 0.02 * r.standard_normal((S, 2)))
    else:  # the transferred swarm starts as large as the random one
        size[:, :, 1, 0] = size[:, :, 0, 0]
    dims = ("seed", "condition", "transfer", "generation")
    coords = dict(seed=np.arange(S), condition=["grade9", "grade18"], transfer=[0, 1],
                  generation=np.arange(G))
    return xr.Dataset({"search_space_size": _da(size, dims, coords)})


def check(claim_id, budget=None, **results):
    res = {}
    for k, v in results.items():
        v = v.copy()
        v.attrs.update(FULL if budget is None else budget)
        res[f"ch4/{k}"] = v
    return claims.get(claim_id).check(res)


def test_significant_on_slopes():
    assert check("ch4.transfer_significant_on_slopes", fig4_5=fig4_5(0.1)).status == "reproduced"
    v = check("ch4.transfer_significant_on_slopes", fig4_5=fig4_5(0.0))
    assert v.status == "not_reproduced", v.detail
    assert check("ch4.transfer_significant_on_slopes",
                 fig4_5=fig4_5(-0.05)).status == "not_reproduced"


def test_significant_with_soft_legs():
    assert check("ch4.transfer_significant_with_compliant_legs",
                 fig4_7=fig4_7(0.0, 0.08)).status == "reproduced"
    assert check("ch4.transfer_significant_with_compliant_legs",
                 fig4_7=fig4_7(0.0, -0.05)).status == "not_reproduced"


def test_not_significant_on_pebbles():
    # a modest head start that is then lost: no consistent advantage over the run
    assert check("ch4.transfer_not_significant_on_pebbles",
                 fig4_8=fig4_8(0.03, 0.0)).status == "reproduced"
    assert check("ch4.transfer_not_significant_on_pebbles",
                 fig4_8=fig4_8(0.15, 0.1)).status == "not_reproduced"


def test_three_of_four_and_except_rocky():
    good = dict(fig4_5=fig4_5(0.1), fig4_7=fig4_7(0.0, 0.08), fig4_8=fig4_8(0.0, 0.0))
    # "not harmed" on pebbles is rule 9's non-inferiority on runs without a failure flag:
    # reproduced only from 40 seeds (tests/claims/test_decidability.py decides it there)
    v = check("ch4.transfer_better_in_three_of_four", **good)
    assert v.status == "inconclusive" and "from 40 seeds" in v.detail, v.detail
    assert check("ch8.ch4_transfer_better_except_rocky", **good).status == "reproduced"
    harmed = dict(good, fig4_8=fig4_8(0.0, -0.1))
    assert check("ch4.transfer_better_in_three_of_four", **harmed).status == "not_reproduced"
    better_everywhere = dict(good, fig4_8=fig4_8(0.0, 0.1))
    assert check("ch8.ch4_transfer_better_except_rocky",
                 **better_everywhere).status == "not_reproduced"


def test_better_gaits_in_all_cases():
    ok = dict(table4_2=table4_2(0.1), table4_3=table4_3(0.13), table4_4=table4_4(0.05))
    assert check("ch4.transfer_gives_better_gaits_in_all_cases", **ok).status == "reproduced"
    # one condition of four against the claim, at Holm's family level (-0.05: p = 0.0075
    # for that part alone, 4 x p > 0.025, inconclusive)
    bad = dict(ok, table4_4=table4_4(-0.1))
    assert check("ch4.transfer_gives_better_gaits_in_all_cases",
                 **bad).status == "not_reproduced"


def test_best_speed_gains():
    t42 = table4_2(0.0)
    t42["score"].loc[dict(grade=9, transfer=1)] = t42["score"].sel(grade=9, transfer=0) * 1.09
    t42["score"].loc[dict(grade=18, transfer=1)] = t42["score"].sel(grade=18, transfer=0) * 1.14
    ok = dict(table4_2=t42, table4_3=table4_3(0.13))
    assert check("ch4.best_speed_gains", **ok).status == "reproduced"
    bad = dict(ok, table4_3=table4_3(0.5))
    assert check("ch4.best_speed_gains", **bad).status == "not_reproduced"
    # the gains are shown in percent beside the thesis's 9 %, and declared so
    v = check("ch4.best_speed_gains", **ok)
    np.testing.assert_allclose(v.measured["grade9.gain_percent_mean"], 9.0, atol=0.5)
    assert v.measured["grade9.thesis_gain_percent"] == 9.0
    assert claims.get("ch4.best_speed_gains").units["gain_percent"] == "percent"
    assert "log" in v.statistic


def test_trains_faster():
    r = np.random.default_rng(9)
    ds = fig4_5(0.0)
    sc = ds["score"].values.copy()
    ramp = np.linspace(0, 0.3, G)
    sc[:, :, 0] += ramp[None, None, :, None]  # random swarm improves slowly
    sc[:, :, 1] += 0.3  # transfer is there from the start
    fast = ds.copy()
    fast["score"] = (ds["score"].dims, sc, ds["score"].attrs)
    assert check("ch4.transfer_trains_faster_on_slopes", fig4_5=fast).status == "reproduced"
    slow = ds.copy()
    sc2 = ds["score"].values.copy() + 0.01 * r.standard_normal(ds["score"].shape)
    sc2[:, :, 1] += ramp[None, None, :, None]
    sc2[:, :, 0] += 0.3
    slow["score"] = (ds["score"].dims, sc2, ds["score"].attrs)
    assert check("ch4.transfer_trains_faster_on_slopes", fig4_5=slow).status == "not_reproduced"


def test_search_space_claims():
    good = dict(fig4_10=fig4_10(1.7), fig4_5=fig4_5(0.1))
    # a causal sentence from two correlations: untestable without an intervention, even
    # when both correlations hold (they are decided and shown in the detail)
    for cid in ("ch4.speedup_from_reduced_search_space", "ch8.ch4_reduced_exploration"):
        v = check(cid, **good)
        assert v.status == "inconclusive" and "intervention" in v.detail, cid
        assert "the two correlations: reproduced" in v.detail
        assert v.measured["smaller_search_space.advantage_ci_low"] > 0
    assert check("ch4.search_space_1_7_times_smaller", fig4_10=fig4_10(1.7)).status == "reproduced"
    assert check("ch4.transfer_starts_with_final_search_space",
                 fig4_10=fig4_10(1.7)).status == "reproduced"
    larger = dict(good, fig4_10=fig4_10(0.7))
    v = check("ch4.speedup_from_reduced_search_space", **larger)
    assert v.status == "inconclusive" and "the two correlations: not_reproduced" in v.detail
    assert check("ch4.search_space_1_7_times_smaller",
                 fig4_10=fig4_10(3.0)).status == "not_reproduced"
    assert check("ch4.transfer_starts_with_final_search_space",
                 fig4_10=fig4_10(1.7, start_match=False)).status == "not_reproduced"


def test_fig4_6_trends():
    ok = fig4_6()
    assert check("ch4.steeper_slopes_shorter_steps", fig4_6=ok).status == "reproduced"
    assert check("ch4.steeper_slopes_feet_further_from_body", fig4_6=ok).status == "reproduced"
    assert check("ch4.parameter_variance_falls_with_slope", fig4_6=ok).status == "reproduced"
    flat_t = fig4_6(t=(0.58, 0.54, 0.50))  # stance shortens with the slope
    assert check("ch4.steeper_slopes_shorter_steps", fig4_6=flat_t).status == "not_reproduced"
    assert check("ch4.steeper_slopes_feet_further_from_body",
                 fig4_6=fig4_6(x0=(143, 140, 137))).status == "not_reproduced"
    assert check("ch4.parameter_variance_falls_with_slope",
                 fig4_6=fig4_6(var=(0.1, 0.2, 0.3))).status == "not_reproduced"


def test_distances():
    assert check("ch4.distance_from_flat_grows_with_slope",
                 table4_2=table4_2(d9=0.5, d18=0.8)).status == "reproduced"
    assert check("ch4.distance_from_flat_grows_with_slope",
                 table4_2=table4_2(d9=0.8, d18=0.5)).status == "not_reproduced"


def _with_distance_shift(t, shift9, shift18, one_pair=None):
    """``t`` with the transferred run's distance = the random run's + shift per grade."""
    d = t["euclidean_distance"].values.copy()
    d[:, 1, 1] = d[:, 1, 0] + shift9
    d[:, 2, 1] = d[:, 2, 0] + shift18
    if one_pair is not None:
        d[0, 2, 1] = d[0, 2, 0] + one_pair
    out = t.copy()
    out["euclidean_distance"] = (t["euclidean_distance"].dims, d,
                                 t["euclidean_distance"].attrs)
    return out


def test_not_necessarily_closer_reads_the_method_not_one_pair():
    t = table4_2()
    rng = np.random.default_rng(8)
    noise = 0.05 * rng.standard_normal(S)
    # the thesis's Tab. 4.2: closer on 9 %, farther on 18 %
    v = check("ch4.transfer_not_necessarily_closer",
              table4_2=_with_distance_shift(t, -0.3 + noise, 0.3 + noise))
    assert v.status == "reproduced" and "grade18" in v.detail, v.detail
    closer = _with_distance_shift(t, -0.3 + noise, -0.3 + noise)
    assert check("ch4.transfer_not_necessarily_closer",
                 table4_2=closer).status == "not_reproduced"
    # one farther pair of ten does not make the method "not necessarily closer"
    one = check("ch4.transfer_not_necessarily_closer",
                table4_2=_with_distance_shift(t, -0.3 + noise, -0.3 + noise, one_pair=0.2))
    assert one.status == "inconclusive" and one.measured["n_pairs_transfer_farther"] == 1


def test_soft_legs_start_worse_learn_faster():
    r = np.random.default_rng(10)
    sc = r.normal(0.2, 0.05, (S, 2, G, N))
    sc[:, 1, 0] -= 0.1  # transferred generation 0 worse
    sc[:, 1, 1:] += 0.1  # then better
    ok = _run_ds(sc)
    assert check("ch4.soft_legs_transfer_starts_worse_learns_faster",
                 fig4_7=ok).status == "reproduced"
    sc2 = r.normal(0.2, 0.05, (S, 2, G, N))
    sc2[:, 1] += 0.1  # better from the start
    assert check("ch4.soft_legs_transfer_starts_worse_learns_faster",
                 fig4_7=_run_ds(sc2)).status == "not_reproduced"


def test_pebbles_head_start_lost():
    assert check("ch4.pebbles_head_start_lost",
                 fig4_8=fig4_8(0.4, 0.0)).status == "reproduced"
    assert check("ch4.pebbles_head_start_lost",
                 fig4_8=fig4_8(-0.15, 0.0)).status == "not_reproduced"


def test_a_head_start_kept_throughout_is_not_lost():
    """"This head start is quickly lost": transferred particles that outscore the random
    ones in every generation (A = 1 throughout) have not lost it (before, the test of
    "smaller later" read a constant A of 1 as inconclusive)."""
    v = check("ch4.pebbles_head_start_lost", fig4_8=fig4_8(5.0, 5.0))
    assert v.status == "not_reproduced", v.detail
    assert v.measured["head_start_lost.A12_second_half_minus_half_mean"] == pytest.approx(0.5)


def test_pebbles_head_start_needs_every_original_particle():
    """"All the original particles outperform the random particles": a first generation
    whose transferred particles beat the random ones on the whole (pooled A > 0.5) but
    where one of them scores below nearly every random particle is not "all outperform"."""
    ds = fig4_8(0.4, 0.0)
    sc = ds["score"].values.copy()
    sc[:, 1, 0, 0] = -1.0  # one original particle fell, in every seed
    ds["score"] = (ds["score"].dims, sc, ds["score"].attrs)
    v = check("ch4.pebbles_head_start_lost", fig4_8=ds)
    assert v.status == "not_reproduced"
    assert v.measured["every_original_outperforms.A12_worst_original_generation0_minus_half"
                      "_mean"] < 0


def _ten_seeds(ds):
    return xr.concat([ds, ds.assign_coords(seed=ds["seed"] + S)], dim="seed")


def test_pebbles_best_particles():
    for gen0 in (True, False):  # with 5 seeds no count decides: untestable, seeds named
        five = check("ch4.pebbles_best_is_transferred", table4_4=table4_4(gen0=gen0))
        assert five.status == "inconclusive" and "not testable" in five.detail
        assert "at least 6 seeds" in five.detail and five.measured["seeds_needed"] == 6
    assert check("ch4.pebbles_best_is_transferred",
                 table4_4=_ten_seeds(table4_4(gen0=True))).status == "reproduced"
    assert check("ch4.pebbles_best_is_transferred",
                 table4_4=_ten_seeds(table4_4(gen0=False))).status == "not_reproduced"
    assert check("ch4.pebbles_transfer_best_close_to_flat",
                 table4_4=table4_4(close=True)).status == "reproduced"
    assert check("ch4.pebbles_transfer_best_close_to_flat",
                 table4_4=table4_4(close=False)).status == "not_reproduced"


def test_step_length_maximised():
    assert check("ch4.step_length_maximised_on_steep_slope",
                 fig4_9=fig4_9(True)).status == "reproduced"
    assert check("ch4.step_length_maximised_on_steep_slope",
                 fig4_9=fig4_9(False)).status == "not_reproduced"


def test_every_ch4_claim_is_implemented_and_layout_errors_are_not_run():
    ch4 = [c for c in claims.CLAIMS if c.id.startswith(("ch4.", "ch8.ch4_"))]
    assert len(ch4) >= 20 and all(c.fn is not None for c in ch4)
    v = check("ch4.transfer_significant_on_slopes", fig4_5=xr.Dataset())
    assert v.status == "not_run" and "layout mismatch" in v.detail


def test_few_seeds_are_inconclusive():
    ds = fig4_5(0.1).isel(seed=slice(0, 2))
    v = check("ch4.transfer_significant_on_slopes", fig4_5=ds)
    assert v.status == "inconclusive"


def test_runs_smaller_than_the_thesis_are_inconclusive():
    small = dict(FULL, generations=2, particles=4)
    v = check("ch4.transfer_significant_on_slopes", budget=small, fig4_5=fig4_5(0.1))
    assert v.status == "inconclusive" and "smaller than the thesis's" in v.detail
    assert "would say reproduced" in v.detail and v.measured["grade9.n_seeds"] == 5.0
    short = dict(FULL, run_seconds=1.0)
    v = check("ch4.parameter_variance_falls_with_slope", budget=short,
              fig4_6=fig4_6(var=(0.1, 0.2, 0.3)))
    assert v.status == "inconclusive"
    v = claims.get("ch4.transfer_significant_on_slopes").check({"ch4/fig4_5": fig4_5(0.1)})
    assert v.status == "not_run" and "run-size attributes" in v.detail


def test_thesis_budget_is_derived_from_its_numbers():
    from thesis.claims import ch4

    assert ch4.thesis_budget() == dict(particles=20.0, generations=13.0, run_seconds=4.0,
                                       transition_seconds=2.0)


def test_search_space_ratio_is_decided_on_its_logarithm():
    """Per-generation ratios alternating 1 and 4 have a geometric mean of 2 (within 25 % of
    1.7 on the log scale) but an arithmetic mean of 2.5 (47 % off): a ratio is decided on
    its logarithm, so the skew of the raw ratio must not decide the verdict."""
    ds = fig4_10(1.7)
    size = ds["search_space_size"].values.copy()
    per_gen = np.where(np.arange(G) % 2 == 0, 1.0, 4.0)
    per_gen[-1] = 2.0  # an odd number of generations: keep the geometric mean at 2
    size[:, :, 1] = size[:, :, 0] / per_gen[None, None]
    ds["search_space_size"] = (ds["search_space_size"].dims, size,
                               ds["search_space_size"].attrs)
    v = check("ch4.search_space_1_7_times_smaller", fig4_10=ds)
    assert v.status == "reproduced"
    np.testing.assert_allclose(v.measured["size_ratio_random_over_transfer_geometric_mean"],
                               2.0, rtol=1e-6)


def test_a_run_whose_best_particle_fell_makes_the_best_score_claims_inconclusive():
    """ch4's failure indicator (rule 3b): a run's best particle that fell (score below -1,
    a fallen robot's -2 + upright share) leaves no claim on the best scores decided, even
    where the numbers would otherwise reproduce it; the run is named."""
    from thesis.claims import ch4 as C

    t42 = table4_2(0.0)
    t42["score"].loc[dict(grade=9, transfer=1)] = t42["score"].sel(grade=9, transfer=0) * 1.09
    t42["score"].loc[dict(grade=18, transfer=1)] = t42["score"].sel(grade=18, transfer=0) * 1.14
    ok = dict(table4_2=t42, table4_3=table4_3(0.13))
    all_ok = dict(ok, table4_4=table4_4(0.05))
    assert check("ch4.best_speed_gains", **ok).status == "reproduced"
    assert check("ch4.transfer_gives_better_gaits_in_all_cases", **all_ok).status == "reproduced"
    fell = t42.copy(deep=True)
    fell["score"].loc[dict(seed=2, grade=18, transfer=0)] = -1.6
    for claim, res in (("ch4.best_speed_gains", dict(ok, table4_2=fell)),
                       ("ch4.transfer_gives_better_gaits_in_all_cases",
                        dict(all_ok, table4_2=fell))):
        v = check(claim, **res)
        assert v.status == "inconclusive", (claim, v.detail)
        assert "best particle fell" in v.detail and "seed=2, grade=18, transfer=0" in v.detail
        assert v.measured["failed_runs"] == 1
    assert C.failed_runs({"ch4/table4_2": fell}, "ch4/table4_2") == [
        "ch4/table4_2: seed=2, grade=18, transfer=0"]
    # a best that walked slowly (not below -1) is a value, not a failure
    slow = t42.copy(deep=True)
    slow["score"].loc[dict(seed=2, grade=18, transfer=0)] = 0.01
    assert C.failed_runs({"ch4/table4_2": slow}, "ch4/table4_2") == []
