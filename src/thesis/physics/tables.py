"""Assemble the builder's declarations into static index tables and parameter arrays.

Called by :meth:`thesis.physics.builder.Builder.build`, whose declarations it reads from
the builder it is given; it imports nothing of ``builder.py``. Everything constant over a
simulation -- body indices of every row, joint frames in body coordinates, rest relative
rotations, the contact-pair list -- is computed here once, in numpy, so the traced step
only does dense, static-shaped arithmetic.
"""

from __future__ import annotations

import numpy as np
import jax.numpy as jnp

from thesis.physics.types import DofKind, JointType, Model, State

#: Which of a joint's six equality rows (3 linear, 3 angular, in the joint frame) each
#: joint type keeps: a hinge frees one rotation, a universal joint two, a ball three, a
#: slider one translation, a fixed joint nothing (``Model.joint_row_mask``).
_ROW_MASK = {
    JointType.HINGE: (1, 1, 1, 0, 1, 1),
    JointType.UNIVERSAL: (1, 1, 1, 1, 0, 0),
    JointType.BALL: (1, 1, 1, 0, 0, 0),
    JointType.FIXED: (1, 1, 1, 1, 1, 1),
    JointType.SLIDER: (0, 1, 1, 1, 1, 1),
}


def _arr(x, shape, dtype):
    a = np.asarray(x, np.float64)
    if a.size == 0:
        a = np.zeros(shape, np.float64)
    return jnp.asarray(a.reshape(shape), dtype=dtype)


def build_model(b, dtype):
    nb = len(b.bodies)
    world = nb
    fix = lambda i: world if i < 0 else i  # noqa: E731
    J = b.joints
    nj = len(J)

    # joint coordinates (dofs)
    dof_names, dof_joint, dof_kind, dof_slot = [], [], [], []
    first_dof = {}
    for ji, j in enumerate(J):
        first_dof[j["name"]] = len(dof_names)
        for k in range(JointType(j["type"]).dof_width()):
            dof_names.append(f"{j['name']}:{k}")
            dof_joint.append(ji)
            dof_kind.append(DofKind.LINEAR if j["type"] == JointType.SLIDER else DofKind.ANGULAR)
            dof_slot.append(k)

    def dof_of(joint, axis):
        return first_dof[joint] + axis

    limits = [(first_dof[j["name"]] + k, lo, hi, j["hz"], j["zeta"])
              for j in J if j["limits"] is not None
              for k, (lo, hi) in enumerate(j["limits"])]
    # joint limits use the builder's limit softness
    limits = [(d, lo, hi, b.limit_hz, b.limit_zeta) for d, lo, hi, _, _ in limits]

    S = b.servos
    pairs_s, pairs_o, pairs_is, pairs_m = [], [], [], []
    for si, s in enumerate(b.cspheres):
        for pi, p in enumerate(b.planes):
            pairs_s.append(si)
            pairs_o.append(pi)
            pairs_is.append(False)
            pairs_m.append(s["material"] if s["material"] is not None else p["material"])
    for s1, s2, m in b.sphere_pairs:
        pairs_s.append(s1)
        pairs_o.append(s2)
        pairs_is.append(True)
        pairs_m.append(m)
    torsional = any(b.materials[m]["torsional"] > 0 for m in pairs_m)
    absolute = any(m["stiffness"] > 0 for m in b.materials)
    # directional friction: the pair's directional sphere and the side it is on (+1 body b,
    # -1 body a, 0 none); planes are body a, so a sphere against a plane is body b
    directed = [s["direction"] is not None for s in b.cspheres]
    dir_sphere, dir_sign = [], []
    for si, other, is_s in zip(pairs_s, pairs_o, pairs_is):
        if is_s and directed[si] and directed[other]:
            raise ValueError(f"sphere pair ({si}, {other}): both contact spheres have a "
                             "friction direction; give it to at most one of them")
        if is_s and directed[si]:
            dir_sphere.append(si)
            dir_sign.append(-1)
        elif is_s and directed[other]:
            dir_sphere.append(other)
            dir_sign.append(1)
        elif not is_s and directed[si]:
            dir_sphere.append(si)
            dir_sign.append(1)
        else:
            dir_sphere.append(0)
            dir_sign.append(0)

    field = _field_tables(b, dtype)

    tex = b.textures
    if tex:
        h = max(t["image"].shape[0] for t in tex)
        w = max(t["image"].shape[1] for t in tex)
        if any(t["image"].shape[:2] != (h, w) for t in tex):
            raise ValueError("all textures must have the same size")
        textures = np.stack([t["image"] for t in tex])
    else:
        textures = np.ones((1, 1, 1, 3))
    G, C = b.geoms, b.cameras
    tex_index = lambda name: -1 if name is None else [t["name"] for t in tex].index(name)  # noqa

    f = lambda key, src, shape: _arr([x[key] for x in src], shape, dtype)  # noqa: E731
    ints = lambda xs: np.asarray(xs, dtype=np.int32).reshape(-1)  # noqa: E731

    model = Model(
        name=b.name, n_body=nb, body_names=tuple(x["name"] for x in b.bodies),
        solver_iterations=b.solver_iterations, reortho_iterations=b.reortho_iterations,
        sweep_order=b.sweep_order, contact_relaxation=b.contact_relaxation,
        row_relaxation=b.row_relaxation,
        momentum=b.momentum, momentum_restart=b.momentum_restart,
        joint_names=tuple(j["name"] for j in J),
        joint_type=ints([int(j["type"]) for j in J]),
        joint_body1=ints([fix(j["b1"]) for j in J]),
        joint_body2=ints([fix(j["b2"]) for j in J]),
        joint_row_mask=np.asarray([_ROW_MASK[j["type"]] for j in J], bool).reshape(nj, 6),
        dof_names=tuple(dof_names), dof_joint=ints(dof_joint), dof_kind=ints(dof_kind),
        dof_slot=ints(dof_slot),
        servo_names=tuple(s["name"] for s in S),
        servo_dof=ints([dof_of(s["joint"], s["axis"]) for s in S]),
        servo_kind=ints([int(s["kind"]) for s in S]),
        limit_dof=ints([l[0] for l in limits]),
        jspring_dof=ints([dof_of(s["joint"], s["axis"]) for s in b.jsprings]),
        spring_names=tuple(s["name"] for s in b.springs),
        spring_body1=ints([fix(s["b1"]) for s in b.springs]),
        spring_body2=ints([fix(s["b2"]) for s in b.springs]),
        tether_names=tuple(t["name"] for t in b.tethers),
        tether_body=ints([t["body"] for t in b.tethers]),
        csphere_body=ints([fix(s["body"]) for s in b.cspheres]),
        pair_sphere=ints(pairs_s), pair_other=ints(pairs_o),
        pair_is_sphere=np.asarray(pairs_is, bool).reshape(-1), pair_material=ints(pairs_m),
        pair_dir_sphere=ints(dir_sphere), pair_dir_sign=ints(dir_sign),
        field_name=field["name"], field_query=field["query"], field_k=field["k"],
        field_grid=field["grid"], field_material=field["material"],
        field_dir_sign=field["dir_sign"],
        torsional=bool(torsional), toi_correction=bool(b.toi_correction),
        absolute_contact=bool(absolute),
        material_names=tuple(m["name"] for m in b.materials),
        plane_names=tuple(p["name"] for p in b.planes),
        geom_type=ints([int(g["type"]) for g in G]),
        geom_body=ints([g["body"] for g in G]),
        geom_texture=ints([tex_index(g["texture"]) for g in G]),
        camera_names=tuple(c["name"] for c in C),
        camera_body=ints([c["body"] for c in C]),
        camera_pixels=tuple(c["pixels"] for c in C),
        dt=jnp.asarray(b.dt, dtype), gravity=jnp.asarray(b.gravity, dtype),
        warm_start=jnp.asarray(b.warm_start, dtype), relaxation=jnp.asarray(b.relaxation, dtype),
        restitution_threshold=jnp.asarray(b.restitution_threshold, dtype),
        contact_slop=jnp.asarray(b.contact_slop, dtype),
        body_mass=f("mass", b.bodies, (nb,)), body_inertia=f("inertia", b.bodies, (nb, 3, 3)),
        joint_anchor1=f("anchor1", J, (nj, 3)), joint_anchor2=f("anchor2", J, (nj, 3)),
        joint_frame1=f("frame1", J, (nj, 3, 3)), joint_frame2=f("frame2", J, (nj, 3, 3)),
        joint_rel_rot=f("rel", J, (nj, 3, 3)),
        joint_hz=f("hz", J, (nj,)), joint_zeta=f("zeta", J, (nj,)),
        servo_gain=f("gain", S, (len(S),)), servo_max_torque=f("torque", S, (len(S),)),
        servo_max_velocity=f("vmax", S, (len(S),)), servo_deadband=f("deadband", S, (len(S),)),
        servo_lo=f("lo", S, (len(S),)), servo_hi=f("hi", S, (len(S),)),
        servo_stiffness=f("k", S, (len(S),)), servo_damping=f("c", S, (len(S),)),
        limit_lo=_arr([l[1] for l in limits], (len(limits),), dtype),
        limit_hi=_arr([l[2] for l in limits], (len(limits),), dtype),
        limit_hz=_arr([l[3] for l in limits], (len(limits),), dtype),
        limit_zeta=_arr([l[4] for l in limits], (len(limits),), dtype),
        jspring_k=f("k", b.jsprings, (len(b.jsprings),)),
        jspring_c=f("c", b.jsprings, (len(b.jsprings),)),
        jspring_rest=f("rest", b.jsprings, (len(b.jsprings),)),
        spring_anchor1=f("a1", b.springs, (len(b.springs), 3)),
        spring_anchor2=f("a2", b.springs, (len(b.springs), 3)),
        spring_k=f("k", b.springs, (len(b.springs),)),
        spring_c=f("c", b.springs, (len(b.springs),)),
        spring_rest=f("rest", b.springs, (len(b.springs),)),
        tether_anchor=f("anchor", b.tethers, (len(b.tethers), 3)),
        tether_rail_point=f("rail_point", b.tethers, (len(b.tethers), 3)),
        tether_rail_dir=f("rail_dir", b.tethers, (len(b.tethers), 3)),
        tether_k=f("k", b.tethers, (len(b.tethers),)),
        tether_c=f("c", b.tethers, (len(b.tethers),)),
        tether_slack=f("slack", b.tethers, (len(b.tethers),)),
        csphere_radius=f("radius", b.cspheres, (len(b.cspheres),)),
        csphere_offset=f("offset", b.cspheres, (len(b.cspheres), 3)),
        csphere_direction=_arr([np.zeros(3) if c["direction"] is None else c["direction"]
                                for c in b.cspheres], (len(b.cspheres), 3), dtype),
        plane_normal=f("normal", b.planes, (len(b.planes), 3)),
        plane_offset=f("offset", b.planes, (len(b.planes),)),
        field_centre=field["centre"], field_radius=field["radius"],
        field_origin=field["origin"], field_cell=field["cell"],
        material_friction=f("friction", b.materials, (len(b.materials),)),
        material_restitution=f("restitution", b.materials, (len(b.materials),)),
        material_hz=f("hz", b.materials, (len(b.materials),)),
        material_zeta=f("zeta", b.materials, (len(b.materials),)),
        material_torsional=f("torsional", b.materials, (len(b.materials),)),
        material_friction_forward=f("friction_forward", b.materials, (len(b.materials),)),
        material_friction_backward=f("friction_backward", b.materials, (len(b.materials),)),
        material_stiffness=f("stiffness", b.materials, (len(b.materials),)),
        material_damping=f("damping", b.materials, (len(b.materials),)),
        geom_size=f("size", G, (len(G), 3)), geom_pos=f("pos", G, (len(G), 3)),
        geom_rot=f("rot", G, (len(G), 3, 3)), geom_color=f("color", G, (len(G), 3)),
        textures=jnp.asarray(textures, dtype),
        camera_pos=f("pos", C, (len(C), 3)), camera_rot=f("rot", C, (len(C), 3, 3)),
        camera_focal=f("focal", C, (len(C),)), camera_sensor=f("sensor", C, (len(C), 2)),
    )
    vel = f("vel", b.bodies, (nb, 3))
    state = State(
        pos=f("pos", b.bodies, (nb, 3)), rot=f("rot", b.bodies, (nb, 3, 3)), vel=vel,
        angvel=f("angvel", b.bodies, (nb, 3)), prev_vel=vel,
        joint_impulse=jnp.zeros((nj, 6), dtype), row_impulse=jnp.zeros((model.n_rows,), dtype),
        time=jnp.zeros((), dtype),
        field_id=jnp.full((model.n_field_pair,), -1.0, dtype),
    )
    return model, state


def _field_tables(b, dtype):
    """Static and traced tables of the builder's sphere field (or of none)."""
    none = dict(name="", query=np.zeros((0,), np.int32), k=0, grid=(0, 0, 0),
                material=np.zeros((0,), np.int32), dir_sign=np.zeros((0,), np.int32),
                centre=jnp.zeros((0, 3), dtype), radius=jnp.zeros((0,), dtype),
                origin=jnp.zeros((2,), dtype), cell=jnp.ones((), dtype))
    f = b.field
    if f is None:
        return none
    n_cs = len(b.cspheres)
    query = list(range(n_cs)) if f["spheres"] is None else f["spheres"]
    if not query or min(query) < 0 or max(query) >= n_cs:
        raise ValueError(f"sphere field {f['name']!r}: query spheres {query} must be "
                         f"indices of the {n_cs} contact spheres")
    if b.cspheres and any(b.cspheres[i]["body"] < 0 for i in query):
        raise ValueError(f"sphere field {f['name']!r}: query spheres must sit on dynamic bodies")
    r_query = max(b.cspheres[i]["radius"] for i in query)
    layout = field_layout(f["centres"], f["radii"], r_query, f["cell_size"], f["capacity"],
                          f["bounds"], f["name"])
    mats = [b.cspheres[i]["material"] for i in query]
    dirs = [int(b.cspheres[i]["direction"] is not None) for i in query]
    centre, radius = pack_field(f["centres"], f["radii"], layout)
    return dict(name=f["name"], query=np.asarray(query, np.int32), k=f["k"],
                grid=layout["grid"],
                material=np.asarray([f["material"] if m is None else m for m in mats], np.int32),
                dir_sign=np.asarray(dirs, np.int32),
                centre=jnp.asarray(centre, dtype), radius=jnp.asarray(radius, dtype),
                origin=jnp.asarray(layout["origin"], dtype),
                cell=jnp.asarray(layout["cell"], dtype))


#: z of an empty grid slot's centre [m]: far below any floor (radius 0), finite so that
#: the contact geometry of an unused candidate stays finite.
EMPTY_Z = -1.0e6


def field_layout(centres, radii, r_query, cell_size=None, capacity=None, bounds=None,
                 name="field"):
    """The grid of a sphere field: ``dict(grid=(nx, ny, capacity), origin=(2,), cell)``.

    The grid covers ``bounds`` (default: the centres' x-y bounding box) plus one empty
    border cell on every side, so the 3 x 3 neighbourhood of any (clipped) cell is made of
    distinct cells; ``cell`` defaults to (and must be at least) the largest field radius
    plus ``r_query`` (1 % more by default). Raises ``ValueError`` naming the field for a
    layout that does not fit (a sphere outside the bounds, a cell over capacity, a cell
    that is too small).
    """
    centres = np.asarray(centres, np.float64).reshape(-1, 3)
    radii = np.asarray(radii, np.float64).reshape(-1)
    r_max = float(radii.max()) if radii.size else 0.0
    need = r_max + float(r_query)
    # 1 % over the minimum: round-off where a sphere sits on a cell border cannot move it
    # two cells away from a query sphere that touches it (float32 x-y 2,000 cells out
    # are good to ~1e-4 cells)
    cell = 1.01 * need if cell_size is None else float(cell_size)
    if not cell > 0 or cell < need * (1 - 1e-9):
        raise ValueError(f"sphere field {name!r}: cell_size {cell} must be >= the largest "
                         f"field radius plus the largest query radius ({need})")
    if bounds is None:
        if not centres.shape[0]:
            raise ValueError(f"sphere field {name!r}: give bounds for an empty field")
        lo, hi = centres[:, :2].min(0), centres[:, :2].max(0)
    else:
        lo, hi = (np.asarray(x, np.float64).reshape(2) for x in bounds)
        if not np.all(hi >= lo):
            raise ValueError(f"sphere field {name!r}: bounds {bounds} need x_max >= x_min "
                             "and y_max >= y_min")
    n = np.floor((hi - lo) / cell).astype(int) + 1 + 2  # inner cells, one border cell a side
    origin = lo - cell
    layout = dict(grid=(int(n[0]), int(n[1]), 0), origin=origin, cell=cell)
    counts = np.bincount(_cells(centres, layout, name), minlength=int(n[0] * n[1]))
    cap = int(counts.max(initial=0)) if capacity is None else int(capacity)
    if counts.max(initial=0) > cap:
        raise ValueError(f"sphere field {name!r}: a cell holds {int(counts.max())} spheres, "
                         f"capacity is {cap}")
    layout["grid"] = (int(n[0]), int(n[1]), max(cap, 1))
    return layout


def _cells(centres, layout, name):
    """Flat cell index of each centre; ``ValueError`` if one lies outside the bounds."""
    n = np.asarray(layout["grid"][:2])
    u = (centres[:, :2] - layout["origin"]) / layout["cell"]
    inside = np.all((u >= 1 - 1e-9) & (u <= n - 1 + 1e-9), axis=1)  # round-off at the bounds
    ij = np.clip(np.floor(u).astype(np.int64), 1, n - 2)
    ny = int(n[1])
    if not inside.all():
        bad = centres[~inside][0]
        raise ValueError(f"sphere field {name!r}: centre {bad.tolist()} lies outside the "
                         "field's bounds")
    return ij[:, 0] * ny + ij[:, 1]


def pack_field(centres, radii, layout, name="field"):
    """Cell-major arrays ``(centre (nx ny cap, 3), radius (nx ny cap,))`` of a layout.

    Spheres fill the slots of their cell in input order; empty slots sit at
    ``EMPTY_Z`` with radius 0.
    """
    centres = np.asarray(centres, np.float64).reshape(-1, 3)
    radii = np.broadcast_to(np.asarray(radii, np.float64), (centres.shape[0],))
    nx, ny, cap = layout["grid"]
    cell_of = _cells(centres, layout, name)
    order = np.argsort(cell_of, kind="stable")
    cells = cell_of[order]
    first = np.searchsorted(cells, cells, side="left")
    slot = np.arange(cells.size) - first
    if slot.size and slot.max() >= cap:
        raise ValueError(f"sphere field {name!r}: a cell holds {int(slot.max()) + 1} "
                         f"spheres, capacity is {cap}")
    ix, iy = np.divmod(np.arange(nx * ny), ny)
    centre = np.zeros((nx * ny, cap, 3))
    centre[:, :, 0] = (layout["origin"][0] + (ix[:, None] + 0.5) * layout["cell"])
    centre[:, :, 1] = (layout["origin"][1] + (iy[:, None] + 0.5) * layout["cell"])
    centre[:, :, 2] = EMPTY_Z
    radius = np.zeros((nx * ny, cap))
    centre[cells, slot] = centres[order]
    radius[cells, slot] = radii[order]
    return centre.reshape(-1, 3), radius.reshape(-1)
