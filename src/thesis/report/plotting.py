"""Figure helpers shared by the chapter report modules (:mod:`thesis.report.chapters`)."""

from __future__ import annotations

from thesis.report.model import NOT_RUN


def save_figure(fig, path):
    """Lay out ``fig``, write it to ``path`` (PNG at the report's resolution, set by
    :mod:`thesis.report.render`), close it; returns ``path``."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def not_run_panel(ax, what: str) -> None:
    """Mark the axes ``ax`` of a figure panel whose result ``what`` is missing as
    "not run" (a report never draws a number it did not read)."""
    ax.text(0.5, 0.5, f"{what}: {NOT_RUN}", ha="center", va="center", transform=ax.transAxes)
    ax.set_axis_off()
