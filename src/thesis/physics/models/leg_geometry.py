"""Geometry of the Oncilla's three-segment pantographic legs (§3.2.1, §3.3.1.2, §4.5):
segment lengths, joint limits and the leg and joint order; the fore legs
(:func:`oncilla_geometry`) and the longer hind legs (:func:`oncilla_hind_geometry`).

The engine's Oncilla model (:mod:`thesis.physics.models.oncilla`) is built from this
geometry, and the gait code's kinematics (:mod:`thesis.gaits.leg`, which re-exports
every name here) computes with it; it lives on the engine side so that the engine
imports no chapter package. Frames and angle conventions: :mod:`thesis.gaits.leg`.
"""

from __future__ import annotations

import dataclasses
import math

import jax
import jax.numpy as jnp

__all__ = ["LEGS", "JOINTS", "SIDES", "IS_FORE", "R_MAX", "R_MIN", "R_MAX_HIND",
           "KNEE_RANGE_HIND_RATIO", "LegGeometry", "knee_angle_for_reach", "leg_geometries",
           "oncilla_geometry", "oncilla_hind_geometry"]

#: Leg order of every 12-vector of joint commands.
LEGS = ("LF", "RF", "LH", "RH")
#: Joint order within a leg.
JOINTS = ("scapula", "hip", "knee")
#: +1 for left legs, -1 for right legs (order of LEGS).
SIDES = (1.0, -1.0, 1.0, -1.0)
#: True for fore legs (order of LEGS).
IS_FORE = (True, True, False, False)

# ---- design values of the default geometry (see :func:`oncilla_geometry`) ----------
#: Maximal hip-foot distance [m]: the reach circle that bounds the step length of Tab. 4.1.
R_MAX = 0.167
#: Minimal hip-foot distance [m] at full knee flexion.
R_MIN = 0.100
#: Maximal hip-foot distance of a hind leg [m] (see :func:`oncilla_hind_geometry`).
R_MAX_HIND = 0.182
#: Knee motor range of a hind leg over a fore leg's: 2200 / 1850 encoder counts
#: (liboncilla-hw ``HWOncillaBackend.h``, docs/sources.md#oncilla-hind-legs).
KNEE_RANGE_HIND_RATIO = 2200.0 / 1850.0


def _deg(x: float) -> float:
    return x * math.pi / 180.0


@dataclasses.dataclass(frozen=True)
class LegGeometry:
    """Geometry and joint limits of one Oncilla leg (the fore legs share one, the hind
    legs another: :func:`leg_geometries`).

    Attributes:
        femur: proximal segment, hip→knee [m].
        tibia: middle segment, knee→heel [m].
        foot: distal segment, heel→toe, kept parallel to the femur by the pantograph's
            parallel link [m]; the parallel link's length equals ``tibia`` (parallelogram).
        hip_min, hip_max: hip (femur) angle limits from the downward vertical [rad].
        knee_min, knee_max: inner knee angle limits [rad] (flexion stop, extension stop).
        scapula_min, scapula_max: ab/adduction limits [rad] (+ = abduction).
        knee_spring_rest: rest angle of the knee's extension spring [rad]; the spring
            pushes the knee open against the cable (§6.2), here up to the extension stop.
    """

    femur: float
    tibia: float
    foot: float
    hip_min: float
    hip_max: float
    knee_min: float
    knee_max: float
    scapula_min: float
    scapula_max: float
    knee_spring_rest: float

    def replace(self, **kw) -> "LegGeometry":
        return dataclasses.replace(self, **kw)

    @property
    def lower(self) -> jnp.ndarray:
        """(2,) sagittal joint lower limits (hip, knee) [rad]."""
        return jnp.stack([jnp.asarray(self.hip_min), jnp.asarray(self.knee_min)])

    @property
    def upper(self) -> jnp.ndarray:
        """(2,) sagittal joint upper limits (hip, knee) [rad]."""
        return jnp.stack([jnp.asarray(self.hip_max), jnp.asarray(self.knee_max)])


jax.tree_util.register_dataclass(
    LegGeometry,
    data_fields=[f.name for f in dataclasses.fields(LegGeometry)],
    meta_fields=[],
)


def knee_angle_for_reach(femur: float, tibia: float, foot: float, r: float) -> float:
    """Inner knee angle [rad] at which the hip-foot distance equals ``r`` [m] (law of
    cosines on the two-link equivalent with links femur+foot and tibia)."""
    a, b = femur + foot, tibia
    return math.acos((a * a + b * b - r * r) / (2.0 * a * b))


def oncilla_geometry() -> LegGeometry:
    """The default Oncilla leg. No public source gives the Oncilla's segment lengths or
    joint ranges (docs/sources.md#oncilla-legs), so they are chosen from what the thesis states:

    * Reach R_MAX = 167 mm: Tab. 4.1 bounds the step length by "the maximal step length at
      the height x0, such that the points A and B ... never go out of the reachable region",
      and Fig. 4.9 says most particles lie on that edge, "the end of the robot's range of
      motion". The (a, x0) pairs of the optimised particles in Tab. 4.2–4.4 all satisfy a² +
      x0² = (167 mm)² to within 0.1 mm, i.e. a_max(x0) = sqrt(R² - x0²): A = (y0 + a, x0)
      lies on a reach circle of radius 167 mm (a is the semi-axis; the stride is 2a,
      §3.3.1.3 "the major axis 2a"). The circle is also consistent with the ~0.15 m leg of
      the Cheetah-cub predecessor (Spröwitz et al. 2013) scaled to the larger Oncilla.
    * Reach R_MIN = 100 mm (knee flexion stop): small enough that the swing heights found
      for the half ellipse (b ≤ 26 mm at x0 ≈ 138 mm, Tab. 3.1a) are reachable, and
      large enough that the tallest splines of Tab. 4.1 (control points 70 mm, apex
      52.5 mm above the stance line at x0 = 126 mm) are cut by the actuator range, as
      §3.3.1.2 ("a dent in the top, because the knee cannot flex any further") and §4.2
      ("limited to the range of the actuators") describe. An assumption.
    * Segments femur 65 mm, tibia 70 mm, foot 40 mm: three segments of comparable
      length (cat-like, §3.2.1) summing to 175 mm so that the extension stop that gives
      R_MAX leaves the knee bent (≈145°), as a spring-loaded pantograph must be to act
      as a spring; knee limits follow from R_MIN and R_MAX (:func:`knee_angle_for_reach`).
    * Hip range [-30°, 65°]: wide enough that the reach circle, not the hip range, bounds
      the stance over the whole x0 range [126, 158] mm of Tab. 4.1 (foot up to ±41° from
      the vertical at full extension; checked in the tests); the offset towards positive
      angles is because the knee points forward, so the femur leans forward.
    * Scapula [-5°, +10°]: "about 5° of adduction and 10° of abduction" (§3.3.2.5).
    """
    femur, tibia, foot = 0.065, 0.070, 0.040
    knee_min = knee_angle_for_reach(femur, tibia, foot, R_MIN)
    knee_max = knee_angle_for_reach(femur, tibia, foot, R_MAX)
    return LegGeometry(
        femur=femur, tibia=tibia, foot=foot, hip_min=_deg(-30.0), hip_max=_deg(65.0),
        knee_min=knee_min, knee_max=knee_max, scapula_min=_deg(-5.0),
        scapula_max=_deg(10.0), knee_spring_rest=knee_max,
    )


def oncilla_hind_geometry() -> LegGeometry:
    """The Oncilla's hind leg: longer, with more knee range than the fore leg.

    Sources and choices (docs/sources.md#oncilla-hind-legs; declared in ``departures/ch3.py``,
    ``ch3.oncilla_model``):

    * **Longer reach, R_MAX_HIND = 182 mm.** The thesis's optimised particles (Tab.
      4.2-4.4) all lie on the fore legs' 167 mm reach circle (a² + x0² = 166.8-166.9²
      mm², y0_fore = 0), and their hind offsets y0_hind of -5 to -24 mm put the hind foot's
      back point B = (y0_hind - a, x0) 168.7 to 181.9 mm from the hip, which the real
      robot's hind legs reached (Tab. 4.1 keeps A and B of every leg inside its reachable
      region). 182 mm is the farthest of them, rounded up. The segments are the fore
      leg's scaled by R_MAX_HIND / R_MAX (1.09: femur 70.8, tibia 76.3, foot 43.6 mm), so
      the extension stop sits at the same inner knee angle (≈145°). No source gives the
      hind segments' lengths; uniform scaling is the choice.
    * **More knee range, x 2200 / 1850.** The robot's backend gives the hind knee motors
      2200 encoder counts of range against 1850 for the fore ones (liboncilla-hw
      ``HWOncillaBackend.h``, marked "todo CHECK" there). Read as proportional to the knee
      angle (an assumption: the counts are the motor's, the knee is cable-driven), the hind
      knee's range is the fore range x 1.19; the extra range is put on the flexion side (the
      extension stop already gives the reach above), so the hind leg folds to ≈90 mm from
      the hip.
    * Hip range and scapula range as the fore leg's (the backend gives one hip range,
      the thesis one scapula range).
    """
    fore = oncilla_geometry()
    k = R_MAX_HIND / R_MAX
    femur, tibia, foot = fore.femur * k, fore.tibia * k, fore.foot * k
    knee_max = knee_angle_for_reach(femur, tibia, foot, R_MAX_HIND)
    knee_min = knee_max - KNEE_RANGE_HIND_RATIO * (fore.knee_max - fore.knee_min)
    return fore.replace(femur=femur, tibia=tibia, foot=foot, knee_min=knee_min,
                        knee_max=knee_max, knee_spring_rest=knee_max)


def leg_geometries(fore: LegGeometry | None = None,
                   hind: LegGeometry | None = None) -> tuple[LegGeometry, ...]:
    """The four legs' geometries in LEGS order (LF, RF, LH, RH): ``fore`` for the fore
    legs and ``hind`` for the hind ones (defaults :func:`oncilla_geometry` and
    :func:`oncilla_hind_geometry`)."""
    fore = fore or oncilla_geometry()
    hind = hind or oncilla_hind_geometry()
    return tuple(fore if f else hind for f in IS_FORE)
