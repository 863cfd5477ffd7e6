"""Plain data the report renders: tables and figures produced by the chapter modules.

A chapter module ``thesis.report.chapters.<ch>`` exposes

- ``tables(results: dict[str, xr.Dataset]) -> list[Table]``: thesis beside reproduced;
- ``figures(results: dict[str, xr.Dataset], outdir: Path) -> list[Figure]``: renders
  matplotlib figures into ``outdir`` (PNG) and describes them.

``results`` maps result keys such as ``"ch2/table2_2"`` to loaded datasets
(:func:`thesis.store.load_results`); a missing key means the experiment was not run,
and the chapter module must then show "not run" (never a number it did not read).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

NOT_RUN = "not run"


@dataclass(frozen=True)
class Table:
    """One table of the report.

    Attributes:
        id: stable id, e.g. ``"table2_2"``.
        title: caption shown above the table.
        thesis_ref: the thesis table or section, e.g. ``"Tab. 2.2"``.
        columns: column headers.
        rows: cells as already formatted strings (``NOT_RUN`` where nothing was measured).
        note: free text under the table (profile sizes, statistic used, ...).
    """

    id: str
    title: str
    thesis_ref: str
    columns: list[str]
    rows: list[list[str]]
    note: str = ""


@dataclass(frozen=True)
class Figure:
    """One rendered figure.

    Attributes:
        id: stable id, e.g. ``"fig3_4"``.
        title: caption.
        thesis_ref: the thesis figure, e.g. ``"Fig. 3.4"``.
        path: the PNG file written by the chapter module.
        note: free text under the figure.
    """

    id: str
    title: str
    thesis_ref: str
    path: Path
    note: str = ""


@dataclass
class Section:
    """A chapter's part of the report."""

    chapter: str
    title: str
    tables: list[Table] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
