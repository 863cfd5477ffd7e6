"""Puppy II, the quadruped of thesis ch. 5 (§5.3.1, Fig. 5.2), on the shared engine.

What the thesis fixes (§5.3.1): "four identical legs, each controlled by a single
servomotor at the hip joint. The knee joints are not directly controllable, but are
passively moveable due to the spring attached between the upper and lower limb.
Underneath the feet there is an adhesive skin attached with asymmetrical friction"; a
potentiometer on each of the 8 joints, a tactile (force) sensor on each paw, an IMU and
an overhead camera giving position and velocity. Nothing else: no public source gives
Puppy II's mass, dimensions, segment lengths, spring rates or servo parameters
(docs/sources.md#puppy). Every number below is therefore a choice, made from the
robot's class (a small, dog-sized walking robot of the Zurich AI Lab's "Puppy" line
built from hobby servos) and from what a simulation of it needs; none was
fitted to a result of the thesis.

* **Mass 1.5 kg**: trunk 1.1 kg (a 0.22 x 0.11 x 0.05 m box carrying four hobby servos
  of ~55 g, the IMU and the electronics), each leg 0.10 kg (femur 0.06 kg: servo horn
  and aluminium bracket; tibia 0.04 kg: a light rod with the paw and its force
  sensor). Small walking robots built from hobby servos weigh 1-2 kg.
* **Legs**: hips at the trunk's lower side edges, (+-0.09, +-0.055) m from the trunk
  centre, 0.015 m below it; femur and tibia 0.065 m each (the robot stands ~0.14 m
  high). Build pose: femur 20 deg backward of the downward vertical, tibia 20 deg
  forward of it, so the knee points backward and the paw sits straight below the hip;
  all four legs identical ("four identical legs"). Probes on the isotropic floor before
  any data existed: with the knee pointing forward, or with hips 0.15 m apart and
  0.075 m segments, the fore-hind anti-phase sine gait pitched the robot over within
  1-3 s at 1 Hz (and with the knee forward it walked backward); the geometry above
  stays upright at 0.25-1.72 Hz and walks forward at 1 and 1.72 Hz.
* **Hip servo** (the only actuator per leg): position servo, gain 50 1/s (as the
  engine's other robots), 1.0 N m and 6 rad/s (a standard hobby servo's 0.6-1.2 N m
  and 60 deg / 0.15-0.2 s); commands within +-0.8 rad of the build pose. The fastest
  gait of Tab. 5.1 (1.72 Hz, amplitude 0.28 rad) needs ~3 rad/s.
* **Passive knee**: a hinge between femur and tibia with a torsion spring (the
  thesis's "spring attached between the upper and lower limb") of 3.0 N m/rad, rest
  angle at the build pose (no preload), damping 0.005 N m s/rad, and limits: no
  extension beyond the build pose (0 rad) and at most 1.2 rad of flexion. The rate and
  the preload are chosen (no source gives them, docs/sources.md#puppy-body): the preload
  must not exceed the standing load, ~0.08 N m per knee, or the knee rests on its stop
  and never flexes in stance, where the Puppy II's passive knees flex under the robot's
  weight (§5.3.1 "passively moveable"); with none, the knee takes ~0.08 / 3 = 0.03 rad
  standing and more under a gait's stance loads. The rate is kept from the first model:
  with 0.6 N m/rad the front knees folded by 0.45 rad when standing and the robot
  pitched over in a gait; with 2.0 it turned over in slow (0.25 Hz) gaits (both probes
  with a 0.1 rad preload, which held the knees on their stops when standing).
  Knee angle: positive = flexion.
* **Paws**: a 12 mm contact sphere at the tibia's distal end, carrying the paw's force
  sensor. The skin's "asymmetrical friction" is the engine's directional friction
  (``Builder.add_contact_sphere(..., direction=...)``) along the robot's forward axis
  (the world +x of the build pose, fixed in the tibia): a paw sliding backward meets
  the floor's full Coulomb coefficient mu, one sliding forward ``skin_ratio * mu``
  (default 0.5), sideways mu. The thesis gives no ratio; directional skins (scales,
  bristles, ski skins) grip two to several times harder against their grain than with
  it, and 0.5 is the mild end of that range: the skin helps the stance push the robot
  forward without making a backward slide impossible. The floor's mu comes from the
  terrain (the chapter's terrain code sets the floor material, forward coefficient
  included); this file builds the robot on a plain default floor (friction 0.6).
* **Bumpers**: four 10 mm contact spheres at the trunk's lower corners catch a fall.
* **Solver**: the builder's dt 5 ms (4 physics steps per 20 ms sample of the 50 Hz
  recordings); chapter 5 runs ``ch5.model.dt``, 1.25 ms, because at 5 ms and again at 2.5
  ms the convergence table (``thesis validate puppy``: the chapter's recordings at dt / 2
  and with twice the sweeps, 20 trials per Tab. 5.1 cell and a follow-up on the cells it
  leaves undecided) found cells whose speed moved beyond its 3 % tolerance under dt / 2
  (at 5 ms the bound on foam at 1.72 Hz and the random gait on Styrofoam and linoleum at
  1 Hz; at 2.5 ms the bound on foam at 1.52 and 1.72 Hz, +3.9 and +3.3 %, while twice the
  sweeps converged); at 1.25 ms it converged (largest change +1.5 % under dt / 2, +0.3 %
  under twice the sweeps, no trial fell). 120 block-Jacobi sweeps with relaxation 0.3 (the
  relaxation the Oncilla needed for its light legs under a heavy trunk,
  thesis.physics.models.oncilla). 120 sweeps are the fewest of 30, 60 and 120 at which
  that table, at 5 ms and an earlier 10 % tolerance, found no cell whose speed moved
  beyond tolerance: at 30 and 60
  sweeps the slow (0.25 Hz) gaits on the softest floor, Styrofoam, walk more than 10 %
  slower than with more sweeps, i.e. the solver had not converged on the paws' contacts.
  At 120 the table's verdict is "inconclusive", not "converged": no change is shown
  beyond tolerance, but the trial-to-trial spread of a few cells (the turn on Styrofoam
  at 1.25-1.52 Hz, the random gaits) leaves their intervals wider than 10 %.
* **Compliance** (physical, independent of dt; :mod:`thesis.physics.builder`): joint and
  limit rows 200 Hz, critically damped (``JOINT_HZ``): 1 / dt at the 5-ms step
  (docs/sources.md#puppy-body). The floor contact is either the engine's relative
  softness, 50 Hz critically damped (``CONTACT_HZ``, 0.25 / dt at 5 ms, with 1 mm of
  contact slop), or, with ``contact_stiffness`` given, a spring-damper in physical units
  [N/m, N s/m] (``Builder.add_material(..., stiffness=)``) with no slop: the spring is
  then the paw-floor contact's whole compliance. Chapter 5's terrains use the latter
  (:func:`thesis.ch5.recordings.terrain_model`, values from docs/sources.md#ch5-terrain-contact);
  being physical, a smaller step refines the same robot.

Sensors the chapter records (§5.3.1) map onto the engine's: hip and knee
``joint_angle`` (potentiometers), paw ``contact_force``, trunk ``imu_acc`` and
``imu_gyro``; :func:`magnetometer`, :func:`heading` and :func:`wall_distance` compute the
rest from the trunk pose, as a magnetometer, the overhead camera and a range reading
would.

Servo order (``SERVO_NAMES``) and leg order: LF, RF, LH, RH (left fore, right fore,
left hind, right hind).
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from thesis.physics.builder import Builder

#: Leg names, in servo order.
LEGS = ("LF", "RF", "LH", "RH")
#: Total mass [kg].
MASS = 1.5
#: Trunk size [m] (length, width, height) and mass [kg].
TRUNK = (0.22, 0.11, 0.05)
TRUNK_MASS = 1.1
#: Femur and tibia length [m] and mass [kg].
FEMUR, TIBIA = 0.065, 0.065
FEMUR_MASS, TIBIA_MASS = 0.06, 0.04
#: Hip positions relative to the trunk centre [m], LEGS order.
HIPS = ((0.09, 0.055, -0.015), (0.09, -0.055, -0.015), (-0.09, 0.055, -0.015),
        (-0.09, -0.055, -0.015))
#: Build-pose inclination of the femur from the downward vertical [rad] (negative:
#: backward; the tibia is inclined by the opposite angle, so the knee points backward).
LEG_ANGLE = math.radians(-20.0)
#: Paw contact sphere radius [m].
PAW_RADIUS = 0.012
#: Hip servo and knee joint names, LEGS order.
SERVO_NAMES = tuple(f"{leg}_hip" for leg in LEGS)
KNEE_NAMES = tuple(f"{leg}_knee" for leg in LEGS)


def _seg(phi):
    """Unit vector (x, 0, z) of a segment at angle phi from the downward vertical
    (positive phi points forward, +x)."""
    return np.array([math.sin(phi), 0.0, -math.cos(phi)])


def _roty(phi):
    """Rotation about y taking a box's long (z) axis onto a segment at angle phi."""
    c, s = math.cos(-phi), math.sin(-phi)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def leg_height() -> float:
    """Height of the hips above the paw centres at the build pose [m]."""
    return (FEMUR + TIBIA) * math.cos(LEG_ANGLE)


#: Softness of the joint and joint-limit rows [Hz] (module docstring, "Compliance").
JOINT_HZ = 200.0
#: Softness of the paws' and bumpers' contacts [Hz].
CONTACT_HZ = 50.0


def puppy(*, dt=0.005, solver_iterations=120, relaxation=0.3, servo_gain=50.0,
          hip_torque=1.0, hip_velocity=6.0, hip_range=0.8, knee_spring=3.0,
          knee_preload=0.0, knee_damping=0.005, knee_max_flexion=1.2, friction=0.6,
          restitution=0.0, skin_ratio=0.5, joint_hz=JOINT_HZ, contact_hz=CONTACT_HZ,
          contact_stiffness=None, contact_damping=0.0, sweep_order="jacobi", momentum=0.85,
          dtype=jnp.float32):
    """Build Puppy II standing on a flat floor (plane ``"floor"``, material
    ``"default"``); returns ``(Model, State)``.

    Args:
        dt: physics step [s]; solver_iterations, relaxation: solver settings;
            sweep_order, momentum: the solver's order of updates and the momentum
            order's extrapolation factor (:mod:`thesis.physics.solver`; the default is
            the Jacobi order every chapter-5 result used).
        servo_gain [1/s], hip_torque [N m], hip_velocity [rad/s]: hip position servos.
        hip_range: hip commands are clipped to +-hip_range of the build pose [rad].
        knee_spring [N m/rad], knee_preload [rad], knee_damping [N m s/rad]: the passive
            knee's torsion spring (rest angle ``-knee_preload``, i.e. pushing towards
            extension against the stop at 0); knee_max_flexion [rad]: the flexion stop.
        friction, restitution: the default floor material (terrains replace it).
        skin_ratio: the paws' forward / backward friction ratio (1: isotropic friction);
            the floor material's ``friction_forward`` is ``skin_ratio * friction``.
        joint_hz [Hz]: softness of the joint and limit rows; contact_hz [Hz]: of the
            floor contacts (critically damped; physical, independent of dt).
        contact_stiffness [N/m], contact_damping [N s/m]: the floor contact as a
            spring-damper in physical units, without contact slop (None: the relative
            softness ``contact_hz`` with 1 mm of slop; module docstring, "Compliance").
    Hip commands (the servo actions) are angles relative to the build pose [rad],
    positive = femur swung forward.
    """
    physical = contact_stiffness is not None
    b = Builder("puppy", dt=dt, solver_iterations=solver_iterations, relaxation=relaxation,
                friction=friction, restitution=restitution,
                contact_slop=0.0 if physical else 0.001,
                joint_hz=joint_hz, limit_hz=joint_hz, contact_hz=contact_hz,
                sweep_order=sweep_order, momentum=momentum)
    if not 0.0 < float(skin_ratio) <= 1.0:
        raise ValueError(f"puppy: skin_ratio must lie in (0, 1], got {skin_ratio}")
    default = b.materials[0]
    b.add_material("default", friction, restitution, default["hz"], default["zeta"],
                   friction_forward=float(skin_ratio) * friction, friction_backward=friction,
                   stiffness=contact_stiffness, damping=contact_damping if physical else 0.0)
    b.add_plane("floor", (0, 0, 1), 0.0, color=(0.35, 0.35, 0.4))
    z_hip = leg_height() + PAW_RADIUS
    z_trunk = z_hip - HIPS[0][2]
    b.add_box("trunk", TRUNK, (0, 0, z_trunk), mass=TRUNK_MASS, color=(0.85, 0.85, 0.9))
    lx, ly, lz = (t / 2 for t in TRUNK)
    for sx, sy in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
        b.add_contact_sphere("trunk", 0.01, (sx * (lx - 0.01), sy * (ly - 0.01), -lz + 0.01))
    for leg, (hx, hy, hz) in zip(LEGS, HIPS):
        hip = np.array([hx, hy, z_trunk + hz])
        knee = hip + FEMUR * _seg(LEG_ANGLE)
        paw = knee + TIBIA * _seg(-LEG_ANGLE)
        b.add_box(f"{leg}_femur", (0.02, 0.02, FEMUR), (hip + knee) / 2,
                  rot=_roty(LEG_ANGLE), mass=FEMUR_MASS, color=(0.2, 0.2, 0.2))
        b.add_box(f"{leg}_tibia", (0.012, 0.012, TIBIA), (knee + paw) / 2,
                  rot=_roty(-LEG_ANGLE), mass=TIBIA_MASS, color=(0.6, 0.6, 0.6))
        # hip about -y: a positive angle swings the femur forward
        b.add_hinge(f"{leg}_hip", "trunk", f"{leg}_femur", hip, (0, -1, 0))
        # knee axis chosen so that folding the knee (the paw moving towards the hip) is a
        # positive angle; the stop at 0 keeps it from extending past the build pose
        knee_axis = (0, 1, 0) if LEG_ANGLE > 0 else (0, -1, 0)
        b.add_hinge(f"{leg}_knee", f"{leg}_femur", f"{leg}_tibia", knee, knee_axis,
                    limits=(0.0, knee_max_flexion))
        b.add_joint_spring(f"{leg}_knee", knee_spring, knee_damping, rest_angle=-knee_preload)
        # the skin's grain: the robot's forward axis, in the tibia's frame
        b.add_contact_sphere(f"{leg}_tibia", PAW_RADIUS, (0, 0, -TIBIA / 2),
                             direction=_roty(-LEG_ANGLE).T @ np.array([1.0, 0.0, 0.0]))
        b.add_position_servo(f"{leg}_hip", servo_gain, hip_torque, hip_velocity,
                             command_range=(-hip_range, hip_range), name=f"{leg}_hip")
    return b.build(dtype)


def hip_dofs(model) -> np.ndarray:
    """(4,) indices into ``joint_angle`` of the hips, LEGS order."""
    return np.array([model.dof(f"{leg}_hip") for leg in LEGS])


def knee_dofs(model) -> np.ndarray:
    """(4,) indices into ``joint_angle`` of the knees, LEGS order."""
    return np.array([model.dof(f"{leg}_knee") for leg in LEGS])


def paw_spheres(model) -> np.ndarray:
    """(4,) indices into ``contact_force`` of the paws, LEGS order (after the 4 bumpers)."""
    return np.arange(4, 8)


def trunk_index(model) -> int:
    """Index of the trunk body."""
    return model.body("trunk")


def magnetometer(trunk_rot, field=(0.42, 0.0, -0.91)):
    """(..., 3) magnetometer reading: the unit geomagnetic field in the trunk frame.

    ``field``: world field direction (x = magnetic north; an inclination of ~65 deg down,
    as in central Europe where Puppy II was recorded). Units: fraction of the field's
    magnitude [1].
    """
    f = jnp.asarray(field, jnp.asarray(trunk_rot).dtype)
    f = f / jnp.linalg.norm(f)
    return jnp.einsum("...ji,j->...i", trunk_rot, f)


def heading(trunk_rot):
    """(...,) heading of the trunk's forward axis in the floor plane [rad], (-pi, pi],
    0 along world x, counter-clockwise positive (what the overhead camera derives)."""
    fwd = trunk_rot[..., :, 0]
    return jnp.arctan2(fwd[..., 1], fwd[..., 0])


def wall_distance(trunk_pos, trunk_rot, half_width=2.0, max_range=4.0):
    """(...,) distance [m] from the trunk centre along its heading to the nearest wall of
    a square arena ``|x|, |y| <= half_width`` centred on the origin, clipped to the range
    finder's ``max_range``. Outside the arena the nearest wall line ahead counts."""
    h = heading(trunk_rot)
    d = jnp.stack([jnp.cos(h), jnp.sin(h)], -1)
    p = trunk_pos[..., :2]
    big = jnp.asarray(max_range, p.dtype)
    ts = []
    for axis in (0, 1):
        for wall in (-half_width, half_width):
            v = d[..., axis]
            ok = jnp.abs(v) > 1e-6
            t = (wall - p[..., axis]) / jnp.where(ok, v, 1.0)
            ts.append(jnp.where(ok & (t > 0), t, big))
    return jnp.minimum(jnp.min(jnp.stack(ts, -1), -1), big)
