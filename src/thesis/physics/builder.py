"""Model builder: the only host-to-device boundary of the engine (thesis §7.2;
docs/sources.md#tpx-bodies).

A robot file declares bodies, joints, servos, springs, materials, planes, contact spheres
and cameras by name, in world coordinates of the initial pose, and ``build()`` turns them
into a :class:`~thesis.physics.types.Model` (static topology as numpy arrays, physical
parameters as ``jax.Array``) and the initial :class:`~thesis.physics.types.State`.

Decisions (documented here because the original's JSON format leaves them implicit):

* Inertia: boxes ``m (b^2 + c^2) / 12`` etc.; solid spheres ``0.4 m r^2``. The original's
  sphere inertia ``0.4 m`` without ``r^2`` (docs/sources.md#tpx-bodies quirk) only with
  ``inertia="tpx_quirk"``.
* Softness: every constraint row is a damped spring of natural frequency ``hz`` and
  damping ratio ``zeta`` (docs/sources.md#tpx-step item 3, see ``constraint.py``), relative to the
  row's effective mass: a row of effective mass m acts as a spring of stiffness
  m (2 pi hz)^2 [N/m or N m/rad] with damping 2 zeta m (2 pi hz), so a light body carrying
  a heavy one (a foot under a torso) sags by ``g / (2 pi hz)^2`` times the mass ratio.
  ``hz`` is a physical property of the robot, not of the integrator: it does not change
  with ``dt``, so halving the step or doubling the sweeps refines a simulation of the
  same robot (the engine's validation shows the convergence). Defaults
  (:data:`JOINT_HZ`, :data:`LIMIT_HZ`, :data:`CONTACT_HZ`, ``zeta = 1``, critical
  damping) are 100 Hz for joints and limits and 25 Hz for contacts: ``1 / dt`` and
  ``0.25 / dt`` at the builder's default dt of 0.01 s, the step of every model built
  with the defaults (ball, arm, quadruped, cart-pole; docs/sources.md#engine-compliance);
  a model with another step states its own (:func:`thesis.physics.models.oncilla.oncilla`,
  :func:`thesis.physics.models.puppy.puppy`). Stiff joints keep the sag below a
  millimetre; contacts stiffer than a quarter of the step rate, with warm starting and a
  non-converged parallel solve, can sustain a small bouncing limit cycle (seen on the
  quadruped at 0.5 / dt), so a model should keep ``contact_hz <= 0.25 / dt`` at the
  coarsest step it runs.
* ``relaxation`` (default 0.5) under-relaxes the parallel block updates of the solver;
  1.0 diverges on chains where a light body links two heavier ones (see ``solver.py``).
* ``restitution_threshold`` defaults to ``2 |g| dt``: a resting contact gains ``|g| dt`` of
  approach speed every step, which must not bounce.
* Anchors and axes are given in world coordinates at the initial pose and stored in the
  body frames; "world" (or None) as body1 fixes a joint to the world.
"""

from __future__ import annotations

import numpy as np
import jax.numpy as jnp

from thesis.physics.math import quat_to_rot
from thesis.physics.tables import build_model
from thesis.physics.types import SWEEP_ORDERS, GeomType, JointType, ServoKind

__all__ = ["Builder", "box_inertia", "sphere_inertia", "JOINT_HZ", "LIMIT_HZ", "CONTACT_HZ"]

#: Default softness of joint rows [Hz] (natural frequency, module docstring); independent
#: of dt: 1 / dt at the default dt 0.01 s.
JOINT_HZ = 100.0
#: Default softness of joint-limit rows [Hz]; independent of dt.
LIMIT_HZ = 100.0
#: Default softness of the "default" contact material [Hz]; independent of dt: 0.25 / dt
#: at the default dt 0.01 s.
CONTACT_HZ = 25.0

def box_inertia(mass, size):
    """(3, 3) inertia of a solid box of full edge lengths ``size`` about its centre [kg m^2]."""
    a, b, c = size
    return mass / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def sphere_inertia(mass, radius, kind="solid"):
    """(3, 3) inertia of a sphere: ``"solid"`` 0.4 m r^2, ``"tpx_quirk"`` 0.4 m
    (docs/sources.md#tpx-bodies)."""
    if kind == "solid":
        return 0.4 * mass * radius ** 2 * np.eye(3)
    if kind == "tpx_quirk":
        return 0.4 * mass * np.eye(3)
    raise ValueError(f"unknown sphere inertia kind {kind!r}")


def _rot(rot):
    if rot is None:
        return np.eye(3)
    r = np.asarray(rot, dtype=np.float64)
    return quat_to_rot(r) if r.shape == (4,) else r


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def _perp(a):
    t = np.array([1.0, 0, 0]) if abs(a[0]) < 0.9 else np.array([0, 1.0, 0])
    return _unit(t - a * (a @ t))


class Builder:
    """Declarative model construction by name (docs/architecture.md#engine-rules).

    Args:
        name: model name.
        dt: time step [s]. solver_iterations: PGS sweeps per step. gravity: (3,) [m/s^2].
        warm_start: fraction of the previous impulses used as the initial guess
        (docs/sources.md#tpx-step).
        relaxation: Jacobi relaxation factor of the solver (see ``solver.py``).
        sweep_order: ``"jacobi"`` (default: every joint block and scalar row updated from
            the same velocities), ``"blocks_first"`` (the joint blocks, then the scalar
            rows from the velocities the new block impulses give) or ``"momentum"``
            (blocks-first sweeps with extrapolated impulses); see ``solver.py``.
        momentum, momentum_restart: the ``"momentum"`` order's extrapolation factor in
            [0, 1) and whether a sweep whose update grew drops it (``solver.py``,
            Momentum); the other orders ignore both.
        contact_relaxation: None (default: ``relaxation``) or the relaxation factor of the
            contact rows alone (``solver.py``, Contact relaxation).
        row_relaxation: None (default: ``relaxation``) or the relaxation factor of the
            scalar rows that are not contacts (servo, limit, spring, tether), divided by
            the number of rows of a joint coordinate that can act; the joint blocks keep
            ``relaxation`` (``solver.py``, Momentum).
        joint_hz, joint_zeta: default joint softness [Hz], damping ratio (None:
            :data:`JOINT_HZ`, ratio 1); physical, independent of dt.
        limit_hz, limit_zeta: default joint-limit softness (None: :data:`LIMIT_HZ`).
        reortho_iterations: eq. 7.1 steps per time step.
        restitution_threshold: [m/s] (None: 2 |g| dt). contact_slop: [m] penetration
            left uncorrected (the original's ground ``delta``, docs/sources.md#tpx-contact).
        toi_correction: correct positions for the time of impact of sphere-plane contacts
            (``step.toi_correction``); off by default, as in the original engine.
        friction, restitution, contact_hz, contact_zeta: the "default" material
            (``contact_hz`` None: :data:`CONTACT_HZ`).
    """

    def __init__(self, name, *, dt=0.01, solver_iterations=20, gravity=(0.0, 0.0, -9.81),
                 warm_start=0.85, relaxation=0.5, joint_hz=None, joint_zeta=1.0,
                 limit_hz=None, limit_zeta=1.0, reortho_iterations=1,
                 restitution_threshold=None, contact_slop=0.0, friction=0.5,
                 restitution=0.0, contact_hz=None, contact_zeta=1.0, toi_correction=False,
                 sweep_order="jacobi", contact_relaxation=None, momentum=0.85,
                 momentum_restart=True, row_relaxation=None):
        self.name = name
        self.dt = float(dt)
        self.solver_iterations = int(solver_iterations)
        self.gravity = np.asarray(gravity, dtype=np.float64)
        self.warm_start = float(warm_start)
        self.relaxation = float(relaxation)
        if sweep_order not in SWEEP_ORDERS:
            raise ValueError(f"sweep_order must be one of {SWEEP_ORDERS}, got {sweep_order!r}")
        self.sweep_order = str(sweep_order)
        if contact_relaxation is not None and not 0.0 < float(contact_relaxation) <= 1.0:
            raise ValueError(f"contact_relaxation must be None or in (0, 1], got "
                             f"{contact_relaxation!r}")
        self.contact_relaxation = (None if contact_relaxation is None
                                   else float(contact_relaxation))
        if row_relaxation is not None and not 0.0 < float(row_relaxation) <= 1.0:
            raise ValueError(f"row_relaxation must be None or in (0, 1], got "
                             f"{row_relaxation!r}")
        self.row_relaxation = None if row_relaxation is None else float(row_relaxation)
        if not 0.0 <= float(momentum) < 1.0:
            raise ValueError(f"momentum must be in [0, 1), got {momentum!r}")
        self.momentum = float(momentum)
        self.momentum_restart = bool(momentum_restart)
        self.joint_hz = JOINT_HZ if joint_hz is None else float(joint_hz)
        self.joint_zeta = float(joint_zeta)
        self.limit_hz = LIMIT_HZ if limit_hz is None else float(limit_hz)
        self.limit_zeta = float(limit_zeta)
        self.reortho_iterations = int(reortho_iterations)
        g = float(np.linalg.norm(self.gravity))
        self.restitution_threshold = (2.0 * g * self.dt if restitution_threshold is None
                                      else float(restitution_threshold))
        self.contact_slop = float(contact_slop)
        self.toi_correction = bool(toi_correction)
        self.bodies, self.joints, self.servos, self.springs, self.jsprings = [], [], [], [], []
        self.tethers = []
        self.field = None
        self.materials, self.planes, self.cspheres, self.sphere_pairs = [], [], [], []
        self.geoms, self.cameras, self.textures = [], [], []
        self.add_material("default", friction, restitution,
                          CONTACT_HZ if contact_hz is None else contact_hz, contact_zeta)

    # ---- lookup ---------------------------------------------------------------------
    def _body(self, name):
        if name is None or name == "world":
            return -1
        for i, b in enumerate(self.bodies):
            if b["name"] == name:
                return i
        raise KeyError(f"no body {name!r}")

    def _pose(self, i):
        if i < 0:
            return np.zeros(3), np.eye(3)
        return self.bodies[i]["pos"], self.bodies[i]["rot"]

    def _joint(self, name):
        for i, j in enumerate(self.joints):
            if j["name"] == name:
                return i
        raise KeyError(f"no joint {name!r}")

    def _material(self, name):
        if name is None:
            return None
        return [m["name"] for m in self.materials].index(name)

    def _texture(self, name):
        if name is None:
            return -1
        return [t["name"] for t in self.textures].index(name)

    # ---- bodies ---------------------------------------------------------------------
    def _add_body(self, name, pos, rot, mass, inertia, vel=(0, 0, 0), angvel=(0, 0, 0)):
        if any(b["name"] == name for b in self.bodies):
            raise ValueError(f"duplicate body {name!r}")
        self.bodies.append(dict(name=name, pos=np.asarray(pos, np.float64), rot=_rot(rot),
                                mass=float(mass), inertia=np.asarray(inertia, np.float64),
                                vel=np.asarray(vel, np.float64),
                                angvel=np.asarray(angvel, np.float64)))
        return name

    def add_box(self, name, size, pos, rot=None, mass=None, density=1000.0,
                color=(0.8, 0.8, 0.8), texture=None, visible=True, inertia=None):
        """Add a solid box body of full edge lengths ``size`` [m] at ``pos`` (its centre).

        Mass is ``density * volume`` [kg/m^3] unless ``mass`` [kg] is given
        (docs/sources.md#tpx-bodies). ``rot`` is a 3x3 matrix or a quaternion [w, x, y, z].
        ``inertia`` (3, 3) [kg m^2] about the centre, body frame, replaces the solid box's for a
        body whose mass is not spread evenly (e.g. motors mounted at its sides). Returns ``name``.
        """
        size = np.asarray(size, np.float64)
        m = density * float(np.prod(size)) if mass is None else float(mass)
        inertia = box_inertia(m, size) if inertia is None else np.asarray(inertia, np.float64)
        self._add_body(name, pos, rot, m, inertia)
        if visible:
            self.geoms.append(dict(type=GeomType.BOX, body=len(self.bodies) - 1,
                                   size=size / 2, pos=np.zeros(3), rot=np.eye(3),
                                   color=color, texture=texture))
        return name

    def add_sphere(self, name, radius, pos, rot=None, mass=None, density=1000.0,
                   color=(0.8, 0.8, 0.8), texture=None, inertia="solid", visible=True):
        """Add a solid sphere body of ``radius`` [m]; ``inertia="tpx_quirk"`` reproduces the
        original's 0.4 m (docs/sources.md#tpx-bodies). Returns ``name``."""
        m = density * 4.0 / 3.0 * np.pi * radius ** 3 if mass is None else float(mass)
        self._add_body(name, pos, rot, m, sphere_inertia(m, radius, inertia))
        if visible:
            self.geoms.append(dict(type=GeomType.SPHERE, body=len(self.bodies) - 1,
                                   size=np.array([radius, 0, 0]), pos=np.zeros(3),
                                   rot=np.eye(3), color=color, texture=texture))
        return name

    def set_velocity(self, body, vel=(0, 0, 0), angvel=(0, 0, 0)):
        """Initial world linear [m/s] and angular [rad/s] velocity of a body."""
        b = self.bodies[self._body(body)]
        b["vel"], b["angvel"] = np.asarray(vel, np.float64), np.asarray(angvel, np.float64)

    # ---- joints ---------------------------------------------------------------------
    def _add_joint(self, name, jtype, body1, body2, anchor, axis1, axis2, limits, hz, zeta):
        i1, i2 = self._body(body1), self._body(body2)
        p1, r1 = self._pose(i1)
        p2, r2 = self._pose(i2)
        e1 = _unit(axis1)
        e2 = _perp(e1) if axis2 is None else _unit(np.asarray(axis2) - e1 * (e1 @ _unit(axis2)))
        frame = np.stack([e1, e2, np.cross(e1, e2)], axis=1)
        anchor = np.asarray(p2 if anchor is None else anchor, np.float64)
        width = JointType(jtype).dof_width()
        if limits is not None:
            limits = np.asarray(limits, np.float64).reshape(-1, 2)
            if limits.shape[0] not in (1, width):
                raise ValueError(f"joint {name!r}: need 1 or {width} (lo, hi) limits")
            limits = np.broadcast_to(limits, (width, 2))
        self.joints.append(dict(
            name=name, type=JointType(jtype), b1=i1, b2=i2,
            anchor1=r1.T @ (anchor - p1), anchor2=r2.T @ (anchor - p2),
            frame1=r1.T @ frame, frame2=r2.T @ frame, rel=r1.T @ r2, limits=limits,
            hz=self.joint_hz if hz is None else float(hz),
            zeta=self.joint_zeta if zeta is None else float(zeta)))
        return name

    def add_hinge(self, name, body1, body2, anchor, axis, limits=None, hz=None, zeta=None):
        """Hinge about world ``axis`` through world point ``anchor``; limits (lo, hi) [rad].
        The angle is the rotation of body2 relative to body1 about the axis, 0 at build."""
        return self._add_joint(name, JointType.HINGE, body1, body2, anchor, axis, None,
                               limits, hz, zeta)

    def add_universal(self, name, body1, body2, anchor, axis1, axis2, limits=None,
                      hz=None, zeta=None):
        """Universal joint: ``axis1`` fixed in body1, ``axis2`` (made orthogonal) fixed in
        body2; coordinates (angle about axis1, angle about axis2) [rad]."""
        return self._add_joint(name, JointType.UNIVERSAL, body1, body2, anchor, axis1,
                               axis2, limits, hz, zeta)

    def add_ball(self, name, body1, body2, anchor, hz=None, zeta=None):
        """Ball-and-socket joint; coordinates are the rotation vector of body2 relative to
        body1 in body1's frame [rad]."""
        return self._add_joint(name, JointType.BALL, body1, body2, anchor, (1, 0, 0),
                               (0, 1, 0), None, hz, zeta)

    def add_fixed(self, name, body1, body2, anchor=None, hz=None, zeta=None):
        """Weld body2 to body1 in their relative pose at build time."""
        return self._add_joint(name, JointType.FIXED, body1, body2, anchor, (1, 0, 0),
                               (0, 1, 0), None, hz, zeta)

    def add_slider(self, name, body1, body2, axis, limits=None, hz=None, zeta=None):
        """Prismatic joint along world ``axis``; coordinate = displacement of body2's CoM
        along the axis (fixed in body1) since build [m]; limits (lo, hi) [m]."""
        return self._add_joint(name, JointType.SLIDER, body1, body2, None, axis, None,
                               limits, hz, zeta)

    # ---- actuators and springs ------------------------------------------------------
    def add_position_servo(self, joint, gain, max_torque, max_velocity, deadband=0.0,
                           axis_index=0, command_range=None, name=None):
        """Position servo (docs/sources.md#tpx-servo): drives the joint coordinate's rate towards
        ``-clip(gain * error, +-max_velocity)`` (zero inside ``deadband``) with at most
        ``max_torque`` [N m, or N for sliders]. ``gain`` [1/s]; commands are clipped to
        ``command_range`` (default: the joint limits, if any). Returns the servo index."""
        return self._add_servo(joint, ServoKind.POSITION, gain, max_torque, max_velocity,
                               deadband, axis_index, command_range, name)

    def add_compliant_servo(self, joint, stiffness, damping, max_torque, max_velocity,
                            axis_index=0, command_range=None, name=None):
        """Compliant position drive: a PD law ``stiffness * (command - q) - damping * qdot``
        [N m or N] on the joint coordinate q, integrated implicitly like a joint spring
        whose rest angle is the command, bounded by ``max_torque`` and with its
        position-correction rate bounded by ``max_velocity`` [rad/s or m/s]. Unlike a
        position servo (a hard velocity row), a load on the joint deflects q from the
        command by about load / stiffness: the motor angle a motor encoder reads. Both
        ``stiffness`` and ``damping`` must be positive. Returns the servo index."""
        if not (stiffness > 0 and damping > 0):
            raise ValueError(f"compliant servo on {joint!r}: stiffness and damping must be "
                             f"positive, got {stiffness}, {damping}")
        return self._add_servo(joint, ServoKind.COMPLIANT, 0.0, max_torque, max_velocity,
                               0.0, axis_index, command_range, name, stiffness, damping)

    def add_velocity_servo(self, joint, max_torque, axis_index=0, name=None):
        """Velocity servo: drives the joint coordinate's rate to the command [rad/s, m/s]
        with at most ``max_torque``. Returns the servo index."""
        return self._add_servo(joint, ServoKind.VELOCITY, 0.0, max_torque, np.inf, 0.0,
                               axis_index, None, name)

    def _add_servo(self, joint, kind, gain, max_torque, max_velocity, deadband, axis_index,
                   command_range, name, stiffness=0.0, damping=0.0):
        j = self.joints[self._joint(joint)]
        if command_range is None:
            command_range = ((-np.inf, np.inf) if j["limits"] is None
                             else tuple(j["limits"][axis_index]))
        self.servos.append(dict(joint=joint, axis=int(axis_index), kind=kind, gain=gain,
                                torque=max_torque, vmax=max_velocity, deadband=deadband,
                                lo=command_range[0], hi=command_range[1],
                                k=stiffness, c=damping,
                                name=name or f"{joint}:{axis_index}"))
        return len(self.servos) - 1

    def add_spring(self, name, body1, body2, anchor1, anchor2, stiffness, damping,
                   rest_length=None):
        """Linear spring-damper between world points ``anchor1`` (on body1) and
        ``anchor2`` (on body2) at build time; stiffness [N/m], damping [N s/m];
        rest length [m] defaults to the build-time distance. Integrated implicitly."""
        i1, i2 = self._body(body1), self._body(body2)
        p1, r1 = self._pose(i1)
        p2, r2 = self._pose(i2)
        a1, a2 = np.asarray(anchor1, np.float64), np.asarray(anchor2, np.float64)
        rest = float(np.linalg.norm(a2 - a1)) if rest_length is None else float(rest_length)
        self.springs.append(dict(name=name, b1=i1, b2=i2, a1=r1.T @ (a1 - p1),
                                 a2=r2.T @ (a2 - p2), k=stiffness, c=damping, rest=rest))
        return name

    def add_tether(self, name, body, anchor, rail_point, rail_direction, stiffness, damping,
                   slack):
        """A safety tether: a thread from world point ``anchor`` on ``body`` (at build
        time) to a carriage that slides freely along a straight world rail through
        ``rail_point`` along ``rail_direction``.

        Models the "light thread to an overhead rail" that limited the Oncilla's lateral
        movement on the treadmill, "loose during normal operation" (thesis §4.5). The
        carriage is massless and frictionless, so it always sits at the foot of the
        perpendicular from the anchor to the rail and the thread pulls perpendicular to
        the rail. The thread is a tension-only spring-damper (``stiffness`` [N/m],
        ``damping`` [N s/m], integrated implicitly like every spring here): no force while
        the anchor is within ``slack`` [m] of the rail, ``k (d - slack) + c d'`` (never
        pushing) beyond it. One unilateral row per tether (``constraint.py``); its tension
        is the sensor ``tether_force``. Returns ``name``."""
        i = self._body(body)
        if i < 0:
            raise ValueError(f"tether {name!r}: the tethered body must be a dynamic body")
        p, r = self._pose(i)
        u = _unit(rail_direction)
        self.tethers.append(dict(name=name, body=i, anchor=r.T @ (np.asarray(anchor, float) - p),
                                 rail_point=np.asarray(rail_point, np.float64), rail_dir=u,
                                 k=float(stiffness), c=float(damping), slack=float(slack)))
        return name

    def add_joint_spring(self, joint, stiffness, damping, rest_angle=0.0, axis_index=0):
        """Spring-damper on a joint coordinate: stiffness [N m/rad or N/m], damping
        [N m s/rad or N s/m], rest coordinate [rad or m]. Integrated implicitly."""
        self._joint(joint)
        self.jsprings.append(dict(joint=joint, axis=int(axis_index), k=stiffness,
                                  c=damping, rest=rest_angle))
        return len(self.jsprings) - 1

    # ---- contact --------------------------------------------------------------------
    def add_material(self, name, friction, restitution, stiffness_hz, damping_ratio,
                     torsional=0.0, friction_forward=None, friction_backward=None,
                     stiffness=None, damping=0.0):
        """Contact material: Coulomb friction, restitution, softness (natural frequency
        [Hz], damping ratio) and torsional friction length [m] (torque bound =
        torsional * normal force). Replaces a material of the same name.

        ``friction_forward`` / ``friction_backward`` (default: ``friction``) are the
        Coulomb coefficients of a *directional* contact sphere (``add_contact_sphere(...,
        direction=...)``) sliding forward / backward along its direction; ``friction``
        then bounds the lateral sliding. Contacts of spheres without a direction use
        ``friction`` in every direction.

        ``stiffness`` [N/m] and ``damping`` [N s/m] (opt-in) make the contact an implicit
        spring-damper in physical units, independent of the bodies' masses (a material
        stiffness measured or derived from a modulus): its normal row then has
        ``erp = h k / (h k + c)`` and ``cfm = 1 / (h (h k + c))`` on the impulse
        (:mod:`thesis.physics.constraint`), and ``stiffness_hz`` / ``damping_ratio`` are
        unused. Static, a contact pressed by F sinks F / k beyond the slop. Without
        ``stiffness`` (or with 0) the softness is relative to the contact's effective mass
        (natural frequency, damping ratio) as before."""
        fwd = friction if friction_forward is None else friction_forward
        bwd = friction if friction_backward is None else friction_backward
        m = dict(name=name, friction=friction, restitution=restitution, hz=stiffness_hz,
                 zeta=damping_ratio, torsional=torsional, friction_forward=fwd,
                 friction_backward=bwd,
                 stiffness=0.0 if stiffness is None else float(stiffness),
                 damping=float(damping))
        if m["stiffness"] < 0 or m["damping"] < 0 or (m["stiffness"] == 0 and m["damping"] > 0):
            raise ValueError(f"material {name!r}: stiffness {stiffness} N/m and damping "
                             f"{damping} N s/m must be >= 0, damping only with a stiffness")
        names = [x["name"] for x in self.materials]
        if name in names:
            self.materials[names.index(name)] = m
        else:
            self.materials.append(m)
        return name

    def add_plane(self, name, normal, offset, material="default", color=(0.9, 0.9, 0.9),
                  texture=None, visible=True, collide=True):
        """Static infinite plane {x : n.x = offset} (any orientation, for slopes).
        ``collide=False`` makes a purely visual plane (e.g. a camera backdrop)."""
        n = _unit(normal)
        if collide:
            self.planes.append(dict(name=name, normal=n, offset=float(offset),
                                    material=self._material(material)))
        if visible:
            t1 = _perp(n)
            self.geoms.append(dict(type=GeomType.PLANE, body=-1, size=np.zeros(3),
                                   pos=n * float(offset),
                                   rot=np.stack([t1, np.cross(n, t1), n], axis=1),
                                   color=color, texture=texture))
        return name

    def add_contact_sphere(self, body, radius, offset=(0, 0, 0), material=None,
                           direction=None):
        """Collision sphere of ``radius`` [m] at ``offset`` (body frame) on ``body``. It
        collides with every plane and with spheres listed by ``add_sphere_pair``; its
        material (if given) overrides the plane's. Returns its index.

        ``direction`` (body frame, normalised here) makes its friction directional, like
        a skin with scales or bristles (Puppy II's feet, thesis §5.3.1: "an adhesive skin
        attached with asymmetrical friction"): in each contact the first friction row
        lies along the direction projected onto the contact plane, bounded by the
        material's ``friction_forward`` times the normal force while the sphere slides
        forward along it and ``friction_backward`` while it slides backward; the second
        (lateral) row by ``friction``, together an elliptic cone in the grain's frame
        (``thesis.physics.solver.cone``). Without a direction the friction cone is the
        isotropic one (and the model compiles to the same program as one built without
        the option)."""
        if direction is not None:
            direction = np.asarray(direction, np.float64).reshape(3)
            if not np.linalg.norm(direction) > 0:
                raise ValueError("add_contact_sphere: direction must be a non-zero 3-vector")
            direction = direction / np.linalg.norm(direction)
        self.cspheres.append(dict(body=self._body(body), radius=float(radius),
                                  offset=np.asarray(offset, np.float64),
                                  material=self._material(material), direction=direction))
        return len(self.cspheres) - 1

    def add_sphere_pair(self, sphere1, sphere2, material="default"):
        """Let contact spheres ``sphere1`` and ``sphere2`` (indices) collide."""
        self.sphere_pairs.append((int(sphere1), int(sphere2), self._material(material)))

    def add_sphere_field(self, name, centres, radii, material="default", *, k=2,
                         spheres=None, cell_size=None, capacity=None, bounds=None):
        """A static field of world-fixed spheres (pebbles, rough ground) that collide with
        the dynamic contact spheres ``spheres`` (indices; default: every contact sphere
        at ``build()``), each checking only its ``k`` nearest field spheres per step.

        Detection costs the same for any number N of field spheres: at build time the
        spheres are sorted into a uniform x-y grid of ``cell_size`` [m] cells holding at
        most ``capacity`` spheres each (``thesis.physics.collision.field_contacts``); a
        query sphere looks at the 3 x 3 cells around its centre only and keeps the ``k``
        smallest gaps, so the solver gets ``k`` contact rows per query sphere (inactive
        ones clamp to zero impulse). Field spheres never collide with planes or with each
        other, and they do not move.

        Args:
            name: the field's name (one field per model).
            centres: (N, 3) world centres [m]. radii: () or (N,) radii [m].
            material: contact material (a query sphere's own material overrides it, as
                against planes).
            k: field spheres per query sphere and step (static).
            spheres: contact-sphere indices that collide with the field.
            cell_size: grid cell edge [m]; minimum: the largest field radius plus the
                largest query-sphere radius (a touching sphere then lies in the 3 x 3
                neighbourhood); default 1 % more than that.
            capacity: spheres per cell; default: the most in any cell of this layout.
            bounds: ((x_min, y_min), (x_max, y_max)) the grid covers [m]; default: the
                centres' bounding box. Other layouts of the same model
                (:func:`thesis.physics.terrain.set_field`) must fit the bounds and the
                capacity, which fix the compiled shapes.
        Returns ``name``.
        """
        if self.field is not None:
            raise ValueError(f"model {self.name!r} already has the sphere field "
                             f"{self.field['name']!r}; one field per model")
        centres = np.asarray(centres, np.float64).reshape(-1, 3)
        radii = np.broadcast_to(np.asarray(radii, np.float64), (centres.shape[0],)).copy()
        if int(k) < 1:
            raise ValueError(f"sphere field {name!r}: k must be >= 1, got {k}")
        self.field = dict(name=name, centres=centres, radii=radii,
                          material=self._material(material), k=int(k),
                          spheres=None if spheres is None else [int(i) for i in spheres],
                          cell_size=cell_size, capacity=capacity, bounds=bounds)
        return name

    # ---- rendering ------------------------------------------------------------------
    def add_texture(self, name, image):
        """Register an RGB texture ``image`` (h, w, 3) with values in [0, 1]."""
        img = np.asarray(image, np.float64)
        if img.ndim != 3 or img.shape[2] != 3 or img.min() < 0 or img.max() > 1:
            raise ValueError("texture must be (h, w, 3) in [0, 1]")
        self.textures.append(dict(name=name, image=img))
        return name

    def add_camera(self, name, body, pos, rot, focal_length, sensor_size, pixels):
        """Pinhole camera; ``pos``/``rot`` relative to ``body`` ("world" for a fixed camera);
        camera frame x right, y down, z forward (docs/sources.md#tpx-camera). Returns ``name``."""
        self.cameras.append(dict(name=name, body=self._body(body), pos=np.asarray(pos, float),
                                 rot=_rot(rot), focal=float(focal_length),
                                 sensor=tuple(sensor_size), pixels=tuple(int(p) for p in pixels)))
        return name

    # ---- build ----------------------------------------------------------------------
    def build(self, dtype=jnp.float32):
        """Compile the declarations into ``(Model, State)`` with float arrays of ``dtype``."""
        return build_model(self, dtype)
