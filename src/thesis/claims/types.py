"""Verdicts, claims, and strict access to the result datasets a claim reads.

A :class:`Claim` quotes the thesis, names the published numbers it rests on
(``thesis.paper`` keys) and the result datasets it needs (``"ch2/table2_2"``), and
decides a :class:`Verdict` from those datasets with a check function. ``Claim.check``
handles the two cases every claim shares: a required dataset is missing (``not_run``,
naming it) and a dataset lacks a variable or coordinate the check reads (``not_run``,
"layout mismatch: ..."). A claim whose experiment is not built yet has ``fn=None`` and
reports "check not implemented: experiment not built" once its datasets exist.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

STATUSES = ("reproduced", "not_reproduced", "inconclusive", "not_run")
NOT_IMPLEMENTED = "check not implemented: experiment not built"


class LayoutError(ValueError):
    """A result dataset lacks a variable, dimension or coordinate value a check reads."""


def _plain(v: object) -> float | str:
    if isinstance(v, str):
        return v
    if isinstance(v, (bool, np.bool_)):
        return float(v)
    if isinstance(v, (int, float, np.integer, np.floating)):
        return float(v)
    return str(v)


@dataclass(frozen=True)
class Verdict:
    """The outcome of checking one claim.

    Attributes:
        status: ``"reproduced"``, ``"not_reproduced"``, ``"inconclusive"`` or ``"not_run"``.
        measured: the numbers behind the decision (means, interval bounds, counts,
            p-values), JSON-ready floats or strings.
        statistic: the test or interval used, in words.
        detail: why this status, in one or two sentences.
    """

    status: str
    measured: dict[str, float | str] = field(default_factory=dict)
    statistic: str = ""
    detail: str = ""

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"unknown status {self.status!r}; one of {STATUSES}")
        object.__setattr__(self, "measured", {str(k): _plain(v) for k, v in self.measured.items()})

    def to_dict(self) -> dict[str, object]:
        """JSON-ready ``{"status", "measured", "statistic", "detail"}`` (NaN becomes None)."""
        measured = {k: (None if isinstance(v, float) and not np.isfinite(v) else v)
                    for k, v in self.measured.items()}
        return {"status": self.status, "measured": measured,
                "statistic": self.statistic, "detail": self.detail}


Results = Mapping[str, xr.Dataset]
CheckFn = Callable[[Results], Verdict]


@dataclass(frozen=True)
class Claim:
    """One claim of the thesis as a computed check.

    Attributes:
        id: stable id, ``"ch<n>.<short_name>"`` (``ch8.*`` for the §8.1 conclusions).
        chapter: thesis chapter (2 to 8).
        section: where the wording is, e.g. ``"§2.6"``.
        quote: the thesis's own wording, verbatim (whitespace aside).
        summary: what the check tests, in one sentence (direction, statistic, margin).
        paper_keys: ``thesis.paper`` keys of the published numbers the claim rests on.
        requires: result keys the check needs, e.g. ``("ch2/table2_2",)``.
        reads: ``"<result key>:<variable>"`` items the check reads (documentation).
        fn: the check on the loaded results; ``None`` while the experiment is not built.
        units: the units of the numbers the check reports, by a word of their names
            (``{"error": "percent", "ratio": "1"}``); empty when the check reports the
            variables it reads in their own units. The report prefers these to the units
            of the variables read, which a transformed number (a log ratio) does not have.
    """

    id: str
    chapter: int
    section: str
    quote: str
    summary: str
    paper_keys: tuple[str, ...] = ()
    requires: tuple[str, ...] = ()
    reads: tuple[str, ...] = ()
    fn: CheckFn | None = None
    units: Mapping[str, str] = field(default_factory=dict)

    def check(self, results: Results) -> Verdict:
        """Decide the verdict from ``results`` (result key -> dataset); never raises on data."""
        missing = [r for r in self.requires if r not in results]
        if missing:
            return Verdict("not_run", detail="missing datasets: " + ", ".join(missing))
        if self.fn is None:
            return Verdict("not_run", detail=NOT_IMPLEMENTED)
        try:
            return self.fn(results)
        except LayoutError as err:
            return Verdict("not_run", detail=f"layout mismatch: {err}")


# ------------------------------------------------------------------ dataset access


def variable(results: Results, key: str, name: str, dims: Iterable[str] = ()) -> xr.DataArray:
    """``results[key][name]`` as float, checking it has every dim in ``dims``.

    Raises:
        LayoutError: the variable or one of the dims is absent.
    """
    ds = results[key]
    if name not in ds.data_vars:
        raise LayoutError(f"{key} has no variable {name!r} (has {sorted(ds.data_vars)})")
    da = ds[name]
    for d in dims:
        if d not in da.dims:
            raise LayoutError(f"{key}:{name} has no dimension {d!r} (dims {da.dims})")
    return da.astype(float)


def pick(da: xr.DataArray, **coords: object) -> xr.DataArray:
    """``da.sel(**coords)``, raising :class:`LayoutError` naming a missing coordinate value."""
    for dim, value in coords.items():
        if dim not in da.dims:
            raise LayoutError(f"{da.name!r} has no dimension {dim!r} (dims {da.dims})")
        values = list(np.atleast_1d(value))
        have = list(da[dim].values)
        absent = [v for v in values if v not in have]
        if absent:
            raise LayoutError(f"{da.name!r} lacks {dim}={absent} (has {have})")
    return da.sel(coords)  # dict form: a dim named 'method' must not hit sel(method=...)


def as_fraction(da: xr.DataArray) -> xr.DataArray:
    """Convert a rate stored with units ``"1"``/``""`` (fraction) or ``"percent"``/``"%"``.

    Raises:
        LayoutError: any other unit.
    """
    unit = str(da.attrs.get("units", "")).strip()
    if unit in ("1", "", "fraction"):
        return da
    if unit in ("percent", "%"):
        return da / 100.0
    raise LayoutError(f"{da.name!r} has units {unit!r}; expected '1' or 'percent'")
