"""Constraint rows of one time step: joints, servos, limits, springs, contacts.

Every row i asks ``J_i v + bias_i + cfm_i * lambda_i = 0`` for the post-step velocities v
and its accumulated impulse lambda_i in [lo_i, hi_i] (docs/sources.md#tpx-step). The rows come in
two families with static shapes:

* joint blocks (n_joint, 6): the equality rows of each joint, solved together;
* scalar rows (n_rows,): ``[servos | limits | joint springs | springs | tethers |
  contact normals | friction t1 | friction t2 | (torsion)]`` in that static order.

Softness (docs/sources.md#tpx-step item 3, derived so its units are consistent): a row with natural
frequency f [Hz] and damping ratio zeta behaves as an implicit spring-damper of stiffness
``k = m_eff w^2`` and damping ``c = 2 m_eff zeta w`` (w = 2 pi f); with h = dt this gives
``erp = h k / (h k + c) = hw / (hw + 2 zeta)`` and an impulse-space
``cfm = 1 / (h (h k + c)) = gamma / m_eff`` with ``gamma = 1 / (hw (hw + 2 zeta))``.
The original wrote ``CFM = 1/(c + dt k)`` and applied it to impulses, which differs by a
factor dt (a unit slip, kept out). Springs with explicit k [N/m], c [N s/m] use the same
expressions without m_eff (``cfm_abs``), i.e. they are integrated implicitly and stay
stable for any stiffness. A contact material with a ``stiffness`` [N/m] (and ``damping``
[N s/m]; ``Builder.add_material``) is such a spring too: its normal row takes that
``erp`` and ``cfm_abs`` instead of the relative softness (opt-in: a model without one
assembles its rows exactly as before, ``Model.absolute_contact``).

Servos (docs/sources.md#tpx-servo): a hard velocity row along the joint coordinate with target rate
``-clip(gain * (q - q_cmd), +-v_max)`` (zero inside the dead band) for position servos,
or the command for velocity servos, and impulse bounded by ``max_torque * dt``. A
compliant drive (``ServoKind.COMPLIANT``) is the same row made soft: an implicit
spring-damper towards the command (stiffness, damping, as a joint spring with the command
as its rest angle) whose position-correction rate is clipped to ``+-v_max``.
Tethers (``Builder.add_tether``): a spring row on the anchor's distance d from its rail
with impulse in [-inf, 0] (pull only) while d > slack and [0, 0] while slack, so a slack
tether applies exactly no impulse.
Contacts (docs/sources.md#tpx-contact): normal row with position correction beyond ``contact_slop``
and restitution ``e * min(v_n + threshold, 0)`` (continuous in the approach speed), two friction
rows ``t1``, ``t2`` bounded *together* by a Coulomb cone ``|(lambda_t1, lambda_t2)| <= mu lambda_n``
(the solver projects the pair, see ``solver`` and ``rows["cone"]``; a per-row box would be a pyramid
aligned with the world's axes on a level floor, ``sqrt(2)`` times too strong at 45 deg to them) and
an optional torsional row ``|lambda_tau| <= torsional * lambda_n`` (a box). A contact with a
directional sphere (``Model.directional``) has an elliptic cone in its grain's frame: ``t1`` lies
along the sphere's direction (``collision.directional_basis``: a negative impulse resists sliding
forward) with the semi-axis ``mu_backward`` on the positive side and ``mu_forward`` on the negative
side, ``t2`` across it with ``mu``; the rows then carry a lower-bound coefficient ``fric_lo`` beside
``fric``. Where the grain turns towards the contact normal, the forward and backward coefficients
fade into the lateral one (``collision.directional_basis``'s weight): a grain normal to the surface
has no forward or backward, every tangential slide crosses it.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from thesis.physics.types import Model, ServoKind

__all__ = ["softness", "scalar_rows"]

INF = float("inf")


def softness(hz, zeta, dt):
    """(erp, gamma) of rows with natural frequency ``hz`` [Hz] and damping ratio ``zeta``."""
    hw = dt * 2.0 * jnp.pi * hz
    denom = hw + 2.0 * zeta
    return hw / denom, 1.0 / (hw * denom)


def _spring(k, c, dt):
    """(erp, cfm_abs) of an implicit spring-damper with stiffness k and damping c."""
    hk_c = dt * k + c
    return dt * k / hk_c, 1.0 / (dt * hk_c)


def scalar_rows(m: Model, dofs, contacts, spring_geo, vel6, action, tether_geo=None):
    """Assemble the scalar rows.

    Args:
        dofs: (q, qdot, ja, jb) from ``kinematics.joint_coordinates``.
        contacts: dict from ``collision.detect``.
        spring_geo: (d, length, ra, rb) of the body springs (n_spring, ...).
        vel6: (n_body + 1, 6) velocities after gravity (for restitution).
        action: (n_servo,) servo commands.
        tether_geo: (unit, length, r) of ``step.tether_geometry`` (models with tethers).
    Returns:
        dict of (n_rows, ...) arrays ``ja``, ``jb``, ``bias``, ``gamma``, ``cfm_abs``,
        ``lo``, ``hi``, ``fric`` (friction-bound coefficient, applied to the impulse of
        row ``ref``), ``fric_lo`` (lower-bound coefficient; only in directional models),
        and static numpy ``body_a``, ``body_b``, ``ref``, ``is_fric`` (rows bounded by a
        box of ``fric`` times their normal impulse: torsion), ``cone`` (``(first, n)``:
        the ``t1`` rows are ``first ... first + n - 1``, the ``t2`` rows the next ``n``,
        their normals the ``n`` rows before ``first``; ``None`` without contacts), ``dof``
        (the joint coordinate of a servo, limit or joint-spring row, -1 for the others).
    """
    q, qdot, dja, djb = dofs
    dt = m.dt
    dtype = vel6.dtype
    parts = []  # (ja, jb, bias, gamma, cfm_abs, lo, hi, fric, body_a, body_b)
    fric_lo = []  # per part: lower friction-bound coefficient, None = fric (directional)

    def add(ja, jb, bias, gamma, cfm_abs, lo, hi, fric, ba, bb, lower=None):
        n = ja.shape[0]
        if n:
            bc = lambda x: jnp.broadcast_to(jnp.asarray(x, dtype), (n,))  # noqa: E731
            parts.append((ja, jb, bc(bias), bc(gamma), bc(cfm_abs), bc(lo), bc(hi),
                          bc(fric), np.broadcast_to(ba, (n,)), np.broadcast_to(bb, (n,))))
            fric_lo.append(None if lower is None else bc(lower))

    dof_b1 = m.joint_body1[m.dof_joint] if m.n_dof else np.zeros((0,), np.int32)
    dof_b2 = m.joint_body2[m.dof_joint] if m.n_dof else np.zeros((0,), np.int32)

    # servos (docs/sources.md#tpx-servo)
    if m.n_servo:
        d = m.servo_dof
        cmd = jnp.clip(action.astype(dtype), m.servo_lo, m.servo_hi)
        err = q[d] - cmd
        # inside the dead band the servo aims at zero velocity; a dead band of 0 means none,
        # so the row (and its gradient w.r.t. the command) acts at zero error too
        live = (jnp.abs(err) >= m.servo_deadband).astype(dtype)
        target_pos = -jnp.clip(m.servo_gain * err * live, -m.servo_max_velocity,
                               m.servo_max_velocity)
        is_pos = np.asarray(m.servo_kind == ServoKind.POSITION)
        target = jnp.where(is_pos, target_pos, cmd)
        imp = m.servo_max_torque * dt
        bias, cfm = -target, 0.0
        is_pd = np.asarray(m.servo_kind == ServoKind.COMPLIANT)
        if is_pd.any():  # static: models without compliant drives keep their program
            k = jnp.where(is_pd, m.servo_stiffness, 1.0)
            c = jnp.where(is_pd, m.servo_damping, 1.0)
            erp, cfm_pd = _spring(k, c, dt)
            bias_pd = jnp.clip(erp / dt * (q[d] - cmd), -m.servo_max_velocity,
                               m.servo_max_velocity)
            bias = jnp.where(is_pd, bias_pd, bias)
            cfm = jnp.where(is_pd, cfm_pd, 0.0)
        add(dja[d], djb[d], bias, 0.0, cfm, -imp, imp, 0.0, dof_b1[d], dof_b2[d])

    # joint limits: one unilateral row per limited coordinate, on the violated side
    nl = int(m.limit_dof.shape[0])
    if nl:
        d = m.limit_dof
        below, above = q[d] - m.limit_lo, m.limit_hi - q[d]
        sign = jnp.where(below < above, 1.0, -1.0).astype(dtype)
        c = jnp.minimum(below, above)
        erp, gamma = softness(m.limit_hz, m.limit_zeta, dt)
        active = c < 0
        add(dja[d] * sign[:, None], djb[d] * sign[:, None], erp / dt * c, gamma, 0.0, 0.0,
            jnp.where(active, INF, 0.0), 0.0, dof_b1[d], dof_b2[d])

    # joint springs
    nk = int(m.jspring_dof.shape[0])
    if nk:
        d = m.jspring_dof
        erp, cfm = _spring(m.jspring_k, m.jspring_c, dt)
        add(dja[d], djb[d], erp / dt * (q[d] - m.jspring_rest), 0.0, cfm, -INF, INF, 0.0,
            dof_b1[d], dof_b2[d])

    # body springs along the line between the anchors
    if len(m.spring_names):
        dvec, length, ra, rb = spring_geo
        erp, cfm = _spring(m.spring_k, m.spring_c, dt)
        ja = jnp.concatenate([-dvec, -jnp.cross(ra, dvec)], -1)
        jb = jnp.concatenate([dvec, jnp.cross(rb, dvec)], -1)
        add(ja, jb, erp / dt * (length - m.spring_rest), 0.0, cfm, -INF, INF, 0.0,
            m.spring_body1, m.spring_body2)

    # tethers: tension-only implicit spring-damper on the anchor's distance from the rail
    if m.tether_names:
        unit, length, r = tether_geo
        erp, cfm = _spring(m.tether_k, m.tether_c, dt)
        jb = jnp.concatenate([unit, jnp.cross(r, unit)], -1)  # rate of the distance
        taut = length > m.tether_slack
        add(jnp.zeros_like(jb), jb, erp / dt * (length - m.tether_slack), 0.0, cfm,
            jnp.where(taut, -INF, 0.0), 0.0, 0.0, m.n_body, m.tether_body)

    # contacts
    np_ = m.n_contact
    contact_start = sum(p[0].shape[0] for p in parts)
    if np_:
        n, ra, rb = contacts["normal"], contacts["ra"], contacts["rb"]
        ba, bb = contacts["body_a"], contacts["body_b"]
        mat = m.contact_material
        erp, gamma = softness(m.material_hz[mat], m.material_zeta[mat], dt)
        cfm_n = 0.0
        if m.absolute_contact:  # materials in physical units (N/m, N s/m) where k > 0
            k_n = m.material_stiffness[mat]
            is_abs = k_n > 0
            erp_abs, cfm_abs = _spring(jnp.where(is_abs, k_n, 1.0), m.material_damping[mat], dt)
            erp = jnp.where(is_abs, erp_abs, erp)
            gamma = jnp.where(is_abs, 0.0, gamma)
            cfm_n = jnp.where(is_abs, cfm_abs, 0.0)
        ja_n = jnp.concatenate([-n, -jnp.cross(ra, n)], -1)
        jb_n = jnp.concatenate([n, jnp.cross(rb, n)], -1)
        vn = jnp.sum(ja_n * vel6[ba], -1) + jnp.sum(jb_n * vel6[bb], -1)
        dist = contacts["dist"]
        active = dist < 0
        pen = erp / dt * jnp.minimum(dist + m.contact_slop, 0.0)
        bounce = m.material_restitution[mat] * jnp.minimum(vn + m.restitution_threshold, 0.0)
        # a bouncing contact is a hard velocity target (softness would eat the bounce)
        hard = bounce < pen
        add(ja_n, jb_n, jnp.minimum(pen, bounce), jnp.where(hard, 0.0, gamma),
            0.0 if not m.absolute_contact else jnp.where(hard, 0.0, cfm_n),
            0.0, jnp.where(active, INF, 0.0), 0.0, ba, bb)
        if m.directional:  # t1: -mu_forward <= lambda / lambda_n <= mu_backward
            mu = m.material_friction[mat]
            # the grain's weight (0 where it is normal to the contact plane, 1 from
            # DIRECTIONAL_FADE on; 0 for contacts without a direction)
            w = contacts["dir_weight"]
            bounds = ((mu + w * (m.material_friction_backward[mat] - mu),
                       mu + w * (m.material_friction_forward[mat] - mu)), (mu, mu))
        else:  # isotropic: the program of a model without directional spheres
            bounds = ((None, None), (None, None))
        for t, (hi_c, lo_c) in zip((contacts["t1"], contacts["t2"]), bounds):
            add(jnp.concatenate([-t, -jnp.cross(ra, t)], -1),
                jnp.concatenate([t, jnp.cross(rb, t)], -1), 0.0, 0.0, 0.0, -INF, INF,
                m.material_friction[mat] if hi_c is None else hi_c, ba, bb, lower=lo_c)
        if m.torsional:
            z = jnp.zeros_like(n)
            add(jnp.concatenate([z, -n], -1), jnp.concatenate([z, n], -1), 0.0, 0.0, 0.0,
                -INF, INF, m.material_torsional[mat], ba, bb)

    if not parts:
        z = jnp.zeros((0,), dtype)
        e = np.zeros((0,), np.int32)
        return dict(ja=jnp.zeros((0, 6), dtype), jb=jnp.zeros((0, 6), dtype), bias=z,
                    gamma=z, cfm_abs=z, lo=z, hi=z, fric=z, body_a=e, body_b=e, ref=e,
                    is_fric=np.zeros((0,), bool), cone=None, dof=e)
    cols = list(zip(*parts))
    out = {k: jnp.concatenate(v) for k, v in zip(
        ("ja", "jb", "bias", "gamma", "cfm_abs", "lo", "hi", "fric"), cols[:8])}
    if m.directional:
        out["fric_lo"] = jnp.concatenate([p[7] if lo is None else lo
                                          for p, lo in zip(parts, fric_lo)])
    out["body_a"] = np.concatenate(cols[8]).astype(np.int32)
    out["body_b"] = np.concatenate(cols[9]).astype(np.int32)
    nr = out["bias"].shape[0]
    ref = np.arange(nr, dtype=np.int32)
    is_fric = np.zeros((nr,), bool)
    cone = None
    if np_:
        for r in range(1, m.rows_per_contact):
            s = contact_start + r * np_
            ref[s:s + np_] = contact_start + np.arange(np_)
            is_fric[s:s + np_] = r == 3  # torsion: a box; t1, t2 (r = 1, 2): the cone
        cone = (contact_start + np_, np_)
    out["ref"], out["is_fric"], out["cone"] = ref, is_fric, cone
    # the joint coordinate of each servo, limit and joint-spring row (they come first, in
    # that order), -1 for the others: rows of one coordinate share their Jacobian
    on_dof = np.concatenate([np.asarray(d, np.int32).reshape(-1) for d in (
        m.servo_dof if m.n_servo else (), m.limit_dof, m.jspring_dof)])
    out["dof"] = np.concatenate([on_dof, np.full((nr - len(on_dof),), -1, np.int32)])
    return out
