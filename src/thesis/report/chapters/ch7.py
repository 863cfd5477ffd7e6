"""Report of chapter 7: ball throw (§7.2.1), arm (§7.3.2), quadruped gait (§7.3.3) and
the pendulum from pixels (§7.3.3.1), from ``results/<profile>/ch7/*.nc``.

Thesis numbers come from :mod:`thesis.paper`; every reproduced number is read from a
dataset (mean ± standard deviation over seeds, with how many seeds reached a threshold);
missing datasets show "not run". Every declared table and figure is always produced
(a figure of a missing dataset says "not run").
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thesis import paper
from thesis.paper import select
from thesis.report.format import fmt, mean_spread
from thesis.report.plotting import not_run_panel, save_figure
from thesis.report.model import NOT_RUN, Figure, Table


def _paper(key: str) -> str:
    try:
        return fmt(paper.get(key).value)
    except KeyError:
        return "—"


def _sizes(ds, keys) -> str:
    return ", ".join(f"{k}={ds.attrs[k]}" for k in keys if k in ds.attrs)


def _reach(values) -> str:
    """mean ± sd of the finite counts and how many seeds reached the threshold."""
    v = np.asarray(values, float).ravel()
    n_ok = int(np.isfinite(v).sum())
    if n_ok == 0:
        return f"not reached (0/{v.size} seeds)"
    return f"{mean_spread(v)}; reached {n_ok}/{v.size}"


def ball_table(results) -> Table:
    ds = results.get("ch7/ball")
    rows = []
    for m, label in (("gradient", "gradient descent (BPTT)"), ("cmaes", "CMA-ES")):
        got = [NOT_RUN] * 4
        if ds is not None and m in ds["method"].values:
            d = ds.sel({"method": m})
            got = [_reach(d["iterations"].values), mean_spread(d["wall_seconds"].values),
                   mean_spread(d["final_position_error"].values),
                   mean_spread(d["final_velocity_error"].values)]
        rows.append([label, _paper(f"ball/method={m}/iterations"), got[0],
                     _paper(f"ball/method={m}/wall_seconds"), got[1], got[2], got[3]])
    note = "" if ds is None else (
        "Iterations: gradient evaluations (gradient descent) or candidates (CMA-ES) until "
        "both errors are below the tolerances; wall time excludes compilation and covers "
        "the whole run (to convergence or the budget). " + _sizes(
            ds, ["horizon_s", "tol_position_m", "tol_velocity_mps", "gradient_max_iterations",
                 "cmaes_max_evaluations", "cmaes_popsize"]))
    return Table(id="ball", title="Throwing a ball: gradient descent against CMA-ES",
                 thesis_ref="§7.2.1",
                 columns=["method", "iterations (thesis)", "iterations (reproduced)",
                          "wall s (thesis)", "wall s (reproduced)", "position error m",
                          "velocity error"], rows=rows, note=note)


def arm_fixed_table(results) -> Table:
    ds = results.get("ch7/arm_fixed")
    rows = []
    for thr, name in ((0.04, "4cm"), (0.01, "1cm")):
        for m in ("gradient", "cmaes"):
            got = NOT_RUN
            var = f"evaluations_to_{name}"
            if ds is not None and var in ds and m in ds["method"].values:
                got = _reach(ds[var].sel({"method": m}).values)
            no_conv = _paper("arm_fixed/cmaes_evaluations_without_convergence")
            thesis = _paper(f"arm_fixed/threshold_m={thr}/evaluations") if m == "gradient" \
                else f"no convergence in {no_conv}"
            rows.append([f"within {thr * 100:g} cm", m, thesis, got])
    note = "" if ds is None else (
        "Error: end-effector distance averaged over the final eval_window_s. Best error "
        "reached: " + "; ".join(
            f"{m} {mean_spread(ds['best_error'].sel({'method': m}).min('evaluation').values)} m"
            for m in ds["method"].values) + ". " + _sizes(
            ds, ["network", "n_params", "episode_s", "gradient_evaluations",
                 "cmaes_evaluations", "cmaes_variant", "grad_decay", "learning_rate"]))
    return Table(id="arm_fixed", title="4-DoF arm reaching a fixed point: model evaluations",
                 thesis_ref="§7.3.2.1", columns=["threshold", "method", "thesis",
                                                 "reproduced (mean ± sd over seeds)"],
                 rows=rows, note=note)


def arm_random_table(results) -> Table:
    ds = results.get("ch7/arm_random")
    rows = []
    for thr, name in ((0.1, "10cm"), (0.05, "5cm")):
        got = NOT_RUN
        if ds is not None and f"updates_to_{name}" in ds:
            got = _reach(ds[f"updates_to_{name}"].values)
        rows.append([f"mean error below {thr * 100:g} cm",
                     _paper(f"arm_random/threshold_m={thr}/updates"), got])
    if ds is not None:
        rows.append(["final mean test error [m]", "—",
                     mean_spread(ds["test_error"].isel(check=-1).values)])
    note = "" if ds is None else "Profile sizes (the thesis: 3 x 1024 hidden, batch 128): " \
        + _sizes(ds, ["network", "n_params", "batch", "updates", "episode_s", "test_batch"])
    return Table(id="arm_random", title="4-DoF arm reaching random points: update steps",
                 thesis_ref="§7.3.2.2", columns=["quantity", "thesis", "reproduced"],
                 rows=rows, note=note)


def gait_table(results) -> Table:
    ds = results.get("ch7/quadruped_gait")
    got = [NOT_RUN] * 4
    if ds is not None:
        got = [str(int(ds.attrs.get("evaluations", ds.sizes["evaluation"]))),
               mean_spread(ds["final_speed"].values),
               mean_spread(ds["speed"].max("evaluation").values), NOT_RUN]
        if "hand_tuned_speed" in ds:
            got[3] = (f"{float(ds['hand_tuned_speed']):.3f} (best upright of "
                      f"{ds.sizes['trot']} open-loop trots, {int(ds['hand_tuned_upright'])} "
                      f"upright; {ds.attrs.get('hand_tuned_trot', '')})")
    rows = [["model evaluations", _paper("quadruped_gait/evaluations"), got[0]],
            ["speed after the evaluations [m/s]", _paper("quadruped_gait/evaluations=500/speed"),
             got[1]],
            ["best speed seen during training [m/s]", "—", got[2]],
            ["hand-tuned trot [m/s]", _paper("quadruped_gait/hand_tuned_speed"), got[3]]]
    note = "" if ds is None else _sizes(ds, ["network", "n_params", "episode_s", "dt",
                                             "servo_torque", "learning_rate", "grad_decay",
                                             "total_mass_kg"])
    if ds is not None and "hand_tuned_speed_by_torque" in ds:
        by = ds["hand_tuned_speed_by_torque"]
        note += (" Best upright open-loop trot by servo torque bound: " + ", ".join(
            f"{float(t):g} N m {float(v):.3f} m/s" for t, v in zip(by["trot_torque"].values,
                                                                  by.values)) + ".")
    return Table(id="quadruped_gait", title="Quadruped gait learned through the engine",
                 thesis_ref="§7.3.3", columns=["quantity", "thesis", "reproduced"], rows=rows,
                 note=note)


def pendulum_table(results) -> Table:
    ds = results.get("ch7/pendulum_pixels")
    got = [NOT_RUN] * 3
    if ds is not None:
        got = [_reach(ds["episodes_to_up"].values), mean_spread(ds["stays_up_s"].values),
               str(int(ds.attrs.get("n_params", 0)))]
    rows = [["episodes until swung up and held", _paper("pendulum_pixels/episodes"), got[0]],
            ["test run: seconds up after first coming up", "—", got[1]],
            ["controller parameters", _paper("pendulum_pixels/n_params"), got[2]]]
    note = "" if ds is None else "Profile sizes (the thesis: 288 x 96 pixels): " + _sizes(
        ds, ["pixels", "conv_channels", "hidden", "episode_s", "episodes", "test_s",
             "up_angle_deg", "hold_s"])
    return Table(id="pendulum_pixels", title="Cart-pole swing-up from camera pixels",
                 thesis_ref="§7.3.3.1", columns=["quantity", "thesis", "reproduced"],
                 rows=rows, note=note)


def _cell(ds, engine=None, **coords):
    """Seconds of one Tab. 7.1 cell (median over repeats where present), NaN if absent."""
    if ds is None or "seconds" not in ds:
        return float("nan")
    da = ds["seconds"]
    sel = {k: v for k, v in {**coords, "engine": engine}.items() if v is not None}
    try:
        da = da.sel(sel)
    except (KeyError, ValueError):
        return float("nan")
    extra = list(da.dims)
    return float(da.median(extra)) if extra else float(da)


def _diverged(peers, engine, at) -> str:
    """Why a peer cell of Tab. 7.1 simulated no sane robot ("" when it did, or when the
    dataset does not say): a non-finite final distance or, for gradient cells, a
    non-finite gradient (``distance_finite`` / ``gradient_finite`` of
    ``ch7/table7_1_peers``)."""
    checks = [("distance_finite", "diverged: distance not finite")]
    if at.get("gradient"):
        checks.append(("gradient_finite", "diverged: gradient not finite"))
    for var, why in checks:
        if peers is None or var not in peers:
            continue
        try:
            ok = peers[var].sel(engine=engine, **at)
        except (KeyError, ValueError):
            continue
        if np.isfinite(ok).all() and float(ok.min()) < 1.0:
            return why
    return ""


def table7_1_table(results) -> Table:
    """Tab. 7.1: the thesis's CPU column, this engine and the MuJoCo MJX / MuJoCo C peers on
    the same CPU (``ch7/table7_1_peers``, optional), with the MJX / engine ratio."""
    ours, peers = results.get("ch7/table7_1"), results.get("ch7/table7_1_peers")
    rows = []
    show = (lambda v: NOT_RUN if not np.isfinite(v) else f"{v:.3g}")  # noqa: E731
    cells = sorted(select("table7_1", "seconds", device="cpu"),
                   key=lambda pv: (dict(pv.coords)["batch"], dict(pv.coords)["n_params"],
                                   dict(pv.coords)["gradient"]))
    for pv in cells:  # the thesis's CPU cells: batch, controller size, with/without gradient
        at = dict(pv.coords)
        batch, n_params, gradient = at["batch"], at["n_params"], at["gradient"]
        thesis = fmt(pv.value)
        eng = _cell(ours, **at)
        mjx = _cell(peers, "mjx", **at)
        c = _cell(peers, "mujoco_c", **at)
        mjx_bad, c_bad = _diverged(peers, "mjx", at), _diverged(peers, "mujoco_c", at)
        ratio = ("— (MJX diverged)" if mjx_bad else f"{mjx / eng:.2f}"
                 if np.isfinite(mjx) and np.isfinite(eng) and eng > 0 else NOT_RUN)
        rows.append([str(batch), f"{n_params:,}", "yes" if gradient else "no",
                     thesis, show(eng), show(mjx) + (f" ({mjx_bad})" if mjx_bad else ""),
                     ratio, "—" if gradient else
                     show(c) + (f" ({c_bad})" if c_bad else "")])
    note = ("Seconds to simulate the batch for 10 model seconds on this machine's CPU; the "
            "thesis's column is its 6-core i7 5930K. MJX / engine below 1: MJX is faster. "
            "Peers come from the optional `table7_1_peers` benchmark (`bench` extra). A peer "
            "cell whose rollout or gradient is not finite timed a diverged simulation, not "
            "the same work: it is marked diverged and has no ratio.")
    return Table(id="table7_1", title="Tab. 7.1: engine speed beside MuJoCo MJX and MuJoCo C",
                 thesis_ref="Tab. 7.1",
                 columns=["robots", "parameters", "gradient", "thesis CPU [s]", "engine [s]",
                          "MJX [s]", "MJX / engine", "MuJoCo C [s]"], rows=rows, note=note)


def tables(results) -> list[Table]:
    """The six chapter-7 tables (thesis beside reproduced)."""
    return [ball_table(results), table7_1_table(results), arm_fixed_table(results),
            arm_random_table(results), gait_table(results), pendulum_table(results)]


# ----------------------------------------------------------------------------- figures


def _fig_ball(results, outdir):
    import matplotlib.pyplot as plt

    ds = results.get("ch7/ball")
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    if ds is None:
        not_run_panel(ax, "ch7/ball")
    else:
        for s in ds["seed"].values:
            g = ds["gradient_loss"].sel(seed=s).values
            ax.plot(np.arange(1, g.size + 1), g, color="C0", lw=1,
                    label="gradient descent" if s == ds["seed"].values[0] else None)
            c = np.fmin.accumulate(np.nan_to_num(ds["cmaes_loss"].sel(seed=s).values, nan=np.inf))
            c = np.where(np.isfinite(c), c, np.nan)
            ax.plot(np.arange(1, c.size + 1), c, color="C1", lw=1,
                    label="CMA-ES (best so far)" if s == ds["seed"].values[0] else None)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("model evaluations")
        ax.set_ylabel("position + velocity error")
        ax.legend()
    return save_figure(fig, Path(outdir) / "ball_loss.png")


def _fig_arm(results, outdir):
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.6, 3.6))
    ds = results.get("ch7/arm_fixed")
    if ds is None:
        not_run_panel(a1, "ch7/arm_fixed")
    else:
        for i, m in enumerate(ds["method"].values):
            for s in ds["seed"].values:
                y = ds["best_error"].sel({"method": m, "seed": s}).values
                a1.plot(ds["evaluation"].values, y, color=f"C{i}", lw=1,
                        label=m if s == ds["seed"].values[0] else None)
        for thr in (0.04, 0.01):
            a1.axhline(thr, color="grey", ls=":", lw=0.8)
        a1.set_yscale("log")
        a1.set_xlabel("model evaluations")
        a1.set_ylabel("best end-effector error [m]")
        a1.set_title("fixed target (§7.3.2.1)")
        a1.legend()
    ds = results.get("ch7/arm_random")
    if ds is None:
        not_run_panel(a2, "ch7/arm_random")
    else:
        for s in ds["seed"].values:
            a2.plot(ds["check"].values, ds["test_error"].sel(seed=s).values, lw=1,
                    label=f"seed {s}")
        for thr in (0.1, 0.05):
            a2.axhline(thr, color="grey", ls=":", lw=0.8)
        a2.set_xlabel("update steps")
        a2.set_ylabel("mean test error [m]")
        a2.set_title("random targets (§7.3.2.2)")
        a2.legend()
    return save_figure(fig, Path(outdir) / "arm_learning.png")


def _fig_curve(results, key, var, ylabel, name, outdir, xdim):
    import matplotlib.pyplot as plt

    ds = results.get(key)
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    if ds is None:
        not_run_panel(ax, key)
    else:
        for s in ds["seed"].values:
            ax.plot(ds[xdim].values, ds[var].sel(seed=s).values, lw=1, label=f"seed {s}")
        ax.set_xlabel(xdim.replace("_", " ") + "s")
        ax.set_ylabel(ylabel)
        ax.legend()
    return save_figure(fig, Path(outdir) / f"{name}.png")


def _fig_frames(results, key, name, outdir, scale):
    import matplotlib.pyplot as plt

    ds = results.get(key)
    if ds is None or "frames" not in ds:
        fig, ax = plt.subplots(figsize=(6.4, 1.6))
        not_run_panel(ax, key)
        return save_figure(fig, Path(outdir) / f"{name}.png")
    f = ds["frames"].values
    n = f.shape[0]
    fig, axes = plt.subplots(1, n, figsize=(scale * n, scale * f.shape[1] / f.shape[2] + 0.4))
    for ax, img, t in zip(np.atleast_1d(axes), f, ds["frame_time"].values):
        ax.imshow(img, interpolation="nearest")
        ax.set_title(f"t = {t:.2f} s", fontsize=8)
        ax.set_axis_off()
    return save_figure(fig, Path(outdir) / f"{name}.png")


def figures(results, outdir) -> list[Figure]:
    """Learning curves and frame strips of chapter 7 (PNG files in ``outdir``)."""
    outdir = Path(outdir)
    g = results.get("ch7/quadruped_gait")
    p = results.get("ch7/pendulum_pixels")
    return [
        Figure(id="ball_loss", title="Ball throw: loss per model evaluation, gradient "
               "descent (BPTT) and CMA-ES (best so far), every seed", thesis_ref="§7.2.1",
               path=_fig_ball(results, outdir)),
        Figure(id="arm_learning", title="4-DoF arm: error per model evaluation (fixed "
               "target) and mean test error per update (random targets)",
               thesis_ref="§7.3.2", path=_fig_arm(results, outdir)),
        Figure(id="gait_learning", title="Quadruped: mean forward speed of the spine per "
               "model evaluation", thesis_ref="§7.3.3",
               path=_fig_curve(results, "ch7/quadruped_gait", "speed", "speed [m/s]",
                               "gait_learning", outdir, "evaluation")),
        Figure(id="gait_frames", title="Quadruped: the learned gait seen by the engine's "
               "camera (tracking shot)", thesis_ref="§7.3.3",
               path=_fig_frames(results, "ch7/quadruped_gait", "gait_frames", outdir, 1.8),
               note="" if g is None else f"seed {g.attrs.get('frames_seed', '')}"),
        Figure(id="pendulum_learning", title="Cart-pole from pixels: episode loss",
               thesis_ref="§7.3.3.1",
               path=_fig_curve(results, "ch7/pendulum_pixels", "loss", "loss [m]",
                               "pendulum_learning", outdir, "episode")),
        Figure(id="pendulum_frames", title="Cart-pole: camera frames the learned controller "
               "sees at the start of its test run", thesis_ref="Fig. 7.4",
               path=_fig_frames(results, "ch7/pendulum_pixels", "pendulum_frames", outdir, 2.4),
               note="" if p is None else f"{p.attrs.get('pixels')} pixels"),
    ]
