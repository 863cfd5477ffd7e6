"""Model and State pytrees and the enums of the engine (thesis §7.2,
docs/architecture.md#engine).

Both are frozen dataclasses registered with ``jax.tree_util``. Fields listed in a class's
``_STATIC`` tuple are topology and loop counts (ints, tuples, numpy arrays, strings): they
go into the tree definition, so shapes and loop bounds stay static under ``jit`` and a
model with other topology compiles anew. Every other field is a ``jax.Array`` leaf:
physical parameters can be differentiated (morphology gradients) and batched with
``vmap``. Build them only with keywords and change them with ``.replace(...)``.

Conventions: world frame z up; a body's pose is (pos, rot) with
``world_point = pos + rot @ local_point`` (the original engine stored ``rot`` transposed,
docs/sources.md#tpx-bodies); ``pos`` is the centre of mass; ``vel``/``angvel`` are world-frame
linear and angular velocities of the centre of mass. Index ``n_body`` stands for the static world
body in every body-index array (``geom_body`` and ``camera_body`` use -1 for the world, as in the
camera contract).
"""

from __future__ import annotations

import dataclasses
import enum
from typing import Any

import jax
import numpy as np

__all__ = ["JointType", "DofKind", "ServoKind", "GeomType", "Model", "State", "SWEEP_ORDERS"]


class JointType(enum.IntEnum):
    """Joint kinds (docs/sources.md#tpx-rows). ``dof_width()`` is the number of free joint
    coordinates."""

    HINGE = 0
    UNIVERSAL = 1
    BALL = 2
    FIXED = 3
    SLIDER = 4

    def dof_width(self) -> int:
        return {0: 1, 1: 2, 2: 3, 3: 0, 4: 1}[int(self)]


class DofKind(enum.IntEnum):
    """A joint coordinate is an angle [rad] or a displacement [m]."""

    ANGULAR = 0
    LINEAR = 1


class ServoKind(enum.IntEnum):
    """Position servo (target coordinate), velocity servo (target rate)
    (docs/sources.md#tpx-servo), or compliant position drive (an implicit spring-damper
    towards the command, bounded in torque and speed: ``Builder.add_compliant_servo``)."""

    POSITION = 0
    VELOCITY = 1
    COMPLIANT = 2


class GeomType(enum.IntEnum):
    """Visual geometry kinds read by the camera (:mod:`thesis.physics.camera`)."""

    SPHERE = 0
    BOX = 1
    PLANE = 2


class _StaticAux:
    """Hashable wrapper of static field values (numpy arrays compared by value)."""

    __slots__ = ("values", "_key")

    def __init__(self, values):
        self.values = values
        self._key = tuple(_freeze(v) for v in values)

    def __hash__(self):
        return hash(self._key)

    def __eq__(self, other):
        return isinstance(other, _StaticAux) and self._key == other._key


def _freeze(v):
    if isinstance(v, np.ndarray):
        return ("nd", v.dtype.str, v.shape, v.tobytes())
    if isinstance(v, (list, tuple)):
        return tuple(_freeze(x) for x in v)
    return v


def _register(cls):
    static = cls._STATIC
    names = [f.name for f in dataclasses.fields(cls)]
    data = [n for n in names if n not in static]

    def flatten_with_keys(obj):
        children = [(jax.tree_util.GetAttrKey(n), getattr(obj, n)) for n in data]
        return children, _StaticAux(tuple(getattr(obj, n) for n in static))

    def flatten(obj):
        return [getattr(obj, n) for n in data], _StaticAux(tuple(getattr(obj, n) for n in static))

    def unflatten(aux, children):
        obj = object.__new__(cls)
        for n, v in zip(data, children):
            object.__setattr__(obj, n, v)
        for n, v in zip(static, aux.values):
            object.__setattr__(obj, n, v)
        return obj

    jax.tree_util.register_pytree_with_keys(cls, flatten_with_keys, unflatten, flatten)
    return cls


#: Orders of the updates within one solver sweep (``Model.sweep_order``,
#: :mod:`thesis.physics.solver`).
SWEEP_ORDERS = ("jacobi", "blocks_first", "momentum")


class _Replace:
    def replace(self, **changes):
        """A copy with the given fields changed (keywords only)."""
        return dataclasses.replace(self, **changes)


@_register
@dataclasses.dataclass(frozen=True, kw_only=True, eq=False)
class Model(_Replace):
    """A rigid-body scene: bodies, joints, servos, springs, contacts, geometry, cameras.

    Static (topology, counts; numpy / int / tuple):
        name: model name.
        n_body: number of dynamic bodies (the world is index ``n_body``).
        body_names: (n_body,) names.
        solver_iterations: block-Jacobi PGS sweeps per step.
        sweep_order: ``"jacobi"``, ``"blocks_first"`` or ``"momentum"``, the order of the
            updates within a sweep (:data:`SWEEP_ORDERS`, :mod:`thesis.physics.solver`).
        momentum: extrapolation factor beta in [0, 1) of the ``"momentum"`` order (the
            others ignore it); momentum_restart: whether that order drops the
            extrapolation for a sweep whose update grew (:mod:`thesis.physics.solver`,
            Momentum).
        contact_relaxation: None (default: the contact rows use ``relaxation``) or the
            relaxation factor of the contact rows alone (normals, friction, torsion;
            :mod:`thesis.physics.solver`, Contact relaxation).
        row_relaxation: None (default: ``relaxation``) or the relaxation factor of the
            other scalar rows (the joints' servo, limit and spring rows, tethers), divided
            by the number of rows of a joint coordinate that can act; the joint blocks
            keep ``relaxation`` (:mod:`thesis.physics.solver`, Momentum).
        reortho_iterations: eq. 7.1 steps per time step.
        joint_names, joint_type (n_joint,) JointType, joint_body1/joint_body2 (n_joint,)
            body indices, joint_row_mask (n_joint, 6) bool: which of the 6 equality rows
            (3 linear, 3 angular) of a joint are used.
        dof_names, dof_joint (n_dof,), dof_kind (n_dof,) DofKind, dof_slot (n_dof,) index
            of the coordinate within its joint.
        servo_names, servo_dof (n_servo,), servo_kind (n_servo,) ServoKind.
        limit_dof (n_limit,), jspring_dof (n_jspring,), spring_names,
        spring_body1/spring_body2 (n_spring,).
        tether_names, tether_body (n_tether,): body of each tether (``Builder.add_tether``).
        csphere_body (n_csphere,) body of each contact sphere.
        pair_sphere (n_pair,) contact sphere, pair_other (n_pair,) plane index or second
        contact sphere, pair_is_sphere (n_pair,) bool, pair_material (n_pair,) material.
        pair_dir_sphere (n_pair,) the pair's contact sphere with a friction direction,
        pair_dir_sign (n_pair,) +1 if that sphere is the pair's body b, -1 if body a, 0 if
        the pair's friction is isotropic (``directional``: any pair is not).
        field_name: name of the model's static sphere field ("" without one,
            ``Builder.add_sphere_field``); field_query (n_query,) the contact spheres that
            collide with it; field_k: field spheres each of them checks per step (its K
            nearest candidates); field_grid (nx, ny, capacity): the field's uniform x-y
            grid, border cells included; field_material (n_query,) material of each
            query sphere's field contacts; field_dir_sign (n_query,) 1 where the query
            sphere has a friction direction. A field adds ``n_query * field_k`` contacts
            after the listed pairs (``n_field_pair``; ``n_contact`` counts both).
        torsional: whether contacts carry a torsional-friction row.
        absolute_contact: whether some material's contact is a spring-damper in physical
            units (``material_stiffness`` > 0; ``Builder.add_material(..., stiffness=)``).
            Without one the contact rows are assembled exactly as before the option existed.
        toi_correction: whether a body's position is corrected for the time of impact of
            its sphere-plane contacts (``step.toi_correction``; off by default).
        material_names, plane_names.
        geom_type (G,) GeomType, geom_body (G,) (-1 world), geom_texture (G,) (-1 none).
        camera_names, camera_body (C,) (-1 world), camera_pixels ((px_w, px_h), ...).
        batched: the step runs under ``jax.vmap`` over a batch of robots (default False).
            Gives the solver its robots-last ``jax.vmap`` rule (``thesis.physics.solver``:
            the sweeps vectorise over robots). Tab. 7.1, batch 128 over two cores, forward
            1,296 parameters: 6.56 s (vmapped scatter-add) -> 5.12 s (vmapped one-hot
            product) -> 2.7 s (XLA flags of ``thesis.jaxsetup``) -> 1.2 s (robots-last
            rule with a scatter-add over contiguous rows). Results agree with an unbatched
            model up to float round-off; reverse-mode gradients work in either order of
            ``jax.grad`` and ``jax.vmap``, forward-mode (``jax.jvp``) does not (a
            ``custom_vjp``). Leave it False for one robot.

    Traced (jax.Array):
        dt: () time step [s]. gravity: (3,) [m/s^2]. warm_start: () fraction of last
        step's impulses used as the initial guess. relaxation: () Jacobi relaxation factor.
        restitution_threshold: () approach speed below which no bounce is added [m/s].
        contact_slop: () allowed penetration before position correction [m].
        body_mass (n_body,) [kg]; body_inertia (n_body, 3, 3) about the CoM, body frame
        [kg m^2].
        joint_anchor1/2 (n_joint, 3) anchor in body1/body2 frame [m]; joint_frame1/2
        (n_joint, 3, 3) joint axes (columns: axis 1, axis 2, their cross product) in the
        body1/body2 frames; joint_rel_rot (n_joint, 3, 3) rest relative rotation
        rot1^T rot2; joint_hz, joint_zeta (n_joint,) softness (natural frequency [Hz],
        damping ratio).
        servo_gain [1/s], servo_max_torque [N m or N], servo_max_velocity [rad/s or m/s],
        servo_deadband [rad or m], servo_lo/servo_hi command range (n_servo,);
        servo_stiffness [N m/rad or N/m], servo_damping [N m s/rad or N s/m] (n_servo,) of
        compliant drives (0 for the other kinds).
        limit_lo, limit_hi (n_limit,) [rad or m]; limit_hz, limit_zeta (n_limit,).
        jspring_k [N m/rad or N/m], jspring_c [N m s/rad or N s/m], jspring_rest (n_jspring,).
        spring_anchor1/2 (n_spring, 3) body frames [m], spring_k [N/m], spring_c [N s/m],
        spring_rest [m] (n_spring,).
        tether_anchor (n_tether, 3) body frame [m], tether_rail_point (n_tether, 3) world
        [m], tether_rail_dir (n_tether, 3) unit world rail direction, tether_k [N/m],
        tether_c [N s/m], tether_slack [m] (n_tether,).
        csphere_radius (n_csphere,) [m], csphere_offset (n_csphere, 3) body frame [m],
        csphere_direction (n_csphere, 3) unit friction direction, body frame (zero for
        isotropic spheres).
        plane_normal (n_plane, 3) unit, plane_offset (n_plane,) [m]: plane n.x = offset.
        field_centre (nx * ny * capacity, 3) world centres of the field's spheres, cell by
        cell (``capacity`` slots per cell; empty slots far below the floor with radius 0),
        field_radius (nx * ny * capacity,) [m], field_origin (2,) world x-y of the grid's
        corner [m], field_cell () grid cell edge [m] (``thesis.physics.terrain.set_field``
        packs a layout into them).
        material_friction, material_restitution, material_hz, material_zeta,
        material_torsional [m], material_friction_forward, material_friction_backward
        (n_material,) (directional spheres sliding forward / backward; see
        ``Builder.add_contact_sphere``); material_stiffness [N/m], material_damping
        [N s/m] (n_material,): a contact in physical units (0: the relative softness
        ``material_hz``, ``material_zeta`` applies).
        geom_size (G, 3), geom_pos (G, 3), geom_rot (G, 3, 3), geom_color (G, 3),
        textures (T, h, w, 3).
        camera_pos (C, 3), camera_rot (C, 3, 3), camera_focal (C,) [m], camera_sensor (C, 2) [m].
    """

    _STATIC = (
        "name", "n_body", "body_names", "solver_iterations", "reortho_iterations",
        "joint_names", "joint_type", "joint_body1", "joint_body2", "joint_row_mask",
        "dof_names", "dof_joint", "dof_kind", "dof_slot",
        "servo_names", "servo_dof", "servo_kind", "limit_dof", "jspring_dof",
        "spring_names", "spring_body1", "spring_body2", "tether_names", "tether_body",
        "csphere_body", "pair_sphere", "pair_other", "pair_is_sphere", "pair_material",
        "pair_dir_sphere", "pair_dir_sign",
        "field_name", "field_query", "field_k", "field_grid", "field_material",
        "field_dir_sign", "torsional", "toi_correction", "absolute_contact", "material_names",
        "plane_names",
        "geom_type", "geom_body", "geom_texture",
        "camera_names", "camera_body", "camera_pixels", "batched", "sweep_order",
        "contact_relaxation", "row_relaxation", "momentum", "momentum_restart",
    )

    name: str
    n_body: int
    body_names: tuple
    solver_iterations: int
    reortho_iterations: int
    joint_names: tuple
    joint_type: np.ndarray
    joint_body1: np.ndarray
    joint_body2: np.ndarray
    joint_row_mask: np.ndarray
    dof_names: tuple
    dof_joint: np.ndarray
    dof_kind: np.ndarray
    dof_slot: np.ndarray
    servo_names: tuple
    servo_dof: np.ndarray
    servo_kind: np.ndarray
    limit_dof: np.ndarray
    jspring_dof: np.ndarray
    spring_names: tuple
    spring_body1: np.ndarray
    spring_body2: np.ndarray
    tether_names: tuple
    tether_body: np.ndarray
    csphere_body: np.ndarray
    pair_sphere: np.ndarray
    pair_other: np.ndarray
    pair_is_sphere: np.ndarray
    pair_material: np.ndarray
    pair_dir_sphere: np.ndarray
    pair_dir_sign: np.ndarray
    field_name: str
    field_query: np.ndarray
    field_k: int
    field_grid: tuple
    field_material: np.ndarray
    field_dir_sign: np.ndarray
    torsional: bool
    toi_correction: bool
    absolute_contact: bool
    material_names: tuple
    plane_names: tuple
    geom_type: np.ndarray
    geom_body: np.ndarray
    geom_texture: np.ndarray
    camera_names: tuple
    camera_body: np.ndarray
    camera_pixels: tuple
    batched: bool = False
    sweep_order: str = "jacobi"
    contact_relaxation: float | None = None
    row_relaxation: float | None = None
    momentum: float = 0.85
    momentum_restart: bool = True

    dt: Any
    gravity: Any
    warm_start: Any
    relaxation: Any
    restitution_threshold: Any
    contact_slop: Any
    body_mass: Any
    body_inertia: Any
    joint_anchor1: Any
    joint_anchor2: Any
    joint_frame1: Any
    joint_frame2: Any
    joint_rel_rot: Any
    joint_hz: Any
    joint_zeta: Any
    servo_gain: Any
    servo_max_torque: Any
    servo_max_velocity: Any
    servo_deadband: Any
    servo_lo: Any
    servo_hi: Any
    servo_stiffness: Any
    servo_damping: Any
    limit_lo: Any
    limit_hi: Any
    limit_hz: Any
    limit_zeta: Any
    jspring_k: Any
    jspring_c: Any
    jspring_rest: Any
    spring_anchor1: Any
    spring_anchor2: Any
    spring_k: Any
    spring_c: Any
    spring_rest: Any
    tether_anchor: Any
    tether_rail_point: Any
    tether_rail_dir: Any
    tether_k: Any
    tether_c: Any
    tether_slack: Any
    csphere_radius: Any
    csphere_offset: Any
    csphere_direction: Any
    plane_normal: Any
    plane_offset: Any
    field_centre: Any
    field_radius: Any
    field_origin: Any
    field_cell: Any
    material_friction: Any
    material_restitution: Any
    material_hz: Any
    material_zeta: Any
    material_torsional: Any
    material_friction_forward: Any
    material_friction_backward: Any
    material_stiffness: Any
    material_damping: Any
    geom_size: Any
    geom_pos: Any
    geom_rot: Any
    geom_color: Any
    textures: Any
    camera_pos: Any
    camera_rot: Any
    camera_focal: Any
    camera_sensor: Any

    # ---- derived static sizes -------------------------------------------------------
    @property
    def n_joint(self) -> int:
        return len(self.joint_names)

    @property
    def n_dof(self) -> int:
        return len(self.dof_names)

    @property
    def n_servo(self) -> int:
        return len(self.servo_names)

    @property
    def n_csphere(self) -> int:
        return int(self.csphere_body.shape[0])

    @property
    def n_pair(self) -> int:
        return int(self.pair_sphere.shape[0])

    @property
    def n_field_pair(self) -> int:
        """Contacts with the sphere field: ``field_k`` per query sphere."""
        return int(self.field_query.shape[0]) * int(self.field_k)

    @property
    def n_contact(self) -> int:
        """All contacts: the listed pairs, then the field's."""
        return self.n_pair + self.n_field_pair

    @property
    def contact_material(self) -> np.ndarray:
        """(n_contact,) material of every contact (static)."""
        return np.concatenate([self.pair_material,
                               np.repeat(self.field_material, self.field_k)]).astype(np.int32)

    @property
    def contact_dir_sphere(self) -> np.ndarray:
        """(n_contact,) the contact's sphere with a friction direction (see pair_dir_*)."""
        return np.concatenate([self.pair_dir_sphere,
                               np.repeat(self.field_query, self.field_k)]).astype(np.int32)

    @property
    def contact_dir_sign(self) -> np.ndarray:
        """(n_contact,) +1 / -1 / 0 as ``pair_dir_sign``; a query sphere is body b."""
        return np.concatenate([self.pair_dir_sign,
                               np.repeat(self.field_dir_sign, self.field_k)]).astype(np.int32)

    @property
    def directional(self) -> bool:
        """Whether any contact has directional friction (a static branch of the step)."""
        return bool(np.any(self.contact_dir_sign != 0))

    @property
    def rows_per_contact(self) -> int:
        return 4 if self.torsional else 3

    @property
    def n_rows(self) -> int:
        """Number of scalar (non-joint-block) constraint rows."""
        return (self.n_servo + int(self.limit_dof.shape[0]) + int(self.jspring_dof.shape[0])
                + len(self.spring_names) + len(self.tether_names)
                + self.n_contact * self.rows_per_contact)

    def body(self, name: str) -> int:
        """Index of the body called ``name``."""
        return self.body_names.index(name)

    def dof(self, name: str) -> int:
        """Index of a joint coordinate: ``"joint"`` (first) or ``"joint:k"``."""
        return self.dof_names.index(name if ":" in name else f"{name}:0")

    def servo(self, name: str) -> int:
        """Index of the servo called ``name`` (default name: its joint coordinate)."""
        return self.servo_names.index(name)


@_register
@dataclasses.dataclass(frozen=True, kw_only=True, eq=False)
class State(_Replace):
    """Dynamic state of a model (all traced).

    Attributes:
        pos: (n_body, 3) world position of each body's centre of mass [m].
        rot: (n_body, 3, 3) orientation, world_point = pos + rot @ local_point.
        vel: (n_body, 3) world linear velocity [m/s].
        angvel: (n_body, 3) world angular velocity [rad/s].
        prev_vel: (n_body, 3) linear velocity one step earlier (for the accelerometer).
        joint_impulse: (n_joint, 6) last step's joint-row impulses (warm start) [N s].
        row_impulse: (n_rows,) last step's scalar-row impulses [N s or N m s].
        time: () simulated time [s].
        field_id: (n_field_pair,) which field sphere (slot index into ``field_centre``)
            each field contact held in the last step, stored as a float so that a State
            stays a tree of float leaves (``jax.grad`` over a State); it carries each
            field contact's warm start over to the same field sphere (``step``).
    """

    _STATIC = ()

    pos: Any
    rot: Any
    vel: Any
    angvel: Any
    prev_vel: Any
    joint_impulse: Any
    row_impulse: Any
    time: Any
    field_id: Any
