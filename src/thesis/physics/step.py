"""One time step of the engine, written as the algorithm of docs/sources.md#tpx-step / thesis §7.2.

1. apply gravity (external forces) to the velocities;
2. detect contacts and build the constraint rows (joints, servos, limits, springs, tethers,
   contacts) at the current poses;
3. warm-start with a fraction of last step's impulses (a sphere field's contacts keep
   the impulse of their field sphere, ``field_warm_start``) and run the projected
   block-Jacobi solver for the new velocities;
4. integrate the poses with semi-implicit Euler and re-orthonormalise (eq. 7.1);
5. optionally (``Model.toi_correction``) correct the positions of bodies whose sphere-plane
   contacts were hit during the last step for the time of impact (``toi_correction``).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics import collision, constraint, integrator, kinematics, solver
from thesis.physics.math import decay_gradient, mv, safe_norm
from thesis.physics.types import Model, State

__all__ = ["step", "solver_problem", "SOLVER_ARGS", "spring_geometry", "tether_geometry",
           "field_warm_start",
           "toi_correction"]


def spring_geometry(m: Model, pos, rot):
    """Unit direction (n_spring, 3), length (n_spring,), and anchor offsets of springs."""
    b1, b2 = m.spring_body1, m.spring_body2
    ra = mv(rot[b1], m.spring_anchor1)
    rb = mv(rot[b2], m.spring_anchor2)
    d = pos[b2] + rb - pos[b1] - ra
    length = safe_norm(d)
    ok = length > 1e-9
    unit = jnp.where(ok[:, None], d / jnp.where(ok, length, 1.0)[:, None], 0.0)
    return unit, length, ra, rb


def tether_geometry(m: Model, pos, rot):
    """Tethers' distance from their rails (``Builder.add_tether``).

    Returns (unit (n_tether, 3), length (n_tether,), r (n_tether, 3)): the unit vector
    from the carriage (the anchor's foot on the rail) to the anchor, their distance [m]
    and the anchor's offset from its body's CoM [m]. ``unit`` is 0 where the anchor is
    on the rail (gradient-safe).
    """
    b = m.tether_body
    r = mv(rot[b], m.tether_anchor)
    rel = pos[b] + r - m.tether_rail_point
    u = m.tether_rail_dir
    perp = rel - jnp.sum(rel * u, -1, keepdims=True) * u
    length = safe_norm(perp)
    ok = length > 1e-9
    unit = jnp.where(ok[:, None], perp / jnp.where(ok, length, 1.0)[:, None], 0.0)
    return unit, length, r


def field_warm_start(m: Model, row_impulse, old_id, new_id):
    """Last step's impulses of the field contacts moved to this step's slots.

    A field contact slot holds whichever of the ``k`` nearest field spheres sorts there
    (``collision.field_contacts``); when the set changes, a field sphere may move to
    another slot. Each slot's warm start is the impulse its field sphere (``new_id``) had
    in the last step (``old_id``), 0 for a field sphere that was not among the nearest.

    Args:
        row_impulse: (n_rows,) last step's scalar-row impulses.
        old_id, new_id: (n_field_pair,) field sphere of each slot, last step and now.
    Returns:
        (n_rows,) the impulses with the field contacts' normal, friction (and torsion)
        rows permuted.
    """
    nq, k = int(m.field_query.shape[0]), m.field_k
    n_fp = m.n_field_pair
    match = (old_id.reshape(nq, k)[:, :, None] == new_id.reshape(nq, k)[:, None, :])
    src = jnp.argmax(match, axis=1).reshape(-1)  # old slot of each new slot's sphere
    found = jnp.any(match, axis=1).reshape(-1)
    first = m.n_rows - m.rows_per_contact * m.n_contact + m.n_pair
    base = np.asarray([first + g * m.n_contact for g in range(m.rows_per_contact)])
    slot0 = np.repeat(np.arange(nq) * k, k)  # first slot of each new slot's query sphere
    rows = (base[:, None] + np.arange(n_fp)[None, :]).reshape(-1)  # the field rows
    from_rows = (base[:, None] + slot0[None, :] + src[None, :]).reshape(-1)
    moved = jnp.where(jnp.tile(found, m.rows_per_contact), row_impulse[from_rows], 0.0)
    return row_impulse.at[rows].set(moved.astype(row_impulse.dtype))


def toi_correction(m: Model, contacts, vel, angvel):
    """Time since impact (n_body,) [s] of each body's sphere-plane contacts hit last step.

    A time-stepped engine lands a falling body at the first step at which it penetrates,
    so the landing time is a whole number of steps and the final state does not depend
    continuously on, e.g., the height of a throw (the derivative of where a ball stops
    w.r.t. its vertical launch speed is exactly 0; Hu et al. 2020, DiffTaichi, §4 "time
    of impact"). A contact that penetrates by ``-dist`` while approaching at the speed
    ``-v_n`` of the last step (pre-gravity velocities ``vel``/``angvel``, beyond the
    restitution threshold) was hit ``tau = dist / v_n`` ago (0 <= tau <= dt); the body
    should have moved with its new velocity since then, so ``step`` adds
    ``tau (v_new - v_old)`` to its position. Sphere-sphere pairs and rotations are not
    corrected; a resting contact (|v_n| below the threshold) gets tau = 0.

    Args:
        contacts: dict of ``collision.detect`` at the step's poses.
        vel, angvel: (n_body, 3) world velocities of the last step [m/s, rad/s].
    Returns:
        (n_body,) tau [s]: the largest over the body's contacts, 0 without an impact.
    """
    plane = np.nonzero(~m.pair_is_sphere)[0]
    body = contacts["body_b"][plane]
    n, rb = contacts["normal"][plane], contacts["rb"][plane]
    v_point = vel[body] + jnp.cross(angvel[body], rb)
    vn = jnp.sum(n * v_point, -1)
    dist = contacts["dist"][plane]
    hit = (dist < 0) & (vn < -m.restitution_threshold)
    tau = jnp.clip(dist / jnp.where(hit, vn, -1.0), 0.0, m.dt)
    tau = jnp.where(hit, tau, 0.0)
    return jax.ops.segment_max(tau, body, num_segments=m.n_body, indices_are_sorted=False
                               ).clip(0.0)


#: Keys of :func:`solver_problem` that are :func:`thesis.physics.solver.solve`'s arguments,
#: in its order.
SOLVER_ARGS = ("v0", "inv_m", "inv_iw", "blocks", "rows", "guess_joint", "guess_row")


def solver_problem(model: Model, state: State, action, *, warm_start_grad=1.0) -> dict:
    """Steps 1-3 of :func:`step` up to the solve: the velocity-level problem of this step.

    Args: as :func:`step`.
    Returns:
        dict: ``v0`` (n_body + 1, 6) velocities after external forces, ``inv_m``,
        ``inv_iw`` (:func:`thesis.physics.solver.inverse_mass`), ``blocks`` and ``rows``
        (the constraint rows), ``guess_joint`` (n_joint, 6) and ``guess_row`` (n_rows,)
        the warm start (``model.warm_start`` times last step's impulses), and the step's
        ``contacts`` (:func:`thesis.physics.collision.detect`); ``solver.solve(model,
        *(problem[k] for k in SOLVER_ARGS))`` is the step's solve.
    """
    m, s = model, state
    dt = m.dt
    with jax.named_scope("external_forces"):
        vel0 = s.vel + dt * m.gravity[None, :]
        pos, rot, v0 = kinematics.extend(m, s.pos, s.rot, vel0, s.angvel)
    with jax.named_scope("constraints"):
        fr = kinematics.joint_frames(m, pos, rot)
        dofs = kinematics.joint_coordinates(m, fr, v0)
        ja, jb, err = kinematics.joint_rows(m, fr)
        erp, gamma = constraint.softness(m.joint_hz, m.joint_zeta, dt)
        blocks = dict(ja=ja, jb=jb, bias=erp[:, None] / dt * err,
                      gamma=jnp.broadcast_to(gamma[:, None], err.shape),
                      body_a=m.joint_body1, body_b=m.joint_body2)
        contacts = collision.detect(m, pos, rot)
        springs = spring_geometry(m, pos, rot)
        tethers = tether_geometry(m, pos, rot) if m.tether_names else None
        rows = constraint.scalar_rows(m, dofs, contacts, springs, v0, action, tethers)
    with jax.named_scope("solver"):
        inv_m, inv_iw = solver.inverse_mass(m, rot)
        guess_j, guess_r = s.joint_impulse, s.row_impulse
        if m.n_field_pair:
            guess_r = field_warm_start(m, guess_r, s.field_id, contacts["field_id"])
        if not (isinstance(warm_start_grad, (int, float)) and warm_start_grad == 1.0):
            guess_j, guess_r = decay_gradient((guess_j, guess_r), warm_start_grad)
    return dict(v0=v0, inv_m=inv_m, inv_iw=inv_iw, blocks=blocks, rows=rows,
                guess_joint=m.warm_start * guess_j, guess_row=m.warm_start * guess_r,
                contacts=contacts)


def step(model: Model, state: State, action, *, warm_start_grad=1.0) -> State:
    """Advance ``state`` by ``model.dt``.

    Args:
        model: the Model. state: the State.
        action: (n_servo,) servo commands (rad / m for position servos, rad/s / m/s for
            velocity servos).
        warm_start_grad: fraction of the gradient that flows through the warm start (last
            step's impulses as the solver's initial guess, docs/sources.md#tpx-step step 4); the forward
            pass is unchanged. 1.0 (default) is the exact derivative of the truncated
            solver; 0.0 treats the initial guess as a constant, as the derivative of a
            converged solve would (its solution does not depend on the guess). Measured on
            the Tab. 7.1 quadruped's closed loop: the gradient grows x1.31 per step with
            the warm start (0.85) and x1.03 with warm start 0.
    Returns:
        The next State (its ``joint_impulse``/``row_impulse`` are this step's impulses).
    """
    m, s = model, state
    dt = m.dt
    p = solver_problem(m, s, action, warm_start_grad=warm_start_grad)
    contacts = p["contacts"]
    with jax.named_scope("solver"):
        v, lam_j, lam_r = solver.solve(m, *(p[k] for k in SOLVER_ARGS))
    with jax.named_scope("integrate"):
        nb = m.n_body
        new_pos, new_rot, new_w = integrator.integrate(m, s.pos, s.rot, v[:nb, :3], v[:nb, 3:])
        if m.toi_correction and m.n_pair and not m.pair_is_sphere.all():
            tau = toi_correction(m, contacts, s.vel, s.angvel)
            new_pos = new_pos + tau[:, None] * (v[:nb, :3] - s.vel)
    extra = dict(field_id=contacts["field_id"]) if m.n_field_pair else {}
    return s.replace(pos=new_pos, rot=new_rot, vel=v[:nb, :3], angvel=new_w,
                     prev_vel=s.vel, joint_impulse=lam_j, row_impulse=lam_r,
                     time=s.time + dt, **extra)
