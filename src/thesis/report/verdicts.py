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

from thesis.claims import basis

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


def claims_html(claims: list[dict], chapter: int | None = None) -> str:
    """Table of the claims of ``chapter`` (all when None), departures beside each verdict."""
    sel = [c for c in claims if chapter is None or c.get("chapter") == chapter]
    if not sel:
        return ""
    rows = []
    for c in sel:
        rows.append("<tr>" + "".join([
            f"<td>{html.escape(c.get('id', ''))}<br><span class=note>"
            f"{html.escape(c.get('section', ''))}</span></td>",
            f"<td>{html.escape(c.get('quote', ''))}<br><span class=note>"
            f"{html.escape(c.get('summary', ''))}</span></td>",
            f"<td>{html.escape(paper_text(c.get('paper')))}</td>",
            f"<td>{html.escape(kv_text(c.get('measured')))}</td>",
            f"<td>{status_html(c.get('status', 'not_run'))}<br><b>"
            f"{html.escape(c.get('reading', ''))}</b><br><span class=note>"
            f"{html.escape(c.get('detail', ''))}</span></td>",
            f"<td>{_deps_html(c.get('departures', []))}</td>",
        ]) + "</tr>")
    return ("<table><thead><tr><th>claim</th><th>thesis says / what is checked</th>"
            "<th>thesis numbers</th><th>measured</th><th>verdict</th>"
            "<th>departures it rests on</th></tr></thead>"
            f"<tbody>{''.join(rows)}</tbody></table>")


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
    return ("<h3>Departures from the thesis</h3><table><thead><tr><th>id</th><th>kind</th>"
            "<th>the thesis</th><th>the pipeline</th><th>why</th><th>config values</th>"
            "<th>thesis values</th><th>results</th></tr></thead>"
            f"<tbody>{''.join(rows)}</tbody></table>")


def summary_lines(claims: list[dict], chapter: int) -> list[str]:
    """Markdown bullets of a chapter's claims, each with its departures beneath."""
    lines = []
    for c in claims:
        if c.get("chapter") != chapter:
            continue
        lines.append(f"- **{c.get('reading') or c.get('status', '')}** `{c.get('id')}`: "
                     f"{c.get('detail', '')}")
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
