"""The report's first screen and the top of ``summary.md``: where each chapter stands.

Per report section (chapters 2-7, §8.2, the Oncilla's model checks, §8.1's conclusions)
one :class:`ChapterStatus`, generated from what is on disk, never typed:

* what ran: the results present under ``results/<profile>/<section>/``, the profile and
  the git commit(s) recorded in their provenance attributes (``profile``, ``git_commit``,
  ``git_dirty``, ``host``), and when the newest was started;
* the verdicts of its claims (``claims.json``, :func:`thesis.claims.evaluate_all`) counted
  per status, and how many were decided again on perturbed twin runs (fragile when they
  move) and on native twin runs (ISA-dependent when they move);
* its headline: one claim per section (:data:`HEADLINES`, a choice of which claim stands
  for the chapter, not a result), its verdict with the thesis's numbers beside the
  measured ones, both read from ``claims.json``.

Chapter 6's runs carry their own perturbed twins: the status counts the runs whose
outcome the twin changed (their ``flipped`` variable). :func:`twin_verdicts_md` lists every
claim decided again on twin runs with its verdict on each (method section).

Beside it, :func:`optional_runs` says which of the runs outside ``make all`` (the twin
runs, Tab. 5.3's protocol variants, the MuJoCo/MJX peers, chapter 2's width pilot and
training-step bench, the Oncilla's model checks) are on disk, with the command that makes
each. The README points here instead of
quoting results (issue: results only where the pipeline writes them).
"""

from __future__ import annotations

import html
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from thesis.claims import kinds as claim_kinds
from thesis.report import verdicts as V
from thesis.report.chapters import CHAPTERS

__all__ = ["HEADLINES", "SECTIONS", "STATUS_ORDER", "ChapterStatus", "chapter_status",
           "optional_runs", "status_md", "status_html", "twin_verdicts_md",
           "twin_verdicts_html"]

#: Verdict statuses in the order the status table counts them.
STATUS_ORDER = ("reproduced", "not_reproduced", "inconclusive", "not_run")

#: Section id -> (what it reproduces, the code that does it). ``ch8`` holds §8.1's
#: conclusions, which read the other chapters' results.
SECTIONS: dict[str, tuple[str, str]] = {
    "ch2": ("chirp-Z spatial transformer networks on synthesised cluttered MNIST "
            "sequences (Tab. 2.2, §2.4 scaling)", "thesis.ch2"),
    "ch3": ("Oncilla trotting and turning gaits optimised by PSO (Tab. 3.1, 3.2, "
            "Fig. 3.4, 3.5)", "thesis.ch3, thesis.gaits, thesis.optim"),
    "ch4": ("transfer learning of gaits with PSO: slopes, softer front legs, pebbles "
            "(Tab. 4.2-4.4, Fig. 4.3, 4.5-4.10)",
            "thesis.ch4, thesis.gaits, thesis.optim.transfer"),
    "ch5": ("terrain classification from simulated Puppy II recordings: LR, ELM, "
            "reservoirs, SFA + ICA, CMA-ES tuning (Tab. 5.3-5.6, Fig. 5.3)",
            "thesis.ch5"),
    "ch6": ("an embodied trot and walk learned online (ELM + delay buffer + RLS), "
            "power-off, minimal sizes (Fig. 6.4-6.6)", "thesis.ch6"),
    "ch7": ("the differentiable engine: ball throw, Tab. 7.1, arm, quadruped gait, "
            "pendulum from pixels", "thesis.physics, thesis.ch7"),
    "coopt": ("§8.2 made real: controller and body co-optimised by gradient; the "
              "engine's gradient beside REINFORCE and ES estimates", "thesis.coopt"),
    "model": ("the simulated Oncilla's own checks (falls, roll-overs, push recovery) and "
              "the Puppy II's paw contact against sourced values; no thesis claim",
              "thesis.modelcheck"),
    "ch8": ("§8.1's conclusions, decided on the chapters' results", "thesis.claims.ch8"),
}

#: Section id -> the claim whose verdict and numbers stand for it on the first screen
#: (a choice of emphasis: every claim is listed in its section below).
HEADLINES: dict[str, str] = {
    "ch2": "ch2.spatial_transformers_beat_plain",
    "ch3": "ch3.half_ellipse_fastest",
    "ch4": "ch4.transfer_significant_on_slopes",
    "ch5": "ch5.rc_touch_best_overall",
    "ch6": "ch6.trot_h50_b5_stable",
    "ch7": "ch7.gradient_costs_small_factor",
    "coopt": "ch8.coopt_joint_beats_controller_only",
    "ch8": "ch8.ch2_prior_in_architecture_beats_cnn",
}

_CONCLUSIONS_TITLE = "§8.1 — Conclusions"


@dataclass(frozen=True)
class ChapterStatus:
    """Where one report section stands.

    Attributes:
        chapter: section id (``"ch2"`` ... ``"ch7"``, ``"coopt"``, ``"model"``, ``"ch8"``).
        title: its report title.
        results: its result keys on disk (``"ch3/table3_1"``, ...), sorted.
        profiles: the ``profile`` attributes of those results.
        commits: their ``git_commit`` (10 characters, ``+dirty`` when ``git_dirty``).
        hosts: their ``host`` attributes.
        latest: the newest ``started`` attribute (ISO time), "" when none.
        counts: verdict status -> number of the section's claims.
        twinned, fragile: claims decided again on perturbed twin runs; of those, moved.
        native, isa_dependent: claims decided again on native twin runs; of those, moved.
        runs_twinned, runs_flipped: runs that carry their own perturbed twin (chapter 6,
            the ``flipped`` variable of :mod:`thesis.ch6.twins`); of those, the runs
            whose outcome the twin changed.
        headline: the headline claim's entry of ``claims.json`` (None when absent).
    """

    chapter: str
    title: str
    results: list[str] = field(default_factory=list)
    profiles: list[str] = field(default_factory=list)
    commits: list[str] = field(default_factory=list)
    hosts: list[str] = field(default_factory=list)
    latest: str = ""
    counts: dict[str, int] = field(default_factory=dict)
    twinned: int = 0
    fragile: int = 0
    native: int = 0
    isa_dependent: int = 0
    runs_twinned: int = 0
    runs_flipped: int = 0
    headline: dict | None = None
    kinds: dict[str, int] = field(default_factory=dict)

    @property
    def ran(self) -> bool:
        """Whether anything of the section is on disk or decided."""
        return bool(self.results) or any(
            n for s, n in self.counts.items() if s != "not_run")


def _section_of(claim: Mapping) -> str:
    """The report section a claim belongs to: ``coopt`` for §8.2, ``ch8`` for §8.1, else
    ``ch<chapter>``."""
    if claim.get("section") == "§8.2":
        return "coopt"
    return f"ch{int(claim.get('chapter', 0))}"


def _commit(ds: xr.Dataset) -> str:
    dirty = str(ds.attrs.get("git_dirty", 0)) not in ("0", "False", "false", "")
    return str(ds.attrs.get("git_commit", "?"))[:10] + ("+dirty" if dirty else "")


def _flips(dss: list[xr.Dataset]) -> tuple[int, int]:
    """(runs with a per-run twin, runs whose outcome it changed) over the datasets'
    ``flipped`` variables (1 where the twin's outcome differs; NaN where not run)."""
    flags = [np.asarray(d["flipped"].values, dtype=float).ravel()
             for d in dss if "flipped" in d.data_vars]
    flags = np.concatenate(flags) if flags else np.zeros(0)
    flags = flags[np.isfinite(flags)]
    return int(flags.size), int((flags > 0.5).sum())


def chapter_status(results: Mapping[str, xr.Dataset],
                   claims: list[dict]) -> list[ChapterStatus]:
    """One :class:`ChapterStatus` per report section, in report order, §8.1 last.

    Args:
        results: ``{"<section>/<artifact>": Dataset}`` as ``thesis.store.load_results``.
        claims: the ``claims`` list of ``claims.json``.
    """
    by_id = {c.get("id"): c for c in claims}
    out = []
    for ch, title in [*CHAPTERS.items(), ("ch8", _CONCLUSIONS_TITLE)]:
        keys = sorted(k for k in results if k.split("/", 1)[0] == ch)
        dss = [results[k] for k in keys]
        sel = [c for c in claims if _section_of(c) == ch]
        counts = {s: 0 for s in STATUS_ORDER}
        for c in sel:
            s = str(c.get("status", "not_run"))
            counts[s] = counts.get(s, 0) + 1
        runs_twinned, runs_flipped = _flips(dss)
        kinds: dict[str, int] = {}
        for c in sel:
            k = claim_kinds.kind_of(c)
            if k and c.get("status") == "inconclusive":
                kinds[k] = kinds.get(k, 0) + 1
        out.append(ChapterStatus(
            chapter=ch, title=title, results=keys,
            profiles=sorted({str(d.attrs.get("profile", "?")) for d in dss}),
            commits=sorted({_commit(d) for d in dss}),
            hosts=sorted({str(d.attrs["host"]) for d in dss if "host" in d.attrs}),
            latest=max((str(d.attrs["started"]) for d in dss if "started" in d.attrs),
                       default=""),
            counts={s: n for s, n in counts.items() if n},
            twinned=sum("perturbed" in c for c in sel),
            fragile=sum(bool(c.get("fragile")) for c in sel),
            native=sum("native" in c for c in sel),
            isa_dependent=sum(bool(c.get("isa_dependent")) for c in sel),
            runs_twinned=runs_twinned, runs_flipped=runs_flipped,
            headline=by_id.get(HEADLINES.get(ch)),
            kinds={k: kinds[k] for k in sorted(kinds, key=_kind_order)}))
    return out


#: Result names listed per section in the status (the rest are counted).
_NAMES_SHOWN = 8


def _what_ran(s: ChapterStatus) -> str:
    if not s.results:
        return "no results" if s.chapter != "ch8" else "reads the chapters' results"
    names = [k.split("/", 1)[1] for k in s.results]
    names = ", ".join(names[:_NAMES_SHOWN]) + (
        f" and {len(names) - _NAMES_SHOWN} more" if len(names) > _NAMES_SHOWN else "")
    plural = "" if len(s.results) == 1 else "s"
    return (f"{len(s.results)} result{plural} ({names}); profile {', '.join(s.profiles)}; "
            f"commit {', '.join(s.commits)}"
            + (f"; host {', '.join(s.hosts)}" if s.hosts else "")
            + (f"; newest started {s.latest}" if s.latest else ""))


def _kind_order(kind: str) -> int:
    return claim_kinds.KINDS.index(kind) if kind in claim_kinds.KINDS else len(
        claim_kinds.KINDS)


def _kind_words(s: ChapterStatus) -> str:
    """The inconclusive verdicts counted by kind ("" when none carries one)."""
    return ", ".join(f"{n} {k}" for k, n in s.kinds.items())


def _verdict_words(s: ChapterStatus) -> str:
    if not s.counts:
        return "no claims"
    words = ", ".join(f"{n} {st.replace('_', ' ')}" for st, n in s.counts.items())
    kinds = _kind_words(s)
    return words + (f" (inconclusive: {kinds})" if kinds else "")


def _twin_words(s: ChapterStatus) -> str:
    if not s.counts:
        return "—"
    parts = [f"{s.fragile} of {s.twinned} fragile" if s.twinned else "no perturbed twins",
             f"{s.isa_dependent} of {s.native} ISA-dependent" if s.native
             else "no native twins"]
    if s.runs_twinned:
        parts.append(f"the per-run twins change {s.runs_flipped} of {s.runs_twinned} "
                     "run outcomes")
    return "; ".join(parts)


def _headline_words(s: ChapterStatus, limit: int = 2) -> tuple[str, str, str]:
    """(claim id and verdict, thesis numbers, measured numbers) of the headline, the
    numbers in words, at most ``limit`` items each (the claim's row has them all)."""
    c = s.headline
    if c is None:
        return ("—", "—", "—")
    thesis = "; ".join(V.paper_words(c.get("paper"))[:limit]) or "—"
    measured = [x for w in V.measured_words(c.get("measured")) for x in w.split("; ")]
    return (f"{c.get('id')}: {c.get('reading') or c.get('status', '')}", thesis,
            "; ".join(measured[:limit]) or "—")


def optional_runs(results: Mapping[str, xr.Dataset], decided: Mapping,
                  profile: str) -> list[tuple[str, str, str]]:
    """(what, the command that makes it, whether it is on disk) for each run outside
    ``make all`` that the report reads when present.

    Args:
        results: the profile's results.
        decided: ``claims.json`` as a dict (``twin_runs``, ``native_runs``: the result
            keys of the perturbed and native twin runs read).
        profile: the profile, for the commands.
    """
    cfg = f"--config profile={profile}"
    twins = sorted({k.split("/")[0] for k in decided.get("twin_runs") or []})
    native = sorted({k.split("/")[0] for k in decided.get("native_runs") or []})

    def have(*keys: str) -> str:
        got = [k for k in keys if k in results]
        return "on disk" if len(got) == len(keys) else "not run"
    return [
        ("perturbed twin runs (fragility: every initial state or weight moved by one "
         "float32 ulp; ch6's runs carry their own)",
         f"snakemake <chapter> {cfg} perturb=1e-7 --cores 2",
         f"read for {', '.join(twins)}" if twins else "not run"),
        ("native twin runs (every CPU pin lifted: the host's own kernels)",
         f"snakemake <chapter> {cfg} isa=native --cores 2",
         f"read for {', '.join(native)}" if native else "not run"),
        ("Tab. 5.3's selection-protocol variants (blocks, parts drawn across trials)",
         f"snakemake ch5_variants {cfg} --cores 2",
         have("ch5/table5_3_blocks", "ch5/table5_3_parts")),
        ("Tab. 7.1's MuJoCo/MJX peers", f"snakemake ch7_table7_1_peers {cfg} --cores 2",
         have("ch7/table7_1_peers")),
        ("chapter 2's width pilot and training-step bench (the measurements behind the "
         "profile's ch2 sizes)", f"snakemake ch2_pilot {cfg} --cores 2",
         have("ch2/width_pilot", "ch2/train_step")),
        ("the simulated Oncilla's model checks (section 'model')",
         f"thesis bench oncilla --profile {profile}", have("model/oncilla")),
        ("the Puppy II's paw contact against the sourced values (section 'model')",
         f"thesis bench puppy-contact --profile {profile}", have("model/puppy_contact")),
        ("the Puppy II's terrains across gaits, one gait held out (section 'model')",
         f"thesis bench puppy-heldout --profile {profile}", have("model/puppy_heldout")),
        ("the fit of the Oncilla's unsourced values to the split's fitted side (section "
         "'model')", f"thesis validate oncilla --only fit --profile {profile}",
         have("model/fit")),
    ]


def status_md(rows: list[ChapterStatus], optional: list[tuple[str, str, str]] | None = None
              ) -> list[str]:
    """The status as Markdown lines: one table row per section, then the optional runs."""
    lines = ["## Status", "",
             "Generated from the results on disk and `claims.json`; every section below "
             "has the tables, figures and claims behind it.", "",
             "| section | what ran | verdicts | twin runs | headline claim | thesis | "
             "measured |", "|---|---|---|---|---|---|---|"]
    for s in rows:
        head, thesis, measured = _headline_words(s)
        cells = [s.title, _what_ran(s), _verdict_words(s), _twin_words(s), head, thesis,
                 measured]
        lines.append("| " + " | ".join(c.replace("|", "/") for c in cells) + " |")
    lines.append("")
    if optional:
        lines += ["Runs outside `make all`, read when present:", "",
                  "| run | command | here |", "|---|---|---|"]
        lines += [f"| {w} | `{c}` | {h} |" for w, c, h in optional]
        lines.append("")
    return lines


def status_html(rows: list[ChapterStatus],
                optional: list[tuple[str, str, str]] | None = None) -> str:
    """The status as the report's first screen: a table with one row per section
    (``id="status"``, each row ``data-chapter=<section>``), then the optional runs."""
    body = []
    for s in rows:
        head, thesis, measured = _headline_words(s)
        badges = " ".join(f"{V.status_html(st)} {n}" for st, n in s.counts.items()) \
            or '<span class="notrun">no claims</span>'
        if s.kinds:
            badges += (f'<br><span class="note">inconclusive: {html.escape(_kind_words(s))}'
                       "</span>")
        cls = "" if s.ran else ' class="notrun"'
        what, code = SECTIONS.get(s.chapter, ("", ""))
        body.append(
            f'<tr data-chapter="{html.escape(s.chapter)}">'
            f'<td><a href="#{html.escape(s.chapter)}">{html.escape(s.title)}</a><br>'
            f'<span class="note">{html.escape(what)} (<code>{html.escape(code)}</code>)</span>'
            f"</td><td{cls}>{html.escape(_what_ran(s))}</td><td>{badges}</td>"
            f"<td>{html.escape(_twin_words(s))}</td>"
            + (f"<td><code>{html.escape(head)}</code><br><b>thesis</b> {html.escape(thesis)}"
               f"<br><b>measured</b> {html.escape(measured)}</td></tr>"
               if s.headline is not None else "<td>—</td></tr>"))
    table = ('<h2 id="status">Status</h2><p class="note">Generated from the results on '
             "disk and <code>claims.json</code>; each section below holds the tables, "
             "figures and claims behind its row.</p>"
             '<table class="claims"><colgroup><col style="width:20%"><col style="width:24%">'
             '<col style="width:16%"><col style="width:12%"><col style="width:28%">'
             "</colgroup><thead><tr><th>section</th><th>what ran</th><th>verdicts</th>"
             "<th>twin runs</th><th>headline: thesis beside measured</th></tr></thead>"
             f"<tbody>{''.join(body)}</tbody></table>")
    if optional:
        table += ('<table class="claims"><thead><tr><th>run outside make all</th>'
                  "<th>command</th><th>here</th></tr></thead><tbody>" + "".join(
                      f"<tr><td>{html.escape(w)}</td><td><code>{html.escape(c)}</code></td>"
                      f"<td>{html.escape(h)}</td></tr>" for w, c, h in optional)
                  + "</tbody></table>")
    return table


def _twin_rows(claims: list[dict]) -> list[tuple[str, str, str, str, str]]:
    """(claim id, verdict on the runs, on perturbed twins, on native twins, what moved)
    for every claim decided again on twin runs."""
    rows = []
    for c in claims:
        if "perturbed" not in c and "native" not in c:
            continue

        def words(d):
            return str(d.get("status", "")).replace("_", " ") if d else "—"
        moved = [w for w, flag in (("fragile", "fragile"), ("ISA-dependent", "isa_dependent"))
                 if c.get(flag)]
        rows.append((str(c.get("id", "")), words(c), words(c.get("perturbed")),
                     words(c.get("native")), ", ".join(moved) or "holds"))
    return rows


def twin_verdicts_md(claims: list[dict]) -> list[str]:
    """Markdown table of every claim decided again on twin runs: its verdict on the runs,
    on the perturbed and on the native twins (empty when no claim has twins)."""
    rows = _twin_rows(claims)
    if not rows:
        return []
    return (["### Verdicts on the twin runs", "",
             "| claim | runs | perturbed twins | native twins | |", "|---|---|---|---|---|"]
            + [f"| `{r[0]}` | " + " | ".join(r[1:]) + " |" for r in rows] + [""])


def twin_verdicts_html(claims: list[dict]) -> str:
    """The table of :func:`twin_verdicts_md` as HTML, folded away (it lists every claim
    with twins); "" when no claim has twins."""
    rows = _twin_rows(claims)
    if not rows:
        return ""
    body = "".join(
        f"<tr><td><code>{html.escape(r[0])}</code></td>"
        + "".join(f"<td>{html.escape(x)}</td>" for x in r[1:4])
        + f'<td class="{"fragile" if r[4] != "holds" else "note"}">{html.escape(r[4])}</td></tr>'
        for r in rows)
    return ("<details><summary>Verdicts of every claim on the runs and on their twins "
            f"({len(rows)} claims)</summary><div class=\"wide\"><table><thead><tr>"
            "<th>claim</th><th>runs</th><th>perturbed twins</th><th>native twins</th>"
            f"<th>moved</th></tr></thead><tbody>{body}</tbody></table></div></details>")
