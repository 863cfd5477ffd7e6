"""Registered experiments of chapter 5 (thesis.registry): recordings, Tab. 5.3-5.6, Fig. 5.3.

``ch5/puppy_recordings`` (:mod:`thesis.ch5.data`) simulates the trials once per
profile into ``data/synthetic/puppy/<profile>.h5``; every experiment here reads that file
(``--input recordings=...``) and the selection, tuning and verification protocol of
:mod:`thesis.ch5.protocol` and :mod:`thesis.ch5.tuning`:

* ``table5_3``: LR and RC on the 8 sensor groups (train and test accuracy), each tuned
  per seed and group; also the tuned hyper-parameters (read by ``fig5_3``);
* ``table5_4``: LR, leaky ELM and RC over hidden-node counts on touch and minimal;
* ``table5_5``: SFA2 and RC-SFA on the 8 groups;
* ``table5_6``: SFA2, ELM-SFA and RC-SFA over node counts, minimal, bound-right trials;
* ``fig5_3``: RC trained on bound right at 1 Hz, confusion matrices on the other
  frequencies (bound right) and on the other gaits (1 Hz);
* ``table5_3_blocks``, ``table5_3_parts``: Tab. 5.3 with the other two selection modes
  (:mod:`thesis.ch5.selections`; the tables above use ``ch5.protocol.selection``),
  sensitivity variants run by the optional Snakemake target ``ch5_variants``.

The separability measurement (``ch5/separability``) lives in
:mod:`thesis.ch5.separability`.

Every table also carries the generalisation map: ``accuracy_cells`` splits
the test accuracy into the time steps whose (terrain, gait, frequency) cell has training
trials in the fold (``seen``) and the rest (``unseen``), pooled over the two folds, with
``seen_share`` and each subset's ``majority_share_cells``; and the fold-sharing
measurements ``shared_tuning`` / ``shared_verification`` (percent of the evaluation time
steps whose recording also feeds the fold's training side: 0 for trial-disjoint folds)
and the attributes ``selection_mode`` and ``selection_levels`` (per seed and terrain).

Every accuracy carries its baselines, computed from the labels of the sets it is scored
on: ``majority_share`` (seed, split; Fig. 5.3: seed, test), the share of the time steps
of the most frequent terrain (what a classifier that always answers it scores; the test
sets hold the remaining trials, so they are unbalanced), and ``chance``, 100 / the number
of terrains.

The classifiers are small dense linear algebra (matrices of at most a few hundred
columns): every experiment runs with one BLAS thread (``threadpoolctl``), which was ~10x
faster than OpenBLAS's threads on a shared two-core machine, and leaves Snakemake to run
the tables side by side.

Seeds: seed s draws its selections from stream ``"ch5/<artifact>/selection"``, its hidden
layers from ``"ch5/<artifact>/weights/<nodes>"``, its CMA-ES and FastICA seeds from
``"ch5/<artifact>/cma/..."`` (thesis.seeding), so artifacts never share random numbers.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.runctx import RunContext
from thesis.ch5 import gaits as G
from thesis.ch5 import methods as M
from thesis.ch5 import protocol as P
from thesis.ch5 import recordings as REC
from thesis.ch5 import selections as SEL
from thesis.ch5 import sensors as S
from thesis.ch5 import tuning as T

SELECTIONS = tuple(S.GROUPS)
SPLITS = ("train", "test")
#: Test time steps whose (terrain, gait, frequency) cell has training trials in the fold,
#: and those whose cell has none (the generalisation map).
CELLS = ("seen", "unseen")


# --------------------------------------------------------------------------- shared
def _load(ctx: RunContext) -> REC.Recordings:
    return REC.load(ctx.input("recordings"))


def _normalised(recs: REC.Recordings, trials: np.ndarray) -> np.ndarray:
    """Signals z-scored over the samples of ``trials`` (§5.3.1, before selection)."""
    idx = np.concatenate([np.arange(recs.offset[t], recs.offset[t] + recs.length[t])
                          for t in trials])
    _, mean, std = P.normalise(recs.signals[idx])
    return (recs.signals.astype(np.float64) - mean) / std


def cell_codes(recs: REC.Recordings) -> np.ndarray:
    """(n_trials,) integer code of each trial's (terrain, gait, frequency) cell of Tab. 5.1."""
    keys = [(int(recs.terrain[t]), int(recs.gait[t]), round(float(recs.frequency[t]), 3))
            for t in range(recs.n_trials)]
    index = {k: i for i, k in enumerate(sorted(set(keys)))}
    return np.array([index[k] for k in keys], int)


class _Study:
    """One seed's selections of an experiment's trials and the parts of every fold.

    ``mode`` is the selection mode (:mod:`thesis.ch5.selections`); the study records
    each terrain's fallback level and, per fold, the share of the evaluation time steps
    whose recording also feeds the fold's training side."""

    def __init__(self, ctx: RunContext, recs, signals, trials, seed: int, mode: str):
        cfg = ctx.config
        pc = cfg["protocol"]
        self.recs, self.signals, self.cfg, self.seed, self.ctx = recs, signals, cfg, seed, ctx
        rng = seeding.rng(ctx.root_seed, f"{ctx.key}/selection", seed)
        sel = SEL.select(mode, recs.length, recs.terrain, trials, rng, int(pc["selections"]),
                         int(pc["samples"]), int(pc["part_target"]), REC.TERRAINS)
        self.selections, self.remaining = sel.selections, sel.remaining
        self.level = {REC.TERRAINS[r]: lev for r, lev in sel.level.items()}
        self.tuning = P.tuning_folds(self.selections)
        self.verification = P.verification_folds(self.selections, self.remaining, recs.length)
        self.shared = {which: np.array([SEL.shared_share(f) for f in getattr(self, which)])
                       for which in ("tuning", "verification")}
        self.cells = cell_codes(recs)
        self._cache: dict = {}

    def seen(self, fold: int, trials: np.ndarray) -> np.ndarray:
        """(len(trials),) whether each trial's cell has a training trial in verification
        fold ``fold``."""
        train = {self.cells[s.trial] for s in self.verification[fold].train}
        return np.isin(self.cells[np.asarray(trials, int)], sorted(train))

    def cell_baselines(self, n_terrains: int) -> tuple[float, np.ndarray]:
        """(seen share, (2,) majority share of the seen / unseen test time steps), pooled
        over the two verification folds [percent]."""
        counts = np.zeros((2, n_terrains))
        for i, split in enumerate(self.verification):
            trials = np.array([s.trial for s in split.test], int)
            steps = np.array([s.length for s in split.test], float)
            seen = self.seen(i, trials)
            for c, mask in enumerate((seen, ~seen)):
                counts[c] += np.bincount(self.recs.terrain[trials[mask]], weights=steps[mask],
                                         minlength=n_terrains)
        total = counts.sum(1)
        with np.errstate(invalid="ignore", divide="ignore"):
            share = 100.0 * counts[0].sum() / total.sum() if total.sum() else np.nan
            return float(share), 100.0 * counts.max(1) / total

    def parts(self, group: str, which: str) -> list[tuple[P.Parts, P.Parts]]:
        """(train, test) parts of the ``which`` folds (``"tuning"``/``"verification"``)."""
        key = (group, which)
        if key not in self._cache:
            cols = S.columns(group)
            tgt = int(self.cfg["protocol"]["part_target"])
            self._cache[key] = [
                tuple(P.to_parts(self.signals, self.recs.offset, self.recs.terrain, segs, cols,
                                 tgt) for segs in (split.train, split.test))
                for split in getattr(self, which)]
        return self._cache[key]


def _kwargs(cfg: dict, root_seed: int, key: str, seed: int) -> dict:
    m = cfg["methods"]
    return dict(n_slow=int(m["n_slow"]), n_bins=int(m["histogram_bins"]),
                ica_max_iter=int(m["ica_max_iter"]),
                ica_seed=seeding.int_seed(root_seed, f"{key}/ica", seed))


def _draw(ctx: RunContext, nodes: int, seed: int) -> M.Draw:
    rng = seeding.rng(ctx.root_seed, f"{ctx.key}/weights/{nodes}", seed)
    return M.draw(rng, nodes, len(S.NAMES))


def _tune(ctx: RunContext, study: _Study, group: str, method: str, draw: M.Draw,
          tag: str) -> dict:
    """CMA-ES on the threefold tuning folds of ``study`` (§5.2.5)."""
    cfg = ctx.config
    folds = study.parts(group, "tuning")
    kw = _kwargs(cfg, ctx.root_seed, ctx.key, study.seed)

    def objective(params: dict) -> float:
        accs = []
        for train, val in folds:  # the training predictions are not needed here
            fitted = M.fit(method, params, draw, train, len(REC.TERRAINS), **kw)
            accs.append(P.accuracy(M.predict(fitted, val), val.labels()))
        return float(np.mean(accs))

    ranges = {k: tuple(v) for k, v in cfg["search"].items() if k != "sigma0"}
    res = T.tune(objective, M.PARAMS[method], ranges,
                 seed=seeding.int_seed(ctx.root_seed, f"{ctx.key}/cma/{tag}", study.seed),
                 generations=int(cfg["tuning"]["generations"]),
                 sigma0=float(cfg["search"]["sigma0"]))
    ctx.log.info("%s seed %d %s %s: CV accuracy %.1f %% after %d evaluations (%s)", ctx.key,
                 study.seed, group, tag, res["best_score"], res["evaluations"],
                 ", ".join(f"{k}={v:.3g}" for k, v in res["best"].items()))
    return res


def _verify(ctx: RunContext, study: _Study, group: str, method: str, params: dict,
            draw: M.Draw) -> tuple[np.ndarray, np.ndarray]:
    """Twofold verification: (2 folds, 2 splits) train/test accuracy [percent], and (2
    cells) test accuracy on the time steps of seen / unseen cells (:data:`CELLS`), pooled
    over both folds [percent; NaN where a fold set has none]."""
    kw = _kwargs(ctx.config, ctx.root_seed, ctx.key, study.seed)
    out = np.zeros((2, 2))
    hits = np.zeros((2, 2))  # cell, (correct, total)
    for i, (train, test) in enumerate(study.parts(group, "verification")):
        ptr, (pte,) = M.evaluate(method, params, draw, train, [test], len(REC.TERRAINS), **kw)
        out[i] = P.accuracy(ptr, train.labels()), P.accuracy(pte, test.labels())
        seen = np.repeat(study.seen(i, test.trial), test.length)
        right = pte == test.labels()
        for c, mask in enumerate((seen, ~seen)):
            hits[c] += right[mask].sum(), mask.sum()
    with np.errstate(invalid="ignore"):
        return out, 100.0 * hits[:, 0] / hits[:, 1]


def _single_thread(fn):
    """Run ``fn`` with one BLAS/OpenMP thread (see module docstring)."""
    import functools

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        from threadpoolctl import threadpool_limits

        with threadpool_limits(1):
            return fn(*args, **kwargs)

    return wrapper


@_single_thread
def _grid(ctx: RunContext, trials: np.ndarray, cells: list[tuple[str, str, int]],
          mode: str | None = None) -> dict:
    """Tune and verify every (group, method, nodes) cell for every seed.

    With ``ch5.tuning.per_seed`` false the hyper-parameters of a cell are tuned once, on
    the first seed's tuning folds, and verified on every seed (a declared deviation).
    ``mode``: selection mode (None: the profile's ``ch5.protocol.selection``).
    Returns arrays keyed by name with a leading seed axis and a cell axis.
    """
    mode = str(ctx.config["protocol"]["selection"]) if mode is None else mode
    recs = _load(ctx)
    signals = _normalised(recs, trials)
    seeds = list(ctx.config["seeds"])
    per_seed = bool(ctx.config["tuning"]["per_seed"])
    n = len(cells)
    acc = np.full((len(seeds), n, 2, 2), np.nan)  # seed, cell, fold, split
    cv = np.full((len(seeds), n), np.nan)
    params = {p: np.full((len(seeds), n), np.nan) for p in
              ("pca_rate", "leak", "input_scaling", "spectral_radius")}
    evals = np.zeros((len(seeds), n))
    majority = np.full((len(seeds), 2, 2), np.nan)  # seed, fold, split
    cell_acc = np.full((len(seeds), n, 2), np.nan)  # seed, cell, seen/unseen
    seen_share = np.full(len(seeds), np.nan)
    n_remaining = np.zeros(len(seeds), int)
    cell_majority = np.full((len(seeds), 2), np.nan)
    shared = {w: np.full((len(seeds), k), np.nan) for w, k in (("tuning", 3),
                                                                ("verification", 2))}
    levels = {}
    tuned: dict = {}
    for si, seed in enumerate(seeds):
        study = _Study(ctx, recs, signals, trials, seed, mode)
        majority[si] = _study_majority(study, len(REC.TERRAINS))
        seen_share[si], cell_majority[si] = study.cell_baselines(len(REC.TERRAINS))
        for w in shared:
            shared[w][si] = study.shared[w]
        levels[int(seed)] = study.level
        n_remaining[si] = len(study.remaining)
        ctx.log.info("%s seed %d (%s selections): levels %s; evaluation steps sharing a "
                     "recording with training: tuning %s %%, verification %s %%", ctx.key,
                     seed, mode, study.level, np.round(study.shared["tuning"], 1),
                     np.round(study.shared["verification"], 1))
        for ci, (group, method, nodes) in enumerate(cells):
            draw = _draw(ctx, nodes, seed) if method not in ("lr", "sfa2") else None
            tag = f"{group}/{method}/{nodes}"
            if per_seed or tag not in tuned:
                tune_study = study if per_seed or si == 0 else None
                if tune_study is None:
                    raise RuntimeError("tuning study missing")
                tuned[tag] = _tune(ctx, tune_study, group, method, draw, tag)
                evals[si, ci] = tuned[tag]["evaluations"]
            res = tuned[tag]
            cv[si, ci] = res["best_score"]
            for k, v in res["best"].items():
                params[k][si, ci] = v
            acc[si, ci], cell_acc[si, ci] = _verify(ctx, study, group, method, res["best"],
                                                    draw)
            ctx.log.info("%s seed %d %s: train %.1f %%, test %.1f %%", ctx.key, seed, tag,
                         acc[si, ci, :, 0].mean(), acc[si, ci, :, 1].mean())
    return dict(acc=acc, cv=cv, params=params, evals=evals, seeds=seeds, recs=recs,
                majority=majority, cell_acc=cell_acc, seen_share=seen_share,
                cell_majority=cell_majority, shared=shared, levels=levels, mode=mode,
                n_remaining=n_remaining)


def majority_share(segments, terrain: np.ndarray, n_terrains: int) -> float:
    """Percent of the time steps of ``segments`` that belong to their most frequent
    terrain: the accuracy of always answering that terrain (§5.3.2's score of a constant
    classifier). ``terrain``: (n_trials,) label per trial."""
    counts = np.bincount([int(terrain[s.trial]) for s in segments],
                         weights=[s.length for s in segments], minlength=n_terrains)
    return 100.0 * float(counts.max() / counts.sum()) if counts.sum() else float("nan")


def _study_majority(study: _Study, n_terrains: int) -> np.ndarray:
    """(2 folds, 2 splits) majority-class share of each verification fold's train/test set."""
    return np.array([[majority_share(segs, study.recs.terrain, n_terrains)
                      for segs in (split.train, split.test)] for split in study.verification])


def _pct(values, long_name: str) -> tuple:
    return values, {"units": "percent", "long_name": long_name}


def _grid_dataset(g: dict, dims: list[str], coords: dict, shape: tuple, ref: str,
                  ctx: RunContext) -> xr.Dataset:
    """Dataset of a :func:`_grid` result whose cells reshape to ``shape`` over ``dims``."""
    s = len(g["seeds"])
    acc = g["acc"].reshape((s,) + shape + (2, 2))
    ds = xr.Dataset(coords={"seed": g["seeds"], **coords, "fold": [0, 1],
                            "split": list(SPLITS)})
    d = ["seed", *dims]
    ds["accuracy_fold"] = (d + ["fold", "split"], acc, {
        "units": "percent", "long_name": "time steps classified correctly, per verification "
                                        "fold (train: the fold's training selection; test: "
                                        "the other selection and the remaining trials)"})
    ds["accuracy"] = (d + ["split"], acc.mean(axis=-2), {
        "units": "percent", "long_name": "time steps classified correctly, mean of the two "
                                        "verification folds (§5.3.2)"})
    ds["cv_accuracy"] = (d, g["cv"].reshape((s,) + shape), {
        "units": "percent", "long_name": "threefold cross-validation accuracy of the tuned "
                                        "hyper-parameters (CMA-ES objective)"})
    for k, v in g["params"].items():
        unit = "1"
        ds[k] = (d, v.reshape((s,) + shape), {"units": unit, "long_name": f"tuned {k} "
                                              "(NaN: not a parameter of the method)"})
    ds["majority_share"] = (("seed", "split"), g["majority"].mean(axis=1), {
        "units": "percent", "long_name": "time steps of the set's most frequent terrain, mean "
                                        "of the two verification folds: the accuracy of a "
                                        "classifier that always answers that terrain"})
    ds["chance"] = ((), 100.0 / len(REC.TERRAINS), {
        "units": "percent", "long_name": "chance level, 1 / number of terrains"})
    ds["cma_evaluations"] = (d, g["evals"].reshape((s,) + shape), {
        "units": "1", "long_name": "CMA-ES evaluations spent on this seed (0: reused the "
                                   "first seed's tuning)"})
    _cells_variables(ds, g, d, shape)
    recs = g["recs"]
    ds.attrs.update(thesis_ref=ref, seeds=list(g["seeds"]), selection_mode=g["mode"],
                    selection_levels=json.dumps(g["levels"]),
                    tuned_per_seed=int(bool(ctx.config["tuning"]["per_seed"])),
                    cma_generations=int(ctx.config["tuning"]["generations"]),
                    samples_per_selection=int(ctx.config["protocol"]["samples"]),
                    n_trials=int(recs.n_trials), recordings=str(recs.path),
                    recordings_config=recs.config_json,
                    stopped_trials=json.dumps(list(recs.stopped_trials)))
    return ds


def _cells_variables(ds: xr.Dataset, g: dict, dims: list[str], shape: tuple) -> None:
    """Add the generalisation map and the fold-sharing measurements of a :func:`_grid`
    result to ``ds`` (``dims``/``shape``: the cell dims after ``seed``)."""
    s = len(g["seeds"])
    ds.coords["cells"] = list(CELLS)
    ds.coords["tuning_fold"] = [0, 1, 2]
    ds["accuracy_cells"] = (dims + ["cells"], g["cell_acc"].reshape((s,) + shape + (2,)), {
        "units": "percent", "long_name": "test time steps classified correctly, split by "
                                        "whether their (terrain, gait, frequency) cell has "
                                        "training trials in the fold (seen) or not (unseen), "
                                        "pooled over the two verification folds"})
    ds["seen_share"] = (("seed",), g["seen_share"], {
        "units": "percent", "long_name": "test time steps whose (terrain, gait, frequency) "
                                        "cell has training trials in the fold, pooled over "
                                        "the two verification folds"})
    ds["majority_share_cells"] = (("seed", "cells"), g["cell_majority"], {
        "units": "percent", "long_name": "time steps of the most frequent terrain among the "
                                        "seen / unseen test time steps (their baseline)"})
    ds["shared_tuning"] = (("seed", "tuning_fold"), g["shared"]["tuning"], {
        "units": "percent", "long_name": "validation time steps of each threefold tuning "
                                        "fold whose recording also feeds its training "
                                        "selections"})
    ds["remaining_trials"] = (("seed",), g["n_remaining"], {
        "units": "1", "long_name": "trials no selection touched (added to every "
                                   "verification fold's test set)"})
    ds["shared_verification"] = (("seed", "fold"), g["shared"]["verification"], {
        "units": "percent", "long_name": "test time steps of each verification fold whose "
                                        "recording also feeds its training selection"})


def _with_cells(g: dict, keep) -> dict:
    """``g`` restricted to the grid cells ``keep`` (a slice of the cell axis)."""
    return dict(g, acc=g["acc"][:, keep], cv=g["cv"][:, keep], evals=g["evals"][:, keep],
                params={k: v[:, keep] for k, v in g["params"].items()},
                cell_acc=g["cell_acc"][:, keep])


# --------------------------------------------------------------------------- tables
def _table5_3(ctx: RunContext, mode: str | None) -> xr.Dataset:
    nodes = int(ctx.config["methods"]["nodes"])
    cells = [(g, m, nodes) for g in SELECTIONS for m in ("lr", "rc")]
    trials = _load(ctx).trials()
    g = _grid(ctx, trials, cells, mode)
    ds = _grid_dataset(g, ["selection", "method"], {"selection": list(SELECTIONS),
                                                    "method": ["lr", "rc"]},
                       (len(SELECTIONS), 2), "Tab. 5.3", ctx)
    ds["dimensions"] = ("selection", [S.GROUP_DIMS[s] for s in SELECTIONS],
                        {"units": "1", "long_name": "signals in the sensor group (Tab. 5.2)"})
    ds.attrs["nodes"] = nodes
    return ds


def table5_3(ctx: RunContext) -> xr.Dataset:
    """Tab. 5.3: LR and RC on the 8 sensor groups, train and test accuracy, with the
    profile's selection mode (``ch5.protocol.selection``, the primary protocol)."""
    return _table5_3(ctx, None)


def table5_3_blocks(ctx: RunContext) -> xr.Dataset:
    """Tab. 5.3 with the previous protocol's selections (consecutive blocks of the
    concatenated trials, a trial cut across selections): a sensitivity variant."""
    return _table5_3(ctx, "blocks")


def table5_3_parts(ctx: RunContext) -> xr.Dataset:
    """Tab. 5.3 with selections drawn as parts across trials (whole trials assigned to one
    selection, parts drawn within it): a sensitivity variant (§5.3.1 "We split all trials
    into parts")."""
    return _table5_3(ctx, "parts")


def table5_4(ctx: RunContext) -> xr.Dataset:
    """Tab. 5.4: LR, leaky ELM and RC over hidden-node counts on touch and minimal."""
    c = ctx.config["table5_4"]
    groups, nodes = list(c["selections"]), [int(n) for n in c["nodes"]]
    cells = [(g, m, n) for g in groups for m in ("elm", "rc") for n in nodes]
    cells += [(g, "lr", 0) for g in groups]
    trials = _load(ctx).trials()
    g = _grid(ctx, trials, cells)
    s = len(g["seeds"])
    hid = _with_cells(g, slice(None, -len(groups)))
    ds = _grid_dataset(hid, ["selection", "method", "nodes"],
                       {"selection": groups, "method": ["elm", "rc"], "nodes": nodes},
                       (len(groups), 2, len(nodes)), "Tab. 5.4", ctx)
    lr = g["acc"][:, -len(groups):].mean(axis=-2)  # seed, group, split
    ds["lr_accuracy"] = (("seed", "selection", "split"), lr, {
        "units": "percent", "long_name": "LR (no hidden layer) time steps classified "
                                        "correctly, mean of the two verification folds"})
    ds["lr_cv_accuracy"] = (("seed", "selection"), g["cv"][:, -len(groups):], {
        "units": "percent", "long_name": "threefold cross-validation accuracy of LR"})
    ds["lr_accuracy_cells"] = (("seed", "selection", "cells"), g["cell_acc"][:, -len(groups):], {
        "units": "percent", "long_name": "LR test time steps classified correctly on seen / "
                                        "unseen cells, pooled over the two folds"})
    ds.attrs["n_seeds"] = s
    return ds


def table5_5(ctx: RunContext) -> xr.Dataset:
    """Tab. 5.5: SFA2 and RC-SFA on the 8 sensor groups (unsupervised, Bayes readout)."""
    nodes = int(ctx.config["methods"]["nodes"])
    cells = [(g, m, nodes) for g in SELECTIONS for m in ("sfa2", "rc_sfa")]
    g = _grid(ctx, _load(ctx).trials(), cells)
    ds = _grid_dataset(g, ["selection", "method"], {"selection": list(SELECTIONS),
                                                    "method": ["sfa2", "rc_sfa"]},
                       (len(SELECTIONS), 2), "Tab. 5.5", ctx)
    ds["dimensions"] = ("selection", [S.GROUP_DIMS[s] for s in SELECTIONS],
                        {"units": "1", "long_name": "signals in the sensor group (Tab. 5.2)"})
    ds.attrs["nodes"] = nodes
    return ds


def table5_6(ctx: RunContext) -> xr.Dataset:
    """Tab. 5.6: ELM-SFA and RC-SFA over node counts and SFA2, minimal, bound right only."""
    nodes = [int(n) for n in ctx.config["table5_6"]["nodes"]]
    cells = [("minimal", m, n) for m in ("elm_sfa", "rc_sfa") for n in nodes]
    cells += [("minimal", "sfa2", 0)]
    recs = _load(ctx)
    g = _grid(ctx, recs.trials(["bound_right"]), cells)
    hid = _with_cells(g, slice(None, -1))
    ds = _grid_dataset(hid, ["method", "nodes"], {"method": ["elm_sfa", "rc_sfa"],
                                                  "nodes": nodes},
                       (2, len(nodes)), "Tab. 5.6", ctx)
    ds["sfa2_accuracy"] = (("seed", "split"), g["acc"][:, -1].mean(axis=-2), {
        "units": "percent", "long_name": "SFA2 time steps classified correctly, mean of the "
                                        "two verification folds"})
    ds["sfa2_accuracy_cells"] = (("seed", "cells"), g["cell_acc"][:, -1], {
        "units": "percent", "long_name": "SFA2 test time steps classified correctly on seen "
                                        "/ unseen cells, pooled over the two folds"})
    ds.attrs.update(selection="minimal", gaits="bound_right")
    return ds


# --------------------------------------------------------------------------- Fig. 5.3
@_single_thread
def fig5_3(ctx: RunContext) -> xr.Dataset:
    """Fig. 5.3: RC trained on bound right at 1 Hz; confusion on other frequencies (bound
    right) and on other gaits (1 Hz). Hyper-parameters: Tab. 5.3's RC optimum of the
    group (``--input table5_3=...``), per seed."""
    cfg = ctx.config["fig5_3"]
    group = cfg["selection"]
    recs = _load(ctx)
    t53 = xr.load_dataset(ctx.input("table5_3"), engine="h5netcdf")
    signals = _normalised(recs, recs.trials())
    br = G.GAITS.index("bound_right")
    one_hz = np.isclose(recs.frequency, 1.0)
    seeds = list(ctx.config["seeds"])
    nt = len(REC.TERRAINS)
    conf = np.zeros((len(seeds), 2, nt, nt), np.int64)
    n_train = np.zeros((len(seeds), nt), int)
    cols = S.columns(group)
    tgt = int(ctx.config["protocol"]["part_target"])
    nodes = int(ctx.config["methods"]["nodes"])
    kw = _kwargs(ctx.config, ctx.root_seed, ctx.key, 0)
    tests = {"frequency": np.flatnonzero((recs.gait == br) & ~one_hz),
             "gait": np.flatnonzero((recs.gait != br) & one_hz)}
    for si, seed in enumerate(seeds):
        rng = seeding.rng(ctx.root_seed, f"{ctx.key}/train", seed)
        train = []
        for r in range(nt):
            pool = np.flatnonzero((recs.gait == br) & one_hz & (recs.terrain == r))
            pick = rng.permutation(pool)[:int(cfg["max_train_trials"])]
            n_train[si, r] = len(pick)
            train += list(pick)
        seg = lambda ids: [P.Segment(int(t), 0, int(recs.length[t])) for t in ids]  # noqa
        tr = P.to_parts(signals, recs.offset, recs.terrain, seg(train), cols, tgt)
        params = {k: float(t53[k].sel({"seed": seed, "selection": group, "method": "rc"}))
                  for k in M.PARAMS["rc"]}
        draw = M.draw(seeding.rng(ctx.root_seed, f"{ctx.key}/weights/{nodes}", seed), nodes,
                      len(S.NAMES))
        fitted = M.fit("rc", params, draw, tr, nt, **dict(kw, ica_seed=0))
        for ti, (name, ids) in enumerate(tests.items()):
            te = P.to_parts(signals, recs.offset, recs.terrain, seg(ids), cols, tgt)
            conf[si, ti] = P.confusion(M.predict(fitted, te), te.labels(), nt)
        ctx.log.info("fig5_3 seed %d: training trials per terrain %s", seed, n_train[si])
    ds = xr.Dataset(coords={"seed": seeds, "test": list(tests), "true": list(REC.TERRAINS),
                            "predicted": list(REC.TERRAINS)})
    ds["confusion"] = (("seed", "test", "true", "predicted"), conf, {
        "units": "1", "long_name": "time steps of each true terrain classified as each "
                                   "terrain"})
    with np.errstate(invalid="ignore"):
        recall = 100.0 * np.einsum("stii->sti", conf) / conf.sum(-1)
    ds["recall"] = (("seed", "test", "true"), recall, {
        "units": "percent", "long_name": "time steps of the true terrain classified "
                                        "correctly (NaN: terrain absent from the test)"})
    ds["train_trials"] = (("seed", "true"), n_train, {
        "units": "1", "long_name": "bound-right 1 Hz training trials of the terrain"})
    steps = conf.sum(-1).astype(float)  # (seed, test, true) time steps per true terrain
    with np.errstate(invalid="ignore"):
        ds["majority_share"] = (("seed", "test"), 100.0 * steps.max(-1) / steps.sum(-1), {
            "units": "percent", "long_name": "time steps of the test's most frequent "
                                            "terrain: the accuracy of always answering it"})
    ds["chance"] = ((), 100.0 / nt, {
        "units": "percent", "long_name": "chance level, 1 / number of terrains (a constant "
                                        "classifier's mean recall over the terrains)"})
    ds.attrs.update(thesis_ref="Fig. 5.3", seeds=seeds, selection=group, nodes=nodes,
                    min_train_trials=int(cfg["min_train_trials"]))
    return ds
