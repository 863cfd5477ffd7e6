"""Report of chapter 3: Tab. 3.1, Tab. 3.2 (all five strategies), robustness, Fig. 3.4,
Fig. 3.5 and the PSO convergence, from ``results/<profile>/ch3/*.nc``.

Thesis numbers come from :mod:`thesis.paper` (``select``); every reproduced number is read
from a dataset and shown as mean ± standard deviation over seeds; missing datasets show
"not run".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thesis import paper
from thesis.report.format import fmt, mean_spread
from thesis.report.model import NOT_RUN, Figure, Table

GAITS = ("sine", "half_ellipse", "spline")
STRATEGIES = ("step_size", "step_speed", "step_size_constant_speed", "torque", "scapulae")


def _paper(artifact, variable, **coords) -> str:
    hits = paper.select(artifact, variable, **coords)
    return fmt(hits[0].value) if hits else "—"


def _sizes(ds, keys) -> str:
    return ", ".join(f"{k}={ds.attrs[k]}" for k in keys if k in ds.attrs)


def table3_1(results) -> Table:
    ds = results.get("ch3/table3_1")
    rows = []
    for gait in ("half_ellipse", "spline"):
        names = [e.coord_dict()["parameter"] for e in paper.select("table3_1", "value", gait=gait)]
        for name in names:
            got = NOT_RUN
            if ds is not None and name in ds["parameter"].values:
                got = mean_spread(ds["value"].sel(gait=gait, parameter=name).values)
            rows.append([gait, name, _paper("table3_1", "value", gait=gait, parameter=name), got])
    note = ""
    if ds is not None:
        note = "PSO sizes: " + _sizes(ds, [k for k in ds.attrs if k.startswith("pso_")])
        if "fallen" in ds:  # evaluations whose robot fell, as ch4 records them
            falls = []
            for gait in GAITS:
                arr = ds["fallen"].sel(gait=gait).values  # (seed, generation, particle)
                f = arr[np.isfinite(arr)]
                ran = np.flatnonzero(np.isfinite(arr).any(axis=(0, 2)))
                last = arr[:, ran[-1]] if ran.size else arr[:, :0]
                last = last[np.isfinite(last)]
                if f.size:
                    falls.append(f"{gait} {100 * f.mean():.0f} % of all evaluations"
                                 + (f", {100 * last.mean():.0f} % in the last generation"
                                    if last.size else ""))
            note += ". Fallen during PSO: " + "; ".join(falls) + "."
    return Table(id="table3_1", title="Optimised gait parameters", thesis_ref="Tab. 3.1",
                 columns=["gait", "parameter", "thesis", "reproduced (mean ± sd over seeds)"],
                 rows=rows, note=note)


def table3_2(results) -> Table:
    ds = results.get("ch3/table3_2")
    rows = []
    for st in STRATEGIES:
        row = [st]
        for var in ("speed", "angular_speed", "turning_radius"):
            row.append(_paper("table3_2", var, strategy=st))
            row.append(NOT_RUN if ds is None else mean_spread(ds[var].sel(strategy=st).values))
        row.append(NOT_RUN if ds is None else mean_spread(ds["stable"].sel(strategy=st).values, 2))
        row.append(NOT_RUN if ds is None else mean_spread(ds["fallen"].sel(strategy=st).values, 2))
        rows.append(row)
    note = ("Thesis: only step_size and scapulae gave stable turns on the robot "
            "(§3.3.2.2-§3.3.2.4). Angular speed is signed, + in the commanded direction. ")
    if ds is not None:
        note += (f"Straight gait at the turning frequency: "
                 f"{mean_spread(ds['forward_speed'].values)} m/s (thesis "
                 f"{_paper('table3_2', 'forward_speed')} m/s).")
    return Table(id="table3_2", title="Turning strategies", thesis_ref="Tab. 3.2",
                 columns=["strategy", "speed thesis [m/s]", "speed [m/s]",
                          "angular speed thesis [°/s]", "angular speed [°/s]",
                          "radius thesis [m]", "radius [m]", "stable", "fell"],
                 rows=rows, note=note)


def robustness_table(results) -> Table:
    ds = results.get("ch3/robustness")
    rows = [[g, NOT_RUN if ds is None else mean_spread(ds["fraction_walking"].sel(gait=g).values, 2)]
            for g in GAITS]
    note = "" if ds is None else _sizes(ds, ["scale", "min_speed"])
    return Table(id="robustness", title="Fraction of perturbed gaits still walking",
                 thesis_ref="§3.3.1.1", columns=["gait", "fraction walking"], rows=rows,
                 note="Thesis: half ellipse most robust, sine least (no number). " + note)


def tables(results) -> list[Table]:
    """Tab. 3.1, Tab. 3.2 and the robustness table."""
    return [table3_1(results), table3_2(results), robustness_table(results)]


def _fig3_4(ds, path):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    f = ds["frequency"].values
    for g, marker in zip(GAITS, ("+", "x", "o")):
        sp = ds["speed"].sel(gait=g)
        ax.errorbar(f, sp.mean("seed"), yerr=sp.std("seed"), marker=marker, ls="-",
                    label=g, capsize=2)
        th = ds["theoretical_speed"].sel(gait=g)
        if np.isfinite(th.values).any():
            ax.plot(f, th.mean("seed"), "--", lw=1, label=f"{g} theoretical")
    ax.set_xlabel("gait frequency [Hz]")
    ax.set_ylabel("speed [m/s]")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def _smooth(y, n):
    if n <= 1:
        return y
    k = np.ones(n) / n
    return np.convolve(y, k, mode="same") / np.convolve(np.ones_like(y), k, mode="same")


def _fig3_5(ds, path):
    import matplotlib.pyplot as plt

    n = max(1, int(round(float(ds.attrs.get("gait_period", 0.0)) / 0.01)))
    strategies = list(ds["strategy"].values)
    fig, axes = plt.subplots(2 * len(strategies), 1, figsize=(6, 2 * 2 * len(strategies)),
                             sharex=True)
    t = ds["time"].values
    for k, (st, colour) in enumerate(zip(strategies, ("tab:red", "tab:blue"))):
        for seed in ds["seed"].values:
            lat = ds["lateral_position"].sel(strategy=st, seed=seed).values
            yaw = ds["yaw"].sel(strategy=st, seed=seed).values
            axes[2 * k].plot(t, _smooth(lat, n), color=colour, lw=1)
            axes[2 * k + 1].plot(t, _smooth(yaw, n), color=colour, lw=1)
        axes[2 * k].axhline(float(ds["setpoint"]), color="k", lw=1)
        axes[2 * k].set_ylabel(f"{st}\nlateral [m]")
        axes[2 * k + 1].set_ylabel("yaw [°]")
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def _pso(ds, path):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.5))
    for g, c in zip(GAITS, ("tab:gray", "tab:red", "tab:blue")):
        for i, seed in enumerate(ds["seed"].values):
            y = ds["best_fitness"].sel(gait=g, seed=seed).values
            ax.plot(ds["generation"].values, y, color=c, lw=1, label=g if i == 0 else None)
    ax.set_xlabel("generation")
    ax.set_ylabel("best fitness (eq. 3.3)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def figures(results, outdir: Path) -> list[Figure]:
    """Fig. 3.4, Fig. 3.5 and the PSO convergence (only those whose data exist)."""
    outdir = Path(outdir)
    out = []
    ds = results.get("ch3/fig3_4")
    if ds is not None:
        p = outdir / "fig3_4.png"
        _fig3_4(ds, p)
        t31 = results.get("ch3/table3_1")
        note = "" if t31 is None else (
            f"simulation rate {fmt(float(t31['robot_seconds_per_wall_second']))} robot-s "
            "per wall-s (batched PSO generations)")
        out.append(Figure(id="fig3_4", title="Speed against gait frequency",
                          thesis_ref="Fig. 3.4", path=p, note=note))
    ds = results.get("ch3/fig3_5")
    if ds is not None:
        p = outdir / "fig3_5.png"
        _fig3_5(ds, p)
        out.append(Figure(id="fig3_5", title="Tracking the LED: step size vs scapulae",
                          thesis_ref="Fig. 3.5", path=p))
    ds = results.get("ch3/table3_1")
    if ds is not None:
        p = outdir / "pso_convergence.png"
        _pso(ds, p)
        out.append(Figure(id="pso_convergence", title="PSO convergence",
                          thesis_ref="§3.3.1.2-3", path=p))
    return out
