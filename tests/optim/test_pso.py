"""PSO (eq. 3.1–3.2, §4.4 transfer init) on known functions; reproducibility; bounds."""

import numpy as np
import pytest

from thesis.optim import pso


def sphere(x):
    return -np.sum((x - 0.7) ** 2, axis=1)


def rosenbrock(x):
    return -np.sum(100.0 * (x[:, 1:] - x[:, :-1] ** 2) ** 2 + (1.0 - x[:, :-1]) ** 2, axis=1)


def rastrigin(x):
    d = x.shape[1]
    return -(10.0 * d + np.sum(x**2 - 10.0 * np.cos(2 * np.pi * x), axis=1))


def test_sphere_5d():
    lo, hi = -5 * np.ones(5), 5 * np.ones(5)
    h, _ = pso.run_pso(sphere, 1, 20, 150, lo, hi)
    assert h.best_fitness[-1] > -1e-8
    np.testing.assert_allclose(h.best_position, 0.7, atol=1e-4)


def test_rosenbrock_2d():
    lo, hi = -2 * np.ones(2), 2 * np.ones(2)
    h, _ = pso.run_pso(rosenbrock, 2, 30, 300, lo, hi)
    np.testing.assert_allclose(h.best_position, [1.0, 1.0], atol=2e-2)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_rastrigin_2d_global(seed):
    lo, hi = -5.12 * np.ones(2), 5.12 * np.ones(2)
    h, _ = pso.run_pso(rastrigin, seed, 40, 200, lo, hi)
    # the global minimum 0 at the origin; the nearest local minima have cost ~1
    assert h.best_fitness[-1] > -1e-3
    np.testing.assert_allclose(h.best_position, 0.0, atol=5e-3)


def test_history_shapes_and_monotone_best():
    lo, hi = -np.ones(3), np.ones(3)
    h, st = pso.run_pso(sphere, 5, 7, 11, lo, hi)
    assert h.positions.shape == (11, 7, 3) and h.fitness.shape == (11, 7)
    assert np.all(np.diff(h.best_fitness) >= 0)
    np.testing.assert_allclose(h.fitness, sphere(h.positions.reshape(-1, 3)).reshape(11, 7))
    assert st.generation == 11
    assert st.g_fit == pytest.approx(h.best_fitness[-1])


def test_same_seed_identical_different_seed_differs():
    lo, hi = -3 * np.ones(4), 3 * np.ones(4)
    a, _ = pso.run_pso(rastrigin, 42, 10, 20, lo, hi)
    b, _ = pso.run_pso(rastrigin, 42, 10, 20, lo, hi)
    c, _ = pso.run_pso(rastrigin, 43, 10, 20, lo, hi)
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.fitness, b.fitness)
    assert not np.allclose(a.positions, c.positions)


def test_jax_key_and_generator_seeds_reproducible():
    import jax

    lo, hi = np.zeros(2), np.ones(2)
    s1 = pso.pso_init(jax.random.key(3), 5, lo, hi)
    s2 = pso.pso_init(jax.random.key(3), 5, lo, hi)
    s3 = pso.pso_init(jax.random.key(4), 5, lo, hi)
    np.testing.assert_array_equal(s1.x, s2.x)
    assert not np.allclose(s1.x, s3.x)
    g = np.random.default_rng(9)
    s4 = pso.pso_init(g, 5, lo, hi)
    s5 = pso.pso_init(g, 5, lo, hi)  # the generator is copied, not consumed
    np.testing.assert_array_equal(s4.x, s5.x)


def test_tell_is_pure():
    lo, hi = -np.ones(3), np.ones(3)
    s = pso.pso_init(0, 6, lo, hi)
    f = sphere(pso.ask(s))
    t1 = pso.tell(s, f)
    t2 = pso.tell(s, f)
    np.testing.assert_array_equal(t1.x, t2.x)
    assert s.generation == 0 and np.all(np.isneginf(s.p_fit))


def test_bounds_respected_even_with_optimum_outside():
    lo, hi = np.array([0.0, -1.0, 2.0]), np.array([1.0, 0.0, 3.0])

    def far(x):  # optimum at (5, 5, 5), outside the box
        return -np.sum((x - 5.0) ** 2, axis=1)

    h, _ = pso.run_pso(far, 3, 12, 40, lo, hi)
    assert np.all(h.positions >= lo) and np.all(h.positions <= hi)
    np.testing.assert_allclose(h.best_position, [1.0, 0.0, 3.0], atol=1e-9)


def test_velocity_clamp():
    lo, hi = np.zeros(2), np.array([1.0, 10.0])
    s = pso.pso_init(0, 50, lo, hi, v_max_fraction=0.1)
    for _ in range(5):
        assert np.all(np.abs(s.v) <= 0.1 * (hi - lo) + 1e-12)
        s = pso.tell(s, np.random.default_rng(s.generation).random(50))


def test_project_applied():
    lo, hi = np.zeros(2), np.ones(2)

    def proj(x):  # feasible set: x1 <= x0
        x = x.copy()
        x[:, 1] = np.minimum(x[:, 1], x[:, 0])
        return x

    h, _ = pso.run_pso(lambda x: x[:, 1] - 0.1 * x[:, 0], 0, 10, 30, lo, hi, project=proj)
    assert np.all(h.positions[:, :, 1] <= h.positions[:, :, 0] + 1e-12)
    np.testing.assert_allclose(h.best_position, [1.0, 1.0], atol=1e-3)


def test_nan_fitness_is_worst():
    s = pso.pso_init(0, 4, np.zeros(1), np.ones(1))
    s = pso.tell(s, np.array([np.nan, 1.0, np.nan, 0.5]))
    assert s.g_fit == 1.0 and np.isneginf(s.p_fit[0])


def test_best_particles_selects_top_over_all_generations():
    X = np.arange(24, dtype=float).reshape(3, 4, 2)
    F = np.array([[0, 5, 1, 2], [9, 3, np.nan, 4], [7, 8, 6, -1]], dtype=float)
    top = pso.best_particles(X, F, 3)
    np.testing.assert_array_equal(top, [X[1, 0], X[2, 1], X[2, 0]])


def test_transfer_init_concentrates_near_previous_optimum():
    d = 12
    lo, hi = np.zeros(d), 100.0 * np.ones(d)
    centre = np.full(d, 40.0)
    # a previous run's particles scattered around `centre`
    prev = centre + np.random.default_rng(0).normal(0, 1.0, (5, 20, d))
    prev_f = -np.sum((prev - centre) ** 2, axis=-1)
    init = pso.best_particles(prev, prev_f, 20)
    s = pso.pso_init(7, 20, lo, hi, init=init)
    np.testing.assert_array_equal(s.x, init)
    assert np.all(np.abs(s.v) <= 1.0)  # v(0) = r, r ~ U(-1, 1) (§4.4)
    x1 = pso.tell(s, -np.sum((s.x - 60.0) ** 2, axis=1)).x
    rnd = pso.pso_init(7, 20, lo, hi)
    spread_transfer = np.linalg.norm(s.x - centre, axis=1).max()
    spread_random = np.linalg.norm(rnd.x - centre, axis=1).min()
    assert spread_transfer < 10.0 < spread_random
    # one move later the swarm is still far more concentrated than a random swarm
    assert np.mean(np.std(x1, axis=0)) < 0.2 * np.mean(np.std(rnd.x, axis=0))


def test_transfer_init_shape_checked():
    with pytest.raises(ValueError):
        pso.pso_init(0, 5, np.zeros(2), np.ones(2), init=np.zeros((4, 2)))


def test_search_space_size_scales_and_shrinks():
    lo, hi = np.zeros(3), np.array([1.0, 10.0, 100.0])
    r = np.random.default_rng(0)
    x = lo + r.random((200, 3)) * (hi - lo)
    s_full = pso.search_space_size(x, lo, hi)
    np.testing.assert_allclose(s_full, np.sqrt(1 / 12), rtol=0.1)  # uniform on [0, 1]
    small = lo + (0.5 + 0.1 * (r.random((200, 3)) - 0.5)) * (hi - lo)
    np.testing.assert_allclose(pso.search_space_size(small, lo, hi), 0.1 * s_full, rtol=0.15)
    # per generation along a converging run
    h, _ = pso.run_pso(sphere, 0, 20, 30, -5 * np.ones(4), 5 * np.ones(4))
    s = pso.search_space_size(h.positions, -5 * np.ones(4), 5 * np.ones(4))
    assert s.shape == (30,) and s[-1] < 0.1 * s[0]
