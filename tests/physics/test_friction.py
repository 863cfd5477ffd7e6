"""Directional (anisotropic) friction: a contact sphere with a body-fixed direction has
the Coulomb bounds mu_forward / mu_backward along it and mu across it."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, constraint, step, terrain

G = 9.81
MU_F, MU_B, MU_LAT = 0.2, 0.8, 0.5
DT = 0.005


def _skin_block(direction=(1.0, 0.0, 0.0), mu=(MU_LAT, MU_F, MU_B), vel=(0, 0, 0),
                dtype=jnp.float32, lift=0.002):
    """A 1 kg box on four contact spheres of material ``skin`` (lateral, forward,
    backward friction ``mu``) with friction ``direction`` (body frame; None: isotropic),
    ``lift`` above the level floor."""
    b = Builder("skin", dt=DT, solver_iterations=20, relaxation=0.5)
    b.add_material("skin", mu[0], 0.0, 50.0, 1.0, friction_forward=mu[1],
                   friction_backward=mu[2])
    b.add_plane("floor", (0, 0, 1), 0.0)
    # wide base: tipping would need mu > 1.5 (friction x CoM height 0.1 m against the
    # normal force x half-base 0.15 m), so each contact keeps a quarter of the load
    b.add_box("box", (0.4, 0.4, 0.1), (0, 0, 0.1 + lift), mass=1.0)
    for sx in (-0.15, 0.15):
        for sy in (-0.15, 0.15):
            b.add_contact_sphere("box", 0.05, (sx, sy, -0.05), material="skin",
                                 direction=direction)
    b.set_velocity("box", vel)
    return b.build(dtype)


def _velocities(m, s, n):
    def body(s, _):
        s = step(m, s, jnp.zeros((0,), s.pos.dtype))
        return s, s.vel[0]
    return np.asarray(jax.jit(lambda s: jax.lax.scan(body, s, None, length=n)[1])(s))


def _slope_acc(v, axis):
    t = np.arange(len(v)) * DT
    return np.polyfit(t[100:], v[100:, axis], 1)[0]


@pytest.mark.parametrize("heading_deg, angle_deg, direction, expect", [
    # slope rising along +x: gravity pulls towards -x
    (0, 20, (-1, 0, 0), ("slide", MU_F)),  # pulled forward: mu_forward 0.2 < tan 20 = 0.36
    (0, 20, (1, 0, 0), ("stick", MU_B)),  # pulled backward: mu_backward 0.8 > 0.36
    (0, 45, (1, 0, 0), ("slide", MU_B)),  # tan 45 = 1 > 0.8: slides backward anyway
    # slope rising along +y: pulled across the direction, lateral mu 0.5
    (90, 20, (1, 0, 0), ("stick", MU_LAT)),  # 0.36 < 0.5
    (90, 30, (1, 0, 0), ("slide", MU_LAT)),  # 0.58 > 0.5
])
def test_block_on_a_slope_has_the_coulomb_bound_of_its_sliding_direction(
        heading_deg, angle_deg, direction, expect):
    m, s = _skin_block(direction)
    th, h = np.deg2rad(angle_deg), np.deg2rad(heading_deg)
    v = _velocities(terrain.incline(m, th, h), s, 200)
    axis = 0 if heading_deg == 0 else 1
    kind, mu = expect
    if kind == "stick":
        # held, up to the creep and rocking of the 20-sweep parallel solver (~1 cm/s;
        # isotropic contacts creep alike), against >= 1 m/s after 1 s of sliding
        assert abs(v[100:, axis].mean()) < 0.03
    else:
        # Coulomb: a = g (sin - mu cos) down the slope
        np.testing.assert_allclose(_slope_acc(v, axis), -G * (np.sin(th) - mu * np.cos(th)),
                                   rtol=0.02)


def test_same_push_slides_one_way_and_sticks_the_other():
    """The same force (gravity on a 20 deg slope) on a block turned either way."""
    th = np.deg2rad(20.0)
    out = {}
    for name, d in (("forward", (-1.0, 0.0, 0.0)), ("backward", (1.0, 0.0, 0.0))):
        m, s = _skin_block(d)
        out[name] = _velocities(terrain.incline(m, th), s, 200)[-1, 0]
    assert out["forward"] < -1.0 and abs(out["backward"]) < 0.1


def test_equal_coefficients_equal_the_isotropic_cone(x64):
    """Direction along x with mu_f = mu_b = mu: the elliptic cone is the isotropic disc,
    so the slide is the same; the directional basis turns with the body, which yaws by
    round-off here (differences ~1e-7)."""
    vel = (2.0, 0.7, 0.0)
    m_iso, s_iso = _skin_block(None, (0.4, 0.4, 0.4), vel, jnp.float64)
    m_dir, s_dir = _skin_block((1.0, 0.0, 0.0), (0.4, 0.4, 0.4), vel, jnp.float64)
    assert not m_iso.directional and m_dir.directional
    np.testing.assert_allclose(_velocities(m_dir, s_dir, 150), _velocities(m_iso, s_iso, 150),
                               atol=1e-6)


def test_isotropic_models_have_no_directional_rows():
    m, s = _skin_block(None)
    rows = _rows(m, s)
    assert "fric_lo" not in rows and not m.directional
    m, s = _skin_block((0.0, 1.0, 0.0))
    rows = _rows(m, s)
    lo, hi = np.asarray(rows["fric_lo"]), np.asarray(rows["fric"])
    t1 = slice(m.n_rows - 3 * m.n_pair + m.n_pair, m.n_rows - m.n_pair)
    np.testing.assert_allclose(lo[t1], MU_F)
    np.testing.assert_allclose(hi[t1], MU_B)
    np.testing.assert_allclose(lo[m.n_rows - m.n_pair:], MU_LAT)


def _rows(m, s):
    from thesis.physics import collision, kinematics
    from thesis.physics.step import spring_geometry

    pos, rot, v0 = kinematics.extend(m, s.pos, s.rot, s.vel, s.angvel)
    fr = kinematics.joint_frames(m, pos, rot)
    dofs = kinematics.joint_coordinates(m, fr, v0)
    contacts = collision.detect(m, pos, rot)
    springs = spring_geometry(m, pos, rot)
    return constraint.scalar_rows(m, dofs, contacts, springs, v0, jnp.zeros((0,)))


def _pair_block(order, dtype=jnp.float32):
    """The skin block resting on a large static world sphere (a sphere pair); ``order``
    says which of the pair is sphere1 (body a)."""
    b = Builder("pair", dt=DT, solver_iterations=20, relaxation=0.5)
    b.add_material("skin", MU_LAT, 0.0, 50.0, 1.0, friction_forward=MU_F,
                   friction_backward=MU_B)
    b.add_box("box", (0.4, 0.4, 0.1), (0, 0, 0.102), mass=1.0)
    big = b.add_contact_sphere("world", 50.0, (0.0, 0.0, -50.0))
    for sx in (-0.15, 0.15):
        for sy in (-0.15, 0.15):
            i = b.add_contact_sphere("box", 0.05, (sx, sy, -0.05), direction=(-1, 0, 0))
            b.add_sphere_pair(*((i, big) if order == "block_first" else (big, i)), "skin")
    return b.build(dtype)


def test_direction_of_a_sphere_pair_either_way_round():
    """A directional sphere is body a or body b of a listed pair depending on the order
    of add_sphere_pair; the bounds follow the sphere either way."""
    th = np.deg2rad(20.0)
    acc = {}
    for order in ("block_first", "block_second"):
        m, s = _pair_block(order)
        assert set(np.asarray(m.pair_dir_sign).tolist()) == (
            {-1} if order == "block_first" else {1})
        acc[order] = _slope_acc(_velocities(terrain.incline(m, th), s, 200), 0)
    np.testing.assert_allclose(acc["block_first"], acc["block_second"], rtol=1e-3)
    # pulled forward: mu_forward, not mu_backward (which would hold the block); the
    # 50-m sphere's curvature steepens the slope by ~0.5 deg over the slide (+6 %)
    np.testing.assert_allclose(acc["block_first"], -G * (np.sin(th) - MU_F * np.cos(th)),
                               rtol=0.1)
    with pytest.raises(ValueError, match="both contact spheres have a friction direction"):
        b = Builder("bad")
        b.add_box("a", (0.1, 0.1, 0.1), (0, 0, 0))
        b.add_box("c", (0.1, 0.1, 0.1), (1, 0, 0))
        b.add_sphere_pair(b.add_contact_sphere("a", 0.1, direction=(1, 0, 0)),
                          b.add_contact_sphere("c", 0.1, direction=(1, 0, 0)))
        b.build()


def test_gradient_of_a_directional_slide_matches_finite_differences(x64):
    """Slide forward along the direction at 2 m/s: d(stop distance)/d(mu_forward) from
    jax.grad equals central differences, and mu_backward does not enter."""
    m, s = _skin_block((1.0, 0.0, 0.0), vel=(2.0, 0.0, 0.0), dtype=jnp.float64, lift=0.0)

    def final_x(mu_f, mu_b):
        mm = terrain.set_material(m, "skin", friction_forward=mu_f, friction_backward=mu_b)
        body = lambda s, _: (step(mm, s, jnp.zeros((0,), s.pos.dtype)), None)  # noqa: E731
        return jax.lax.scan(body, s, None, length=60)[0].pos[0, 0]

    f = jax.jit(final_x)
    gf, gb = jax.jit(jax.grad(final_x, argnums=(0, 1)))(MU_F, MU_B)
    fd = (f(MU_F + 1e-6, MU_B) - f(MU_F - 1e-6, MU_B)) / 2e-6
    assert np.isfinite(gf) and gf < 0  # more forward friction, shorter slide
    np.testing.assert_allclose(gf, fd, rtol=1e-5)
    assert abs(float(gb)) < 1e-9 * abs(float(gf))
