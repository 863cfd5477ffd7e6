"""The record of one departure from the thesis: a deviation from its stated setup, or a
choice where the thesis is silent.

A :class:`Departure` is declared once, in the module of its chapter
(``thesis.departures.ch<n>``), and names the result datasets that rest on it. It is data,
not prose in a docstring, so that it can travel with every verdict that rests on those
results (results' attributes, ``claims.json``, the report, ``summary.md``).
"""

from __future__ import annotations

from dataclasses import dataclass

#: ``deviation``: the thesis states a setup and the pipeline uses another;
#: ``choice``: the thesis leaves the setting open and the pipeline fixed it.
KINDS = ("deviation", "choice")


@dataclass(frozen=True)
class Departure:
    """One departure from the thesis.

    Attributes:
        id: stable id, ``"ch<n>.<short_name>"``, e.g. ``"ch7.arm_servo_torque"``.
        kind: ``"deviation"`` or ``"choice"`` (:data:`KINDS`).
        results: result keys that rest on it, e.g. ``("ch7/arm_fixed", "ch7/arm_random")``.
        thesis: what the thesis states (a deviation) or leaves open (a choice), with its
            section, in words. A published number is referred to through ``paper_keys``
            rather than written here.
        ours: what the pipeline does instead, in words.
        why: the reason, in one or two sentences.
        config: dotted config paths that hold the pipeline's value (their values are
            recorded beside the departure), e.g. ``("ch7.arm_fixed.servo_torque",)``.
        paper_keys: ``thesis.paper`` keys of the stated setup value (deviations).
        thesis_config: ``((path, value), ...)``: the config values that are the thesis's
            own setup where the thesis states it in words rather than as a published
            number (e.g. ``(("ch7.ball.toi_correction", False),)``). Optional.

    A deviation is *in effect* in a run unless every path of ``config`` holds the thesis's
    value there: a ``thesis.paper`` setup entry naming that path (see
    :attr:`thesis.paper.PaperValue.config`) or an item of ``thesis_config``. Whether it is
    in effect is decided where the thesis's numbers may be read (``thesis.claims``);
    a choice is always in effect.
    """

    id: str
    kind: str
    results: tuple[str, ...]
    thesis: str
    ours: str
    why: str
    config: tuple[str, ...] = ()
    paper_keys: tuple[str, ...] = ()
    thesis_config: tuple[tuple[str, object], ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"departure {self.id!r}: kind {self.kind!r} not in {KINDS}")
        if not self.results:
            raise ValueError(f"departure {self.id!r} names no result it affects")
        if not self.id.startswith("ch") or "." not in self.id:
            raise ValueError(f"departure id {self.id!r} is not 'ch<n>.<short_name>'")
        for path, _ in self.thesis_config:
            if path not in self.config:
                raise ValueError(f"departure {self.id!r}: thesis_config path {path!r} is not "
                                 "one of its config paths")
