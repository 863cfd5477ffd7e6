"""The 4-DoF robot arm of thesis §7.3.2 (Fig. 7.3c).

Thesis §7.3.2: "2 degrees of freedom actuated universal joint" at the base and a 2-DoF
actuated elbow, 1 m long, 32 kg, servos with gain 30 1/s, torque 30 N m, velocity
45 deg/s. Layout from [TPX] ``robotmodel/robot_arm.json`` (FACTS §2.10): each 2-DoF joint
is two hinges around a 0.1 m sphere (base: z then y, elbow: z then y), boxes
0.14 x 0.14 x 0.5 m, end effector sphere r 0.1 m fixed on top at z 1.1 m, density
1000 kg/m^3 (total 32.2 kg); y hinges limited to +-90 deg; servo dead band 0.01 rad;
ground contacts on the elbow and end-effector spheres (mu 0.5, slop 0.01 m, restitution
0.01); dt 0.01 s, 20 solver iterations, warm start 0.85; the base is fixed to the world
(the JSON's 1e6 kg "universe"). The JSON's 10 N m torque is overridden by the thesis's 30.
"""

from __future__ import annotations

import numpy as np
import jax.numpy as jnp

from thesis.physics.builder import Builder


def arm4(*, dt=0.01, solver_iterations=20, warm_start=0.85, servo_gain=30.0,
         servo_max_torque=30.0, servo_max_velocity=np.deg2rad(45.0), servo_deadband=0.01,
         hinge_limit=np.deg2rad(90.0), friction=0.5, restitution=0.01, contact_slop=0.01,
         gravity=(0.0, 0.0, -9.81), dtype=jnp.float32):
    """Build the arm; returns ``(Model, State)``. Servo order: base z, base y, elbow z,
    elbow y (radians); end effector body ``"sphere2"``."""
    b = Builder("arm4", dt=dt, solver_iterations=solver_iterations, warm_start=warm_start,
                gravity=gravity, contact_slop=contact_slop, friction=friction,
                restitution=restitution)
    b.add_plane("floor", (0, 0, 1), 0.0, color=(0.5, 0.5, 0.5))
    b.add_sphere("sphere0", 0.1, (0, 0, 0.1), color=(0.2, 0.2, 0.8))
    b.add_box("femur", (0.14, 0.14, 0.5), (0, 0, 0.35), color=(0.8, 0.6, 0.1))
    b.add_sphere("sphere1", 0.1, (0, 0, 0.6), color=(0.2, 0.2, 0.8))
    b.add_box("tibia", (0.14, 0.14, 0.5), (0, 0, 0.85), color=(0.8, 0.6, 0.1))
    b.add_sphere("sphere2", 0.1, (0, 0, 1.1), color=(0.9, 0.1, 0.1))
    lim = (-hinge_limit, hinge_limit)
    b.add_hinge("joint0", "world", "sphere0", (0, 0, 0.1), (0, 0, 1))
    b.add_hinge("joint1", "sphere0", "femur", (0, 0, 0.1), (0, 1, 0), limits=lim)
    b.add_hinge("joint2", "femur", "sphere1", (0, 0, 0.6), (0, 0, 1))
    b.add_hinge("joint3", "sphere1", "tibia", (0, 0, 0.6), (0, 1, 0), limits=lim)
    b.add_fixed("effector", "tibia", "sphere2", (0, 0, 1.1))
    for j in ("joint0", "joint1", "joint2", "joint3"):
        b.add_position_servo(j, servo_gain, servo_max_torque, servo_max_velocity,
                             deadband=servo_deadband, name=j)
    b.add_contact_sphere("sphere1", 0.1)
    b.add_contact_sphere("sphere2", 0.1)
    return b.build(dtype)
