"""Report of chapter 6: success per configuration, minimal values, the teacher screen, the
criteria and choices the thesis leaves open, Fig. 6.4 / 6.5 / 6.6 and the success rates of
the sweeps, from ``results/<profile>/ch6/*.nc``.

Thesis numbers come from :mod:`thesis.paper`; every reproduced number is read from a
dataset; missing datasets show "not run".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thesis import paper
from thesis.claims import ch6 as claims6
from thesis.report.format import fmt, mean_spread
from thesis.report.model import NOT_RUN, Figure, Table

#: Sweeps in report order: (artifact, what the thesis says of it).
SWEEPS = (
    ("trot", "§6.5: stable, returns after power-off; §6.4: phase 1 alone fails; power-off "
             "duration not stated"),
    ("walk", "§6.5: the walk needs B = 12 and 30-s stages"),
    ("linear_feedback", "§6.3.1: not stable, does not always return"),
    ("minimal_hidden", "§6.5: B = 0 needs H = 128 ± 32"),
    ("minimal_buffer", "§6.5: H = 12 needs B >= 16"),
    ("minimal_training", "§6.5: H = 250, B = 0: 1.18-s stages suffice"),
)


def _value(key: str) -> str:
    return fmt(paper.get(key).value)


def _outcomes(row) -> str:
    vals = [str(v) for v in np.asarray(row).ravel()]
    return ", ".join(f"{o} {vals.count(o)}" for o in sorted(set(vals)))


def success_table(results) -> Table:
    """Success rate, outcomes, training MSE and speed per sweep and configuration."""
    rows = []
    for name, thesis in SWEEPS:
        ds = results.get(f"ch6/{name}")
        if ds is None:
            rows.append([name, NOT_RUN] + [""] * 8 + [thesis])
            continue
        for c in ds["config"].values:
            d = ds.sel(config=c)
            s = d["success"].values
            rows.append([
                name, str(c), str(int(d["hidden"])), str(int(d["buffer"])),
                str(int(d["n_signals"])), fmt(float(d["stage1_seconds"])),
                fmt(float(d["off_seconds"])),
                f"{int(np.nansum(s))}/{int(np.isfinite(s).sum())}", _outcomes(d["outcome"].values),
                f"{fmt(np.nanmedian(d['train_mse'].values))} / "
                f"{mean_spread(d['speed'].values, 2)}", thesis])
    note = (f"A {claims6.SUCCESS_RULE} (thesis.claims.ch6). Outcomes per seed: "
            "fallen, dies_out, erratic, no_return (the three failure modes of §6.4 and a fall) "
            "or stable (success). Speed: forward trunk speed on the last window of running.")
    return Table(id="success", title="Success of the learned controllers per configuration",
                 thesis_ref="§6.4-6.5",
                 columns=["experiment", "config", "H", "B", "N", "stage [s]", "off [s]",
                          "success", "outcomes", "train MSE [rad²] (median) / speed [m/s]",
                          "thesis"], rows=rows, note=note)


def minimal_table(results) -> Table:
    """Per-seed minimal H (B = 0), B (H = 12) and stage length (H = 250, B = 0)."""
    specs = (("minimal_hidden", "hidden", "H at B = 0", "minimal_hidden/min_hidden_neurons"),
             ("minimal_buffer", "buffer", "B at H = 12", "minimal_buffer/min_buffer_steps"),
             ("minimal_training", "stage1_seconds", "stage length [s] at H = 250, B = 0",
              "minimal_training/stage_seconds"))
    rows = []
    for name, coord, label, key in specs:
        ds = results.get(f"ch6/{name}")
        thesis = _value(key)
        if name == "minimal_hidden":
            thesis += f" ± {_value('minimal_hidden/min_hidden_neurons_uncertainty')}"
        if ds is None:
            rows.append([label, thesis, NOT_RUN, NOT_RUN])
            continue
        per = claims6.minimal_per_seed(ds["success"].values, ds[coord].values)
        grid = ", ".join(fmt(v) for v in ds[coord].values)
        shown = ", ".join("none" if not np.isfinite(v) else fmt(v) for v in per)
        rows.append([label, thesis, f"{shown} (grid {grid})", mean_spread(per)])
    return Table(id="minimal", title="Minimal controller sizes and training time per seed",
                 thesis_ref="§6.5", columns=["quantity", "thesis", "per seed", "mean ± sd"],
                 rows=rows,
                 note="Per seed: the smallest grid value from which the seed succeeds at every "
                      "larger one ('none': it fails at the largest).")


def teacher_table(results) -> Table:
    """The teacher screen: every candidate, whether it passed, the chosen ones."""
    ds = results.get("ch6/teacher")
    thesis = (f"trot at {_value('sec6.4/target_gait_frequency')} Hz, about "
              f"{_value('sec6.4/target_gait_speed')} m/s")
    if ds is None:
        return Table(id="teacher", title="Teacher screen", thesis_ref="§6.4",
                     columns=["candidate"], rows=[[NOT_RUN]], note="Thesis: " + thesis)
    chosen = {int(ds["chosen"].sel(gait=g)) for g in ds["gait"].values}
    rows = []
    for i, c in enumerate(ds["candidate"].values):
        d = ds.isel(candidate=i)
        rows.append([str(c), fmt(float(d["candidate_up_seconds"])),
                     fmt(float(d["candidate_speed"])), fmt(float(d["candidate_rec_speed"])),
                     "yes" if float(d["candidate_passed"]) == 1 else "no",
                     "teacher" if i in chosen else ""])
    fixed = ds.attrs.get("teacher_source") == "fixed"
    note = (f"Thesis: {thesis}. "
            + ("Candidates: the fixed trot and walk teachers of the configuration "
               "(ch6.teacher.fixed), at the teacher frequency" if fixed else
               "Candidates: chapter 3's optima at the teacher frequency with scaled strides")
            + ", open loop through the whole protocol incl. the power-off "
            "(thesis.ch6.teacher). Passed: upright until power-off and walking forward "
            "after power-on.")
    for g in ds["gait"].values:
        if float(ds["teacher_passed"].sel(gait=g)) != 1:
            note += (f" The fixed {g} teacher did not pass this check; the controllers learn "
                     "it all the same." if fixed else
                     f" No {g} candidate passed: the {g} teacher is the one upright longest.")
    return Table(id="teacher", title="Teacher screen (open loop)", thesis_ref="§6.4",
                 columns=["candidate", "upright [s]", "speed [m/s]", "speed after power-on "
                          "[m/s]", "passed", ""], rows=rows, note=note)


def criteria_table(results) -> Table:
    """The thresholds and protocol lengths, read from the trot dataset's attributes."""
    ds = results.get("ch6/trot")
    if ds is None:
        return Table(id="criteria", title="Success criteria and protocol", thesis_ref="§6.4",
                     columns=["setting", "value"], rows=[[NOT_RUN, ""]])
    rows = [[k, fmt(v) if isinstance(v, (int, float, np.number)) else str(v)]
            for k, v in ds.attrs.items() if k.startswith(("criteria_", "protocol_"))]
    rows.append(["controller period [s]", fmt(float(ds.attrs.get("controller_dt", np.nan)))])
    note = ("The thesis gives no numerical criteria, power-off duration or mixing schedule; "
            "these are the pipeline's choices (config ch6.criteria and ch6.protocol; "
            "thesis.departures.ch6): a linear ramp of the teacher's share in the second "
            "stage, the walk as a lateral sequence (LF .25, RF .75, LH 0, RH .5 cycles, duty "
            "0.75), the knee encoder on the motor side of the cable.")
    return Table(id="criteria", title="Success criteria and protocol (choices)",
                 thesis_ref="§6.4", columns=["setting", "value"], rows=rows, note=note)


def loop_table(results) -> Table:
    """Per seed of the base trot (H = 50, B = 5): outcome, the amplitude ratio in the first
    and last teacher period of the running stage, and the per-period multiplier of that
    amplitude (``cycle_multiplier``), which puts a number on "dies out"."""
    ds = results.get("ch6/trot")
    cols = ["seed", "outcome", "amplitude, first period", "amplitude, last period",
            "multiplier per period"]
    if ds is None or "cycle_multiplier" not in ds:
        return Table(id="loop", title="The learned loop as a dynamical system (base trot)",
                     thesis_ref="§6.4-6.5", columns=cols, rows=[[NOT_RUN] + [""] * 4])
    d = ds.sel(config=ds["config"].values[list(ds["role"].values).index("base")])
    rows = []
    for seed in d["seed"].values:
        e = d.sel(seed=seed)
        a = e["running_amplitude"].values
        a = a[np.isfinite(a)]
        rows.append([str(seed), str(e["outcome"].values),
                     fmt(a[0]) if a.size else "—", fmt(a[-1]) if a.size else "—",
                     fmt(float(e["cycle_multiplier"]))])
    m = d["cycle_multiplier"].values
    note = (f"Config {d['config'].values}. Multiplier: exp of the least-squares slope of the "
            "log amplitude ratio per teacher period over the running stage (thesis.ch6."
            "criteria.cycle_multiplier); < 1: the oscillation decays towards a fixed point "
            "by that factor per period. Median over seeds "
            f"{fmt(float(np.nanmedian(m)))}; below 0.95 in {int(np.sum(m < 0.95))} of "
            f"{int(np.isfinite(m).sum())} seeds.")
    return Table(id="loop", title="The learned loop as a dynamical system (base trot)",
                 thesis_ref="§6.4-6.5", columns=cols, rows=rows, note=note)


def tables(results) -> list[Table]:
    """Success per configuration, minimal values, the teacher screen, the criteria, the
    base trot's loop dynamics."""
    return [success_table(results), minimal_table(results), teacher_table(results),
            criteria_table(results), loop_table(results)]


# ------------------------------------------------------------------ figures
def _joint_space(ds, path, title):
    import matplotlib.pyplot as plt

    configs = list(ds["config"].values)
    fig, axes = plt.subplots(2, len(configs), figsize=(4 * len(configs), 6.5), squeeze=False,
                             sharex=True, sharey=True)
    for j, c in enumerate(configs):
        d = ds.sel(config=c)
        for seed in d["seed"].values:
            ok = float(d["success"].sel(seed=seed)) == 1
            t = d["rh_teacher"].sel(seed=seed).values
            lr = d["rh_learned"].sel(seed=seed).values
            axes[0, j].plot(t[:, 0], t[:, 1], lw=0.7, color="tab:gray")
            axes[1, j].plot(lr[:, 0], lr[:, 1], lw=0.7,
                            color="tab:green" if ok else "tab:red", alpha=0.8)
        axes[0, j].set_title(f"{c}: teacher (first seconds of stage 1)", fontsize=8)
        axes[1, j].set_title(f"learned (end of running; green: success)", fontsize=8)
        axes[1, j].set_xlabel("q_hip [rad]")
    for i in range(2):
        axes[i, 0].set_ylabel("q_knee [rad]")
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


KIND_COLOURS = {"no_window": "tab:blue", "few_hidden": "tab:orange",
                "too_few_signals": "yellowgreen"}


def _fig6_6(ds, path):
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    t = ds["train_time"].values
    for i, c in enumerate(ds["curve"].values):
        kind = str(ds["curve_kind"].values[i])
        col = KIND_COLOURS.get(kind, "k")
        cur = ds["curve_mse"].sel(curve=c).values
        for row in cur:
            a.plot(t, row, color=col, lw=0.4, alpha=0.5)
        a.plot(t, np.nanmedian(cur, axis=0), color=col, lw=1.5, label=f"{c} ({kind})")
    a.set_yscale("log")
    a.set_xlabel("training time [s]")
    a.set_ylabel("MSE [rad²], moving average over one period")
    a.legend(fontsize=6)
    n = ds["n_signals"].values
    for si, _ in enumerate(ds["seed"].values):
        s = ds["success"].values[:, si]
        m = ds["train_mse"].values[:, si]
        b.scatter(n[s == 1], m[s == 1], marker="o", color="tab:green", s=12,
                  label="success" if si == 0 else None)
        b.scatter(n[s != 1], m[s != 1], marker="x", color="tab:red", s=12,
                  label="failure" if si == 0 else None)
    b.set_xscale("log")
    b.set_yscale("log")
    b.set_xlabel("N = (B + 1) H + 1")
    b.set_ylabel("training MSE [rad²]")
    b.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def _success_rates(results, path):
    import matplotlib.pyplot as plt

    panels = (("minimal_hidden", "hidden", "H (B = 0)", "minimal_hidden/min_hidden_neurons"),
              ("minimal_buffer", "buffer", "B (H = 12)", "minimal_buffer/min_buffer_steps"),
              ("minimal_training", "stage1_seconds", "stage length [s] (H = 250, B = 0)",
               "minimal_training/stage_seconds"),
              ("trot", "off_seconds", "motors-off duration [s] (H = 50, B = 5)", None))
    fig, axes = plt.subplots(2, 2, figsize=(9, 6))
    for ax, (name, coord, label, key) in zip(axes.ravel(), panels):
        ds = results.get(f"ch6/{name}")
        if ds is not None and name == "trot":  # the base and its power-off variants
            ds = ds.isel(config=np.flatnonzero(ds["role"].values != "phase1_only"))
        ax.set_xlabel(label)
        ax.set_ylabel("success rate")
        ax.set_ylim(-0.05, 1.05)
        if ds is None:
            ax.set_title(f"{name}: {NOT_RUN}", fontsize=8)
            continue
        x = ds[coord].values.astype(float)
        order = np.argsort(x)
        rate = np.nanmean(ds["success"].values, axis=1)
        ax.plot(x[order], rate[order], "o-")
        ax.axhline(claims6.WORKS_RATE, color="tab:green", ls=":", lw=1)
        ax.axhline(claims6.FAILS_RATE, color="tab:red", ls=":", lw=1)
        if key is not None:
            ax.axvline(paper.get(key).value, color="k", ls="--", lw=1, label="thesis")
            ax.legend(fontsize=7)
        ax.set_title("trot: power-off sweep" if name == "trot" else name, fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def figures(results, outdir: Path) -> list[Figure]:
    """Fig. 6.4, Fig. 6.5, Fig. 6.6 and the success rates of the sweeps."""
    outdir = Path(outdir)
    out = []
    for fid, ref, title in (("fig6_4", "Fig. 6.4", "Right hind leg in joint space: trot"),
                            ("fig6_5", "Fig. 6.5", "Right hind leg in joint space: walk")):
        ds = results.get(f"ch6/{fid}")
        if ds is not None:
            p = outdir / f"{fid}.png"
            _joint_space(ds, p, title)
            out.append(Figure(id=fid, title=title, thesis_ref=ref, path=p))
    ds = results.get("ch6/fig6_6")
    if ds is not None:
        p = outdir / "fig6_6.png"
        _fig6_6(ds, p)
        out.append(Figure(id="fig6_6", title="Training MSE over time and against N",
                          thesis_ref="Fig. 6.6", path=p))
    if any(f"ch6/{n}" in results for n in ("minimal_hidden", "minimal_buffer",
                                           "minimal_training", "trot")):
        p = outdir / "success_rates.png"
        _success_rates(results, p)
        rates = [results[k]["robot_seconds_per_wall_second"] for k in sorted(results)
                 if "robot_seconds_per_wall_second" in results[k]]
        note = "" if not rates else (
            "simulation rate " + ", ".join(f"{fmt(float(r))}" for r in rates)
            + " robot-s per wall-s (per experiment, wall clock)")
        out.append(Figure(id="success_rates", title="Success rate along each sweep",
                          thesis_ref="§6.5", path=p, note=note))
    return out
