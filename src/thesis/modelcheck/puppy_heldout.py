"""``thesis bench puppy-heldout`` (registry ``model/puppy_heldout``): does the terrain in the
simulated Puppy II recordings carry across gaits, as it did on the real robot (§5.3-5.4:
one reservoir classifies the terrains of every gait)? Decided in advance and reported whatever it shows; the terrains are never
re-tuned on its outcome.

**Data.** The chapter's recordings at the profile's settings: the trials of
:func:`thesis.ch5.recordings.generate` run with the pipeline's own random streams
(``ch5/puppy_recordings``), so they are the trials of the pipeline's
``data/synthetic/puppy/<profile>.h5``; or that file itself
(``physics.puppy_heldout.recordings``), accepted only when it was made with the
profile's ch5 recording settings. Only the trials of ``terrains`` (default F, S, L, the
terrains recorded in every gait of Tab. 5.1) enter; the signals are z-scored over those
trials' samples (§5.3.1) and the ``selection`` group's columns (default the four touch
sensors) are classified. Every segment is cut into parts of about ``ch5.protocol.part_target``
samples, each an independent sequence (reservoir state reset), and the score is the
percentage of time steps classified correctly (§5.3.2), as in the chapter.

**Classifier.** The chapter's reservoir pipeline (:mod:`thesis.ch5.methods` ``rc``: PCA,
leaky ESN of ``ch5.methods.nodes`` nodes, least-squares readout) at fixed
hyper-parameters, the CMA-ES start point of ``ch5.search``
(:func:`thesis.ch5.separability.start_params`; no tuning). Seed s draws W_in and W_res
from stream ``model/puppy_heldout/weights/<nodes>`` (thesis.seeding) of the profile's
root seed; ``seeds`` (default 5) draws.

**Test A (held-out gait).** For each gait g with trials on the terrains: train on every
trial of the other gaits, test on every trial of g. Per seed: accuracy, the held-out
set's majority share (the share of its time steps of its most frequent terrain: what
always answering that terrain scores) and the difference in points. Pooled over the
held-out gaits: correct time steps over all test time steps, against the pooled
majority (each fold's majority steps summed over the folds, over all test steps).
Mean over seeds and its two-sided ``confidence`` t interval (n - 1 degrees of freedom).
**The pooled difference decides**: pass when its mean is >= ``min_difference`` (15)
points AND its interval's lower bound is > ``min_lower_bound`` (5) points. Each held-out
gait gets the same rule, reported beside it, not deciding (a gait with few trials, e.g.
the random gait's one per terrain at the smoke profile, gives a coarse majority share).
The seeds vary only the reservoir's draw, not the data: the interval measures how much
the verdict depends on the draw, not on the recordings.

**Diagnostic (not deciding).** On the same split, a linear discriminant
(``sklearn.discriminant_analysis.LinearDiscriminantAnalysis``, default solver) on per-part
features of the same channels (each channel's mean and standard deviation over the part),
each part's prediction counted for its time steps. If it beats the majority share
where the reservoir does not, the method fails; if neither does, the channels carry no
terrain that crosses gaits.

**Test B (within a cell).** For each (gait, frequency) cell with trials of at least two
of the terrains: the first half of each trial's samples (``length // 2``) trains, the
second half tests (a split that exists at one trial per cell). Per seed the accuracy
pooled over the cells (correct test time steps over all); pass when its mean over seeds
is >= ``min_within_cell`` (80 %). Per cell accuracy, majority share and the linear
discriminant's accuracy are reported beside it.

Output: an xarray dataset (dims ``seed``, ``heldout`` (the held-out gaits), ``cell``)
with both verdicts in its attributes and the log.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.ch5 import gaits as G
from thesis.ch5 import methods as M
from thesis.ch5 import protocol as P
from thesis.ch5 import recordings as REC
from thesis.ch5 import sensors as S

__all__ = ["t_interval", "decide", "majority_steps", "lda_correct", "rc_correct",
           "heldout_gait", "within_cell", "puppy_heldout"]

#: The ch5 keys the recordings generator reads (registry READS of ch5/puppy_recordings).
RECORDING_KEYS = ("model", "recordings", "gaits", "terrains", "jitter", "noise", "touch")


def t_interval(values, confidence: float) -> tuple[float, float, float]:
    """(mean, low, high) of ``values`` (n,) with its two-sided Student-t interval at
    ``confidence`` (n - 1 degrees of freedom); low = high = mean when they all agree."""
    from scipy import stats

    v = np.asarray(values, float)
    m = float(v.mean())
    if v.size < 2:
        return m, float("nan"), float("nan")
    half = float(stats.t.ppf(0.5 + confidence / 2.0, v.size - 1) * v.std(ddof=1)
                 / np.sqrt(v.size))
    return m, m - half, m + half


def decide(differences, min_difference: float, min_lower_bound: float,
           confidence: float) -> dict:
    """Test A's rule on the per-seed ``differences`` (n,) [points]: dict of ``mean``,
    ``low``, ``high`` (t interval) and ``passed`` (mean >= ``min_difference`` and
    low > ``min_lower_bound``)."""
    m, lo, hi = t_interval(differences, confidence)
    passed = bool(m >= min_difference and np.isfinite(lo) and lo > min_lower_bound)
    return dict(mean=m, low=lo, high=hi, passed=passed)


def majority_steps(labels: np.ndarray, n_classes: int) -> int:
    """Time steps of the most frequent class among ``labels`` (n_steps,)."""
    return int(np.bincount(np.asarray(labels, int), minlength=n_classes).max())


def _window_features(parts: P.Parts) -> np.ndarray:
    """(P, 2 D) each channel's mean and standard deviation over each part's valid steps."""
    mask = P.valid_mask(parts.length, parts.x.shape[1])[..., None]
    n = parts.length[:, None].astype(float)
    mean = (parts.x * mask).sum(1) / n
    var = (((parts.x - mean[:, None]) * mask) ** 2).sum(1) / n
    return np.concatenate([mean, np.sqrt(var)], axis=1)


def lda_correct(train: P.Parts, test: P.Parts) -> int:
    """Test time steps classified correctly by a linear discriminant fitted on the
    per-part features (:func:`_window_features`) of ``train``; a part's prediction counts
    for each of its steps."""
    from sklearn.discriminant_analysis import LinearDiscriminantAnalysis

    lda = LinearDiscriminantAnalysis().fit(_window_features(train), train.label)
    pred = lda.predict(_window_features(test))
    return int(test.length[pred == test.label].sum())


def rc_correct(params: dict, draw: M.Draw, train: P.Parts, test: P.Parts,
               n_classes: int) -> int:
    """Test time steps classified correctly by the chapter's reservoir pipeline (``rc``,
    :func:`thesis.ch5.methods.fit`) with ``params`` and ``draw``, fitted on ``train``."""
    f = M.fit("rc", params, draw, train, n_classes)
    return int(np.sum(M.predict(f, test) == test.labels()))


def _segments(trials, length, half: str | None = None):
    out = []
    for t in trials:
        L = int(length[t])
        a, b = {None: (0, L), "first": (0, L // 2), "second": (L // 2, L)}[half]
        out.append(P.Segment(int(t), a, b))
    return out


def heldout_gait(signals, offset, length, label, gait, trials, columns, part_target: int,
                 params: dict, draws: list, n_classes: int) -> dict:
    """Test A's counts (module docstring).

    Args:
        signals: (n_samples, n_signals) z-scored, every trial end to end; offset, length,
            label, gait: (n_trials,) per trial (label: class index 0..n_classes-1 of the
            trials used); trials: indices of the trials used; columns: signal columns.
        params, draws: the reservoir's hyper-parameters and one :class:`M.Draw` per seed.
    Returns:
        dict of ``gaits`` (held-out gait indices, ascending), ``n`` (G,) test steps,
        ``majority`` (G,) their majority steps, ``rc`` (seeds, G) and ``lda`` (G,) correct
        steps.
    """
    trials = np.asarray(trials, int)
    gaits = np.unique(gait[trials])
    n, maj, lda = (np.zeros(len(gaits), np.int64) for _ in range(3))
    rc = np.zeros((len(draws), len(gaits)), np.int64)
    for j, g in enumerate(gaits):
        tr = _segments(trials[gait[trials] != g], length)
        te = _segments(trials[gait[trials] == g], length)
        train = P.to_parts(signals, offset, label, tr, columns, part_target)
        test = P.to_parts(signals, offset, label, te, columns, part_target)
        n[j], maj[j], lda[j], rc[:, j] = _fold(train, test, params, draws, n_classes)
    return dict(gaits=gaits, n=n, majority=maj, rc=rc, lda=lda)


def _fold(train, test, params: dict, draws: list, n_classes: int):
    """One split's counts: test time steps, the majority's correct steps, the linear
    discriminant's and (per draw) the reservoir's correct steps."""
    rc = [rc_correct(params, d, train, test, n_classes) for d in draws]
    return (test.n_samples, majority_steps(test.labels(), n_classes),
            lda_correct(train, test), rc)


def _cells(gait, frequency, label, trials) -> list[np.ndarray]:
    """The trial sets of each (gait, frequency) cell among ``trials`` with trials of at
    least two classes, by gait then frequency."""
    out = []
    trials = np.asarray(trials, int)
    for g in np.unique(gait[trials]):
        mine = trials[gait[trials] == g]
        for f in np.unique(np.round(frequency[mine], 6)):
            ids = mine[np.isclose(frequency[mine], f)]
            if len(np.unique(label[ids])) >= 2:
                out.append(ids)
    return out


def within_cell(signals, offset, length, label, gait, frequency, trials, columns,
                part_target: int, params: dict, draws: list, n_classes: int) -> dict:
    """Test B's counts (module docstring); arguments as :func:`heldout_gait` plus
    ``frequency`` (n_trials,) [Hz].

    Returns:
        dict of ``cells`` (list of trial index arrays), ``n`` (C,) test steps,
        ``majority`` (C,), ``rc`` (seeds, C) and ``lda`` (C,) correct steps.
    """
    cells = _cells(gait, frequency, label, trials)
    n, maj, lda = (np.zeros(len(cells), np.int64) for _ in range(3))
    rc = np.zeros((len(draws), len(cells)), np.int64)
    for c, ids in enumerate(cells):
        train = P.to_parts(signals, offset, label, _segments(ids, length, "first"), columns,
                           part_target)
        test = P.to_parts(signals, offset, label, _segments(ids, length, "second"), columns,
                          part_target)
        n[c], maj[c], lda[c], rc[:, c] = _fold(train, test, params, draws, n_classes)
    return dict(cells=cells, n=n, majority=maj, rc=rc, lda=lda)


def _recordings(ctx, ch5: dict, path) -> REC.Recordings:
    """The chapter's recordings: simulated with the pipeline's streams, or read from
    ``path`` after checking that it was made with the profile's recording settings."""
    want = {k: ch5[k] for k in RECORDING_KEYS}
    if path is None:
        recs, info = REC.generate(want, ctx.root_seed, log=ctx.log,
                                  experiment="ch5/puppy_recordings")
        ctx.log.info("puppy heldout: simulated %d trials in %.0f s", recs.n_trials,
                     info["wall_seconds"])
        return recs
    recs = REC.load(path)
    got = json.loads(recs.config_json)
    if json.loads(json.dumps(want, sort_keys=True)) != {k: got.get(k) for k in want}:
        raise ValueError(f"{path}: made with other ch5 recording settings than the "
                         "profile's (physics.puppy_heldout.recordings)")
    return recs


def puppy_heldout(ctx) -> xr.Dataset:
    """``thesis bench puppy-heldout`` (registry ``model/puppy_heldout``; module docstring):
    Test A (held-out gait, reservoir vs the held-out majority share, linear discriminant
    beside it) and Test B (within-cell accuracy) on the chapter's recordings.

    Returns a dataset with dims ``seed``, ``heldout`` (held-out gait) and ``cell``
    (gait x frequency); accuracies and shares in percent, differences in points.
    """
    from threadpoolctl import threadpool_limits

    from thesis.ch5.experiments import _normalised
    from thesis.ch5.separability import start_params

    full = ctx.full_config
    ch5, cfg = full["ch5"], full["physics"]["puppy_heldout"]
    terrains = [str(t) for t in cfg["terrains"]]
    seeds = [int(s) for s in cfg["seeds"]]
    conf = float(cfg["confidence"])
    recs = _recordings(ctx, ch5, cfg["recordings"])
    keep = [REC.TERRAINS.index(t) for t in terrains]
    trials = np.flatnonzero(np.isin(recs.terrain, keep))
    label = np.full(recs.n_trials, -1, int)
    for i, r in enumerate(keep):
        label[recs.terrain == r] = i
    signals = _normalised(recs, trials)
    cols = S.columns(str(cfg["selection"]))
    tgt = int(ch5["protocol"]["part_target"])
    nodes = int(ch5["methods"]["nodes"])
    ranges = {k: tuple(v) for k, v in ch5["search"].items() if k != "sigma0"}
    params = start_params("rc", ranges)
    draws = [M.draw(seeding.rng(ctx.root_seed, f"{ctx.key}/weights/{nodes}", s), nodes,
                    len(S.NAMES)) for s in seeds]
    k = len(terrains)
    ctx.log.info("puppy heldout: %d trials of %s, %s (%d columns), rc %d nodes at %s",
                 len(trials), "".join(terrains), cfg["selection"], len(cols), nodes,
                 {p: round(v, 4) for p, v in params.items()})
    with threadpool_limits(1):
        a = heldout_gait(signals, recs.offset, recs.length, label, recs.gait, trials, cols,
                         tgt, params, draws, k)
        b = within_cell(signals, recs.offset, recs.length, label, recs.gait, recs.frequency,
                        trials, cols, tgt, params, draws, k)

    # Test A
    acc = 100.0 * a["rc"] / a["n"]
    maj = 100.0 * a["majority"] / a["n"]
    diff = acc - maj
    lda = 100.0 * a["lda"] / a["n"]
    pooled_acc = 100.0 * a["rc"].sum(1) / a["n"].sum()
    pooled_maj = 100.0 * a["majority"].sum() / a["n"].sum()
    pooled_lda = 100.0 * a["lda"].sum() / a["n"].sum()
    rule = (float(cfg["min_difference"]), float(cfg["min_lower_bound"]), conf)
    per_gait = [decide(diff[:, j], *rule) for j in range(len(a["gaits"]))]
    pooled = decide(pooled_acc - pooled_maj, *rule)
    # Test B
    cell_acc = 100.0 * b["rc"] / b["n"]
    within = 100.0 * b["rc"].sum(1) / b["n"].sum()
    w_mean, w_lo, w_hi = t_interval(within, conf)
    b_pass = bool(w_mean >= float(cfg["min_within_cell"]))

    gait_names = [G.GAITS[int(g)] for g in a["gaits"]]
    cell_names = [f"{G.GAITS[int(recs.gait[ids[0]])]} {float(recs.frequency[ids[0]]):g} Hz"
                  for ids in b["cells"]]
    verdict_a = (f"Test A (pooled over held-out gaits, deciding): difference "
                 f"{pooled['mean']:.1f} points [{pooled['low']:.1f}, {pooled['high']:.1f}] "
                 f"-> {'PASS' if pooled['passed'] else 'FAIL'} (rule: mean >= {rule[0]:g} "
                 f"and lower bound > {rule[1]:g})")
    verdict_b = (f"Test B (within cell, pooled): {w_mean:.1f} % [{w_lo:.1f}, {w_hi:.1f}] -> "
                 f"{'PASS' if b_pass else 'FAIL'} (rule: mean >= {cfg['min_within_cell']:g} %)")
    pct = dict(units="%")
    pts = dict(units="points")
    ds = xr.Dataset(
        {
            "accuracy": (("seed", "heldout"), acc, dict(pct, long_name="reservoir's test "
                         "accuracy on the held-out gait's trials")),
            "majority_share": (("heldout",), maj, dict(pct, long_name="held-out set's "
                               "majority share")),
            "difference": (("seed", "heldout"), diff, dict(pts, long_name="accuracy minus "
                           "majority share")),
            "difference_mean": (("heldout",), [d["mean"] for d in per_gait],
                                dict(pts, long_name="mean difference over seeds")),
            "difference_low": (("heldout",), [d["low"] for d in per_gait],
                               dict(pts, long_name=f"lower bound of the {conf:.0%} t interval")),
            "difference_high": (("heldout",), [d["high"] for d in per_gait],
                                dict(pts, long_name=f"upper bound of the {conf:.0%} t interval")),
            "passed": (("heldout",), [d["passed"] for d in per_gait],
                       dict(units="1", long_name="the held-out gait meets Test A's rule "
                            "(reported, not deciding)")),
            "lda_accuracy": (("heldout",), lda, dict(pct, long_name="linear discriminant "
                             "on per-part mean and std, held-out gait (diagnostic)")),
            "test_steps": (("heldout",), a["n"], dict(units="1", long_name="time steps of the "
                           "held-out set")),
            "pooled_accuracy": (("seed",), pooled_acc, dict(pct, long_name="reservoir's accuracy "
                                "pooled over the held-out gaits")),
            "pooled_majority_share": ((), pooled_maj, dict(pct, long_name="each fold's majority "
                                      "steps over all test steps")),
            "pooled_difference_mean": ((), pooled["mean"], dict(pts, long_name="pooled difference, "
                                       "mean over seeds (deciding)")),
            "pooled_difference_low": ((), pooled["low"], dict(pts, long_name="its lower t bound")),
            "pooled_difference_high": ((), pooled["high"],
                                       dict(pts, long_name="its upper t bound")),
            "pooled_passed": ((), pooled["passed"], dict(units="1", long_name="Test A's "
                              "verdict (deciding)")),
            "pooled_lda_accuracy": ((), pooled_lda, dict(pct, long_name="linear discriminant "
                                    "pooled over the held-out gaits (diagnostic)")),
            "cell_accuracy": (("seed", "cell"), cell_acc, dict(pct, long_name="reservoir, "
                              "second half of each trial after training on the first halves")),
            "cell_majority_share": (("cell",), 100.0 * b["majority"] / b["n"],
                                    dict(pct, long_name="majority share of the cell's test "
                                         "halves")),
            "cell_lda_accuracy": (("cell",), 100.0 * b["lda"] / b["n"],
                                  dict(pct, long_name="linear discriminant within the "
                                       "cell (diagnostic)")),
            "cell_trials": (("cell",), [len(ids) for ids in b["cells"]],
                            dict(units="1", long_name="trials in the cell")),
            "within_accuracy": (("seed",), within, dict(pct, long_name="reservoir within "
                                "cells, pooled over cells")),
            "within_passed": ((), b_pass, dict(units="1", long_name="Test B's verdict")),
        },
        coords=dict(seed=seeds, heldout=gait_names, cell=cell_names),
        attrs=dict(title="Puppy II terrains across gaits: held-out-gait and within-cell "
                   "accuracy of the reservoir on the touch channels",
                   thesis_ref="§5.3-5.4 (Tab. 5.1's terrains)",
                   terrains="".join(terrains), selection=str(cfg["selection"]),
                   nodes=nodes, params=json.dumps(params), test_a=verdict_a,
                   test_b=verdict_b, seeds=seeds))
    for j, g in enumerate(gait_names):
        d = per_gait[j]
        ctx.log.info("puppy heldout %s: rc %.1f %% (seeds %s), majority %.1f %%, "
                     "difference %.1f [%.1f, %.1f] points (%s), lda %.1f %%", g,
                     acc[:, j].mean(), np.round(acc[:, j], 1).tolist(), maj[j], d["mean"],
                     d["low"], d["high"], "pass" if d["passed"] else "fail", lda[j])
    ctx.log.info("puppy heldout pooled: rc %.1f %%, majority %.1f %%, lda %.1f %%",
                 pooled_acc.mean(), pooled_maj, pooled_lda)
    ctx.log.info("puppy heldout: %s", verdict_a)
    for c, name in enumerate(cell_names):
        ctx.log.info("puppy heldout cell %s (%d trials): rc %.1f %%, majority %.1f %%, "
                     "lda %.1f %%", name, len(b["cells"][c]), cell_acc[:, c].mean(),
                     100.0 * b["majority"][c] / b["n"][c], 100.0 * b["lda"][c] / b["n"][c])
    ctx.log.info("puppy heldout: %s", verdict_b)
    return ds
