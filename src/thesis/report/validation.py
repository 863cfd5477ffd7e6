"""Report tables of the Oncilla model's validation (``results/<profile>/model/validation.nc``
and ``convergence.nc``, :mod:`thesis.modelcheck.validation`): V1-V6 passed or failed with
their numbers, the published gaits on the model, every published optimum's foot path
inside or outside the model's reach, the convergence table in dt and solver sweeps, and the
knee spring's calibration to V1 (``calibration.nc``, :mod:`thesis.modelcheck.calibration`),
the fit of the unsourced values to the split's fitted side (``fit.nc``,
:mod:`thesis.modelcheck.fit`), V7, Tab. 4.4's pebble optima on chapter 4's pebble field
(``pebbles.nc``, :mod:`thesis.modelcheck.pebbles`), and the Puppy II's recordings in dt and
sweeps (``puppy_convergence.nc``, :mod:`thesis.modelcheck.puppy_convergence`).

Every number is read from the datasets; without one a table says "not run".
"""

from __future__ import annotations

import math

import numpy as np

from thesis.report.format import fmt
from thesis.report.model import NOT_RUN, Table

VALIDATION = "model/validation"
CONVERGENCE = "model/convergence"
CALIBRATION = "model/calibration"
FIT = "model/fit"
PEBBLES = "model/pebbles"
PUPPY_CONVERGENCE = "model/puppy_convergence"


def _deg(x) -> str:
    x = float(x)
    return "—" if not np.isfinite(x) else f"{math.degrees(x):.1f}"


#: The stop records of the datasets (thesis.modelcheck.validation.STOPS) and their labels.
STOP_LABELS = (("stance_knee_stop", "knee stop"), ("stance_cable_taut", "cable taut"))


def _stops_cell(d) -> str:
    """The share of stance on each stop, fore / hind pair [%] (mean over the pair's legs
    and the other dimensions of ``d``), or — for a dataset without the record."""
    parts = []
    for var, label in STOP_LABELS:
        if var not in d:
            return "—"
        x = d[var]
        pair = [x.sel(leg=[g for g in x["leg"].values if str(g).endswith(end)]).values
                for end in ("F", "H")]
        vals = [np.nanmean(v) if np.isfinite(v).any() else np.nan for v in pair]
        parts.append(f"{label} {_pct(vals[0])} / {_pct(vals[1])}")
    return "; ".join(parts)


def targets_table(results: dict) -> Table:
    """V1-V6: passed or failed, with the numbers beside the bounds."""
    ds = results.get(VALIDATION)
    if ds is None:
        rows = [[NOT_RUN, NOT_RUN, NOT_RUN]]
        note = ""
    else:
        rows = [[str(t), "passed" if int(p) else "FAILED", str(txt)]
                for t, p, txt in zip(ds["target"].values, ds["target_passed"].values,
                                     ds["target_text"].values)]
        note = (f"{int(ds.sizes['start'])} perturbed starts per case (trunk velocity kick, "
                f"sd {fmt(float(np.std(ds['start_kick'].values)), 2)} m/s measured); "
                f"settle {ds.attrs.get('settle')} s, 1-s self-transition, "
                f"{ds.attrs.get('seconds')} s window; dt "
                f"{fmt(1e3 * float(ds.attrs.get('dt', np.nan)), 3)} ms, "
                f"{ds.attrs.get('solver_iterations')} sweeps; untethered, flat floor. "
                "Targets and their bounds: thesis.modelcheck.targets (written before the "
                "model was run); a speed of nan: fewer than half the starts stayed up.")
    return Table(id="oncilla_validation", title="Validation of the simulated Oncilla "
                 "(targets V1-V6)", thesis_ref="Tab. 3.1, Fig. 3.4, §3.3.1, Tab. 4.2",
                 columns=["target", "verdict", "numbers"], rows=rows, note=note)


def cases_table(results: dict) -> Table:
    """The published gaits on the model: one row per gait and frequency."""
    ds = results.get(VALIDATION)
    cols = ["gait", "f [Hz]", "theory [m/s]", "speed [m/s] (starts)", "share of theory",
            "fallen", "stance compression [mm]", "max |roll| [deg]", "max |pitch| [deg]",
            "max scapula error [deg]", "stance on a stop, fore / hind [%]"]
    if ds is None:
        return Table(id="oncilla_validation_cases", title="Published gaits on the model",
                     thesis_ref="Tab. 3.1, Fig. 3.4", columns=cols,
                     rows=[[NOT_RUN] * len(cols)])
    rows = []
    for c in range(int(ds.sizes["case"])):
        d = ds.isel(case=c)
        sp = d["speed"].values
        rows.append([str(d["case_gait"].values), fmt(float(d["case_frequency"]), 3),
                     fmt(float(d["theoretical_speed"]), 3),
                     f"{fmt(float(d['case_speed']), 3)} ({', '.join(fmt(v, 2) for v in sp)})",
                     fmt(float(d["speed_share"]), 2),
                     f"{int(d['case_falls'])} / {len(sp)}",
                     fmt(1e3 * float(np.nanmean(d["stance_compression"].values))
                         if np.isfinite(d["stance_compression"].values).any() else np.nan, 2),
                     _deg(np.nanmax(d["roll_max"].values)
                          if np.isfinite(d["roll_max"].values).any() else np.nan),
                     _deg(np.nanmax(d["pitch_max"].values)
                          if np.isfinite(d["pitch_max"].values).any() else np.nan),
                     _deg(np.nanmax(d["scapula_max_deviation"].values)
                          if np.isfinite(d["scapula_max_deviation"].values).any() else np.nan),
                     _stops_cell(d)])
    return Table(id="oncilla_validation_cases", title="Published gaits on the model",
                 thesis_ref="Tab. 3.1, Fig. 3.4, Tab. 4.2", columns=cols, rows=rows,
                 note="speed: mean over the starts that stayed up (— when fewer than half "
                      "did), each start's in brackets; stance compression: commanded minus "
                      "simulated hip-to-toe length in stance; angles while up in the window; "
                      "stance on a stop: share of the legs' stance samples with the knee "
                      "motor on its extension stop, and with the cable taut (the leg held "
                      "by the stop rows, not by the knee's spring).")


def reach_table(results: dict) -> Table:
    """Every published optimum's foot path inside or outside the model's reach."""
    ds = results.get(VALIDATION)
    legs = [] if ds is None else [str(x) for x in ds["leg"].values]
    cols = ["gait", "source", "flat ground"] + [f"{leg} outside reach: stance / swing"
                                                for leg in legs]
    if ds is None:
        return Table(id="oncilla_reach", title="Published foot paths and the model's reach",
                     thesis_ref="Fig. 3.3, §3.3.1, Tab. 4.2-4.4", columns=cols + ["—"],
                     rows=[[NOT_RUN] * 4])
    r = ds["reach_outside"]
    rows = [[str(g), str(src), "yes" if int(fl) else "no",
             *[f"{100 * float(st):.0f} % / {100 * float(sw):.0f} %"
               for st, sw in zip(r.sel(published=g, path_part="stance").values,
                                 r.sel(published=g, path_part="swing").values)]]
            for g, src, fl in zip(ds["published"].values, ds["published_source"].values,
                                  ds["published_flat"].values)]
    return Table(id="oncilla_reach", title="Published foot paths and the model's reach",
                 thesis_ref="Fig. 3.3, §3.3.1, Tab. 4.2-4.4", columns=cols, rows=rows,
                 note="share of one cycle's foot targets (100 phases) more than 1 mm from the "
                      "nearest point the leg's joint ranges reach (thesis.gaits.leg.reachable).")


def _pct(x, digits: int = 0) -> str:
    x = float(x)
    return "—" if np.isnan(x) else "inf" if np.isinf(x) else f"{100 * x:.{digits}f}"


def _rule_note(ds, runs: str) -> str:
    """The three-valued rule of a convergence table, with its tolerances and level."""
    a = ds.attrs
    level = f"{100 * (1 - float(a.get('alpha', np.nan))):.0f} %"
    if "case_fall_tolerance" in a:
        falls = (f"every {runs}'s fall-rate change within "
                 f"{_pct(a['case_fall_tolerance'])} points (the change over all runs is "
                 f"shown against {_pct(a.get('fall_tolerance', np.nan))} points, not decided)")
    else:
        falls = (f"the fall-rate change over all runs within "
                 f"{_pct(a.get('fall_tolerance', np.nan))} points")
    return (f"Converged when every {runs}'s speed change has its {level} interval within "
            f"{_pct(a.get('speed_tolerance', np.nan))} % and {falls} (and no {runs} walks at "
            "one setting and falls at the other); not converged when one quantity's "
            "Bonferroni interval lies wholly beyond its tolerance; otherwise inconclusive, "
            f"with the starts per {runs} that would decide it (thesis.modelcheck."
            "convergence_rule). Intervals over the runs' sampling spread; "
            f"a speed needs {a.get('min_up_runs', '?')} runs that stayed up.")


def _case_name(r, i: int) -> str:
    c = r.isel(case=i)
    name = str(c["case_gait"].values) if "case_gait" in c.coords else str(i)
    if "case_frequency" in c.coords:
        name += f" at {fmt(float(c['case_frequency']), 3)} Hz"
    if "case_terrain" in c.coords:
        name += f" on {c['case_terrain'].values}"
    return name


def _verdict_cells(r, tol: float) -> list[str]:
    """A refined setting's speed evidence, its fall-rate change with the interval ends,
    and its verdict: the cases whose speed moved beyond the tolerance (Bonferroni lower
    end above it), else the case with the widest interval (the one that keeps the table
    from converging)."""
    ch = np.asarray(r["speed_change"].values, float)
    up = np.asarray(r["speed_change_upper"].values, float)
    lo = np.asarray(r["speed_change_lower_k"].values, float)
    beyond = [i for i in np.argsort(-np.nan_to_num(lo, nan=-np.inf)) if lo[i] > tol]
    if beyond:
        speed = "; ".join(f"{_case_name(r, i)}: {_pct(ch[i])} % (>= {_pct(lo[i])} %)"
                          for i in beyond)
    elif np.isfinite(up).any():
        i = int(np.nanargmax(up))
        speed = f"none beyond; widest: {_case_name(r, i)}, {_pct(ch[i])} % (<= {_pct(up[i])} %)"
    else:
        speed = "—"
    moved = int(np.isinf(ch).sum())
    if moved:
        speed += f"; {moved} case(s) up at one setting only"
    pooled = (f"{_pct(r['fall_rate_change'], 1)} (<= {_pct(r['fall_rate_change_upper'], 1)}, "
              f">= {_pct(r['fall_rate_change_lower_k'], 1)})")
    verdict = str(r["verdict"].values)
    if "case_fall_rate_change" not in r:
        return [speed, pooled, verdict]
    cf = np.asarray(r["case_fall_rate_change"].values, float)
    cup = np.asarray(r["case_fall_rate_change_upper"].values, float)
    clo = np.asarray(r["case_fall_rate_change_lower_k"].values, float)
    ctol = float(r.attrs.get("case_fall_tolerance", np.inf))
    far = [i for i in np.argsort(-clo) if clo[i] > ctol]
    if far:
        fall = "; ".join(f"{_case_name(r, i)}: {_pct(cf[i], 1)} (>= {_pct(clo[i], 1)})"
                         for i in far)
    else:
        i = int(np.nanargmax(cup))
        fall = (f"none beyond; widest: {_case_name(r, i)}, {_pct(cf[i], 1)} "
                f"(<= {_pct(cup[i], 1)})")
    fall += f"; over all runs {pooled}"
    if verdict == "inconclusive" and "starts_to_decide" in r:
        need = np.asarray(r["starts_to_decide"].values, float)
        need = need[np.isfinite(need)]
        if need.size:
            verdict += f" (about {int(np.ceil(need.max()))} starts per case would decide it)"
    return [speed, fall, verdict]


def convergence_table(results: dict) -> Table:
    """The validation quantities at dt, dt / 2 and dt with twice the sweeps, decided
    three-valued (:mod:`thesis.modelcheck.convergence_rule`)."""
    ds = results.get(CONVERGENCE)
    cols = ["setting", "dt [ms]", "sweeps", "fall rate",
            "speed changes beyond the tolerance (Bonferroni lower end)",
            "fall-rate changes [points] per case beyond the tolerance (interval ends)",
            "verdict", "V1-V6 failed at the setting"]
    if ds is None:
        return Table(id="oncilla_convergence", title="Convergence in the time step and sweeps",
                     thesis_ref="—", columns=cols, rows=[[NOT_RUN] * len(cols)])
    rows = []
    for s in ds["setting"].values:
        d = ds.sel(setting=s)
        row = [str(s), fmt(1e3 * float(d["dt"]), 3), str(int(d["solver_iterations"])),
               f"{_pct(d['total_fall_rate'], 1)} %"]
        row += _verdict_cells(ds.sel(refined=s), float(ds.attrs.get("speed_tolerance", 0.1))) \
            if s in ds["refined"].values \
            else ["(reference)", "(reference)", ""]
        if "target_passed" in d:
            failed = [str(t) for t, p in zip(d["target"].values, d["target_passed"].values)
                      if not int(p)]
            row.append(", ".join(failed) or "none")
        else:
            row.append("—")
        rows.append(row)
    return Table(id="oncilla_convergence", title="Convergence of the validation in the time "
                 "step and the solver sweeps", thesis_ref="Tab. 3.1, Fig. 3.4, Tab. 4.2",
                 columns=cols, rows=rows,
                 note=f"{ds.attrs.get('starts', '?')} perturbed starts per case, the same at "
                      f"every setting. Overall: {ds.attrs.get('verdict', '?')}. "
                      + _rule_note(ds, "case")
                      + (f" V1-V6 at each setting on the first {ds.attrs['target_starts']} "
                         "starts, the validation's own (thesis.modelcheck.targets)."
                         if "target_starts" in ds.attrs else ""))


def convergence_cases_table(results: dict) -> Table:
    """Per case: speed and fall rate at each setting of the convergence table."""
    ds = results.get(CONVERGENCE)
    settings = [] if ds is None else [str(s) for s in ds["setting"].values]
    cols = ["gait", "f [Hz]"] + [f"speed [m/s] at {s}" for s in settings] \
        + [f"fallen at {s}" for s in settings] + [f"max scapula error [deg] at {s}"
                                                   for s in settings] \
        + [f"stance on a stop, fore / hind [%] at {s}" for s in settings]
    if ds is None:
        return Table(id="oncilla_convergence_cases", title="Convergence per case",
                     thesis_ref="—", columns=["—"], rows=[[NOT_RUN]])
    rows = []
    for c in range(int(ds.sizes["case"])):
        d = ds.isel(case=c)
        rows.append([str(d["case_gait"].values), fmt(float(d["case_frequency"]), 3),
                     *[fmt(float(v), 3) for v in d["case_speed"].values],
                     *[f"{100 * float(v):.0f} %" for v in d["fall_rate"].values],
                     *[_deg(v) for v in d["scapula_max_deviation"].values],
                     *[_stops_cell(d.sel(setting=s)) for s in d["setting"].values]])
    return Table(id="oncilla_convergence_cases", title="Convergence of the validation per "
                 "gait and frequency", thesis_ref="Tab. 3.1, Fig. 3.4, Tab. 4.2",
                 columns=cols, rows=rows,
                 note="speed: mean over the starts that stayed up (nan: fewer than "
                      f"{ds.attrs.get('min_up_runs', '?')} did); the same perturbed starts "
                      "at every setting; stance on a stop: as in the published gaits' table, "
                      "mean over the starts.")


def calibration_table(results: dict) -> Table:
    """The fitted knee spring: the grid, the refinement runs in each bracket, the fit, its
    residual, whether it holds and the value the chapters run (every fitted value is shown
    with its fit and residual, docs/architecture.md#engine-rules)."""
    ds = results.get(CALIBRATION)
    cols = ["knee spring [N m/rad]", "speed [m/s] (starts)", "fallen",
            "stance compression [mm]", "role"]
    title = "Calibration: the knee spring fitted to V1 alone"
    ref = "Tab. 3.1a, §3.3.1.2-3, §3.3.3"
    if ds is None:
        return Table(id="oncilla_calibration", title=title, thesis_ref=ref, columns=cols,
                     rows=[[NOT_RUN] * len(cols)])

    def speeds(gait, sp):
        return f"{fmt(float(gait), 3)} ({', '.join(fmt(v, 3) for v in sp)})"

    rows = []
    for k in ds["knee_spring"].values:
        d = ds.sel(knee_spring=k)
        sp = d["grid_speed"].values
        comp = d["grid_compression"].values
        rows.append([fmt(float(k), 3), speeds(d["grid_gait_speed"], sp),
                     f"{int(d['grid_fallen'].sum())} / {len(sp)}",
                     fmt(1e3 * float(np.nanmean(comp)) if np.isfinite(comp).any() else np.nan, 3),
                     "grid"])
    for i in range(ds.sizes.get("refinement", 0)):
        d = ds.isel(refinement=i)
        b = int(d["refinement_bracket"])
        sp = d["refinement_speed"].values
        role = (f"refinement of {fmt(float(ds['bracket_stiff'][b]), 3)}-"
                f"{fmt(float(ds['bracket_soft'][b]), 3)}")
        rows.append([fmt(float(d["refinement_knee_spring"]), 4),
                     speeds(d["refinement_gait_speed"], sp),
                     f"{int(d['refinement_fallen'].sum())} / {len(sp)}", "—", role])
    fit = float(ds["fitted_knee_spring"])
    holds = bool(int(ds["fit_holds"]))
    rows.append([fmt(fit, 4), speeds(ds["residual_speed"], ds["residual_start_speed"].values),
                 "—", "—", "fit" + ("" if int(ds["fit_inside_grid"]) else
                                    " (no bracket: the nearest grid point)")])
    conf = float(ds["configured_knee_spring"])
    band = f"{fmt(float(ds['target_low']), 3)}-{fmt(float(ds['target_high']), 3)}"
    agree = ""
    if "agreement_width" in ds:
        n_ok = int(ds["grid_starts_agree"].sum()) + int(ds["refinement_starts_agree"].sum())
        n_all = ds.sizes["knee_spring"] + ds.sizes.get("refinement", 0)
        agree = (f" (none fell and their speeds spread by at most "
                 f"{fmt(float(ds['agreement_width']), 3)} m/s, the thesis's two speeds; "
                 f"{n_ok} of {n_all} runs" + ("" if int(ds["fit_starts_agree"]) else
                                            "; none agrees, so the nearest run is shown")
                 + ")")
    contact = ds.attrs.get("contact_relaxation", "none")
    contacts = "" if contact == "none" else f", the contact rows at {contact}"
    note = (f"target {fmt(float(ds['target_speed']), 3)} m/s (V1's midpoint), Tab. 3.1a at "
            f"{ds.attrs.get('frequency')} Hz, {int(ds.sizes['start'])} perturbed starts, "
            f"dt {fmt(1e3 * float(ds.attrs.get('dt', np.nan)), 3)} ms, "
            f"{ds.attrs.get('solver_iterations')} sweeps ({ds.attrs.get('sweep_order')}, "
            f"relaxation {ds.attrs.get('relaxation')}{contacts}). "
            f"{ds.sizes.get('bracket', 0)} "
            f"bracket(s), each refined by regula falsi in log k unless one of its ends already "
            f"lies within the thesis's speeds with its starts agreeing; the fit is the run "
            f"nearest the target among those whose starts agree{agree}: "
            f"{fmt(fit, 4)} N m/rad, residual {fmt(float(ds['residual']), 3)} m/s; "
            + ("it holds (within" if holds else "it does NOT hold (outside")
            + f" the thesis's {band} m/s). "
            + f"The chapters run {fmt(conf, 4)} N m/rad (ch4.model.knee_spring): "
            + ("the fit." if int(ds["configured_matches_fit"]) else
               "NOT the fit: the configured spring differs from what the procedure gives "
               "on this profile's model.")
            + " V1's speed is a calibration target, not a validation: claims whose thesis "
              "number it is are marked.")
    return Table(id="oncilla_calibration", title=title, thesis_ref=ref, columns=cols,
                 rows=rows, note=note)


def fit_table(results: dict) -> Table:
    """The fit of the Oncilla's unsourced values (foot plates, knee spring, drives) to the
    fitted side of the split (Tab. 3.1a and 3.1b at 1.5 Hz): per parameter its bounds,
    start, fit, whether it ended at a bound and whether the chapters run it; the note gives
    the objective, each case's speed and falls at the fit and the published speeds."""
    ds = results.get(FIT)
    cols = ["parameter", "unit", "bounds", "start", "fit", "at a bound", "the chapters run"]
    title = "Fit: the Oncilla's unsourced values fitted to the split's fitted side"
    ref = "Tab. 3.1a, Tab. 3.1b, §3.3.1.2-3, §3.3.3"
    if ds is None:
        return Table(id="oncilla_fit", title=title, thesis_ref=ref, columns=cols,
                     rows=[[NOT_RUN] * len(cols)])
    side = {-1: "low", 1: "high", 0: "inside"}
    rows = []
    for i, name in enumerate(ds["parameter"].values):
        held = bool(int(ds["held"][i]))
        conf = ("—" if "configured" not in ds else fmt(float(ds["configured"][i]), 4)
                + ("" if int(ds["configured_matches_fit"][i]) else " (not the fit)"))
        rows.append([str(name), str(ds["parameter_unit"].values[i]),
                     f"{fmt(float(ds['parameter_low'][i]), 3)}-"
                     f"{fmt(float(ds['parameter_high'][i]), 3)}",
                     fmt(float(ds["parameter_start"][i]), 4),
                     fmt(float(ds["fit_value"][i]), 4) + (" (held)" if held else ""),
                     "—" if held else side[int(ds["fit_at_bound"][i])], conf])
    cases = "; ".join(
        f"{c}: {fmt(float(ds['fit_case_speed'][j]), 3)} m/s against "
        f"{fmt(float(ds['case_target_low'][j]), 3)}"
        + ("" if float(ds["case_target_high"][j]) == float(ds["case_target_low"][j]) else
           f"-{fmt(float(ds['case_target_high'][j]), 3)}")
        + f", {int(ds['fit_case_falls'][j])} of {ds.sizes['start']} starts fell"
        for j, c in enumerate(ds["case"].values))
    model = (f"dt {fmt(1e3 * float(ds.attrs['dt']), 4)} ms, {ds.attrs.get('solver_iterations')} "
             f"sweeps ({ds.attrs.get('sweep_order')})" if "dt" in ds.attrs else "the model")
    feet = ds.attrs.get("configured_feet")
    note = (f"Objective {fmt(float(ds['fit_objective']), 3)} (sum of squared log speed errors "
            f"+ {ds.attrs.get('fall_penalty')} per fallen start) at evaluation "
            f"{int(ds['fit_evaluation']) + 1} of {ds.sizes['evaluation']} "
            f"({ds.attrs.get('design_points')} initial points, then Nelder-Mead from the best "
            f"{ds.attrs.get('local_starts')}, at most {ds.attrs.get('local_evaluations')} "
            f"evaluations each); {cases}. {model}, foot plates, "
            f"{ds.attrs.get('starts')} perturbed starts per case. "
            f"{ds.attrs.get('held_reason', '')}. These speeds are calibration targets, not "
            "validation: claims whose thesis number they are are marked."
            + ("" if feet in (None, "plate") else
               f" The chapters run feet '{feet}', not the fitted plates."))
    return Table(id="oncilla_fit", title=title, thesis_ref=ref, columns=cols, rows=rows,
                 note=note)


def puppy_convergence_table(results: dict) -> Table:
    """The Puppy II's recordings at dt, dt / 2 and twice the sweeps, per Tab. 5.1 cell and
    frequency."""
    ds = results.get(PUPPY_CONVERGENCE)
    title = "Convergence of the Puppy II's recordings in the time step and the solver sweeps"
    ref = "§5.3.1, Tab. 5.1"
    settings = [] if ds is None else [str(x) for x in ds["setting"].values]
    cols = ["gait", "terrain", "f [Hz]"] + [f"speed [m/s] at {x}" for x in settings] \
        + [f"turned over at {x}" for x in settings] \
        + [f"speed change [%] at {x} (upper end)" for x in settings[1:]] \
        + [f"paw-force fluctuation change at {x}" for x in settings[1:]] \
        + [f"follow-up: paired speed change [%] at {x} (upper end)" for x in settings[1:]]
    if ds is None:
        return Table(id="puppy_convergence", title=title, thesis_ref=ref, columns=["—"],
                     rows=[[NOT_RUN]])
    followed = ({int(c): i for i, c in enumerate(ds["followed_case"].values)}
                if "followed_case" in ds else {})

    def change(v, u):
        return (f"{_pct(v)} (<= {_pct(u)})" if np.isfinite(float(v)) else
                "moved (up at one setting only)" if np.isinf(float(v)) else "—")

    rows = []
    for c in range(int(ds.sizes["case"])):
        d = ds.isel(case=c)
        freq = fmt(float(d["case_frequency"]), 3) if "case_frequency" in d.coords else "—"
        if c in followed:
            f = ds.isel(followed=followed[c])
            fu = [f"{change(v, u)}, {int(n)} pairs" for v, u, n in zip(
                f["followup_speed_change"].values, f["followup_speed_change_upper"].values,
                f["followup_pairs"].values)]
        else:
            fu = ["—"] * (len(settings) - 1)
        rows.append([str(d["case_gait"].values), str(d["case_terrain"].values), freq,
                     *[fmt(float(v), 3) for v in d["case_speed"].values],
                     *[f"{100 * float(v):.0f} %" for v in d["fall_rate"].values],
                     *[change(v, u) for v, u in zip(d["speed_change"].values,
                                                    d["speed_change_upper"].values)],
                     *[f"{100 * float(v):.1f} %" for v in d["touch_change"].values], *fu])
    tol = float(ds.attrs.get("speed_tolerance", 0.1))
    verdicts = "; ".join(
        f"{r}: {ds['verdict'].sel(refined=r).values} (speeds moved beyond the tolerance "
        f"(Bonferroni lower end): {_verdict_cells(ds.sel(refined=r), tol)[0]}; fall rate "
        f"{_pct(ds['fall_rate_change'].sel(refined=r), 1)} points, "
        f"<= {_pct(ds['fall_rate_change_upper'].sel(refined=r), 1)})"
        for r in ds["refined"].values)
    stage1 = ("stage1_verdict" in ds and ", ".join(
        f"{r}: {ds['stage1_verdict'].sel(refined=r).values}" for r in ds["refined"].values))
    followup = (f" Follow-up stage (the table alone: {stage1}): the {len(followed)} cells it "
                f"left undecided ran again, {ds.attrs.get('followup_trials')} fresh trials "
                "each, speeds paired trial by trial; a followed cell is decided by its "
                "follow-up (last columns)." if followed else
                f" No follow-up stage (the table alone: {stage1})." if stage1 else "")
    return Table(id="puppy_convergence", title=title, thesis_ref=ref, columns=cols, rows=rows,
                 note=f"Overall: {ds.attrs.get('verdict', '?')}; {verdicts}.{followup} Each case's "
                      f"trials ({ds.attrs.get('trials_per_cell')} per cell and frequency, "
                      f"{ds.attrs.get('samples')} samples at 50 Hz) from the same starts, "
                      "jitter and noise at every setting; speed over the ground from the "
                      "camera, over the trials that did not turn over. "
                      + _rule_note(ds, "case") + " The paw forces are shown, not decided.")


def pebbles_table(results: dict) -> Table:
    """V7: each of Tab. 4.4's pebble optima on the pebble field and on flat ground."""
    ds = results.get(PEBBLES)
    cols = ["gait (Tab. 4.4)", "published [m/s]", "pebbles: speed [m/s] (fallen)",
            "flat: speed [m/s] (fallen)"]
    if ds is None:
        return Table(id="oncilla_pebbles", title="Tab. 4.4's pebble optima on the simulated "
                     "pebble field (target V7)", thesis_ref="§4.6.3, Tab. 4.4", columns=cols,
                     rows=[[NOT_RUN] * len(cols)])
    n = int(ds.sizes["start"])

    def cell(floor, g) -> str:
        c = ds.sel(floor=floor, gait=g)
        return f"{fmt(float(c['case_speed']), 2)} ({int(c['case_falls'])} of {n})"

    rows = [[str(g).removeprefix("table4_4_terrainpebbly_"),
             fmt(float(ds["published_speed"].sel(gait=g)), 2), cell("pebbly", g),
             cell("flat", g)] for g in ds["gait"].values]
    verdict = "passed" if int(ds["target_passed"].values[0]) else "FAILED"
    return Table(id="oncilla_pebbles", title="Tab. 4.4's pebble optima on the simulated "
                 "pebble field (target V7)", thesis_ref="§4.6.3, Tab. 4.4", columns=cols,
                 rows=rows, note=(
                     f"V7 {verdict}: {ds['target_text'].values[0]}. Each gait re-evaluated "
                     f"from standstill as chapter 4 re-evaluates its best particles, {n} "
                     f"starts per floor at random places on the strip (pebbles "
                     f"{fmt(100 * float(ds.attrs.get('pebble_diameter', np.nan)), 1)} cm, "
                     f"coverage {fmt(float(ds.attrs.get('pebble_coverage', np.nan)), 2)}); "
                     "the flat-ground runs are recorded, not decided. A speed of nan: fewer "
                     "than half the starts stayed up. Claims on the pebble runs carry V7 "
                     "beside their verdict where it failed."))


def tables(results: dict) -> list[Table]:
    """The validation's tables (``results`` keyed like ``"model/validation"``)."""
    return [targets_table(results), pebbles_table(results), cases_table(results),
            reach_table(results),
            convergence_table(results), convergence_cases_table(results),
            calibration_table(results), fit_table(results), puppy_convergence_table(results)]
