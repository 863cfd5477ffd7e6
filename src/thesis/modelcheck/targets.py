"""Validation targets of the simulated Oncilla (docs/architecture.md#engine-rules): what
the real robot walked, as published in the thesis, and the rules that decide whether the
model meets it.

Written before any model change is tried, so that no rule is chosen after seeing what the
model does. This is validation-decision code: like :mod:`thesis.claims` it reads the
published numbers from :mod:`thesis.paper` (the published gait parameter vectors it runs
and the speeds it compares with), and :mod:`thesis.modelcheck.validation` runs the gaits
and hands the measurements to :func:`decide`. No chapter's experiment imports it.

Targets (thesis sections in brackets):

* **V1** (§3.3.1.3, §3.3.3): Tab. 3.1a's half ellipse at 1.5 Hz walks within the two
  speeds the thesis gives for it (:func:`published_speeds`), widened by
  :data:`SPEED_TOLERANCE` (25 %): [low x 0.75, high x 1.25].
* **V2** (§3.3.1.3): Tab. 3.1b's spline walks the speeds the thesis gives for it at 1.5 Hz
  and at its fastest frequency (:func:`published_speeds`), each within 25 %.
* **V3** (§3.3, §4.5-4.6: the thesis reports no fall on flat ground): none of the
  published flat-ground gaits (:func:`published_gaits` with ``flat=True``: Tab. 3.1a,
  Tab. 3.1b and Tab. 4.2's flat optimum, at every frequency the instrument runs them)
  falls: at most :data:`MAX_FALLS` fall in all their runs together.
* **V4** (Fig. 3.4, §3.3.1.2-3): (a) the half ellipse's speed is linear in frequency over
  :data:`LINEAR_BAND` (0.5-2 Hz): R^2 of a least-squares line >= :data:`LINEAR_R2`; (b) at
  a roughly constant share of the theoretical speed 2 a f / duty
  (:func:`thesis.gaits.trajectories.theoretical_speed`): "roughly constant" is a spread
  (max - min) / mean of the share over those frequencies of at most
  :data:`SHARE_SPREAD` (0.25); (c) the spline near theory at :data:`NEAR_BAND`
  (1.5-2 Hz): "near" is a share within :data:`NEAR_TOLERANCE` (20 %) of 1 at every
  frequency run there. The stance compression that §3.3.1.2 gives as the reason for (b)
  is measured and recorded beside it, not decided.
* **V5** (§3.3.1.3 "it performs better than ... our half ellipse approach"): the spline
  faster than the half ellipse at 1.5 Hz.
* **V6** (§3.3.1.1 "the plane in which the legs move does not change"; the scapulae are
  commanded 0 in every trot): each scapula within :data:`SCAPULA_TOLERANCE_DEG` (2 deg)
  of its command while trotting: the largest deviation over all legs and all upright
  window samples of every published trot.

* **V7** (§4.6.3, Tab. 4.4; decided by :func:`decide_pebbles` on the runs of
  :mod:`thesis.modelcheck.pebbles`, not by the flat-ground instrument): each pebble optimum
  the thesis published (Tab. 4.4's three pebbly rows, :func:`pebble_gaits`) walks on the
  simulated pebble field of chapter 4 its published speed within :data:`SPEED_TOLERANCE`
  (25 %), re-evaluated from standstill as chapter 4 re-evaluates its best particles. Falls
  are not capped beyond that: §4.6.3 expects "an ill placed pebble" to tip the robot over
  now and then, but a gait whose starts fall more often than they stay up has no speed
  (:func:`gait_speed`) and fails. Every claim that rests on the pebble runs reads it.

A gait's speed at one frequency is the mean over its perturbed starts that stayed up;
fewer than half of them up makes the speed undefined (NaN) and a speed target on it
failed ("fell"). Every decision returns its numbers beside its bounds.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from thesis import paper

#: Relative tolerance of every published speed (V1, V2).
SPEED_TOLERANCE = 0.25
#: Falls allowed over all runs of the published flat-ground gaits (V3).
MAX_FALLS = 1
#: Frequency band [Hz] of Fig. 3.4's linear half-ellipse characteristic (V4a, V4b).
LINEAR_BAND = (0.5, 2.0)
#: Least R^2 of the linear fit of speed on frequency (V4a).
LINEAR_R2 = 0.95
#: Largest (max - min) / mean of the share of the theoretical speed over LINEAR_BAND (V4b).
SHARE_SPREAD = 0.25
#: Frequency band [Hz] where the spline "follows the theoretical prediction" (V4c).
NEAR_BAND = (1.5, 2.0)
#: Largest |share - 1| of the spline's theoretical speed inside NEAR_BAND (V4c).
NEAR_TOLERANCE = 0.20
#: Largest scapula deviation from its command while trotting [deg] (V6).
SCAPULA_TOLERANCE_DEG = 2.0
#: Least fraction of a gait's starts that must stay up for its speed to be defined.
MIN_UPRIGHT_FRACTION = 0.5
#: The targets of the flat-ground instrument (:mod:`thesis.modelcheck.validation`), in order.
TARGETS = ("V1", "V2", "V3", "V4", "V5", "V6")
#: The pebble field's target (:func:`decide_pebbles`, :mod:`thesis.modelcheck.pebbles`).
PEBBLE_TARGET = "V7"
#: Every target, in order.
ALL_TARGETS = TARGETS + (PEBBLE_TARGET,)
#: Frequency [Hz] of V1's speed: the gait of §3.3.3's forward speed, read from the paper
#: (V2's frequencies come with its speeds, :func:`published_speeds`).
V1_FREQUENCY = float(paper.get("sec3.3.3/turning_frequency").value)


@dataclasses.dataclass(frozen=True)
class PublishedGait:
    """One published gait parameter vector.

    Attributes:
        name: id in the datasets (``tab3_1a``, ``tab3_1b``, ``tab4_2_grade0`` ...).
        family: ``"ellipse"`` or ``"spline"`` (keys of
            :data:`thesis.gaits.trajectories.FAMILIES`).
        params: (P,) the vector in the family's order (thesis units: mm, Hz, d.u.).
        source: where it was printed (``"Tab. 3.1a"`` ...).
        flat: True if the thesis ran it on flat ground (the gaits V3 decides on).
    """

    name: str
    family: str
    params: tuple
    source: str
    flat: bool


#: Tab. 3.1a (half ellipse) in :class:`thesis.gaits.trajectories.EllipseGait` order.
ELLIPSE_ORDER = ("x0", "y0_fore", "y0_hind", "a", "b_fore", "b_hind", "duty", "f")
#: Tab. 3.1b / Tab. 4.1-4.4 (spline) in :class:`thesis.gaits.trajectories.SplineGait` order.
SPLINE_ORDER = ("f", "a", "x0", "y0_fore", "y0_hind", "duty", "l0_fore", "l1_fore",
                "l0_hind", "l1_hind", "l2", "l3")
#: Column names of Tab. 4.2-4.4 for each spline parameter (r = rear = hind).
_CH4_COLUMNS = dict(f="f", a="a", x0="x0", y0_fore="y0f", y0_hind="y0r", duty="t_stance",
                    l0_fore="l0f", l1_fore="l1f", l0_hind="l0r", l1_hind="l1r", l2="l2",
                    l3="l3")


def _tab3_1(gait: str, order) -> tuple:
    names = {"duty": "t_stance_f"}
    return tuple(float(paper.get(f"table3_1/gait={gait}/parameter={names.get(n, n)}/value")
                       .value) for n in order)


def _gait_name(prefix: str) -> str:
    """Gait name of a Tab. 4.2-4.4 row's key prefix: ``table4_4/terrain=pebbly/transfer=1/
    rank=2`` -> ``table4_4_terrainpebbly_transfer1_rank2``."""
    table, *coords = prefix.split("/")
    return table + "_" + "_".join(c.replace("=", "") for c in coords)


def _ch4_optima() -> list[PublishedGait]:
    out = []
    for table in ("Tab. 4.2", "Tab. 4.3", "Tab. 4.4"):
        prefixes = sorted({e.key.rsplit("/", 1)[0] for e in paper.table(table)
                           if e.key.endswith("/f")})
        for pre in prefixes:
            p = tuple(float(paper.get(f"{pre}/{_CH4_COLUMNS[n]}").value) for n in SPLINE_ORDER)
            name = _gait_name(pre)
            if any(g.params == p for g in out):
                continue  # Tab. 4.3's and 4.4's flat rows repeat Tab. 4.2's flat optimum
            out.append(PublishedGait(name, "spline", p, table, "grade=0" in pre.split("/")))
    return out


def tab3_1_gaits() -> list[PublishedGait]:
    """Tab. 3.1a (half ellipse) and Tab. 3.1b (spline), read from Tab. 3.1 alone: the gaits
    of the calibration's fitted-on measurements (:mod:`thesis.modelcheck.split`)."""
    return [PublishedGait("tab3_1a", "ellipse", _tab3_1("half_ellipse", ELLIPSE_ORDER),
                          "Tab. 3.1a", True),
            PublishedGait("tab3_1b", "spline", _tab3_1("spline", SPLINE_ORDER),
                          "Tab. 3.1b", True)]


def published_gaits() -> list[PublishedGait]:
    """Every published gait parameter vector of the loci families: Tab. 3.1a (half
    ellipse), Tab. 3.1b (spline) and the optima of Tab. 4.2-4.4 (spline; Tab. 4.3's and
    4.4's flat rows repeat Tab. 4.2's flat optimum and are left out). The
    sine gait was tuned by hand and never published (§3.3.1.1)."""
    return [*tab3_1_gaits(), *_ch4_optima()]


#: The paper keys of V1's two speeds (§3.3.1.3's comparison speed, §3.3.3's forward speed):
#: the calibration's target (:mod:`thesis.modelcheck.calibration`).
V1_PAPER_KEYS = ("fig3_4/gait=half_ellipse/speed_compared", "table3_2/forward_speed")


def v1_speeds() -> tuple[float, float]:
    """(lo, hi) [m/s]: V1's two published speeds of Tab. 3.1a at 1.5 Hz (§3.3.1.3's
    comparison speed and §3.3.3's forward speed), read alone (:data:`V1_PAPER_KEYS`: on the
    fitted side of :mod:`thesis.modelcheck.split`, what the calibration reads)."""
    lo, hi = (paper.get(k).value for k in V1_PAPER_KEYS)
    return float(lo), float(hi)


#: The paper key of Tab. 3.1b's published speed at 1.5 Hz (Fig. 3.4, §3.3.1.3): V2's fitted
#: part (:mod:`thesis.modelcheck.split`), what the model fit reads beside V1's speeds.
V2_FIT_PAPER_KEY = "fig3_4/gait=spline/frequency=1.5/speed"


def v2_fitted_speed() -> float:
    """Tab. 3.1b's published speed at 1.5 Hz [m/s] (:data:`V2_FIT_PAPER_KEY`), read alone:
    the fitted side of :mod:`thesis.modelcheck.split`, unlike its fastest speed."""
    return float(paper.get(V2_FIT_PAPER_KEY).value)


def published_speeds() -> dict:
    """The published speeds the targets compare with [m/s], read from :mod:`thesis.paper`:
    ``v1`` (lo, hi) of Tab. 3.1a at 1.5 Hz (:func:`v1_speeds`), ``v2`` {frequency [Hz]:
    speed} of Tab. 3.1b at 1.5 Hz and at its fastest frequency (§3.3.1.3). The fastest is
    validation only (:mod:`thesis.modelcheck.split`): no calibration calls this."""
    lo, hi = v1_speeds()
    v15 = v2_fitted_speed()
    vmax = paper.get("fig3_4/gait=spline/max_speed").value
    fmax = paper.get("fig3_4/gait=spline/max_speed_frequency").value
    return dict(v1=(lo, hi), v2={1.5: float(v15), float(fmax): float(vmax)})


def speed_bounds(lo: float, hi: float | None = None) -> tuple[float, float]:
    """(low, high) [m/s] accepted for a published speed ``lo`` (or interval lo-hi):
    [lo (1 - SPEED_TOLERANCE), hi (1 + SPEED_TOLERANCE)]."""
    hi = lo if hi is None else hi
    return lo * (1.0 - SPEED_TOLERANCE), hi * (1.0 + SPEED_TOLERANCE)


def gait_speed(speeds, fallen) -> float:
    """A gait's speed at one frequency [m/s]: the mean over the starts that stayed up
    (``speeds``, ``fallen`` (S,)); NaN when fewer than MIN_UPRIGHT_FRACTION stayed up."""
    s = np.asarray(speeds, np.float64)
    up = ~np.asarray(fallen, bool) & np.isfinite(s)
    if up.sum() < MIN_UPRIGHT_FRACTION * len(s) or not up.any():
        return float("nan")
    return float(s[up].mean())


def within(x: float, lo: float, hi: float) -> bool:
    """True where ``x`` is finite and lies in [lo, hi] (a speed within its accepted range;
    also the calibration's "the fit holds")."""
    return bool(np.isfinite(x) and lo <= x <= hi)


def speed_text(speed: dict, key: tuple) -> str:
    """The speed [m/s] of ``key`` = (gait name, frequency [Hz]) in ``speed`` as the
    validation's text writes it: 'not run' where the case is absent, 'fell (no speed)' where
    it is NaN (fewer than half the starts stayed up, :func:`gait_speed`)."""
    if key not in speed:
        return "not run"
    v = float(speed[key])
    return f"{v:.3f} m/s" if math.isfinite(v) else "fell (no speed)"


def _result(passed: bool, measured: dict, bounds: dict, text: str) -> dict:
    return dict(passed=bool(passed), measured=measured, bounds=bounds, text=text)


def linear_r2(x, y) -> float:
    """R^2 of the least-squares line y = c0 + c1 x ((N,) each; NaN below 3 points)."""
    x, y = np.asarray(x, np.float64), np.asarray(y, np.float64)
    if len(x) < 3 or not np.isfinite(y).all():
        return float("nan")
    A = np.column_stack([np.ones_like(x), x])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    tot = ((y - y.mean()) ** 2).sum()
    return float(1.0 - ((y - A @ coef) ** 2).sum() / tot) if tot > 0 else float("nan")


def decide(speed: dict, theory: dict, falls: int, runs: int, scapula_max_deg: float) -> dict:
    """Decide V1-V6 from the instrument's measurements.

    Args:
        speed: {(gait name, frequency [Hz]): speed [m/s]} (:func:`gait_speed`) of at least
            ``tab3_1a`` and ``tab3_1b``.
        theory: {(gait name, frequency): theoretical speed [m/s]} for the same keys.
        falls, runs: falls and runs of the published flat-ground gaits (V3).
        scapula_max_deg: largest scapula deviation from its command while trotting [deg].

    Returns:
        {target: dict(passed (bool), measured (dict of numbers), bounds (dict), text)}.
        A target whose frequencies were not run fails with NaN numbers.
    """
    pub = published_speeds()
    out = {}
    # V1
    lo, hi = speed_bounds(*pub["v1"])
    v = speed.get(("tab3_1a", V1_FREQUENCY), float("nan"))
    out["V1"] = _result(within(v, lo, hi), {f"speed_{V1_FREQUENCY:g}Hz": v},
                        {"low": lo, "high": hi},
                        f"Tab. 3.1a at {V1_FREQUENCY:g} Hz: "
                        f"{speed_text(speed, ('tab3_1a', V1_FREQUENCY))}, accepted "
                        f"{lo:.3f}-{hi:.3f}")
    # V2
    meas, bnd, ok = {}, {}, True
    for f, target in pub["v2"].items():
        lo, hi = speed_bounds(target)
        v = speed.get(("tab3_1b", f), float("nan"))
        meas[f"speed_{f:g}Hz"] = v
        bnd[f"low_{f:g}Hz"], bnd[f"high_{f:g}Hz"] = lo, hi
        ok &= within(v, lo, hi)
    out["V2"] = _result(ok, meas, bnd, "Tab. 3.1b: " + ", ".join(
        f"{speed_text(speed, ('tab3_1b', f))} at {f:g} Hz (accepted {bnd[f'low_{f:g}Hz']:.3f}-"
        f"{bnd[f'high_{f:g}Hz']:.3f})" for f in pub["v2"]))
    # V3
    out["V3"] = _result(falls <= MAX_FALLS, {"falls": int(falls), "runs": int(runs)},
                        {"max_falls": MAX_FALLS},
                        f"{falls} of {runs} runs of the published flat-ground gaits fell "
                        f"(at most {MAX_FALLS} allowed)")
    # V4
    fe = sorted(f for (g, f) in speed if g == "tab3_1a"
                and LINEAR_BAND[0] - 1e-9 <= f <= LINEAR_BAND[1] + 1e-9)
    ve = np.array([speed[("tab3_1a", f)] for f in fe])
    share = ve / np.array([theory[("tab3_1a", f)] for f in fe]) if fe else np.array([])
    r2 = linear_r2(fe, ve)
    spread = (float((share.max() - share.min()) / share.mean())
              if len(share) >= 2 and np.isfinite(share).all() else float("nan"))
    fs = sorted(f for (g, f) in speed if g == "tab3_1b"
                and NEAR_BAND[0] - 1e-9 <= f <= NEAR_BAND[1] + 1e-9)
    near = np.array([speed[("tab3_1b", f)] / theory[("tab3_1b", f)] for f in fs])
    worst = float(np.max(np.abs(near - 1.0))) if len(near) and np.isfinite(near).all() \
        else float("nan")
    a_ok = np.isfinite(r2) and r2 >= LINEAR_R2
    b_ok = np.isfinite(spread) and spread <= SHARE_SPREAD
    c_ok = np.isfinite(worst) and worst <= NEAR_TOLERANCE
    meas = {"ellipse_r2": r2, "ellipse_share_spread": spread,
            "ellipse_share_min": float(share.min()) if len(share) else float("nan"),
            "ellipse_share_max": float(share.max()) if len(share) else float("nan"),
            "spline_worst_share_error": worst, "ellipse_frequencies": len(fe),
            "spline_frequencies": len(fs)}
    out["V4"] = _result(a_ok and b_ok and c_ok, meas,
                        {"min_r2": LINEAR_R2, "max_share_spread": SHARE_SPREAD,
                         "max_share_error": NEAR_TOLERANCE},
                        f"half ellipse over {LINEAR_BAND[0]:g}-{LINEAR_BAND[1]:g} Hz "
                        f"({len(fe)} frequencies): R^2 {r2:.3f} (>= {LINEAR_R2}), share of "
                        f"theory {meas['ellipse_share_min']:.2f}-{meas['ellipse_share_max']:.2f}"
                        f", spread {spread:.2f} (<= {SHARE_SPREAD}); spline at "
                        f"{NEAR_BAND[0]:g}-{NEAR_BAND[1]:g} Hz ({len(fs)} frequencies): "
                        f"share of theory off 1 by up to {worst:.2f} (<= {NEAR_TOLERANCE})")
    # V5
    vs = speed.get(("tab3_1b", 1.5), float("nan"))
    ve15 = speed.get(("tab3_1a", 1.5), float("nan"))
    out["V5"] = _result(bool(np.isfinite(vs) and np.isfinite(ve15) and vs > ve15),
                        {"spline_1.5Hz": vs, "ellipse_1.5Hz": ve15}, {},
                        f"spline {speed_text(speed, ('tab3_1b', 1.5))} vs half ellipse "
                        f"{speed_text(speed, ('tab3_1a', 1.5))} at 1.5 Hz")
    # V6
    m = float(scapula_max_deg)
    out["V6"] = _result(bool(math.isfinite(m) and m <= SCAPULA_TOLERANCE_DEG),
                        {"scapula_max_deviation_deg": m},
                        {"max_deg": SCAPULA_TOLERANCE_DEG},
                        f"largest scapula deviation from its command while trotting "
                        f"{m:.2f} deg (<= {SCAPULA_TOLERANCE_DEG})")
    return out


def pebble_gaits() -> list[PublishedGait]:
    """Tab. 4.4's pebble optima (its three ``terrain=pebbly`` rows: without transfer, and
    the transferred run's best and its best after the first generation), the gaits V7
    runs on the pebble field."""
    return [g for g in _ch4_optima() if g.name.startswith("table4_4_terrainpebbly")]


def pebble_speed_keys() -> dict[str, str]:
    """{gait name (:func:`pebble_gaits`): paper key of the speed Tab. 4.4 gives for it}."""
    keys = {}
    for e in paper.table("Tab. 4.4"):
        if not e.key.endswith("/speed") or "terrain=pebbly" not in e.key:
            continue
        keys[_gait_name(e.key.rsplit("/", 1)[0])] = e.key
    return keys


def pebble_speeds() -> dict[str, float]:
    """{gait name (:func:`pebble_gaits`): the speed [m/s] Tab. 4.4 gives for it} (measured
    on the real pebbly treadmill; validation only, :mod:`thesis.modelcheck.split`)."""
    return {n: float(paper.get(k).value) for n, k in pebble_speed_keys().items()}


def decide_pebbles(speed: dict, falls: dict, runs: int) -> dict:
    """Decide V7 from the pebble field's runs.

    Args:
        speed: {gait name (:func:`pebble_gaits`): speed [m/s]} (:func:`gait_speed` over its
            starts; NaN when fewer than half stayed up).
        falls: {gait name: fallen starts}; a gait absent here was not run (its falls are
            written -1).
        runs: starts per gait.

    Returns:
        {"V7": dict(passed, measured, bounds, text)} as :func:`decide` returns each target;
        a published pebble gait missing from ``speed`` fails with NaN.
    """
    meas, bnd, ok, parts = {}, {}, True, []
    for name, published in pebble_speeds().items():
        lo, hi = speed_bounds(published)
        v = float(speed.get(name, float("nan")))
        meas[f"{name}_speed"] = v
        meas[f"{name}_falls"] = int(falls[name]) if name in falls else -1
        bnd[f"{name}_low"], bnd[f"{name}_high"] = lo, hi
        ok &= within(v, lo, hi)
        txt = (f"{speed_text(speed, name)}, {falls[name]} of {runs} fell" if name in falls
               else "not run")
        parts.append(f"{name.removeprefix('table4_4_terrainpebbly_')}: {txt} "
                     f"(accepted {lo:.3f}-{hi:.3f})")
    return {PEBBLE_TARGET: _result(ok, meas, bnd, "Tab. 4.4's pebble optima on the "
                                   "simulated pebble field: " + "; ".join(parts))}
