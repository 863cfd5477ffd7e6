"""Report section of the Oncilla model's own checks, from
``results/<profile>/model/oncilla*.nc`` (``thesis bench oncilla``; a second model's
dataset, written with ``--output results/<profile>/model/oncilla_<label>.nc``, sits beside
the first and is shown beside it, by its ``model_label``); the validation tables
(:mod:`thesis.report.validation`) and the Puppy II's paw contact
(:mod:`thesis.report.puppy_contact`, ``thesis bench puppy-contact``) and its terrains
across gaits (:mod:`thesis.report.puppy_heldout`, ``thesis bench puppy-heldout``) follow.

No thesis numbers: the checks measure the simulated robot, not a claim. Every number is
read from a dataset; without one the section says "not run".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thesis.report.format import fmt
from thesis.report.model import NOT_RUN, Figure, Table

#: Parameters of the fall-rate figure: dataset name, axis label.
BINNED = (("a", "a [mm]"), ("x0", "x0 [mm]"), ("f", "f [Hz]"))


def _datasets(results: dict) -> list[tuple[str, object]]:
    """(label, dataset) of every ``model/oncilla*`` result, in key order."""
    out = []
    for key in sorted(results):
        if key.startswith("model/oncilla"):
            ds = results[key]
            out.append((str(ds.attrs.get("model_label", key.split("/", 1)[1])), ds))
    return out


def _pct(x) -> str:
    x = float(x)
    return "—" if not np.isfinite(x) else f"{100 * x:.0f} %"


def _push_words(ds, posture: str) -> str:
    """'recovered up to J N s; fell from J N s' for one posture (pushes > 0; whether the
    unpushed run fell is said apart)."""
    d = ds.sel(posture=posture)
    push = d["push"].values
    fell = d["push_fallen"].values.astype(bool)
    before = d["push_fell_before"].values.astype(bool)
    pushed = push > 0
    ok = push[~fell & ~before & pushed]
    bad = push[fell & ~before & pushed]
    words = [f"recovered up to {fmt(ok.max())} N s" if ok.size else "recovered from none"]
    if bad.size:
        words.append(f"fell from {fmt(bad.min())} N s")
    if (fell & ~before & ~pushed).any():
        words.append("the unpushed run fell too")
    if before.any():
        words.append(f"down before the push at {', '.join(fmt(v) for v in push[before])} N s")
    return "; ".join(words)


def summary_table(results) -> Table:
    """One column per measured model: standing, fall rates, pushes, encoder R^2."""
    sets = _datasets(results)
    labels = [lab for lab, _ in sets] or ["current"]
    rows_spec = [
        ("standing trunk height [m] (nominal)", lambda d: (
            f"{float(d['stand_trunk_height']):.4f} ({float(d['nominal_trunk_height']):.4f})")),
        ("standing CoM height [m] (build pose)", lambda d: (
            f"{float(d['stand_com_height']):.4f} ({float(d['nominal_com_height']):.4f})")),
        ("standing toe depth below hip [mm] (nominal)", lambda d: (
            f"{-1e3 * float(d['stand_toe'].sel(axis='z').mean()):.1f} "
            f"({-1e3 * float(d['nominal_toe'].sel(axis='z').mean()):.1f})")),
        ("random Tab. 4.1 trots that fell", lambda d: (
            f"{_pct(d['fall_rate'])} of {d.sizes['gait']}")),
        ("random trots that fell by rolling over sideways", lambda d: (
            _pct(d["roll_fall_rate"]))),
        ("lateral push, standing", lambda d: _push_words(d, "standing")),
        ("lateral push, trotting the nominal gait", lambda d: _push_words(d, "trotting")),
        ("encoder R^2 on contact forces, nominal trot (mean of 8)", lambda d: (
            f"{float(np.nanmean(d['encoder_r2_forces_nominal'])):.2f}")),
        ("encoder R^2 on the command, nominal trot", lambda d: (
            f"{float(np.nanmean(d['encoder_r2_command_nominal'])):.2f}")),
        ("share of the rest the forces explain, nominal trot", lambda d: (
            f"{float(np.nanmean(d['encoder_r2_forces_given_command_nominal'])):.2f}")),
        ("encoder R^2 on contact forces beyond the gait phase, nominal trot", lambda d: (
            f"{float(np.nanmean(d['encoder_r2_forces_beyond_phase_nominal'])):.2f}")),
        ("same, mean over the random trots used", lambda d: (
            f"{float(np.nanmean(d['encoder_r2_forces_beyond_phase_mean'])):.2f} "
            f"({int(d['encoder_gaits_used'])} trots)")),
        ("share of the rest the forces explain, mean over the random trots", lambda d: (
            f"{float(np.nanmean(d['encoder_r2_forces_given_command_mean'])):.2f} "
            f"({int(d['encoder_gaits_used'])} trots)")),
    ]
    rows = []
    for name, fn in rows_spec:
        rows.append([name] + ([fn(ds) for _, ds in sets] if sets else [NOT_RUN]))
    note = ""
    if sets:
        ds = sets[0][1]
        note = (f"Flat floor, untethered; random trots uniform over Tab. 4.1's ranges from "
                f"standstill, {ds.attrs.get('settle')} s settle then "
                f"{ds.attrs.get('seconds')} s; fallen: trunk below "
                f"{ds.attrs.get('fall_height')} m or tilted beyond 60 degrees. Push: "
                f"a sideways impulse on the trunk {ds.attrs.get('push_time')} s into the "
                "gait or standing. Encoders: the 8 hip and knee encoders as chapter 6 reads "
                "them, minus their command; R^2 of linear fits on the 12 toe contact-force "
                "components and on the joint's last command samples; 'beyond the gait "
                "phase': both signals minus their fit by the gait phase's first "
                f"{ds.attrs.get('phase_harmonics', 10)} harmonics. Models: "
                + "; ".join(f"{lab} (model code {str(d.attrs.get('model_code_sha256', ''))[:10]})"
                            for lab, d in sets) + ".")
    return Table(id="oncilla_checks", title="Model-level checks of the simulated Oncilla",
                 thesis_ref="Tab. 4.1, §4.5, §6.1", columns=["check"] + labels, rows=rows,
                 note=note)


def tables(results) -> list[Table]:
    from thesis.report import puppy_contact, puppy_heldout, validation

    return [summary_table(results), *validation.tables(results),
            *puppy_contact.tables(results), *puppy_heldout.tables(results)]


def figures(results, outdir: Path) -> list[Figure]:
    """Fall rate of the random trots against a, x0 and f, one line per model."""
    sets = _datasets(results)
    if not sets:
        return []
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(BINNED), figsize=(10, 3.2), sharey=True)
    for ax, (name, label) in zip(axes, BINNED):
        for lab, ds in sets:
            n = ds[f"gaits_by_{name}"].values
            ax.plot(ds[f"{name}_bin"].values, 100 * ds[f"fall_rate_by_{name}"].values,
                    marker="o", label=f"{lab} (n = {int(n.sum())})")
        ax.set_xlabel(label)
        ax.set_ylim(-5, 105)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("fallen [%]")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    path = Path(outdir) / "oncilla_fall_rate.png"
    fig.savefig(path)
    plt.close(fig)
    return [Figure(id="oncilla_fall_rate", thesis_ref="Tab. 4.1",
                   title="Random Tab. 4.1 trots from standstill on a flat floor, untethered: "
                         "share that fell, per bin of a, x0 and f",
                   path=path)]
