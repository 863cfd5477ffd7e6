"""The record of one published number of the thesis, and the helpers that build keys.

A :class:`PaperValue` is one number printed in the thesis (a table cell or a number in
the prose), together with the verbatim text it was read from, so that
``tests/paper/test_sources.py`` can check both that the text occurs in the thesis and
that the number printed there is the stored value.

Keys mirror how result datasets are indexed: ``<artifact>/<dim>=<coord>/.../<variable>``,
e.g. ``"table2_2/model=ffn_spn/d=1/transform=chirp_z/test_error"`` is the thesis's value
of ``results/<profile>/ch2/table2_2.nc`` variable ``test_error`` at
``model="ffn_spn", d=1, transform="chirp_z"``. Numbers from the prose that have no result
dataset use a section id as artifact (``"sec7.3.2.1/evaluations_to_4cm"``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

#: A number as printed: optional sign (only at the start of a token), digits with
#: optional space/comma thousands groups ("60 000", "1,065,888"), optional decimals.
#: Digits glued to a preceding letter, "_", "{" or "^" are indices or names
#: ("x_0", "SFA2", "y_{0,fore}") and are not numbers.
_NUMBER = re.compile(
    r"(?<![\w{^.])"  # not an index or part of a name / longer number
    r"(?P<sign>(?<![\w.)\]])[-−])?"
    r"(?P<num>\d{1,3}(?:[ ,]\d{3})+(?![\d.])|\d+(?:\.\d+)?)"
)


def numbers_in(text: str) -> list[float]:
    """All numbers printed in ``text``, in order of appearance, as floats.

    Thousands separators (single spaces or commas between groups of three digits) are
    removed; a leading ``-`` or ``−`` counts as a sign only where it starts a token
    ("\\t-6.83" is -6.83, "15-20" is 15 and 20).
    """
    out = []
    for m in _NUMBER.finditer(text):
        num = m.group("num").replace(" ", "").replace(",", "")
        val = float(num)
        if m.group("sign"):
            val = -val
        out.append(val)
    return out


def normalise_ws(text: str) -> str:
    """Collapse every run of whitespace (spaces, tabs, newlines) to one space and strip."""
    return " ".join(text.split())


#: How a setup number relates to its config value (:attr:`PaperValue.config_form`).
CONFIG_FORMS = ("value", "each", "length", "contains")


def _same(a: object, b: object) -> bool:
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b or a == b
    try:
        return abs(float(a) - float(b)) <= 1e-9 * max(1.0, abs(float(a)))
    except (TypeError, ValueError):
        return a == b


def config_matches(stated: object, form: str, value: object) -> bool:
    """Whether config ``value`` is the thesis's ``stated`` setup number under ``form``."""
    items = list(value) if isinstance(value, (list, tuple)) else None
    if form == "value":
        return items is None and _same(stated, value)
    if items is None:
        return False
    if form == "each":
        return bool(items) and all(_same(stated, v) for v in items)
    if form == "length":
        return _same(stated, len(items))
    if form == "contains":
        return any(_same(stated, v) for v in items)
    i = int(form.split(":", 1)[1])
    return i < len(items) and _same(stated, items[i])


def make_key(artifact: str, coords: tuple[tuple[str, object], ...], variable: str) -> str:
    """``artifact/dim=value/.../variable``: the key of a published number."""
    parts = [artifact, *(f"{k}={v}" for k, v in coords), variable]
    return "/".join(parts)


@dataclass(frozen=True)
class PaperValue:
    """One number published in the thesis.

    Attributes:
        key: unique id, ``make_key(artifact, coords, variable)``.
        table: where it is printed: ``"Tab. 2.2"``, ``"§7.2.1"``, ``"Fig. 3.4"`` ...
        row: the row label as printed (or a short description for prose numbers).
        column: the column label as printed (or the quantity for prose numbers).
        value: the number as printed (``None`` where the thesis does not give it in its
            text, e.g. Tab. 5.4, which is an image).
        unit: UDUNITS-like unit of ``value``: ``"1"`` for dimensionless numbers,
            ``"percent"`` for values the thesis prints in percent (stored as printed,
            e.g. 4.4 for 4.4 %), ``"m/s"``, ``"s"``, ``"mm"``, ``"Hz"`` ...
        source: the table row or sentence of thesis.txt the number is read from,
            verbatim up to whitespace.
        pos: index of ``value`` among :func:`numbers_in` ``(source)``; ``None`` when the
            value is not printed in ``source`` (a ditto mark, an unavailable table).
        note: caveats of the transcription (ambiguous headers, ditto marks, rounding).
        artifact: the result artifact the number compares with (``"table2_2"``) or a
            section id for prose numbers without a dataset (``"sec3.3.3"``).
        variable: the dataset variable (``"test_error"``) or the quantity's name.
        coords: ``((dim, coord value), ...)`` selecting the cell in the dataset.
        same_as: key of the entry whose printed value a ditto mark repeats.
        config: for a number of the thesis's stated *setup* (a size, a torque, a duration
            it says it used), the dotted config path that holds the pipeline's value,
            e.g. ``"ch7.arm_fixed.servo_torque"``; empty for results.
        config_form: how ``value`` relates to the config value at ``config``
            (:data:`CONFIG_FORMS`): ``"value"`` equal, ``"each"`` every list item equal,
            ``"length"`` the list's length, ``"item:<i>"`` its i-th item, ``"contains"``
            one of its items.
    """

    key: str
    table: str
    row: str
    column: str
    value: float | None
    unit: str
    source: str
    pos: int | None = 0
    note: str = ""
    artifact: str = ""
    variable: str = ""
    coords: tuple[tuple[str, object], ...] = field(default_factory=tuple)
    same_as: str | None = None
    config: str = ""
    config_form: str = "value"

    def __post_init__(self) -> None:
        if self.config_form not in CONFIG_FORMS and not (
                self.config_form.startswith("item:") and self.config_form[5:].isdigit()):
            raise ValueError(f"paper value {self.key!r}: config_form {self.config_form!r} not "
                             f"in {CONFIG_FORMS} or 'item:<i>'")

    def matches_config(self, value: object) -> bool:
        """Whether a config value equals the thesis's stated setup (see ``config_form``)."""
        return config_matches(self.value, self.config_form, value)

    def coord_dict(self) -> dict[str, object]:
        """``coords`` as a dict, e.g. ``{"model": "ffn_spn", "d": 1}``."""
        return dict(self.coords)


def entry(
    *,
    table: str,
    artifact: str,
    variable: str,
    value: float | None,
    unit: str,
    source: str,
    pos: int | None = 0,
    coords: tuple[tuple[str, object], ...] = (),
    row: str = "",
    column: str = "",
    note: str = "",
    same_as: str | None = None,
    config: str = "",
    config_form: str = "value",
) -> PaperValue:
    """Build a :class:`PaperValue` whose key is derived from artifact, coords, variable."""
    return PaperValue(
        key=make_key(artifact, coords, variable),
        table=table,
        row=row,
        column=column or variable,
        value=value,
        unit=unit,
        source=source,
        pos=pos,
        note=note,
        artifact=artifact,
        variable=variable,
        coords=tuple(coords),
        same_as=same_as,
        config=config,
        config_form=config_form,
    )
