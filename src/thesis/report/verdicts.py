"""Claims beside their verdicts and the departures they rest on, as HTML and Markdown.

Reads ``claims.json`` entries (:func:`thesis.claims.evaluate`): every verdict is shown
with its *reading* ("reproduced as stated", "reproduced under a declared deviation", ...)
and, beside it, the departures of the results it rests on: deviations in effect with the
run's config values and the thesis's stated values (``thesis.paper`` keys), deviations
declared but not in effect in this run, and the choices made where the thesis is silent.
Per chapter, :func:`chapter_departures` lists every departure of its results once.
"""

from __future__ import annotations

import html
import json

from thesis.claims import basis, model_validity
from thesis.claims import ch6 as claims_ch6

STATUS_COLOURS = {
    "reproduced": "#1b7837",
    "not_reproduced": "#b2182b",
    "inconclusive": "#b8860b",
    "not_run": "#777777",
}


def _short(v) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    if isinstance(v, (list, dict)):
        return json.dumps(v)
    return str(v)


def kv_text(d) -> str:
    """``k = v; ...`` of a dict (floats to 4 significant digits)."""
    if not d:
        return ""
    if isinstance(d, dict):
        return "; ".join(f"{k} = {_short(v)}" for k, v in d.items())
    if isinstance(d, list):
        return "; ".join(kv_text(x) for x in d)
    return str(d)


def paper_text(entries) -> str:
    """The thesis's numbers a claim rests on: ``value unit (key)``."""
    return "; ".join(f"{_short(e.get('value'))} {e.get('unit', '')}".strip()
                     + f" ({e.get('key', '')})" for e in entries or [])


def departure_text(d: dict) -> str:
    """One departure in one line: kind, id, the run's config values, the thesis's values."""
    ours = ", ".join(f"{p} = {_short(v)}" for p, v in d.get("config", {}).items())
    thesis = "; ".join(f"{_short(e['value'])} {e.get('unit', '')}".strip() + f" ({e['key']})"
                       for e in d.get("paper", []) if e.get("value") is not None)
    state = "" if d.get("in_effect", True) else " [not in effect in this run]"
    parts = [f"{d['kind']} {d['id']}{state}: {d['ours']}"]
    if ours:
        parts.append(f"this run: {ours}")
    if thesis:
        parts.append(f"thesis: {thesis}")
    return " | ".join(parts)


def split(deps) -> tuple[list, list, list]:
    """(deviations in effect, deviations not in effect, choices)."""
    dev = [d for d in deps if d["kind"] == "deviation"]
    return ([d for d in dev if d["in_effect"]], [d for d in dev if not d["in_effect"]],
            [d for d in deps if d["kind"] != "deviation"])


def twin_text(c: dict) -> str:
    """The verdict on the perturbed twin runs (:func:`thesis.claims.perturbed_view`):
    "" where the claim's results have no twins."""
    twin = c.get("perturbed")
    if not twin:
        return ""
    status = str(twin.get("status", "")).replace("_", " ")
    if c.get("fragile"):
        return f"FRAGILE: the perturbed twin runs give '{status}'"
    return f"the perturbed twin runs give the same verdict ({status})"


def status_html(status: str) -> str:
    """A coloured badge of a verdict status."""
    colour = STATUS_COLOURS.get(status, "#777")
    return (f'<span class="status" style="background:{colour}">'
            f"{html.escape(status.replace('_', ' '))}</span>")


def _deps_html(deps) -> str:
    on, off, choices = split(deps)
    items = []
    for d in on + off:
        cls = "" if d["in_effect"] else ' class="note"'
        items.append(f"<li{cls} title=\"{html.escape(d['why'])}\">"
                     f"{html.escape(departure_text(d))}</li>")
    if choices:
        items.append('<li class="note">choices: ' + ", ".join(
            f'<code title="{html.escape(d["ours"])}">{html.escape(d["id"])}</code>'
            for d in choices) + "</li>")
    return f"<ul>{''.join(items)}</ul>" if items else "none"


_UNIT_WORDS = {"percent": "%", "1": "", "": "", "fraction": "", "m s-1": "m/s",
               "rad s-1": "rad/s"}


def unit_words(unit: str | None) -> str:
    """A unit as a reader writes it ("percent" -> "%", "1" -> nothing)."""
    u = str(unit or "").strip()
    return _UNIT_WORDS.get(u, u)


def _words(key: str) -> str:
    return key.replace("_", " ")


def paper_words(entries) -> list[str]:
    """The thesis's numbers in words: ``Tab. 5.3 useful, TEST RC: 76.3 %``."""
    out = []
    for e in entries or []:
        where = " ".join(str(e.get(k) or "") for k in ("table", "row")).strip()
        col = str(e.get("column") or "")
        if col and col != str(e.get("key", "")).rsplit("/", 1)[-1]:
            where = f"{where}, {col}" if where else col
        value = f"{_short(e.get('value'))} {unit_words(e.get('unit'))}".strip()
        out.append(f"{where or e.get('key', '')}: {value}")
    return out


def _group(measured: dict) -> dict[str, dict]:
    """Measured numbers by part (``"part.name"`` keys of combined verdicts; "" for none)."""
    parts: dict[str, dict] = {}
    for k, v in (measured or {}).items():
        part, _, name = k.rpartition(".")
        parts.setdefault(part, {})[name] = v
    return parts


def _interval_items(d: dict) -> tuple[list[str], set[str]]:
    """(``"x: mean M, 95 % interval [L, H]"`` per interval in ``d``, the keys used)."""
    lines, used = [], set()
    for k in d:
        if not k.endswith("_ci_low"):
            continue
        base = k[: -len("_ci_low")]
        mean_key = f"{base}_mean" if f"{base}_mean" in d else None
        high_key = f"{base}_ci_high"
        if high_key not in d:
            continue
        used |= {k, high_key} | ({mean_key} if mean_key else set())
        mean = f"{_short(d[mean_key])}, " if mean_key else ""
        lines.append(f"{_words(base)}: {mean}95 % interval [{_short(d[k])}, "
                     f"{_short(d[high_key])}]")
    return lines, used


def measured_words(measured: dict) -> list[str]:
    """The numbers behind a verdict in words: per part, its intervals first (mean with its
    95 % interval), then its seed count and the other numbers."""
    out = []
    for part, d in _group(measured).items():
        intervals, used = _interval_items(d)
        rest = []
        if "n_seeds" in d:
            rest.append(f"{_short(d['n_seeds']).removesuffix('.0')} seeds")
            used.add("n_seeds")
        rest += [f"{_words(k)} {_short(v)}" for k, v in d.items() if k not in used]
        text = "; ".join(intervals + rest)
        out.append(f"{_words(part)}: {text}" if part else text)
    return out


def _units_words(units: dict, measured_units: dict | None = None) -> str:
    """The units note beside the measured numbers.

    A claim that declares the units of the numbers it reports (``measured_units``) is
    labelled with those ("numbers in: error in %; ratio in 1 ..."). Otherwise only the
    units of the variables it *reads* are known, and they are named as such ("read from:
    mse curve in rad^2"), not as the units of every shown number: a log ratio or a
    relative gain computed from a variable does not carry the variable's unit.
    """
    if measured_units:
        items = [f"{k.replace('_', ' ')} in {unit_words(u) or 'units of 1'}"
                 for k, u in measured_units.items() if u not in (None, "")]
        return "numbers in: " + "; ".join(dict.fromkeys(items)) if items else ""
    items = [f"{k.split(':')[-1].replace('_', ' ')} in {unit_words(u) or 'units of 1'}"
             for k, u in (units or {}).items() if u not in (None, "")]
    return "read from: " + "; ".join(dict.fromkeys(items)) if items else ""


def _list_html(items: list[str]) -> str:
    return "<ul>" + "".join(f"<li>{html.escape(x)}</li>" for x in items) + "</ul>"


def _numbers_html(c: dict) -> str:
    """Measured vs thesis numbers in words and units; the raw keys behind a fold-out."""
    thesis = paper_words(c.get("paper"))
    measured = measured_words(c.get("measured"))
    units = _units_words(c.get("units"), c.get("measured_units"))
    parts = []
    if thesis:
        parts.append("<b>thesis</b>" + _list_html(thesis))
    if measured:
        parts.append("<b>measured</b>" + (f' <span class="note">({html.escape(units)})'
                                           "</span>" if units else "") + _list_html(measured))
    if c.get("statistic"):
        parts.append(f'<span class="note">{html.escape(c["statistic"])}</span>')
    raw = kv_text(c.get("measured"))
    keys = "; ".join(e.get("key", "") for e in c.get("paper") or [])
    if raw or keys:
        parts.append("<details><summary>raw keys</summary>"
                     + (f"<p><b>measured</b> <code>{html.escape(raw)}</code></p>" if raw else "")
                     + (f"<p><b>thesis</b> <code>{html.escape(keys)}</code></p>" if keys else "")
                     + "</details>")
    return "".join(parts) or "—"


def claims_html(claims: list[dict], chapter: int | None = None) -> str:
    """Table of the claims of ``chapter`` (all when None): per claim the sentence and what
    is checked, the verdict with its reading and reason, the measured and the thesis's
    numbers in words (raw keys folded away) and the departures beside it."""
    sel = [c for c in claims if chapter is None or c.get("chapter") == chapter]
    if not sel:
        return ""
    rows = []
    for c in sel:
        rows.append("<tr>" + "".join([
            f"<td>{html.escape(c.get('quote', ''))}<br><span class=note>"
            f"{html.escape(c.get('summary', ''))}<br><code>{html.escape(c.get('id', ''))}"
            f"</code> {html.escape(c.get('section', ''))}</span></td>",
            f"<td>{status_html(c.get('status', 'not_run'))}<br><b>"
            f"{html.escape(c.get('reading', ''))}</b><br><span class=note>"
            f"{html.escape(c.get('detail', ''))}</span>"
            + (f"<br><span class=\"{'fragile' if c.get('fragile') else 'note'}\">"
               f"{html.escape(twin_text(c))}</span>" if twin_text(c) else "")
            + (f"<br><span class=\"fragile\">{html.escape(model_validity.text(c))}</span>"
               if model_validity.text(c) else "") + "</td>",
            f"<td>{_numbers_html(c)}</td>",
            f"<td>{_deps_html(c.get('departures', []))}</td>",
        ]) + "</tr>")
    return ('<table class="claims"><colgroup><col style="width:30%"><col style="width:22%">'
            '<col style="width:30%"><col style="width:18%"></colgroup>'
            "<thead><tr><th>the thesis says / what is checked</th><th>verdict</th>"
            "<th>measured and thesis numbers, interval</th>"
            "<th>departures it rests on</th></tr></thead>"
            f"<tbody>{''.join(rows)}</tbody></table>")


def method_html(power: dict | None) -> str:
    """The method section: how a verdict is decided, and the power of the rules
    (``claims_power.json``, :func:`thesis.claims.calibration.power_table`)."""
    text = (
        "<p>Every claim is decided per seed (the unit of replication) by one set of rules "
        "(<code>thesis.claims.stats</code>). An interval is the mean over seeds with its 95 % "
        "Student t interval; a claim is <i>reproduced</i> only when the one-sided 2.5 % "
        "test behind that interval says so: A beats B when the interval of the paired "
        "advantage lies above 0, A is like B when the interval of the difference lies "
        "inside the margin, X is beyond a bound when its interval is. The interval was "
        "chosen on a calibration simulation alone (<code>thesis.claims.calibration</code>, "
        "3, 5 and 10 seeds, normal, exponential and heavy-tailed per-seed laws): the "
        "bootstrap interval used before said 'reproduced' far more often than 2.5 % under "
        "no difference, and rank or sign-flip tests cannot reach 2.5 % below 6 seeds. It "
        "assumes independent seeds and per-seed values (paired differences) roughly "
        "symmetric about their mean. 'In most runs' is an exact binomial test against "
        "1/2 (5 seeds or fewer can never show it: inconclusive), and so are sentences about "
        "what a method usually does ('learns in', 'reached within N evaluations'); an "
        "existential sentence ('an attractor was found') holds only when more seeds show "
        "it, each repeated by its perturbed twin run, than runs passing by chance at 5 % "
        "would give (without a twin, against 5 % itself), the rate beside it; a "
        "claim that holds when some configuration does corrects for looking at all of "
        "them (Holm); a claim about classification quality needs the methods to beat the "
        "test set's majority-class share first. Fewer than 3 seeds, or a profile smaller "
        "than the thesis's setup, give <i>inconclusive</i>. Every inconclusive verdict "
        "says why: its simulated model failed validation (the targets named), the profile "
        "is smaller than the thesis's setup, it needs about N seeds (80 % power of its "
        "rule at the measured effect, within the paper profile's seed count), or it is "
        "ambiguous at any seed count the paper profile has.</p>")
    text += decidability_html()
    if not power or not power.get("rows"):
        return ('<h2 id="method">Method: how a verdict is decided</h2>' + text
                + '<p class="notrun">power table not computed (run <code>thesis check</code>)'
                  "</p>")
    rows = power["rows"]
    # one row per rule and truth, one column per seed count ("—": not computed there)
    lines = list(dict.fromkeys((r["rule"], r["truth"]) for r in rows))
    ns = sorted({int(r["n_seeds"]) for r in rows})
    cell = {(r["rule"], r["truth"], int(r["n_seeds"])): r["power"] for r in rows}
    head = "".join(f"<th>{n} seeds</th>" for n in ns)
    body = "".join(
        f"<tr><td>{html.escape(_RULE_WORDS.get(rule, rule))}</td>"
        f"<td>{html.escape(truth)}</td>" + "".join(
            f"<td>{100 * cell[(rule, truth, n)]:.0f} %</td>" if (rule, truth, n) in cell
            else "<td>—</td>" for n in ns) + "</tr>" for rule, truth in lines)
    return ('<h2 id="method">Method: how a verdict is decided</h2>' + text
            + "<h3>Power: probability of 'reproduced' when the claim is true</h3>"
            '<div class="wide"><table><thead><tr><th>rule</th><th>what is true</th>' + head
            + "</tr></thead><tbody>" + body + "</tbody></table></div>"
            + f'<p class="note">Simulated with {power.get("reps")} draws per cell (seeded), '
              "normal per-seed differences in standard deviations; 'in most runs' and "
              "chapter 6's 'a configuration works / fails' (against success rates of "
              f"{claims_ch6.FAILS_RATE:g} / {claims_ch6.WORKS_RATE:g}) exact; runs that "
              "fail: working runs near 1.0, failed ones near 0.2 (declared range 0-0.4), "
              "decided with each seed's failure flag. "
              f"Nominal false-'reproduced' rate {100 * power.get('nominal', 0.025):g} %.</p>")


def decidability_html() -> str:
    """The seeds each claim needs (:mod:`thesis.claims.decidability`), one row per claim:
    the first seed count at which its thesis-shaped synthetic data are reproduced and the
    reversed finding not reproduced ("none up to 100" where no grid point decides it),
    beside the paper profile's ("—": a measurement without seeds), and why a claim beyond
    it is untestable there."""
    from thesis import claims as all_claims
    from thesis.claims import decidability

    rows = []
    for cid, need in decidability.SEEDS_NEEDED.items():
        rec = decidability.record(cid, all_claims.get(cid).requires)
        rows.append(f"<tr><td><code>{html.escape(cid)}</code></td>"
                    f"<td>{'none up to 100' if need is None else need}</td>"
                    f"<td>{rec['paper_seeds'] if rec['paper_seeds'] is not None else '—'}</td>"
                    f"<td>{html.escape(rec['untestable']) or 'decidable'}</td></tr>")
    return ("<h3>Seeds a claim needs: the decidability test</h3><p class=note>The first "
            "seed count (of 3, 5, 10, 20, 40, 100) at which the thesis-shaped synthetic "
            "finding is reproduced and the reversed finding not reproduced; the fixtures' "
            "own per-seed noise is small, so this is what the rule needs, not what real "
            "runs' spread needs (an inconclusive verdict's own 'needs about N seeds' "
            "is sized at its measured spread). A claim read from one measurement without "
            "seeds (a timing of Tab. 7.1, the hand-tuned trot) is decided at any seed count: "
            "3, the grid's first, and its paper profile column is '—'.</p>"
            "<table><thead><tr><th>claim</th>"
            "<th>seeds needed</th><th>paper profile</th><th>at the paper profile</th>"
            "</tr></thead><tbody>" + "".join(rows) + "</tbody></table>")


def _moved_text(claims: list[dict], twin: str, flag: str) -> str:
    """'k of n claims decided on twins, m moved: ids' (or 'no twin runs') for one chapter's
    claims and one kind of twin (``twin``: the claim's key of the twin verdict, ``flag``:
    its key of "the verdict moved")."""
    checked = [c for c in claims if twin in c]
    moved = [c["id"] for c in checked if c.get(flag)]
    if not checked:
        return "no twin runs"
    return (f"{len(checked)} of {len(claims)} claims decided on twins, {len(moved)} "
            + ("fragile" if flag == "fragile" else "moved")
            + (": " + ", ".join(moved) if moved else ""))


def fragility_html(claims: list[dict], twin_runs: list[str] | None = None,
                   native_runs: list[str] | None = None) -> str:
    """How much of each chapter's verdicts survives a rounding-level perturbation of its
    runs, and another instruction set: per chapter, the claims decided again on perturbed
    twin runs (chapter 6's own per-run twins; every other chapter's
    ``results/<profile>-perturbed/``, ``twin_runs``) and those whose verdict moved
    (fragile); the claims decided again on native twin runs (``results/<profile>-native/``,
    ``native_runs``: every CPU pin lifted) and those whose verdict moved (ISA-dependent);
    or that no such twin runs were made."""
    text = ("<h3 id=\"fragility\">Fragility: the verdicts on perturbed and native twin "
            "runs</h3><p>A closed loop that is chaotic at the rounding level turns a last-bit "
            "difference (another CPU's kernels) into another outcome. A perturbed twin run "
            "starts every simulation (chapter 2: every network's initial weights) moved by "
            "about one float32 ulp (relative 1e-7) and is decided by the same rules; a "
            "verdict it moves is <b class=fragile>fragile</b>. Chapter 6's runs carry their "
            "own twins; the other chapters' are made with <code>snakemake --config "
            "profile=&lt;p&gt; perturb=1e-7</code> into <code>results/&lt;p&gt;-perturbed/"
            "</code>. A native twin run computes with the host's own kernels instead of the "
            "AVX2-class ones every run is pinned to (<code>snakemake --config "
            "profile=&lt;p&gt; isa=native</code> into <code>results/&lt;p&gt;-native/</code>; "
            "on an AVX-512 host, AVX-512 numpy, OpenBLAS and XLA code); a verdict it moves "
            "depends on the instruction set.</p>")
    rows = []
    for ch in sorted({int(c.get("chapter", 0)) for c in claims}):
        sel = [c for c in claims if int(c.get("chapter", 0)) == ch]
        rows.append(f"<tr><td>{ch}</td>"
                    f"<td>{html.escape(_moved_text(sel, 'perturbed', 'fragile'))}</td>"
                    f"<td>{html.escape(_moved_text(sel, 'native', 'isa_dependent'))}</td></tr>")
    for label, runs in (("Perturbed twin runs", twin_runs), ("Native twin runs", native_runs)):
        if runs:
            text += (f"<p class=note>{label} read: {len(runs)} results ("
                     + html.escape(", ".join(sorted({k.split('/')[0] for k in runs})))
                     + ").</p>")
    return (text + "<table><thead><tr><th>chapter</th><th>verdicts on perturbed twin runs"
            "</th><th>verdicts on native twin runs</th></tr></thead><tbody>" + "".join(rows)
            + "</tbody></table>")


_RULE_WORDS = {"rule4_beats": "A beats B", "rule5_equivalent": "A is like B",
               "rule10_majority": "in most runs",
               "rate_works": "a configuration works (ch. 6)",
               "rate_fails": "a configuration fails (ch. 6)",
               "rule6_failing_runs": "X above a bound, runs that fail (rule 3b)",
               "rule10_exists": "it happened (existence, repeated by its twin)",
               "rule10_exists_spurious": "it happened, but no event exists (false "
                                         "existence)"}


def counts(claims: list[dict]) -> dict[str, int]:
    """Number of claims per reading, in :data:`thesis.claims.basis.READINGS` order."""
    out = {r: 0 for r in basis.READINGS}
    for c in claims:
        r = c.get("reading") or c.get("status", "?").replace("_", " ")
        out[r] = out.get(r, 0) + 1
    return {k: v for k, v in out.items() if v}


def chapter_departures(results: dict, chapter: str) -> list[dict]:
    """Every departure of the chapter's results once, with the results it reaches."""
    merged: dict[str, dict] = {}
    for key, ds in sorted(results.items()):
        if not key.startswith(chapter + "/"):
            continue
        for rec in basis.result_departures(key, ds):
            have = merged.setdefault(rec["id"], {**rec, "results": []})
            have["results"].append(key)
            have["in_effect"] = have["in_effect"] or rec["in_effect"]
    return sorted(merged.values(), key=lambda d: (d["kind"] != "deviation", d["id"]))


def departures_html(deps: list[dict]) -> str:
    """Table of a chapter's departures (deviations first)."""
    if not deps:
        return ""
    rows = []
    for d in deps:
        rows.append("<tr>" + "".join(
            f"<td>{html.escape(x)}</td>" for x in (
                d["id"], d["kind"] + ("" if d["in_effect"] else " (not in effect)"),
                d["thesis"], d["ours"], d["why"],
                kv_text(d.get("config")) or "—",
                paper_text(d.get("paper")) or "—", ", ".join(d["results"]))) + "</tr>")
    return ('<h3>Departures from the thesis</h3><div class="wide"><table><thead><tr>'
            "<th>id</th><th>kind</th>"
            "<th>the thesis</th><th>the pipeline</th><th>why</th><th>config values</th>"
            "<th>thesis values</th><th>results</th></tr></thead>"
            f"<tbody>{''.join(rows)}</tbody></table></div>")


def summary_lines(claims: list[dict], chapter: int) -> list[str]:
    """Markdown bullets of a chapter's claims, each with its departures beneath."""
    lines = []
    for c in claims:
        if c.get("chapter") != chapter:
            continue
        twin = f" ({twin_text(c)})" if twin_text(c) else ""
        unvalidated = f" [{model_validity.text(c)}]" if model_validity.text(c) else ""
        lines.append(f"- **{c.get('reading') or c.get('status', '')}**{unvalidated} "
                     f"`{c.get('id')}`: {c.get('detail', '')}{twin}")
        on, off, choices = split(c.get("departures", []))
        for d in on + off:
            lines.append(f"  - {departure_text(d)}")
        if choices:
            lines.append("  - choices: " + ", ".join(f"`{d['id']}`" for d in choices))
    return lines


def summary_departures(deps: list[dict]) -> list[str]:
    """Markdown table of a chapter's departures."""
    if not deps:
        return []
    out = ["#### Departures from the thesis", "",
           "| id | kind | the pipeline | this run | thesis |", "|---|---|---|---|---|"]
    for d in deps:
        kind = d["kind"] + ("" if d["in_effect"] else " (not in effect)")
        cells = [f"`{d['id']}`", kind, d["ours"], kv_text(d.get("config")) or "—",
                 paper_text(d.get("paper")) or "—"]
        out.append("| " + " | ".join(c.replace("|", "/") for c in cells) + " |")
    return out + [""]
