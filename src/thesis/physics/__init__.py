"""The shared differentiable rigid-body engine (thesis chapter 7, §7.2;
docs/architecture.md#engine).

Public API (rules: docs/architecture.md#engine-rules); everything not re-exported here is private:

* ``Builder`` -> ``build(dtype) -> (Model, State)``; ``Model``/``State`` pytrees and the
  enums ``JointType``, ``DofKind``, ``ServoKind``, ``GeomType``;
* ``step(model, state, action) -> State``;
* ``sensors(model, state) -> dict``;
* ``rollout`` / ``batched_rollout`` / ``decay_gradient`` (BPTT through closed loops);
* ``render``, ``render_batch``, ``project_points`` (differentiable camera, ``camera.py``);
* ``box_inertia``, ``sphere_inertia``, ``orthonormalize`` (eq. 7.1), ``safe_norm``;
* terrain as data (``terrain``): ``incline`` (slopes by rotated gravity), ``grade_angle``,
  ``set_material`` (floor friction, restitution, softness), ``set_field`` /
  ``clear_field`` (a sphere field's layout); per-robot model leaves through
  ``batched_rollout(..., per_robot=...)``;
* ``Builder`` elements for chapters 4-6: ``add_sphere_field`` (static pebbles, K nearest
  per contact sphere), ``add_tether`` (tension-only thread to a rail),
  ``add_contact_sphere(..., direction=...)`` with ``add_material(..., friction_forward=,
  friction_backward=)`` (directional friction);
* ``perturbation``: rounding-level perturbed twins (``scale_positions``; the process-wide
  size of ``thesis --perturb`` that every ``rollout`` starts under).

Module map: ``types`` (Model, State, enums), ``math``, ``builder`` + ``tables`` (host ->
device), ``kinematics`` (joint frames, coordinates, rows), ``collision``, ``constraint``
(row assembly, softness), ``solver`` (projected block Jacobi), ``integrator``
(semi-implicit Euler + eq. 7.1), ``sensors``, ``step``, ``rollout``, ``camera``,
``terrain`` (terrain parameters as model leaves).
"""

from thesis.physics.builder import Builder as Builder
from thesis.physics.builder import box_inertia as box_inertia
from thesis.physics.builder import sphere_inertia as sphere_inertia
from thesis.physics.math import orthonormalize as orthonormalize
from thesis.physics.math import safe_norm as safe_norm
from thesis.physics.rollout import batched_rollout as batched_rollout
from thesis.physics.rollout import decay_gradient as decay_gradient
from thesis.physics.rollout import rollout as rollout
from thesis.physics.sensors import sensors as sensors
from thesis.physics.step import step as step
from thesis.physics.types import DofKind as DofKind
from thesis.physics.types import GeomType as GeomType
from thesis.physics.types import JointType as JointType
from thesis.physics.types import Model as Model
from thesis.physics.types import ServoKind as ServoKind
from thesis.physics.types import State as State

from thesis.physics import perturbation as perturbation
from thesis.physics import terrain as terrain
from thesis.physics.terrain import grade_angle as grade_angle
from thesis.physics.terrain import incline as incline
from thesis.physics.terrain import clear_field as clear_field
from thesis.physics.terrain import set_field as set_field
from thesis.physics.terrain import set_material as set_material

from thesis.physics.camera import project_points as project_points
from thesis.physics.camera import render as render
from thesis.physics.camera import render_batch as render_batch

__all__ = [
    "Builder", "Model", "State", "JointType", "DofKind", "ServoKind", "GeomType",
    "step", "sensors", "rollout", "batched_rollout", "decay_gradient", "render",
    "render_batch", "project_points",
    "box_inertia", "sphere_inertia", "orthonormalize", "safe_norm",
    "terrain", "incline", "grade_angle", "set_material", "set_field", "clear_field",
    "perturbation",
]
