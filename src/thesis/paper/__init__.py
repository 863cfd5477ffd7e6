"""The thesis's published numbers, as data.

Only ``thesis.claims`` and ``thesis.report`` import this package.

Every number is a :class:`PaperValue` quoting the thesis text it was read from. Public API:

- ``ALL``: every entry, chapters 2 to 7 in order;
- :func:`get` ``(key)``: one entry by key, e.g.
  ``get("table2_2/model=rnn_spn/d=2/transform=chirp_z/test_error").value == 1.8``;
- :func:`table` ``(table_id)``: the entries of a table or artifact, by thesis reference
  (``"Tab. 2.2"``, ``"§7.2.1"``) or artifact id (``"table2_2"``, ``"ball"``);
- :func:`select` ``(artifact, variable=None, **coords)``: entries of an artifact whose
  coordinates match, for lining thesis values up with a result dataset;
- :func:`setup` ``(path=None)``: the numbers of the thesis's stated setup, each naming the
  config path of the pipeline's value (:attr:`PaperValue.config`).
"""

from __future__ import annotations

from thesis.paper import ch2, ch3, ch4, ch5, ch6, ch7
from thesis.paper.types import (CONFIG_FORMS, PaperValue, config_matches, make_key,
                                normalise_ws, numbers_in)

__all__ = ["ALL", "CONFIG_FORMS", "PaperValue", "config_matches", "get", "table", "select",
           "setup", "make_key", "numbers_in", "normalise_ws"]

ALL: tuple[PaperValue, ...] = (
    *ch2.ENTRIES, *ch3.ENTRIES, *ch4.ENTRIES, *ch5.ENTRIES, *ch6.ENTRIES, *ch7.ENTRIES,
)

_BY_KEY: dict[str, PaperValue] = {}
for _e in ALL:
    if _e.key in _BY_KEY:
        raise ValueError(f"duplicate paper key {_e.key!r}")
    _BY_KEY[_e.key] = _e
del _e


def get(key: str) -> PaperValue:
    """The published number stored under ``key``; ``KeyError`` naming close keys if absent."""
    try:
        return _BY_KEY[key]
    except KeyError:
        prefix = key.split("/", 1)[0]
        near = [k for k in _BY_KEY if k.startswith(prefix)][:5]
        raise KeyError(f"no paper value {key!r}; keys of {prefix!r} include {near}") from None


def table(table_id: str) -> list[PaperValue]:
    """Entries printed in ``table_id`` (``"Tab. 2.2"``, ``"§7.2.1"``) or of that artifact."""
    return [e for e in ALL if e.table == table_id or e.artifact == table_id]


def select(artifact: str, variable: str | None = None, **coords: object) -> list[PaperValue]:
    """Entries of ``artifact`` (and ``variable``) whose coords include all of ``coords``."""
    out = []
    for e in ALL:
        if e.artifact != artifact or (variable is not None and e.variable != variable):
            continue
        c = e.coord_dict()
        if all(k in c and c[k] == v for k, v in coords.items()):
            out.append(e)
    return out


def setup(path: str | None = None) -> list[PaperValue]:
    """Entries of the thesis's stated setup (those with a config path), or those of ``path``."""
    return [e for e in ALL if e.config and (path is None or e.config == path)]
