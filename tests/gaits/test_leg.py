"""Pantographic leg kinematics: forward map, numerical IK, reachable area (§3.3.1.2)."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from matplotlib.path import Path

from thesis.gaits import leg as L

G = L.oncilla_geometry()


def _joint_samples(n, seed=0, margin=1e-3):
    r = np.random.default_rng(seed)
    hip = r.uniform(G.hip_min + margin, G.hip_max - margin, n)
    knee = r.uniform(G.knee_min + margin, G.knee_max - margin, n)
    return hip, knee


def test_forward_straight_leg_and_pantograph():
    # a straight leg (knee = π) points along the hip angle with length femur+tibia+foot
    p = np.asarray(L.forward(G, 0.3, math.pi))
    total = G.femur + G.tibia + G.foot
    np.testing.assert_allclose(p, [total * math.sin(0.3), -total * math.cos(0.3)], atol=1e-6)
    # reach depends on the knee only (law of cosines on the two-link equivalent)
    for knee in (G.knee_min, 2.0, G.knee_max):
        r = [float(jnp.linalg.norm(L.forward(G, h, knee))) for h in (-0.4, 0.1, 0.9)]
        np.testing.assert_allclose(r, r[0], rtol=1e-6)
    np.testing.assert_allclose(jnp.linalg.norm(L.forward(G, 0.2, G.knee_max)), L.R_MAX,
                               rtol=1e-6)
    np.testing.assert_allclose(jnp.linalg.norm(L.forward(G, 0.2, G.knee_min)), L.R_MIN,
                               rtol=1e-6)


def test_encoder_convention_signs():
    # more hip angle moves the foot forward; more knee angle extends the leg (Fig. 6.4)
    p0 = L.forward(G, 0.3, 2.0)
    assert L.forward(G, 0.4, 2.0)[0] > p0[0]
    assert jnp.linalg.norm(L.forward(G, 0.3, 2.1)) > jnp.linalg.norm(p0)


def test_inverse_round_trip_over_reachable_area(x64):
    hip, knee = _joint_samples(2000)
    targets = L.forward(G, hip, knee)
    q = L.inverse(G, targets)
    back = L.forward(G, q[:, 0], q[:, 1])
    assert float(jnp.max(jnp.linalg.norm(back - targets, axis=-1))) < 1e-9
    np.testing.assert_allclose(q[:, 0], hip, atol=1e-7)  # the map is one-to-one
    np.testing.assert_allclose(q[:, 1], knee, atol=1e-7)


def test_inverse_float32_accuracy():
    hip, knee = _joint_samples(500, seed=1)
    targets = L.forward(G, jnp.float32(hip), jnp.float32(knee))
    q = L.inverse(G, targets)
    assert q.dtype == jnp.float32
    err = jnp.linalg.norm(L.forward(G, q[:, 0], q[:, 1]) - targets, axis=-1)
    assert float(jnp.max(err)) < 2e-6  # 2 µm


def test_inverse_matches_closed_form_oracle(x64):
    hip, knee = _joint_samples(300, seed=2)
    t = L.forward(G, hip, knee)
    np.testing.assert_allclose(L.inverse(G, t), L.inverse_closed_form(G, t), atol=1e-8)


def test_unreachable_targets_projected_to_limits(x64):
    # beyond full extension, straight down: knee at its extension stop, foot at R_MAX
    q = L.inverse(G, jnp.array([0.0, -0.20]))
    np.testing.assert_allclose(q[1], G.knee_max, atol=1e-9)
    p = L.forward(G, q[0], q[1])
    np.testing.assert_allclose(jnp.linalg.norm(p), L.R_MAX, rtol=1e-9)
    np.testing.assert_allclose(p[0], 0.0, atol=1e-4)
    # too close to the hip: knee at its flexion stop
    q = L.inverse(G, jnp.array([0.0, -0.07]))
    np.testing.assert_allclose(q[1], G.knee_min, atol=1e-9)
    lo, hi = np.asarray(G.lower), np.asarray(G.upper)
    q = np.asarray(L.inverse(G, jnp.array(np.random.default_rng(0).normal(0, 0.2, (200, 2)))))
    assert np.all(q >= lo - 1e-12) and np.all(q <= hi + 1e-12)


def test_reachable_mask_against_closed_form(x64):
    xs, zs = np.meshgrid(np.linspace(-0.2, 0.2, 81), np.linspace(-0.2, 0.0, 41))
    pts = np.stack([xs.ravel(), zs.ravel()], axis=-1)
    mask = np.asarray(L.reachable(G, pts))
    q = np.asarray(L.inverse_closed_form(G, pts))
    lo, hi = np.asarray(G.lower), np.asarray(G.upper)
    with np.errstate(invalid="ignore"):
        inside = np.isfinite(q).all(-1) & np.all((q >= lo) & (q <= hi), axis=-1)
    # compare away from a 1 mm band around the boundary
    poly = L.reach_boundary(G, 2000)
    dist = np.min(np.linalg.norm(pts[:, None, :] - poly[None], axis=-1), axis=1)
    far = dist > 1e-3
    assert inside[far].sum() > 200 and (~inside[far]).sum() > 200
    np.testing.assert_array_equal(mask[far], inside[far])
    # obviously unreachable points are flagged
    bad = np.array([[0.0, -0.2], [0.0, -0.05], [0.0, 0.1], [-0.16, -0.05], [0.3, -0.1]])
    assert not np.any(np.asarray(L.reachable(G, bad)))


def test_reach_boundary_encloses_reachable_area(x64):
    poly = L.reach_boundary(G, 300)
    assert np.all(np.asarray(L.reachable(G, poly, tol=1e-6)))
    r = np.random.default_rng(3)
    pts = r.uniform([-0.2, -0.2], [0.2, 0.0], (3000, 2))
    in_poly = Path(poly).contains_points(pts)
    mask = np.asarray(L.reachable(G, pts))
    assert in_poly.sum() > 300
    assert np.mean(in_poly == mask) > 0.995  # disagreement only within the polygon's chords


def test_reach_circle_bounds_stance_over_x0_range():
    # documented design property: over x0 ∈ [126, 158] mm the hip range never binds, so
    # the horizontal extent at depth x0 is ±sqrt(R_MAX² - x0²) (a_max of Tab. 4.1)
    x0 = np.linspace(0.126, 0.158, 17)
    ext = L.horizontal_extent(G, x0)
    circle = np.sqrt(L.R_MAX**2 - x0**2)
    np.testing.assert_allclose(ext[:, 1], circle, atol=2e-5)
    np.testing.assert_allclose(ext[:, 0], -circle, atol=2e-5)
    assert np.all(np.isnan(L.horizontal_extent(G, np.array([0.20]))))


def test_inverse_is_differentiable_and_vmappable(x64):
    q_true = jnp.array([0.4, 2.0])
    p = L.forward(G, q_true[0], q_true[1])
    J = jax.jacfwd(lambda q: L.forward(G, q[0], q[1]))(q_true)
    dq_dp = jax.jacfwd(lambda t: L.inverse(G, t))(p)
    np.testing.assert_allclose(dq_dp, np.linalg.inv(np.asarray(J)), rtol=1e-6, atol=1e-8)
    g = jax.grad(lambda t: jnp.sum(L.inverse(G, t) ** 2))(p)  # reverse mode
    np.testing.assert_allclose(g, 2 * np.asarray(dq_dp).T @ np.asarray(q_true), rtol=1e-6)
    batch = jnp.stack([p, p * 0.95])
    f = jax.jit(jax.vmap(lambda t: L.inverse(G, t)))
    np.testing.assert_allclose(f(batch), L.inverse(G, batch), atol=1e-12)
    # gradient with respect to a geometry parameter flows too
    dg = jax.jacfwd(lambda fem: jnp.sum(L.inverse(G.replace(femur=fem), p)))(G.femur)
    assert np.isfinite(float(dg)) and float(dg) != 0.0


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_forward3d_inverse3d_round_trip(x64, side):
    r = np.random.default_rng(4)
    hip, knee = _joint_samples(200, seed=5)
    scap = r.uniform(G.scapula_min, G.scapula_max, 200)
    p = L.forward3d(G, scap, hip, knee, side)
    q = L.inverse3d(G, p, side)
    np.testing.assert_allclose(q, np.stack([scap, hip, knee], -1), atol=1e-7)
    # abduction moves the foot outward: +y for a left leg, -y for a right leg
    out = L.forward3d(G, G.scapula_max, 0.5, 2.0, side)
    assert side * float(out[1]) > 0.0
    # the sagittal distance is preserved by the scapula rotation
    np.testing.assert_allclose(jnp.linalg.norm(p[:, 1:], axis=-1),
                               -L.forward(G, hip, knee)[:, 1], rtol=1e-9)


def test_scapula_range_sidewise_step():
    # §3.3.2.5: 5° adduction + 10° abduction give a sidewise step of about 4 cm at the
    # leg's depth (the thesis quotes 4.2 cm)
    d = 0.16
    lo = L.forward3d(G, G.scapula_min, 0.0, G.knee_max, 1.0)
    hi = L.forward3d(G, G.scapula_max, 0.0, G.knee_max, 1.0)
    step = float(hi[1] - lo[1])
    assert 0.03 < step < 0.05
    np.testing.assert_allclose(step, (math.sin(G.scapula_max) - math.sin(G.scapula_min))
                               * float(-L.forward(G, 0.0, G.knee_max)[1]), rtol=1e-6)
    assert d > 0


def test_hind_leg_reaches_tab_4_2_hind_foot(x64):
    """The hind leg (docs/sources.md#oncilla-hind-legs: hind knee motors 2200 counts vs
    1850; Tab. 4.2-4.4's hind feet up to 181.9 mm from the hip) reaches R_MAX_HIND at its extension stop,
    has 2200/1850 of the fore knee range, and at the stance depths of Tab. 4.1 reaches
    wider than the fore leg."""
    H = L.oncilla_hind_geometry()
    a, b = H.femur + H.foot, H.tibia
    reach = math.sqrt(a * a + b * b - 2 * a * b * math.cos(H.knee_max))
    assert reach == pytest.approx(L.R_MAX_HIND, abs=1e-9)
    assert (H.knee_max - H.knee_min) == pytest.approx(
        (G.knee_max - G.knee_min) * 2200 / 1850, rel=1e-12)
    assert (H.hip_min, H.hip_max) == (G.hip_min, G.hip_max)
    # Tab. 4.2's flat optimum: B of the hind locus at (y0_hind - a, -x0)
    b_hind = np.array([(-16.39 - 95.3) * 1e-3, -0.137])
    assert bool(L.reachable(H, b_hind, tol=2e-5))
    assert not bool(L.reachable(G, b_hind, tol=2e-5))
    # over x0 of Tab. 4.1 the hind leg's horizontal extent contains the fore leg's
    x0 = np.linspace(0.126, 0.158, 33)
    fore, hind = L.horizontal_extent(G, x0), L.horizontal_extent(H, x0)
    assert np.all(hind[:, 0] < fore[:, 0] - 0.015) and np.all(hind[:, 1] > fore[:, 1] + 0.015)


def test_inverse_legs_uses_each_legs_geometry(x64):
    legs = L.leg_geometries()
    assert legs[0] is legs[1] and legs[2] is legs[3] and legs[0] is not legs[2]
    r = np.random.default_rng(7)
    tgt = np.stack([np.stack([r.uniform(-0.05, 0.05, 30), r.uniform(-0.01, 0.01, 30),
                              r.uniform(-0.15, -0.13, 30)], -1) for _ in range(4)], axis=-2)
    q = L.inverse_legs(legs, tgt)
    assert q.shape == (30, 4, 3)
    for i, g in enumerate(legs):
        np.testing.assert_allclose(q[:, i], L.inverse3d(g, tgt[:, i], L.SIDES[i]), atol=1e-12)
        foot = L.forward3d(g, q[:, i, 0], q[:, i, 1], q[:, i, 2], L.SIDES[i])
        np.testing.assert_allclose(foot, tgt[:, i], atol=1e-7)
