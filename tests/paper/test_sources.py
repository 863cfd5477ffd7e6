"""Every published number in ``thesis.paper`` is traced to the thesis text it was read from.

Two independent checks catch transcription errors: the quoted ``source`` must occur in
thesis.txt (whitespace normalised), and the number printed at position ``pos`` of that
source must equal ``value``. The first check needs the thesis's text, which the repository
does not ship: a plain-text copy of the public thesis (https://biblio.ugent.be/publication/8562053)
at ``$THESIS_TXT``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest

from thesis import paper
from thesis.paper import PaperValue, normalise_ws, numbers_in

_CANDIDATES = [os.environ.get("THESIS_TXT", "")]


def _thesis_text() -> str | None:
    for c in _CANDIDATES:
        if c and Path(c).is_file():
            return normalise_ws(Path(c).read_text(encoding="utf-8"))
    return None


def _printed_value_problem(e: PaperValue) -> str | None:
    """Why ``e.value`` is not the number printed at ``e.pos`` of ``e.source`` (None if it is)."""
    if e.pos is None:
        if e.same_as is not None:
            ref = paper.get(e.same_as)
            return None if ref.value == e.value else f"ditto of {e.same_as} differs"
        if e.value is None and e.note:
            return None
        return "no printed position, but neither a ditto reference nor an unavailable value"
    nums = numbers_in(e.source)
    if e.pos >= len(nums):
        return f"pos {e.pos} beyond the {len(nums)} numbers {nums}"
    if e.value is None or not math.isclose(nums[e.pos], e.value, rel_tol=0, abs_tol=1e-9):
        return f"printed {nums[e.pos]} but stored {e.value}"
    return None


def test_keys_unique_and_derived_from_fields():
    keys = [e.key for e in paper.ALL]
    assert len(keys) == len(set(keys))
    for e in paper.ALL:
        assert e.key == paper.make_key(e.artifact, e.coords, e.variable)
        assert paper.get(e.key) is e


@pytest.mark.parametrize("e", paper.ALL, ids=lambda e: e.key)
def test_value_is_the_number_printed_in_source(e):
    assert _printed_value_problem(e) is None, _printed_value_problem(e)


def test_a_transcription_error_is_caught():
    good = paper.get("table2_2/model=ffn_spn/d=1/transform=bilinear/test_error")
    wrong_value = PaperValue(**{**good.__dict__, "value": 4.5})
    wrong_column = PaperValue(**{**good.__dict__, "pos": good.pos + 1})
    assert _printed_value_problem(good) is None
    assert "printed 4.4" in _printed_value_problem(wrong_value)
    assert _printed_value_problem(wrong_column) is not None


def test_sources_are_verbatim_thesis_text():
    text = _thesis_text()
    if text is None:
        pytest.skip("thesis.txt not found (set THESIS_TXT); the printed-value test still runs")
    missing = [e.key for e in paper.ALL if normalise_ws(e.source) not in text]
    assert not missing, missing


def test_numbers_in_parses_thesis_notation():
    assert numbers_in("FFN-SPN $d=1$\t4.4\t4.5") == [1.0, 4.4, 4.5]
    assert numbers_in("$y_{0,\\mathrm{hind}}~(\\mathrm{mm})$\t-6.83") == [-6.83]
    assert numbers_in("15-20 minutes") == [15.0, 20.0]
    assert numbers_in("2 107 396 parameters, 1,065,888 and 1147904") == [2107396, 1065888,
                                                                          1147904]
    assert numbers_in("x_0 SFA2 l_2") == []


def test_tables_complete():
    """Every result cell of each table (setup entries, such as Tab. 2.2's rows of d, aside)."""
    counts = {t: len([e for e in paper.table(t) if not e.config]) for t in
              ("Tab. 2.2", "Tab. 3.1", "Tab. 3.2", "Tab. 4.2", "Tab. 4.3", "Tab. 4.4",
               "Tab. 5.3", "Tab. 5.4", "Tab. 5.5", "Tab. 5.6", "Tab. 7.1")}
    assert counts == {"Tab. 2.2": 24, "Tab. 3.1": 20, "Tab. 3.2": 6, "Tab. 4.2": 70,
                      "Tab. 4.3": 42, "Tab. 4.4": 56, "Tab. 5.3": 32, "Tab. 5.4": 1,
                      "Tab. 5.5": 32, "Tab. 5.6": 14, "Tab. 7.1": 32}
    assert paper.get("table5_4/accuracy").value is None


def test_select_lines_up_with_dataset_coords():
    cells = paper.select("table7_1", "seconds", device="gpu", batch=128)
    assert sorted(e.value for e in cells) == [17.8, 18.3, 128.0, 129.0]
    with pytest.raises(KeyError):
        paper.get("table2_2/no/such/key")


def test_setup_entries_name_a_config_path_of_every_profile():
    from thesis.config import load_config
    from thesis.departures import config_value

    assert paper.setup(), "the thesis's stated setup is data"
    for profile in ("smoke", "default", "paper"):
        cfg = load_config(profile)
        for e in paper.setup():
            config_value(cfg, e.config)  # KeyError names a path that does not exist


def test_config_forms():
    assert paper.config_matches(128.0, "each", [128, 128])
    assert not paper.config_matches(128.0, "each", [128, 64])
    assert paper.config_matches(2.0, "length", [128, 128])
    assert paper.config_matches(96.0, "item:1", [288, 96])
    assert not paper.config_matches(96.0, "item:0", [288, 96])
    assert paper.config_matches(2.0, "contains", [1, 2, 3])
    assert not paper.config_matches(2.0, "contains", [1, 3])
    assert paper.config_matches(30.0, "value", 30)
    assert not paper.config_matches(30.0, "value", 150.0)
    assert not paper.config_matches(30.0, "value", [30.0])
    with pytest.raises(ValueError):
        PaperValue(**{**paper.setup()[0].__dict__, "config_form": "sum"})
