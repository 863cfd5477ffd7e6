"""Every departure of the pipeline from the thesis, declared once per chapter.

``DEPARTURES`` collects the chapter modules ``ch2`` ... ``ch7`` and ``coopt`` (§8.2; each a tuple
``DEPARTURES`` of :class:`Departure`); :func:`for_result` lists those a result rests on,
:func:`records` the same as JSON-ready records with the values the run's configuration
held at their config paths (``thesis run`` writes them into the result's attribute
``departures``, :data:`ATTR`). Experiment code may import this package; it imports nothing
from the rest of ``thesis``.
"""

from __future__ import annotations

from thesis.departures import ch2, ch3, ch4, ch5, ch6, ch7, coopt
from thesis.departures.types import KINDS, Departure

__all__ = ["ATTR", "DEPARTURES", "Departure", "KINDS", "config_value", "for_result", "get",
           "record", "records"]

#: Result attribute holding the JSON list of :func:`records` of the run.
ATTR = "departures"

DEPARTURES: tuple[Departure, ...] = (
    *ch2.DEPARTURES, *ch3.DEPARTURES, *ch4.DEPARTURES, *ch5.DEPARTURES, *ch6.DEPARTURES,
    *ch7.DEPARTURES, *coopt.DEPARTURES,
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


def config_value(config: dict, path: str) -> object:
    """The value at dotted ``path`` (``"ch7.arm_fixed.servo_torque"``) of a configuration.

    Raises:
        KeyError: naming the first missing part of ``path``.
    """
    node: object = config
    for i, part in enumerate(path.split(".")):
        if not isinstance(node, dict) or part not in node:
            raise KeyError(f"config has no key {'.'.join(path.split('.')[:i + 1])!r} "
                           f"(departure config path {path!r})")
        node = node[part]
    return node


def record(d: Departure, config: dict) -> dict[str, object]:
    """JSON-ready record of departure ``d`` with the values ``config`` holds at its paths."""
    return {"id": d.id, "kind": d.kind, "thesis": d.thesis, "ours": d.ours, "why": d.why,
            "results": list(d.results), "paper_keys": list(d.paper_keys),
            "config": {p: config_value(config, p) for p in d.config},
            "thesis_config": {p: v for p, v in d.thesis_config}}


def records(key: str, config: dict) -> list[dict[str, object]]:
    """:func:`record` of every departure result ``key`` rests on, for a run with ``config``
    (the whole validated configuration, defaults filled)."""
    return [record(d, config) for d in for_result(key)]
