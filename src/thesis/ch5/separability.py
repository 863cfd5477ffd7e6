"""How much terrain the simulated recordings carry: leave-one-trial-out accuracy per cell.

Tab. 5.3-5.6 ask a classifier trained on one or two recordings per terrain to classify
the other trials, mostly of other gaits and frequencies, so a low score there can mean
that the methods fail, that the simulated terrains are too alike, or that the split asks
for generalisation. This experiment (``ch5/separability``; departure
``ch5.separability``) measures the second alone: within each (gait, frequency) cell of
Tab. 5.1 that has trials of at least ``ch5.separability.min_terrains`` terrains, every
trial is classified by the method fitted on all the cell's other trials
(leave-one-trial-out), and the accuracy is the share of the cell's time steps classified
correctly (§5.3.2), beside the cell's majority-class share and chance (1 / the cell's
terrains).

Each method is the pipeline of :mod:`thesis.ch5.methods` without PCA, at fixed
hyper-parameters: the CMA-ES start point of :mod:`thesis.ch5.tuning` (the centre of
``ch5.search``), never tuned here. The expansions (EMA, leaky ELM, leaky ESN, SFA2's
quadratic terms) then fit nothing and are computed once per trial; the readouts are
refitted per fold from per-trial sums (:func:`loto_linear`: the least-squares readout
from the Gram matrices of the other trials; :func:`loto_unsupervised`: SFA from their
moments, then FastICA and the naive-Bayes readout on their slow features). Trials are
cut into parts and every part starts from a zero state, as in the tables; the signals are
z-scored over all trials (§5.3.1).
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.runctx import RunContext
from thesis.ch5 import gaits as G
from thesis.ch5 import methods as M
from thesis.ch5 import protocol as P
from thesis.ch5 import readout
from thesis.ch5 import recordings as REC
from thesis.ch5 import sensors as S
from thesis.ch5 import tuning as T
from thesis.ch5.sfa import sfa_from_moments

__all__ = ["cells", "start_params", "loto_linear", "loto_unsupervised", "separability"]


def cells(recs: REC.Recordings, min_terrains: int) -> list[tuple[str, float, np.ndarray]]:
    """The (gait, frequency [Hz], trial indices) cells of the recordings with trials of at
    least ``min_terrains`` terrains, in Tab. 5.1's gait order then by frequency."""
    out = []
    for gi, gait in enumerate(G.GAITS):
        for f in np.unique(recs.frequency[recs.gait == gi]):
            ids = np.flatnonzero((recs.gait == gi) & np.isclose(recs.frequency, f))
            if len(np.unique(recs.terrain[ids])) >= int(min_terrains):
                out.append((gait, float(f), ids))
    return out


def start_params(method: str, ranges: dict) -> dict[str, float]:
    """The hyper-parameters of ``method`` at the CMA-ES start point (the unit cube's
    centre mapped through ``ranges``, :func:`thesis.ch5.tuning.decode`)."""
    names = M.PARAMS[method]
    return T.decode(np.full(len(names), 0.5), names, ranges)


def loto_linear(feats: list[np.ndarray], labels: np.ndarray,
                n_classes: int) -> list[np.ndarray]:
    """Leave-one-trial-out least-squares readout (eq. 5.1, +-1 targets, bias column).

    Args:
        feats: per trial j, (n_j, F) features of its time steps; labels: (n_trials,)
            terrain of each trial.
    Returns:
        per trial, (n_j,) predicted terrain, from the readout fitted on all other trials:
        the minimum-norm solution of the normal equations of the other trials (their Gram
        matrices summed), which is :func:`thesis.ch5.readout.fit_linear` on their
        stacked features up to rounding.
    """
    grams, cross = [], []
    for f, r in zip(feats, labels):
        xb = np.concatenate([np.asarray(f, np.float64), np.ones((len(f), 1))], axis=1)
        grams.append(xb.T @ xb)
        sx = xb.sum(axis=0)
        b = -np.repeat(sx[:, None], int(n_classes), axis=1)
        b[:, int(r)] = sx
        cross.append(b)
    gram, rhs = sum(grams), sum(cross)
    out = []
    for j, f in enumerate(feats):
        w, *_ = np.linalg.lstsq(gram - grams[j], rhs - cross[j], rcond=None)
        out.append(readout.predict_linear(w, f))
    return out


def _part_diffs(f: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Differences of consecutive steps of flat features ``f`` within each part."""
    d = np.diff(f, axis=0)
    cut = np.cumsum(lengths)[:-1] - 1  # a difference across a part boundary
    keep = np.ones(len(d), bool)
    keep[cut[cut < len(d)]] = False
    return d[keep]


def loto_unsupervised(feats: list[np.ndarray], part_lengths: list[np.ndarray],
                      labels: np.ndarray, n_classes: int, *, n_slow: int, n_bins: int,
                      ica_seed: int, ica_max_iter: int) -> list[np.ndarray]:
    """Leave-one-trial-out SFA -> FastICA -> naive Bayes (§5.2.4, eq. 5.8-5.9).

    Args:
        feats: per trial, (n_j, F) expanded features; part_lengths: per trial, (parts,)
            lengths of its parts in ``feats`` order (derivatives stay within parts);
        labels: (n_trials,) terrain of each trial; the rest as :func:`methods.fit`.
    Returns:
        per trial, (n_j,) predicted terrain from the pipeline fitted on the other trials
        (SFA from their summed moments, FastICA and the histograms on their slow features).
    """
    from sklearn.decomposition import FastICA

    n = np.array([len(f) for f in feats], float)
    s1 = [f.sum(axis=0) for f in feats]
    s2 = [f.T @ f for f in feats]
    diffs = [_part_diffs(f, ln) for f, ln in zip(feats, part_lengths)]
    nd = np.array([len(d) for d in diffs], float)
    d2 = [d.T @ d for d in diffs]
    S1, S2, D2 = sum(s1), sum(s2), sum(d2)
    out = []
    for j, f in enumerate(feats):
        nn = n.sum() - n[j]
        mean = (S1 - s1[j]) / nn
        cov = (S2 - s2[j]) / nn - np.outer(mean, mean)
        sfa = sfa_from_moments(mean, cov, (D2 - d2[j]) / max(nd.sum() - nd[j], 1.0), n_slow)
        others = [k for k in range(len(feats)) if k != j]
        slow = np.concatenate([sfa.transform(feats[k]) for k in others])
        lab = np.concatenate([np.full(len(feats[k]), int(labels[k])) for k in others])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # FastICA convergence warnings: max_iter is ours
            ica = FastICA(n_components=slow.shape[1], whiten="unit-variance",
                          random_state=ica_seed, max_iter=ica_max_iter,
                          fun=M.logcosh_contrast).fit(slow)
        bayes = readout.fit_bayes(ica.transform(slow), lab, n_classes, n_bins)
        out.append(readout.predict_bayes(bayes, ica.transform(sfa.transform(f))))
    return out


def _cell_features(method, params, draw, signals, recs, ids, cols, part_target):
    """Per trial of ``ids``: (flat features, part lengths)."""
    segs = [P.Segment(int(t), 0, int(recs.length[t])) for t in ids]
    parts = P.to_parts(signals, recs.offset, recs.terrain, segs, cols, part_target)
    f = M.expand_raw(method, params, draw, parts)
    per_trial = np.array([parts.length[parts.trial == t].sum() for t in ids])
    edges = np.concatenate([[0], np.cumsum(per_trial)])
    return ([f[a:b] for a, b in zip(edges[:-1], edges[1:])],
            [parts.length[parts.trial == t] for t in ids])


def separability(ctx: RunContext) -> xr.Dataset:
    """``ch5/separability``: leave-one-trial-out accuracy per (gait, frequency) cell, sensor
    group and method, with the cell's majority share and chance (see module docstring).

    Raises:
        ValueError: no cell has trials of ``min_terrains`` terrains, or an unknown method.
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(1):  # small dense algebra: one BLAS thread (experiments.py)
        return _separability(ctx)


def _separability(ctx: RunContext) -> xr.Dataset:
    from thesis.ch5.experiments import _normalised

    cfg = ctx.config
    sc = cfg["separability"]
    groups, methods = list(sc["selections"]), list(sc["methods"])
    bad = [m for m in methods if m not in M.METHODS]
    if bad:
        raise ValueError(f"ch5.separability.methods: unknown {bad}; one of {M.METHODS}")
    recs = REC.load(ctx.input("recordings"))
    found = cells(recs, int(sc["min_terrains"]))
    if not found:
        raise ValueError(f"ch5.separability: no (gait, frequency) cell has trials of "
                         f"{sc['min_terrains']} terrains")
    signals = _normalised(recs, recs.trials())
    seeds = [int(s) for s in (sc.get("seeds") or cfg["seeds"])]
    nodes = int(cfg["methods"]["nodes"])
    tgt = int(cfg["protocol"]["part_target"])
    nt = len(REC.TERRAINS)
    ranges = {k: tuple(v) for k, v in cfg["search"].items() if k != "sigma0"}
    params = {m: {k: round(v, 6) for k, v in start_params(m, ranges).items()
                  if k != "pca_rate"} for m in methods}  # no PCA here
    mc = cfg["methods"]
    names = [f"{g} {f:.2f} Hz" for g, f, _ in found]
    conf = np.zeros((len(seeds), len(found), len(groups), len(methods), nt, nt), np.int64)
    for si, seed in enumerate(seeds):
        draw = M.draw(seeding.rng(ctx.root_seed, f"{ctx.key}/weights/{nodes}", seed), nodes,
                      len(S.NAMES))
        ica_seed = seeding.int_seed(ctx.root_seed, f"{ctx.key}/ica", seed)
        for ci, (_, _, ids) in enumerate(found):
            labels = recs.terrain[ids]
            for gi, group in enumerate(groups):
                cols = S.columns(group)
                for mi, m in enumerate(methods):
                    feats, lens = _cell_features(m, params[m], draw, signals, recs, ids, cols,
                                                 tgt)
                    if m in M.SUPERVISED:
                        pred = loto_linear(feats, labels, nt)
                    else:
                        pred = loto_unsupervised(
                            feats, lens, labels, nt, n_slow=int(mc["n_slow"]),
                            n_bins=int(mc["histogram_bins"]), ica_seed=ica_seed,
                            ica_max_iter=int(mc["ica_max_iter"]))
                    truth = np.concatenate([np.full(len(p), r) for p, r in zip(pred, labels)])
                    conf[si, ci, gi, mi] = P.confusion(np.concatenate(pred), truth, nt)
            ctx.log.info("separability seed %d %s: %s", seed, names[ci], "; ".join(
                f"{g} " + ", ".join(
                    f"{m} {100 * np.trace(conf[si, ci, gi, mi]) / conf[si, ci, gi, mi].sum():.1f}"
                    for mi, m in enumerate(methods)) for gi, g in enumerate(groups)))
    return _dataset(ctx, recs, found, names, groups, methods, seeds, conf, params, nodes)


def _dataset(ctx, recs, found, names, groups, methods, seeds, conf, params, nodes):
    nt = len(REC.TERRAINS)
    steps = np.array([np.bincount(recs.terrain[ids], weights=recs.length[ids], minlength=nt)
                      for _, _, ids in found])  # cell, terrain
    trials = np.array([np.bincount(recs.terrain[ids], minlength=nt) for _, _, ids in found])
    ds = xr.Dataset(coords={"seed": seeds, "cell": names, "selection": groups,
                            "method": methods, "terrain": list(REC.TERRAINS)})
    ds["gait"] = ("cell", [g for g, _, _ in found], {"units": "1",
                                                     "long_name": "gait of the cell"})
    ds["frequency"] = ("cell", [f for _, f, _ in found], {"units": "Hz",
                                                          "long_name": "gait frequency"})
    ds["trials"] = (("cell", "terrain"), trials, {"units": "1", "long_name": "trials"})
    ds["samples"] = (("cell", "terrain"), steps, {"units": "1", "long_name": "time steps"})
    total = conf.sum(axis=(-1, -2))
    with np.errstate(invalid="ignore", divide="ignore"):
        acc = 100.0 * np.trace(conf, axis1=-2, axis2=-1) / total
        recall = 100.0 * np.diagonal(conf, axis1=-2, axis2=-1) / conf.sum(-1)
    ds["accuracy"] = (("seed", "cell", "selection", "method"), acc, {
        "units": "percent", "long_name": "leave-one-trial-out time steps classified "
                                        "correctly, pooled over the cell's trials"})
    ds["recall"] = (("seed", "cell", "selection", "method", "terrain"), recall, {
        "units": "percent", "long_name": "time steps of the terrain classified correctly "
                                        "(NaN: no trial of the terrain in the cell)"})
    ds["confusion"] = (("seed", "cell", "selection", "method", "true", "predicted"), conf, {
        "units": "1", "long_name": "time steps of each true terrain classified as each"})
    ds["majority_share"] = ("cell", 100.0 * steps.max(1) / steps.sum(1), {
        "units": "percent", "long_name": "time steps of the cell's most frequent terrain: the "
                                        "accuracy of always answering it"})
    ds["chance"] = ("cell", 100.0 / (trials > 0).sum(1), {
        "units": "percent", "long_name": "chance level, 1 / the cell's number of terrains"})
    ds.attrs.update(thesis_ref="Tab. 5.1 cells", seeds=seeds, nodes=nodes,
                    hyper_parameters=json.dumps(params), pca="none",
                    protocol="leave-one-trial-out within each (gait, frequency) cell",
                    n_trials=int(recs.n_trials), recordings=str(recs.path))
    return ds
