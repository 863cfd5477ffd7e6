"""Chapter 4's conditions as model leaves, the speed-only fitness and the treadmill order
(no simulation)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from thesis.config import load_config
from thesis.gaits import conditions as C
from thesis.gaits import runner as R
from thesis.ch4 import transfer_runs as TR


@pytest.fixture(scope="module")
def cfg():
    return load_config("smoke")["ch4"]


def test_slopes_rotate_gravity_uphill_forward(cfg):
    flat, _ = C.condition_model(cfg, "flat")
    for grade, deg in ((9, 5.14), (18, 10.2)):
        m, _ = C.condition_model(cfg, C.grade_name(grade))
        g = np.asarray(m.gravity, float)
        assert np.linalg.norm(g) == pytest.approx(np.linalg.norm(np.asarray(flat.gravity)), 1e-6)
        assert math.degrees(math.atan2(-g[0], -g[2])) == pytest.approx(deg, abs=0.01)
        assert g[0] < 0 and g[1] == 0  # a robot walking along +x climbs
    assert C.condition_names(cfg) == ("grade9", "grade18", "compliant", "pebbly")


def test_soft_front_legs_halve_only_the_front_knee_springs(cfg):
    flat, _ = C.condition_model(cfg, "flat")
    soft, _ = C.condition_model(cfg, "compliant")
    k0, k1 = np.asarray(flat.jspring_k), np.asarray(soft.jspring_k)
    idx = C.front_spring_index(flat)
    names = [flat.dof_names[int(d)] for d in flat.jspring_dof]
    assert [names[i].split(":")[0] for i in idx] == ["LF_cable", "RF_cable"]
    np.testing.assert_allclose(k1[idx], 0.5 * k0[idx])
    rest = np.setdiff1d(np.arange(k0.size), idx)
    np.testing.assert_array_equal(k1[rest], k0[rest])
    with pytest.raises(ValueError, match="unknown ch4 condition"):
        C.condition_model(cfg, "grade30")


def test_every_condition_has_the_safety_thread_and_untethered_never_pulls(cfg):
    m, _ = C.condition_model(cfg, "grade18")
    assert m.tether_names == ("thread",)
    np.testing.assert_allclose(np.asarray(m.tether_slack), cfg["tether"]["slack"], rtol=1e-6)
    bare = C.untethered(m)
    assert np.asarray(bare.tether_slack).min() >= 100.0
    np.testing.assert_array_equal(np.asarray(bare.tether_k), np.asarray(m.tether_k))


def _rolled(model, state, angle):
    """Trunk rotation of ``state`` rolled by ``angle`` [rad] about the trunk's long axis."""
    c, s = math.cos(angle), math.sin(angle)
    roll = np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])
    tr = R.O.trunk_index(model)
    rot = np.asarray(state.rot).copy()
    rot[tr] = rot[tr] @ roll
    return rot


def test_the_thread_is_slack_standing_and_taut_when_the_head_drops_or_strays(cfg):
    """The default single thread (§4.5) is loose on the standing robot with room for the
    head to drop 7 cm below the build pose (walking trots lower it that far, see the
    config's ``slack``), taut once the head drops 9 cm or the robot strays 0.4 m sideways,
    and a 25-degree roll hardly stretches it; a bridle (two threads from the head's top
    corners) is stretched by the same roll either way: the bridle limits roll, the single
    thread does not."""
    from thesis.physics.step import tether_geometry
    m, st = C.base_model(cfg)
    assert m.tether_names == ("thread",)
    slack = float(cfg["tether"]["slack"])
    _, d0, _ = tether_geometry(m, st.pos, st.rot)
    assert float(d0[0]) < slack - 0.07
    for shift in ((0.0, 0.0, -0.09), (0.0, 0.4, 0.0), (0.0, -0.4, 0.0)):
        _, d, _ = tether_geometry(m, np.asarray(st.pos) + np.asarray(shift), st.rot)
        assert float(d[0]) > slack
    _, d_roll, _ = tether_geometry(m, st.pos, _rolled(m, st, 0.44))
    assert float(d_roll[0]) < float(d0[0]) + 0.01
    bridle, st2 = R.O.oncilla(tether_rail_height=cfg["tether"]["rail_height"],
                              tether_slack=slack, tether_stiffness=1.0, tether_damping=0.0,
                              tether_width=R.O.TRUNK[1])
    assert bridle.tether_names == ("thread_left", "thread_right")
    _, d2_0, _ = tether_geometry(bridle, st2.pos, st2.rot)
    for angle in (0.44, -0.44):
        _, d2, _ = tether_geometry(bridle, st2.pos, _rolled(bridle, st2, angle))
        assert np.asarray(d2).max() > np.asarray(d2_0).max() + 0.03
    with pytest.raises(ValueError, match="tether_width"):
        R.O.oncilla(tether_rail_height=1.0, tether_slack=slack, tether_stiffness=1.0,
                    tether_width=0.3)


def _sim(z, up, x, dt=0.01):
    """A fake simulate() result: trunk height z, up-vector z-component up, position x."""
    model, _ = C.base_model(load_config("smoke")["ch4"])
    trunk = R.O.trunk_index(model)
    B, K = z.shape
    pos = np.zeros((B, K, model.n_body, 3))
    pos[:, :, :, 2] = 0.15
    pos[:, :, trunk, 0] = x
    pos[:, :, trunk, 2] = z
    rot = np.broadcast_to(np.eye(3), (B, K, model.n_body, 3, 3)).copy()
    rot[:, :, trunk, 2, 2] = up
    return model, dict(pos=pos, rot=rot, t=(np.arange(K) + 1) * dt)


def test_speed_terms_speed_falls_and_upright_fraction():
    K = 100  # 1 s
    t = (np.arange(K) + 1) * 0.01
    z = np.full((3, K), 0.15)
    up = np.ones((3, K))
    x = np.stack([0.3 * t, 0.3 * t, -0.1 * t])
    z[1, 60:] = np.linspace(0.15, 0.05, K - 60)  # robot 1 sinks to the floor
    t_fall = t[np.argmax(z[1] < 0.08)]
    model, sim = _sim(z, up, x)
    out = R.speed_terms(model, sim, 0.5, 0.08)
    assert out["speed"][0] == pytest.approx(0.3, rel=1e-5)
    assert out["speed"][2] == pytest.approx(-0.1, rel=1e-5)
    assert list(out["fallen"]) == [False, True, False]
    assert not out["exploded"].any()
    assert out["upright"][1] == pytest.approx((t_fall - 0.5) / 0.5, abs=1e-9)
    assert out["upright"][0] == 1.0 and out["finite"].all()
    score = TR.score_of(out)
    assert score[1] == pytest.approx(TR.FALLEN_SCORE + out["upright"][1])
    assert score[1] < min(score[0], score[2])
    tilted = up.copy()
    tilted[0, 90:] = 0.3  # rolled over: tilted more than 60 degrees
    model, sim = _sim(np.full((3, K), 0.15), tilted, x)
    assert R.speed_terms(model, sim, 0.5, 0.08)["fallen"][0]


def test_speed_terms_flags_non_finite_robots():
    K = 50
    z = np.full((2, K), 0.15)
    model, sim = _sim(z, np.ones((2, K)), np.zeros((2, K)))
    sim["pos"][1, 10] = np.nan
    out = R.speed_terms(model, sim, 0.1, 0.08)
    assert list(out["finite"]) == [True, False] and out["fallen"][1]


def test_treadmill_predecessors():
    pos = np.arange(2 * 3 * 1, dtype=float).reshape(2, 3, 1)
    prev = TR.treadmill_predecessors(pos)
    assert prev[..., 0].tolist() == [[0, 0, 1], [2, 3, 4]]


def test_heading_turns_the_robot_about_the_vertical(cfg):
    _, state = C.base_model(cfg)
    s = R.batch_states(state, 2, heading=np.array([0.0, math.pi / 2]))
    p0, p1 = np.asarray(s.pos[0]), np.asarray(s.pos[1])
    np.testing.assert_allclose(p1[:, 0], -p0[:, 1], atol=1e-6)
    np.testing.assert_allclose(p1[:, 1], p0[:, 0], atol=1e-6)
    np.testing.assert_allclose(p1[:, 2], p0[:, 2], atol=1e-6)
    r = np.asarray(s.rot[1])
    np.testing.assert_allclose(np.einsum("bij,bkj->bik", r, r), np.broadcast_to(np.eye(3), r.shape),
                               atol=1e-6)


def test_pebble_layout_covers_the_strip_with_1cm_pebbles_on_the_floor(cfg):
    pc = cfg["pebbles"]
    c, r = C.pebble_layout(cfg, 0)
    assert r == pytest.approx(0.5 * pc["diameter"])
    L, W = pc["strip_length"], pc["strip_width"]
    # expected coverage: footprints over the strip's area
    assert len(c) * math.pi * r * r / (L * W) == pytest.approx(pc["coverage"], rel=1e-3)
    assert c[:, 0].min() >= 0 and c[:, 0].max() <= L
    assert np.abs(c[:, 1]).max() <= W / 2
    np.testing.assert_allclose(c[:, 2], r)  # resting on the floor
    np.testing.assert_array_equal(C.pebble_layout(cfg, 0)[0], c)  # one layout per root seed
    assert not np.array_equal(C.pebble_layout(cfg, 1)[0][:10], c[:10])


def test_pebbly_model_has_the_field_and_the_thread(cfg):
    m, _ = C.condition_model(cfg, "pebbly", 0)
    assert m.field_name == "pebbles" and m.field_k == cfg["pebbles"]["k"]
    assert m.tether_names == ("thread",)
    with pytest.raises(ValueError, match="root seed"):
        C.condition_model(cfg, "pebbly")


def test_start_range_leaves_room_for_the_walk_and_names_a_short_strip(cfg):
    assert C.start_range(cfg, "flat", 1.0) is None
    lo, hi = C.start_range(cfg, "pebbly", 4.0)
    m = cfg["pebbles"]["start_margin"]
    assert lo == m and hi == pytest.approx(cfg["pebbles"]["strip_length"] - m - 1.5 * 4.0)
    short = dict(cfg, pebbles=dict(cfg["pebbles"], strip_length=3.0))
    with pytest.raises(ValueError, match="strip_length"):
        C.start_range(short, "pebbly", 4.0)
    s = TR.start_sampler(cfg, 0, "pebbly", 4.0)
    x0, x1 = s(0, 50), s(1, 50)
    assert x0.min() >= lo and x0.max() <= hi and not np.array_equal(x0, x1)
    np.testing.assert_array_equal(s(0, 50), x0)
    assert TR.start_sampler(cfg, 0, "grade9", 4.0) is None


def test_thread_load_counts_taut_poses_and_their_tension(cfg):
    """Robot 0 stands loose under the thread; robot 1's trunk sits 12 cm lower (past the
    thread's play) for the second half of the window: taut half the time, with a tension
    of k (d - slack)."""
    K = 100
    z = np.full((2, K), 0.172)
    z[1, K // 2:] = 0.172 - 0.12
    model, sim = _sim(z, np.ones((2, K)), np.zeros((2, K)))
    out = C.thread_load(model, sim, 0.0, sim["t"][-1])
    assert out["taut"][0] == 0.0 and out["thread_force"][0] == 0.0
    assert out["taut"][1] == pytest.approx(0.5)
    a = np.asarray(model.tether_anchor, float)  # body frame, identity rotation here
    head = z[1, -1] + a[:, 2]
    d = np.hypot(a[:, 1], float(cfg["tether"]["rail_height"]) - head)
    k = np.asarray(model.tether_k, float)
    steady = np.sum(k * (d - float(cfg["tether"]["slack"])))
    # the step's own sample carries a damping term (finite-difference rate); the other
    # taut samples are steady
    assert out["thread_force"][1] == pytest.approx(0.5 * steady, rel=0.05)
    bare = C.thread_load(C.untethered(model), sim, 0.0, sim["t"][-1])
    np.testing.assert_array_equal(bare["taut"], 0.0)


@pytest.mark.parametrize("chapter", ["ch3", "ch4", "ch6"])
def test_the_model_section_s_solver_settings_reach_the_solver(chapter):
    from thesis.ch6 import sweep as SW
    from thesis.ch3 import experiments as E

    build = {"ch3": E.model_of, "ch4": C.base_model, "ch6": SW.model_of}[chapter]
    section = load_config("smoke")[chapter]
    m = section["model"]
    default, _ = build(section)
    assert float(default.warm_start) == pytest.approx(m["warm_start"])
    assert float(default.relaxation) == pytest.approx(m["relaxation"])
    assert default.sweep_order == m["sweep_order"]
    assert default.contact_relaxation == m["contact_relaxation"]
    other = "jacobi" if m["sweep_order"] == "blocks_first" else "blocks_first"
    changed = dict(section, model=dict(m, warm_start=0.25, relaxation=0.7, sweep_order=other,
                                       contact_relaxation=0.4))
    model, _ = build(changed)
    assert float(model.warm_start) == pytest.approx(0.25)
    assert float(model.relaxation) == pytest.approx(0.7)
    assert model.sweep_order == other
    assert model.contact_relaxation == pytest.approx(0.4)


def test_pebbly_starts_overlap_no_pebble_and_the_field_has_its_relaxation(cfg):
    """Every start on the strip (random place and heading) is set down above the pebbles:
    no foot contact sphere overlaps a pebble, as a start pose built on the bare floor does
    among 1-cm pebbles. The field's contact rows take ``pebbles.contact_relaxation``, the
    flat floor the model's."""
    from scipy.spatial import cKDTree

    from thesis.physics import collision

    model, state = C.condition_model(cfg, "pebbly", 0)
    flat, flat_state = C.condition_model(cfg, "flat")
    assert model.contact_relaxation == pytest.approx(cfg["pebbles"]["contact_relaxation"])
    assert flat.contact_relaxation == cfg["model"].get("contact_relaxation")
    centres, r = C.pebble_layout(cfg, 0)
    tree = cKDTree(centres)
    n = 200
    fw = TR.start_sampler(cfg, 0, "pebbly", 4.0)(0, n)
    heads = np.random.default_rng(0).uniform(-0.05, 0.05, n)
    q = np.asarray(model.field_query)
    radius = np.asarray(model.csphere_radius)[q]

    def worst_gap(st) -> float:
        s = R.batch_states(st, n, heading=heads, forward=fw)
        gaps = []
        for i in range(n):
            c = np.asarray(collision.sphere_centres(model, s.pos[i], s.rot[i]))[q]
            d, _ = tree.query(c)
            gaps.append(np.min(d - r - radius))
        return float(np.min(gaps))

    assert worst_gap(state) >= -1e-6
    assert np.asarray(state.pos)[:, 2] == pytest.approx(np.asarray(flat_state.pos)[:, 2] + 2 * r)
    assert worst_gap(flat_state) < -1e-3  # the bare floor's start pose would overlap
