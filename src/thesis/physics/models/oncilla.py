"""The Oncilla quadruped of thesis ch. 3 (§3.2.1) and §4.5 on the shared engine.

What the thesis and public sources fix, and what had to be chosen (every number below cites
its reason, sources in docs/sources.md#oncilla; the chapters' knee spring, drive stiffness and
foot plates' size are fitted, thesis.modelcheck.fit, departure ch4.oncilla_fit):

* **Mass 5.1 kg** (Spröwitz et al. 2018, docs/sources.md#oncilla-mass). Split: each leg 0.27
  kg (femur 0.10, knee drum 0.03, tibia 0.08, foot 0.06: light segments, the motors sit in
  the body, §3.2.1 "low-inertia actuator", "actuated through a cable mechanism by a second
  actuator in the main body"), the rest (4.02 kg) in the trunk, which carries the 8 hip/knee
  motors, the 4 scapula servos, the Roboard and the battery (§4.5).
* **Motors outboard** (the official simulation's render: the motors sit outboard at the
  body's sides, docs/sources.md#oncilla-mass): of the trunk's 4.02 kg, one motor unit per
  leg (``MOTOR_UNIT`` 0.36 kg: hip and knee motor with gearhead 0.15 kg each and the scapula
  servo 0.06 kg, a choice: no source gives the parts' masses) sits at its leg's hip (x, y)
  at the trunk's mid-height; the remaining 2.58 kg fills the trunk box. The trunk's inertia
  is the box's plus the four units' parallel-axis terms (:func:`trunk_inertia`), about twice
  the roll inertia of a solid 4.02-kg box.
* **Trunk and hips** (the official AMARSi simulation, docs/sources.md#oncilla-hips): the
  fore ab/adduction (L0, scapula) axes lie +0.175 m forward of the trunk frame and +-0.069 m
  sideways; the hind ones are assumed to mirror them (-0.175 m: the hind axes are not
  visible in the source). The legs hang outboard of their L0 axes by ``LEG_OFFSET`` 0.031 m
  (the source shows an offset but its value is unreadable; 0.031 m is the width of a motor
  unit between axis and leg, a choice), a 0.20 m track. **Checked against the official
  simulation's render** (the 600 x 404 screenshot, docs/sources.md#oncilla-hips): a
  homography fitted to 8 dots of the floor's square tile lattice (residuals <= 1.2 px) puts
  6 further dots within 5 px of their lattice points, and the floor's right angle gives the
  camera a 43 deg field of view (Webots' default 45 deg). Through it the three feet marked
  on the floor stand 0.59-0.62 lattice units apart sideways and 1.15-1.17 fore to hind: a
  track of 0.53 (+-0.03 for +-2 px) of the fore-hind foot spacing, 0.19-0.21 m with the feet
  0.35-0.38 m apart fore to hind (the hips 0.35 m apart, the feet slightly beyond them in
  the render). The render so agrees with the 0.20 m track within about 10 % and gives no
  support to a wider one, although a wider track is the change that removes most falls of
  random trots. The marks under the feet are about 3 x 3 cm on the floor. The scapula axis
  is modelled in the leg's plane, through the hip point, not 0.031 m inboard of it: with the
  axis inboard, the engine's 30 Jacobi sweeps per step did not hold the scapula servos (the
  standing robot's scapulae drifted 8-11 deg within 2 s; 80 sweeps held them to 1 deg), and
  the lateral foot motion per degree of scapula differs by the cosine of the 0.031 / 0.14 m
  lever ratio only. The trunk box is 0.40 x 0.14 x 0.07 m: its sides at the L0 axes, its
  ends 2.5 cm beyond the hips, 7 cm tall (no source gives the shell). The hips sit 0.02 m
  below the trunk's centre. The 0.35 m hip spacing is about twice the longest stride of Tab.
  3.1 (2a = 182 mm), so fore and hind feet never collide.
* **Legs**: the three-segment pantograph of :mod:`thesis.gaits.leg` (foot segment kept
  parallel to the femur). Fore legs femur 65 mm, tibia 70 mm, foot 40 mm with the joint
  ranges of :func:`thesis.physics.models.leg_geometry.oncilla_geometry` (hip [-30, 65] deg,
  knee from the 100-167 mm reach, scapula -5..+10 deg = "about 5 deg of adduction and 10 deg
  of abduction", §3.3.2.5). Hind legs longer, with more knee range
  (:func:`~thesis.physics.models.leg_geometry.oncilla_hind_geometry`: the fore segments x
  1.09 for a 182 mm reach, the hind foot of Tab. 4.2-4.4's optima reaching 181.9 mm from the
  hip; the knee range x 2200 / 1850, the hind/fore knee motor counts of liboncilla-hw,
  docs/sources.md#oncilla-hind-legs). **Why longer hind legs:** the thesis's own optima, not
  the motor counts: Tab. 4.2-4.4's hind stance targets need about 177-182 mm of reach from
  the hip, beyond the fore legs' 167 mm, while §3.3.1 says the optimisation allowed only
  foot paths in the reachable area, so the real hind legs reached them. The counts are weak
  evidence: ``HW_RANGE_L1_FORE`` / ``_HIND`` (1850 / 2200) are marked "TODO: CHECK" in
  liboncilla-hw and applied to hip and knee alike, and a public controller's configuration
  (``OncillaServer/initial.config``) gives the knee 1350 counts on three legs and 2200 on
  one. Only the knee range's size rests on them. Cheetah-cub, the predecessor, has fore and
  hind legs of different segment proportions (Spröwitz et al. 2013), which agrees with the
  kept choice but gives no Oncilla number. No public source readable here gives the
  Oncilla's segment lengths, the legs' lateral offset, the feet's size or any spring rate.
  The Frontiers article and its supplementary material were found only as their openings.
  The drives' configured gains exist only in the motor boards' raw units (liboncilla-hw
  ``config/MotorSection.h``: P 400, I 20, D 200, max torque 1100), which no source converts
  to N m/rad. Every leg stands with its toe ``BUILD_DEPTH`` below its hip, so the trunk is
  level at build whatever the legs' lengths. The segment masses are the same for all legs (a
  choice: no source gives them). Bodies per leg: femur, knee drum, tibia, foot. The
  pantograph's parallel link (hip -> upper end of the foot segment, length = tibia) is
  massless and modelled as a stiff spring (``link_stiffness``) between the femur's hip point
  and the foot segment, which closes the parallelogram without a loop joint.
* **Scapula and hip**: one universal joint trunk -> femur at the hip point; its first
  axis (body x, sign per side so that + = abduction) is the scapula servo, its second
  (about -y, so + = femur forward, the hip convention of :mod:`thesis.gaits.leg`) the
  hip servo.
* **Knee: cable + extension spring** (§3.2.1, Fig. 3.1b). The knee motor winds a cable
  that *flexes* the knee; a spring *extends* it. Modelled as a drum body on the knee
  axis driven by the knee servo (femur -> drum hinge, the cable length set by the
  motor) and the tibia hinged on the drum (drum -> tibia hinge, same axis) with
  (a) a joint limit at 0, so the tibia cannot open beyond what the cable allows (taut
  cable), but may fold further (slack cable), and (b) the extension spring on that
  hinge (``knee_spring`` N m/rad, preload ``knee_preload`` rad). Under the body weight
  the knee folds beyond the commanded angle until the spring balances the load: the
  compression of §3.3.1.2 that makes the robot slower than the theoretical speed.
  The spring rate (10 N m/rad, preload 0.02 rad) is chosen so that standing on four
  legs folds the knees by about 0.05 rad and lowers the hips by about 1 cm (7 % of the
  hip height), more in the two-leg stance of a trot; no public value exists
  (docs/sources.md#oncilla-knee-spring). Chapters 3, 4 and 6 do not run this default: they run
  the value :mod:`thesis.modelcheck.calibration` fits to V1 alone
  (``ch3/ch4/ch6.model.knee_spring``; departure ``ch3.knee_spring_fitted``). The drum
  carries the knee motor's rotor inertia reflected through the cable (an invisible
  0.2 m, 30 g box: 2e-4 kg m^2, an assumption); without it the 2e-6 kg m^2 drum made
  the engine's block-Jacobi solver (thesis.physics.solver) diverge within one step and
  the legs fold.
* **Solver**: 30 block-Jacobi sweeps per 2.5 ms step with relaxation 0.3. The engine default
  relaxation 1.0 diverged on these chains of light bodies hanging from a 4 kg trunk. With 15
  sweeps at 0.5 the standing robot was quiet for 1.7 s and then jumped 6 cm; with 30 sweeps
  at 0.5 it stood, but 13 of 24 random PSO gaits "exploded" (trunk thrown tens of metres
  up); 30 sweeps at 0.3 stand still and kept those gaits physical (as did halving dt, at
  twice the cost). These are this function's defaults (30 sweeps, ``sweep_order="jacobi"``,
  relaxation 0.3), which the smoke profile uses. **The chapters' former solver**
  (before the momentum order below): 120 sweeps in the ``blocks_first`` order at relaxation 1.0, the
  contact rows at 0.3 (:mod:`thesis.physics.solver`, Sweep order, Contact relaxation). In
  the Jacobi order the servo and limit rows of the scapula/hip joint converge slowly: at 120
  sweeps the scapulae swung up to 8 deg off their command (V6), and Tab. 3.1b's spline
  walked 0.31 m/s at 1.5 Hz against 0.43 / 0.48 m/s at 480 / 960 sweeps, which hold the
  scapulae within 3 / 1 deg (the half ellipse moved by at most 4 %). Blocks first at
  relaxation 1.0, 120 sweeps give the 960-sweep speeds and hold the scapulae within 1 deg; a
  chapter's job costs 1.3-2.2x the CPU of the Jacobi order at the same sweeps; relaxation
  0.5 in the Jacobi order diverges. The contact rows at relaxation 1.0 explode on ch4's
  pebble field, where a toe touches the floor and up to two pebbles at once: of the 200
  first-generation evaluations of its five seeds' two swarms, 200 exploded at 1.0, 1 at 0.5
  and none at 0.3. At the fitted knee spring (2.0) ``model/convergence`` finds Tab. 3.1b at
  1.5 Hz not converged at half the step (its speed moves by more than 10 %), while twice the
  sweeps stays inconclusive. The one alternative the chapters' solver rule named (Jacobi at
  relaxation 0.3, 240 sweeps, contacts at 0.3) refits to the same knee spring (2.0) and is
  not converged either: Tab. 4.2's flat optimum at 2.6 Hz moves by more than 10 % under
  twice its sweeps (480). By that rule the chapters keep blocks first. **Warm start**
  (``warm_start``): the engine's 0.85; 1.0 helps the Jacobi order (120 sweeps then give
  about 480's speeds) but was not needed. **Momentum order** (``sweep_order="momentum"``,
  ``momentum``, ``row_relaxation``, ``momentum_restart``; the chapters' order, below): the
  blocks-first sweeps from extrapolated impulses (:mod:`thesis.physics.solver`, Momentum);
  ``thesis bench solver`` measures its sweeps against the direct solution (config
  ``physics.solver_bench``: momentum 0.85 with the joint blocks at 0.65, the other rows at
  0.8, the contacts at 0.5, restart). As the chapters' solver at half their step (dt 1.25
  ms, 40 sweeps; 0.63 s CPU per simulated robot-second against 0.70 s for 2.5 ms / 120
  blocks-first sweeps, Tab. 3.1b at 1.5 Hz, 16 robots, median of 3) it is **not converged**
  by ``model/convergence`` (30 starts per case, the fitted knee spring 2.0): twice the
  sweeps is inconclusive (no case beyond 10 % with its interval; the half ellipse moves
  by less than 0.1 %), but under half the step Tab. 3.1b at 0.5 Hz (77 % of its starts
  fall) walks 0.085 -> 0.032 m/s, beyond 10 % with its Bonferroni interval; the half
  ellipse moves by at most 0.7 % at every frequency, Tab. 3.1b by 1.2 % at 1.5 Hz (0.325
  m/s; interval to 14 %) and 3.3 % at 2.6 Hz (no fall; to 6 %), Tab. 4.2's flat optimum
  by 5.8 % at its own 1.98 Hz (no fall; to 9.4 %), and that optimum's fall rate at 2.6 Hz
  goes 7 % -> 40 % (the rule pools the fall rate over the cases: +2.5 points). At 60
  sweeps (0.89 s CPU per robot-second) the table is the same (Tab. 3.1b at 0.5 Hz 0.094
  -> 0.031 m/s under half the step; the flat optimum +5.8 % at 1.98 Hz, 10 % -> 37 %
  falls at 2.6 Hz): the step, not the sweeps, moves them. A quarter of the step (0.625 ms,
  40 momentum sweeps, about 1.8x the CPU) is **inconclusive**: twice the sweeps moves no
  case that stays up by more than 0.3 % (falls +0.2 points), but under half that step
  (0.3125 ms) Tab. 3.1b moves +6.9 % at 1.5 Hz (0.322 -> 0.344 m/s) and +7.3 % at 2 Hz
  (its falls 47 % -> 60 %), Tab. 4.2's flat optimum at 2.6 Hz +24 % (falls 40 % -> 90 %),
  while the half ellipse moves by at most 0.4 % at every frequency: the published splines'
  speeds and falls have not settled at any step tried. **The chapters' step and solver**
  (``ch3/ch4/ch6.model``; ch6 at 8.2 / 13 ms, within 1 %): 0.625 ms, 20 momentum sweeps
  (the settings above), with the foot plates. It was the finer of two plate candidates
  fixed before ``model/convergence`` ran on them; 1.25 ms / 40 sweeps is not converged (the
  half ellipse, converged under every step with point feet, moves 78 % at 0.5 Hz and 20 %
  at 1 and 2.6 Hz under half of it: the plates' corner contacts need the shorter step).
  On the fitted model (plates, knee spring and drives of ``ch4.oncilla_fit``) the default
  table (30 starts per case, its 3 % speed tolerance) finds this step **not converged**:
  under half of it the half ellipse walks faster at every frequency, beyond 3 % with its
  Bonferroni interval (+5.7 / +7.7 / +10.1 % at 0.5 / 1 / 1.5 Hz, lower ends +3.4 / +5.4 /
  +7.5 %), as does Tab. 3.1b at 2.6 Hz (+5.4 %, lower end +4.0 %); twice the sweeps is
  inconclusive (no case beyond 3 % with its interval; the largest, Tab. 3.1b at 1.5 Hz,
  +6.4 %, interval down to -5.3 %). V3 fails at every setting (7 / 11 / 9 of 85 runs; at
  this step all at 1 Hz: Tab. 3.1b 3 of 5, Tab. 4.2's flat optimum 4 of 5), so its falls
  are the model's, not the step's. V6 fails at this step on one run of 85 (2.6 deg:
  Tab. 3.1b at 0.5 Hz, a kick to the right fore scapula in one 10-ms period as the robot,
  rolled 30 deg, comes back onto that foot; it decays within 0.3 s) and passes under half
  the step (0.70 deg; at most 0.87 over the table's 30 starts per case). Half this step
  (0.3125 ms, twice the CPU; the same table with ``--set ch4.model.dt=0.0003125``) is not
  converged either: under its own half step Tab. 4.2's flat optimum at 0.5 Hz moves +12.6
  % (Bonferroni interval +4.7 to +17.5 %) and the half ellipse at 1 Hz +5.3 % (+2.7 to
  +6.9 %); the 1.5-2 Hz cases settle there, the slow gaits (0.5-1 Hz) do not, and the falls
  at 1 Hz stay (57-80 % of the starts at every setting). So no step within twice the
  chapters' CPU converges every case, and a finer one would also need the fit made again at
  it: the chapters keep 0.625 ms, declared not converged, and every verdict that rests on
  the Oncilla is shown beside ``model/convergence``'s verdict (ch3.oncilla_model). On ch4's
  pebble field the contact rows take 0.3 (``ch4.pebbles.contact_relaxation``): at the
  chapters' 0.5 the momentum order diverges where a foot's five spheres each touch the floor
  and three pebbles (Tab. 4.4's optima thrown up at 20 sweeps, metres high at 80; none
  thrown at 0.3 with 20, 40 or 80 sweeps). Five contacts per foot cost 1.6x the CPU of one;
  this step 1.35x the CPU per simulated second of 2.5 ms / 120 blocks-first sweeps with
  plates (Tab. 3.1b at 1.5 Hz, 16 robots, median of 3).
* **Drives** (liboncilla-hw, thesis §6.1; docs/sources.md#oncilla-drives). The hip and knee
  motors are brushless motors with position drivers: compliant drives
  (``Builder.add_compliant_servo``), a PD law on the motor angle with stiffness
  ``drive_stiffness`` 20 N m/rad (the chapters run model/fit's value) and damping
  ``drive_damping`` = stiffness / ``DRIVE_DAMPING_RATIO`` (0.4 N m s/rad), bounded by 4 N
  m and 12 rad/s (a 2 Hz trot needs about 2 pi 2 0.5 = 6.3 rad/s at the hip). A load on the
  leg deflects the motor angle by load / stiffness, which is what the motor encoders of ch6
  read ("the rotary encoders in the motors", §6.1). liboncilla-hw configures stiffness and
  damping per motor but its values are not public, so they are chosen: the drive reaches its
  4 N m bound at 0.2 rad (11.5 deg) of error, and stiffness / damping = 50 1/s keeps the
  time constant of the stiff position servos it replaces (gain 50 1/s, like the engine's
  other robots). The knee drive turns the knee drum (the motor's side of the cable). The
  scapula (L0) servo is the official simulation's (docs/sources.md#oncilla-scapula-servo): a
  stiff actuated joint, P gain 10 1/s, 10 N m, 10 rad/s, no spring, no damping (a hard
  position servo, docs/sources.md#tpx-servo). Commands are the *thesis* joint angles of
  :mod:`thesis.gaits.leg` (hip from the downward vertical, inner knee angle, scapula);
  :func:`commands_to_action` subtracts the build pose. New commands every 10 ms (§3.2.2),
  held in between; the physics step ``dt`` is 2.5 ms (four steps per command): at 5 ms some
  gaits (fast leg swings from the settle pose) made the engine diverge to NaN within 0.1 s,
  at 2.5 ms the same gaits walk.
* **Compliance of the constraints** (physical, independent of dt;
  :mod:`thesis.physics.builder`): every joint and joint-limit row is a critically damped
  spring of ``joint_hz`` 400 Hz and every floor contact one of ``contact_hz`` 100 Hz,
  relative to the row's effective mass (a toe under the 5.1-kg robot: contact stiffness
  about m_eff (2 pi 100 Hz)^2). They equal 1 / dt and 0.25 / dt at the 2.5-ms step
  (docs/sources.md#oncilla-compliance); being physical, they make halving dt or doubling
  the sweeps simulate the same robot (the convergence table of ``thesis validate
  oncilla``). No source gives the real robot's values. The contact's
  100 Hz on a toe row's effective mass (at most the 60-g foot segment: at most 2.4e4
  N/m) is of the order of our estimate for a Hertz contact of a 10-mm rubber sphere
  under half the robot's weight (about 3e4 N/m with a Young's modulus of a few MPa, an
  assumed generic rubber value: no source gives the toes' material); nothing is fitted to
  that estimate. With the Jacobi order the table found the published gaits
  whose fore legs rest on their extension stops in stance (``stance_knee_stop``,
  ``stance_cable_taut`` of the validation) not converged; for the chapters' solver see
  Solver above.
* **Foot plates** (``feet="plate"``, the chapters' feet; this function's default
  ``"sphere"``, one toe sphere per foot, is the smoke profile's). The official simulation's render
  (docs/sources.md#oncilla-feet) shows each foot as a flat plate pointing forward, the
  shank standing on it. Measured there through the floor lattice (as the track): length
  72 +- 5 mm (62-87 mm over the four feet; 60-90 mm bounds where a fit needs it), width
  38 +- 5 mm but open (per foot +-8-12 mm: bounds 28-50 mm), the toe 40 mm behind the
  front edge and 32 mm ahead of the heel (about 4 mm behind the plate's centre), 4-7 mm
  thick. The render shows the visual shape only; whether the contact shape is this plate
  is not shown. Modelled as contact points: the toe sphere, and one ``PLATE_RADIUS`` (3
  mm, half a 6-mm plate) sphere under each of the plate's four corners, ``toe_offset``
  ahead of the toe (default ``foot_length / 2 + 4 mm``, the measured place of the toe) and
  ``foot_length - toe_offset`` behind it, +-``foot_width / 2`` to the sides, their lowest
  points level with the toe sphere's (the plate's underside; the standing height is the
  sphere model's). The rounded heel is taken as its bounding rectangle's corners (the
  rounding is not measured). The plate is rigid on the foot segment, flat and pointing
  forward in the build pose (the render's standing robot; the segment stands
  ``build_pose`` 's hip angle from vertical there), so it tilts with the segment as the hip
  swings and the foot rolls onto its toe or heel edge. Its mass (``plate_mass``, 0.02 kg:
  a 72 x 38 x 6 mm plate of a plastic of about 1.2 g/cm^3, a choice) is taken from the
  foot segment's 0.06 kg, so each leg keeps its 0.27 kg and the robot its 5.1 kg: the foot
  body is the segment (0.04 kg, its box) and the plate (a solid box) together, its origin
  at their common centre of mass (the drawn segment box sits there, about 2 cm toward the
  toe of the segment's middle). The corner spheres are added after the four toe spheres,
  so :func:`toe_spheres` keeps its indices (:func:`plate_spheres`). **What the plates do
  to the validation** (``thesis validate oncilla --only validation --profile default``, and
  the same with ``--set ch4.model.feet=sphere``: the fitted values kept, only the feet
  changed): they keep the published gaits up (7 of 85 runs fall, 33 with point toes) and
  cost V2's top speed and V4's linearity. With plates the splines run above their
  theoretical speed (share 1.06-1.29: Tab. 3.1b from 2 Hz, Tab. 4.2's optimum from 1.5
  Hz; at most 0.85 with point toes), the trunk gaining 20-88 mm per cycle over the
  theoretical stride ((speed - theoretical speed) / frequency of the validation's cases),
  up to about the fitted plate's 85-mm length: the plate acts as a rocker that lengthens
  the stride (on the trajectories no case has a flight phase, and the fore plates' loaded
  corners advance heel to toe with little sliding). The half ellipse's share falls from
  0.92 at 1 Hz to 0.61 at 2 Hz (R^2 0.904); with point toes it is linear (0.72-0.82, R^2
  1.000).
* **Feet**: a 10 mm contact sphere at each toe; rubber on the treadmill belt, friction 0.8
  (rubber on a dry hard surface, docs/sources.md#oncilla-feet). Four 20 mm bumper spheres at
  the trunk's lower corners catch a fall. The floor plane z = 0 carries the material
  ``"floor"`` (``friction``, ``restitution``), which every contact sphere uses: a terrain
  changes it with :func:`thesis.physics.terrain.set_material` and tilts gravity with
  :func:`thesis.physics.terrain.incline`, both without recompiling.
* **Camera** (§3.2.1): the Wii remote IR camera, 1024 x 768 pixels, looking forward from
  the front of the trunk; a 33 x 25 deg field of view (the commonly quoted horizontal
  33 deg of that module; square pixels give the vertical). Focal length 1 mm and sensor
  (2 tan 16.5 deg, 0.75 of it) mm (only the ratio matters).
* **LED and distance sensor** (§3.2.2, Fig. 3.2): the infrared LED sits at the front of
  the treadmill, ``led_distance`` ahead of the robot at ``led_height``; the treadmill
  keeps that distance constant, so :func:`led_position` puts it at the trunk's current
  forward position plus ``led_distance`` (on the treadmill's centre line y = 0). The
  Sharp distance sensor (§4.5) measures along the trunk's forward axis to that front
  wall (:func:`distance_sensor`).

Servo order (``SERVO_NAMES``): per leg LF, RF, LH, RH the scapula, hip and knee: the
order of :data:`~thesis.physics.models.leg_geometry.LEGS` x
:data:`~thesis.physics.models.leg_geometry.JOINTS`.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from thesis.physics.models import leg_geometry as L
from thesis.physics.builder import Builder, box_inertia

#: Total mass [kg] (docs/sources.md#oncilla-mass).
MASS = 5.1
#: Leg segment masses [kg]: femur, knee drum, tibia, foot.
LEG_MASSES = (0.10, 0.03, 0.08, 0.06)
#: Trunk size [m] (length, width, height).
TRUNK = (0.40, 0.14, 0.07)
#: Scapula (L0) axis positions relative to the trunk centre [m] (LEGS order;
#: docs/sources.md#oncilla-hips).
SCAPULAE = ((0.175, 0.069, -0.02), (0.175, -0.069, -0.02), (-0.175, 0.069, -0.02),
            (-0.175, -0.069, -0.02))
#: Sideways offset of each leg's plane outboard of its scapula axis [m] (a choice).
LEG_OFFSET = 0.031
#: Hip positions (the femur's upper end, in the leg's plane) relative to the trunk centre
#: [m] (LEGS order).
HIPS = tuple((x, y + (LEG_OFFSET if y > 0 else -LEG_OFFSET), z) for x, y, z in SCAPULAE)
#: Mass of one leg's motor unit (hip and knee motors, scapula servo) in the trunk [kg].
MOTOR_UNIT = 0.36
#: Design depth of the feet below the hips at build time [m] (mid Tab. 4.1 x0 range).
BUILD_DEPTH = 0.142
#: Toe contact sphere radius [m].
TOE_RADIUS = 0.010
#: Foot models of :func:`oncilla` (``feet``).
FEET = ("sphere", "plate")
#: Foot plate length and width [m], measured in the official simulation's render
#: (docs/sources.md#oncilla-feet: 72 +- 5 and 38 +- 5 mm; the width is open, 28-50 mm).
FOOT_LENGTH, FOOT_WIDTH = 0.072, 0.038
#: The toe's place behind the plate's centre [m] (docs/sources.md#oncilla-feet: the toe 40
#: mm behind the front edge of a 72 mm plate).
TOE_BEHIND_CENTRE = 0.004
#: Radius of the plate's corner contact spheres [m]: half a 6 mm plate (4-7 mm in the
#: render, docs/sources.md#oncilla-feet).
PLATE_RADIUS = 0.003
#: Mass of one foot plate [kg], taken from the foot segment's (a choice: no source).
PLATE_MASS = 0.02
#: Ratio drive_stiffness / drive_damping [1/s] of the hip and knee drives: the position
#: servos' time constant, kept when a profile sets another stiffness (Drives).
DRIVE_DAMPING_RATIO = 50.0
#: Camera pixels (Wii remote IR camera, §3.2.1).
CAMERA_PIXELS = (1024, 768)
#: Commands per second (§3.2.2: "new commands to the robot every 10 ms").
COMMAND_PERIOD = 0.01

SERVO_NAMES = tuple(f"{leg}_{j}" for leg in L.LEGS for j in L.JOINTS)


def _u(phi):
    """Unit vector (x, z) of a segment at angle phi from the downward vertical."""
    return np.array([math.sin(phi), 0.0, -math.cos(phi)])


def _roty(phi):
    """Rotation about y taking a box's long (z) axis onto a segment at angle phi."""
    c, s = math.cos(-phi), math.sin(-phi)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def build_pose(geom: L.LegGeometry | None = None, depth: float = BUILD_DEPTH):
    """(hip, knee) [rad] of the build pose of a leg of geometry ``geom`` (default: a fore
    leg): toe straight below the hip at ``depth`` [m]."""
    geom = geom or L.oncilla_geometry()
    a, b = float(geom.femur) + float(geom.foot), float(geom.tibia)
    # law of cosines on the two-link equivalent (numpy: safe inside traced code)
    knee = math.acos((a * a + b * b - depth * depth) / (2 * a * b))
    hip = math.acos((a * a + depth * depth - b * b) / (2 * a * depth))
    return hip, knee


def trunk_inertia(trunk_mass: float = MASS - 4 * sum(LEG_MASSES)) -> np.ndarray:
    """(3, 3) inertia [kg m^2] of the trunk about its centre, body frame: a solid box of
    ``trunk_mass - 4 MOTOR_UNIT`` plus the four motor units as point masses at their hips'
    (x, y) and the trunk's mid-height (see the module docstring)."""
    core = trunk_mass - 4 * MOTOR_UNIT
    a, b, c = TRUNK
    inertia = core / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    for x, y, _ in HIPS:
        r = np.array([x, y, 0.0])
        inertia += MOTOR_UNIT * (r @ r * np.eye(3) - np.outer(r, r))
    return inertia


#: Softness of the joint and joint-limit rows [Hz] (module docstring, "Compliance").
JOINT_HZ = 400.0
#: Softness of the floor contacts [Hz].
CONTACT_HZ = 100.0


def oncilla(*, dt=0.0025, solver_iterations=30, relaxation=0.3, drive_stiffness=20.0,
            drive_damping=0.4, hip_torque=4.0, knee_torque=4.0, scapula_gain=10.0,
            scapula_torque=10.0, hip_velocity=12.0, knee_velocity=12.0,
            scapula_velocity=10.0, knee_spring=10.0, knee_preload=0.02, knee_damping=0.05,
            link_stiffness=2e4, link_damping=20.0, friction=0.8, restitution=0.0,
            drum_size=0.2, field=None,
            camera_pixels=CAMERA_PIXELS, geom: L.LegGeometry | None = None,
            hind_geom: L.LegGeometry | None = None, dtype=jnp.float32,
            tether_rail_height=None, tether_slack=0.0, tether_stiffness=0.0,
            tether_damping=0.0, tether_width=0.0, joint_hz=JOINT_HZ,
            contact_hz=CONTACT_HZ, warm_start=0.85, sweep_order="jacobi",
            contact_relaxation=None, momentum=0.85, row_relaxation=None,
            momentum_restart=True, feet="sphere", foot_length=FOOT_LENGTH,
            foot_width=FOOT_WIDTH, toe_offset=None, plate_mass=PLATE_MASS):
    """Build the Oncilla on a flat floor (material ``"floor"``); returns ``(Model, State)``.

    Args:
        dt: physics step [s] (commands stay at 10 ms, see module docstring).
        joint_hz [Hz]: softness of every joint and joint-limit row; contact_hz [Hz]: of
            the floor contacts (critically damped; physical, independent of dt).
        warm_start: fraction of the last step's impulses the solver starts from (the
            engine's 0.85, docs/sources.md#tpx-step, by default; see the module docstring's Solver).
        relaxation, sweep_order, contact_relaxation: the solver's relaxation factor, the
            order of its updates within a sweep and the contact rows' own relaxation
            factor (None: ``relaxation``) (:mod:`thesis.physics.solver`; module
            docstring, Solver). momentum, momentum_restart: the extrapolation factor of
            the ``"momentum"`` order and whether a sweep whose update turned drops it
            (ignored by the others). row_relaxation: None (``relaxation``) or the
            relaxation factor of the scalar rows that are not contacts
            (:class:`thesis.physics.Builder`).
        drive_stiffness [N m/rad], drive_damping [N m s/rad]: the hip and knee drives' PD.
        scapula_gain [1/s]: the scapula servos' position gain.
        hip_torque, knee_torque, scapula_torque: servo torque limits [N m].
        hip_velocity, knee_velocity, scapula_velocity: servo speed limits [rad/s].
        knee_spring [N m/rad], knee_preload [rad], knee_damping [N m s/rad]: the knee's
            extension spring acting against the cable.
        link_stiffness [N/m], link_damping [N s/m]: the pantograph's parallel link.
        drum_size: edge [m] of the invisible knee-drum box whose inertia stands for the
            reflected rotor inertia of the knee motor.
        tether_rail_height: None (default, no tether) or the height [m] of an overhead
            rail along the treadmill's axis (world x, above y = 0) with the safety thread
            of §4.5 from the robot's head (the trunk's front top edge) to a carriage
            sliding freely on it (``Builder.add_tether``): a tension-only spring of
            ``tether_stiffness`` [N/m] and ``tether_damping`` [N s/m], slack while the head
            is within ``tether_slack`` [m] of the rail. Its leaves (``tether_k`` ...) may
            be changed without recompiling; a slack longer than the robot can stray
            removes it (zero stiffness is not allowed by the engine's spring row).
        tether_width: 0 (default): one thread from the middle of the head's top edge
            (``"thread"``); > 0: a bridle of two such threads (``"thread_left"``,
            ``"thread_right"``) from the head's top edge at y = +-``tether_width`` / 2 [m]
            to the same rail. One thread on the trunk's centre line is a point restraint
            that a roll about the trunk's long axis hardly stretches; the bridle's
            off-centre anchors move away from the rail as the trunk rolls, so it also
            limits roll once taut.
        field: optional static sphere field on the floor (pebbles, §4.6): a dict of
            :meth:`thesis.physics.Builder.add_sphere_field` arguments (``centres``,
            ``radii``, optional ``k``, ``capacity``, ``bounds``, ``cell_size``,
            ``material`` (default ``"floor"``)); its ``spheres`` may be ``"toes"`` (the
            default: the four toe spheres, which carry the robot), ``"all"`` (the trunk
            bumpers too, which touch the ground only when the robot has fallen; with K = 2
            that is 16 field contacts instead of 8, and the cell grows to the bumpers'
            reach) or contact-sphere indices. Without it the floor is the plain plane.
        geom, hind_geom: the fore and the hind legs' geometry (defaults
            :func:`~thesis.physics.models.leg_geometry.oncilla_geometry` and
            :func:`~thesis.physics.models.leg_geometry.oncilla_hind_geometry`).
        feet: ``"sphere"`` (default: one toe sphere per foot) or ``"plate"`` (the
            render's foot plates, module docstring: the toe sphere and four corner spheres
            per foot, :func:`plate_corners`). With plates, a ``field``'s ``"toes"`` are the
            toe and corner spheres.
        foot_length, foot_width [m]: the plate's size (``feet="plate"`` only).
        toe_offset [m]: how far the plate reaches forward of the toe (None:
            ``foot_length / 2 + TOE_BEHIND_CENTRE``, the measured place of the toe).
        plate_mass [kg]: the plate's mass, taken from the foot segment's.
    The servo commands of :func:`commands_to_action` are in thesis joint angles.
    """
    if feet not in FEET:
        raise ValueError(f"oncilla feet must be one of {FEET}, got {feet!r}")
    corners = plate_corners(foot_length, foot_width, toe_offset)
    if feet == "plate" and not 0.0 <= plate_mass < LEG_MASSES[3]:
        raise ValueError(f"plate_mass must lie in [0, {LEG_MASSES[3]}) kg (the foot "
                         f"segment's mass), got {plate_mass}")
    legs = L.leg_geometries(geom, hind_geom)
    b = Builder("oncilla", dt=dt, solver_iterations=solver_iterations, friction=friction,
                relaxation=relaxation, joint_hz=joint_hz, limit_hz=joint_hz,
                contact_hz=contact_hz, restitution=restitution, contact_slop=0.001,
                warm_start=warm_start, sweep_order=sweep_order,
                contact_relaxation=contact_relaxation, momentum=momentum,
                momentum_restart=momentum_restart, row_relaxation=row_relaxation)
    # the floor's own material (same values as the builder's default material), so that a
    # terrain can change it: terrain.set_material("floor")
    b.add_material("floor", friction, restitution, float(contact_hz), 1.0)
    b.add_plane("floor", (0, 0, 1), 0.0, material="floor", color=(0.3, 0.3, 0.3))
    m_leg = sum(LEG_MASSES)
    z_trunk = BUILD_DEPTH + TOE_RADIUS - HIPS[0][2]
    b.add_box("trunk", TRUNK, (0, 0, z_trunk), mass=MASS - 4 * m_leg, color=(0.2, 0.4, 0.8),
              inertia=trunk_inertia(MASS - 4 * m_leg))
    lx, ly, lz = (t / 2 for t in TRUNK)
    for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        b.add_contact_sphere("trunk", 0.02, (sx * (lx - 0.02), sy * (ly - 0.02), -lz + 0.02))
    toes, plates = [], []
    for leg, side, (hx, hy, hz), geom in zip(L.LEGS, L.SIDES, HIPS, legs):
        femur, tibia, foot = geom.femur, geom.tibia, geom.foot
        hip0, knee0 = build_pose(geom)
        hip = np.array([hx, hy, z_trunk + hz])
        knee = hip + femur * _u(hip0)
        t_dir = _u(hip0 + knee0 - math.pi)
        heel = knee + tibia * t_dir
        toe = heel + foot * _u(hip0)
        top = heel - femur * _u(hip0)  # upper end of the foot segment (parallelogram)
        mf, md, mt, mfo = LEG_MASSES
        b.add_box(f"{leg}_femur", (0.02, 0.02, femur), (hip + knee) / 2, rot=_roty(hip0),
                  mass=mf, color=(0.9, 0.7, 0.1))
        b.add_box(f"{leg}_drum", (drum_size, drum_size, drum_size), knee, mass=md, visible=False)
        b.add_box(f"{leg}_tibia", (0.015, 0.015, tibia), (knee + heel) / 2,
                  rot=_roty(hip0 + knee0 - math.pi), mass=mt, color=(0.9, 0.3, 0.1))
        seg = (0.012, 0.012, femur + foot)
        if feet == "plate":
            centre, inertia = _plate_foot(seg, (top + toe) / 2, toe, _roty(hip0), mfo,
                                          plate_mass, corners, foot_width)
            b.add_box(f"{leg}_foot", seg, centre, rot=_roty(hip0), mass=mfo,
                      color=(0.3, 0.3, 0.3), inertia=inertia)
            plates.append([_roty(hip0).T @ (toe + c - centre) for c in corners])
        else:
            centre = (top + toe) / 2
            b.add_box(f"{leg}_foot", seg, centre, rot=_roty(hip0), mass=mfo,
                      color=(0.3, 0.3, 0.3))
        lim_s = (geom.scapula_min, geom.scapula_max)
        lim_h = (geom.hip_min - hip0, geom.hip_max - hip0)
        b.add_universal(f"{leg}_shoulder", "trunk", f"{leg}_femur", hip, (side, 0, 0),
                        (0, -1, 0), limits=(lim_s, lim_h))
        b.add_hinge(f"{leg}_knee", f"{leg}_femur", f"{leg}_drum", knee, (0, -1, 0),
                    limits=(geom.knee_min - knee0, geom.knee_max - knee0))
        b.add_hinge(f"{leg}_cable", f"{leg}_drum", f"{leg}_tibia", knee, (0, -1, 0),
                    limits=(-1.2, 0.0))
        b.add_joint_spring(f"{leg}_cable", knee_spring, knee_damping, rest_angle=knee_preload)
        b.add_hinge(f"{leg}_heel", f"{leg}_tibia", f"{leg}_foot", heel, (0, -1, 0))
        b.add_spring(f"{leg}_link", f"{leg}_femur", f"{leg}_foot", hip, top, link_stiffness,
                     link_damping)
        toe_at = ((0, 0, -(femur + foot) / 2) if feet == "sphere"
                  else _roty(hip0).T @ (toe - centre))
        toes.append(b.add_contact_sphere(f"{leg}_foot", TOE_RADIUS, toe_at))
        b.add_position_servo(f"{leg}_shoulder", scapula_gain, scapula_torque,
                             scapula_velocity, axis_index=0, name=f"{leg}_scapula")
        b.add_compliant_servo(f"{leg}_shoulder", drive_stiffness, drive_damping, hip_torque,
                              hip_velocity, axis_index=1, name=f"{leg}_hip")
        b.add_compliant_servo(f"{leg}_knee", drive_stiffness, drive_damping, knee_torque,
                              knee_velocity, name=f"{leg}_knee")
    # the plates' corners after the four toes, so that the toes keep indices 4-7
    for leg, offsets in zip(L.LEGS, plates):
        toes += [b.add_contact_sphere(f"{leg}_foot", PLATE_RADIUS, o) for o in offsets]
    # onboard camera at the front of the trunk: camera z = body x, x = -body y, y = -body z
    cam_rot = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    fw = 2.0 * math.tan(math.radians(16.5)) * 1e-3
    b.add_camera("onboard", "trunk", (lx, 0.0, 0.0), cam_rot, 1e-3, (fw, 0.75 * fw),
                 camera_pixels)
    if tether_rail_height is not None:
        if not 0.0 <= tether_width <= TRUNK[1]:
            raise ValueError(f"tether_width must be in [0, {TRUNK[1]}] m (the trunk's width), "
                             f"got {tether_width}")
        half = 0.5 * float(tether_width)
        anchors = {"thread": 0.0} if half == 0.0 else {"thread_left": half, "thread_right": -half}
        for name, y in anchors.items():
            b.add_tether(name, "trunk", (lx, y, z_trunk + lz), (0.0, 0.0, tether_rail_height),
                         (1.0, 0.0, 0.0), tether_stiffness, tether_damping, tether_slack)
    if field is not None:
        kw = dict(field)
        spheres = kw.pop("spheres", "toes")
        spheres = {"all": None, "toes": toes}.get(spheres, spheres) \
            if isinstance(spheres, str) else spheres
        if isinstance(spheres, str):
            raise ValueError(f"oncilla field spheres must be 'all', 'toes' or indices, "
                             f"got {spheres!r}")
        kw.setdefault("material", "floor")
        b.add_sphere_field(kw.pop("name", "field"), kw.pop("centres"), kw.pop("radii"),
                           spheres=spheres, **kw)
    model, state = b.build(dtype)
    return model, state


def toe_spheres() -> tuple:
    """Contact-sphere indices of the four toes (LEGS order); 0-3 are the trunk bumpers."""
    return (4, 5, 6, 7)


#: The plate's corners in :func:`plate_corners` order.
PLATE_CORNERS = ("front_left", "front_right", "heel_left", "heel_right")


def plate_spheres(feet: str = "sphere") -> tuple:
    """Contact-sphere indices of the plates' corners (LEGS order, :data:`PLATE_CORNERS`
    within a leg) of a model built with ``feet``; none for ``"sphere"``."""
    return tuple(range(8, 8 + 4 * len(PLATE_CORNERS))) if feet == "plate" else ()


def plate_corners(foot_length=FOOT_LENGTH, foot_width=FOOT_WIDTH, toe_offset=None):
    """(4, 3) centres of a plate's corner spheres relative to the toe sphere's centre in
    the build pose [m] (world axes: x forward, y left, z up), :data:`PLATE_CORNERS` order:
    ``toe_offset`` (None: ``foot_length / 2 + TOE_BEHIND_CENTRE``) ahead of the toe and
    ``foot_length - toe_offset`` behind it, +-``foot_width / 2`` to the sides, their lowest
    points level with the toe sphere's (docs/sources.md#oncilla-feet)."""
    length, width = float(foot_length), float(foot_width)
    ahead = length / 2 + TOE_BEHIND_CENTRE if toe_offset is None else float(toe_offset)
    if not (length > 0 and width > 0 and 0.0 <= ahead <= length):
        raise ValueError(f"foot plate {length} x {width} m with the toe {ahead} m behind "
                         "its front edge is not a plate under its toe")
    dz = PLATE_RADIUS - TOE_RADIUS
    return np.array([[ahead, width / 2, dz], [ahead, -width / 2, dz],
                     [ahead - length, width / 2, dz], [ahead - length, -width / 2, dz]])


def _plate_foot(seg_size, seg_centre, toe, rot, mass, plate_mass, corners, width):
    """World centre of mass and body-frame inertia (3, 3) about it of a foot segment (box
    ``seg_size`` centred at ``seg_centre``, rotation ``rot``) of ``mass - plate_mass`` and
    its plate (a level box under the corners ``corners`` (4, 3) relative to the ``toe``,
    ``width`` wide, ``2 PLATE_RADIUS`` thick) of ``plate_mass`` [kg]."""
    m_seg = mass - plate_mass
    lo, hi = corners[:, 0].min(), corners[:, 0].max()
    plate_centre = toe + np.array([(lo + hi) / 2, 0.0, corners[0, 2]])
    centre = (m_seg * seg_centre + plate_mass * plate_centre) / mass
    # inertias in the body frame; the plate box is level in the world (rot^T turns it)
    i_seg = box_inertia(m_seg, np.asarray(seg_size, np.float64))
    i_plate = rot.T @ box_inertia(plate_mass, np.array([hi - lo, width, 2 * PLATE_RADIUS])) @ rot
    inertia = i_seg + i_plate
    for m, c in ((m_seg, seg_centre), (plate_mass, plate_centre)):
        d = rot.T @ (c - centre)
        inertia = inertia + m * (d @ d * np.eye(3) - np.outer(d, d))
    return centre, inertia


def build_offsets(geom: L.LegGeometry | None = None,
                  hind_geom: L.LegGeometry | None = None) -> np.ndarray:
    """(12,) thesis joint angles [rad] of the build pose (scapula 0, hip0, knee0 per leg,
    each leg's from its geometry: fore ``geom``, hind ``hind_geom``, defaults as
    :func:`oncilla`)."""
    return np.concatenate([np.array([0.0, *build_pose(g)])
                           for g in L.leg_geometries(geom, hind_geom)])


def commands_to_action(commands, geom: L.LegGeometry | None = None,
                       hind_geom: L.LegGeometry | None = None):
    """Servo targets (12,) [rad, engine angles] for thesis joint commands (..., 12) [rad]."""
    c = jnp.asarray(commands)
    return c - jnp.asarray(build_offsets(geom, hind_geom), c.dtype)


def trunk_index(model) -> int:
    """Index of the trunk body."""
    return model.body("trunk")


def led_position(trunk_pos, led_distance=1.5, led_height=0.10, lateral=0.0):
    """(..., 3) world position of the LED [m]: ``led_distance`` ahead of the trunk's
    forward position (the treadmill keeps the distance constant, §3.2.2), at the track's
    centre line ``lateral`` and ``led_height`` above the belt."""
    x = trunk_pos[..., 0] + led_distance
    return jnp.stack([x, jnp.full_like(x, lateral), jnp.full_like(x, led_height)], axis=-1)


def distance_sensor(trunk_pos, trunk_rot, wall_x):
    """Reading [m] of the forward distance sensor (§4.5): distance from the trunk front
    along the trunk's x axis to the wall plane x = ``wall_x`` (inf if facing away)."""
    fwd = trunk_rot[..., :, 0]
    front = trunk_pos + TRUNK[0] / 2 * fwd
    cos = fwd[..., 0]
    return jnp.where(cos > 1e-6, (wall_x - front[..., 0]) / jnp.where(cos > 1e-6, cos, 1.0),
                     jnp.inf)
