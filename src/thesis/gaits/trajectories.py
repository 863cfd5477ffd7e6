"""The three open-loop trot families of §3.3.1 / §4.2 as pure functions of time.

Each family is a small frozen object exposing

* ``names``, ``units``: the parameter vector layout (thesis table order),
* ``lower``, ``upper``: (P,) box bounds (the thesis ranges; a dependent range such as
  a ∈ [0, a_max(x0)] appears as its loosest box and is enforced by ``project``),
* ``project(params)``: NumPy map onto the feasible set (pass to the PSO),
* ``commands_at_phase(params, phase)`` and ``commands(params, t)``: the (12,) joint
  commands [rad] (per leg scapula, hip, knee; legs LF, RF, LH, RH — ``leg.LEGS``,
  ``leg.JOINTS``) at gait phase ``phase`` [cycles] or time ``t`` [s] (phase = f t).
  Pure jnp: usable under ``jit``/``vmap``; the robot receives them every 10 ms (§3.2.2),
  i.e. ``t = 0.01 k``.

Loci families also expose ``foot_targets(params, phase)`` -> (4, 3) hip-frame foot
positions [m] that the commands track through :func:`thesis.gaits.leg.inverse3d`.

Gait parameters are in the thesis's units (mm, Hz, duty factor in d.u., rad for the sine
gait), so that bounds and the transfer impulse of §4.4 read as in the thesis.

Trot phasing (§3.3.1.2 "adjacent legs have a phase shift of 180°"): diagonal pairs in
phase, LF = RH = 0, RF = LH = 1/2 cycle (``TROT_PHASE``). Phase 0 of a leg is touchdown
at the front point A of its locus; the stance (fraction ``duty`` = t_stance f of the
cycle) runs at constant parameter speed from A to the back point B, the swing returns.

Thesis x0 (depth below the hip) and y0 (horizontal offset, + forward) are the hip-frame
``-z`` and ``x``. Turning by rotating the loci about a vertical axis through their centre
(§3.3.2.5, up to 20°) is available through the optional per-leg ``yaw`` [rad].
"""

from __future__ import annotations

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np

from thesis.gaits import leg as L

#: Phase offset [cycles] of each leg for a trot (LEGS order): diagonal pairs in phase.
TROT_PHASE = (0.0, 0.5, 0.5, 0.0)
#: Phase offsets [cycles] of a lateral-sequence walk (LEGS order LF, RF, LH, RH): the feet
#: touch down LH, LF, RH, RF a quarter cycle apart, so "each leg has a different phase"
#: (§6.5). The thesis does not print its walk; this is Hildebrand's lateral sequence.
WALK_PHASE = (0.25, 0.75, 0.0, 0.5)
#: Range of the depth of the locus centre below the hip, x0 [mm] (Tab. 4.1).
X0_RANGE = (126.0, 158.0)
#: Range of the gait frequency f [Hz] (Tab. 4.1).
F_RANGE = (1.5, 2.0)
#: Range of the stance fraction t_stance f [d.u.] of the spline gait (Tab. 4.1).
DUTY_RANGE = (0.4, 0.6)
#: Range of the Bézier control-point offsets l_i [mm] (Tab. 4.1).
L_RANGE = (0.0, 70.0)


def theoretical_speed(a_mm, frequency, duty):
    """Theoretical robot speed [m/s]: the foot's mean ground speed in stance (Fig. 3.4).

    The foot covers the stride 2a (a the semi-axis, §3.3.1.3 "the major axis 2a") in
    the stance time t_stance = duty / f, so v = 2 a f / duty. Broadcasts over arrays.

    Args:
        a_mm: semi-axis a [mm]; frequency: f [Hz]; duty: t_stance f [d.u.].
    """
    return 2.0 * jnp.asarray(a_mm) * 1e-3 * jnp.asarray(frequency) / jnp.asarray(duty)


def leg_phases(phase, offsets=TROT_PHASE) -> jnp.ndarray:
    """(..., 4) per-leg phase in [0, 1) for the global gait phase(s) [cycles].

    ``offsets``: (4,) phase offset of each leg [cycles], LEGS order (default: the trot's
    ``TROT_PHASE``; ``WALK_PHASE`` for the walk of §6.5)."""
    p = jnp.asarray(phase)[..., None] + jnp.asarray(offsets)
    return jnp.mod(p, 1.0)


class ReachTable:
    """Horizontal extent of one leg's reachable area vs depth, tabulated for fast
    projection.

    ``extent(x0)`` -> (x_min, x_max) [mm] at depth x0 [mm]; from these, a_max(x0) =
    (x_max - x_min)/2 and y0 ∈ [x_min + a, x_max - a] keep A = (y0 + a, x0) and
    B = (y0 - a, x0) reachable (Tab. 4.1).
    """

    def __init__(self, geom: L.LegGeometry, x0_lo: float = 100.0, x0_hi: float = 170.0,
                 step: float = 0.25):
        self.x0 = np.arange(x0_lo, x0_hi + 1e-9, step)
        ext = L.horizontal_extent(geom, self.x0 * 1e-3) * 1e3
        self.xmin, self.xmax = ext[:, 0], ext[:, 1]

    def extent(self, x0):
        x0 = np.asarray(x0, dtype=np.float64)
        return np.interp(x0, self.x0, self.xmin), np.interp(x0, self.x0, self.xmax)

    def a_max(self, x0):
        lo, hi = self.extent(x0)
        return np.maximum(0.5 * (hi - lo), 0.0)

    def y0_range(self, x0, a):
        lo, hi = self.extent(x0)
        return lo + np.asarray(a), hi - np.asarray(a)


def _bezier(p0, p1, p2, p3, u):
    """Cubic Bézier point at parameter u ∈ [0, 1] (control points broadcast with u)."""
    v = 1.0 - u
    return v**3 * p0 + 3 * v * v * u * p1 + 3 * v * u * u * p2 + u**3 * p3


@dataclasses.dataclass(frozen=True, eq=False)
class _LociGait:
    """Shared machinery of the foot-locus families (ellipse, spline).

    ``geom`` is the fore legs' geometry, ``hind_geom`` the hind legs'
    (:func:`thesis.gaits.leg.oncilla_hind_geometry`: longer, so their reachable area is
    larger). The stride a is common to all legs, so a_max(x0) is the smaller of the two
    (the fore legs'); each pair's offset y0 is bounded by its own legs' area.
    """

    geom: L.LegGeometry = dataclasses.field(default_factory=L.oncilla_geometry)
    #: (4,) phase offset of each leg [cycles], LEGS order: the trot by default (chapters 3
    #: and 4), ``WALK_PHASE`` for the walk teacher of chapter 6.
    phase_offsets: tuple = TROT_PHASE
    hind_geom: L.LegGeometry = dataclasses.field(default_factory=L.oncilla_hind_geometry)

    def __post_init__(self):
        object.__setattr__(self, "table", ReachTable(self.geom))
        object.__setattr__(self, "hind_table", ReachTable(self.hind_geom))
        object.__setattr__(self, "legs", L.leg_geometries(self.geom, self.hind_geom))

    def a_max(self, x0):
        """Largest semi-axis a [mm] at depth x0 [mm] that every leg's A and B can reach."""
        return np.minimum(self.table.a_max(x0), self.hind_table.a_max(x0))

    # subclasses define: names, units, _i (index dict), lower/upper, _locus
    def index(self, name: str) -> int:
        return self.names.index(name)

    def frequency(self, params):
        return jnp.asarray(params)[..., self.index("f")]

    def duty(self, params):
        return jnp.asarray(params)[..., self.index("duty")]

    def _box(self, extra_lo: dict, extra_hi: dict):
        lo_f, hi_f = self.table.extent(X0_RANGE[0])
        lo_h, hi_h = self.hind_table.extent(X0_RANGE[0])
        lo = {"x0": X0_RANGE[0], "a": 0.0, "y0_fore": lo_f, "y0_hind": lo_h, **extra_lo}
        hi = {"x0": X0_RANGE[1], "a": float(self.a_max(X0_RANGE[0])),
              "y0_fore": hi_f, "y0_hind": hi_h, **extra_hi}
        return (np.array([lo[n] for n in self.names], dtype=np.float64),
                np.array([hi[n] for n in self.names], dtype=np.float64))

    def project(self, params) -> np.ndarray:
        """Clip to the box, then a into [0, a_max(x0)] and each pair's y0 into its legs'
        [y_min, y_max] (the dependent ranges of Tab. 4.1, §3.3.1.2). Shape (..., P) ->
        (..., P)."""
        p = np.clip(np.array(params, dtype=np.float64), self.lower, self.upper)
        ix0, ia = self.index("x0"), self.index("a")
        x0 = p[..., ix0]
        p[..., ia] = np.clip(p[..., ia], 0.0, self.a_max(x0))
        for n, table in (("y0_fore", self.table), ("y0_hind", self.hind_table)):
            ylo, yhi = table.y0_range(x0, p[..., ia])
            i = self.index(n)
            p[..., i] = np.clip(p[..., i], ylo, np.maximum(yhi, ylo))
        return p

    def inverse(self, targets) -> jnp.ndarray:
        """(..., 4, 3) joint angles [rad] for (..., 4, 3) hip-frame foot targets [m], each
        leg through its own geometry (:func:`thesis.gaits.leg.inverse_legs`)."""
        return L.inverse_legs(self.legs, targets)

    def foot_targets(self, params, phase, yaw=None) -> jnp.ndarray:
        """(4, 3) foot targets in each hip frame [m] at gait phase ``phase`` [cycles].

        ``yaw``: optional (4,) rotation [rad] of each leg's locus about the vertical axis
        through its centre (turning with the scapulae, §3.3.2.5)."""
        params = jnp.asarray(params)
        s = leg_phases(phase, self.phase_offsets)
        fore = jnp.asarray(L.IS_FORE)
        dx, depth = self._locus(params, s, fore)  # (4,), (4,) in mm, dx from centre
        y0 = jnp.where(fore, params[self.index("y0_fore")], params[self.index("y0_hind")])
        yaw = jnp.zeros(4, dtype=dx.dtype) if yaw is None else jnp.asarray(yaw)
        x = (y0 + dx * jnp.cos(yaw)) * 1e-3
        y = dx * jnp.sin(yaw) * 1e-3
        z = -depth * 1e-3
        return jnp.stack([x, y, z], axis=-1)

    def commands_at_phase(self, params, phase, yaw=None) -> jnp.ndarray:
        """(12,) joint commands [rad] at gait phase ``phase`` [cycles] (via IK)."""
        targets = self.foot_targets(params, phase, yaw)
        return self.inverse(targets).reshape(12)

    def commands(self, params, t, yaw=None) -> jnp.ndarray:
        """(12,) joint commands [rad] at time ``t`` [s] (phase = f t)."""
        return self.commands_at_phase(params, self.frequency(params) * t, yaw)

    def speed(self, params):
        """Theoretical speed [m/s] of Fig. 3.4 for these parameters."""
        return theoretical_speed(jnp.asarray(params)[..., self.index("a")],
                                 self.frequency(params), self.duty(params))


@dataclasses.dataclass(frozen=True, eq=False)
class EllipseGait(_LociGait):
    """Half-ellipse foot loci (Fig. 3.3a, Tab. 3.1a): flat stance at depth x0 from
    A = (y0 + a) to B = (y0 - a), swing over a half ellipse of height b.

    Layout (Tab. 3.1a order): x0 [mm], y0_fore [mm], y0_hind [mm], a [mm], b_fore [mm],
    b_hind [mm], duty = t_stance f [d.u.], f [Hz].

    The thesis gives no ranges for this family; we use those of Tab. 4.1 for the shared
    quantities (x0, a, y0, f) and [0, 70] mm (the l_i range of Tab. 4.1) for b. The duty
    range is [0.5, 0.6]: the lower end is the "either two or four feet touch the ground"
    assumption of §3.3.1.2 (below 0.5 both feet of a side leave the ground, §3.3.2.3),
    the upper end that of Tab. 4.1. b may exceed the reachable height: the IK then stops
    at the knee's flexion limit and the path gets the "dent" of §3.3.1.2.
    The swing advances uniformly in the ellipse angle.
    """

    names = ("x0", "y0_fore", "y0_hind", "a", "b_fore", "b_hind", "duty", "f")
    units = ("mm", "mm", "mm", "mm", "mm", "mm", "1", "Hz")

    def __post_init__(self):
        super().__post_init__()
        lo, hi = self._box({"b_fore": 0.0, "b_hind": 0.0, "duty": 0.5, "f": F_RANGE[0]},
                           {"b_fore": 70.0, "b_hind": 70.0, "duty": 0.6, "f": F_RANGE[1]})
        object.__setattr__(self, "lower", lo)
        object.__setattr__(self, "upper", hi)

    def _locus(self, params, s, fore):
        x0, a = params[self.index("x0")], params[self.index("a")]
        b = jnp.where(fore, params[self.index("b_fore")], params[self.index("b_hind")])
        duty = params[self.index("duty")]
        st = s < duty
        u_st = s / duty
        u_sw = (s - duty) / (1.0 - duty)
        dx = jnp.where(st, a - 2.0 * a * u_st, -a * jnp.cos(jnp.pi * u_sw))
        depth = jnp.where(st, x0, x0 - b * jnp.sin(jnp.pi * u_sw))
        return dx, depth


@dataclasses.dataclass(frozen=True, eq=False)
class SplineGait(_LociGait):
    """Bézier foot loci (Fig. 3.3b, Fig. 4.2, Tab. 4.1): two cubic Bézier curves between
    A = (y0 + a, x0) and B = (y0 - a, x0) whose inner control points lie vertically
    above/below A and B ("we only allow P_i to move vertically"; with l = 4b/3 the swing
    is the usual cubic approximation of a half ellipse of height b, §3.3.1.3):

    * stance A → B: control points A + l2 (deeper), B + l3 (deeper), for all legs;
    * swing  B → A: control points B - l1, A - l0 (higher), per fore / hind pair.

    Layout (Tab. 4.1 order, 12 parameters): f [Hz], a [mm], x0 [mm], y0_fore [mm],
    y0_hind [mm], duty = t_stance [d.u.], l0_fore, l1_fore, l0_hind, l1_hind, l2, l3 [mm].
    Ranges as Tab. 4.1. Reachability: A and B by ``project`` (a ≤ a_max(x0),
    y0 ∈ [y_min, y_max]); the rest of the curve by the IK's joint-limit projection, as
    "these splines are subsequently limited to the range of the actuators" (§4.2).
    Each curve advances uniformly in its Bézier parameter, so the stance starts and
    ends with zero horizontal foot speed.
    """

    names = ("f", "a", "x0", "y0_fore", "y0_hind", "duty", "l0_fore", "l1_fore",
             "l0_hind", "l1_hind", "l2", "l3")
    units = ("Hz", "mm", "mm", "mm", "mm", "1", "mm", "mm", "mm", "mm", "mm", "mm")

    def __post_init__(self):
        super().__post_init__()
        ls = ("l0_fore", "l1_fore", "l0_hind", "l1_hind", "l2", "l3")
        lo, hi = self._box({"f": F_RANGE[0], "duty": DUTY_RANGE[0],
                            **{n: L_RANGE[0] for n in ls}},
                           {"f": F_RANGE[1], "duty": DUTY_RANGE[1],
                            **{n: L_RANGE[1] for n in ls}})
        object.__setattr__(self, "lower", lo)
        object.__setattr__(self, "upper", hi)

    def _locus(self, params, s, fore):
        P = lambda n: params[self.index(n)]  # noqa: E731
        x0, a, duty = P("x0"), P("a"), P("duty")
        l0 = jnp.where(fore, P("l0_fore"), P("l0_hind"))
        l1 = jnp.where(fore, P("l1_fore"), P("l1_hind"))
        st = s < duty
        u = jnp.where(st, s / duty, (s - duty) / (1.0 - duty))
        # horizontal control points: stance A, A, B, B; swing B, B, A, A
        sx = jnp.where(st, 1.0, -1.0)
        dx = _bezier(sx * a, sx * a, -sx * a, -sx * a, u)
        d_st = _bezier(x0, x0 + P("l2"), x0 + P("l3"), x0, u)
        d_sw = _bezier(x0, x0 - l1, x0 - l0, x0, u)
        return dx, jnp.where(st, d_st, d_sw)


@dataclasses.dataclass(frozen=True, eq=False)
class SineGait:
    """Sine control signals in joint space (§3.3.1.1): hip and knee each follow
    offset + amplitude · sin(2π (f t + leg phase) + joint phase); one frequency; left and
    right legs share parameters apart from the trot phase (``TROT_PHASE``); the scapulae
    get a constant 0 ("the plane in which the legs move does not change").

    Layout (13 parameters): f [Hz], then for fore and for hind legs: hip_amp [rad],
    hip_phase [rad], hip_offset [rad], knee_amp [rad], knee_phase [rad], knee_offset [rad].

    The thesis tuned this gait by hand and gives no ranges; ours: f ∈ [0.5, 2.5] Hz
    (covers the frequencies of Fig. 3.4), amplitudes up to half the joint range, phases
    in [0, 2π], offsets inside the joint limits; commands are clipped to the limits
    (the fore legs' ``geom`` and the hind legs' ``hind_geom``, each for its pair).
    """

    geom: L.LegGeometry = dataclasses.field(default_factory=L.oncilla_geometry)
    hind_geom: L.LegGeometry = dataclasses.field(default_factory=L.oncilla_hind_geometry)

    names = ("f", "hip_amp_fore", "hip_phase_fore", "hip_offset_fore", "knee_amp_fore",
             "knee_phase_fore", "knee_offset_fore", "hip_amp_hind", "hip_phase_hind",
             "hip_offset_hind", "knee_amp_hind", "knee_phase_hind", "knee_offset_hind")
    units = ("Hz",) + ("rad",) * 12

    def __post_init__(self):
        lo, hi = [0.5], [2.5]
        for g in (self.geom, self.hind_geom):
            hr = 0.5 * (float(g.hip_max) - float(g.hip_min))
            kr = 0.5 * (float(g.knee_max) - float(g.knee_min))
            lo += [0.0, 0.0, float(g.hip_min), 0.0, 0.0, float(g.knee_min)]
            hi += [hr, 2 * math.pi, float(g.hip_max), kr, 2 * math.pi, float(g.knee_max)]
        object.__setattr__(self, "lower", np.array(lo))
        object.__setattr__(self, "upper", np.array(hi))

    def index(self, name: str) -> int:
        return self.names.index(name)

    def frequency(self, params):
        return jnp.asarray(params)[..., 0]

    def project(self, params) -> np.ndarray:
        """Clip to the box (no dependent ranges)."""
        return np.clip(np.array(params, dtype=np.float64), self.lower, self.upper)

    def commands_at_phase(self, params, phase) -> jnp.ndarray:
        """(12,) joint commands [rad] at gait phase ``phase`` [cycles]."""
        p = jnp.asarray(params)
        s = leg_phases(phase)  # (4,)
        fore = jnp.asarray(L.IS_FORE)
        pick = lambda i: jnp.where(fore, p[1 + i], p[7 + i])  # noqa: E731
        f, h = self.geom, self.hind_geom
        lim = lambda name: jnp.where(fore, getattr(f, name), getattr(h, name))  # noqa: E731
        hip = pick(2) + pick(0) * jnp.sin(2 * jnp.pi * s + pick(1))
        knee = pick(5) + pick(3) * jnp.sin(2 * jnp.pi * s + pick(4))
        hip = jnp.clip(hip, lim("hip_min"), lim("hip_max"))
        knee = jnp.clip(knee, lim("knee_min"), lim("knee_max"))
        scap = jnp.zeros_like(hip)
        return jnp.stack([scap, hip, knee], axis=-1).reshape(12)

    def commands(self, params, t) -> jnp.ndarray:
        """(12,) joint commands [rad] at time ``t`` [s]."""
        return self.commands_at_phase(params, self.frequency(params) * t)


#: Period of the robot's command updates [s] ("new commands to the robot every 10 ms").
COMMAND_DT = 0.01


def command_series(family, params, n_steps: int, dt: float = COMMAND_DT, t0: float = 0.0):
    """Open-loop command table: (n_steps, 12) joint commands [rad] at t0 + k dt.

    The gaits are open loop, so a rollout can read its servo targets from this table
    instead of solving the IK inside the physics loop; vmap over ``params`` for a whole
    generation of particles.
    """
    t = t0 + dt * jnp.arange(n_steps)
    p = jnp.asarray(params)
    return jax.vmap(lambda s: family.commands(p, s))(t)


#: Family name -> class.
FAMILIES = {"sine": SineGait, "ellipse": EllipseGait, "spline": SplineGait}
