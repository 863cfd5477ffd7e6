"""Chapter 2 in the report: Tab. 2.2 (thesis beside reproduced), training curves, scaling,
and the measurements behind the chapter's configured sizes.

Reads ``ch2/table2_2`` (test_error over model x d x transform x seed, valid_error over
epoch), ``ch2/chirpz_scaling`` (median times over layer x pass x size) and, when
present, ``ch2/width_pilot`` and ``ch2/train_step`` (:mod:`thesis.report.pilots`). Every
number shown is read from those datasets or from :mod:`thesis.paper`; a missing dataset
shows "not run".
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from thesis import paper
from thesis.report import pilots
from thesis.report.format import mean_interval_text
from thesis.report.model import NOT_RUN, Figure, Table

MODELS = ("ffn_spn", "rnn_spn")
DS = (1, 2, 3)
TRANSFORMS = ("bilinear", "bilinear_no_skew", "chirp_z", "none")
HEAD = {"bilinear": "bilinear", "bilinear_no_skew": "bilinear no skew", "chirp_z": "chirp-Z",
        "none": "no spatial"}
LABEL = {"ffn_spn": "FFN-SPN", "rnn_spn": "RNN-SPN"}


def _thesis(model: str, d: int, t: str) -> str:
    try:
        v = paper.get(f"table2_2/model={model}/d={d}/transform={t}/test_error")
    except KeyError:
        return NOT_RUN
    return f"{v.value:.1f}" if v.value is not None else NOT_RUN  # printed with one decimal


def _reproduced(ds, model: str, d: int, t: str) -> str:
    if ds is None or "test_error" not in ds:
        return NOT_RUN
    da = ds["test_error"]
    try:
        vals = da.sel(model=model, d=d, transform=t).values
    except (KeyError, IndexError, ValueError):
        return NOT_RUN
    scale = 100.0 if da.attrs.get("units", "1") == "1" else 1.0
    return mean_interval_text(np.asarray(vals, float) * scale)


def tables(results: dict) -> list[Table]:
    """Tab. 2.2: per-digit test error [%] per (model, d) row and transform, thesis value
    beside the reproduced mean over seeds with its 95 % Student t interval; then the width
    pilot's and the training-step bench's tables (:func:`thesis.report.pilots.tables`)."""
    ds = results.get("ch2/table2_2")
    columns = ["model"]
    for t in TRANSFORMS:
        columns += [f"{HEAD[t]}: thesis (%)", f"{HEAD[t]}: reproduced (%)"]
    rows = []
    for m in MODELS:
        for d in DS:
            row = [f"{LABEL[m]} d={d}"]
            for t in TRANSFORMS:
                row += [_thesis(m, d, t), _reproduced(ds, m, d, t)]
            rows.append(row)
    if ds is None:
        note = "ch2/table2_2 not run."
    else:
        a = ds.attrs
        note = ("Reproduced: mean [95 % Student t interval] over seeds "
                f"{[int(s) for s in np.atleast_1d(a.get('seeds', []))]}; "
                f"{a.get('n_train')} training / {a.get('n_valid')} validation / "
                f"{a.get('n_test')} test sequences, at most {_epochs(a.get('max_epochs'))} epochs "
                f"of {_epoch_size(a)} "
                f"(patience {a.get('patience')}), batch {a.get('batch_size')}, "
                f"{a.get('optimizer')} lr {a.get('learning_rate')}; widths {a.get('widths')}; "
                f"digits: {a.get('digit_source')}; d run: {[int(d) for d in ds['d'].values]} "
                "(other rows: not run). 'no spatial' has no down-sampling and is "
                "trained once per model and seed, shown in every d row (thesis: ditto marks).")
    return [Table(id="table2_2", title="Per-digit test error on cluttered MNIST sequences",
                  thesis_ref="Tab. 2.2", columns=columns, rows=rows, note=note),
            *pilots.tables(results)]


def _epoch_size(attrs) -> str:
    """What one epoch is (``epoch_sequences`` attribute; 0 or absent: a whole pass)."""
    n = int(attrs.get("epoch_sequences", 0) or 0)
    return f"{n} sequences (a stream of shuffled passes)" if n else "a whole pass"


def _epochs(attr) -> str:
    """The ``max_epochs`` attribute, a number or JSON ``{model: epochs}``, as text."""
    try:
        per = json.loads(attr) if isinstance(attr, str) else attr
    except ValueError:
        return str(attr)
    if isinstance(per, dict):
        return ", ".join(f"{LABEL.get(m, m)} {n}" for m, n in per.items()) or "?"
    return str(per)


def _curves(ds, outdir: Path) -> Figure | None:
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    if ds is None or "valid_error" not in ds:
        return None
    ve = ds["valid_error"]
    fig, axes = plt.subplots(len(ds["model"]), len(ds["d"]), figsize=(4 * len(ds["d"]),
                             3.2 * len(ds["model"])), squeeze=False, sharey=True)
    epochs = ds["epoch"].values
    colors = {"bilinear": "C0", "bilinear_no_skew": "C1", "chirp_z": "C2", "none": "C7"}
    for i, m in enumerate(ds["model"].values):
        for j, d in enumerate(ds["d"].values):
            ax = axes[i, j]
            for t in ds["transform"].values:
                v = 100 * ve.sel(model=m, d=d, transform=t).values  # (seed, epoch)
                v = np.atleast_2d(v)
                if not np.isfinite(v).any():
                    continue
                ran = np.isfinite(v).any(axis=0)  # a model that trains fewer epochs
                v, ep = v[:, ran], epochs[ran]
                mean = np.nanmean(v, axis=0)
                ax.plot(ep, mean, color=colors.get(str(t)), label=HEAD.get(str(t), str(t)))
                if v.shape[0] > 1:
                    ax.fill_between(ep, np.nanmin(v, axis=0), np.nanmax(v, axis=0),
                                    color=colors.get(str(t)), alpha=0.15, lw=0)
            ax.set_title(f"{LABEL.get(str(m), m)}, d={int(d)}")
            ax.xaxis.set_major_locator(MaxNLocator(integer=True))
            ax.set_xlabel("epoch")
            if j == 0:
                ax.set_ylabel("validation error per digit (%)")
            ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8)
    fig.tight_layout()
    path = Path(outdir) / "training_curves.png"
    fig.savefig(path)
    plt.close(fig)
    return Figure(id="training_curves", title="Validation error during training (mean over "
                  "seeds, band = min-max)", thesis_ref="Tab. 2.2", path=path,
                  note=f"{ds.attrs.get('n_train')} training sequences; an epoch is "
                       f"{ds.attrs.get('epoch_sequences') or 'a pass over them'}"
                       " sequences.")


def _scaling(ds, outdir: Path) -> Figure | None:
    import matplotlib.pyplot as plt

    if ds is None or "seconds" not in ds:
        return None
    n = ds["size"].values.astype(float)
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for layer, color in zip(ds["layer"].values, ("C2", "C1", "C0")):
        for p, style in zip(ds["pass"].values, ("-", "--")):
            t = ds["seconds"].sel(layer=layer, **{"pass": p}).values
            b = float(ds["exponent_n2logn"].sel(layer=layer, **{"pass": p}))
            ax.loglog(n, t, style, marker="o", color=color,
                      label=f"{layer} {p.replace('_', '+')} (b={b:.2f})")
    ref = n**2 * np.log(n)
    t0 = float(ds["seconds"].sel(layer=ds["layer"].values[0], **{"pass": "forward"}).values[-1])
    ax.loglog(n, ref / ref[-1] * t0, ":", color="k", label="∝ n² log n")
    ax.set_xlabel("image side n (px)")
    ax.set_ylabel(f"median time per batch of {ds.attrs.get('batch')} (s)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    path = Path(outdir) / "chirpz_scaling.png"
    fig.savefig(path)
    plt.close(fig)
    return Figure(id="chirpz_scaling", title="Cost of the chirp-Z layer and the bilinear "
                  "sampler against image size; b = fitted exponent of t ∝ (n² log n)^b",
                  thesis_ref="§2.4", path=path,
                  note=f"backend {ds.attrs.get('backend')}, {ds.attrs.get('repeats')} timed "
                  "runs after compilation (median).")


def figures(results: dict, outdir: Path) -> list[Figure]:
    """Training curves of Tab. 2.2's runs and the §2.4 scaling plot (PNG in ``outdir``)."""
    out = []
    for f in (_curves(results.get("ch2/table2_2"), outdir),
              _scaling(results.get("ch2/chirpz_scaling"), outdir)):
        if f is not None:
            out.append(f)
    return out
