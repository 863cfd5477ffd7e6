"""Contact detection: sphere-plane and sphere-sphere pairs, sphere fields (thesis §7.2,
docs/sources.md#tpx-contact).

The original engine only knew spheres against the ground z = 0; here a plane may have any
orientation (slopes) and listed pairs of contact spheres collide too. The pair list is
static (built once): every contact sphere against every plane, then the listed sphere
pairs, so detection is a fixed set of dense vector operations. A contact is *active* when
its signed distance is negative; inactive pairs still produce rows, whose impulses the
solver clamps to zero (fixed shapes, no branches).

A static sphere field (``Builder.add_sphere_field``: pebbles, rough ground, thousands of
world-fixed spheres) adds a fixed number of contacts after the pairs: each query sphere
against its ``k`` nearest field spheres, chosen every step among the spheres of the 3 x 3
cells of a uniform x-y grid around it (:func:`field_contacts`). Listing N pebbles as
pairs costs rows for all of them, which grows with N; the grid keeps the cost independent
of N.

Collision functions are kept in a static table keyed by (GeomType, GeomType).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from thesis.physics.math import mv, safe_norm, tangent_basis
from thesis.physics.types import GeomType, Model

__all__ = ["DIRECTIONAL_FADE", "sphere_centres", "sphere_plane", "sphere_sphere",
           "directional_basis",
           "field_candidates", "field_contacts", "COLLISION_FUNCS", "detect"]


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


def _sphere_pair_geometry(c1, r1, c2, r2):
    """(normal from 1 to 2, signed gap, contact point) of spheres (c1, r1), (c2, r2)."""
    d = c2 - c1
    length = safe_norm(d)
    ok = length > 1e-9
    up = jnp.broadcast_to(jnp.asarray([0.0, 0.0, 1.0], d.dtype), d.shape)
    n = jnp.where(ok[:, None], d / jnp.where(ok, length, 1.0)[:, None], up)
    dist = length - r1 - r2
    point = 0.5 * (c1 + r1[:, None] * n + c2 - r2[:, None] * n)
    return n, dist, point


def sphere_sphere(m: Model, centres, pos, sphere1, sphere2):
    """Sphere ``sphere1`` (body a) against ``sphere2`` (body b); normal from 1 to 2."""
    c1, c2 = centres[sphere1], centres[sphere2]
    r1, r2 = m.csphere_radius[sphere1], m.csphere_radius[sphere2]
    n, dist, point = _sphere_pair_geometry(c1, r1, c2, r2)
    return dict(normal=n, dist=dist, ra=point - pos[m.csphere_body[sphere1]],
                rb=point - pos[m.csphere_body[sphere2]])


def field_candidates(m: Model, centres):
    """Slot indices (n_query, 9 capacity) of the field spheres in the 3 x 3 grid cells
    around each query sphere's centre (``Builder.add_sphere_field``).

    The cell of a centre is clipped to the grid's inner cells, so the neighbourhood is 9
    distinct cells even for a sphere far outside the field (its candidates are then far
    away and stay inactive).
    """
    nx, ny, cap = m.field_grid
    c = centres[m.field_query][:, :2]
    lo = np.ones((1, 2))
    hi = np.asarray([[nx - 2.0, ny - 2.0]])
    u = jnp.clip((c - m.field_origin[None]) / m.field_cell, lo, hi)
    ij = jnp.floor(u).astype(jnp.int32)
    cell = ij[:, 0] * ny + ij[:, 1]
    # static offsets of the 9 cells' slots from the centre cell's first slot
    d = np.array([dx * ny + dy for dx in (-1, 0, 1) for dy in (-1, 0, 1)], np.int64)
    offsets = ((d[:, None] * cap + np.arange(cap)[None, :]).reshape(-1)).astype(np.int32)
    return cell[:, None] * cap + offsets[None, :]


def _get(arr, idx):
    """``arr[idx]`` along axis 0 for indices known to be in bounds (no wrap or clamp ops)."""
    return arr.at[idx].get(mode="promise_in_bounds")


def _k_smallest(gap, cand, k):
    """(n, k) entries of ``cand`` at the ``k`` smallest ``gap`` of each row (k static).

    ``k`` rounds of argmin, each masking its pick: for the few nearest of a few dozen
    candidates a handful of small fused loops, measured slightly cheaper on the CPU than
    ``lax.top_k`` (a sort): 7.1 against 8.3 us of CPU time per Oncilla detection.
    """
    picks = []
    for _ in range(k):
        j = jnp.argmin(gap, axis=1)
        picks.append(jnp.take_along_axis(cand, j[:, None], axis=1)[:, 0])
        gap = jnp.where(jnp.arange(gap.shape[1])[None, :] == j[:, None], jnp.inf, gap)
    return jnp.stack(picks, axis=1)


def _sort_small(x):
    """Rows of (n, k) sorted ascending by an odd-even transposition network (k static,
    small): k rounds of elementwise min/max, cheaper on the CPU than a sort."""
    cols = [x[:, i] for i in range(x.shape[1])]
    for r in range(len(cols)):
        for i in range(r % 2, len(cols) - 1, 2):
            cols[i], cols[i + 1] = (jnp.minimum(cols[i], cols[i + 1]),
                                    jnp.maximum(cols[i], cols[i + 1]))
    return jnp.stack(cols, axis=1)


def field_contacts(m: Model, centres, pos):
    """Contacts of the query spheres with their ``field_k`` nearest field spheres.

    Of the 3 x 3-cell candidates (:func:`field_candidates`) each query sphere keeps the
    ``k`` smallest gaps, ordered by slot index so that a field sphere
    stays in the same contact slot while it remains among the ``k`` nearest. The field
    sphere is body a (the world), the query sphere body b, as for a listed pair of a world
    sphere with it (``sphere_sphere``).

    Returns the contact dict of ``sphere_sphere`` for (n_query * k,) contacts, query
    sphere by query sphere, plus ``field_id`` (n_query * k,): the slot indices as floats.
    """
    q, k = m.field_query, m.field_k
    # which field spheres: a discrete choice, made without gradients
    # (the query sphere's own radius is the same for all its candidates: left out)
    sg = jax.lax.stop_gradient
    cand = field_candidates(m, sg(centres))
    d = _get(sg(m.field_centre), cand) - sg(centres[q])[:, None]
    gap = jnp.sqrt(jnp.sum(d * d, -1)) - _get(sg(m.field_radius), cand)
    ids = _sort_small(_k_smallest(gap, cand, k)).reshape(-1)
    # their contact geometry, differentiable in both spheres
    query = np.repeat(q, k)
    n, dist, point = _sphere_pair_geometry(_get(m.field_centre, ids), _get(m.field_radius, ids),
                                           centres[query], m.csphere_radius[query])
    return dict(normal=n, dist=dist, ra=point - pos[np.full(query.shape, m.n_body)],
                rb=point - pos[m.csphere_body[query]], field_id=ids.astype(pos.dtype))


#: Angle [rad] between a directional sphere's grain and the contact plane below which
#: its forward and backward coefficients fade linearly (in the sine) into the lateral
#: one: a grain normal to the surface has no forward or backward (every slide crosses
#: it), so near there the choice must not hang on the sign of a tiny tilt. 10 deg keeps
#: the fade out of the way of grains that lie along the surface (Puppy II's paws).
DIRECTIONAL_FADE = 10.0 * 3.141592653589793 / 180.0


def directional_basis(m: Model, rot, normal, t1, t2, dir_sphere, dir_sign):
    """Friction directions of contacts with a directional sphere (``Builder.
    add_contact_sphere(..., direction=...)``) and the weight of their grain.

    ``t1`` becomes the sphere's world direction projected onto the contact plane,
    normalised and signed so that a positive rate along it is the directional sphere
    sliding *forward* relative to the other surface (``-d`` when the sphere is body a);
    ``t2 = n x t1``. The weight is ``min(1, |projection| / sin(DIRECTIONAL_FADE))``: 1 for
    a grain along the surface, falling to 0 as it turns normal to it, where the
    constraint rows use the lateral coefficient in every direction (``constraint``), so
    the arbitrary ``t1`` of a grain normal to the plane does not matter. Contacts without
    a direction (``dir_sign`` 0, static) keep ``t1``/``t2`` with weight 0.

    Args:
        rot: (n_body + 1, 3, 3) extended rotations. normal, t1, t2: (P, 3).
        dir_sphere, dir_sign: static (P,) numpy arrays (``Model.pair_dir_*``).
    Returns:
        (t1, t2, weight (P,)).
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
    weight = jnp.minimum(length / np.sin(DIRECTIONAL_FADE), 1.0) * jnp.asarray(
        sign != 0, length.dtype)
    return u1, u2, weight


#: Pairwise contact functions keyed by (GeomType, GeomType) of (shape a, shape b).
COLLISION_FUNCS = {
    (GeomType.PLANE, GeomType.SPHERE): sphere_plane,
    (GeomType.SPHERE, GeomType.SPHERE): sphere_sphere,
}


def detect(m: Model, pos, rot):
    """All contacts of the model at extended poses ``pos``/``rot`` (n_body + 1).

    Returns a dict with (n_contact, ...) arrays ``normal`` (unit, from a to b), ``dist``
    [m], ``ra``/``rb`` contact point relative to the CoM of body a / b [m], ``t1``/``t2``
    friction directions, ``dir_weight`` (directional models only: the grain's weight of
    :func:`directional_basis`, 0 for contacts without a direction), and static
    ``body_a``/``body_b`` (numpy) body indices: the
    listed pairs (n_pair), then the sphere field's contacts (n_field_pair, with their
    ``field_id``, see :func:`field_contacts`).
    """
    if m.n_field_pair:  # static: models without a field never trace this
        return _with_field(m, pos, rot)
    return _detect_pairs(m, pos, rot)


def _with_field(m: Model, pos, rot):
    """:func:`detect` for a model with a sphere field."""
    centres = sphere_centres(m, pos, rot)
    fc = field_contacts(m, centres, pos)
    fc["t1"], fc["t2"] = tangent_basis(fc["normal"])
    query = np.repeat(m.field_query, m.field_k)
    if np.any(m.field_dir_sign != 0):
        fc["t1"], fc["t2"], fc["dir_weight"] = directional_basis(
            m, rot, fc["normal"], fc["t1"], fc["t2"], query,
            np.repeat(m.field_dir_sign, m.field_k))
    elif m.directional:
        fc["dir_weight"] = jnp.zeros(query.shape, pos.dtype)
    fc["body_a"] = np.full(query.shape, m.n_body, np.int32)
    fc["body_b"] = m.csphere_body[query].astype(np.int32)
    if m.n_pair == 0:
        return fc
    out = _detect_pairs(m, pos, rot)
    joined = {k: (np.concatenate if isinstance(out[k], np.ndarray) else jnp.concatenate)(
        [out[k], fc[k]]) for k in out}
    joined["field_id"] = fc["field_id"]
    return joined


def _detect_pairs(m: Model, pos, rot):
    """The listed pairs of :func:`detect` (every sphere-plane pair and sphere pair)."""
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
    if np.any(m.pair_dir_sign != 0):  # static: isotropic models never trace this
        out["t1"], out["t2"], out["dir_weight"] = directional_basis(
            m, rot, out["normal"], out["t1"], out["t2"], m.pair_dir_sphere, m.pair_dir_sign)
    elif m.directional:  # the directional spheres are in the field
        out["dir_weight"] = jnp.zeros((m.n_pair,), dtype)
    world = m.n_body
    other = np.where(is_s, m.pair_other, 0)  # plane pairs: index unused
    sb1 = m.csphere_body[m.pair_sphere]
    sb2 = m.csphere_body[other] if m.n_csphere else sb1
    # sphere-plane: a = world, b = the sphere; sphere pairs: a = sphere1, b = sphere2
    out["body_a"] = np.where(is_s, sb1, world).astype(np.int32)
    out["body_b"] = np.where(is_s, sb2, sb1).astype(np.int32)
    return out
