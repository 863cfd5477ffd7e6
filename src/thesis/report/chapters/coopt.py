"""Report section of §8.2 made real (``results/<profile>/coopt/``): tables and figures.

The thesis publishes no number for these experiments, so the tables show what was
measured only (mean ± sd over seeds); the verdicts are the ``ch8.coopt_*`` claims.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thesis.report.format import fmt, mean_spread
from thesis.report.plotting import not_run_panel, save_figure
from thesis.report.model import NOT_RUN, Figure, Table

ARMS = "coopt/arms"
GRADS = "coopt/gradients"


def arms_table(results) -> Table:
    """Final speed per arm, nominal and from perturbed starts, and the final bodies."""
    ds = results.get(ARMS)
    cols = ["arm", "first evaluation [m/s]", "final speed [m/s]",
            "perturbed starts [m/s]", "final body (mean over seeds)"]
    if ds is None:
        return Table(id="arms", title="Co-optimisation arms", thesis_ref="§8.2",
                     columns=cols, rows=[[NOT_RUN] * len(cols)])
    rows = []
    for arm in ds["arm"].values:
        a = ds.sel({"arm": arm})
        body = a["final_morphology"].mean("seed").values
        rows.append([str(arm), mean_spread(a["speed"].isel(evaluation=0).values),
                     mean_spread(a["final_speed"].values),
                     mean_spread(a["perturbed_speed"].mean("start").values),
                     ", ".join(f"{n} {fmt(v, 3)}" for n, v in
                               zip(ds["param"].values, body))])
    note = (f"{ds.attrs.get('evaluations')} gradient evaluations per run, episodes of "
            f"{ds.attrs.get('episode_s')} s, servo torque {ds.attrs.get('servo_torque')} N m, "
            f"network {ds.attrs.get('network')}; from perturbed starts the common initial "
            f"gait reaches {mean_spread(ds['initial_perturbed_speed'].values)} m/s. Units: "
            f"{ds.attrs.get('morphology_units')}.")
    return Table(id="arms", title="Controller only, morphology only and both, same budget",
                 thesis_ref="§8.2", columns=cols, rows=rows, note=note)


def gradients_table(results) -> Table:
    """Rollouts each estimator needs to reach the cosine threshold, per group and horizon."""
    ds = results.get(GRADS)
    cols = ["group", "horizon [steps]", "parameters", "|exact gradient|",
            "REINFORCE rollouts", "ES rollouts", "median cos at the largest count (RF / ES)"]
    if ds is None:
        return Table(id="gradients", title="Analytic and estimated gradients",
                     thesis_ref="§8.2", columns=cols, rows=[[NOT_RUN] * len(cols)])
    rows = []
    budget = int(ds.attrs.get("rollouts_max", 0))

    def need(v):
        v = np.asarray(v, float)
        reached = v[np.isfinite(v)]
        txt = mean_spread(reached, 3) if reached.size else "never"
        return f"{txt}; {reached.size} of {v.size} within {budget}"

    for g in ds["group"].values:
        n_par = ds.attrs.get(f"n_params_{g}", "")
        for h in ds["horizon"].values:
            sel = ds.sel({"group": g, "horizon": h})
            last = sel["median_cosine"].isel(rollouts=-1)
            rows.append([str(g), str(int(h)), str(n_par), mean_spread(sel["analytic_norm"]),
                         need(sel["rollouts_to_threshold"].sel({"estimator": "reinforce"})),
                         need(sel["rollouts_to_threshold"].sel({"estimator": "es"})),
                         f"{fmt(float(last.sel({'estimator': 'reinforce'}).mean()), 3)} / "
                         f"{fmt(float(last.sel({'estimator': 'es'}).mean()), 3)}"])
    note = (f"Threshold cos > {ds.attrs.get('cos_threshold')}; noise sigma "
            f"{ds.attrs.get('sigma')}; {len(ds['seed'])} probe point(s); the engine's "
            "gradient costs one rollout and its backward pass.")
    return Table(id="gradients", title="Rollouts an estimator needs to agree with the "
                 "engine's gradient", thesis_ref="§8.2", columns=cols, rows=rows, note=note)


def tables(results) -> list[Table]:
    """The two §8.2 tables."""
    return [arms_table(results), gradients_table(results)]


# ----------------------------------------------------------------------------- figures


def _fig_learning(results, path):
    import matplotlib.pyplot as plt

    ds = results.get(ARMS)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    if ds is None:
        not_run_panel(axes[0], "coopt/arms")
        not_run_panel(axes[1], "coopt/arms")
        return save_figure(fig, path)
    colours = {"controller": "C0", "morphology": "C1", "joint": "C2"}
    x = ds["evaluation"].values
    for arm in ds["arm"].values:
        sp = ds["speed"].sel({"arm": arm}).values
        for i, row in enumerate(sp):
            axes[0].plot(x, row, color=colours.get(str(arm), "k"), alpha=0.35, lw=0.8,
                         label=str(arm) if i == 0 else None)
        axes[0].plot(x, sp.mean(0), color=colours.get(str(arm), "k"), lw=2)
    axes[0].set_xlabel("gradient evaluation")
    axes[0].set_ylabel("mean forward speed [m/s]")
    axes[0].legend()
    body = ds["morphology"].sel({"arm": "joint"}).mean("seed")
    lo, hi = ds["param_lo"].values, ds["param_hi"].values
    for j, name in enumerate(ds["param"].values):
        axes[1].plot(x, (body.values[:, j] - lo[j]) / (hi[j] - lo[j]), label=str(name))
    axes[1].set_ylim(0, 1)
    axes[1].set_xlabel("gradient evaluation")
    axes[1].set_ylabel("joint arm's body, fraction of its bounds")
    axes[1].legend(fontsize=7, ncol=2)
    return save_figure(fig, path)


def _draw_body(ax, values, names, colour, label):
    """Side view (x-z) of one front and one hind leg and the spine from the parameters."""
    from matplotlib.patches import Circle, Rectangle

    v = dict(zip(names, values))
    lf, lt, r = v["femur_length"], v["tibia_length"], v["foot_radius"]
    zh = lf + lt + r
    ax.add_patch(Rectangle(
        (-0.35, zh - 0.05), 0.7, 0.1, fill=False, ec=colour, lw=2, label=label))
    for sx in (1.0, -1.0):
        x = sx * v["hip_x"]
        ax.plot([x, x], [zh, r], color=colour, lw=3)
        ax.plot([x], [zh - lf], "o", color=colour)
        ax.add_patch(Circle(
            (x, r), r, fill=False, ec=colour, lw=1.5))


def _fig_bodies(results, path):
    import matplotlib.pyplot as plt

    ds = results.get(ARMS)
    fig, ax = plt.subplots(figsize=(8, 4))
    if ds is None:
        not_run_panel(ax, "coopt/arms")
        return save_figure(fig, path)
    names = list(ds["param"].values)
    s0 = ds["seed"].values[0]
    _draw_body(ax, ds["param_built"].values, names, "0.5", "built (ch7 quadruped)")
    for arm, c in (("morphology", "C1"), ("joint", "C2")):
        vals = ds["final_morphology"].sel({"arm": arm, "seed": s0}).values
        _draw_body(ax, vals, names, c, f"{arm} arm, seed {s0}")
    ax.axhline(0, color="k", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlim(-0.5, 0.5)
    ax.set_ylim(-0.02, 0.75)
    ax.set_xlabel("x [m] (forward)")
    ax.set_ylabel("z [m]")
    ax.legend(fontsize=8, loc="upper right")
    return save_figure(fig, path)


def _fig_estimators(results, path):
    import matplotlib.pyplot as plt

    ds = results.get(GRADS)
    if ds is None:
        fig, ax = plt.subplots(figsize=(6, 3))
        not_run_panel(ax, "coopt/gradients")
        return save_figure(fig, path)
    G, H = len(ds["group"]), len(ds["horizon"])
    fig, axes = plt.subplots(G, H, figsize=(4.5 * H, 3.4 * G), squeeze=False)
    n = ds["rollouts"].values
    for gi, g in enumerate(ds["group"].values):
        for hi, h in enumerate(ds["horizon"].values):
            ax = axes[gi, hi]
            for est, c in (("reinforce", "C3"), ("es", "C0")):
                cs = ds["cosine"].sel({"group": g, "horizon": h, "estimator": est})
                med = ds["median_cosine"].sel({"group": g, "horizon": h, "estimator": est})
                for s in ds["seed"].values:
                    ax.plot(n, med.sel({"seed": s}).values, "o-", color=c, ms=3,
                            label=est if s == ds["seed"].values[0] else None)
                    lo = cs.sel({"seed": s}).min("block").values
                    hi_ = cs.sel({"seed": s}).max("block").values
                    ax.fill_between(n, lo, hi_, color=c, alpha=0.12)
            ax.axhline(float(ds.attrs.get("cos_threshold", 0.9)), color="k", ls=":", lw=1)
            ax.set_xscale("log")
            ax.set_ylim(-0.2, 1.02)
            ax.set_title(f"{g} ({ds.attrs.get(f'n_params_{g}', '')} params), {int(h)} steps",
                         fontsize=9)
            ax.set_xlabel("rollouts")
            ax.set_ylabel("cos(estimate, exact)")
            ax.legend(fontsize=8)
    return save_figure(fig, path)


def _fig_spread(results, path):
    import matplotlib.pyplot as plt

    ds = results.get(GRADS)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    if ds is None:
        not_run_panel(axes[0], "coopt/gradients")
        not_run_panel(axes[1], "coopt/gradients")
        return save_figure(fig, path)
    h = ds["variance_horizon"].values
    for g, c in zip(ds["group"].values, ("C0", "C1")):
        sp = ds["start_relative_spread"].sel({"group": g})
        nm = ds["start_gradient_norm"].sel({"group": g}).median("start")
        for i, s in enumerate(ds["seed"].values):
            axes[0].plot(h, sp.sel({"seed": s}).values, "o-", color=c,
                         label=str(g) if i == 0 else None)
            axes[1].plot(h, nm.sel({"seed": s}).values, "o-", color=c,
                         label=str(g) if i == 0 else None)
    for ax, lab in zip(axes, ("relative spread over perturbed starts",
                              "median norm of the exact gradient")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("horizon [steps]")
        ax.set_ylabel(lab)
        ax.legend(fontsize=8)
    return save_figure(fig, path)


def figures(results, outdir) -> list[Figure]:
    """Learning curves, bodies before/after, estimator convergence, gradient spread."""
    outdir = Path(outdir)
    return [
        Figure(id="learning", title="Speed per gradient evaluation of the three arms (thin: "
               "seeds, thick: mean) and the joint arm's body", thesis_ref="§8.2",
               path=_fig_learning(results, outdir / "learning.png")),
        Figure(id="bodies", title="Side view of the built body and the final bodies",
               thesis_ref="§8.2", path=_fig_bodies(results, outdir / "bodies.png")),
        Figure(id="estimators", title="REINFORCE and ES against the engine's gradient: "
               "median cosine over blocks (band: min-max) against rollouts",
               thesis_ref="§8.2", path=_fig_estimators(results, outdir / "estimators.png")),
        Figure(id="spread", title="The engine's gradient over perturbed starts against the "
               "horizon", thesis_ref="§8.2", path=_fig_spread(results, outdir / "spread.png")),
    ]
