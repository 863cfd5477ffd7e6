"""Validation target V7 (:mod:`thesis.modelcheck.targets`; §4.6.3, Tab. 4.4): the pebble
optima the thesis published, run on chapter 4's simulated pebble field.

Chapter 4's pebble claims rest on the simulated robot walking the pebbly treadmill the way
the real one did. The flat-ground targets V1-V6 cannot tell: they never put the robot on
pebbles. Here each of Tab. 4.4's three pebbly optima (:func:`thesis.modelcheck.targets.
pebble_gaits`) is evaluated as chapter 4 re-evaluates its best particles
(:func:`thesis.ch4.transfer_runs.evaluate_particles` with the particle entering from its
own gait): from standstill in its own pose, with the safety thread, a random initial
heading (``ch4.reeval.heading_deg``) and a random start along the pebble strip
(:func:`thesis.gaits.conditions.start_range`), ``physics.oncilla_pebbles.starts`` times.
The same gaits with the same headings run on the flat floor beside them, recorded and not
decided: a gait that falls on pebbles but not on flat ground falls because of the pebbles.
The pebble field (``ch4.pebbles``) is chapter 4's, fixed before any of these runs.

A robot whose simulation is not finite stops the check with
:class:`thesis.errors.SimulationDiverged`; nothing is written.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.ch4 import transfer_runs as TR
from thesis.gaits import conditions as C
from thesis.modelcheck import targets as TG
from thesis.modelcheck.validation import _a

#: The floors each gait runs on: the pebble field (decided) and flat ground (beside it).
FLOORS = ("pebbly", "flat")
#: What each run keeps: what chapter 4 keeps of a re-evaluation.
FIELDS = TR.REEVAL_FIELDS


def pebble_starts(ch4: dict, root_seed: int, gaits: int, starts: int) -> tuple[np.ndarray,
                                                                               np.ndarray]:
    """(headings [rad], positions along x [m]), each (gaits, starts): U(-h, h) with h =
    ``ch4.reeval.heading_deg``, and uniform over the pebble strip's start range, from the
    stream ``model/pebbles`` of the root seed."""
    rng = seeding.rng(root_seed, "model/pebbles", 0)
    h = np.deg2rad(float(ch4["reeval"]["heading_deg"]))
    heading = h * rng.uniform(-1.0, 1.0, (gaits, starts))
    lo, hi = C.start_range(ch4, "pebbly", TR.protocol_times(ch4)[2])
    return heading, rng.uniform(lo, hi, (gaits, starts))


def run_floor(ch4: dict, root_seed: int, floor: str, params: np.ndarray, heading: np.ndarray,
              forward: np.ndarray | None, timing: TR.Timing) -> dict:
    """Evaluate each gait of ``params`` (G, 12) from standstill on ``floor`` ("pebbly" or
    "flat") once per start (``heading``, ``forward`` (G, R); ``forward`` None on flat
    ground). Returns {field: (G, R)} of :data:`FIELDS`.

    Raises:
        SimulationDiverged: a robot's simulation was not finite.
    """
    model, state = C.condition_model(ch4, floor, root_seed)
    g, r = heading.shape
    # one evaluation per robot, as chapter 4's generation 0: the step is the evaluation
    return TR.reevaluate(model, state, ch4, params, heading, unit=g * r, timing=timing,
                         forward=forward, step=0,
                         label=lambda row: (f"model/pebbles:{floor}", int(root_seed)))


def pebbles(ctx) -> xr.Dataset:
    """``thesis validate oncilla --only pebbles``: Tab. 4.4's pebble optima on the pebble
    field and on flat ground, and V7 decided on the pebble runs (module docstring)."""
    full = ctx.full_config
    ch4, starts = full["ch4"], int(full["physics"]["oncilla_pebbles"]["starts"])
    gaits = TG.pebble_gaits()
    params = np.array([g.params for g in gaits], np.float64)
    heading, forward = pebble_starts(ch4, ctx.root_seed, len(gaits), starts)
    timing = TR.Timing()
    runs = {f: run_floor(ch4, ctx.root_seed, f, params, heading,
                         forward if f == "pebbly" else None, timing) for f in FLOORS}
    names = [g.name for g in gaits]
    speed = {f: [TG.gait_speed(runs[f]["speed"][i], runs[f]["fallen"][i])
                 for i in range(len(gaits))] for f in FLOORS}
    falls = {f: runs[f]["fallen"].sum(axis=1).astype(int) for f in FLOORS}
    decided = TG.decide_pebbles(dict(zip(names, speed["pebbly"])),
                                dict(zip(names, falls["pebbly"].tolist())), starts)
    v7 = decided[TG.PEBBLE_TARGET]
    ctx.log.info("pebble check: %s", v7["text"])
    published = TG.pebble_speeds()
    D = ("floor", "gait", "start")
    data = {
        "speed": (D, np.stack([runs[f]["speed"] for f in FLOORS]), _a(
            "m s-1", "mean forward trunk speed over the window")),
        "fallen": (D, np.stack([runs[f]["fallen"] for f in FLOORS]).astype(np.int8), _a(
            "1", "1 if the run fell (ch4's criterion)")),
        "score": (D, np.stack([runs[f]["score"] for f in FLOORS]), _a(
            "m s-1", "ch4's score: the window speed, or -2 plus the upright fraction if it "
                     "fell")),
        "taut": (D, np.stack([runs[f]["taut"] for f in FLOORS]), _a(
            "1", "fraction of the window the safety thread was taut")),
        "thread_force": (D, np.stack([runs[f]["thread_force"] for f in FLOORS]), _a(
            "N", "mean estimated thread tension over the window")),
        "heading": (("gait", "start"), heading, _a("rad", "initial heading")),
        "start_x": (("gait", "start"), forward, _a(
            "m", "start along the pebble strip (the flat runs start at the origin)")),
        "case_speed": (("floor", "gait"), np.array([speed[f] for f in FLOORS]), _a(
            "m s-1", "speed of the gait: mean over the starts that stayed up (NaN: fewer "
                     "than half)")),
        "case_falls": (("floor", "gait"), np.array([falls[f] for f in FLOORS]), _a(
            "1", "fallen starts")),
        "published_speed": (("gait",), np.array([published[n] for n in names]), _a(
            "m s-1", "the speed Tab. 4.4 gives for the gait (on the real pebbly treadmill)")),
        "target_passed": (("target",), np.array([int(v7["passed"])], np.int8), _a(
            "1", "1 if the target passed")),
        "target_text": (("target",), np.array([v7["text"]]), _a(
            "1", "the target's numbers beside its bounds",
            renders="target_passed, case_speed, case_falls and the speed bounds")),
    }
    for side in ("low", "high"):
        data[f"speed_{side}"] = (("gait",), np.array([v7["bounds"][f"{n}_{side}"]
                                                      for n in names]), _a(
            "m s-1", f"V7's {side} bound of the gait's speed (published x (1 -/+ 0.25))"))
    ds = xr.Dataset(data, coords=dict(floor=list(FLOORS), gait=names,
                                      start=np.arange(starts), target=[TG.PEBBLE_TARGET]))
    for k, v in timing.variables().items():
        ds[k] = v
    pc = ch4["pebbles"]
    ds.attrs.update(
        title="Validation of the simulated Oncilla on the thesis's pebble optima (V7)",
        thesis_ref="§4.6.3, Tab. 4.4", seeds=[int(ctx.root_seed)],
        dt=float(ch4["model"]["dt"]), solver_iterations=int(ch4["model"]["solver_iterations"]),
        pebble_diameter=float(pc["diameter"]), pebble_coverage=float(pc["coverage"]),
        targets_passed="V7" if v7["passed"] else "", targets_failed="" if v7["passed"] else "V7")
    return ds
