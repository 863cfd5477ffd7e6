"""Gait families of §3.3.1 / §4.2: layouts, bounds, periodicity, loci through FK."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.gaits import leg as L
from thesis.gaits import trajectories as T

G = L.oncilla_geometry()
H = L.oncilla_hind_geometry()
LEG_GEOMS = L.leg_geometries()


def _fk_all(q12):
    """(..., 12) joint commands -> (..., 4, 3) foot positions in the hip frames, each leg
    through its own geometry."""
    q = q12.reshape(q12.shape[:-1] + (4, 3))
    return jnp.stack([L.forward3d(g, q[..., i, 0], q[..., i, 1], q[..., i, 2], L.SIDES[i])
                      for i, g in enumerate(LEG_GEOMS)], axis=-2)


@pytest.fixture(scope="module")
def fams():
    return {"sine": T.SineGait(), "ellipse": T.EllipseGait(), "spline": T.SplineGait()}


def _params(fam, **kw):
    p = 0.5 * (fam.lower + fam.upper)
    for k, v in kw.items():
        p[fam.index(k)] = v
    return p


ELLIPSE = dict(x0=140.0, a=60.0, y0_fore=5.0, y0_hind=-10.0, b_fore=20.0, b_hind=25.0,
               duty=0.55, f=1.8)
SPLINE = dict(f=1.7, a=55.0, x0=135.0, y0_fore=0.0, y0_hind=-8.0, duty=0.5, l0_fore=30.0,
              l1_fore=20.0, l0_hind=25.0, l1_hind=35.0, l2=10.0, l3=5.0)


def test_layouts_and_bounds(fams):
    assert len(fams["spline"].names) == 12  # "In total, there are therefore 12 parameters"
    assert len(fams["ellipse"].names) == 8  # Tab. 3.1a
    assert len(fams["sine"].names) == 13
    for fam in fams.values():
        assert fam.lower.shape == fam.upper.shape == (len(fam.names),)
        assert len(fam.units) == len(fam.names)
        assert np.all(fam.lower <= fam.upper)
    sp = fams["spline"]
    for name, lo, hi in [("f", 1.5, 2.0), ("x0", 126, 158), ("duty", 0.4, 0.6),
                         ("l0_fore", 0, 70), ("l2", 0, 70), ("l3", 0, 70)]:
        assert (sp.lower[sp.index(name)], sp.upper[sp.index(name)]) == (lo, hi)


@pytest.mark.parametrize("name", ["sine", "ellipse", "spline"])
def test_commands_finite_periodic_and_jittable(fams, name):
    fam = fams[name]
    p = fam.project(_params(fam, **(ELLIPSE if name == "ellipse" else
                                    SPLINE if name == "spline" else {})))
    f = float(fam.frequency(p))
    t = jnp.arange(0.0, 1.0, 0.01)  # commands every 10 ms (§3.2.2)
    run = jax.jit(jax.vmap(fam.commands, in_axes=(None, 0)))
    c0 = run(jnp.asarray(p), t)
    c1 = run(jnp.asarray(p), t + 1.0 / f)
    assert c0.shape == (100, 12) and bool(jnp.all(jnp.isfinite(c0)))
    np.testing.assert_allclose(c0, c1, atol=2e-4)
    # not constant, and not periodic at half the period (a real full cycle)
    assert float(jnp.ptp(c0[:, 1])) > 0.05
    np.testing.assert_array_equal(np.asarray(c0), np.asarray(run(jnp.asarray(p), t)))
    # joint limits respected
    q = np.asarray(c0).reshape(-1, 4, 3)
    for legs, g in ((slice(0, 2), G), (slice(2, 4), H)):
        assert np.all(q[:, legs, 1] >= g.hip_min - 1e-6)
        assert np.all(q[:, legs, 1] <= g.hip_max + 1e-6)
        assert np.all(q[:, legs, 2] >= g.knee_min - 1e-6)
        assert np.all(q[:, legs, 2] <= g.knee_max + 1e-6)
    # vmap over a batch of particles (one generation in one call)
    P = np.stack([p, fam.project(fam.lower + 0.3 * (fam.upper - fam.lower))])
    cb = jax.jit(jax.vmap(fam.commands, in_axes=(0, None)))(jnp.asarray(P), 0.37)
    np.testing.assert_allclose(cb[0], fam.commands(jnp.asarray(p), 0.37), atol=1e-5)


@pytest.mark.parametrize("name", ["sine", "ellipse", "spline"])
def test_trot_phasing(fams, name):
    fam = fams[name]
    p = jnp.asarray(fam.project(_params(fam, **(ELLIPSE if name == "ellipse" else
                                                SPLINE if name == "spline" else {}))))
    ph = jnp.linspace(0.0, 1.0, 40, endpoint=False)
    c = jax.vmap(lambda s: fam.commands_at_phase(p, s))(ph).reshape(40, 4, 3)
    c_half = jax.vmap(lambda s: fam.commands_at_phase(p, s + 0.5))(ph).reshape(40, 4, 3)
    # left and right legs of a pair are half a cycle apart (hip, knee)
    np.testing.assert_allclose(c[:, 0, 1:], c_half[:, 1, 1:], atol=1e-4)  # LF vs RF
    np.testing.assert_allclose(c[:, 2, 1:], c_half[:, 3, 1:], atol=1e-4)  # LH vs RH
    assert float(jnp.max(jnp.abs(c[:, 0, 1:] - c[:, 1, 1:]))) > 0.05
    np.testing.assert_allclose(T.leg_phases(0.3), [0.3, 0.8, 0.8, 0.3], atol=1e-6)


def test_ellipse_locus_shape_and_tracking(fams):
    fam = fams["ellipse"]
    p = jnp.asarray(fam.project(_params(fam, **ELLIPSE)))
    ph = jnp.linspace(0.0, 1.0, 200, endpoint=False)
    tgt = jax.vmap(lambda s: fam.foot_targets(p, s))(ph)  # (200, 4, 3)
    cmd = jax.jit(jax.vmap(lambda s: fam.commands_at_phase(p, s)))(ph)
    np.testing.assert_allclose(_fk_all(cmd), tgt, atol=3e-6)  # FK(IK(target)) = target
    s = np.asarray(T.leg_phases(ph))  # (200, 4)
    x_mm, depth = np.asarray(tgt[..., 0]) * 1e3, -np.asarray(tgt[..., 2]) * 1e3
    stance = s < ELLIPSE["duty"]
    np.testing.assert_allclose(depth[stance], ELLIPSE["x0"], atol=1e-3)  # flat bottom
    for leg, (y0, b) in enumerate([(5.0, 20.0), (5.0, 20.0), (-10.0, 25.0), (-10.0, 25.0)]):
        sw = ~stance[:, leg]
        e = ((x_mm[sw, leg] - y0) / ELLIPSE["a"]) ** 2 + ((ELLIPSE["x0"] - depth[sw, leg]) / b) ** 2
        np.testing.assert_allclose(e, 1.0, atol=1e-3)  # on the half ellipse
        assert np.all(depth[sw, leg] <= ELLIPSE["x0"] + 1e-6)  # above the stance line
        assert np.isclose(x_mm[stance[:, leg], leg].max(), y0 + 60.0, atol=2.0)  # A
    np.testing.assert_allclose(np.asarray(tgt[..., 1]), 0.0, atol=1e-12)  # no yaw


def test_ellipse_too_high_gets_the_dent(fams):
    fam = fams["ellipse"]
    p = jnp.asarray(fam.project(_params(fam, **{**ELLIPSE, "x0": 126.0, "b_fore": 70.0})))
    ph = jnp.linspace(0.0, 1.0, 100, endpoint=False)
    tgt = jax.vmap(lambda s: fam.foot_targets(p, s))(ph)[:, 0]
    cmd = jax.jit(jax.vmap(lambda s: fam.commands_at_phase(p, s)))(ph).reshape(100, 4, 3)
    foot = _fk_all(cmd.reshape(100, 12))[:, 0]
    r_tgt = np.linalg.norm(np.asarray(tgt), axis=-1)
    r_foot = np.linalg.norm(np.asarray(foot), axis=-1)
    assert r_tgt.min() < L.R_MIN - 0.02  # the target goes above the flexion stop ...
    assert r_foot.min() > L.R_MIN - 1e-5  # ... the commanded foot does not: the dent
    np.testing.assert_allclose(cmd[:, 0, 2].min(), G.knee_min, atol=1e-6)


def test_spline_locus_endpoints_and_tracking(fams):
    fam = fams["spline"]
    p = jnp.asarray(fam.project(_params(fam, **SPLINE)))
    duty = SPLINE["duty"]
    A = fam.foot_targets(p, 0.0)[0]
    B = fam.foot_targets(p, duty - 1e-9)[0]
    np.testing.assert_allclose(np.asarray(A) * 1e3, [SPLINE["y0_fore"] + 55.0, 0, -135.0],
                               atol=1e-4)
    np.testing.assert_allclose(np.asarray(B) * 1e3, [SPLINE["y0_fore"] - 55.0, 0, -135.0],
                               atol=1e-3)
    ph = jnp.linspace(0.0, 1.0, 200, endpoint=False)
    tgt = jax.vmap(lambda s: fam.foot_targets(p, s))(ph)
    cmd = jax.jit(jax.vmap(lambda s: fam.commands_at_phase(p, s)))(ph)
    assert bool(jnp.all(L.reachable(G, jnp.stack([tgt[..., 0], tgt[..., 2]], -1))))
    np.testing.assert_allclose(_fk_all(cmd), tgt, atol=3e-6)
    # apex of the fore swing: Bézier with heights l1, l0 peaks at max of the cubic
    u = np.linspace(0, 1, 2001)
    h = 3 * (1 - u) ** 2 * u * 20.0 + 3 * (1 - u) * u**2 * 30.0
    depth = -np.asarray(tgt[:, 0, 2]) * 1e3
    np.testing.assert_allclose(135.0 - depth.min(), h.max(), atol=0.05)
    # the curved stance dips below the stance line (l2, l3 > 0)
    assert depth.max() > 135.0 + 0.375 * (10.0 + 5.0) - 0.05


def test_spline_approximates_half_ellipse():
    # §3.3.1.3: "For certain parameter values, these can approximate the half ellipses"
    sp, el = T.SplineGait(), T.EllipseGait()
    b = 24.0
    ps = sp.project(_params(sp, **{**SPLINE, "l0_fore": 4 * b / 3, "l1_fore": 4 * b / 3}))
    pe = el.project(_params(el, **{**ELLIPSE, "x0": 135.0, "a": 55.0, "y0_fore": 0.0,
                                   "b_fore": b, "duty": 0.5}))
    ph = jnp.linspace(0.5, 1.0, 101)
    ts = jax.vmap(lambda s: sp.foot_targets(jnp.asarray(ps), s))(ph)[:, 0]
    te = jax.vmap(lambda s: el.foot_targets(jnp.asarray(pe), s))(ph)[:, 0]
    assert float(jnp.max(jnp.abs(ts[:, 2].min() - te[:, 2].min()))) < 1e-6  # same apex
    # shapes close: max vertical gap at matching x below 15 % of b
    xs = np.asarray(ts[:, 0])
    order = np.argsort(np.asarray(te[:, 0]))
    ze = np.interp(xs, np.asarray(te[order, 0]), np.asarray(te[order, 2]))
    assert np.max(np.abs(ze - np.asarray(ts[:, 2]))) < 0.15 * b * 1e-3


def test_project_keeps_A_and_B_reachable(fams):
    r = np.random.default_rng(0)
    for name in ("ellipse", "spline"):
        fam = fams[name]
        P = fam.project(r.uniform(fam.lower - 20, fam.upper + 20, (300, len(fam.names))))
        assert np.all(P >= fam.lower - 1e-9) and np.all(P <= fam.upper + 1e-9)
        x0, a = P[:, fam.index("x0")], P[:, fam.index("a")]
        assert np.all(a <= fam.table.a_max(x0) + 1e-9)
        assert np.all(a <= fam.hind_table.a_max(x0) + 1e-9)
        for yname, geom in (("y0_fore", G), ("y0_hind", H)):
            y0 = P[:, fam.index(yname)]
            pts = [np.stack([y0 + a, -x0], -1), np.stack([y0 - a, -x0], -1)]
            mask = L.reachable(geom, np.concatenate(pts) * 1e-3, tol=2e-5)
            assert bool(jnp.all(mask)), yname
        np.testing.assert_allclose(fam.project(P), P)  # idempotent
    # a_max follows the reach circle: a_max(x0) = sqrt(R² - x0²)
    sp = fams["spline"]
    np.testing.assert_allclose(sp.table.a_max(np.array([126.0, 158.0])),
                               np.sqrt(167.0**2 - np.array([126.0, 158.0]) ** 2), atol=0.05)


def test_theoretical_speed_matches_stance_foot_speed(fams):
    fam = fams["ellipse"]
    p = fam.project(_params(fam, **ELLIPSE))
    v = float(fam.speed(p))
    np.testing.assert_allclose(v, 2 * 0.060 * 1.8 / 0.55, rtol=1e-6)
    f = ELLIPSE["f"]
    t = jnp.linspace(0.0, ELLIPSE["duty"] / f, 50)[1:-1]  # inside LF's stance
    x = jax.vmap(lambda s: fam.foot_targets(jnp.asarray(p), f * s)[0, 0])(t)
    speed = -np.diff(np.asarray(x)) / np.diff(np.asarray(t))
    np.testing.assert_allclose(speed, v, rtol=1e-3)  # foot moves back at v in stance
    # broadcasting: the Fig. 3.4 line over frequencies
    line = T.theoretical_speed(60.0, jnp.linspace(0.5, 2.5, 5), 0.5)
    np.testing.assert_allclose(line, 0.24 * np.linspace(0.5, 2.5, 5), rtol=1e-6)


def test_yaw_turns_loci_with_scapulae(fams):
    fam = fams["ellipse"]
    p = jnp.asarray(fam.project(_params(fam, **{**ELLIPSE, "a": 40.0})))
    yaw = jnp.deg2rad(jnp.array([5.0, 5.0, -5.0, -5.0]))  # fore and hind opposite (§3.3.2.5)
    ph = jnp.linspace(0.0, 1.0, 60, endpoint=False)
    tgt = jax.vmap(lambda s: fam.foot_targets(p, s, yaw))(ph)
    cmd = jax.jit(jax.vmap(lambda s: fam.commands_at_phase(p, s, yaw)))(ph)
    assert float(jnp.max(jnp.abs(tgt[..., 1]))) > 0.003
    assert float(jnp.max(jnp.abs(cmd.reshape(60, 4, 3)[..., 0]))) > 0.01
    np.testing.assert_allclose(_fk_all(cmd), tgt, atol=5e-6)
    # rotation keeps the locus' horizontal extent (a rigid rotation about its centre)
    dx = tgt[:, 0, 0] - float(p[fam.index("y0_fore")]) * 1e-3
    np.testing.assert_allclose(jnp.max(jnp.hypot(dx, tgt[:, 0, 1])), 0.040, rtol=1e-3)


def test_command_series_matches_commands(fams):
    fam = fams["spline"]
    p = jnp.asarray(fam.project(_params(fam, **SPLINE)))
    tab = jax.jit(lambda q: T.command_series(fam, q, 50))(p)
    assert tab.shape == (50, 12)
    np.testing.assert_allclose(tab[17], fam.commands(p, 17 * T.COMMAND_DT), atol=1e-5)
    batch = jax.vmap(lambda q: T.command_series(fam, q, 5))(jnp.stack([p, p]))
    assert batch.shape == (2, 5, 12)


@pytest.mark.parametrize("cls", [T.EllipseGait, T.SplineGait])
def test_walk_phasing_shifts_each_leg(cls):
    """A family built with ``WALK_PHASE`` gives each leg the trot family's commands of
    that leg at its own phase offset; the default is the trot, unchanged."""
    trot, walk = cls(), cls(phase_offsets=T.WALK_PHASE)
    p = jnp.asarray(trot.project(_params(trot, **(ELLIPSE if cls is T.EllipseGait else SPLINE))))
    ph = jnp.linspace(0.0, 1.0, 24, endpoint=False)
    c_walk = jax.vmap(lambda s: walk.commands_at_phase(p, s))(ph).reshape(24, 4, 3)
    for leg, (w_off, t_off) in enumerate(zip(T.WALK_PHASE, T.TROT_PHASE)):
        c_trot = jax.vmap(lambda s: trot.commands_at_phase(p, s + w_off - t_off))(ph)
        np.testing.assert_allclose(c_walk[:, leg], c_trot.reshape(24, 4, 3)[:, leg], atol=1e-5)
    explicit = cls(phase_offsets=T.TROT_PHASE)
    np.testing.assert_array_equal(trot.commands_at_phase(p, 0.3),
                                  explicit.commands_at_phase(p, 0.3))
    assert len(set(T.WALK_PHASE)) == 4  # every leg its own phase
    np.testing.assert_allclose(T.leg_phases(0.3, T.WALK_PHASE), [0.55, 0.05, 0.3, 0.8],
                               atol=1e-6)


def test_hind_offsets_of_tab_4_2_kept_fore_clipped(fams):
    """Tab. 4.2's flat optimum (x0 137 mm, a 95.3 mm, y0_hind -16.39 mm) puts the hind
    foot's B 181 mm from the hip: the hind legs reach it, so the projection keeps the
    offset; a fore leg could not (its offset range at that a is ~0)."""
    sp = fams["spline"]
    p = _params(sp, x0=137.0, a=95.3, y0_fore=0.0, y0_hind=-16.39)
    q = sp.project(p)
    assert q[sp.index("a")] == pytest.approx(95.3, abs=0.05)
    assert q[sp.index("y0_hind")] == pytest.approx(-16.39, abs=1e-9)
    lo, hi = sp.table.y0_range(137.0, 95.3)
    assert hi - lo < 0.5  # the fore pair is on its reach circle: y0_fore pinned near 0
    p2 = _params(sp, x0=137.0, a=95.3, y0_fore=-16.39, y0_hind=0.0)
    assert sp.project(p2)[sp.index("y0_fore")] > -0.25


def test_sine_gait_clips_each_pair_to_its_knee_range(fams):
    sine = fams["sine"]
    p = 0.5 * (sine.lower + sine.upper)
    for side in ("fore", "hind"):
        p[sine.index(f"knee_amp_{side}")] = 0.0
        p[sine.index(f"knee_offset_{side}")] = -10.0  # below every knee stop
    q = np.asarray(sine.commands_at_phase(jnp.asarray(p), 0.1)).reshape(4, 3)
    np.testing.assert_allclose(q[:, 2], [G.knee_min, G.knee_min, H.knee_min, H.knee_min],
                               atol=1e-6)
