"""integrator.py: semi-implicit Euler against closed forms, its order, eq. 7.1 and momentum."""

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics import Builder, step


def _free_body(dt, vel=(0, 0, 0), angvel=(0, 0, 0), gravity=(0, 0, -9.81), size=(0.5, 0.5, 0.5)):
    b = Builder("free", dt=dt, gravity=gravity)
    b.add_box("box", size, (0.0, 0.0, 10.0))
    b.set_velocity("box", vel, angvel)
    return b.build(jnp.float32)


def _run(m, s, n):
    f = jax.jit(lambda s: jax.lax.scan(lambda s, _: (step(m, s, jnp.zeros((0,))), s.pos[0]),
                                       s, None, length=n))
    return f(s)


def test_free_fall_and_projectile_against_closed_form():
    dt, n = 0.01, 100
    m, s = _free_body(dt, vel=(2.0, -1.0, 3.0))
    s, _ = _run(m, s, n)
    t = n * dt
    exact = np.array([2.0 * t, -1.0 * t, 10.0 + 3.0 * t - 0.5 * 9.81 * t * t])
    # semi-implicit Euler: z_n = z0 + v0 t - g dt^2 n (n + 1) / 2, i.e. an O(dt) offset
    err = np.abs(np.asarray(s.pos[0]) - exact)
    assert err[0] < 1e-4 and err[1] < 1e-4
    np.testing.assert_allclose(err[2], 0.5 * 9.81 * dt * t, rtol=1e-3)
    np.testing.assert_allclose(np.asarray(s.vel[0]), [2.0, -1.0, 3.0 - 9.81 * t], atol=1e-4)


def test_empirical_order_is_one(x64):
    errs, dts = [], [0.02, 0.01, 0.005]
    for dt in dts:
        b = Builder("free", dt=dt)
        b.add_box("box", (1, 1, 1), (0, 0, 0))
        m, s = b.build(jnp.float64)
        s, _ = _run(m, s, int(round(1.0 / dt)))
        errs.append(abs(float(s.pos[0, 2]) + 0.5 * 9.81))
    slope = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    assert abs(slope - 1.0) < 0.05  # declared order of semi-implicit Euler


def test_rotation_stays_orthonormal_over_10k_steps():
    m, s = _free_body(0.01, angvel=(3.0, -7.0, 11.0), gravity=(0, 0, 0), size=(0.3, 0.6, 1.0))
    s, _ = _run(m, s, 10_000)
    r = np.asarray(s.rot[0], np.float64)
    assert np.abs(r.T @ r - np.eye(3)).max() < 1e-5
    assert np.all(np.isfinite(np.asarray(s.angvel)))


def test_angular_momentum_conserved_free_asymmetric_body(x64):
    b = Builder("spin", dt=0.005, gravity=(0, 0, 0))
    b.add_box("box", (0.2, 0.5, 1.0), (0, 0, 0))
    b.set_velocity("box", (0, 0, 0), (2.0, 1.0, 3.0))
    m, s = b.build(jnp.float64)

    def momentum(s):
        r, i = s.rot[0], m.body_inertia[0]
        return r @ i @ r.T @ s.angvel[0]

    l0 = np.asarray(momentum(s))
    s2, _ = _run(m, s, 2000)
    np.testing.assert_allclose(np.asarray(momentum(s2)), l0, rtol=1e-9, atol=1e-9)
    # the body really tumbles: its world angular velocity is not constant
    w0, w1 = np.asarray(s.angvel[0]), np.asarray(s2.angvel[0])
    assert np.linalg.norm(w1 - w0) > 0.1 * np.linalg.norm(w0)


def test_angular_momentum_conserved_jointed_bodies(x64):
    """Two boxes linked by a ball joint, no gravity: total angular momentum about the
    centre of mass stays constant (constraint impulses are internal)."""
    b = Builder("pair", dt=0.002, gravity=(0, 0, 0), solver_iterations=30)
    b.add_box("a", (0.4, 0.2, 0.2), (-0.2, 0, 0))
    b.add_box("b", (0.4, 0.2, 0.2), (0.2, 0, 0))
    b.add_ball("j", "a", "b", (0, 0, 0))
    b.set_velocity("a", (0, 0.5, 0), (0, 0, 2.0))
    b.set_velocity("b", (0, -0.5, 0.3), (1.0, 0, -1.0))
    m, s = b.build(jnp.float64)

    def momentum(s):
        mass = m.body_mass[:, None]
        orbital = jnp.sum(jnp.cross(s.pos, mass * s.vel), 0)
        spin = jnp.einsum("nab,nbc,ndc,nd->a", s.rot, m.body_inertia, s.rot, s.angvel)
        return orbital + spin

    l0 = np.asarray(momentum(s))
    s2, _ = _run(m, s, 1000)
    assert np.abs(np.asarray(momentum(s2)) - l0).max() < 2e-3 * np.linalg.norm(l0)
