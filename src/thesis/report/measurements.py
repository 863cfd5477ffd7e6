"""The measurements page ``reports/<profile>/measurements.md``: what the last run of a
profile cost, generated from what the pipeline recorded, never typed in.

Sources:

* Snakemake's benchmark files ``benchmarks/<profile>/<chapter>/<name>.tsv`` (one per job:
  wall seconds ``s``, peak resident memory ``max_rss`` [MB], ``cpu_time`` [s]), read with
  :func:`thesis.resources.read_benchmark`;
* the results' provenance attributes ``started`` (ISO time) and ``wall_seconds``, whose
  earliest start and latest end give the span of the run that produced the results now on
  disk (an incremental run's span covers only what it reran: the page says so);
* every variable marked ``measurement="wall_clock"`` (timings that are machine-dependent
  and therefore not regressed), with its median;
* the profile's ``budget`` (config/schema.yaml; docs/architecture.md#profiles), which the
  jobs' times are held against (:func:`budget_lines`).

The README links this page instead of quoting timings: results and timings are generated
by the pipeline (docs/architecture.md#report).
"""

from __future__ import annotations

import datetime as dt
from pathlib import Path

import numpy as np
import xarray as xr

from thesis import resources

__all__ = ["budget_lines", "job_rows", "measurements_md"]


def job_rows(profile: str, bench_root: Path = Path("benchmarks")) -> list[dict]:
    """One row per benchmark file of ``profile``: ``chapter``, ``job``, ``s`` [s],
    ``max_rss`` [MB], ``cpu_time`` [s]; sorted by chapter then job. Empty when the
    profile has not run here. A malformed benchmark file raises ValueError naming it."""
    root = Path(bench_root) / profile
    rows = []
    for path in sorted(root.glob("*/*.tsv")):
        b = resources.read_benchmark(path)
        rows.append(dict(chapter=path.parent.name, job=path.stem, s=b["s"],
                         max_rss=b["max_rss"], cpu_time=b["cpu_time"]))
    return rows


def _span(results: dict[str, xr.Dataset]) -> tuple[str, str, float] | None:
    """(first start, last end, seconds between) over the results' provenance, or None."""
    starts, ends = [], []
    for ds in results.values():
        started, wall = ds.attrs.get("started"), ds.attrs.get("wall_seconds")
        if started is None or wall is None:
            continue
        t0 = dt.datetime.fromisoformat(str(started))
        starts.append(t0)
        ends.append(t0 + dt.timedelta(seconds=float(wall)))
    if not starts:
        return None
    first, last = min(starts), max(ends)
    return first.isoformat(timespec="seconds"), last.isoformat(timespec="seconds"), \
        (last - first).total_seconds()


def _fmt_s(s: float) -> str:
    s = float(s)
    if s < 60:
        return f"{s:.1f} s"
    m, sec = divmod(int(round(s)), 60)
    h, m = divmod(m, 60)
    return f"{h} h {m:02d} min {sec:02d} s" if h else f"{m} min {sec:02d} s"


def budget_lines(rows: list[dict], budget: dict | None) -> list[str]:
    """Markdown lines holding the jobs of :func:`job_rows` against the profile's ``budget``
    (``{"hours": h, "cores": n}``; None: no budget, no lines).

    Two bounds decide without knowing how the scheduler packed the jobs onto the cores:
    the jobs' summed CPU time over ``n`` cores is the least wall time any packing needs, and
    their summed wall time the most (one job after another). The budget is **kept** when
    the most fits it, **exceeded** when the least does not, and otherwise depends on the
    packing (the run's own span, above, is the measured answer for a run from scratch).
    """
    if not budget:
        return []
    limit, cores = 3600.0 * float(budget["hours"]), int(budget["cores"])
    head = ["## Budget", "",
            f"The profile's budget: the whole pipeline within {_fmt_s(limit)} on {cores} CPU "
            "cores (`budget` in its config)."]
    if not rows:
        return head + ["No benchmark files: nothing to hold against it.", ""]
    cpu = sum(float(r["cpu_time"]) for r in rows)
    wall = sum(float(r["s"]) for r in rows)
    least = cpu / cores
    if wall <= limit:
        verdict = "**kept**: the jobs one after another fit it"
    elif least > limit:
        verdict = (f"**exceeded**: even with every core busy throughout the jobs need "
                   f"{least / limit:.2f} x the budget")
    else:
        verdict = "**kept or not**, depending on how the jobs pack onto the cores"
    return head + ["", f"| jobs' CPU time, summed | over {cores} cores (the least wall time) "
                   "| jobs' wall time, summed (the most) | budget |", "|---|---|---|---|",
                   f"| {_fmt_s(cpu)} | {_fmt_s(least)} | {_fmt_s(wall)} | {_fmt_s(limit)} |",
                   "", f"Budget {verdict}.", ""]


def measurements_md(profile: str, results: dict[str, xr.Dataset],
                    bench_root: Path = Path("benchmarks"), budget: dict | None = None) -> str:
    """Markdown of the measurements page (module docstring) for ``profile``.

    Args:
        results: ``{"<chapter>/<artifact>": Dataset}`` as ``thesis.store.load_results``.
        bench_root: folder holding ``<profile>/<chapter>/<name>.tsv``.
        budget: the profile's ``budget`` config entry (None: none).
    """
    lines = [f"# Measurements, profile `{profile}`", "",
             "Generated by `thesis report` from `benchmarks/` and the results' provenance; "
             "machine-dependent, so never regressed. Timings taken while other work loaded "
             "the machine overstate wall time (each result's `host` attribute names the "
             "machine).", ""]
    span = _span(results)
    if span:
        lines += [f"Results on disk were produced between {span[0]} and {span[1]} "
                  f"(span {_fmt_s(span[2])}; for an incremental run, only what it reran).", ""]
    rows = job_rows(profile, bench_root)
    if rows:
        lines += ["## Jobs (Snakemake benchmarks)", "",
                  "| chapter | job | wall | CPU time | peak memory |", "|---|---|---|---|---|"]
        per_ch: dict[str, float] = {}
        for r in rows:
            per_ch[r["chapter"]] = per_ch.get(r["chapter"], 0.0) + r["s"]
            lines.append(f"| {r['chapter']} | {r['job']} | {_fmt_s(r['s'])} | "
                         f"{_fmt_s(r['cpu_time'])} | {r['max_rss']:.0f} MB |")
        lines += ["", "| chapter | job time, summed |", "|---|---|"]
        lines += [f"| {ch} | {_fmt_s(s)} |" for ch, s in sorted(per_ch.items())]
        lines += [f"| all | {_fmt_s(sum(per_ch.values()))} |", ""]
    else:
        lines += [f"No benchmark files under `{Path(bench_root) / profile}`: the profile "
                  "has not run through Snakemake here.", ""]
    lines += budget_lines(rows, budget)
    walls = []
    for key, ds in sorted(results.items()):
        for name, var in ds.data_vars.items():
            if var.attrs.get("measurement") != "wall_clock":
                continue
            vals = np.asarray(var.values, dtype=float)
            vals = vals[np.isfinite(vals)]
            med = f"{np.median(vals):.4g}" if vals.size else "no finite value"
            walls.append(f"| {key} | {name} | {med} {var.attrs.get('units', '')} | "
                         f"{var.attrs.get('long_name', '')} |")
    if walls:
        lines += ["## Wall-clock variables in the results (median over their cells)", "",
                  "| result | variable | median | what |", "|---|---|---|---|", *walls, ""]
    return "\n".join(lines)
