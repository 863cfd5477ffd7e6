"""The gait families read as the thesis wrote them: one test per family
draws the foot path of a published parameter vector (Tab. 3.1a, Tab. 3.1b; the sine gait
was tuned by hand and never published) and compares it with the geometry of Fig. 3.3 and
§3.3.1: the half ellipse's flat stance at depth x0 from A = y0 + a to B = y0 - a and its
swing of height b; the Bézier curves' endpoints A and B, their control points moved only
vertically by l0-l3 (l2, l3 shared by all four legs, "so the same stance trajectory is
applied to each leg"; l0, l1 per fore and hind pair); the fore and hind indexes on the
right legs; the duty t_stance f; the trot's 180-degree phase shift of adjacent legs.

Where the thesis does not settle a choice (which end of a curve l0 and l2 sit at: Fig.
3.3 is not in the text), the test pins the reading of thesis.gaits.trajectories so that a
change of reading is a visible decision."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.gaits import leg as L
from thesis.gaits import trajectories as T
from thesis.modelcheck import targets as TG

N = 400
PHASES = jnp.arange(N) / N


def _published(name):
    return next(g for g in TG.published_gaits() if g.name == name)


def _path(fam, params):
    """(N, 4, 3) foot targets [mm] over one cycle and (N, 4) leg phases."""
    tg = jax.vmap(lambda s: fam.foot_targets(jnp.asarray(params), s))(PHASES)
    return np.asarray(tg) * 1e3, np.asarray(T.leg_phases(PHASES))


def test_half_ellipse_of_tab_3_1a_is_fig_3_3a():
    fam = T.EllipseGait()
    g = _published("tab3_1a")
    P = dict(zip(fam.names, g.params))
    assert P["x0"] == 138.45 and P["a"] == 75.95 and P["b_fore"] == 13.69
    tg, s = _path(fam, g.params)
    x, depth = tg[..., 0], -tg[..., 2]
    stance = s < P["duty"]
    assert stance.mean() == pytest.approx(0.5, abs=1.0 / N)  # t_stance f = 0.5
    for leg, fore in enumerate(L.IS_FORE):
        y0 = P["y0_fore"] if fore else P["y0_hind"]
        b = P["b_fore"] if fore else P["b_hind"]
        st, sw = stance[:, leg], ~stance[:, leg]
        np.testing.assert_allclose(depth[st, leg], P["x0"], atol=1e-3)  # flat bottom at x0
        # stance from A (front) to B (back): the foot moves backwards, the robot forwards
        assert x[st, leg].max() == pytest.approx(y0 + P["a"], abs=1e-3)
        assert x[st, leg].min() == pytest.approx(y0 - P["a"], abs=0.8)
        order = np.argsort(s[st, leg])
        assert np.all(np.diff(x[st, leg][order]) < 0)
        # the swing: a half ellipse of semi-axes a (horizontal) and b (the height)
        assert P["x0"] - depth[sw, leg].min() == pytest.approx(b, abs=0.01)
        e = ((x[sw, leg] - y0) / P["a"]) ** 2 + ((P["x0"] - depth[sw, leg]) / b) ** 2
        np.testing.assert_allclose(e, 1.0, atol=1e-3)
    # hind swings higher than fore (b_hind 26.12 > b_fore 13.69): the indexes are not swapped
    assert (P["x0"] - depth[:, 2:].min()) > (P["x0"] - depth[:, :2].min()) + 10.0
    # trot: LF with RH, RF with LH, the pairs half a cycle apart
    np.testing.assert_allclose(s[:, 0], s[:, 3])
    np.testing.assert_allclose(np.mod(s[:, 0] + 0.5, 1.0), s[:, 1], atol=1e-6)
    # every point within the legs' reach (§3.3.1.2: only reachable half ellipses allowed)
    for leg, geom in enumerate(fam.legs):
        assert bool(jnp.all(L.reachable(geom, jnp.asarray(tg[:, leg, ::2] * 1e-3), tol=1e-3)))
    # theoretical speed of Fig. 3.4: the stance covers 2a in t_stance
    assert float(fam.speed(jnp.asarray(g.params))) == pytest.approx(
        2 * 75.95e-3 * 1.94 / 0.5)


def _cubic_bounds(l_first, l_second):
    """(low, high) of the largest offset of a cubic Bézier whose inner control points
    are moved by l_first and l_second: 3/8 (l1 + l2) at u = 1/2 <= max <= 3/4 max(l)."""
    return 0.375 * (l_first + l_second), 0.75 * max(l_first, l_second)


def test_spline_of_tab_3_1b_is_fig_3_3b():
    fam = T.SplineGait()
    g = _published("tab3_1b")
    P = dict(zip(fam.names, g.params))
    assert (P["l0_fore"], P["l0_hind"], P["l1_fore"], P["l1_hind"], P["l2"], P["l3"]) == \
        (68.0, 11.0, 63.0, 32.0, 63.0, 32.0)
    tg, s = _path(fam, g.params)
    x, depth = tg[..., 0], -tg[..., 2]
    stance = s < P["duty"]
    assert stance.mean() == pytest.approx(0.6, abs=1.0 / N)
    lo, hi = _cubic_bounds(P["l2"], P["l3"])
    stance_shape = []
    for leg, fore in enumerate(L.IS_FORE):
        y0 = P["y0_fore"] if fore else P["y0_hind"]
        st, sw = stance[:, leg], ~stance[:, leg]
        # the curves start and end at A = (y0 + a, x0) and B = (y0 - a, x0)
        a_pt = tg[np.argmin(s[:, leg]), leg]
        np.testing.assert_allclose([a_pt[0], -a_pt[2]], [y0 + P["a"], P["x0"]], atol=1e-3)
        assert x[st, leg].min() == pytest.approx(y0 - P["a"], abs=0.5)
        # the stance dips below x0 (P_i moved only vertically, by l2 and l3)
        dip = depth[st, leg].max() - P["x0"]
        assert lo - 1e-3 <= dip <= hi + 1e-3
        # with l2 > l3 the deepest point lies in the stance's front half (l2 at A)
        deepest = x[st, leg][np.argmax(depth[st, leg])]
        assert deepest > y0
        order = np.argsort(s[st, leg])
        stance_shape.append(np.stack([x[st, leg][order] - y0, depth[st, leg][order]], -1))
        # the swing lifts by its pair's l0, l1
        l0 = P["l0_fore"] if fore else P["l0_hind"]
        l1 = P["l1_fore"] if fore else P["l1_hind"]
        lo_s, hi_s = _cubic_bounds(l0, l1)
        lift = P["x0"] - depth[sw, leg].min()
        assert lo_s - 1e-3 <= lift <= hi_s + 1e-3
    # one stance trajectory for all four legs (up to each pair's y0)
    grid = np.linspace(-0.9 * P["a"], 0.9 * P["a"], 50)
    ref = np.interp(grid, stance_shape[0][::-1, 0], stance_shape[0][::-1, 1])
    for shape in stance_shape[1:]:
        np.testing.assert_allclose(np.interp(grid, shape[::-1, 0], shape[::-1, 1]), ref,
                                   atol=0.05)
    # fore legs (l0, l1 = 68, 63) lift much higher than hind ones (11, 32)
    assert (P["x0"] - depth[:, :2].min()) > (P["x0"] - depth[:, 2:].min()) + 20.0


def test_sine_gait_is_section_3_3_1_1():
    """§3.3.1.1: hip and knee follow sine signals in joint space, one frequency, left and
    right legs with the same parameters half a cycle apart, the scapulae constant. The
    thesis never printed its hand-tuned vector; this one lies inside the family's box."""
    fam = T.SineGait()
    p = 0.5 * (fam.lower + fam.upper)
    p[fam.index("hip_amp_fore")] = 0.2
    p[fam.index("hip_amp_hind")] = 0.3
    p[fam.index("f")] = 1.0
    cmd = np.asarray(jax.vmap(lambda s: fam.commands_at_phase(jnp.asarray(p), s))(PHASES))
    c = cmd.reshape(N, 4, 3)
    np.testing.assert_array_equal(c[..., 0], 0.0)  # scapulae constant 0
    # left and right of a pair: the same signals half a cycle apart
    np.testing.assert_allclose(np.roll(c[:, 0], -N // 2, axis=0), c[:, 1], atol=1e-6)
    np.testing.assert_allclose(np.roll(c[:, 2], -N // 2, axis=0), c[:, 3], atol=1e-6)
    # the hip is offset + amplitude sin: its range is twice the pair's amplitude
    assert np.ptp(c[:, 0, 1]) == pytest.approx(0.4, abs=1e-3)
    assert np.ptp(c[:, 2, 1]) == pytest.approx(0.6, abs=1e-3)
    # the foot path (forward kinematics) is a closed loop in the leg's plane
    foot = np.asarray(L.forward(fam.geom, c[:, 0, 1], c[:, 0, 2]))
    assert np.ptp(foot[:, 0]) > 0.02
    tpl = np.asarray(fam.commands(jnp.asarray(p), 1.0))
    np.testing.assert_allclose(tpl, cmd[0], atol=1e-5)  # period 1 / f
