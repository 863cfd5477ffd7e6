"""The three-valued verdict of a convergence table (docs/architecture.md#engine-rules):
does refining the time step or the solver sweeps move the validation quantities by more
than their tolerance (each case's speed: the table's ``speed_tol``, default
:data:`SPEED_TOLERANCE`; each case's fall rate: :data:`CASE_FALL_TOLERANCE`)?

A convergence table runs the same runs (cases x starts, or Tab. 5.1 cells x trials) at a
reference setting and at refined ones. On a gait that sometimes falls, whether a run falls
and how fast a run that stays up walks are draws from the start's perturbation: a change
between settings is only a change of the robot when it exceeds what the draws alone
would give. A verdict that ignores this reads sampling noise as non-convergence (or as
convergence). The rule, fixed before the runs it decides:

* **Speed of a case** at one setting: the mean forward speed of its runs that stayed up,
  when at least :data:`MIN_UP_RUNS` did (else undefined), with its standard error
  ``s / sqrt(n_up)`` (``s`` the runs' sample standard deviation).
* **Relative speed change** of a case: ``r = (v_g - v_0) / v_0`` with the delta-method
  standard error ``sqrt(se_g^2 + (v_g / v_0)^2 se_0^2) / |v_0|``; the two settings are
  treated as independent samples (they share their starts, so where outcomes correlate
  positively the true error is smaller: conservative).
* **Each case's fall-rate change** ``d_c = p_g,c - p_0,c`` (the rule decides per case: a
  pooled rate lets a case that falls 26 points more cancel one that falls 26 points
  less), with Agresti and Caffo's standard error ``sqrt([q_g(1-q_g) + q_0(1-q_0)] /
  (n_c + 2))``, ``q = (falls + 1) / (n_c + 2)`` (one fall and one stand added, so that a
  case with no fall, or only falls, in a handful of runs still carries sampling error);
  independent settings again, conservative. Its tolerance, :data:`CASE_FALL_TOLERANCE`
  (15 points), is what 20-30 runs per case can bound when a case never falls (0 of 20
  at both settings: upper end 12 points; 0 of 30: 9), while a case whose gait goes from
  standing to falling in most runs (0 -> 60 %) reads as beyond it.
* **Fall-rate change over all runs**: ``d = mean over cases (p_g - p_0)`` with equal runs
  per case, standard error ``sqrt(sum_c [q_g(1-q_g) + q_0(1-q_0)] / (n_c + 2)) / C``, and
  its interval against :data:`FALL_TOLERANCE`, recorded, not decided: it is each case's
  that decides (over one case the pooled rate is that case's, at a tighter tolerance no
  20-30 runs can meet).
* **Where gaits fall** the rule decides each case on two quantities: its fall rate (above)
  and its speed over the runs that stayed up (a gait that walks at one setting and falls
  at the other has moved). A case that falls in about half its runs has a fall rate that
  30 runs cannot bound within 15 points: the table stays inconclusive until more starts
  run, and :func:`starts_to_decide` says how many would.
* **Converged**: every case whose speed is defined at both settings has its two-sided
  ``1 - ALPHA`` interval of ``r`` inside ``+- speed_tol`` (:data:`SPEED_TOLERANCE`
  unless the table sets its own), every case's interval of ``d_c`` inside ``+-
  CASE_FALL_TOLERANCE``, and no case has a speed at one setting only. All must hold,
  so no correction for multiplicity is needed (intersection-union test at level
  ``ALPHA``).
* **Not converged**: some quantity's interval at ``1 - ALPHA / k`` (Bonferroni over the
  ``k`` quantities tested: the cases with a speed at both settings and every case's fall
  rate) lies wholly beyond its tolerance.
* **Inconclusive**: anything else. The runs can tell neither; more starts (runs per
  case) narrow every interval (:func:`starts_to_decide`).

A quantity with no sampling error estimate (fewer than two runs) has an infinite
interval: it cannot make a table converged nor not converged.

A table may add a **follow-up stage** (the Puppy II's does): where it is inconclusive, the
cases it left undecided run again on fresh runs, their speeds paired run by run
(:func:`paired_followup`), and :func:`two_stage` gives the verdict.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

#: Largest relative change of a case's speed between the settings, where a table sets no
#: tolerance of its own (the Oncilla's and the Puppy II's set 3 % from their config).
SPEED_TOLERANCE = 0.10
#: Largest change of the fall rate over all runs [fraction] between the settings.
FALL_TOLERANCE = 0.05
#: Largest change of one case's fall rate [fraction] between the settings (module docstring).
CASE_FALL_TOLERANCE = 0.15
#: Error level of each verdict (two-sided intervals).
ALPHA = 0.05
#: Fewest runs that stayed up for a case's speed (and its standard error) to be defined.
MIN_UP_RUNS = 3
#: The verdicts.
CONVERGED, NOT_CONVERGED, INCONCLUSIVE = "converged", "not converged", "inconclusive"


def case_speeds(speed, fell, case, n_cases: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each case's speed over its runs that stayed up, at one setting.

    Args:
        speed: (N,) each run's forward speed [m/s] (NaN where not measured).
        fell: (N,) bool, whether the run fell.
        case: (N,) int, the run's case index in ``range(n_cases)``.

    Returns:
        (mean, se, n_up), each (n_cases,): mean speed [m/s] and its standard error [m/s]
        over the runs that stayed up (NaN when fewer than :data:`MIN_UP_RUNS` did), and
        the number of those runs.
    """
    speed, fell, case = np.asarray(speed, float), np.asarray(fell, bool), np.asarray(case)
    mean, se, n_up = np.full(n_cases, np.nan), np.full(n_cases, np.nan), np.zeros(n_cases, int)
    for c in range(n_cases):
        v = speed[(case == c) & ~fell & np.isfinite(speed)]
        n_up[c] = len(v)
        if len(v) >= MIN_UP_RUNS:
            mean[c] = v.mean()
            se[c] = v.std(ddof=1) / np.sqrt(len(v))
    return mean, se, n_up


def speed_change(mean, se, mean0, se0) -> tuple[np.ndarray, np.ndarray]:
    """(r, se_r): each case's relative speed change against the reference setting and its
    delta-method standard error (module docstring); NaN where either speed is undefined."""
    mean, se, mean0, se0 = (np.asarray(x, float) for x in (mean, se, mean0, se0))
    with np.errstate(invalid="ignore", divide="ignore"):
        r = (mean - mean0) / mean0
        se_r = np.sqrt(se ** 2 + (mean / mean0) ** 2 * se0 ** 2) / np.abs(mean0)
    return r, se_r


def case_fall_changes(fell, fell0, case, n_cases: int) -> tuple[np.ndarray, ...]:
    """Each case's fall rate at a setting and at the reference, their difference and its
    Agresti-Caffo standard error (module docstring).

    Args:
        fell, fell0: (N,) bool, whether each run fell at the setting and at the reference.
        case: (N,) int, the run's case index in ``range(n_cases)``.

    Returns:
        (p, p0, d, se_d, n), each (n_cases,): the two rates, ``d = p - p0``, its standard
        error (inf for a case with fewer than two runs) and the case's runs.
    """
    fell, fell0, case = np.asarray(fell, bool), np.asarray(fell0, bool), np.asarray(case)
    p, p0, var, n = (np.zeros(n_cases) for _ in range(4))
    for c in range(n_cases):
        m = case == c
        n[c] = int(m.sum())
        if n[c] == 0:
            raise ValueError(f"case {c} has no runs")
        x, x0 = int(fell[m].sum()), int(fell0[m].sum())
        p[c], p0[c] = x / n[c], x0 / n[c]
        q, q0 = (x + 1) / (n[c] + 2), (x0 + 1) / (n[c] + 2)
        var[c] = (q * (1 - q) + q0 * (1 - q0)) / (n[c] + 2) if n[c] >= 2 else np.inf
    return p, p0, p - p0, np.sqrt(var), n.astype(int)


def fall_change(fell, fell0, case, n_cases: int) -> tuple[float, float, float, float]:
    """(p, p0, d, se_d): the fall rate over all runs at a setting and at the reference
    (means of the cases' rates), their difference ``d`` and its Agresti-Caffo standard
    error (module docstring). ``fell``, ``fell0``: (N,) bool; ``case``: (N,) int."""
    p, p0, _, se, _ = case_fall_changes(fell, fell0, case, n_cases)
    return (float(p.mean()), float(p0.mean()), float(p.mean() - p0.mean()),
            float(np.sqrt(np.sum(se ** 2)) / n_cases))


def _quantiles(alpha: float, k: int) -> tuple[float, float]:
    """(z, z_k): the normal quantiles of a two-sided ``1 - alpha`` interval and of its
    Bonferroni version over ``k`` quantities."""
    return float(stats.norm.ppf(1 - alpha / 2)), float(stats.norm.ppf(1 - alpha / (2 * k)))


def decide(r, se_r, defined_one_only, d: float, se_d: float, d_case=None, se_case=None, *,
           speed_tol: float = SPEED_TOLERANCE, fall_tol: float = FALL_TOLERANCE,
           case_fall_tol: float = CASE_FALL_TOLERANCE, alpha: float = ALPHA) -> dict:
    """The verdict of one refined setting (module docstring).

    Args:
        r, se_r: (C,) relative speed changes and their standard errors (NaN: undefined).
        defined_one_only: (C,) bool, cases whose speed is defined at one setting only.
        d, se_d: fall-rate change over all runs and its standard error.
        d_case, se_case: (C,) each case's fall-rate change and its standard error. When
            given, they decide the fall rate and ``d`` is recorded only; None: ``d``
            decides (the rule before it decided per case).

    Returns:
        dict: ``verdict`` (one of :data:`CONVERGED`, :data:`NOT_CONVERGED`,
        :data:`INCONCLUSIVE`), ``k`` (quantities tested), ``z`` and ``z_k`` (the normal
        quantiles of the two intervals), ``speed_upper`` (C,) the upper end of each
        |r|'s ``1 - alpha`` interval, ``speed_lower_k`` (C,) the lower end of |r|'s
        ``1 - alpha / k`` interval, ``fall_upper`` and ``fall_lower_k`` the same for |d|,
        ``case_fall_upper`` and ``case_fall_lower_k`` (C,) for each |d_c| (NaN arrays
        when ``d_case`` is None).
    """
    r, se_r = np.asarray(r, float), np.asarray(se_r, float)
    both = np.isfinite(r)
    se_r = np.where(np.isfinite(se_r), se_r, np.inf)
    se_d = float(se_d) if np.isfinite(se_d) else np.inf
    per_case = d_case is not None
    d_case = np.asarray(d_case if per_case else np.full(r.shape, np.nan), float)
    se_case = np.asarray(se_case if per_case else np.full(r.shape, np.nan), float)
    se_case = np.where(np.isfinite(se_case), se_case, np.inf)
    k = int(both.sum()) + (d_case.size if per_case else 1)
    z, z_k = _quantiles(alpha, k)
    with np.errstate(invalid="ignore"):
        speed_upper = np.where(both, np.abs(r) + z * se_r, np.nan)
        speed_lower_k = np.where(both, np.abs(r) - z_k * se_r, np.nan)
        case_upper = np.abs(d_case) + z * se_case
        case_lower_k = np.abs(d_case) - z_k * se_case
    fall_upper, fall_lower_k = abs(d) + z * se_d, abs(d) - z_k * se_d
    if per_case:
        falls_inside = bool(np.all(case_upper <= case_fall_tol + 1e-12))
        falls_beyond = bool(np.any(case_lower_k > case_fall_tol + 1e-12))
    else:
        falls_inside, falls_beyond = fall_upper <= fall_tol + 1e-12, fall_lower_k > fall_tol + 1e-12
    converged = (bool(np.all(speed_upper[both] <= speed_tol)) and falls_inside
                 and not np.any(defined_one_only))
    beyond = bool(np.any(speed_lower_k[both] > speed_tol)) or falls_beyond
    verdict = CONVERGED if converged else NOT_CONVERGED if beyond else INCONCLUSIVE
    return dict(verdict=verdict, k=k, z=z, z_k=z_k, speed_upper=speed_upper,
                speed_lower_k=speed_lower_k, fall_upper=float(fall_upper),
                fall_lower_k=float(fall_lower_k), case_fall_upper=case_upper,
                case_fall_lower_k=case_lower_k)


def starts_to_decide(change, se, runs, tol: float, z: float, z_k: float) -> np.ndarray:
    """Runs per case at which a change's interval would decide, were the change and the
    runs' spread what these runs show: the standard error shrinks as ``1 / sqrt(runs)``,
    so a change inside the tolerance needs ``runs (z se / (tol - |change|))^2`` for its
    ``1 - ALPHA`` interval to fit inside, one beyond it ``runs (z_k se / (|change| -
    tol))^2`` for its Bonferroni interval to clear it. A projection, not a promise: the
    next runs' change is another draw.

    Args:
        change, se: (...) |change| and its standard error (NaN: untested; inf change: a
            speed at one setting only, decided already).
        runs: (...) or scalar, the runs behind each ``se``.
        tol: the quantity's tolerance. z, z_k: the two intervals' normal quantiles.

    Returns:
        (...) float: the projected runs (at least ``runs``; inf at ``|change| == tol``;
        NaN where untested).
    """
    change, se = np.abs(np.asarray(change, float)), np.asarray(se, float)
    runs = np.broadcast_to(np.asarray(runs, float), change.shape)
    with np.errstate(invalid="ignore", divide="ignore"):
        gap = np.abs(tol - change)
        q = np.where(change < tol, z, z_k)
        need = runs * (q * se / gap) ** 2
    need = np.where(gap == 0, np.inf, np.maximum(need, runs))
    need = np.where(np.isinf(change), runs, need)
    return np.where(np.isnan(change) | np.isnan(se), np.nan, need)


def overall(verdicts) -> str:
    """The table's verdict over its refined settings: not converged if any is, converged
    if all are, else inconclusive."""
    v = [str(x) for x in verdicts]
    if NOT_CONVERGED in v:
        return NOT_CONVERGED
    return CONVERGED if v and all(x == CONVERGED for x in v) else INCONCLUSIVE


def compare_runs(speeds, fells, case, n_cases: int, *, speed_tol: float = SPEED_TOLERANCE,
                 fall_tol: float = FALL_TOLERANCE, case_fall_tol: float = CASE_FALL_TOLERANCE,
                 alpha: float = ALPHA) -> dict:
    """Every refined setting against the first, from the runs, each case's speed and fall
    rate decided on its own (module docstring).

    Args:
        speeds: (G, N) each run's forward speed [m/s] at G settings (the same N runs).
        fells: (G, N) bool, whether the run fell.
        case: (N,) int, each run's case.

    Returns:
        dict of arrays: ``case_speed``, ``case_speed_se`` (G, C); ``fall_rate`` (G, C);
        ``total_fall_rate`` (G,); ``speed_change``, ``speed_change_se``,
        ``speed_change_upper``, ``speed_change_lower_k`` (G-1, C) (|r| bounds; ``inf`` in
        ``speed_change`` where a case's speed is defined at one setting only);
        ``case_fall_rate_change``, ``case_fall_rate_change_se``, ``..._upper``,
        ``..._lower_k`` (G-1, C) (each |d_c| and its bounds); ``fall_rate_change``,
        ``fall_rate_change_se``, ``fall_rate_change_upper``, ``fall_rate_change_lower_k``
        (G-1,) (|d| over all runs and its bounds); ``starts_to_decide`` (G-1, C) the runs
        per case at which both its quantities would decide (:func:`starts_to_decide`);
        ``quantities`` (G-1,) ``k``; ``verdict`` (G-1,) str.
    """
    speeds, fells = np.asarray(speeds, float), np.asarray(fells, bool)
    case = np.asarray(case)
    G = speeds.shape[0]
    sp = [case_speeds(speeds[g], fells[g], case, n_cases) for g in range(G)]
    mean = np.array([s[0] for s in sp])
    se = np.array([s[1] for s in sp])
    falls = np.array([[fells[g][case == c].mean() for c in range(n_cases)] for g in range(G)])
    keys = ("speed_change", "speed_change_se", "speed_change_upper", "speed_change_lower_k",
            "case_fall_rate_change", "case_fall_rate_change_se",
            "case_fall_rate_change_upper", "case_fall_rate_change_lower_k",
            "fall_rate_change", "fall_rate_change_se", "fall_rate_change_upper",
            "fall_rate_change_lower_k", "starts_to_decide", "quantities", "verdict")
    out = {k: [] for k in keys}
    for g in range(1, G):
        r, se_r = speed_change(mean[g], se[g], mean[0], se[0])
        one_only = np.isnan(mean[g]) != np.isnan(mean[0])
        _, _, d_c, se_c, runs = case_fall_changes(fells[g], fells[0], case, n_cases)
        _, _, d, se_d = fall_change(fells[g], fells[0], case, n_cases)
        v = decide(r, se_r, one_only, d, se_d, d_c, se_c, speed_tol=speed_tol,
                   fall_tol=fall_tol, case_fall_tol=case_fall_tol, alpha=alpha)
        change = np.where(one_only, np.inf, np.abs(r))
        need = np.fmax(starts_to_decide(change, se_r, runs, speed_tol, v["z"], v["z_k"]),
                       starts_to_decide(d_c, se_c, runs, case_fall_tol, v["z"], v["z_k"]))
        for k, x in (("speed_change", change), ("speed_change_se", se_r),
                     ("speed_change_upper", v["speed_upper"]),
                     ("speed_change_lower_k", v["speed_lower_k"]),
                     ("case_fall_rate_change", np.abs(d_c)), ("case_fall_rate_change_se", se_c),
                     ("case_fall_rate_change_upper", v["case_fall_upper"]),
                     ("case_fall_rate_change_lower_k", v["case_fall_lower_k"]),
                     ("fall_rate_change", abs(d)), ("fall_rate_change_se", se_d),
                     ("fall_rate_change_upper", v["fall_upper"]),
                     ("fall_rate_change_lower_k", v["fall_lower_k"]),
                     ("starts_to_decide", need), ("quantities", v["k"]),
                     ("verdict", v["verdict"])):
            out[k].append(x)
    res = {k: np.asarray(v) for k, v in out.items()}
    res.update(case_speed=mean, case_speed_se=se, fall_rate=falls,
               total_fall_rate=falls.mean(axis=1))
    return res


# ------------------------------------------------------------------ follow-up stage
#: A case's status at one refined setting (:func:`case_status`).
INSIDE, BEYOND, UNDECIDED, MOVED, UNTESTED = "inside", "beyond", "undecided", "moved", "untested"


def case_status(change, upper, lower_k, *, speed_tol: float = SPEED_TOLERANCE) -> np.ndarray:
    """Each case's status at one refined setting, from its |r| and the two interval ends of
    :func:`compare_runs` or :func:`paired_followup` (each (C,)): ``inside`` (the ``1 - ALPHA``
    interval within the tolerance), ``beyond`` (the Bonferroni interval wholly beyond it),
    ``moved`` (a speed at one setting only: ``change`` inf), ``untested`` (no speed at either:
    ``change`` NaN), else ``undecided``."""
    change, upper, lower_k = (np.asarray(x, float) for x in (change, upper, lower_k))
    out = np.full(change.shape, UNDECIDED, dtype=object)
    with np.errstate(invalid="ignore"):
        out[upper <= speed_tol] = INSIDE
        out[lower_k > speed_tol] = BEYOND
    out[np.isinf(change)] = MOVED
    out[np.isnan(change)] = UNTESTED
    return out.astype(str)


def paired_speed_change(speed, speed0, fell, fell0, case, n_cases: int):
    """Each case's relative speed change over the runs that stayed up at *both* settings,
    paired run by run (a follow-up's runs share their start, jitter and noise across the
    settings): ``r = mean(v) / mean(v0) - 1`` with the ratio estimator's standard error
    ``sd(v - (1 + r) v0) / sqrt(n) / |mean(v0)|`` (delta method).

    Args:
        speed, speed0: (N,) each run's speed [m/s] at the refined and the reference setting.
        fell, fell0: (N,) bool. case: (N,) int in ``range(n_cases)``.

    Returns:
        (r, se_r, pairs, one_only), each (n_cases,): NaN where fewer than
        :data:`MIN_UP_RUNS` runs stayed up at both; ``one_only`` where that many stayed up at
        one setting and not at the other.
    """
    speed, speed0 = np.asarray(speed, float), np.asarray(speed0, float)
    up = ~np.asarray(fell, bool) & np.isfinite(speed)
    up0 = ~np.asarray(fell0, bool) & np.isfinite(speed0)
    case = np.asarray(case)
    r, se = np.full(n_cases, np.nan), np.full(n_cases, np.nan)
    pairs, one_only = np.zeros(n_cases, int), np.zeros(n_cases, bool)
    for c in range(n_cases):
        m = case == c
        both = m & up & up0
        pairs[c] = int(both.sum())
        one_only[c] = (int((m & up).sum()) >= MIN_UP_RUNS) != (int((m & up0).sum()) >= MIN_UP_RUNS)
        if pairs[c] < MIN_UP_RUNS:
            continue
        v, v0 = speed[both], speed0[both]
        ratio = v.mean() / v0.mean()
        r[c] = ratio - 1.0
        se[c] = (v - ratio * v0).std(ddof=1) / np.sqrt(pairs[c]) / abs(v0.mean())
    return r, se, pairs, one_only


def paired_followup(speeds, fells, case, n_cases: int, *, speed_tol: float = SPEED_TOLERANCE,
                    alpha: float = ALPHA) -> dict:
    """The follow-up stage: every refined setting against the first on fresh runs of the
    cases a table left undecided, speeds paired (:func:`paired_speed_change`), the same
    tolerance and error level as :func:`decide` (Bonferroni over the cases with a speed at
    both settings). The fall rate is not retested (the table's own decides it).

    Args:
        speeds, fells: (G, N) the fresh runs at the G settings. case: (N,) int.

    Returns:
        dict of (G-1, C) arrays ``speed_change`` (|r|; inf: a speed at one setting only),
        ``speed_change_se``, ``speed_change_upper``, ``speed_change_lower_k``, ``pairs`` and
        ``status`` (:func:`case_status`).
    """
    speeds, fells = np.asarray(speeds, float), np.asarray(fells, bool)
    out = {k: [] for k in ("speed_change", "speed_change_se", "speed_change_upper",
                           "speed_change_lower_k", "pairs", "status")}
    for g in range(1, speeds.shape[0]):
        r, se, pairs, one_only = paired_speed_change(speeds[g], speeds[0], fells[g], fells[0],
                                                     case, n_cases)
        z, z_k = _quantiles(alpha, max(int(np.isfinite(r).sum()), 1))
        change = np.where(one_only, np.inf, np.abs(r))
        upper, lower_k = np.abs(r) + z * se, np.abs(r) - z_k * se
        out["speed_change"].append(change)
        out["speed_change_se"].append(se)
        out["speed_change_upper"].append(upper)
        out["speed_change_lower_k"].append(lower_k)
        out["pairs"].append(pairs)
        out["status"].append(case_status(change, upper, lower_k, speed_tol=speed_tol))
    return {k: np.asarray(v) for k, v in out.items()}


def two_stage(status, fall_upper, fall_lower_k, followed, followup_status,
              case_fall_upper=None, case_fall_lower_k=None, *,
              fall_tol: float = FALL_TOLERANCE,
              case_fall_tol: float = CASE_FALL_TOLERANCE) -> np.ndarray:
    """The verdict of each refined setting after a follow-up stage.

    The first stage is the table (:func:`compare_runs`). When it is inconclusive, the cases
    it left undecided at any refined setting run again on fresh runs (other starts, jitter
    and noise) and :func:`paired_followup` decides them; a followed case takes its follow-up
    status at every setting, every other case keeps the table's. Then, per setting:
    **converged** when every case with a speed is ``inside``, none ``moved``, and the table's
    fall-rate intervals (each case's when given, else the one over all runs) are within
    their tolerance; **not converged** when a case is ``beyond`` or a fall rate's
    Bonferroni interval is; else **inconclusive**. The fall rates are the table's: the
    follow-up does not retest them.

    Error levels: the follow-up's intervals rest on runs the first stage never saw, so each
    keeps its level whatever the first stage selected. A converged verdict still needs every
    case's interval inside (intersection-union, ``ALPHA`` per case). A case reaches
    "beyond" at most through two tests (the table's and the follow-up's, each Bonferroni at
    ``ALPHA``), so a not-converged verdict errs with at most ``2 ALPHA``.

    Args:
        status: (G-1, C) the table's :func:`case_status` per refined setting.
        fall_upper, fall_lower_k: (G-1,) the table's fall-rate interval ends.
        followed: (F,) int, the cases of the follow-up (indices into C).
        followup_status: (G-1, F) their follow-up status.
        case_fall_upper, case_fall_lower_k: (G-1, C) the table's interval ends of each
            case's fall-rate change (None: the fall rate over all runs only).

    Returns:
        (G-1,) str verdicts.
    """
    status = np.array(status, dtype=object)
    followed = np.asarray(followed, int)
    if followed.size:
        status[:, followed] = np.asarray(followup_status, dtype=object)
    if case_fall_upper is None:  # the fall rate over all runs decides
        up = np.asarray(fall_upper, float)[:, None]
        lo, tol = np.asarray(fall_lower_k, float)[:, None], fall_tol
    else:
        up, lo = np.asarray(case_fall_upper, float), np.asarray(case_fall_lower_k, float)
        tol = case_fall_tol
    out = []
    for s, cup, clo in zip(status, up, lo):
        s = [str(x) for x in s]
        if BEYOND in s or np.any(clo > tol + 1e-12):
            out.append(NOT_CONVERGED)
        elif all(x in (INSIDE, UNTESTED) for x in s) and np.all(cup <= tol + 1e-12):
            out.append(CONVERGED)
        else:
            out.append(INCONCLUSIVE)
    return np.asarray(out)
