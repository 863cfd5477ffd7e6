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


# --- energy-true rotation ------------------------------------------------------------

# A box with three distinct principal moments: (0.2, 0.5, 1.0) m, so I_y is the
# intermediate one; spun almost about y, it flips periodically (tennis-racket effect).
TUMBLE_SIZE = (0.2, 0.5, 1.0)
TUMBLE_W0 = (0.02, 5.0, 0.02)  # rad/s, body = world frame at t = 0


def _tumbling(dt, dtype, angvel=TUMBLE_W0, size=TUMBLE_SIZE):
    b = Builder("tumble", dt=dt, gravity=(0, 0, 0))
    b.add_box("box", size, (0, 0, 0))
    b.set_velocity("box", (0, 0, 0), angvel)
    return b.build(dtype)


def _tumble_trace(m, s, n):
    """Body-frame angular velocity (n, 3), kinetic energy (n,), world momentum (n, 3)."""
    inertia = m.body_inertia[0]

    def body(s, _):
        s = step(m, s, jnp.zeros((0,), s.pos.dtype))
        r, w = s.rot[0], s.angvel[0]
        wb = r.T @ w
        return s, (wb, 0.5 * wb @ inertia @ wb, r @ inertia @ wb)

    return jax.jit(lambda s: jax.lax.scan(body, s, None, length=n))(s)[1]


def _energy0(m, w0):
    w0 = np.asarray(w0, np.float64)
    return 0.5 * w0 @ np.asarray(m.body_inertia[0], np.float64) @ w0


def test_tumbling_body_keeps_energy_and_momentum_float32():
    """No gravity, no contacts, 10^4 steps at dt 1 ms, near the intermediate axis: the
    kinetic energy stays within 0.1 % (the explicit update gained a few per cent) and
    the world angular momentum is kept."""
    m, s = _tumbling(1e-3, jnp.float32)
    wb, ke, lw = (np.asarray(a, np.float64) for a in _tumble_trace(m, s, 10_000))
    e0 = _energy0(m, TUMBLE_W0)
    assert np.abs(ke / e0 - 1.0).max() < 1e-3
    l0 = np.asarray(m.body_inertia[0], np.float64) @ np.asarray(TUMBLE_W0)
    assert np.abs(lw - l0).max() < 1e-3 * np.linalg.norm(l0)
    assert wb[:, 1].min() < -4.0  # the test really covers a flip


def test_tumbling_body_keeps_energy_float64(x64):
    """In float64 the scheme keeps the momentum to round-off and the energy to the
    fixed-point iterations' convergence (4e-8 with two; the explicit update: 3e-2)."""
    m, s = _tumbling(1e-3, jnp.float64)
    wb, ke, lw = (np.asarray(a) for a in _tumble_trace(m, s, 10_000))
    e0 = _energy0(m, TUMBLE_W0)
    assert np.abs(ke / e0 - 1.0).max() < 2e-7
    l0 = np.asarray(m.body_inertia[0]) @ np.asarray(TUMBLE_W0)
    assert np.abs(lw - l0).max() < 1e-9 * np.linalg.norm(l0)


def test_fast_spinning_slender_body_does_not_gain_energy(x64):
    """At dt |w| = 0.5 (a 0.4 m bar at 50 rad/s, dt 10 ms) the iteration has not
    converged; each iterate is kept only where it lowers the residual, and the body loses
    a little energy instead of gaining it (the explicit update: +700 % in 20 s)."""
    b = Builder("bar", dt=1e-2, gravity=(0, 0, 0))
    b.add_box("bar", (0.02, 0.05, 0.4), (0, 0, 0))
    w0 = (30.0, 2.0, 40.0)
    b.set_velocity("bar", (0, 0, 0), w0)
    m, s = b.build(jnp.float64)
    wb, ke, lw = (np.asarray(a) for a in _tumble_trace(m, s, 2000))
    e0 = _energy0(m, w0)
    assert np.all(np.isfinite(ke))
    assert ke.max() < e0 * (1.0 + 1e-9)
    assert ke.min() > 0.9 * e0
    l0 = np.asarray(m.body_inertia[0]) @ np.asarray(w0)
    assert np.abs(lw - l0).max() < 1e-9 * np.linalg.norm(l0)


def _first_flip(t, wy):
    """Time of the first sign change of the intermediate-axis rate, linearly interpolated."""
    i = int(np.argmax(wy < 0.0))
    assert i > 0, "no flip"
    return t[i - 1] + (t[i] - t[i - 1]) * wy[i - 1] / (wy[i - 1] - wy[i])


def test_intermediate_axis_flip_time_matches_eulers_equations(x64):
    """The time of the first flip of the intermediate axis agrees with an accurate
    solution of Euler's equations I w' = (I w) x w (scipy, rtol 1e-12)."""
    from scipy.integrate import solve_ivp

    dt, n = 1e-3, 6000
    m, s = _tumbling(dt, jnp.float64)
    wb = np.asarray(_tumble_trace(m, s, n)[0])
    t_sim = dt * np.arange(1, n + 1)

    inertia = np.asarray(m.body_inertia[0])
    inv_i = np.linalg.inv(inertia)
    sol = solve_ivp(lambda t, w: inv_i @ np.cross(inertia @ w, w), (0.0, dt * n),
                    np.asarray(TUMBLE_W0, np.float64), method="DOP853", rtol=1e-12,
                    atol=1e-12, dense_output=True)
    t_ref = np.linspace(0.0, dt * n, 60_001)
    ref = sol.sol(t_ref)[1]
    flip_ref, flip_sim = _first_flip(t_ref, ref), _first_flip(t_sim, wb[:, 1])
    assert 0.3 < flip_ref < dt * n  # the flip happens inside the window
    # second order in dt: the phase error over one flip is far below a step's worth
    assert abs(flip_sim - flip_ref) < 2e-3 * flip_ref
    # and the whole body-rate history follows Euler's equations up to the flip
    i = t_sim < flip_ref
    np.testing.assert_allclose(wb[i], sol.sol(t_sim[i]).T, atol=2e-3 * np.linalg.norm(TUMBLE_W0))


def test_isotropic_body_keeps_its_angular_velocity(x64):
    """A body with isotropic inertia (a solid sphere) has no gyroscopic term: its
    angular velocity is unchanged step by step, and it turns about it by the Cayley
    angle 2 atan(dt |w| / 2), i.e. dt |w| to third order."""
    dt, w0 = 1e-3, np.array([3.0, -7.0, 11.0])
    b = Builder("ball", dt=dt, gravity=(0, 0, 0))
    b.add_sphere("ball", 0.1, (0, 0, 0))
    b.set_velocity("ball", (0, 0, 0), tuple(w0))
    m, s = b.build(jnp.float64)
    s1 = step(m, s, jnp.zeros((0,)))
    np.testing.assert_allclose(np.asarray(s1.angvel[0]), w0, rtol=1e-13)
    # rotation about w by 2 atan(dt |w| / 2)
    r = np.asarray(s1.rot[0])
    angle = np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1, 1))
    np.testing.assert_allclose(angle, 2 * np.arctan(dt * np.linalg.norm(w0) / 2), rtol=1e-9)
    np.testing.assert_allclose(r @ w0, w0, atol=1e-12)
    sn, tr = _run(m, s, 1000)
    np.testing.assert_allclose(np.asarray(sn.angvel[0]), w0, rtol=1e-12)


def test_rotation_update_gradients_finite(x64):
    """Gradients of the final pose through 200 steps, at a tumbling rate and at rest
    (w = 0, where a norm-based update would give NaN)."""
    m, s = _tumbling(1e-3, jnp.float64)

    def final(w):
        st = s.replace(angvel=s.angvel.at[0].set(w))
        st, _ = _run(m, st, 200)
        return jnp.sum(st.rot[0] * jnp.arange(9.0).reshape(3, 3)) + jnp.sum(st.angvel[0] ** 2)

    for w in (jnp.asarray(TUMBLE_W0), jnp.zeros(3)):
        g = np.asarray(jax.grad(final)(w))
        assert np.all(np.isfinite(g))
        assert np.abs(g).max() > 0.0
    # and the gradient agrees with a central difference at the tumbling rate
    w = jnp.asarray(TUMBLE_W0)
    g = np.asarray(jax.grad(final)(w))
    e = 1e-6
    fd = [(float(final(w.at[k].add(e))) - float(final(w.at[k].add(-e)))) / (2 * e)
          for k in range(3)]
    np.testing.assert_allclose(g, fd, rtol=1e-4, atol=1e-6)
