"""The declared split of the thesis's published Oncilla measurements into what a
calibration may be fitted on and what the model is judged on, the values a calibration
may fit, and the fit's procedure: data, fixed before any fit is run
(docs/architecture.md#engine-rules).

Fitting a value that no source gives to published measurements is system identification
as long as the measurements it is fitted on are declared first and the model is then
judged on published measurements it never saw. This module is that declaration. It reads
no number itself: each measurement names the :mod:`thesis.paper` keys that give it (the
readers are :mod:`thesis.modelcheck.targets`; experiment code never imports the paper),
so a test can check that the calibration reads only the keys of the *fitted on* side
(tests/modelcheck/test_split.py).

* :data:`PARTS`: every sub-target of the validation targets V1-V7
  (:mod:`thesis.modelcheck.targets`) and the published measurements beside them, each on
  exactly one side, :data:`FITTED` (the calibration may read it) or :data:`JUDGED`
  (validation only), with its thesis source and its paper keys. A part whose verdict the
  fitted numbers partly fix although it reads none of them says so in ``note``: its
  verdict is not independent evidence.
* :data:`PARAMETERS`: the only values a calibration may change, each one no source gives,
  with its bounds and where they come from (docs/sources.md anchors). Every sourced value
  stays as it is.
* :data:`PROCEDURE`: the fit's objective, its perturbed starts and initial points, and
  its optimiser: declared, not run here.

The knee-spring calibration that exists (:mod:`thesis.modelcheck.calibration`) reads V1
alone, a subset of the fitted side. :mod:`thesis.modelcheck.fit` runs :data:`PROCEDURE`
(``thesis validate oncilla --only fit``).
"""

from __future__ import annotations

import dataclasses
import math

#: The calibration may read these measurements.
FITTED = "fitted"
#: Validation only: no calibration reads them.
JUDGED = "judged"
SIDES = (FITTED, JUDGED)
#: Frequency [Hz] of every fitted-on measurement: §3.3.3's gait frequency, at which the
#: thesis gives both Tab. 3.1 gaits' speeds (paper key ``sec3.3.3/turning_frequency``).
FIT_FREQUENCY = 1.5
#: A part's ``frequencies`` value meaning every frequency that no other part of the same
#: target names.
OTHER = "other"
#: A part's ``frequencies`` value meaning the part is not split by frequency.
ANY = "any"


@dataclasses.dataclass(frozen=True)
class Part:
    """One published measurement, or one sub-target of a validation target.

    Attributes:
        id: ``"V2.fastest"`` ...; the part of target ``target``.
        target: the validation target it belongs to (``"V1"`` ... ``"V6"``), or None for a
            published measurement no target decides yet.
        side: :data:`FITTED` or :data:`JUDGED`.
        what: the measurement, in words.
        source: where the thesis gives it (table, figure, section).
        paper_keys: the :mod:`thesis.paper` keys of its numbers (empty: a statement
            without a number, quoted in ``what``).
        gaits: published gait names (:func:`thesis.modelcheck.targets.published_gaits`)
            whose runs it reads.
        frequencies: gait frequencies [Hz] of those runs, or :data:`OTHER` / :data:`ANY`.
        note: why the part sits on its side, and whether fitted numbers fix its verdict.
    """

    id: str
    target: str | None
    side: str
    what: str
    source: str
    paper_keys: tuple[str, ...]
    gaits: tuple[str, ...]
    frequencies: tuple[float, ...] | str
    note: str = ""

    def __post_init__(self) -> None:
        if self.side not in SIDES:
            raise ValueError(f"part {self.id!r}: side {self.side!r} not in {SIDES}")
        if isinstance(self.frequencies, str) and self.frequencies not in (OTHER, ANY):
            raise ValueError(f"part {self.id!r}: frequencies {self.frequencies!r}")


_V1_KEYS = ("fig3_4/gait=half_ellipse/speed_compared", "table3_2/forward_speed",
            "sec3.3.3/turning_frequency")
_SPLINE_15 = ("fig3_4/gait=spline/frequency=1.5/speed",)
_SPLINE_FASTEST = ("fig3_4/gait=spline/max_speed", "fig3_4/gait=spline/max_speed_frequency")
_FLAT_OPTIMUM = "table4_2_grade0_transfer0"

PARTS: tuple[Part, ...] = (
    Part("V1", "V1", FITTED,
         "Tab. 3.1a's half ellipse at 1.5 Hz walks the thesis's two speeds for it",
         "§3.3.1.3 (comparison speed), §3.3.3 (forward speed, at its gait frequency)",
         _V1_KEYS, ("tab3_1a",), (FIT_FREQUENCY,),
         "the existing knee-spring calibration's only target"),
    Part("V2.1.5Hz", "V2", FITTED,
         "Tab. 3.1b's spline at 1.5 Hz walks its published speed",
         "§3.3.1.3 (Fig. 3.4)", _SPLINE_15, ("tab3_1b",), (FIT_FREQUENCY,)),
    Part("V2.fastest", "V2", JUDGED,
         "Tab. 3.1b's spline at its fastest frequency walks its published top speed",
         "§3.3.1.3 (Fig. 3.4)", _SPLINE_FASTEST, ("tab3_1b",), OTHER),
    Part("V3.fitted", "V3", FITTED,
         "no start falls: Tab. 3.1a and Tab. 3.1b at 1.5 Hz (the thesis reports no fall on "
         "flat ground)",
         "§3.3 (the gaits walk; no fall is reported)", (), ("tab3_1a", "tab3_1b"),
         (FIT_FREQUENCY,),
         "Tab. 3.1b's: the brief of the split. Tab. 3.1a's: a published speed is a walking "
         "speed, and the calibration's agreement rule already counts a run only when no "
         "start fell"),
    Part("V3.judged", "V3", JUDGED,
         "no start falls: every other flat-ground case (Tab. 3.1a and 3.1b at their other "
         "frequencies, Tab. 4.2's flat optimum at every frequency)",
         "§3.3, §4.5-4.6 (no fall on flat ground is reported)", (),
         ("tab3_1a", "tab3_1b", _FLAT_OPTIMUM), OTHER),
    Part("V4a", "V4", JUDGED,
         "the half ellipse's speed is linear in frequency up to 2 Hz",
         "§3.3.1.2 (Fig. 3.4)", ("fig3_4/gait=half_ellipse/linear_up_to_frequency",),
         ("tab3_1a",), ANY,
         "its 1.5 Hz point is V1's fitted speed; the line is decided by the other "
         "frequencies"),
    Part("V4b", "V4", JUDGED,
         "the half ellipse walks a roughly constant share of its theoretical speed",
         "§3.3.1.2 (Fig. 3.4)", ("fig3_4/gait=half_ellipse/linear_up_to_frequency",),
         ("tab3_1a",), ANY, "its 1.5 Hz share is fixed by V1's fitted speed"),
    Part("V4c", "V4", JUDGED,
         "the spline is near its theoretical speed at 1.5-2 Hz",
         "§3.3.1.3 (Fig. 3.4)", ("fig3_4/gait=spline/linear_up_to_frequency",),
         ("tab3_1b",), ANY,
         "its 1.5 Hz share is fixed by V2.1.5Hz's fitted speed; the frequencies above "
         "1.5 Hz decide it"),
    Part("V5.1.5Hz", "V5", FITTED,
         "the spline walks faster than the half ellipse at 1.5 Hz",
         "§3.3.1.3 (\"it performs better than ... our half ellipse approach\")",
         (), ("tab3_1a", "tab3_1b"), (FIT_FREQUENCY,),
         "the order of two fitted-on speeds (V1, V2.1.5Hz): not evidence"),
    Part("V5.other", "V5", JUDGED,
         "the spline walks faster than the half ellipse at the other frequencies",
         "§3.3.1.3 (Fig. 3.4)", (), ("tab3_1a", "tab3_1b"), OTHER,
         "targets.decide decides V5 at 1.5 Hz only: this part is declared for the "
         "validation, not yet decided"),
    Part("V6", "V6", JUDGED,
         "each scapula stays within 2 deg of its command (0) while trotting",
         "§3.3.1.1 (\"the plane in which the legs move does not change\")", (),
         ("tab3_1a", "tab3_1b", _FLAT_OPTIMUM), ANY),
    Part("V7", "V7", JUDGED,
         "Tab. 4.4's pebble optima walk their published speeds on the simulated pebble field",
         "§4.6.3 (Tab. 4.4)", ("table4_4/terrain=pebbly/transfer=0/rank=1/speed",
                               "table4_4/terrain=pebbly/transfer=1/rank=1/speed",
                               "table4_4/terrain=pebbly/transfer=1/rank=2/speed"),
         ("table4_4_terrainpebbly_transfer0_rank1", "table4_4_terrainpebbly_transfer1_rank1",
          "table4_4_terrainpebbly_transfer1_rank2"), ANY,
         "the pebble field is chapter 4's (ch4.pebbles), fixed before these runs; no fit "
         "runs on pebbles"),
    Part("tab4_2.speed", None, JUDGED,
         "Tab. 4.2's flat optimum walks its published speed at its own frequency",
         "Tab. 4.2", ("table4_2/grade=0/transfer=0/speed",), (_FLAT_OPTIMUM,), ANY,
         "no validation target compares it yet; declared so that none may fit it"),
)

#: The validation targets the parts split (:data:`thesis.modelcheck.targets.ALL_TARGETS`).
TARGETS = ("V1", "V2", "V3", "V4", "V5", "V6", "V7")


def parts(side: str | None = None, target: str | None = None) -> tuple[Part, ...]:
    """The parts on ``side`` (default both) of ``target`` (default all), in order."""
    return tuple(p for p in PARTS if (side is None or p.side == side)
                 and (target is None or p.target == target))


def paper_keys(side: str) -> frozenset[str]:
    """Every :mod:`thesis.paper` key of the parts on ``side``."""
    return frozenset(k for p in parts(side) for k in p.paper_keys)


def part_of(target: str, gait: str | None = None, frequency: float | None = None,
            sub: str | None = None) -> Part:
    """The one part of ``target`` that a run of ``gait`` at ``frequency`` [Hz] (or the
    sub-target ``sub``, e.g. ``"V4a"``) belongs to; a part of :data:`OTHER` frequencies
    takes every frequency that no other part of the target names for that gait.

    Raises:
        LookupError: when no part, or more than one, matches (the split is broken).
    """
    cands = [p for p in parts(target=target) if (sub is None or p.id == sub)
             and (gait is None or gait in p.gaits)]
    named = {f for p in parts(target=target) if not isinstance(p.frequencies, str)
             and (gait is None or gait in p.gaits) for f in p.frequencies}

    def takes(p: Part) -> bool:
        if frequency is None or p.frequencies == ANY:
            return True
        if p.frequencies == OTHER:
            return not any(math.isclose(frequency, f) for f in named)
        return any(math.isclose(frequency, f) for f in p.frequencies)

    hit = [p for p in cands if takes(p)]
    if len(hit) != 1:
        raise LookupError(f"{target} gait={gait} f={frequency} sub={sub}: "
                          f"{[p.id for p in hit]}")
    return hit[0]


@dataclasses.dataclass(frozen=True)
class Parameter:
    """A value no source gives, which a calibration may fit.

    Attributes:
        name: the model argument (:func:`thesis.physics.models.oncilla.oncilla`) or, where
            the model has none yet, the constant it would replace.
        unit: its unit.
        low, high: bounds of the fit.
        start: the model's value now (the fit's first initial point).
        bounds_from: where the bounds come from (docs/sources.md anchor and reading).
        wired: whether a ``ch*.model`` config key sets it today.
    """

    name: str
    unit: str
    low: float
    high: float
    start: float
    bounds_from: str
    wired: bool = True

    def __post_init__(self) -> None:
        if not self.low <= self.start <= self.high:
            raise ValueError(f"parameter {self.name!r}: start {self.start} outside "
                             f"[{self.low}, {self.high}]")


PARAMETERS: tuple[Parameter, ...] = (
    Parameter("foot_length", "m", 0.060, 0.090, 0.072,
              "docs/sources.md#oncilla-feet: the render's plates, 72 +- 5 mm measured, "
              "62-87 mm over the four feet; the fit's bounds are the render's 60-90 mm"),
    Parameter("foot_width", "m", 0.028, 0.050, 0.038,
              "docs/sources.md#oncilla-feet: 38 +- 5 mm measured but open (per foot "
              "+-8-12 mm, the view grazes across it): the render's bounds 28-50 mm"),
    Parameter("knee_spring", "N m rad-1", 1.0, 10.0, 2.0,
              "docs/sources.md#oncilla-knee-spring: no source gives it; the bounds are the "
              "knee-spring calibration's grid (physics.oncilla_calibration.grid: the "
              "model's own 10, which folds the standing knees 0.05 rad, down to 1)"),
    Parameter("drive_stiffness", "N m rad-1", 10.0, 40.0, 20.0,
              "docs/sources.md#oncilla-drives: no source converts the drivers' raw gains; "
              "the bounds put the 4 N m torque bound at 0.4-0.1 rad of error around the "
              "chosen 0.2 rad (a choice, not a reading). drive_damping follows it at "
              "stiffness / damping = 50 1/s, the time constant kept from the position "
              "servos"),
    Parameter("LEG_OFFSET", "m", 0.026, 0.046, 0.031,
              "docs/sources.md#oncilla-hips and #oncilla-feet: the track, 2 (0.069 m + "
              "offset), read 0.19-0.21 m from the small render and 0.23 m from the large "
              "one; the bounds span both, 0.19-0.23 m", wired=False),
)

#: Values of the plate that are measured, not fitted: the toe's place on the plate
#: follows the plate's length (docs/sources.md#oncilla-feet: the toe 40 mm behind the
#: front edge and 32 mm ahead of the heel, about 4 mm behind the plate's centre).
DERIVED = {"toe_offset": "foot_length / 2 + 0.004 m (the toe 4 mm behind the plate's "
                         "centre, as measured)",
           "drive_damping": "drive_stiffness / 50 s-1"}

#: The fit's procedure, declared before it runs (not run by this module).
PROCEDURE = dict(
    physics="ch4.model as the chapters run it when the fit is made (its dt, sweeps, sweep "
            "order and relaxations), feet='plate'",
    cases=(("tab3_1a", FIT_FREQUENCY), ("tab3_1b", FIT_FREQUENCY)),
    protocol="thesis.modelcheck.validation's: untethered, flat floor, ch4.protocol's settle "
             "and fall height, the 1-s self-transition, the window of "
             "physics.oncilla_validation.seconds",
    starts="physics.oncilla_validation.starts perturbed starts, the validation's start kicks "
           "(stream model/validation/starts of the profile's root_seed), the same kicks at "
           "every point of the fit",
    objective="sum over the two cases of the squared log speed error, (ln(v / v_pub))^2, "
              "v the case's speed (thesis.modelcheck.targets.gait_speed); for Tab. 3.1a "
              "the error is to the nearer of the thesis's two speeds and 0 between them; plus "
              "fall_penalty per fallen start of either case; a case without a speed (fewer "
              "than half its starts up) costs undefined_cost",
    # a fallen start costs as much as a speed off by a factor e^0.5 (1.65x), a case without
    # a speed as much as one off by e^2 (7.4x)
    fall_penalty=0.25,
    undefined_cost=4.0,
    initial_points="the model's current values (Parameter.start) and design_points - 1 "
                   "points of a Latin hypercube over the bounds (stream "
                   "model/calibration/design of root_seed), lengths and widths linear, "
                   "the spring and the stiffness in log",
    design_points=32,
    optimiser="evaluate every initial point; then Nelder-Mead in the unit cube of the "
              "bounds (clipped to it) from the best local_starts of them, each at most "
              "local_evaluations evaluations; the fit is the lowest objective of all "
              "evaluations, ties to the earliest",
    local_starts=3,
    local_evaluations=40,
    report="the fit's values, its objective and each case's speed and falls (the residual), "
           "and for each parameter whether it ended at a bound (within 2 % of the range) or "
           "inside: in the departures and the report",
)
