"""The chapter-7 quadruped's body as bounded, differentiable parameters (thesis §8.2).

§8.2: "co-optimizing the controller with its morphology ... both can be optimized
simultaneously using gradient descent". The engine keeps every physical quantity as a
traced leaf of :class:`~thesis.physics.types.Model` (and the initial pose as leaves of
:class:`~thesis.physics.types.State`), so a body is a point in a vector space and a
change of body is ``model.replace(...)``, never a rebuild or a recompilation: the same
terrain-as-data pattern as :mod:`thesis.physics.terrain`.

The body is the quadruped of §7.3.3 (:func:`thesis.physics.models.quadruped`, built
from the same declarations here by :func:`build_body`, which a test checks leaf by
leaf against it) with one addition: a passive rotational spring-damper in parallel with
each knee servo (``Builder.add_joint_spring``), the "spring stiffness and rest angle"
of §8.2's morphological computation. At its built stiffness (:data:`PARAMS`) the spring
is close to absent (1 N m/rad against servos of 20 N m).

Parameters (:data:`PARAMS`, symmetric over the four legs; the bounds are declared as
physically plausible for this 0.7 m robot, see each ``why``):

=================  ======  =======  ================  ==========================================
name               unit    built    bounds            leaves it moves
=================  ======  =======  ================  ==========================================
femur_length       m       0.20     0.10 - 0.30       femur mass/inertia/box, hip+knee anchors,
                                                      initial height of every body
tibia_length       m       0.15     0.08 - 0.25       tibia mass/inertia/box, knee+heel anchors,
                                                      initial height
foot_radius        m       0.05     0.025 - 0.08      foot mass/inertia/sphere, contact radius,
                                                      initial height
hip_x              m       0.30     0.15 - 0.35       hip anchors on the spine, legs' initial x
hip_y              m       0.20     0.175 - 0.30      hip anchors on the spine, legs' initial y
spine_mass         kg      21.0     14 - 28           spine mass and inertia
knee_stiffness     N m/rad 1.0      0.1 - 40          knee spring stiffness
knee_rest          rad     0.0      -0.6 - 0.6        knee spring rest angle
=================  ======  =======  ================  ==========================================

Segments keep the built density (1000 kg/m^3) and cross-section, so a longer segment is
heavier and its inertia is that of the longer box; the feet keep the density too. The
robot starts standing on its feet on the floor: the spine (and the hips) at height
``femur + tibia + foot radius``.

An optimiser works in unconstrained coordinates ``u`` (:func:`to_physical`): value =
lo + (hi - lo) sigmoid(u + u_built), so u = 0 is the built body and every u is a body
within the bounds.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics.builder import Builder
from thesis.physics.models.quadruped import BUMPERS, LEGS

__all__ = ["Param", "PARAMS", "NAMES", "built_values", "to_physical", "to_unconstrained",
           "build_body", "apply", "layout", "SEGMENT_DENSITY"]

#: Density of the legs' segments and feet [kg/m^3] (demi_predator_ground.json).
SEGMENT_DENSITY = 1000.0
#: Cross-section of the femur and tibia boxes [m] (demi_predator_ground.json).
SEGMENT_WIDTH = 0.05
#: Spine box [m] and bumper sphere radius [m] (fixed).
SPINE_SIZE = (0.7, 0.3, 0.1)
BUMPER_RADIUS = 0.05
#: Damping of the knee springs [N m s/rad] (fixed; an implicit spring needs k dt + c > 0).
KNEE_DAMPING = 0.1


@dataclass(frozen=True)
class Param:
    """One morphological parameter: ``name``, ``unit``, the ``built`` value (the ch7
    quadruped's), the bounds ``lo`` < built < ``hi``, and ``why`` the bounds."""

    name: str
    unit: str
    built: float
    lo: float
    hi: float
    why: str


PARAMS: tuple[Param, ...] = (
    Param("femur_length", "m", 0.20, 0.10, 0.30, "half to 1.5 x the built femur"),
    Param("tibia_length", "m", 0.15, 0.08, 0.25, "knee to foot centre; about half to 1.7 x"),
    Param("foot_radius", "m", 0.05, 0.025, 0.08, "a foot no wider than the tibia is long"),
    Param("hip_x", "m", 0.30, 0.15, 0.35, "hips inside the 0.7 m spine"),
    Param("hip_y", "m", 0.20, 0.175, 0.30, "legs beside the 0.3 m-wide spine"),
    Param("spine_mass", "kg", 21.0, 14.0, 28.0, "torso mass +- one third (payload)"),
    Param("knee_stiffness", "N m/rad", 1.0, 0.1, 40.0,
          "from almost none to twice the servo torque per radian"),
    Param("knee_rest", "rad", 0.0, -0.6, 0.6, "within the servos' +-45 deg range"),
)
NAMES: tuple[str, ...] = tuple(p.name for p in PARAMS)


def built_values() -> np.ndarray:
    """(8,) the built values of :data:`PARAMS` (order :data:`NAMES`, their units)."""
    return np.array([p.built for p in PARAMS])


def _bounds(dtype):
    lo = jnp.asarray([p.lo for p in PARAMS], dtype)
    hi = jnp.asarray([p.hi for p in PARAMS], dtype)
    t = np.array([(p.built - p.lo) / (p.hi - p.lo) for p in PARAMS])
    return lo, hi, jnp.asarray(np.log(t / (1.0 - t)), dtype)


def to_physical(u):
    """(..., 8) unconstrained coordinates -> physical values within the bounds (units of
    :data:`PARAMS`); u = 0 gives :func:`built_values`."""
    u = jnp.asarray(u)
    lo, hi, u0 = _bounds(u.dtype)
    return lo + (hi - lo) * jax.nn.sigmoid(u + u0)


def to_unconstrained(values):
    """Inverse of :func:`to_physical` for values strictly inside the bounds."""
    v = jnp.asarray(values)
    lo, hi, u0 = _bounds(v.dtype)
    t = (v - lo) / (hi - lo)
    return jnp.log(t / (1.0 - t)) - u0


def _named(values) -> dict:
    v = np.asarray(values, np.float64) if not isinstance(values, dict) else None
    if v is None:
        return {k: float(values[k]) for k in NAMES}
    return dict(zip(NAMES, v.tolist()))


def build_body(values=None, *, dt=0.01, solver_iterations=20, warm_start=0.85,
               servo_gain=50.0, servo_max_torque=20.0, servo_max_velocity=np.deg2rad(1440.0),
               servo_range=np.deg2rad(45.0), friction=0.5, restitution=0.01,
               contact_slop=0.01, dtype=jnp.float32):
    """``(Model, State)`` of the quadruped with the morphology ``values`` (8 numbers in the
    order of :data:`NAMES`, or a dict by name; None: the built body), by the builder.

    The declarations are those of :func:`thesis.physics.models.quadruped` (same bodies,
    joints, servos, contacts, in the same order) plus a knee spring per leg. This is the
    reference that :func:`apply` must match; experiments build it once (at the built
    values) and move the body with :func:`apply`.
    """
    v = _named(built_values() if values is None else values)
    lf, lt, r = v["femur_length"], v["tibia_length"], v["foot_radius"]
    zh = lf + lt + r
    b = Builder("quadruped_coopt", dt=dt, solver_iterations=solver_iterations,
                warm_start=warm_start, gravity=(0.0, 0.0, -9.81), contact_slop=contact_slop,
                friction=friction, restitution=restitution)
    b.add_plane("floor", (0, 0, 1), 0.0, color=(0.5, 0.5, 0.5))
    b.add_box("spine", SPINE_SIZE, (0, 0, zh), mass=v["spine_mass"], color=(0, 0.8, 0.2))
    for i, (x, y) in enumerate(BUMPERS, 1):
        name = f"spine-sphere{i}"
        b.add_sphere(name, BUMPER_RADIUS, (x, y, zh), visible=False)
        b.add_fixed(f"bumper{i}", "spine", name, (x, y, zh))
        b.add_contact_sphere(name, BUMPER_RADIUS)
    w = SEGMENT_WIDTH
    for i, (sx, sy) in enumerate(LEGS, 1):
        x, y = np.sign(sx) * v["hip_x"], np.sign(sy) * v["hip_y"]
        b.add_box(f"femur{i}", (w, w, lf), (x, y, zh - lf / 2), color=(1, 0.8, 0))
        b.add_box(f"tibia{i}", (w, w, lt), (x, y, r + lt / 2), color=(1, 0.2, 0))
        b.add_sphere(f"foot{i}", r, (x, y, r), color=(0.3, 0.3, 0.3))
        b.add_hinge(f"hip{i}", "spine", f"femur{i}", (x, y, zh), (0, 1, 0))
        b.add_hinge(f"knee{i}", f"femur{i}", f"tibia{i}", (x, y, zh - lf), (0, 1, 0))
        b.add_fixed(f"heel{i}", f"tibia{i}", f"foot{i}", (x, y, r))
        b.add_contact_sphere(f"foot{i}", r)
    rng = (-servo_range, servo_range)
    for joint in [f"knee{i}" for i in range(1, 5)] + [f"hip{i}" for i in range(1, 5)]:
        b.add_position_servo(joint, servo_gain, servo_max_torque, servo_max_velocity,
                             command_range=rng, name=joint)
    for i in range(1, 5):
        b.add_joint_spring(f"knee{i}", v["knee_stiffness"], KNEE_DAMPING, v["knee_rest"])
    return b.build(dtype)


def _box_inertia(m, a, b, c):
    return (m / 12.0) * jnp.stack([b * b + c * c, a * a + c * c, a * a + b * b])


def layout(values) -> dict:
    """Differentiable geometry of the body with morphology ``values`` ((8,) jax array,
    order :data:`NAMES`): per leg i (0-3, order ``LEGS``) the world positions at the
    initial pose ``hip`` (4, 3), ``knee``, ``foot`` [m]; ``hip_height`` [m]; masses
    ``femur_mass``, ``tibia_mass``, ``foot_mass`` (per leg) and ``spine_mass`` [kg]."""
    v = dict(zip(NAMES, [values[i] for i in range(len(NAMES))]))
    lf, lt, r = v["femur_length"], v["tibia_length"], v["foot_radius"]
    zh = lf + lt + r
    sx = jnp.asarray([np.sign(x) for x, _ in LEGS], values.dtype)
    sy = jnp.asarray([np.sign(y) for _, y in LEGS], values.dtype)
    x, y = sx * v["hip_x"], sy * v["hip_y"]
    one = jnp.ones_like(x)
    w2 = SEGMENT_WIDTH * SEGMENT_WIDTH * SEGMENT_DENSITY
    return dict(
        hip=jnp.stack([x, y, zh * one], -1), knee=jnp.stack([x, y, (zh - lf) * one], -1),
        foot=jnp.stack([x, y, r * one], -1), hip_height=zh,
        femur_mass=w2 * lf, tibia_mass=w2 * lt,
        foot_mass=SEGMENT_DENSITY * 4.0 / 3.0 * jnp.pi * r ** 3, spine_mass=v["spine_mass"],
    )


def apply(model, state0, values):
    """``(model, state0)`` with the morphology ``values`` ((8,) physical values, order
    :data:`NAMES`, may be traced) written into their leaves.

    ``model``/``state0`` must come from :func:`build_body` (any values: every leaf the
    parameters reach is overwritten). Differentiable in ``values``; the topology is
    unchanged, so one compiled rollout serves every body. Leaves written: ``body_mass``,
    ``body_inertia``, ``joint_anchor1/2`` (hips, knees, heels), ``csphere_radius`` (feet),
    ``geom_size`` (segments, feet), ``jspring_k``, ``jspring_rest``; in the state the
    bodies' initial positions ``pos`` (standing on the floor, at rest).
    """
    dtype = model.body_mass.dtype
    values = jnp.asarray(values, dtype)
    v = dict(zip(NAMES, [values[i] for i in range(len(NAMES))]))
    lay = layout(values)
    lf, lt, r = v["femur_length"], v["tibia_length"], v["foot_radius"]
    zh = lay["hip_height"]
    w = SEGMENT_WIDTH
    zero = jnp.zeros((), dtype)
    bi = model.body
    ji = model.joint_names.index
    mass, inertia = model.body_mass, model.body_inertia
    a1, a2 = model.joint_anchor1, model.joint_anchor2
    pos = state0.pos
    spine = bi("spine")
    ms = v["spine_mass"]
    mass = mass.at[spine].set(ms)
    inertia = inertia.at[spine].set(jnp.diag(_box_inertia(ms, *(jnp.asarray(s, dtype)
                                                                for s in SPINE_SIZE))))
    pos = pos.at[spine, 2].set(zh)
    for i in range(1, len(BUMPERS) + 1):
        pos = pos.at[bi(f"spine-sphere{i}"), 2].set(zh)
    csr, gsize = model.csphere_radius, model.geom_size
    w_ = jnp.asarray(w, dtype)
    for k in range(len(LEGS)):
        n = k + 1
        f, t, ft = bi(f"femur{n}"), bi(f"tibia{n}"), bi(f"foot{n}")
        hx, hy = lay["hip"][k, 0], lay["hip"][k, 1]
        mf, mt, mfoot = lay["femur_mass"], lay["tibia_mass"], lay["foot_mass"]
        mass = mass.at[f].set(mf).at[t].set(mt).at[ft].set(mfoot)
        inertia = (inertia.at[f].set(jnp.diag(_box_inertia(mf, w_, w_, lf)))
                   .at[t].set(jnp.diag(_box_inertia(mt, w_, w_, lt)))
                   .at[ft].set(0.4 * mfoot * r * r * jnp.eye(3, dtype=dtype)))
        pos = (pos.at[f].set(jnp.stack([hx, hy, zh - lf / 2]))
               .at[t].set(jnp.stack([hx, hy, r + lt / 2]))
               .at[ft].set(jnp.stack([hx, hy, r])))
        hip, knee, heel = ji(f"hip{n}"), ji(f"knee{n}"), ji(f"heel{n}")
        a1 = (a1.at[hip].set(jnp.stack([hx, hy, zero]))
              .at[knee].set(jnp.stack([zero, zero, -lf / 2]))
              .at[heel].set(jnp.stack([zero, zero, -lt / 2])))
        a2 = (a2.at[hip].set(jnp.stack([zero, zero, lf / 2]))
              .at[knee].set(jnp.stack([zero, zero, lt / 2]))
              .at[heel].set(jnp.zeros((3,), dtype)))
        sphere = int(np.flatnonzero(np.asarray(model.csphere_body) == ft)[0])
        csr = csr.at[sphere].set(r)
        gb = np.asarray(model.geom_body)
        g_f, g_t, g_ft = (int(np.flatnonzero(gb == b)[0]) for b in (f, t, ft))
        gsize = (gsize.at[g_f, 2].set(lf / 2).at[g_t, 2].set(lt / 2)
                 .at[g_ft, 0].set(r))
    nk = int(model.jspring_dof.shape[0])
    model = model.replace(
        body_mass=mass, body_inertia=inertia, joint_anchor1=a1, joint_anchor2=a2,
        csphere_radius=csr, geom_size=gsize,
        jspring_k=jnp.broadcast_to(v["knee_stiffness"], (nk,)).astype(dtype),
        jspring_rest=jnp.broadcast_to(v["knee_rest"], (nk,)).astype(dtype))
    return model, state0.replace(pos=pos)
