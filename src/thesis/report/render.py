"""Render ``reports/<profile>/``: figures per chapter, then the page and the summary.

- :func:`render_figures` (one Snakemake rule per chapter): calls the chapter module's
  ``figures(results, outdir)`` and writes ``figures/<ch>/manifest.json``.
- :func:`render_report`: reads the results, ``claims.json``, the rules' power table
  (``claims_power.json``, shown in the method section) and the figure manifests and
  writes ``index.html`` (self-contained: figures inlined as PNG data URIs),
  ``summary.md`` and ``tables/<ch>_<table>.html`` (for ``snakemake --report``); it opens
  on the generated status (:mod:`thesis.report.status`) and ends the chapters with their
  tables as the perturbed and native twin runs give them (:func:`twin_sections`).

Nothing here computes a result: every number shown is read from a results file or from
:mod:`thesis.paper`; what is missing is shown as "not run".
"""

from __future__ import annotations

import base64
import csv
import dataclasses
import html
import importlib
import json
import re
from datetime import datetime, timezone
from pathlib import Path

from thesis import provenance, store
from thesis.errors import DamagedFileError
from thesis.report.chapters import CHAPTERS
from thesis.report import damaged as D
from thesis.report import measurements, status
from thesis.report import verdicts as V
from thesis.report.model import NOT_RUN, Figure, Section, Table

STATUS_COLOURS = V.STATUS_COLOURS

CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;max-width:1200px;
margin:2em auto;padding:0 1em;color:#222;line-height:1.45}
h1{font-size:1.6em}h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:1em 0;font-size:.9em}
th,td{border:1px solid #ccc;padding:.3em .6em;text-align:left;vertical-align:top}
th{background:#f3f3f3}.note{color:#555;font-size:.85em}.fragile{color:#b2182b;font-weight:bold;font-size:.85em}
.status{font-weight:bold;color:#fff;padding:.1em .4em;border-radius:3px;white-space:nowrap}
figure{margin:1em 0}figure img{max-width:100%;border:1px solid #eee}
figcaption{font-size:.9em;color:#444}.notrun{color:#777;font-style:italic}
footer{margin-top:3em;font-size:.8em;color:#555;border-top:1px solid #ddd}
nav a{margin-right:1em}
table.claims{table-layout:fixed;width:100%}
table.claims ul{margin:.2em 0;padding-left:1.1em}
td,th,code{overflow-wrap:anywhere}
details summary{cursor:pointer;color:#555;font-size:.85em}
.wide{max-width:100%;overflow-x:auto}
"""


def _chapter_module(ch: str):
    try:
        return importlib.import_module(f"thesis.report.chapters.{ch}")
    except ModuleNotFoundError as e:
        if e.name == f"thesis.report.chapters.{ch}":
            return None
        raise


def _chapter_results(results: dict, ch: str) -> dict:
    return {k: v for k, v in results.items() if k.startswith(ch + "/")}


def render_figures(ch: str, profile: str, outdir: Path, *, config: dict | None = None,
                   results_root: Path = store.RESULTS_DIR,
                   scanned: tuple[dict, dict] | None = None,
                   set_aside: dict[str, DamagedFileError] | None = None) -> list[Figure]:
    """Render chapter ``ch``'s figures into ``outdir/figures/<ch>/`` and its manifest.
    ``scanned``: the profile's results as :func:`thesis.store.scan_results` read them
    (default: read here); a damaged file is left out, as if not run. A readable result
    that lacks a variable the figures read is left out too and added to ``set_aside``
    (:func:`lacking_variable`)."""
    figdir = Path(outdir) / "figures" / ch
    figdir.mkdir(parents=True, exist_ok=True)
    scanned = scanned or store.scan_results(profile, results_root)
    results = _chapter_results(scanned[0], ch)
    mod = _chapter_module(ch)
    figs: list[Figure] = []
    if mod is not None and results:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        dpi = (config or {}).get("report", {}).get("figure_dpi", 110)
        with plt.rc_context({"savefig.dpi": dpi, "figure.dpi": dpi}):
            figs = _reading(lambda r: list(mod.figures(r, figdir)), results, profile,
                            results_root, set_aside)
    manifest = [{"id": f.id, "title": f.title, "thesis_ref": f.thesis_ref,
                 "path": Path(f.path).name, "note": f.note} for f in figs]
    with store.atomic_path(figdir / "manifest.json") as tmp:
        tmp.write_text(json.dumps(manifest, indent=2))
    return figs


def _load_manifest(outdir: Path, ch: str) -> list[Figure]:
    path = Path(outdir) / "figures" / ch / "manifest.json"
    if not path.exists():
        return []
    out = []
    for f in json.loads(path.read_text()):
        png = path.parent / f["path"]
        if png.exists():
            out.append(Figure(id=f["id"], title=f["title"], thesis_ref=f["thesis_ref"],
                              path=png, note=f.get("note", "")))
    return out


#: xarray's message for a variable a dataset does not hold (``ds["name"]``).
_NO_VARIABLE = re.compile(r"No variable named '([^']+)'")


def lacking_variable(err: KeyError, results: dict) -> tuple[str, list[str]] | None:
    """(variable, keys of ``results`` that lack it) when ``err`` is xarray's "no variable
    named" for a variable some of ``results`` lack (a readable result written by other
    code, or cut short); None for any other KeyError (a defect of the report's code)."""
    m = _NO_VARIABLE.search(str(err.args[0]) if err.args else "")
    if m is None:
        return None
    name = m.group(1)
    keys = [k for k, ds in results.items() if name not in ds.variables]
    return (name, keys) if keys else None


def _reading(make, results: dict, profile: str | None, results_root: Path,
             set_aside: dict[str, DamagedFileError] | None):
    """``make(results)``; where it stops on a variable some results lack
    (:func:`lacking_variable`), those results are set aside as damaged (named with the
    variable and the command that remakes them, in ``set_aside``) and ``make`` runs on
    the rest, as if they had not run."""
    results = dict(results)
    while True:
        try:
            return make(results)
        except KeyError as err:
            found = lacking_variable(err, results)
            if found is None or profile is None:
                raise
            name, keys = found
            for k in keys:
                if set_aside is not None:
                    set_aside[k] = store.damaged_result(
                        profile, k, f"lacks the variable '{name}' that the report reads "
                        "(written by other code, or cut short)", results_root)
                results.pop(k)


def build_sections(results: dict, outdir: Path, *, profile: str | None = None,
                   results_root: Path = store.RESULTS_DIR,
                   set_aside: dict[str, DamagedFileError] | None = None) -> list[Section]:
    """One :class:`Section` per chapter, with its tables and rendered figures. With
    ``profile``, a readable result that lacks a variable a chapter's tables read is set
    aside (``set_aside``) and the chapter built without it (:func:`lacking_variable`)."""
    sections = []
    for ch, title in CHAPTERS.items():
        mod = _chapter_module(ch)
        tables = _reading(lambda r: list(mod.tables(r)), _chapter_results(results, ch),
                          profile, results_root, set_aside) if mod is not None else []
        sections.append(Section(chapter=ch, title=title, tables=tables,
                                figures=_load_manifest(outdir, ch)))
    return sections


#: Kinds of twin run whose tables the report shows after the chapters: (kind, the
#: ``thesis.store.results_name`` keyword naming its results folder).
TWIN_KINDS = (("perturbed", "perturbed"), ("native", "native"))


def twin_sections(profile: str, results_root: Path = store.RESULTS_DIR,
                  set_aside: dict[str, DamagedFileError] | None = None
                  ) -> list[tuple[str, str, list[Section]]]:
    """The chapters' tables as the twin runs on disk give them: per kind of twin run
    (perturbed: ``--config perturb=1e-7``, native: ``--config isa=native``) with results
    under ``results/<profile>-<kind>/``, (kind, that folder's name, one tables-only
    :class:`Section` per chapter with twin results). Read from those datasets by the same
    chapter modules as the runs' own tables, so the numbers a twin run moves (not only the
    verdicts) stand beside the runs'; a cell without a twin result shows "not run". A twin
    result lacking a variable the tables read is set aside as in :func:`build_sections`
    (``set_aside``, keyed ``"<runs>:<chapter>/<artifact>"``)."""
    out = []
    for kind, flag in TWIN_KINDS:
        name = store.results_name(profile, **{flag: True})
        twins, _ = store.scan_results(name, results_root)  # damaged ones: check's list
        sections = []
        for ch, title in CHAPTERS.items():
            mod = _chapter_module(ch)
            chapter = _chapter_results(twins, ch)
            if mod is not None and chapter:
                aside: dict[str, DamagedFileError] = {}
                tables = [dataclasses.replace(t, id=f"{kind}-{t.id}") for t in _reading(
                    lambda r: list(mod.tables(r)), chapter, name, results_root, aside)]
                if set_aside is not None:
                    set_aside.update({f"{name}:{k}": e for k, e in aside.items()})
                sections.append(Section(chapter=ch, title=title, tables=tables))
        if sections:
            out.append((kind, name, sections))
    return out


def _twin_html(twins: list[tuple[str, str, list[Section]]]) -> str:
    """The tables of :func:`twin_sections`, one folded part per chapter."""
    parts = []
    for kind, name, sections in twins:
        parts.append(f'<h2 id="twins-{kind}">Tables of the {kind} twin runs</h2>'
                     f'<p class="note">Read from <code>results/{html.escape(name)}/</code> by '
                     "the chapters' own table code; the verdicts they move are in the method "
                     'section (<a href="#fragility">fragility</a>).</p>')
        parts += [f"<details><summary>{html.escape(s.title)}</summary>"
                  + "".join(_table_html(t) for t in s.tables) + "</details>" for s in sections]
    return "".join(parts)


def _twin_md(twins: list[tuple[str, str, list[Section]]]) -> list[str]:
    """The tables of :func:`twin_sections` as Markdown lines."""
    lines = []
    for kind, name, sections in twins:
        lines += [f"## Tables of the {kind} twin runs", "",
                  f"Read from `results/{name}/` by the chapters' own table code.", ""]
        for s in sections:
            lines += [f"### {s.title}", ""]
            for t in s.tables:
                lines += _table_md(t, "####")
    return lines


def _table_md(t: Table, level: str = "###") -> list[str]:
    """A :class:`Table` as Markdown lines under a heading of ``level``."""
    lines = [f"{level} {t.title} ({t.thesis_ref})", "",
             "| " + " | ".join(t.columns) + " |", "|" + "---|" * len(t.columns)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in t.rows]
    return lines + [""] + ([t.note, ""] if t.note else [])


def _table_html(t: Table) -> str:
    head = "".join(f"<th>{html.escape(c)}</th>" for c in t.columns)
    body = []
    for row in t.rows:
        cells = []
        for c in row:
            cls = ' class="notrun"' if c == NOT_RUN else ""
            cells.append(f"<td{cls}>{html.escape(str(c))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    note = f'<p class="note">{html.escape(t.note)}</p>' if t.note else ""
    return (f'<h3 id="{html.escape(t.id)}">{html.escape(t.title)} '
            f'<small>({html.escape(t.thesis_ref)})</small></h3>'
            f'<div class="wide"><table><thead><tr>{head}</tr></thead>'
            f"<tbody>{''.join(body)}</tbody></table></div>{note}")


def _figure_html(f: Figure) -> str:
    data = base64.b64encode(Path(f.path).read_bytes()).decode()
    note = f" {html.escape(f.note)}" if f.note else ""
    return (f'<figure id="{html.escape(f.id)}"><img alt="{html.escape(f.title)}" '
            f'src="data:image/png;base64,{data}"><figcaption><b>{html.escape(f.thesis_ref)}'
            f"</b> {html.escape(f.title)}.{note}</figcaption></figure>")


def claims_table(claims: list[dict]) -> Table:
    """The claims as a :class:`Table`: sentence, verdict, the numbers in words (thesis
    and measured, with intervals) and the departures."""
    rows = [[c.get("id", ""), c.get("quote", ""), c.get("reading", ""),
             " ".join(x for x in (c.get("detail", ""), V.twin_text(c)) if x),
             "; ".join(V.paper_words(c.get("paper"))),
             "; ".join(V.measured_words(c.get("measured"))),
             "; ".join(V.departure_text(d) for d in c.get("departures", []))]
            for c in claims]
    return Table(id="claims", title="Claims of the thesis and their verdicts",
                 thesis_ref="§2.6, §3.4, §4.8, §5.5, §6.7, §7.5, §8.1",
                 columns=["claim", "thesis says", "verdict", "why", "thesis numbers",
                          "measured (95 % intervals)", "departures"], rows=rows)


def read_power(profile: str, results_root: Path = store.RESULTS_DIR) -> dict | None:
    """``results/<profile>/claims_power.json`` (written by ``thesis check``), or None."""
    path = Path(results_root) / profile / "claims_power.json"
    return json.loads(path.read_text()) if path.exists() else None


def _power_md(power: dict | None) -> list[str]:
    """The power table as Markdown lines (empty when not computed)."""
    if not power or not power.get("rows"):
        return []
    lines = ["### Power: probability of 'reproduced' when the claim is true", "",
             "| rule | truth | " + " | ".join(
                 f"{n} seeds" for n in sorted({r['n_seeds'] for r in power['rows']})) + " |"]
    ns = sorted({r["n_seeds"] for r in power["rows"]})
    lines.append("|---|---|" + "---|" * len(ns))
    for rule, truth in dict.fromkeys((r["rule"], r["truth"]) for r in power["rows"]):
        cells = {r["n_seeds"]: r["power"] for r in power["rows"]
                 if (r["rule"], r["truth"]) == (rule, truth)}
        lines.append(f"| {rule} | {truth} | " + " | ".join(
            f"{100 * cells[n]:.0f} %" if n in cells else "—" for n in ns) + " |")
    return lines + [""]


def wall_times(profile: str, root: Path = Path("benchmarks")) -> list[tuple[str, float]]:
    """(rule output, seconds) from Snakemake's ``benchmark:`` files of a profile."""
    out = []
    base = Path(root) / profile
    if not base.exists():
        return out
    for f in sorted(base.rglob("*.tsv")):
        with open(f) as fh:
            rows = list(csv.DictReader(fh, delimiter="\t"))
        if rows and "s" in rows[0]:
            secs = [float(r["s"]) for r in rows if r.get("s") not in (None, "", "NA")]
            if secs:
                out.append((str(f.relative_to(base).with_suffix("")), sorted(secs)[len(secs) // 2]))
    return out


def _provenance_html(profile: str, results: dict) -> str:
    versions = provenance.package_versions()
    commits = sorted({str(ds.attrs.get("git_commit", "?"))[:10]
                      + ("+dirty" if int(ds.attrs.get("git_dirty", 0)) else "")
                      for ds in results.values()})
    rows = [f"<tr><td>{html.escape(k)}</td><td>{html.escape(k2)}</td>"
            f"<td>{float(ds.attrs.get('wall_seconds', float('nan'))):.1f}</td></tr>"
            for k, ds in sorted(results.items())
            for k2 in [str(ds.attrs.get("started", ""))]]
    bench = "".join(f"<tr><td>{html.escape(n)}</td><td>{s:.1f}</td></tr>"
                    for n, s in wall_times(profile))
    now = datetime.now(timezone.utc).isoformat(timespec="seconds")
    return (
        "<footer><h2>Provenance</h2>"
        f"<p>Profile <b>{html.escape(profile)}</b>; rendered {now}; report code at commit "
        f"{html.escape(provenance.git_commit()[:10])}"
        f"{' (dirty)' if provenance.git_dirty() else ''}; results from commit(s) "
        f"{html.escape(', '.join(commits) or 'none')}.</p>"
        f"<p>Versions: {html.escape(V.kv_text(versions))}. Host: {html.escape(provenance.host())}.</p>"
        '<div class="wide"><table><thead><tr><th>result</th><th>started</th>'
        "<th>compute wall time [s]</th></tr>"
        f"</thead><tbody>{''.join(rows)}</tbody></table></div>"
        + ('<div class="wide"><table><thead><tr><th>rule (snakemake benchmark)</th>'
           "<th>wall time [s]</th></tr>"
           f"</thead><tbody>{bench}</tbody></table></div>" if bench else "")
        + "</footer>")


def _page(title: str, body: str) -> str:
    return (f"<!DOCTYPE html><html lang=en><head><meta charset=utf-8>"
            f"<title>{html.escape(title)}</title><style>{CSS}</style></head>"
            f"<body>{body}</body></html>")


def _chapter_number(ch: str) -> int:
    """Thesis chapter of a report section; -1 for a section that is no chapter (``model``,
    the simulated robot's own checks), which no claim belongs to; ``coopt`` (§8.2 made
    real) holds chapter 8's §8.2 claims."""
    if ch == COOPT_SECTION:
        return 8
    return int(ch.removeprefix("ch")) if ch.startswith("ch") else -1


#: The report section of §8.2's experiments (``thesis.coopt``); its claims are chapter 8's
#: with section §8.2, shown there and not among the §8.1 conclusions.
COOPT_SECTION = "coopt"


def _section_claims(claims: list[dict], ch: str) -> list[dict]:
    """The claims a report section shows: §8.2's in ``coopt``, the rest of chapter 8
    under the conclusions (``"ch8"``), every claim otherwise (filtered by chapter later)."""
    if ch == COOPT_SECTION:
        return [c for c in claims if c.get("section") == "§8.2"]
    if ch == "ch8":
        return [c for c in claims if c.get("section") != "§8.2"]
    return claims


def _summary_md(profile: str, sections: list[Section], claims: list[dict],
                results: dict, power: dict | None = None, damaged=(),
                decided: dict | None = None, twins: list | None = None) -> str:
    lines = [f"# Thesis reproduction — profile `{profile}`", "", *D.damaged_md(list(damaged))]
    lines += status.status_md(status.chapter_status(results, claims),
                              status.optional_runs(results, decided or {}, profile))
    lines += ["Claims: " + ", ".join(f"{k} {v}" for k, v in V.counts(claims).items()), "",
              "A verdict is *as stated* when no declared deviation from the thesis's setup is "
              "in effect in the results it rests on, and *under a declared deviation* "
              "otherwise; the deviations and the choices made where the thesis is silent are "
              "listed beneath each verdict.", ""]
    lines += ["## Method", "", "Per seed; mean over seeds with its 95 % Student t interval; "
              "'reproduced' only at a one-sided 2.5 % (thesis.claims.stats, calibrated by "
              "thesis.claims.calibration).", ""] + _power_md(power)
    lines += status.twin_verdicts_md(claims)
    for s in sections:
        lines += [f"## {s.title}", ""]
        if not s.tables and not s.figures:
            lines += [f"_{NOT_RUN}_", ""]
        for t in s.tables:
            lines += _table_md(t)
        claim_lines = V.summary_lines(_section_claims(claims, s.chapter),
                                      _chapter_number(s.chapter))
        if claim_lines:
            lines += ["### Claims", "", *claim_lines, ""]
        lines += V.summary_departures(V.chapter_departures(results, s.chapter))
    conclusions = V.summary_lines(_section_claims(claims, "ch8"), 8)
    if conclusions:
        lines += ["## §8.1 — Conclusions", "", *conclusions, ""]
    lines += _twin_md(twins or [])
    return "\n".join(lines)


def damaged_files(profile: str, results_root: Path,
                  damaged: dict[str, DamagedFileError]) -> list[DamagedFileError]:
    """The damaged result files a report names: ``damaged`` (the profile's own, as
    :func:`thesis.store.scan_results` found them now) and those ``claims.json`` recorded
    (its twin runs' too), each path once."""
    out = {e.path: e for e in damaged.values()}
    claims_path = Path(results_root) / profile / "claims.json"
    if claims_path.exists():
        for d in json.loads(claims_path.read_text()).get("damaged", []):
            out.setdefault(d["path"], DamagedFileError(d["path"], d["role"], d["cause"],
                                                       d["remake"]))
    return list(out.values())


def render_report(profile: str, outdir: Path, *, config: dict | None = None,
                  results_root: Path = store.RESULTS_DIR,
                  bench_root: Path = Path("benchmarks"),
                  scanned: tuple[dict, dict] | None = None,
                  set_aside: dict[str, DamagedFileError] | None = None) -> Path:
    """Write ``index.html``, ``summary.md``, ``measurements.md`` (jobs' wall time and memory
    from ``bench_root``, :mod:`thesis.report.measurements`) and ``tables/*.html`` under
    ``outdir``. ``scanned``: the profile's results as :func:`thesis.store.scan_results`
    read them (default: read here); damaged files (:func:`damaged_files`) are named at the
    top of the page and of the summary, and what reads them shows "not run"; so is a
    readable result that lacks a variable a chapter's tables read (also added to
    ``set_aside``, :func:`build_sections`)."""
    outdir = Path(outdir)
    results, damaged = scanned or store.scan_results(profile, results_root)
    damaged = damaged_files(profile, results_root, damaged)
    claims_path = Path(results_root) / profile / "claims.json"
    decided = json.loads(claims_path.read_text()) if claims_path.exists() else {}
    claims = decided.get("claims", [])
    aside = {} if set_aside is None else set_aside
    sections = build_sections(results, outdir, profile=profile, results_root=results_root,
                              set_aside=aside)
    twins = twin_sections(profile, results_root, aside)
    named = {e.path for e in damaged}
    damaged = damaged + [e for e in aside.values() if e.path not in named]
    power = read_power(profile, results_root)

    nav = "".join(f'<a href="#{s.chapter}">{s.chapter}</a>' for s in sections)
    verdicts = ", ".join(f"{html.escape(k)} <b>{v}</b>" for k, v in V.counts(claims).items())
    body = [f"<h1>Incorporating Prior Knowledge into Deep Neural Network Controllers of "
            f"Legged Robots — reproduction, profile <code>{html.escape(profile)}</code></h1>",
            D.damaged_html(damaged),
            f"<nav><a href=#method>method</a>{nav}<a href=#claims>claims</a>"
            "<a href=#provenance>provenance</a></nav>",
            status.status_html(status.chapter_status(results, claims),
                               status.optional_runs(results, decided, profile)),
            f"<p>Claims: {verdicts or 'none evaluated'}. A verdict is <i>as stated</i> when no "
            "declared deviation from the thesis's setup is in effect in the results it rests "
            "on, <i>under a declared deviation</i> otherwise; each verdict lists them.</p>",
            V.method_html(power), V.fragility_html(claims, decided.get("twin_runs"),
                                                  decided.get("native_runs")),
            status.twin_verdicts_html(claims)]
    tables_dir = outdir / "tables"
    tables_dir.mkdir(parents=True, exist_ok=True)
    for s in sections:
        body.append(f'<h2 id="{s.chapter}">{html.escape(s.title)}</h2>')
        if not s.tables and not s.figures:
            body.append(f'<p class="notrun">{NOT_RUN}: this chapter\'s experiments have not '
                        "been built or produced no result in this profile.</p>")
        for t in s.tables:
            frag = _table_html(t)
            body.append(frag)
            with store.atomic_path(tables_dir / f"{s.chapter}_{t.id}.html") as tmp:
                tmp.write_text(_page(t.title, frag))
        body.extend(_figure_html(f) for f in s.figures)
        chapter_claims = V.claims_html(_section_claims(claims, s.chapter),
                                       _chapter_number(s.chapter))
        if chapter_claims:
            body.append("<h3>Claims</h3>" + chapter_claims)
        body.append(V.departures_html(V.chapter_departures(results, s.chapter)))
    conclusions = V.claims_html(_section_claims(claims, "ch8"), 8)
    if conclusions:
        body.append('<h2 id="ch8">§8.1 — Conclusions</h2>' + conclusions)
    body.append(_twin_html(twins))
    body.append('<h2 id="claims">All claims</h2>')
    all_claims = V.claims_html(claims) or f'<p class="notrun">{NOT_RUN}</p>'
    body.append(all_claims)
    with store.atomic_path(tables_dir / "claims.html") as tmp:
        tmp.write_text(_page("Claims", all_claims))
    body.append('<div id="provenance"></div>' + _provenance_html(profile, results))
    index = outdir / "index.html"
    with store.atomic_path(index) as tmp:
        tmp.write_text(_page(f"Thesis reproduction ({profile})", "\n".join(body)))
    with store.atomic_path(outdir / "summary.md") as tmp:
        tmp.write_text(_summary_md(profile, sections, claims, results, power, damaged,
                                  decided, twins))
    with store.atomic_path(outdir / "measurements.md") as tmp:
        tmp.write_text(measurements.measurements_md(profile, results, bench_root,
                                                    (config or {}).get("budget")))
    return index
