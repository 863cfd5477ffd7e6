"""Contact detection: sphere-plane and sphere-sphere pairs (thesis §7.2, FACTS §2.6).

The original engine only knew spheres against the ground z = 0; here a plane may have any
orientation (slopes) and listed pairs of contact spheres collide too. The pair list is
static (built once): every contact sphere against every plane, then the listed sphere
pairs, so detection is a fixed set of dense vector operations. A contact is *active* when
its signed distance is negative; inactive pairs still produce rows, whose impulses the
solver clamps to zero (fixed shapes, no branches).

Collision functions are kept in a static table keyed by (GeomType, GeomType).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from thesis.physics.math import mv, safe_norm, tangent_basis
from thesis.physics.types import GeomType, Model

__all__ = ["sphere_centres", "sphere_plane", "sphere_sphere", "directional_basis",
           "COLLISION_FUNCS", "detect"]


def sphere_centres(m: Model, pos, rot):
    """World centres (n_csphere, 3) of the contact spheres from extended poses [m]."""
    b = m.csphere_body
    return pos[b] + mv(rot[b], m.csphere_offset)


def sphere_plane(m: Model, centres, pos, sphere, plane):
    """Sphere (index array) against plane (index array) -> contact geometry dict.

    ``normal`` points from the plane (body a = world) into the sphere (body b); ``dist``
    is the signed gap [m]; ``ra``/``rb`` are contact-point offsets from the CoMs.
    """
    n = m.plane_normal[plane]
    c = centres[sphere]
    r = m.csphere_radius[sphere]
    dist = jnp.sum(n * c, -1) - m.plane_offset[plane] - r
    point = c - r[:, None] * n
    body_b = m.csphere_body[sphere]
    return dict(normal=n, dist=dist, ra=point, rb=point - pos[body_b])


def sphere_sphere(m: Model, centres, pos, sphere1, sphere2):
    """Sphere ``sphere1`` (body a) against ``sphere2`` (body b); normal from 1 to 2."""
    c1, c2 = centres[sphere1], centres[sphere2]
    r1, r2 = m.csphere_radius[sphere1], m.csphere_radius[sphere2]
    d = c2 - c1
    length = safe_norm(d)
    ok = length > 1e-9
    up = jnp.broadcast_to(jnp.asarray([0.0, 0.0, 1.0], d.dtype), d.shape)
    n = jnp.where(ok[:, None], d / jnp.where(ok, length, 1.0)[:, None], up)
    dist = length - r1 - r2
    point = 0.5 * (c1 + r1[:, None] * n + c2 - r2[:, None] * n)
    return dict(normal=n, dist=dist, ra=point - pos[m.csphere_body[sphere1]],
                rb=point - pos[m.csphere_body[sphere2]])


def directional_basis(m: Model, rot, normal, t1, t2, dir_sphere, dir_sign):
    """Friction directions of contacts with a directional sphere (``Builder.
    add_contact_sphere(..., direction=...)``).

    ``t1`` becomes the sphere's world direction projected onto the contact plane,
    normalised and signed so that a positive rate along it is the directional sphere
    sliding *forward* relative to the other surface (``-d`` when the sphere is body a);
    ``t2 = n x t1``. Contacts without a direction (``dir_sign`` 0, static) and contacts
    whose direction is (nearly) normal to the contact plane keep ``t1``/``t2``.

    Args:
        rot: (n_body + 1, 3, 3) extended rotations. normal, t1, t2: (P, 3).
        dir_sphere, dir_sign: static (P,) numpy arrays (``Model.pair_dir_*``).
    """
    sign = np.asarray(dir_sign, np.float64)
    d = mv(rot[m.csphere_body[dir_sphere]], m.csphere_direction[dir_sphere])
    d = d * jnp.asarray(sign, d.dtype)[:, None]
    tang = d - jnp.sum(d * normal, -1, keepdims=True) * normal
    length = safe_norm(tang)
    ok = (length > 1e-6) & jnp.asarray(sign != 0)
    u1 = tang / jnp.where(ok, length, 1.0)[:, None]
    u1 = jnp.where(ok[:, None], u1, t1)
    u2 = jnp.where(ok[:, None], jnp.cross(normal, u1), t2)
    return u1, u2


#: Pairwise contact functions keyed by (GeomType, GeomType) of (shape a, shape b).
COLLISION_FUNCS = {
    (GeomType.PLANE, GeomType.SPHERE): sphere_plane,
    (GeomType.SPHERE, GeomType.SPHERE): sphere_sphere,
}


def detect(m: Model, pos, rot):
    """All contact pairs of the model at extended poses ``pos``/``rot`` (n_body + 1).

    Returns a dict with (n_pair, ...) arrays ``normal`` (unit, from a to b), ``dist`` [m],
    ``ra``/``rb`` contact point relative to the CoM of body a / b [m], ``t1``/``t2``
    friction directions, and static ``body_a``/``body_b`` (numpy) body indices.
    """
    dtype = pos.dtype
    if m.n_pair == 0:
        z3 = jnp.zeros((0, 3), dtype)
        e = np.zeros((0,), np.int32)
        return dict(normal=z3, dist=jnp.zeros((0,), dtype), ra=z3, rb=z3, t1=z3, t2=z3,
                    body_a=e, body_b=e)
    centres = sphere_centres(m, pos, rot)
    is_s = m.pair_is_sphere
    pl, sp = np.nonzero(~is_s)[0], np.nonzero(is_s)[0]
    parts = []
    if pl.size:
        parts.append(COLLISION_FUNCS[(GeomType.PLANE, GeomType.SPHERE)](
            m, centres, pos, m.pair_sphere[pl], m.pair_other[pl]))
    if sp.size:
        parts.append(COLLISION_FUNCS[(GeomType.SPHERE, GeomType.SPHERE)](
            m, centres, pos, m.pair_sphere[sp], m.pair_other[sp]))
    out = {k: jnp.concatenate([p[k] for p in parts]) for k in parts[0]}
    order = np.concatenate([pl, sp])
    if not np.array_equal(order, np.arange(m.n_pair)):  # builder lists planes first
        inv = np.argsort(order)
        out = {k: v[inv] for k, v in out.items()}
    out["t1"], out["t2"] = tangent_basis(out["normal"])
    if m.directional:  # static: isotropic models never trace this
        out["t1"], out["t2"] = directional_basis(m, rot, out["normal"], out["t1"], out["t2"],
                                                 m.pair_dir_sphere, m.pair_dir_sign)
    world = m.n_body
    other = np.where(is_s, m.pair_other, 0)  # plane pairs: index unused
    sb1 = m.csphere_body[m.pair_sphere]
    sb2 = m.csphere_body[other] if m.n_csphere else sb1
    # sphere-plane: a = world, b = the sphere; sphere pairs: a = sphere1, b = sphere2
    out["body_a"] = np.where(is_s, sb1, world).astype(np.int32)
    out["body_b"] = np.where(is_s, sb2, sb1).astype(np.int32)
    return out
