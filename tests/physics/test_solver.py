"""solver.py: projected block Jacobi converges to direct solutions as iterations grow."""

import itertools

import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import Builder, collision, constraint, kinematics, solver
from thesis.physics.step import spring_geometry


def _problem(m, s):
    """Rows and bodies of one step, as the engine builds them."""
    dt = m.dt
    vel0 = s.vel + dt * m.gravity[None, :]
    pos, rot, v0 = kinematics.extend(m, s.pos, s.rot, vel0, s.angvel)
    fr = kinematics.joint_frames(m, pos, rot)
    ja, jb, err = kinematics.joint_rows(m, fr)
    erp, gamma = constraint.softness(m.joint_hz, m.joint_zeta, dt)
    blocks = dict(ja=ja, jb=jb, bias=erp[:, None] / dt * err,
                  gamma=jnp.broadcast_to(gamma[:, None], err.shape),
                  body_a=m.joint_body1, body_b=m.joint_body2)
    rows = constraint.scalar_rows(m, kinematics.joint_coordinates(m, fr, v0),
                                  collision.detect(m, pos, rot), spring_geometry(m, pos, rot),
                                  v0, jnp.zeros((m.n_servo,), v0.dtype))
    inv_m, inv_iw = solver.inverse_mass(m, rot)
    return v0, inv_m, inv_iw, blocks, rows


def _dense(m, v0, inv_m, inv_iw, blocks, rows):
    nb1 = v0.shape[0]
    minv = np.zeros((6 * nb1, 6 * nb1))
    for i in range(nb1):
        minv[6 * i:6 * i + 3, 6 * i:6 * i + 3] = np.eye(3) * float(inv_m[i])
        minv[6 * i + 3:6 * i + 6, 6 * i + 3:6 * i + 6] = np.asarray(inv_iw[i])
    jrows, bias, gam = [], [], []
    mask = np.asarray(m.joint_row_mask)
    for j in range(m.n_joint):
        for r in range(6):
            if mask[j, r]:
                row = np.zeros(6 * nb1)
                row[6 * blocks["body_a"][j]:][:6] += np.asarray(blocks["ja"][j, r])
                row[6 * blocks["body_b"][j]:][:6] += np.asarray(blocks["jb"][j, r])
                jrows.append(row)
                bias.append(float(blocks["bias"][j, r]))
                gam.append(float(blocks["gamma"][j, r]))
    n_eq = len(jrows)
    for i in range(rows["bias"].shape[0]):
        row = np.zeros(6 * nb1)
        row[6 * rows["body_a"][i]:][:6] += np.asarray(rows["ja"][i])
        row[6 * rows["body_b"][i]:][:6] += np.asarray(rows["jb"][i])
        jrows.append(row)
        bias.append(float(rows["bias"][i]))
        gam.append(float(rows["gamma"][i]))
    jmat = np.array(jrows)
    a = jmat @ minv @ jmat.T
    a += np.diag(np.array(gam) * np.diag(a))
    rhs = -(jmat @ np.asarray(v0).reshape(-1) + np.array(bias))
    return jmat, minv, a, rhs, n_eq


def _solve(m, problem, iterations):
    mk = m.replace(solver_iterations=iterations)
    v0, inv_m, inv_iw, blocks, rows = problem
    z = jnp.zeros((m.n_joint, 6), v0.dtype)
    v, _, _ = solver.solve(mk, v0, inv_m, inv_iw, blocks, rows, z,
                           jnp.zeros(rows["bias"].shape, v0.dtype))
    return np.asarray(v).reshape(-1)


@pytest.mark.slow
def test_block_jacobi_converges_to_direct_solve_of_equality_system(x64):
    b = Builder("chain", dt=0.01)
    rot = np.array([[0, 0, 1.0], [0, 1, 0], [-1.0, 0, 0]])
    for i in range(4):
        b.add_box(f"l{i}", (0.05, 0.05, 0.3), (0.15 + 0.3 * i, 0, 1.0), rot=rot,
                  mass=1.0 + i)
        kind = b.add_hinge if i % 2 == 0 else b.add_ball
        args = ((0, 1, 0),) if i % 2 == 0 else ()
        kind(f"j{i}", "world" if i == 0 else f"l{i - 1}", f"l{i}", (0.3 * i, 0, 1.0), *args)
        b.set_velocity(f"l{i}", (0.1 * i, -0.2, 0.3), (0.5, -0.1 * i, 0.2))
    b.add_fixed("weld", "l1", "l3")
    m, s = b.build(jnp.float64)
    problem = _problem(m, s)
    jmat, minv, a, rhs, _ = _dense(m, *problem)
    lam = np.linalg.solve(a, rhs)
    v_direct = np.asarray(problem[0]).reshape(-1) + minv @ jmat.T @ lam
    errs = [np.abs(_solve(m, problem, k) - v_direct).max() for k in (5, 20, 80, 400, 1600)]
    print("errors", errs)
    assert all(e1 < e0 for e0, e1 in zip(errs, errs[1:])), errs
    assert errs[-1] < 1e-6 * np.abs(v_direct).max()


def test_contact_lcp_matches_enumerative_solution(x64):
    """A tilted box pressed into the floor on four frictionless spheres: the LCP
    0 <= lambda _|_ A lambda - rhs >= 0 solved by enumerating the active sets."""
    b = Builder("lcp", dt=0.01)
    b.add_material("m", 0.0, 0.0, 25.0, 1.0)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    rot = np.asarray(__import__("thesis.physics.math", fromlist=["rodrigues"]).rodrigues(
        jnp.asarray([0.05, -0.03, 0.0])))
    b.add_box("box", (0.6, 0.4, 0.1), (0, 0, 0.095), rot=rot)
    for x in (-0.25, 0.25):
        for y in (-0.15, 0.15):
            b.add_contact_sphere("box", 0.05, (x, y, -0.05))
    b.set_velocity("box", (0, 0, -0.8), (0.4, 0.3, 0))
    m, s = b.build(jnp.float64)
    problem = _problem(m, s)
    active = np.asarray(problem[4]["hi"][:4]) > 0
    assert 0 < active.sum() < 4  # a genuine complementarity problem
    jmat, minv, a, rhs, _ = _dense(m, *problem)
    n = 4  # normal rows first; friction rows have mu = 0
    best = None
    for mask in itertools.product([0, 1], repeat=n):
        idx = [i for i in range(n) if mask[i] and active[i]]
        lam = np.zeros(a.shape[0])
        if idx:
            lam[idx] = np.linalg.solve(a[np.ix_(idx, idx)], rhs[idx])
        w = a[:n, :n] @ lam[:n] - rhs[:n]
        if np.all(lam >= -1e-12) and np.all(w[active] >= -1e-9):
            best = lam
            break
    assert best is not None
    v_direct = np.asarray(problem[0]).reshape(-1) + minv @ jmat.T @ best
    errs = [np.abs(_solve(m, problem, k) - v_direct).max() for k in (2, 10, 60, 400)]
    assert errs[-1] < 1e-6 and errs[-1] < errs[0], errs


def _leg_under_trunk(knee_springs=False):
    """A light two-segment leg on a servo-driven universal joint under a 4-kg trunk (the
    Oncilla's scapula/hip pattern), servos off their commands, torques unbounded; with
    ``knee_springs`` two springs on the knee's coordinate instead of its servo."""
    b = Builder("leg", dt=0.0025)
    b.add_box("trunk", (0.4, 0.14, 0.07), (0, 0, 0.3), mass=4.0)
    b.add_box("femur", (0.02, 0.02, 0.065), (0.1, 0.1, 0.2325), mass=0.1)
    b.add_box("tibia", (0.015, 0.015, 0.07), (0.1, 0.1, 0.165), mass=0.08)
    b.add_universal("hip", "trunk", "femur", (0.1, 0.1, 0.265), (1, 0, 0), (0, -1, 0))
    b.add_hinge("knee", "femur", "tibia", (0.1, 0.1, 0.2), (0, -1, 0))
    for name, axis in (("scapula", 0), ("swing", 1)):
        b.add_position_servo("hip", 10.0, 1e6, 1e6, axis_index=axis, name=name)
    if knee_springs:  # two springs on the knee's coordinate, no servo
        for k, rest in ((1e3, 0.3), (2e3, -0.2)):
            b.add_joint_spring("knee", k, 1.0, rest_angle=rest)
    else:
        b.add_position_servo("knee", 50.0, 1e6, 1e6, name="knee")
    b.set_velocity("trunk", (0.3, -0.2, 0.1), (0.5, -0.4, 0.2))
    b.set_velocity("femur", (0.1, 0.4, -0.2), (2.0, 1.0, -0.5))
    return b.build(jnp.float64)


def test_blocks_first_sweeps_reach_the_same_solution_far_sooner(x64):
    """Both sweep orders converge to the direct solution of the equality system; blocks
    first at relaxation 1 gets there in far fewer sweeps than Jacobi at the Oncilla's 0.3
    (solver module docstring, Sweep order)."""
    m, s = _leg_under_trunk()
    problem = _problem(m, s)
    jmat, minv, a, rhs, _ = _dense(m, *problem)
    v_direct = np.asarray(problem[0]).reshape(-1) + minv @ jmat.T @ np.linalg.solve(a, rhs)
    scale = np.abs(v_direct).max()
    jacobi = m.replace(relaxation=jnp.asarray(0.3))
    first = m.replace(relaxation=jnp.asarray(1.0), sweep_order="blocks_first")
    err = {name: [np.abs(_solve(mk, problem, k) - v_direct).max() / scale for k in (30, 120, 4000)]
           for name, mk in (("jacobi", jacobi), ("blocks_first", first))}
    print(err)
    assert err["jacobi"][-1] < 1e-6 and err["blocks_first"][-1] < 1e-6, err
    assert err["blocks_first"][1] < 0.2 * err["jacobi"][1], err
    assert err["blocks_first"][0] < err["jacobi"][0], err


def test_an_unknown_sweep_order_is_refused_with_the_allowed_ones():
    with pytest.raises(ValueError,
                       match="sweep_order must be one of.*jacobi.*blocks_first.*momentum"):
        Builder("x", sweep_order="gauss_seidel")


def _foot_on_three_contacts():
    """A light frictionless foot pressed into the floor on three nearly coincident contact
    spheres (a toe touching the floor and two pebbles at once), and its direct solution."""
    b = Builder("foot", dt=0.0025, relaxation=1.0)
    b.add_material("m", 0.0, 0.0, 100.0, 1.0)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    b.add_box("foot", (0.02, 0.02, 0.02), (0, 0, 0.0095), mass=0.05)
    for x, y in ((0.002, 0.0), (-0.001, 0.0017), (-0.001, -0.0017)):
        b.add_contact_sphere("foot", 0.01, (x, y, 0.0))
    b.set_velocity("foot", (0, 0, -0.5), (0, 0, 0))
    m, s = b.build(jnp.float64)
    problem = _problem(m, s)
    jmat, minv, a, rhs, _ = _dense(m, *problem)
    n = 3  # the normal rows come first; the friction rows carry mu = 0
    assert np.all(np.asarray(problem[4]["hi"][:n]) > 0)
    lam = np.zeros(a.shape[0])
    lam[:n] = np.linalg.solve(a[:n, :n], rhs[:n])
    assert np.all(lam[:n] > 0)  # every contact pushes: the active set is all three
    return m, problem, np.asarray(problem[0]).reshape(-1) + minv @ jmat.T @ lam


def test_contact_relaxation_settles_several_contacts_on_one_light_body(x64):
    """Three contacts on one foot updated in parallel at relaxation 1 overshoot together
    and never settle; the contact rows' own relaxation 0.5 reaches the direct solution
    (solver module docstring, Contact relaxation)."""
    m, problem, v_direct = _foot_on_three_contacts()
    scale = np.abs(v_direct - np.asarray(problem[0]).reshape(-1)).max()
    err = {r: [np.abs(_solve(m.replace(contact_relaxation=r), problem, k) - v_direct).max()
               / scale for k in (119, 120)] for r in (None, 0.5)}
    print(err)
    assert min(err[None]) > 0.3, err
    assert max(err[0.5]) < 1e-6, err


def test_contact_relaxation_equal_to_relaxation_changes_nothing(x64):
    m, problem, _ = _foot_on_three_contacts()
    for order in ("jacobi", "blocks_first"):
        mk = m.replace(sweep_order=order, relaxation=jnp.asarray(0.7))
        np.testing.assert_array_equal(_solve(mk.replace(contact_relaxation=0.7), problem, 30),
                                      _solve(mk, problem, 30))


@pytest.mark.parametrize("value", [0.0, 1.5, -0.2])
def test_a_contact_relaxation_outside_0_1_is_refused(value):
    with pytest.raises(ValueError, match=r"contact_relaxation must be None or in \(0, 1\]"):
        Builder("x", contact_relaxation=value)


def test_row_relaxation_acts_on_the_servo_rows_and_not_on_the_contacts(x64):
    """The servo rows of the leg under its trunk take ``row_relaxation`` (a different
    factor changes the sweeps, the same one changes nothing); the foot's contacts keep
    theirs (solver module docstring, Momentum and Contact relaxation)."""
    m, s = _leg_under_trunk()
    leg = _problem(m, s)
    foot, contacts, _ = _foot_on_three_contacts()
    for order in ("jacobi", "blocks_first", "momentum"):
        mk = m.replace(sweep_order=order, relaxation=jnp.asarray(0.6))
        np.testing.assert_array_equal(_solve(mk.replace(row_relaxation=0.6), leg, 30),
                                      _solve(mk, leg, 30))
        assert np.abs(_solve(mk.replace(row_relaxation=0.8), leg, 30)
                      - _solve(mk, leg, 30)).max() > 1e-6
        fk = foot.replace(sweep_order=order, relaxation=jnp.asarray(0.7))
        np.testing.assert_array_equal(_solve(fk.replace(row_relaxation=0.3), contacts, 30),
                                      _solve(fk, contacts, 30))


def test_row_relaxation_is_shared_by_the_rows_of_one_joint_coordinate(x64):
    """Two springs on one knee coordinate share one Jacobian: updated in parallel at the
    momentum order's 0.65 they overshoot together and the extrapolation diverges;
    ``row_relaxation`` is divided between them and the sweeps reach the direct solution
    (solver module docstring, Momentum)."""
    m, s = _leg_under_trunk(knee_springs=True)
    problem = _problem(m, s)
    dof = problem[4]["dof"]
    assert np.sum(dof == dof[-1]) == 2 and dof[-1] >= 0  # the knee's two spring rows
    jmat, minv, a, rhs, n_eq = _dense(m, *problem)
    a[n_eq:, n_eq:] += np.diag(np.asarray(problem[4]["cfm_abs"]))  # the springs' softness
    v_direct = np.asarray(problem[0]).reshape(-1) + minv @ jmat.T @ np.linalg.solve(a, rhs)
    scale = np.abs(v_direct - np.asarray(problem[0]).reshape(-1)).max()
    mk = m.replace(relaxation=jnp.asarray(0.65), sweep_order="momentum")
    err = {r: [np.abs(_solve(mk.replace(row_relaxation=r), problem, k) - v_direct).max()
               / scale for k in (1000, 2000)] for r in (None, 0.8)}
    print(err)
    assert min(err[None]) > 1.0, err
    assert err[0.8][1] < 1e-3 and err[0.8][1] < err[0.8][0], err


@pytest.mark.parametrize("value", [0.0, 1.5, -0.2])
def test_a_row_relaxation_outside_0_1_is_refused(value):
    with pytest.raises(ValueError, match=r"row_relaxation must be None or in \(0, 1\]"):
        Builder("x", row_relaxation=value)


def _solve_report(m, problem, iterations):
    v0, inv_m, inv_iw, blocks, rows = problem
    z = jnp.zeros((m.n_joint, 6), v0.dtype)
    return solver.solve(m.replace(solver_iterations=iterations), v0, inv_m, inv_iw, blocks,
                        rows, z, jnp.zeros(rows["bias"].shape, v0.dtype), report=True)


def test_momentum_sweeps_reach_the_same_solution_sooner_than_blocks_first(x64):
    """The momentum order (blocks-first sweeps with extrapolated impulses, solver module
    docstring, Momentum) converges to the direct solution of the equality system, in
    fewer sweeps than blocks first; at relaxation 1 it would not (eigenvalues of the
    blocks-first sweep near -1, amplified by the extrapolation)."""
    m, s = _leg_under_trunk()
    problem = _problem(m, s)
    jmat, minv, a, rhs, _ = _dense(m, *problem)
    v_direct = np.asarray(problem[0]).reshape(-1) + minv @ jmat.T @ np.linalg.solve(a, rhs)
    scale = np.abs(v_direct).max()
    first = m.replace(relaxation=jnp.asarray(1.0), sweep_order="blocks_first")
    mom = m.replace(relaxation=jnp.asarray(0.5), sweep_order="momentum")
    err = {name: [np.abs(_solve(mk, problem, k) - v_direct).max() / scale
                  for k in (20, 40, 2000)]
           for name, mk in (("blocks_first", first), ("momentum", mom))}
    print(err)
    assert err["momentum"][-1] < 1e-9, err
    assert err["momentum"][0] < 0.5 * err["blocks_first"][0], err
    assert err["momentum"][1] < 0.1 * err["blocks_first"][1], err


def test_momentum_sweeps_solve_the_contact_lcp(x64):
    """The momentum order's projection after extrapolation keeps the tilted box's contact
    LCP (test above) at its enumerated solution."""
    b = Builder("lcp", dt=0.01, sweep_order="momentum", relaxation=0.5)
    b.add_material("m", 0.0, 0.0, 25.0, 1.0)
    b.add_plane("floor", (0, 0, 1), 0.0, "m")
    b.add_box("box", (0.6, 0.4, 0.1), (0, 0, 0.095))
    for x in (-0.25, 0.25):
        for y in (-0.15, 0.15):
            b.add_contact_sphere("box", 0.05 + 0.004 * (x > 0) + 0.002 * (y > 0),
                                 (x, y, -0.05))
    b.set_velocity("box", (0, 0, -0.8), (0.4, 0.3, 0))
    m, s = b.build(jnp.float64)
    problem = _problem(m, s)
    first = m.replace(sweep_order="blocks_first")
    v_ref = _solve(first, problem, 4000)
    err = [np.abs(_solve(m, problem, k) - v_ref).max() for k in (2, 20, 400)]
    print(err)
    assert err[-1] < 1e-9 and err[-1] < err[0], err


@pytest.mark.parametrize("order", ["blocks_first", "momentum"])
def test_the_solve_reports_a_residual_that_falls_to_zero(x64, order):
    """``report=True`` adds the final relative residual and changes nothing else."""
    m, s = _leg_under_trunk()
    m = m.replace(sweep_order=order, relaxation=jnp.asarray(0.5))
    problem = _problem(m, s)
    res = [float(_solve_report(m, problem, k)[3]) for k in (5, 40, 4000)]
    print(res)
    assert res[0] > 1e-3 and res[0] > res[1] > 1e-10 > res[2], res
    np.testing.assert_array_equal(np.asarray(_solve_report(m, problem, 40)[0]).reshape(-1),
                                  _solve(m, problem, 40))
    with pytest.raises(ValueError, match="one robot"):
        _solve_report(m.replace(batched=True), problem, 5)


@pytest.mark.parametrize("value", [-0.1, 1.0])
def test_a_momentum_outside_0_1_is_refused(value):
    with pytest.raises(ValueError, match=r"momentum must be in \[0, 1\)"):
        Builder("x", momentum=value)
