"""Report of chapter 5: Tab. 5.3-5.6 beside the thesis's, Fig. 5.3's confusion matrices and
the invented model and terrain parameters, from ``results/<profile>/ch5/*.nc``; also the
measurements of the protocol questions: the terrains' separability per (gait, frequency) cell
(``separability``), the generalisation map of Tab. 5.3-5.6 (test accuracy on time steps
whose (terrain, gait, frequency) cell is seen in training vs unseen) and Tab. 5.3 under
the three selection protocols side by side.

Thesis numbers come from :mod:`thesis.paper`; reproduced numbers are read from the
datasets (mean ± standard deviation over seeds of the test/train accuracy, percent of time
steps); a missing dataset shows "not run". Every table shows the test set's majority-class
share and chance beside the accuracies (the datasets' ``majority_share`` and ``chance``).
Tab. 5.4 is an image in the thesis, so its prose statements stand beside the reproduced
table.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from thesis import paper
from thesis.report.format import fmt, mean_spread
from thesis.report.model import NOT_RUN, Figure, Table

SEL = ("useful", "reduced", "minimal", "leg", "agt", "imu", "joints", "touch")
TERRAINS = ("F", "S", "L", "C", "R")


def _paper(artifact, variable, **coords) -> str:
    hits = paper.select(artifact, variable, **coords)
    return fmt(hits[0].value) if hits and hits[0].value is not None else "—"


def _ms(da) -> str:
    return mean_spread(np.asarray(da.values, float).ravel())


def _sel(da, **coords):
    return da.sel(coords)


def _note(ds) -> str:
    if ds is None:
        return ""
    keys = ("tuned_per_seed", "cma_generations", "samples_per_selection", "nodes", "n_trials")
    out = ", ".join(f"{k}={ds.attrs[k]}" for k in keys if k in ds.attrs)
    stopped = json.loads(str(ds.attrs.get("stopped_trials", "[]")))
    return f"{out}, {len(stopped)} trial(s) stopped when the robot turned over."


BASELINE_COLUMNS = ["TEST majority share", "chance"]
BASELINE_NOTE = ("Baselines: the test set's majority-class share (the accuracy of always "
                 "answering its most frequent terrain; the test sets hold the remaining "
                 "trials, so they are unbalanced) and chance (1 / number of terrains); a "
                 "claim about classification quality needs the methods to beat the majority "
                 "share first. ")


def baselines(ds, split: str = "test", **coords) -> list[str]:
    """[majority share (mean ± sd over seeds), chance] of a ch5 dataset [%]; not run when
    ``ds`` is None or lacks them."""
    if ds is None or "majority_share" not in ds or "chance" not in ds:
        return [NOT_RUN, NOT_RUN]
    share = _sel(ds["majority_share"], **({"split": split} if "split" in
                                          ds["majority_share"].dims else {}), **coords)
    return [_ms(share), fmt(float(ds["chance"]))]


def _two_method(results, key, table, ref, title, methods, labels) -> Table:
    ds = results.get(f"ch5/{key}")
    base = baselines(ds)
    rows = []
    for s in SEL:
        row = [s]
        for split in ("train", "test"):
            for m in methods:
                row.append(_paper(key, "accuracy", selection=s, split=split, method=m))
                row.append(NOT_RUN if ds is None else _ms(
                    _sel(ds["accuracy"], selection=s, method=m, split=split)))
        rows.append(row + base)
    cols = ["group"] + [f"{split} {labels[m]} {who}" for split in ("TRAIN", "TEST")
                        for m in methods for who in ("thesis", "ours")] + BASELINE_COLUMNS
    return Table(id=key, title=title, thesis_ref=ref, columns=cols, rows=rows,
                 note="Accuracy [% of time steps], mean ± sd over seeds. " + BASELINE_NOTE
                      + _note(ds))


def table5_4(results) -> Table:
    ds = results.get("ch5/table5_4")
    rows = []
    if ds is not None:
        for s in ds["selection"].values:
            lr = _ms(_sel(ds["lr_accuracy"], selection=s, split="test"))
            for n in ds["nodes"].values:
                rows.append([str(s), str(int(n)), lr] + [
                    _ms(_sel(ds["accuracy"], selection=s, method=m, nodes=n, split=split))
                    for m in ("elm", "rc") for split in ("train", "test")] + baselines(ds))
    else:
        rows = [[s] + [NOT_RUN] * 8 for s in ("touch", "minimal")]
    prose = ("Thesis (the table is an image; §5.4.1.2): LR has 'over 10% more "
             "misclassifications' than any technique with 100 hidden nodes; on touch 'RC "
             "outperforms ELM roughly 10%'; on minimal 'RC and ELM achieve virtually the same "
             "performance'. ")
    return Table(id="table5_4", title="RC vs leaky ELM vs LR by hidden nodes",
                 thesis_ref="Tab. 5.4",
                 columns=["group", "nodes", "LR test", "ELM train", "ELM test", "RC train",
                          "RC test"] + BASELINE_COLUMNS, rows=rows,
                 note=prose + BASELINE_NOTE + _note(ds))


def table5_6(results) -> Table:
    ds = results.get("ch5/table5_6")
    rows = []
    for split in ("train", "test"):
        base = baselines(ds, split=split)
        rows.append([split, "SFA2", _paper("table5_6", "accuracy", selection="minimal",
                                           split=split, method="sfa2"),
                     NOT_RUN if ds is None else _ms(_sel(ds["sfa2_accuracy"], split=split))]
                    + base)
        for m, lab in (("elm_sfa", "ELM-SFA"), ("rc_sfa", "RC-SFA")):
            nodes = [50, 100, 200] if ds is None else [int(n) for n in ds["nodes"].values]
            for n in nodes:
                ours = NOT_RUN if ds is None else _ms(_sel(ds["accuracy"], method=m, nodes=n,
                                                           split=split))
                rows.append([split, f"{lab} {n}N", _paper(
                    "table5_6", "accuracy", selection="minimal", split=split, method=m,
                    nodes=n), ours] + base)
    return Table(id="table5_6", title="Unsupervised, minimal group, bound right only",
                 thesis_ref="Tab. 5.6", columns=["split", "method", "thesis", "ours",
                                                 "majority share of the split", "chance"],
                 rows=rows, note="Accuracy [% of time steps]. " + BASELINE_NOTE + _note(ds))


_LABELS = {"lr": "LR", "elm": "ELM", "rc": "RC", "sfa2": "SFA2", "elm_sfa": "ELM-SFA",
           "rc_sfa": "RC-SFA"}


def separability_verdict(ds) -> str:
    """One sentence on whether the terrains can be told apart in the cell with the most
    terrains: per sensor group the best method's mean accuracy against the cell's majority
    share, and whether it beats that share in every seed (numbers, not a claim)."""
    n_terr = (ds["trials"] > 0).sum("terrain").values
    ci = int(np.argmax(n_terr))
    cell = str(ds["cell"].values[ci])
    maj = float(ds["majority_share"].values[ci])
    parts, beaten = [], []
    for g in ds["selection"].values:
        acc = ds["accuracy"].isel(cell=ci).sel(selection=g)  # seed, method
        means = acc.mean("seed").values
        mi = int(np.nanargmax(means))
        best = acc.isel(method=mi).values
        ok = bool(np.all(best > maj))
        beaten.append(ok)
        parts.append(f"{g}: {_LABELS.get(str(acc['method'].values[mi]), '?')} "
                     f"{mean_spread(best)}")
    head = (f"In {cell} ({int(n_terr[ci])} terrains, majority share {fmt(maj)} %, chance "
            f"{fmt(float(ds['chance'].values[ci]))} %) the best leave-one-trial-out accuracy "
            f"is {'; '.join(parts)}. ")
    trials = ds["trials"].isel(cell=ci).values
    single = [t for t, n in zip(TERRAINS, trials) if n == 1]
    if single:
        head += (f"{', '.join(single)} ha(s) a single trial there, never in its own training "
                 "set, so its time steps cannot be classified correctly (a limit of this "
                 "profile's trial table, not of the terrains). ")
    if len(single) == int(n_terr[ci]):
        return head + "This profile's trials cannot measure the terrains' separability. "
    if all(beaten):
        return head + ("Every group's best method beats the majority share in every seed: "
                       "given a gait and frequency the simulated terrains can be told apart. ")
    if any(beaten):
        return head + ("Only some groups' best method beats the majority share in every seed: "
                       "the simulated terrains are partly separable given a gait and "
                       "frequency. ")
    return head + ("No group's best method beats the majority share in every seed: given a "
                   "gait and frequency the simulated terrains cannot be told apart reliably. ")


def separability_table(results) -> Table:
    """Leave-one-trial-out accuracy per (gait, frequency) cell, group and method, with the
    cell's majority share and chance (``ch5/separability``)."""
    ds = results.get("ch5/separability")
    if ds is None:
        return Table(id="separability", title="Separability of the simulated terrains",
                     thesis_ref="Tab. 5.1 cells", columns=["cell", "group", "trials"]
                     + BASELINE_COLUMNS, rows=[[NOT_RUN] * 5], note="")
    methods = [str(m) for m in ds["method"].values]
    rows = []
    for ci, cell in enumerate(ds["cell"].values):
        trials = ds["trials"].isel(cell=ci).values
        tr = " ".join(f"{t}{int(n)}" for t, n in zip(TERRAINS, trials) if n > 0)
        for g in ds["selection"].values:
            acc = ds["accuracy"].isel(cell=ci).sel(selection=g)
            rows.append([str(cell), str(g), tr] + [_ms(_sel(acc, method=m)) for m in methods]
                        + [fmt(float(ds["majority_share"].values[ci])),
                           fmt(float(ds["chance"].values[ci]))])
    note = (separability_verdict(ds) + "Leave-one-trial-out accuracy [% of the cell's time "
            "steps], mean ± sd over seeds; every trial classified by the method fitted on "
            "the cell's other trials, hyper-parameters fixed at the CMA-ES start point "
            f"({ds.attrs.get('hyper_parameters', '')}), no PCA, {ds.attrs.get('nodes')} "
            "hidden nodes; a terrain with a single trial in a cell is never in its own "
            "training set. Baselines: the cell's majority-class share (always answering "
            "its most frequent terrain) and chance (1 / the cell's terrains).")
    return Table(id="separability", title="Separability of the simulated terrains: "
                 "leave-one-trial-out within each gait and frequency",
                 thesis_ref="Tab. 5.1 cells",
                 columns=["cell", "group", "trials"] + [_LABELS[m] for m in methods]
                 + ["majority share", "chance"], rows=rows, note=note)


def _gen_rows(ds, table, var, label, coords) -> list:
    cells = ds[var]
    for k, v in coords.items():
        cells = _sel(cells, **{k: v})
    maj = ds["majority_share_cells"]
    return [[table, label, _ms(_sel(cells, cells="seen")), _ms(_sel(cells, cells="unseen")),
             _ms(ds["seen_share"]), _ms(_sel(maj, cells="seen")),
             _ms(_sel(maj, cells="unseen")), fmt(float(ds["chance"]))]]


def generalisation_table(results) -> Table:
    """Tab. 5.3-5.6's test accuracy split into time steps of seen / unseen (terrain, gait,
    frequency) cells, per method, with each subset's majority share."""
    rows = []
    for key, ref in (("table5_3", "Tab. 5.3"), ("table5_4", "Tab. 5.4"),
                     ("table5_5", "Tab. 5.5"), ("table5_6", "Tab. 5.6")):
        ds = results.get(f"ch5/{key}")
        if ds is None or "accuracy_cells" not in ds:
            rows.append([ref, NOT_RUN] + [NOT_RUN] * 6)
            continue
        acc = ds["accuracy_cells"]
        sel = [str(s) for s in ds["selection"].values] if "selection" in acc.dims else [None]
        nodes = [int(n) for n in ds["nodes"].values] if "nodes" in acc.dims else [None]
        for s in sel:
            for m in ds["method"].values:
                for n in nodes:
                    c = {k: v for k, v in (("selection", s), ("method", str(m)), ("nodes", n))
                         if v is not None}
                    label = " ".join(x for x in (s, _LABELS[str(m)], f"{n}N" if n else None)
                                     if x)
                    rows += _gen_rows(ds, ref, "accuracy_cells", label, c)
            if "lr_accuracy_cells" in ds:
                rows += _gen_rows(ds, ref, "lr_accuracy_cells", f"{s} LR", {"selection": s})
        if "sfa2_accuracy_cells" in ds:
            rows += _gen_rows(ds, ref, "sfa2_accuracy_cells", "minimal SFA2", {})
    return Table(id="generalisation", title="Generalisation map: test accuracy on seen and "
                 "unseen (terrain, gait, frequency) cells", thesis_ref="Tab. 5.3-5.6",
                 columns=["table", "group / method", "TEST seen", "TEST unseen",
                          "seen share of TEST", "majority share seen",
                          "majority share unseen", "chance"], rows=rows,
                 note="Accuracy [% of time steps], pooled over the two verification folds, "
                      "mean ± sd over seeds: 'seen' are the test time steps whose (terrain, "
                      "gait, frequency) cell has training trials in the fold, 'unseen' the "
                      "rest (they ask for generalisation across gaits and frequencies, which "
                      "the thesis's Fig. 5.3 finds hard); each subset's majority-class share "
                      "is its baseline.")


PROTOCOLS = (("table5_3", "primary"), ("table5_3_blocks", "blocks"),
             ("table5_3_parts", "parts"))


def protocols_table(results) -> Table:
    """Tab. 5.3's test accuracy under the primary selection protocol and its two
    sensitivity variants, side by side, with baselines and the fold-sharing measurements."""
    cols = ["group"]
    for key, label in PROTOCOLS:
        ds = results.get(f"ch5/{key}")
        name = label if ds is None else f"{label} ({ds.attrs.get('selection_mode', '?')})"
        cols += [f"{name} TEST LR", f"{name} TEST RC", f"{name} majority share",
                 f"{name} seen share", f"{name} shared recordings tuning / verification"]
    rows = []
    for s in SEL:
        row = [s]
        for key, _ in PROTOCOLS:
            ds = results.get(f"ch5/{key}")
            if ds is None or "shared_tuning" not in ds:
                row += [NOT_RUN] * 5
                continue
            row += [_ms(_sel(ds["accuracy"], selection=s, method=m, split="test"))
                    for m in ("lr", "rc")]
            row += [baselines(ds)[0], _ms(ds["seen_share"]),
                    f"{fmt(float(ds['shared_tuning'].mean()))} / "
                    f"{fmt(float(ds['shared_verification'].mean()))}"]
        rows.append(row)
    levels, remaining = [], []
    for key, label in PROTOCOLS:
        ds = results.get(f"ch5/{key}")
        if ds is not None and "remaining_trials" in ds:
            remaining.append(f"{label} {_ms(ds['remaining_trials'])}")
        if ds is not None and "selection_levels" in ds.attrs:
            lv = json.loads(str(ds.attrs["selection_levels"]))
            per = {t: sorted({v[t] for v in lv.values() if t in v}) for t in TERRAINS}
            levels.append(f"{label}: " + ", ".join(f"{t} {'/'.join(v)}" for t, v in
                                                     per.items() if v))
    return Table(id="table5_3_protocols", title="Tab. 5.3 by selection protocol",
                 thesis_ref="Tab. 5.3", columns=cols, rows=rows,
                 note="Test accuracy [% of time steps], mean ± sd over seeds. primary: the "
                      "profile's ch5.protocol.selection (claims read it); blocks: the "
                      "previous protocol (consecutive blocks, a recording cut across "
                      "selections); parts: parts across trials, whole trials assigned to one "
                      "selection (departure ch5.trial_disjoint_folds). 'shared recordings': "
                      "% of the validation (tuning) / test (verification) time steps whose "
                      "recording also feeds the fold's training side, mean over folds and "
                      "seeds. Selection level per terrain: " + ("; ".join(levels) or NOT_RUN)
                      + ". Remaining (test-only) trials: " + (", ".join(remaining) or NOT_RUN)
                      + ". " + BASELINE_NOTE)


def setup_table(results) -> Table:
    """The invented model and terrain parameters the results rest on (docs/sources.md#puppy)."""
    ds = next((results[k] for k in ("ch5/table5_3", "ch5/table5_5", "ch5/table5_4",
                                     "ch5/table5_6") if k in results), None)
    rows = []
    if ds is not None:
        cfg = json.loads(str(ds.attrs.get("recordings_config", "{}")))
        for t, mat in cfg.get("terrains", {}).items():
            rows.append([f"terrain {t}", ", ".join(f"{k} {v}" for k, v in mat.items())])
        for key in ("jitter", "noise", "gaits", "model"):
            if key in cfg:
                rows.append([key, json.dumps(cfg[key])])
    return Table(id="setup5", title="Invented simulation parameters (not from the thesis)",
                 thesis_ref="§5.3.1", columns=["what", "value"],
                 rows=rows or [[NOT_RUN, NOT_RUN]],
                 note="No public source gives Puppy II's dimensions, its terrains' materials "
                      "or the dataset (docs/sources.md#puppy): the robot "
                      "(thesis.physics.models.puppy) and "
                      "every value here are choices, fixed before any classifier ran.")


def tables(results) -> list[Table]:
    """Tab. 5.3-5.6, Tab. 5.3 by protocol, the generalisation map, the separability and
    the invented parameters."""
    return [
        _two_method(results, "table5_3", "table5_3", "Tab. 5.3", "Supervised: LR and RC per "
                    "sensor group", ("lr", "rc"), {"lr": "LR", "rc": "RC"}),
        table5_4(results),
        _two_method(results, "table5_5", "table5_5", "Tab. 5.5", "Unsupervised: SFA2 and "
                    "RC-SFA per sensor group", ("sfa2", "rc_sfa"),
                    {"sfa2": "SFA2", "rc_sfa": "RC-SFA"}),
        table5_6(results),
        protocols_table(results),
        generalisation_table(results),
        separability_table(results),
        setup_table(results),
    ]


def _fig5_3(ds, path):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 4))
    for ax, test, title in zip(axes, ("frequency", "gait"),
                               ("other frequencies (bound right)", "other gaits (1 Hz)")):
        c = _sel(ds["confusion"], test=test).sum("seed").values.astype(float)
        rows = c.sum(1, keepdims=True)
        frac = np.divide(c, rows, out=np.full_like(c, np.nan), where=rows > 0)
        ax.imshow(np.nan_to_num(frac), vmin=0, vmax=1, cmap="Greens")
        for i in range(c.shape[0]):
            for j in range(c.shape[1]):
                if rows[i, 0] > 0:
                    ax.text(j, i, f"{frac[i, j]:.2f}", ha="center", va="center", fontsize=7)
        ax.set_xticks(range(5), TERRAINS)
        ax.set_yticks(range(5), TERRAINS)
        ax.set_xlabel("predicted")
        ax.set_ylabel("true")
        ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def figures(results, outdir: Path) -> list[Figure]:
    """Fig. 5.3 (confusion matrices, time steps summed over seeds)."""
    ds = results.get("ch5/fig5_3")
    if ds is None:
        return []
    p = Path(outdir) / "fig5_3.png"
    _fig5_3(ds, p)
    rec = ds["recall"].mean("seed")
    note = "Mean recall per terrain [%]: " + "; ".join(
        f"{t}: " + ", ".join(f"{tr} {fmt(float(rec.sel(test=t, true=tr)))}"
                             for tr in ds["true"].values
                             if np.isfinite(float(rec.sel(test=t, true=tr))))
        for t in ds["test"].values)
    if "majority_share" in ds and "chance" in ds:
        note += ". Baselines [%]: majority-class share, " + "; ".join(
            f"{t} test {_ms(ds['majority_share'].sel(test=t))}" for t in ds["test"].values)
        note += (f"; chance {fmt(float(ds['chance']))} (a constant classifier's mean recall "
                 "over the terrains scored is 100 / their number)")
    note += (". Thesis: frequency test high for S, 'complete misclassification' for F (2 "
             "training trials); gait test poor for F and S, 'fairly decent' for L.")
    return [Figure(id="fig5_3", title="RC generalisation: confusion matrices",
                   thesis_ref="Fig. 5.3", path=p, note=note)]
