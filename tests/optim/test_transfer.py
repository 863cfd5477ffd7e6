"""Transfer initialisation (§4.4), lock-step runs and the per-generation comparison (§4.6)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats as sps

from thesis.optim import pso, transfer

LOWER = np.array([1.5, 0.0, 126.0, 0.4])
UPPER = np.array([2.0, 70.0, 158.0, 0.6])


def _source_run(rng, g=5, n=8):
    x = LOWER + rng.random((g, n, LOWER.size)) * (UPPER - LOWER)
    f = -np.sum(((x - LOWER) / (UPPER - LOWER) - 0.3) ** 2, axis=-1)
    return x, f


def test_impulse_scale_is_a_fraction_of_each_range():
    imp = transfer.impulse_scale(LOWER, UPPER, 70.0)
    np.testing.assert_allclose(imp, (UPPER - LOWER) / 70.0)
    np.testing.assert_allclose(imp[1], 1.0)  # 70 mm range: exactly U(-1, 1) mm
    with pytest.raises(ValueError):
        transfer.impulse_scale(LOWER, UPPER, 0.0)


def test_transfer_swarm_starts_at_the_best_particles_with_bounded_impulse():
    rng = np.random.default_rng(0)
    x, f = _source_run(rng)
    imp = transfer.impulse_scale(LOWER, UPPER, 70.0)
    st = transfer.transfer_init(7, x, f, 6, LOWER, UPPER, impulse=imp)
    order = np.argsort(-f.ravel())[:6]
    np.testing.assert_array_equal(st.x, x.reshape(-1, 4)[order])
    assert np.all(np.abs(st.v) <= imp[None] + 1e-12)
    assert np.all(np.abs(st.v) > 0)  # a random impulse, not zero
    # the draws fill the impulse box, not a corner of it
    big = transfer.transfer_init(8, x, f, 40, LOWER, UPPER, impulse=imp)
    assert np.all(big.v.max(axis=0) > 0.5 * imp) and np.all(big.v.min(axis=0) < -0.5 * imp)
    # personal and global bests are not transferred (§4.4: the new task decides)
    assert np.all(np.isneginf(st.p_fit)) and np.isneginf(st.g_fit)


def test_transfer_respects_the_feasibility_map():
    rng = np.random.default_rng(1)
    x, f = _source_run(rng)

    def project(p):
        p = np.array(p, copy=True)
        p[:, 1] = np.minimum(p[:, 1], 10.0)
        return p

    st = transfer.transfer_init(3, x, f, 5, LOWER, UPPER, impulse=1.0, project=project)
    assert np.all(st.x[:, 1] <= 10.0)


def test_lockstep_evaluates_every_swarm_once_per_generation_and_transfer_helps():
    d = 4

    def sphere(p, centre):
        return -np.sum(((p - LOWER) / (UPPER - LOWER) - centre) ** 2, axis=-1)

    src, _ = pso.run_pso(lambda p: sphere(p, 0.30), 0, 10, 12, LOWER, UPPER)
    calls = []

    def evaluate(gen, xs):
        calls.append((gen, sorted(xs)))
        return {k: sphere(v, 0.32) for k, v in xs.items()}

    imp = transfer.impulse_scale(LOWER, UPPER, 70.0)
    swarms = {"tl": transfer.transfer_init(1, src.positions, src.fitness, 10, LOWER, UPPER,
                                           impulse=imp),
              "rand": pso.pso_init(2, 10, LOWER, UPPER)}
    hist = transfer.run_lockstep(swarms, evaluate, 4)
    assert calls == [(g, ["rand", "tl"]) for g in range(4)]
    assert hist["tl"].positions.shape == (4, 10, d) and hist["rand"].fitness.shape == (4, 10)
    # a nearby optimum: the transferred swarm starts and stays ahead
    assert np.median(hist["tl"].fitness[0]) > np.median(hist["rand"].fitness[0])
    assert hist["tl"].best_fitness[-1] > hist["rand"].best_fitness[-1]


def test_compare_generations_matches_scipy():
    rng = np.random.default_rng(5)
    a = rng.normal(0.3, 1.0, (6, 20))
    b = rng.normal(0.0, 1.0, (6, 20))
    b[2, :5] = a[2, :5]  # ties across the samples
    out = transfer.compare_generations(a, b)
    p1 = [sps.mannwhitneyu(x, y, alternative="greater").pvalue for x, y in zip(a, b)]
    p2 = [sps.mannwhitneyu(x, y, alternative="two-sided").pvalue for x, y in zip(a, b)]
    np.testing.assert_allclose(out["p_greater"], p1, rtol=1e-12)
    np.testing.assert_allclose(out["p_two_sided"], p2, rtol=1e-12)
    np.testing.assert_allclose(out["fisher_greater"],
                               sps.combine_pvalues(p1, method="fisher").pvalue, rtol=1e-12)
    np.testing.assert_allclose(out["fisher_two_sided"],
                               sps.combine_pvalues(p2, method="fisher").pvalue, rtol=1e-12)
    u = [sps.mannwhitneyu(x, y).statistic / (x.size * y.size) for x, y in zip(a, b)]
    np.testing.assert_allclose(out["a12"], u, rtol=1e-12)


def test_compare_generations_direction_and_degenerate_cases():
    better = transfer.compare_generations(np.full((3, 5), 2.0) + np.arange(5),
                                          np.zeros((3, 5)) + np.arange(5) * 0.1)
    assert np.all(better["a12"] == 1.0) and better["fisher_greater"] < 1e-3
    tied = transfer.compare_generations(np.ones((2, 4)), np.ones((2, 4)))
    np.testing.assert_array_equal(tied["p_greater"], [1.0, 1.0])
    np.testing.assert_array_equal(tied["a12"], [0.5, 0.5])
    with pytest.raises(ValueError):
        transfer.compare_generations(np.ones((2, 4)), np.ones((3, 4)))
    assert np.isnan(transfer.fisher([np.nan]))
