"""Static sphere fields: K nearest field spheres per contact sphere
from a uniform grid, at a cost that does not depend on the number of field spheres."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, batched_rollout, rollout, sensors, step, terrain
from thesis.physics.step import field_warm_start

G = 9.81
R_BALL = 0.05


def _ball_on_field(centres, radii, *, z0, vel=(0, 0, 0), k=2, floor=True, dtype=jnp.float32,
                   explicit=False, **field_kw):
    """A solid ball (r 5 cm) above a floor, and field spheres as a sphere field or, with
    ``explicit``, as world contact spheres listed in sphere pairs with the ball (the
    reference the field must reproduce)."""
    b = Builder("field", dt=0.002, solver_iterations=10, relaxation=0.5)
    b.add_material("m", 0.6, 0.0, 100.0, 1.0)
    if floor:
        b.add_plane("floor", (0, 0, 1), 0.0, "m")
    b.add_sphere("ball", R_BALL, (0.0, 0.0, z0), mass=1.0)
    ball = b.add_contact_sphere("ball", R_BALL)
    b.set_velocity("ball", vel)
    radii = np.broadcast_to(np.asarray(radii, float), (len(centres),))
    if explicit:
        for c, r in zip(centres, radii):
            b.add_sphere_pair(b.add_contact_sphere("world", r, c), ball, "m")
    else:
        b.add_sphere_field("pebbles", centres, radii, "m", k=k, **field_kw)
    return b.build(dtype)


def _run(m, s, n):
    none = lambda p, sens, mem, t: (jnp.zeros((0,), s.pos.dtype), mem)  # noqa: E731
    return jax.jit(lambda s: rollout(m, s, none, None, n, record=(
        "body_pos", "body_vel", "body_angvel", "contact_force")))(s)


def _scatter(n, seed=0, half=1.0, r=0.01):
    rng = np.random.default_rng(seed)  # test layout only
    xy = rng.uniform(-half, half, (n, 2))
    return np.c_[xy, np.full(n, r + 1e-3)]


def test_ball_rests_on_a_field_sphere_at_the_sum_of_the_radii():
    centres = _scatter(2000, r=0.1) * [1, 1, 1]
    centres[:, 2] = 0.1
    centres = centres[np.linalg.norm(centres[:, :2], axis=1) > 0.4]  # clear the middle
    centres = np.r_[[[0.0, 0.0, 0.1]], centres]
    m, s = _ball_on_field(centres, 0.1, z0=0.3, floor=False)
    fin, tr = _run(m, s, 400)
    z = np.asarray(tr["body_pos"])[-100:, 0, 2]
    np.testing.assert_allclose(z, 0.1 + 0.1 + R_BALL, atol=1e-4)
    np.testing.assert_allclose(np.asarray(tr["contact_force"])[-1, 0], G, rtol=1e-3)


def test_rolling_across_a_field_equals_explicit_pairs(x64):
    """A ball rolled over pebbles (r 1 cm, 1 mm above the floor) off its path's centre
    line: deflected sideways and lifted exactly as with every pebble listed as a sphere
    pair, while it touches no more than K = 2 pebbles at a time."""
    xs = np.arange(0.15, 1.2, 0.2)
    centres = np.c_[xs, np.where(np.arange(xs.size) % 2, 0.02, -0.03), np.full(xs.size, 0.011)]
    far = _scatter(300, seed=1, half=2.0)
    far = far[np.abs(far[:, 1]) > 0.3]  # a field around the path that the ball never meets
    centres = np.r_[centres, far]
    kw = dict(z0=R_BALL, vel=(1.5, 0.0, 0.0), dtype=jnp.float64)
    mf, sf = _ball_on_field(centres, 0.01, **kw)
    me, se = _ball_on_field(centres, 0.01, explicit=True, **kw)
    assert mf.n_rows == 3 + 3 * 2 and me.n_rows == 3 * (1 + centres.shape[0] + centres.shape[0])
    _, trf = _run(mf, sf, 500)
    _, tre = _run(me, se, 500)
    for key in ("body_pos", "body_vel", "body_angvel"):
        np.testing.assert_allclose(trf[key], tre[key], atol=1e-6, err_msg=key)
    y = np.asarray(trf["body_pos"])[:, 0, 1]
    z = np.asarray(trf["body_pos"])[:, 0, 2]
    assert np.abs(y).max() > 1e-3 and z.max() > R_BALL + 1e-3  # deflected and lifted
    np.testing.assert_allclose(trf["contact_force"], tre["contact_force"][:, :1], atol=1e-5)


def test_rows_do_not_grow_with_the_number_of_field_spheres():
    rows = []
    for n in (10, 10_000):
        m, _ = _ball_on_field(_scatter(n, half=20.0), 0.01, z0=R_BALL, k=3)
        rows.append((m.n_rows, m.n_contact, m.field_grid[2]))
        assert m.field_centre.shape[0] >= n
    assert rows[0][:2] == rows[1][:2] == (3 + 3 * 3, 1 + 3)


def test_gradients_finite_across_contact_onset():
    """Dropped onto a field sphere from 1 cm: finite gradients of the final state w.r.t.
    the initial state and the field's leaves (centres, radii) through the impact."""
    centres = np.array([[0.0, 0.0, 0.1], [0.5, 0.5, 0.1], [-0.4, 0.3, 0.1]])
    m, s = _ball_on_field(centres, 0.1, z0=0.26, floor=False)

    def loss(mm, s0):
        fin = jax.lax.fori_loop(0, 40, lambda i, x: step(mm, x, jnp.zeros((0,))), s0)
        return jnp.sum(fin.pos) + jnp.sum(fin.vel)

    gm, gs = jax.grad(loss, argnums=(0, 1))(m, s)
    for leaf in jax.tree.leaves((gm, gs)):
        assert bool(jnp.all(jnp.isfinite(leaf)))
    assert float(jnp.abs(gm.field_centre).max()) > 0.0  # the impact depends on the pebble


def test_set_field_swaps_layouts_in_one_compilation():
    centres = _scatter(400, half=1.0, r=0.02)
    m, s = _ball_on_field(centres, 0.02, z0=R_BALL, vel=(2.0, 0.0, 0.0),
                          bounds=((-1.0, -1.0), (1.0, 1.0)), capacity=8)
    traces = []

    def run(model):
        traces.append(1)
        fin = jax.lax.fori_loop(0, 300, lambda i, x: step(model, x, jnp.zeros((0,))), s)
        return fin.pos[0]

    f = jax.jit(run)
    a = np.asarray(f(m))
    b = np.asarray(f(terrain.set_field(m, _scatter(400, seed=7, half=1.0, r=0.02), 0.02)))
    flat = np.asarray(f(terrain.clear_field(m)))
    assert len(traces) == 1
    np.testing.assert_allclose(flat[1:], [0.0, R_BALL], atol=1e-3)  # rolls straight on
    assert flat[0] > 0.5
    assert np.abs(a - b).max() > 1e-3 and np.abs(a - flat).max() > 1e-3
    with pytest.raises(ValueError, match="outside the field's bounds"):
        terrain.set_field(m, [[3.0, 0.0, 0.02]], 0.02)
    with pytest.raises(ValueError, match="capacity"):
        terrain.set_field(m, np.zeros((9, 3)), 0.02)
    with pytest.raises(ValueError, match="too large"):
        terrain.set_field(m, np.zeros((1, 3)), 0.5)


def test_per_robot_field_layouts_equal_single_rollouts():
    bounds = ((-1.0, -1.0), (1.0, 1.0))
    layouts = [_scatter(300, seed=i, half=1.0, r=0.02) for i in (3, 4)]
    m, s = _ball_on_field(layouts[0], 0.02, z0=R_BALL, vel=(2.0, 0.3, 0.0), bounds=bounds,
                          capacity=8)
    models = [terrain.set_field(m, c, 0.02) for c in layouts]
    per_robot = {k: jnp.stack([getattr(x, k) for x in models])
                 for k in ("field_centre", "field_radius")}
    none = lambda p, sens, mem, t: (jnp.zeros((0,)), mem)  # noqa: E731
    states = jax.tree.map(lambda x: jnp.stack([x, x]), s)
    _, tr = jax.jit(lambda st: batched_rollout(m, st, none, None, 300, per_robot=per_robot,
                                               record=("body_pos",)))(states)
    for i, mi in enumerate(models):
        _, single = _run(mi, s, 300)
        np.testing.assert_allclose(tr["body_pos"][i], single["body_pos"], atol=1e-5)
    assert float(jnp.abs(tr["body_pos"][0] - tr["body_pos"][1]).max()) > 1e-3


def test_field_warm_start_follows_each_field_sphere_to_its_new_slot():
    m, _ = _ball_on_field(_scatter(50), 0.01, z0=R_BALL, k=3)
    n = m.n_rows
    imp = jnp.arange(n, dtype=jnp.float32) + 100.0
    old_id = jnp.asarray([5.0, 9.0, 12.0])
    new_id = jnp.asarray([9.0, 12.0, 20.0])  # 5 left, 20 came, 9 and 12 moved down a slot
    out = np.asarray(field_warm_start(m, imp, old_id, new_id))
    first = n - m.rows_per_contact * m.n_contact + m.n_pair
    for g in range(m.rows_per_contact):
        a = first + g * m.n_contact
        old = np.asarray(imp[a:a + 3])
        np.testing.assert_array_equal(out[a:a + 3], [old[1], old[2], 0.0])
    keep = np.ones(n, bool)
    for g in range(m.rows_per_contact):
        keep[first + g * m.n_contact:first + g * m.n_contact + 3] = False
    np.testing.assert_array_equal(out[keep], np.asarray(imp)[keep])


def test_builder_checks_the_field():
    b = Builder("bad")
    b.add_sphere("ball", 0.05, (0, 0, 0.1))
    b.add_contact_sphere("ball", 0.05)
    b.add_sphere_field("a", [[0.0, 0.0, 0.0]], 0.01)
    with pytest.raises(ValueError, match="one field per model"):
        b.add_sphere_field("b", [[0.0, 0.0, 0.0]], 0.01)
    b.field["cell_size"] = 0.03
    with pytest.raises(ValueError, match="cell_size"):
        b.build()
    b.field["cell_size"], b.field["capacity"] = None, 0
    with pytest.raises(ValueError, match="capacity"):
        b.build()
    b.field["capacity"], b.field["spheres"] = None, [3]
    with pytest.raises(ValueError, match="query spheres"):
        b.build()
