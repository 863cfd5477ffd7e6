"""Terrain as data: slopes and floor materials as Model leaves.

A chapter that runs a robot on several terrains (ch4: flat, 9 % and 18 % grades, a
pebbly floor; ch5: five floor materials) should compile its rollout once. Everything a
terrain changes is therefore a traced leaf of :class:`~thesis.physics.types.Model`, and
the functions here return ``model.replace(...)`` with new leaf values, never a model of
another topology. A rollout jitted with the model as an *argument* (as
``thesis.gaits.runner`` does) serves every terrain with one compilation; values may be
traced themselves (a batch of terrains through ``batched_rollout(..., per_robot=...)``).

Slopes: :func:`incline` rotates gravity instead of the floor. For one infinite plane the
two are the same physics seen in different frames: a robot on a floor tilted by theta
under vertical gravity moves, relative to that floor, exactly as a robot on the level
floor z = 0 under gravity tilted by theta (rotate the whole scene by -theta: contacts,
joints and inertias are frame-invariant, only the gravity vector turns; the friction cone
is the same in every tangential direction, so a slope's heading does not change how a
body slides on it, ``tests/physics/test_friction_cone.py``). The floor, the
contact spheres, the sphere fields and the fall criteria in world z keep their meaning;
the robot's heading along +x climbs. What changes is the meaning of world z: it is the
slope's normal, not the vertical (an IMU's ``imu_up`` reads the slope's normal, the
accelerometer reads the true specific force, since it subtracts the model's gravity).

Sphere fields (pebbles): :func:`set_field` packs another layout of the same number of
cells and slots into the field's leaves (``field_centre``, ``field_radius``), and
:func:`clear_field` empties it, so a flat floor and a pebbly one can share a compiled
rollout. For a batch whose robots meet different pebbles, either stack per-robot layouts
(``batched_rollout(..., per_robot={"field_centre": ..., "field_radius": ...})``, one
copy of the field per robot) or lay out one long field and start each robot at its own
place along it (its initial state shifted; no copies, the cheaper choice for a long
strip).

Floor materials: :func:`set_material` changes the leaves of a named contact material
(Coulomb friction, restitution, softness); a contact uses the material of its contact
sphere when that has one, else the plane's (``Builder.add_contact_sphere``), so a
robot's floor is the material of its floor plane (``"floor"`` in
:func:`thesis.physics.models.oncilla.oncilla`).
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from thesis.physics.tables import pack_field
from thesis.physics.types import Model

__all__ = ["grade_angle", "incline", "set_material", "set_field", "clear_field"]


def grade_angle(grade):
    """Slope angle [rad] of a ``grade`` (rise over run, e.g. 0.09 for 9 %): atan(grade).

    §4.6.1 gives both forms: "a 9% and an 18% grade, or a 5.14° and a 10.2° slope".
    """
    return jnp.arctan(grade) if not isinstance(grade, (int, float)) else math.atan(grade)


def incline(model: Model, angle, heading=0.0) -> Model:
    """The model on a slope of ``angle`` [rad] rising along the world direction
    ``heading`` [rad] (0: +x), by rotating its gravity (module docstring).

    The magnitude of the model's gravity is kept; ``angle = 0`` restores it to -z.
    Gravity becomes ``|g| (-sin(a) cos(h), -sin(a) sin(h), -cos(a))``: a body walking
    along the heading climbs, one walking against it descends. ``angle`` and ``heading``
    may be traced (no recompilation).
    """
    g = jnp.sqrt(jnp.sum(model.gravity * model.gravity))
    dtype = model.gravity.dtype
    a = jnp.asarray(angle, dtype)
    h = jnp.asarray(heading, dtype)
    down = jnp.stack([-jnp.sin(a) * jnp.cos(h), -jnp.sin(a) * jnp.sin(h), -jnp.cos(a)])
    return model.replace(gravity=g * down)


#: set_material keyword -> Model leaf it changes.
_MATERIAL_LEAVES = {
    "friction": "material_friction",
    "restitution": "material_restitution",
    "stiffness_hz": "material_hz",
    "damping_ratio": "material_zeta",
    "torsional": "material_torsional",
    "friction_forward": "material_friction_forward",
    "friction_backward": "material_friction_backward",
    "stiffness": "material_stiffness",
    "damping": "material_damping",
}


def set_material(model: Model, name: str, **values) -> Model:
    """The model with contact material ``name``'s parameters replaced.

    Keywords (any subset; a value may be traced): ``friction`` (Coulomb coefficient),
    ``restitution`` (coefficient of restitution), ``stiffness_hz`` and ``damping_ratio``
    (contact softness, see ``constraint.py``), ``torsional`` [m] (torsional friction
    length), ``friction_forward`` / ``friction_backward`` (directional contact spheres,
    ``Builder.add_contact_sphere(..., direction=...)``; ``friction`` is then their lateral
    bound, and setting ``friction`` alone leaves these two unchanged), ``stiffness`` [N/m]
    and ``damping`` [N s/m] (a contact in physical units; the model must have been built
    with one, ``Model.absolute_contact``, since that selects the rows' program). Raises
    ``KeyError`` for an unknown material, ``TypeError`` for an unknown keyword, and
    ``ValueError`` for a torsional length on a model built without torsional rows, or a
    stiffness on one built without a physical-unit contact (which rows exist and how they
    are assembled is fixed at build time).
    """
    if name not in model.material_names:
        raise KeyError(f"model {model.name!r} has no material {name!r}; "
                       f"materials: {', '.join(model.material_names)}")
    unknown = set(values) - set(_MATERIAL_LEAVES)
    if unknown:
        raise TypeError(f"set_material: unknown parameter(s) {sorted(unknown)}; "
                        f"allowed: {sorted(_MATERIAL_LEAVES)}")
    if values.get("torsional") is not None and not model.torsional:
        raise ValueError(f"model {model.name!r} was built without torsional friction rows; "
                         "give a material a torsional length before build()")
    if values.get("stiffness") is not None and not model.absolute_contact:
        raise ValueError(f"model {model.name!r} was built without a contact in physical "
                         "units; give a material a stiffness [N/m] before build()")
    i = model.material_names.index(name)
    changes = {}
    for key, value in values.items():
        if value is None:
            continue
        leaf = _MATERIAL_LEAVES[key]
        arr = changes.get(leaf, getattr(model, leaf))
        changes[leaf] = arr.at[i].set(jnp.asarray(value, arr.dtype))
    return model.replace(**changes)


def _field_grid(model: Model) -> dict:
    if not model.n_field_pair:
        raise ValueError(f"model {model.name!r} has no sphere field (Builder.add_sphere_field)")
    return dict(grid=model.field_grid, origin=np.asarray(model.field_origin, np.float64),
                cell=float(model.field_cell))


def set_field(model: Model, centres, radii) -> Model:
    """The model with its sphere field's spheres replaced by ``centres`` (N, 3) [m] and
    ``radii`` (() or (N,)) [m], any N that fits the field's grid.

    Host-side (numpy) packing into the grid built by ``Builder.add_sphere_field``: the
    spheres must lie within its bounds, no cell may hold more than its capacity, and no
    radius may exceed what the cell size allows for the query spheres (``ValueError``
    otherwise, naming the field). The topology is unchanged: no recompilation.
    """
    layout = _field_grid(model)
    centres = np.asarray(centres, np.float64).reshape(-1, 3)
    radii = np.broadcast_to(np.asarray(radii, np.float64), (centres.shape[0],))
    r_query = float(np.max(np.asarray(model.csphere_radius)[model.field_query]))
    if radii.size and float(radii.max()) + r_query > layout["cell"] * (1 + 1e-6):
        raise ValueError(f"sphere field {model.field_name!r}: radius {float(radii.max())} "
                         f"too large for cells of {layout['cell']} m")
    centre, radius = pack_field(centres, radii, layout, model.field_name)
    dtype = model.field_centre.dtype
    return model.replace(field_centre=jnp.asarray(centre, dtype),
                         field_radius=jnp.asarray(radius, dtype))


def clear_field(model: Model) -> Model:
    """The model with an empty sphere field (every slot empty; a flat floor)."""
    return set_field(model, np.zeros((0, 3)), np.zeros((0,)))
