"""Departures of chapter 5 from the thesis (see :class:`thesis.departures.types.Departure`)."""

from __future__ import annotations

from thesis.departures.types import Departure

DEPARTURES: tuple[Departure, ...] = ()
