"""Every departure of the pipeline from the thesis, declared once per chapter.

``DEPARTURES`` collects the chapter modules ``ch2`` ... ``ch7`` (each a tuple
``DEPARTURES`` of :class:`Departure`); :func:`for_result` lists those a result rests on.
Experiment code may import this package; it imports nothing from the rest of ``thesis``.
"""

from __future__ import annotations

from thesis.departures import ch2, ch3, ch4, ch5, ch6, ch7
from thesis.departures.types import KINDS, Departure

__all__ = ["DEPARTURES", "Departure", "KINDS", "for_result", "get"]

DEPARTURES: tuple[Departure, ...] = (
    *ch2.DEPARTURES, *ch3.DEPARTURES, *ch4.DEPARTURES, *ch5.DEPARTURES, *ch6.DEPARTURES,
    *ch7.DEPARTURES,
)

_BY_ID: dict[str, Departure] = {}
for _d in DEPARTURES:
    if _d.id in _BY_ID:
        raise ValueError(f"duplicate departure id {_d.id!r}")
    _BY_ID[_d.id] = _d


def get(departure_id: str) -> Departure:
    """The departure with id ``departure_id``."""
    return _BY_ID[departure_id]


def for_result(key: str) -> tuple[Departure, ...]:
    """Departures that result ``key`` (e.g. ``"ch7/arm_fixed"``) rests on, in order."""
    return tuple(d for d in DEPARTURES if key in d.results)
