"""Report of chapter 4: Tab. 4.2-4.4 beside the thesis's, the per-condition rank-sum
statistics, fallen evaluations, the simulation choices the thesis does not fix, and
Fig. 4.3, 4.5-4.10 and the safety thread's effect, from ``results/<profile>/ch4/*.nc``.

Thesis numbers come from :mod:`thesis.paper`; every reproduced number is read from a
dataset, as mean ± standard deviation over seeds; missing datasets show "not run".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thesis import paper
from thesis.departures import ch4 as departures
from thesis.report.format import fmt, mean_spread
from thesis.report.plotting import save_figure
from thesis.report.model import NOT_RUN, Figure, Table

#: Columns of Tab. 4.2-4.4 as printed (parameters in the thesis's order).
PRINT_ORDER = ("f", "a", "x0", "y0r", "y0f", "t_stance", "l0f", "l1f", "l0r", "l1r", "l2", "l3")
TL, RAND = "tab:green", "tab:orange"


def _paper(artifact, variable, **coords) -> str:
    hits = paper.select(artifact, variable, **coords)
    return fmt(hits[0].value) if hits else "—"


def _cell(thesis: str, ds, var: str, digits: int = 3, **sel) -> str:
    got = NOT_RUN
    if ds is not None:
        v = ds[var].sel(sel).values if var in ds else None
        got = NOT_RUN if v is None else mean_spread(v, digits)
    return f"{thesis} / {got}"


def _best_table(results, key, tid, title, ref, dim, rows) -> Table:
    """rows: (label, {dim: level, transfer: t, [rank: r]}) in print order."""
    ds = results.get(f"ch4/{key}")
    out = []
    for label, sel in rows:
        psel = {k: v for k, v in sel.items()}
        row = [label, "yes" if sel["transfer"] else "no"]
        for p in PRINT_ORDER:
            row.append(_cell(_paper(key, p, **psel), ds, "value", parameter=p, **sel))
        row.append(_cell(_paper(key, "speed", **psel), ds, "speed", **sel))
        row.append(_cell("—", ds, "reeval_speed", **sel))
        row.append(_cell("—", ds, "reeval_taut", 2, **sel))
        row.append(_cell(_paper(key, "euclidean_distance", **psel), ds, "euclidean_distance",
                         **sel))
        row.append(NOT_RUN if ds is None else mean_spread(ds["best_generation"].sel(sel).values, 2))
        out.append(row)
    note = ("Each cell: thesis (one run) / reproduced (mean ± sd over seeds). Speed: in-run "
            "speed of the best particle (the thesis's); re-evaluated: the same particle from "
            "standstill, every repeat and seed pooled; thread taut: the fraction of those "
            "windows with a safety thread taut (0 = walked free, as on the thesis's loose "
            "thread). Distances are in range-normalised units (at most 3.46), the thesis's "
            "normalisation is unknown: compare orderings only. Absolute speeds belong to the "
            "simulated Oncilla, not the robot.")
    if ds is not None:
        note += " Sizes: " + ", ".join(f"{k}={ds.attrs[k]}" for k in
                                       ("particles", "generations", "run_seconds",
                                        "transition_seconds") if k in ds.attrs)
    return Table(id=tid, title=title, thesis_ref=ref,
                 columns=["row", "transfer", *PRINT_ORDER, "speed [m/s]",
                          "re-evaluated speed [m/s]", "thread taut (re-evaluated)",
                          "Euclidean distance", "generation of the best"], rows=out, note=note)


def table4_2(results) -> Table:
    ds = results.get("ch4/table4_2")
    grades = [9, 18] if ds is None else [int(g) for g in ds["grade"].values if g != 0]
    rows = [("flat", dict(grade=0, transfer=0))]
    for g in grades:
        rows += [(f"{g} %", dict(grade=g, transfer=t)) for t in (0, 1)]
    return _best_table(results, "table4_2", "table4_2", "Best particles per grade",
                       "Tab. 4.2", "grade", rows)


def table4_3(results) -> Table:
    rows = [("normal", dict(stiffness="normal", transfer=0))]
    rows += [("compliant", dict(stiffness="compliant", transfer=t)) for t in (0, 1)]
    return _best_table(results, "table4_3", "table4_3",
                       "Best particles with normal and softer front legs", "Tab. 4.3",
                       "stiffness", rows)


def table4_4(results) -> Table:
    rows = [("normal", dict(terrain="normal", transfer=0, rank=1)),
            ("pebbly", dict(terrain="pebbly", transfer=0, rank=1)),
            ("pebbly", dict(terrain="pebbly", transfer=1, rank=1)),
            ("pebbly (best after generation 0)", dict(terrain="pebbly", transfer=1, rank=2))]
    return _best_table(results, "table4_4", "table4_4",
                       "Best particles on normal and pebbly terrain", "Tab. 4.4", "terrain",
                       rows)


def _runs(results):
    """(label, dataset, selection, thesis p bound text) per target condition."""
    out = []
    f45 = results.get("ch4/fig4_5")
    if f45 is not None:
        for g in f45["grade"].values:
            out.append((f"{int(g)} % grade", f45.sel(grade=g),
                        f"< {_paper('fig4_5', 'p_value_upper_bound', grade=int(g))}"))
    for key, label, var in (("fig4_7", "softer front legs", "p_value_upper_bound"),
                            ("fig4_8", "pebbles", "p_value_lower_bound")):
        ds = results.get(f"ch4/{key}")
        if ds is not None:
            out.append((label, ds, ("< " if "upper" in var else "> ") + _paper(key, var)))
    return out


def ranksum_table(results) -> Table:
    rows = []
    for label, ds, bound in _runs(results):
        p = ds["fisher_greater"].values
        p2 = ds["fisher_two_sided"].values
        a12 = ds["a12"].mean("generation").values
        rows.append([label, bound, f"{fmt(np.median(p))} [{fmt(p.min())}, {fmt(p.max())}]",
                     f"{fmt(np.median(p2))} [{fmt(p2.min())}, {fmt(p2.max())}]",
                     mean_spread(a12, 3), mean_spread(ds["a12"].sel(generation=0).values, 3),
                     str(len(p))])
    if not rows:
        rows = [[NOT_RUN] * 7]
    return Table(id="ranksum", title="Transfer against random initialisation, generation by "
                                     "generation", thesis_ref="§4.6",
                 columns=["condition", "thesis p", "Fisher p, transfer greater: median "
                          "[min, max] over seeds", "two-sided: median [min, max]",
                          "mean Vargha-Delaney A", "A in generation 0", "seeds"],
                 rows=rows,
                 note="Per seed, a Wilcoxon rank-sum test of the transferred against the random "
                      "swarm's scores in every generation, combined with Fisher's method (the "
                      "thesis's statistic for its single run); A = P(a transferred particle "
                      "outscores a random one), 0.5 = no difference. The verdicts are the "
                      "claims below (rule 9 of thesis.claims.stats).")


def falls_table(results) -> Table:
    rows = []
    flat = results.get("ch4/flat")
    if flat is not None:
        ff = flat["fallen"].mean("particle")
        rows.append(["flat (source run)", "no", mean_spread(ff.isel(generation=0).values, 2),
                     mean_spread(ff.isel(generation=-1).values, 2),
                     mean_spread(ff.mean("generation").values, 2), _resets(flat),
                     _taut(flat)])
    for label, ds, _ in _runs(results):
        for t in (0, 1):
            ff = ds["fall_fraction"].sel(transfer=t)
            rows.append([label, "yes" if t else "no",
                         mean_spread(ff.isel(generation=0).values, 2),
                         mean_spread(ff.isel(generation=-1).values, 2),
                         mean_spread(ff.mean("generation").values, 2),
                         _resets(ds.sel(transfer=t)), "—"])
    tether = results.get("ch4/tether")
    if tether is not None:
        for t, label in ((1, "flat, with the thread"), (0, "flat, same evaluations without")):
            ff = tether["fall_fraction"].sel(tether=t)
            rows.append([label, "no", mean_spread(ff.isel(generation=0).values, 2),
                         mean_spread(ff.isel(generation=-1).values, 2),
                         mean_spread(ff.mean("generation").values, 2),
                         _resets(tether.sel(tether=t)), _taut(tether.sel(tether=t))])
    if not rows:
        rows = [[NOT_RUN] * 7]
    return Table(id="falls", title="Fraction of fallen evaluations", thesis_ref="§4.5",
                 columns=["run", "transfer", "first generation", "last generation",
                          "all generations", "set back on its feet per generation",
                          "thread taut: standing / fallen evaluations"],
                 rows=rows,
                 note="On the treadmill an assistant intervened on unstable gaits; here a fall "
                      "scores -2 + the fraction of the window the robot stayed up, below every "
                      "gait that walks (departure ch4.fall_handling). A robot that was down "
                      "when its window began, having entered from another gait, was set back "
                      "on its feet at its start pose and is not counted as fallen unless it "
                      "fell again in the gait under test; set back: the mean number of such "
                      "evaluations per generation (departure ch4.fall_reset). Thread taut: "
                      "the mean fraction of the window with a safety thread taut, over the "
                      "evaluations that stayed up and over those that fell (departure "
                      "ch4.tether; the thesis's thread was loose during normal operation).")


def _resets(ds) -> str:
    """Mean ± sd over seeds of the robots set back on their feet per generation."""
    if "reset_count" not in ds:
        return "—"
    return mean_spread(ds["reset_count"].mean("generation").values, 2)


def _taut(ds) -> str:
    """Mean taut fraction of the safety thread over standing / fallen evaluations of ``ds``."""
    if "taut" not in ds:
        return "—"
    taut, fell = ds["taut"].values, ds["fallen"].values.astype(bool)
    up = fmt(float(taut[~fell].mean()), 2) if (~fell).any() else "—"
    down = fmt(float(taut[fell].mean()), 2) if fell.any() else "—"
    return f"{up} / {down}"


def choices_table(results) -> Table:
    rows = [[d.id, d.kind, d.thesis, d.ours, d.why] for d in departures.DEPARTURES]
    return Table(id="choices", title="Simulation choices and deviations", thesis_ref="Ch. 4",
                 columns=["id", "kind", "thesis", "this reproduction", "why"], rows=rows,
                 note="Declared in thesis.departures.ch4; the configuration values are in the "
                      "results' provenance.")


def timing_table(results) -> Table:
    rows = []
    for key in ("flat", "transfer_slopes", "transfer_compliant", "transfer_pebbly", "tether"):
        ds = results.get(f"ch4/{key}")
        if ds is None or "simulated_robot_seconds" not in ds:
            continue
        rows.append([key, fmt(float(ds["simulated_robot_seconds"]), 4),
                     fmt(float(ds["rollout_wall_seconds"]), 3),
                     fmt(float(ds["robot_seconds_per_wall_second"]), 3),
                     fmt(float(ds["robot_seconds_per_cpu_second"]), 3)])
    if not rows:
        rows = [[NOT_RUN] * 5]
    return Table(id="simulation_rate", title="Simulated robot time", thesis_ref="§4.5",
                 columns=["run", "simulated robot-seconds", "rollout wall seconds",
                          "robot-s per wall-s", "robot-s per CPU-s"], rows=rows,
                 note="Wall-clock figures depend on the machine and its load; the rates leave "
                      "out each compiled shape's first call.")


def tables(results) -> list[Table]:
    """Tab. 4.2-4.4, the rank-sum statistics, falls, choices and simulated time."""
    return [table4_2(results), table4_3(results), table4_4(results), ranksum_table(results),
            falls_table(results), choices_table(results), timing_table(results)]


# ------------------------------------------------------------------ figures


def _scores_panel(ax, ds, title):
    gens = ds["generation"].values
    for t, colour, marker, dx in ((1, TL, "^", 0.12), (0, RAND, "v", -0.12)):
        sc = ds["score"].sel(transfer=t).values  # (G, N)
        for g, row in zip(gens, sc):
            ax.scatter(np.full(row.size, g + dx), row, s=9, c=colour, marker=marker, lw=0)
        ax.plot(gens + dx, np.median(sc, axis=1), color=colour, lw=1)
    ax.axhline(-1.0, color="k", lw=0.5, ls=":")
    ax.set_title(title, fontsize=8)
    ax.set_xlabel("generation", fontsize=8)
    ax.tick_params(labelsize=7)


def _fig_scores(ds, path, rows):
    import matplotlib.pyplot as plt

    seeds = list(ds["seed"].values)
    fig, axes = plt.subplots(len(rows), len(seeds), figsize=(2.2 * len(seeds), 2.4 * len(rows)),
                             squeeze=False, sharey=True)
    for r, (label, sub) in enumerate(rows):
        for c, s in enumerate(seeds):
            one = sub.sel(seed=s)
            _scores_panel(axes[r, c], one, f"{label}, seed {s}, p = "
                                           f"{fmt(float(one['fisher_greater']), 2)}")
        axes[r, 0].set_ylabel("score [m/s] (fallen < -1)", fontsize=8)
    save_figure(fig, path)


def _ellipse(ax, mean, cov, colour):
    vals, vecs = np.linalg.eigh(cov)
    vals = np.maximum(vals, 0.0)
    t = np.linspace(0, 2 * np.pi, 100)
    circle = np.stack([np.cos(t), np.sin(t)])
    pts = mean[:, None] + vecs @ (2.0 * np.sqrt(vals)[:, None] * circle)
    ax.plot(pts[0], pts[1], color=colour, lw=1)
    ax.plot(*mean, "o", color=colour, ms=4)


def _fig4_6(ds, path):
    import matplotlib.pyplot as plt

    s = ds["seed"].values[0]
    one = ds.sel(seed=s)
    fig, axes = plt.subplots(1, 2, figsize=(8, 3.6))
    colours = plt.cm.viridis(np.linspace(0, 0.85, one.sizes["grade"]))
    for ax, (px, py) in zip(axes, (("a", "t_stance"), ("x0", "y0r"))):
        for g, colour in zip(one["grade"].values, colours):
            v = one["value"].sel(grade=g)
            ax.scatter(v.sel(parameter=px), v.sel(parameter=py), s=8, color=colour,
                       label=f"{int(g)} %")
            m = one["mean"].sel(grade=g, parameter=[px, py]).values
            c = one["covariance"].sel(grade=g, parameter=[px, py], parameter_b=[px, py]).values
            _ellipse(ax, m, c, colour)
        ax.set_xlabel(px)
        ax.set_ylabel(py)
        ax.legend(fontsize=7)
    fig.suptitle(f"seed {s}: {one.sizes['top']} best particles per grade", fontsize=9)
    save_figure(fig, path)


def _fig4_9(ds, path):
    import matplotlib.pyplot as plt

    seeds = list(ds["seed"].values)
    fig, axes = plt.subplots(1, len(seeds), figsize=(2.6 * len(seeds), 2.8), squeeze=False,
                             sharey=True)
    for ax, s in zip(axes[0], seeds):
        one = ds.sel(seed=s)
        for t, colour, m, m0 in ((1, TL, "+", "^"), (0, RAND, "x", "v")):
            x0 = one["x0"].sel(transfer=t).values
            a = one["a"].sel(transfer=t).values
            ax.scatter(x0[1:].ravel(), a[1:].ravel(), s=10, c=colour, marker=m, lw=0.8)
            ax.scatter(x0[0], a[0], s=14, c=colour, marker=m0, edgecolors="k", lw=0.3)
        ax.plot(ds["x0_edge"].values, ds["a_max"].values, "k-", lw=1)
        ax.set_xlabel("x0 [mm]", fontsize=8)
        ax.set_title(f"seed {s}", fontsize=8)
    axes[0, 0].set_ylabel("a [mm]", fontsize=8)
    save_figure(fig, path)


def _fig4_10(ds, path):
    import matplotlib.pyplot as plt

    conds = list(ds["condition"].values)
    fig, axes = plt.subplots(1, len(conds), figsize=(2.8 * len(conds), 2.8), squeeze=False,
                             sharey=True)
    g = ds["generation"].values
    for ax, c in zip(axes[0], conds):
        for t, colour, m in ((1, TL, "^"), (0, RAND, "v")):
            v = ds["search_space_size"].sel(condition=c, transfer=t)
            ax.plot(g, v.mean("seed"), color=colour, marker=m, ms=4)
            ax.fill_between(g, v.min("seed"), v.max("seed"), color=colour, alpha=0.2)
        ax.set_title(str(c), fontsize=8)
        ax.set_xlabel("generation", fontsize=8)
    axes[0, 0].set_ylabel("search-space size", fontsize=8)
    save_figure(fig, path)


def _fig4_3(ds, path):
    import matplotlib.pyplot as plt

    one = ds.sel(seed=ds["seed"].values[0])
    ex = list(one["example"].values)
    fig, axes = plt.subplots(1, len(ex), figsize=(2.8 * len(ex), 1.9), squeeze=False)
    for ax, e in zip(axes[0], ex):
        for foot, ls in (("fore", "-"), ("hind", "--")):
            y = one["y"].sel(example=e, foot=foot).values
            x = one["x"].sel(example=e, foot=foot).values
            ax.plot(np.append(y, y[0]), np.append(x, x[0]), ls, label=foot)  # closed cycle
        ax.set_xlim(-110, 110)
        ax.set_ylim(175, 95)  # depth grows downwards, as seen from the side
        ax.set_aspect("equal")
        ax.set_title(str(e).replace("_", " "), fontsize=8)
        ax.set_xlabel("y [mm]", fontsize=8)
    axes[0, 0].set_ylabel("x (depth below hip) [mm]", fontsize=8)
    axes[0, 0].legend(fontsize=7)
    save_figure(fig, path)


def _fig_tether(ds, path):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3))
    g = ds["generation"].values
    for t, colour, label in ((1, "tab:blue", "with the thread"), (0, "tab:red", "without")):
        ff = ds["fall_fraction"].sel(tether=t)
        ax.plot(g, ff.mean("seed"), color=colour, marker="o", ms=3, label=label)
        ax.fill_between(g, ff.min("seed"), ff.max("seed"), color=colour, alpha=0.15)
    ax.set_xlabel("generation")
    ax.set_ylabel("fraction fallen")
    ax.set_ylim(0, 1)
    ax.legend(fontsize=8)
    save_figure(fig, path)


def figures(results, outdir: Path) -> list[Figure]:
    """Fig. 4.3, 4.5-4.10 and the safety thread (only those whose data exist)."""
    outdir = Path(outdir)
    out = []

    def add(fid, title, ref, draw, ds, note=""):
        if ds is None:
            return
        p = outdir / f"{fid}.png"
        draw(ds, p)
        out.append(Figure(id=fid, title=title, thesis_ref=ref, path=p, note=note))

    add("fig4_3", "Idealised foot trajectories", "Fig. 4.3", _fig4_3, results.get("ch4/fig4_3"))
    f45 = results.get("ch4/fig4_5")
    if f45 is not None:
        add("fig4_5", "Particle scores per generation on the slopes", "Fig. 4.5",
            lambda ds, p: _fig_scores(ds, p, [(f"{int(g)} %", ds.sel(grade=g))
                                              for g in ds["grade"].values]), f45)
    for key, title, ref in (("fig4_7", "Particle scores per generation, softer front legs",
                             "Fig. 4.7"),
                            ("fig4_8", "Particle scores per generation on pebbles", "Fig. 4.8")):
        add(key, title, ref, lambda ds, p, lab=ref: _fig_scores(ds, p, [(lab, ds)]),
            results.get(f"ch4/{key}"))
    add("fig4_6", "Best particles per inclination", "Fig. 4.6", _fig4_6, results.get("ch4/fig4_6"))
    add("fig4_9", "Step length and depth of every particle on the 18 % grade", "Fig. 4.9",
        _fig4_9, results.get("ch4/fig4_9"))
    add("fig4_10", "Search-space size per generation", "Fig. 4.10", _fig4_10,
        results.get("ch4/fig4_10"))
    add("tether", "Falls with and without the safety thread", "§4.5", _fig_tether,
        results.get("ch4/tether"))
    return out
