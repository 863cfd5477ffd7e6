"""The damaged result files of a report, shown at the top of the page and the summary.

A result file that cannot be used (truncated, empty, of a foreign format, holding another
artifact's dataset: :func:`thesis.store.scan_results`) is set aside; its tables and claims
show "not run", and this block says which file it is, what is wrong with it and the
command that remakes it (:class:`thesis.errors.DamagedFileError`).
"""

from __future__ import annotations

import html

from thesis.errors import DamagedFileError


def damaged_html(damaged: list[DamagedFileError]) -> str:
    """An HTML block listing each damaged file (path, role, cause, remaking command);
    ``""`` when there is none."""
    if not damaged:
        return ""
    items = "".join(
        f"<li><code>{html.escape(e.path)}</code> ({html.escape(e.role)}): "
        f"{html.escape(e.cause)}. Remake it with <code>{html.escape(e.remake)}</code></li>"
        for e in damaged)
    return ('<div id="damaged" class="damaged" style="border:2px solid #b2182b;'
            'padding:.2em 1em;margin:1em 0"><p><b>Damaged result files: '
            f"{len(damaged)}.</b> What reads them shows &ldquo;not run&rdquo;; every other "
            f"table and claim is shown as usual.</p><ul>{items}</ul></div>")


def damaged_md(damaged: list[DamagedFileError]) -> list[str]:
    """The same as Markdown lines (empty when there is none)."""
    if not damaged:
        return []
    return ([f"**Damaged result files: {len(damaged)}.** What reads them shows "
             "\"not run\"; every other table and claim is shown as usual.", ""]
            + [f"- `{e.path}` ({e.role}): {e.cause}. Remake it with `{e.remake}`"
               for e in damaged] + [""])
