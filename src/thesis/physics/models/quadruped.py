"""The quadruped "predator" of thesis §7.3.1 / §7.3.3 (Fig. 7.3b).

Thesis: 8 actuated DoF (a hip and a knee per leg), the torso collides with the ground
through 4 spheres inside the cuboid, 17 rigid bodies (Tab. 7.1), 28.7 kg with 75 % in the
torso, servos limited to 4 N m, 10 s simulated in 1000 steps (§7.3.3) -> dt = 0.01 s.
Geometry and the rest from [TPX] ``robotmodel/demi_predator_ground.json``
(docs/sources.md#tpx-quadruped): spine box 0.7 x 0.3 x 0.1 m at z 0.4 (21 kg); 4 bumper spheres r
0.05 at (+-0.3, +-0.1, 0.4) fixed to the spine; per leg at (+-0.3, +-0.2): femur box 0.05 x 0.05 x
0.2 at z 0.3, tibia box 0.05 x 0.05 x 0.15 at z 0.125, foot sphere r 0.05 at z 0.05 fixed to the
tibia; hips at z 0.4 and knees at z 0.2, axes y; density 1000 kg/m^3; servos gain 50 1/s, 1440
deg/s, commands within +-45 deg, no dead band; servo order knees 1-4 then hips 1-4 (motor ids 0-7);
ground mu 0.5, slop 0.01 m, restitution 0.01; warm start 0.85. Solver iterations: 20, as the JSON's
dt = 0.01 s variant (``demi_predator.json``). Compliance: the builder's physical defaults, joints
and limits 100 Hz, contacts 25 Hz, critically damped (:mod:`thesis.physics.builder`; independent of
dt). Joints are parent -> child (spine -> femur -> tibia), so a positive hip angle rotates the femur
about +y relative to the spine.
"""

from __future__ import annotations

import numpy as np
import jax.numpy as jnp

from thesis.physics.builder import Builder

#: Leg positions (x, y) of legs 1-4 [m] (demi_predator_ground.json).
LEGS = ((0.3, 0.2), (0.3, -0.2), (-0.3, 0.2), (-0.3, -0.2))
#: Bumper sphere positions (x, y) [m] (demi_predator_ground.json).
BUMPERS = ((-0.3, 0.1), (0.3, -0.1), (-0.3, -0.1), (0.3, 0.1))


def quadruped(*, dt=0.01, solver_iterations=20, warm_start=0.85, servo_gain=50.0,
              servo_max_torque=4.0, servo_max_velocity=np.deg2rad(1440.0),
              servo_range=np.deg2rad(45.0), friction=0.5, restitution=0.01,
              contact_slop=0.01, gravity=(0.0, 0.0, -9.81), sphere_inertia="solid",
              joint_hz=None, dtype=jnp.float32):
    """Build the quadruped; returns ``(Model, State)``. Servos: knee1-4, hip1-4 [rad]."""
    b = Builder("quadruped", dt=dt, solver_iterations=solver_iterations,
                warm_start=warm_start, gravity=gravity, contact_slop=contact_slop,
                friction=friction, restitution=restitution, joint_hz=joint_hz)
    b.add_plane("floor", (0, 0, 1), 0.0, color=(0.5, 0.5, 0.5))
    b.add_box("spine", (0.7, 0.3, 0.1), (0, 0, 0.4), color=(0, 0.8, 0.2))
    for i, (x, y) in enumerate(BUMPERS, 1):
        name = f"spine-sphere{i}"
        b.add_sphere(name, 0.05, (x, y, 0.4), inertia=sphere_inertia, visible=False)
        b.add_fixed(f"bumper{i}", "spine", name, (x, y, 0.4))
        b.add_contact_sphere(name, 0.05)
    for i, (x, y) in enumerate(LEGS, 1):
        b.add_box(f"femur{i}", (0.05, 0.05, 0.2), (x, y, 0.3), color=(1, 0.8, 0))
        b.add_box(f"tibia{i}", (0.05, 0.05, 0.15), (x, y, 0.125), color=(1, 0.2, 0))
        b.add_sphere(f"foot{i}", 0.05, (x, y, 0.05), inertia=sphere_inertia,
                     color=(0.3, 0.3, 0.3))
        b.add_hinge(f"hip{i}", "spine", f"femur{i}", (x, y, 0.4), (0, 1, 0))
        b.add_hinge(f"knee{i}", f"femur{i}", f"tibia{i}", (x, y, 0.2), (0, 1, 0))
        b.add_fixed(f"heel{i}", f"tibia{i}", f"foot{i}", (x, y, 0.05))
        b.add_contact_sphere(f"foot{i}", 0.05)
    rng = (-servo_range, servo_range)
    for joint in [f"knee{i}" for i in range(1, 5)] + [f"hip{i}" for i in range(1, 5)]:
        b.add_position_servo(joint, servo_gain, servo_max_torque, servo_max_velocity,
                             command_range=rng, name=joint)
    return b.build(dtype)
