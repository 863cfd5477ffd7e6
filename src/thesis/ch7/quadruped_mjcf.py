"""MJCF of an engine model, for the MuJoCo / MJX peer rows of Tab. 7.1 (``ch7_table7_1_peers``).

:func:`model_to_mjcf` writes the MJCF *from the built engine Model and State* (masses,
inertias, poses, joint anchors and axes, limits, servo parameters, contact spheres,
planes, friction, time step, gravity), so the peer robot cannot drift from ours:
change ``thesis.physics.models.quadruped`` and the MJCF follows.

Mapping (engine -> MJCF) and the unavoidable differences:

* bodies: one MJCF body per engine body, nested along the joint tree (root = the body
  without a parent joint, given a free joint); body frame = the engine's centre-of-mass
  frame, ``<inertial>`` with the engine's mass and full inertia. Fixed joints become
  bodies without a joint (welded: exact in reduced coordinates, soft in the engine);
  hinges become hinge joints with the same anchor, axis and range (``limited``).
* visual boxes/spheres: geoms that do not collide (contype = conaffinity = 0); contact
  spheres: sphere geoms colliding only with the planes (contype 1 vs conaffinity 1 of
  the planes); extra sphere-sphere pairs as ``<pair>``. Friction: the pair material's
  Coulomb coefficient, elliptic cone (the engine's isotropic friction cone), condim 3.
* contact softness: ``solref = (timeconst, zeta)`` with ``timeconst = 1 / (2 pi f zeta)``
  from the material's natural frequency f and damping ratio zeta, floored at 2 dt
  (MuJoCo's own stability floor). Restitution has no MuJoCo equivalent (0.01 here).
* servos: the engine's position servo is a hard velocity row with target rate
  ``-clip(gain (q - q_cmd), +-v_max)`` and torque bound. MJCF: a ``<velocity>``
  actuator with gain ``kv`` and ``forcerange = +-max_torque``; the controller feeds it
  the same clipped target rate (:func:`servo_ctrl`), and ``implicitfast`` integrates the
  actuator damping implicitly, so a stiff ``kv`` stays stable.
* sensors (for the closed loop, same 73 channels as ``bench_engine.sensor_vector``):
  ``jointpos`` and ``jointvel`` of the servoed joints, on a site at each IMU body's
  centre of mass the attitude (``framezaxis`` of the world expressed in the site frame,
  the engine's ``imu_up``) or the ``accelerometer``, then the ``gyro``; ``velocimeter``
  on the root.
"""

from __future__ import annotations

import numpy as np

from thesis.physics.types import GeomType, JointType, ServoKind

__all__ = ["model_to_mjcf", "servo_ctrl", "quadruped_mjcf"]


def _f(x) -> str:
    return " ".join(f"{float(v):.7g}" for v in np.ravel(x))


def _quat(r) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix."""
    r = np.asarray(r, np.float64)
    w = np.sqrt(max(0.0, 1.0 + np.trace(r))) / 2.0
    if w > 1e-6:
        return np.array([w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w),
                         (r[1, 0] - r[0, 1]) / (4 * w)])
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = np.sqrt(max(0.0, 1.0 + r[i, i] - r[j, j] - r[k, k])) * 2.0
    q = np.zeros(4)
    q[0] = (r[k, j] - r[j, k]) / s
    q[1 + i] = s / 4.0
    q[1 + j] = (r[j, i] + r[i, j]) / s
    q[1 + k] = (r[k, i] + r[i, k]) / s
    return q


def _tree(model):
    """(root, {child: joint index}, {parent: [children]}) of the joint graph."""
    nb = model.n_body
    parent_joint, children = {}, {b: [] for b in range(nb)}
    for j in range(model.n_joint):
        b1, b2 = int(model.joint_body1[j]), int(model.joint_body2[j])
        if b1 == nb:
            raise ValueError(f"joint {model.joint_names[j]!r} attaches to the world; "
                             "only free-floating trees are supported")
        if b2 in parent_joint:
            raise ValueError(f"body {model.body_names[b2]!r} has two parent joints (a loop)")
        if JointType(int(model.joint_type[j])) not in (JointType.HINGE, JointType.FIXED):
            raise ValueError(f"joint {model.joint_names[j]!r}: only hinge and fixed joints")
        parent_joint[b2] = j
        children[b1].append(b2)
    roots = [b for b in range(nb) if b not in parent_joint]
    if len(roots) != 1:
        raise ValueError(f"expected one root body, found {roots}")
    return roots[0], parent_joint, children


def model_to_mjcf(model, state, *, imu_bodies, imu: str = "attitude",
                  servo_kv: float = 100.0, solver_iterations: int = 1,
                  ls_iterations: int = 4) -> str:
    """MJCF XML string of a free-floating hinge/fixed-joint tree of the engine.

    Args:
        model, state: the engine's Model and (initial) State.
        imu_bodies: body indices that get an IMU site (attitude or accelerometer + gyro).
        imu: ``"attitude"`` (world up axis in the site frame) or ``"accelerometer"``,
            as ``bench_engine.sensor_vector``.
        servo_kv: velocity-actuator gain [N m s/rad].
        solver_iterations, ls_iterations: MuJoCo solver settings.
    """
    m = model
    pos = np.asarray(state.pos, np.float64)
    rot = np.asarray(state.rot, np.float64)
    mass = np.asarray(m.body_mass, np.float64)
    inertia = np.asarray(m.body_inertia, np.float64)
    root, parent_joint, children = _tree(m)
    dt = float(m.dt)
    lim = {int(d): (float(lo), float(hi)) for d, lo, hi in
           zip(m.limit_dof, np.asarray(m.limit_lo), np.asarray(m.limit_hi))}
    first_dof = {int(j): i for i, j in reversed(list(enumerate(m.dof_joint)))}
    geoms = {b: [] for b in range(m.n_body)}
    for g in range(len(m.geom_type)):
        b = int(m.geom_body[g])
        if b >= 0:
            geoms[b].append(g)
    spheres = {b: [] for b in range(m.n_body)}
    for c, b in enumerate(m.csphere_body):
        spheres[int(b)].append(c)
    friction = np.asarray(m.material_friction, np.float64)
    hz = np.asarray(m.material_hz, np.float64)
    zeta = np.asarray(m.material_zeta, np.float64)
    plane_pairs = ~np.asarray(m.pair_is_sphere, bool)
    mat_of_sphere = {int(s): int(mt) for s, mt in
                     zip(m.pair_sphere[plane_pairs], m.pair_material[plane_pairs])}

    def solref(mt):
        tc = max(1.0 / (2 * np.pi * hz[mt] * max(zeta[mt], 1e-6)), 2 * dt)
        return f"{tc:.6g} {max(zeta[mt], 1e-6):.6g}"

    imu_set = set(int(b) for b in imu_bodies)
    lines = []

    def body(b, depth):
        ind = "  " * depth
        name = m.body_names[b]
        if b == root:
            p, r = pos[b], rot[b]
        else:
            pb = int(m.joint_body1[parent_joint[b]])
            p, r = rot[pb].T @ (pos[b] - pos[pb]), rot[pb].T @ rot[b]
        lines.append(f'{ind}<body name="{name}" pos="{_f(p)}" quat="{_f(_quat(r))}">')
        i = inertia[b]
        lines.append(f'{ind}  <inertial pos="0 0 0" mass="{mass[b]:.9g}" fullinertia="'
                     f'{_f([i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]])}"/>')
        if b == root:
            lines.append(f'{ind}  <freejoint name="root"/>')
        else:
            j = parent_joint[b]
            if JointType(int(m.joint_type[j])) == JointType.HINGE:
                axis = np.asarray(m.joint_frame2[j], np.float64)[:, 0]
                d = first_dof[j]
                rng = (f' limited="true" range="{lim[d][0]:.9g} {lim[d][1]:.9g}"'
                       if d in lim else "")
                lines.append(f'{ind}  <joint name="{m.joint_names[j]}" type="hinge" pos="'
                             f'{_f(m.joint_anchor2[j])}" axis="{_f(axis)}"{rng}/>')
        for g in geoms[b]:
            gt, size = GeomType(int(m.geom_type[g])), np.asarray(m.geom_size[g])
            kind, sz = ("box", _f(size)) if gt == GeomType.BOX else ("sphere", _f(size[:1]))
            lines.append(f'{ind}  <geom type="{kind}" size="{sz}" pos="{_f(m.geom_pos[g])}" '
                         f'quat="{_f(_quat(np.asarray(m.geom_rot[g])))}" rgba="'
                         f'{_f(m.geom_color[g])} 1" contype="0" conaffinity="0" mass="0"/>')
        for c in spheres[b]:
            mt = mat_of_sphere.get(c, 0)
            lines.append(f'{ind}  <geom name="contact{c}" type="sphere" size="'
                         f'{float(m.csphere_radius[c]):.9g}" pos="{_f(m.csphere_offset[c])}" '
                         f'contype="1" conaffinity="0" condim="3" friction="{friction[mt]:.6g} '
                         f'0.005 0.0001" solref="{solref(mt)}" mass="0" group="3"/>')
        if b in imu_set:
            lines.append(f'{ind}  <site name="imu_{name}" pos="0 0 0"/>')
        for ch in children[b]:
            body(ch, depth + 1)
        lines.append(f"{ind}</body>")

    world = []
    for k in range(len(m.plane_names)):
        n = np.asarray(m.plane_normal[k], np.float64)
        t1 = np.array([1.0, 0, 0]) if abs(n[0]) < 0.9 else np.array([0, 1.0, 0])
        t1 = t1 - n * (n @ t1)
        t1 /= np.linalg.norm(t1)
        frame = np.stack([t1, np.cross(n, t1), n], axis=1)
        world.append(f'    <geom name="{m.plane_names[k]}" type="plane" size="0 0 1" pos="'
                     f'{_f(n * float(m.plane_offset[k]))}" quat="{_f(_quat(frame))}" '
                     f'contype="0" conaffinity="1" condim="3" friction="{friction[0]:.6g} '
                     f'0.005 0.0001"/>')
    body(root, 2)
    pairs = [f'    <pair geom1="contact{int(s)}" geom2="contact{int(o)}" condim="3" friction="'
             f'{friction[int(mt)]:.6g} {friction[int(mt)]:.6g} 0.005 0.0001 0.0001"/>'
             for s, o, mt, is_s in zip(m.pair_sphere, m.pair_other, m.pair_material,
                                       m.pair_is_sphere) if is_s]
    acts, sens = [], []
    for s in range(m.n_servo):
        if int(m.servo_kind[s]) not in (ServoKind.POSITION, ServoKind.VELOCITY):
            raise ValueError("unknown servo kind")
        j = int(m.dof_joint[int(m.servo_dof[s])])
        tq = float(m.servo_max_torque[s])
        acts.append(f'    <velocity name="{m.servo_names[s]}" joint="{m.joint_names[j]}" '
                    f'kv="{servo_kv:.9g}" forcelimited="true" forcerange="{-tq:.9g} {tq:.9g}"/>')
    for s in range(m.n_servo):
        sens.append(f'    <jointpos joint="{m.joint_names[int(m.dof_joint[int(m.servo_dof[s])])]}"/>')
    for s in range(m.n_servo):
        sens.append(f'    <jointvel joint="{m.joint_names[int(m.dof_joint[int(m.servo_dof[s])])]}"/>')
    names = [m.body_names[int(b)] for b in imu_bodies]
    if imu == "attitude":
        sens += [f'    <framezaxis objtype="xbody" objname="world" reftype="site" '
                 f'refname="imu_{n}"/>' for n in names]
    elif imu == "accelerometer":
        sens += [f'    <accelerometer site="imu_{n}"/>' for n in names]
    else:
        raise ValueError(f"imu must be 'attitude' or 'accelerometer', got {imu!r}")
    sens += [f'    <gyro site="imu_{n}"/>' for n in names]
    sens.append(f'    <velocimeter site="imu_{m.body_names[root]}"/>')
    g = np.asarray(m.gravity, np.float64)
    return "\n".join([
        f'<mujoco model="{m.name}">',
        '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"/>',
        f'  <option timestep="{dt:.9g}" gravity="{_f(g)}" integrator="implicitfast" '
        f'cone="elliptic" solver="Newton" iterations="{int(solver_iterations)}" '
        f'ls_iterations="{int(ls_iterations)}"/>',
        "  <worldbody>", *world, *lines, "  </worldbody>",
        *(["  <contact>", *pairs, "  </contact>"] if pairs else []),
        "  <actuator>", *acts, "  </actuator>",
        "  <sensor>", *sens, "  </sensor>",
        "</mujoco>", ""])


def servo_ctrl(q, command, gain, max_velocity, lo, hi, deadband, kind):
    """Target joint rate of the engine's servos for the MJCF velocity actuators [rad/s].

    ``-clip(gain (q - clip(command, lo, hi)) [|error| > deadband], +-max_velocity)`` for
    position servos, the clipped command for velocity servos (thesis §7.2,
    docs/sources.md#tpx-servo). Works on numpy or jax arrays of shape (..., n_servo).
    """
    xp = np if isinstance(q, np.ndarray) else __import__("jax.numpy", fromlist=["x"])
    cmd = xp.clip(command, lo, hi)
    err = q - cmd
    live = (xp.abs(err) > deadband).astype(err.dtype)
    rate = -xp.clip(gain * err * live, -max_velocity, max_velocity)
    return xp.where(kind == int(ServoKind.POSITION), rate, cmd)


def quadruped_mjcf(**kwargs) -> str:
    """MJCF of the engine's quadruped (``thesis.physics.models.quadruped``, float64)."""
    import jax.numpy as jnp

    from thesis.ch7.bench_engine import sensor_bodies
    from thesis.physics.models import quadruped

    model, state = quadruped(dtype=jnp.float32)
    return model_to_mjcf(model, state, imu_bodies=sensor_bodies(model), **kwargs)
