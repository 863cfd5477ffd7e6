"""``thesis validate puppy`` (registry ``model/puppy_convergence``): the simulated Puppy
II's recordings at the chapter's time step, at half of it and with twice the solver sweeps
(the convergence table of the Puppy II, docs/architecture.md#engine-rules).

Chapter 5's recordings (:func:`thesis.ch5.recordings.generate`) are made three times
from the same trial table, starts, terrain jitter, gait commands and sensor noise (the
same seeds): at ``ch5.model``'s dt and sweeps, at dt / 2, and at dt with twice the sweeps
(the settings of :data:`thesis.modelcheck.validation.SETTINGS`). Every non-empty cell of
Tab. 5.1 (gait x terrain x frequency) is a case and runs exactly ``trials_per_cell``
replicate trials of ``samples`` samples each (``physics.puppy_convergence``; Tab. 5.1's own
counts, 1-13 per cell, are too few replicates), each trial with its own start, terrain
jitter and noise, the same at every setting.

Measured per trial: its speed over the ground (the distance between the camera's first and
last position over the trial's duration [m/s], the recordings' ``pos_x``, ``pos_y``),
whether it was stopped because the robot turned over (shorter than planned), and the
paw forces' standard deviation over the trial, averaged over the four paws [N] (the touch
signals chapter 5 classifies on; their mean is the robot's weight at any setting, their
fluctuation is what the contact physics shapes). Per case: the speed over the trials that
stayed up, the fall rate and the paw-force fluctuation. The verdict is the Oncilla's
(:func:`thesis.modelcheck.convergence_rule.compare_runs`, a case's trials as its runs):
every case's speed moves by at most ``physics.puppy_convergence.speed_tolerance`` (3 %, the
Oncilla's) and each case's fall rate by at most 15 points against the chapter's own setting,
decided three-valued on intervals over the case's trials (a speed needs 3 trials that stayed
up). A case is one frequency, so a speed's spread is the
trials' own, not the difference between frequencies. The paw forces are recorded beside
it, not decided.

**Follow-up stage** (``physics.puppy_convergence.followup_trials``; fixed before any of its
runs). Twenty trials decide most cells, but on the few whose trials spread widely (a turn on
the soft Styrofoam) the table stays inconclusive. When it does, the cells it left undecided
at either refined setting run again, ``followup_trials`` fresh trials each (stream
``model/puppy_convergence/followup``: other starts, jitter and noise, the same at every
setting), and :func:`thesis.modelcheck.convergence_rule.paired_followup` decides their
speeds, paired trial by trial (a trial keeps its start, jitter, commands and noise across the
settings, so the change is measured within each trial); the table's verdict becomes
:func:`~thesis.modelcheck.convergence_rule.two_stage`'s. The first stage's verdicts stay in
``stage1_verdict``.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from thesis import store
from thesis.modelcheck import convergence_rule as CR
from thesis.modelcheck import validation as V
from thesis.ch5 import gaits as G
from thesis.ch5 import recordings as R
from thesis.ch5 import sensors as S

#: Stream of the convergence's trial table, starts and noise (the same at every setting).
EXPERIMENT = "model/puppy_convergence"


def trial_speeds(recs: R.Recordings, rate: float) -> np.ndarray:
    """(T,) each trial's speed over the ground [m/s]: camera displacement from its first
    to its last sample over the trial's duration (NaN for a one-sample trial)."""
    ix, iy = S.NAMES.index("pos_x"), S.NAMES.index("pos_y")
    out = np.full(len(recs.length), np.nan)
    for i, (o, n) in enumerate(zip(recs.offset, recs.length)):
        if n > 1:
            xy = recs.signals[o:o + n][:, [ix, iy]].astype(np.float64)
            out[i] = float(np.linalg.norm(xy[-1] - xy[0])) / ((n - 1) / rate)
    return out


def touch_fluctuation(recs: R.Recordings) -> np.ndarray:
    """(T,) each trial's paw-force standard deviation over its samples, averaged over the
    four paws [N] (sensor noise included)."""
    cols = [S.NAMES.index(n) for n in S.TOUCH]
    return np.array([float(recs.signals[o:o + n][:, cols].astype(np.float64).std(0).mean())
                     for o, n in zip(recs.offset, recs.length)])


def _cells(recs: R.Recordings):
    """The (gait, terrain, frequency [Hz]) cells present, in Tab. 5.1's order."""
    return list(dict.fromkeys(zip(map(int, recs.gait), map(int, recs.terrain),
                                  map(float, recs.frequency))))


def _case_rows(recs: R.Recordings, cells) -> list[np.ndarray]:
    """Each cell's trial indices in ``recs`` (cells as :func:`_cells` gives them)."""
    return [np.flatnonzero((recs.gait == g) & (recs.terrain == t)
                           & np.isclose(recs.frequency, f)) for g, t, f in cells]


def _case_of(rows, n_trials: int) -> np.ndarray:
    """(n_trials,) each trial's case index from :func:`_case_rows` (-1: none)."""
    case = np.full(n_trials, -1)
    for c, r in enumerate(rows):
        case[r] = c
    return case


def _config(ch5: dict, pc: dict, fdt: float, fsw: int, trials: int | None = None,
            cells=None) -> dict:
    n = int(pc["samples"])
    rec = dict(ch5["recordings"], samples={"default": [n, n]},
               trials_per_frequency=int(pc["trials_per_cell"] if trials is None else trials))
    if cells is not None:
        rec["cells"] = cells
    model = dict(ch5["model"], dt=float(ch5["model"]["dt"]) * fdt,
                 solver_iterations=int(ch5["model"]["solver_iterations"]) * int(fsw))
    return dict(ch5, recordings=rec, model=model)


def _followup(ctx, ch5: dict, pc: dict, cells: list, followed) -> dict:
    """The follow-up stage (module docstring) on the cases ``followed`` (indices into
    ``cells``): fresh trials at every setting, decided by
    :func:`~thesis.modelcheck.convergence_rule.paired_followup`."""
    rate = float(ch5["recordings"]["sample_rate"])
    mine = [cells[i] for i in followed]
    names = [(G.GAITS[g], R.TERRAINS[t], f) for g, t, f in mine]
    speeds, fells, walls, case = [], [], [], None
    for name, fdt, fsw in V.SETTINGS:
        cfg = _config(ch5, pc, fdt, fsw, trials=int(pc["followup_trials"]), cells=names)
        recs, info = R.generate(cfg, ctx.root_seed, experiment=EXPERIMENT + "/followup")
        ctx.log.info("puppy convergence follow-up %s: %d trials of %d cells in %.1f s", name,
                     len(recs.length), len(names), info["wall_seconds"])
        if case is None:
            case = _case_of(_case_rows(recs, mine), len(recs.length))
        speeds.append(trial_speeds(recs, rate))
        fells.append(recs.length < np.asarray(info["planned_length"]))
        walls.append(float(info["wall_seconds"]))
    res = CR.paired_followup(np.asarray(speeds), np.asarray(fells), case, len(names),
                             speed_tol=float(pc["speed_tolerance"]))
    falls = np.array([[f[case == c].mean() for c in range(len(names))] for f in fells])
    return dict(res, fall_rate=falls, walls=np.asarray(walls),
                trials=np.bincount(case, minlength=len(names)))


def _stage1_status(data: dict, speed_tol: float) -> np.ndarray:
    """(G-1, C) each case's status in the table (:func:`convergence_rule.case_status`)."""
    return np.array([CR.case_status(c, u, lo, speed_tol=speed_tol) for c, u, lo in zip(
        data["speed_change"][1], data["speed_change_upper"][1],
        data["speed_change_lower_k"][1])])


def _followup_variables(fu: dict, followed) -> dict:
    """The follow-up's dataset variables (dimension ``followed``)."""
    RF, SF = ("refined", "followed"), ("setting", "followed")
    level = f"{1 - CR.ALPHA:.0%}"
    return {
        "followed_case": (("followed",), np.asarray(followed, int), V._a(
            "1", "case (index) the follow-up ran again")),
        "followup_trials_run": (("followed",), fu["trials"], V._a(
            "1", "fresh trials of the case in the follow-up")),
        "followup_fall_rate": (SF, fu["fall_rate"], V._a(
            "1", "fraction of the follow-up's trials stopped because the robot turned over")),
        "followup_speed_change": (RF, fu["speed_change"], V._a(
            "1", "|relative speed change| over the follow-up's trials up at both settings, "
                 "paired (inf: a speed at one setting only)")),
        "followup_speed_change_se": (RF, fu["speed_change_se"], V._a(
            "1", "standard error of the paired relative speed change (delta method)")),
        "followup_speed_change_upper": (RF, fu["speed_change_upper"], V._a(
            "1", f"upper end of the {level} interval of the paired |speed change|")),
        "followup_speed_change_lower_k": (RF, fu["speed_change_lower_k"], V._a(
            "1", "lower end of the Bonferroni interval of the paired |speed change|")),
        "followup_pairs": (RF, fu["pairs"], V._a(
            "1", "follow-up trials up at both settings (the pairs)")),
        "followup_status": (RF, fu["status"], V._a(
            "1", "the case's follow-up status (thesis.modelcheck.convergence_rule)")),
        "followup_rollout_wall_seconds": (("setting",), fu["walls"], V._a(
            "s", "wall time of the follow-up's recordings", **store.WALL_CLOCK)),
    }


def convergence(ctx) -> xr.Dataset:
    """``model/puppy_convergence``: the module docstring's three settings (§5.3.1's
    recordings, Tab. 5.1's cells and frequencies), and its follow-up stage where the table
    is inconclusive."""
    full = ctx.full_config
    ch5, pc = full["ch5"], full["physics"]["puppy_convergence"]
    rate = float(ch5["recordings"]["sample_rate"])
    speeds, fells, touch, walls, dts, sweeps = [], [], [], [], [], []
    cells, case = None, None
    for name, fdt, fsw in V.SETTINGS:
        cfg = _config(ch5, pc, fdt, fsw)
        recs, info = R.generate(cfg, ctx.root_seed, experiment=EXPERIMENT)
        ctx.log.info("puppy convergence %s: %d trials in %.1f s", name, len(recs.length),
                     info["wall_seconds"])
        planned = np.asarray(info["planned_length"])
        fell = recs.length < planned
        sp, tm = trial_speeds(recs, rate), touch_fluctuation(recs)
        cells = _cells(recs) if cells is None else cells
        rows = _case_rows(recs, cells)
        if case is None:
            case = _case_of(rows, len(recs.length))
        speeds.append(sp)
        fells.append(fell)
        touch.append([float(tm[r].mean()) for r in rows])
        walls.append(float(info["wall_seconds"]))
        dts.append(float(cfg["model"]["dt"]))
        sweeps.append(int(cfg["model"]["solver_iterations"]))
    touch = np.asarray(touch)
    tol = float(pc["speed_tolerance"])
    data, verdicts = V.settings_variables(np.asarray(speeds), np.asarray(fells), case,
                                          len(cells), dts, sweeps, walls, speed_tol=tol)
    stage1 = np.asarray(verdicts)
    status = _stage1_status(data, tol)
    followed = np.flatnonzero((status != CR.INSIDE).any(axis=0))
    ran = (CR.overall(stage1) == CR.INCONCLUSIVE and int(pc["followup_trials"]) > 0
           and followed.size > 0)
    if ran:
        fu = _followup(ctx, ch5, pc, cells, followed)
        verdicts = CR.two_stage(status, data["fall_rate_change_upper"][1],
                                data["fall_rate_change_lower_k"][1], followed, fu["status"],
                                data["case_fall_rate_change_upper"][1],
                                data["case_fall_rate_change_lower_k"][1])
        data.update(_followup_variables(fu, followed))
        change = np.array(data["speed_change"][1], float)
        change[:, followed] = fu["speed_change"]
        data["max_speed_change"] = (data["max_speed_change"][0], V._nanmax_rows(change),
                                    V._a("1", "largest relative speed change, each followed "
                                              "case's from its follow-up (inf: a case whose "
                                              "speed is defined at one setting only)"))
        data["verdict"] = (data["verdict"][0], verdicts, dict(data["verdict"][2], long_name=(
            data["verdict"][2]["long_name"] + "; after the follow-up stage")))
    data["stage1_verdict"] = (("refined",), stage1, V._a(
        "1", "the table's verdict before any follow-up stage"))
    with np.errstate(invalid="ignore", divide="ignore"):
        touch_rel = np.abs(touch[1:] - touch[0]) / np.abs(touch[0])
    data["case_speed"][2]["long_name"] = ("speed over the ground of the case (mean over the "
                                          "trials that stayed up; NaN: fewer than 3)")
    data["fall_rate"][2]["long_name"] = ("fraction of the case's trials stopped because "
                                         "the robot turned over")
    data["touch_std"] = (("setting", "case"), touch, V._a(
        "N", "paw-force standard deviation of the case's trials (mean over paws and "
             "trials)"))
    data["touch_change"] = (("refined", "case"), touch_rel, V._a(
        "1", "|paw-force standard deviation - its value at dt| / its value at dt "
             "(recorded, not decided)"))
    coords = dict(setting=[s[0] for s in V.SETTINGS], refined=[s[0] for s in V.SETTINGS[1:]],
                  case=np.arange(len(cells)),
                  case_gait=("case", [G.GAITS[g] for g, _, _ in cells]),
                  case_terrain=("case", [R.TERRAINS[t] for _, t, _ in cells]),
                  case_frequency=("case", np.array([f for _, _, f in cells])))
    ds = xr.Dataset(data, coords=coords)
    ds["case_gait"].attrs.update(units="1", long_name="gait of the Tab. 5.1 cell")
    ds["case_terrain"].attrs.update(units="1", long_name="terrain of the Tab. 5.1 cell")
    ds["case_frequency"].attrs.update(units="Hz", long_name="gait frequency of the case")
    ds.attrs.update(
        title="Convergence of the simulated Puppy II's recordings in dt and sweeps",
        thesis_ref="§5.3.1, Tab. 5.1 (the recordings of chapter 5)",
        seeds=[int(ctx.root_seed)], samples=int(pc["samples"]),
        trials_per_cell=int(pc["trials_per_cell"]), followup_trials=int(pc["followup_trials"]),
        followup_ran=int(ran), **V.verdict_attrs(verdicts, tol))
    return ds
