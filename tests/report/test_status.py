"""The per-section status (thesis.report.status): what ran, at which profile and commit,
the verdict counts and the headline numbers beside the thesis's, generated from results
and claims built inside the test, in summary.md and on the report's first screen."""

from __future__ import annotations

import json
import re
from datetime import datetime, timezone

import numpy as np
import xarray as xr

from thesis import claims as claims_mod
from thesis import provenance, store
from thesis.report import render, status
from thesis.report.chapters import CHAPTERS

from .test_render import _write_result, fake_chapter  # noqa: F401 (fixture)


def _ds(profile="smoke", commit="abcdef1234567890", dirty=0,
        started="2026-01-02T03:04:05+00:00"):
    return xr.Dataset({"x": ("seed", np.array([1.0]))},
                      attrs={"profile": profile, "git_commit": commit, "git_dirty": dirty,
                             "host": "box", "started": started})


def _claim(cid, chapter, status_, section="§x", **extra):
    return {"id": cid, "chapter": chapter, "section": section, "status": status_,
            "reading": f"{status_.replace('_', ' ')} as stated", "paper": [],
            "measured": {}, "departures": [], **extra}


HEAD = {"id": "ch3.half_ellipse_fastest", "chapter": 3, "section": "§3.4",
        "status": "inconclusive", "reading": "inconclusive under a declared deviation",
        "paper": [{"key": "fig3_4/half_ellipse_max", "table": "Fig. 3.4",
                   "row": "half ellipse", "column": "max speed", "value": 0.317,
                   "unit": "m s-1"}],
        "measured": {"advantage_mean": 0.0123, "advantage_ci_low": -0.01,
                     "advantage_ci_high": 0.0345, "n_seeds": 3.0},
        "departures": [], "perturbed": {"status": "reproduced"}, "fragile": True}


def _claims():
    return [HEAD,
            _claim("ch3.other", 3, "reproduced", perturbed={"status": "reproduced"},
                   native={"status": "not_reproduced"}, isa_dependent=True),
            _claim("ch3.third", 3, "not_reproduced"),
            _claim("ch5.x", 5, "not_run"),
            _claim("ch8.coopt_y", 8, "reproduced", section="§8.2"),
            _claim("ch8.ch3_z", 8, "inconclusive", section="§8.1")]


def test_every_section_gets_a_row_with_what_ran_and_its_verdicts():
    results = {"ch3/table3_1": _ds(), "ch3/fig3_4": _ds(commit="0123456789ab", dirty=1,
                                                        started="2026-02-01T00:00:00+00:00"),
               "coopt/arms": _ds(profile="default")}
    rows = {s.chapter: s for s in status.chapter_status(results, _claims())}
    assert list(rows) == [*CHAPTERS, "ch8"]
    ch3 = rows["ch3"]
    assert ch3.results == ["ch3/fig3_4", "ch3/table3_1"]
    assert ch3.profiles == ["smoke"]
    assert ch3.commits == ["0123456789+dirty", "abcdef1234"]
    assert ch3.latest == "2026-02-01T00:00:00+00:00"
    assert ch3.counts == {"reproduced": 1, "not_reproduced": 1, "inconclusive": 1}
    assert (ch3.twinned, ch3.fragile, ch3.native, ch3.isa_dependent) == (2, 1, 1, 1)
    assert ch3.headline is HEAD
    # §8.2's claims count under coopt, §8.1's under the conclusions, none under ch2
    assert rows["coopt"].counts == {"reproduced": 1} and rows["coopt"].profiles == ["default"]
    assert rows["ch8"].counts == {"inconclusive": 1}
    assert rows["ch5"].counts == {"not_run": 1} and not rows["ch5"].ran
    assert rows["ch2"].counts == {} and rows["ch2"].results == [] and not rows["ch2"].ran


def test_markdown_and_html_carry_the_numbers_read_from_claims():
    rows = status.chapter_status({"ch3/table3_1": _ds()}, _claims())
    optional = status.optional_runs({"ch5/table5_3_blocks": _ds()},
                                    {"twin_runs": ["ch3/table3_1", "ch4/flat"]}, "smoke")
    md = "\n".join(status.status_md(rows, optional))
    line = next(x for x in md.splitlines() if x.startswith("| Chapter 3"))
    assert "1 result (table3_1); profile smoke; commit abcdef1234" in line
    assert "1 reproduced, 1 not reproduced, 1 inconclusive" in line
    assert "1 of 2 fragile; 1 of 1 ISA-dependent" in line
    assert "Fig. 3.4 half ellipse, max speed: 0.317 m/s" in line       # the thesis's
    assert "advantage: 0.0123, 95 % interval [-0.01, 0.0345]" in line  # measured
    assert "read for ch3, ch4" in md and "snakemake ch5_variants --config profile=smoke" in md
    assert "| Tab. 5.3's selection-protocol variants" in md and "| not run |" in md
    page = status.status_html(rows, optional)
    assert re.findall(r'data-chapter="([^"]+)"', page) == [*CHAPTERS, "ch8"]
    assert "0.317 m/s" in page and "[-0.01, 0.0345]" in page
    assert "no results" in page  # ch2: nothing on disk
    assert "(<code>thesis.ch3, thesis.gaits, thesis.optim</code>)" in page  # the code behind ch3


def test_long_result_lists_are_counted_not_listed():
    results = {f"ch4/fig4_{i:02d}": _ds() for i in range(11)}
    ch4 = next(s for s in status.chapter_status(results, []) if s.chapter == "ch4")
    words = status._what_ran(ch4)
    assert words.startswith("11 results (fig4_00, fig4_01,") and "fig4_07 and 3 more)" in words


def test_headlines_name_real_claims_and_sections():
    ids = {c.id for c in claims_mod.CLAIMS}
    assert set(status.HEADLINES.values()) <= ids, set(status.HEADLINES.values()) - ids
    assert set(status.SECTIONS) == {*CHAPTERS, "ch8"}
    for ch, cid in status.HEADLINES.items():
        c = claims_mod.get(cid)
        assert status._section_of({"chapter": c.chapter, "section": c.section}) == ch


def test_report_first_screen_and_summary_start_with_the_status(
        tmp_path, fake_chapter):  # noqa: F811
    results, out = tmp_path / "results", tmp_path / "reports"
    _write_result(results)  # ch3/fig3_4, profile smoke, this checkout's commit
    (results / "smoke" / "claims.json").write_text(json.dumps({"claims": _claims()}))
    page = render.render_report("smoke", out, results_root=results).read_text()
    first = page.index('<h2 id="status">')
    assert first < page.index('<h2 id="method">') and first < page.index('<h2 id="ch2">')
    assert page.index("<h2") == first  # the first section of the page
    head = page[first:page.index('<h2 id="method">')]
    assert re.findall(r'data-chapter="([^"]+)"', head) == [*CHAPTERS, "ch8"]
    commit = provenance.git_commit()[:10]
    assert f"profile smoke; commit {commit}" in head
    summary = (out / "summary.md").read_text()
    assert summary.index("## Status") < summary.index("## Method")
    row = next(x for x in summary.splitlines() if x.startswith("| Chapter 3"))
    assert "1 result (fig3_4)" in row and "0.317 m/s" in row


def test_per_run_twin_flips_and_twin_verdicts_are_read_from_data():
    flipped = xr.Dataset({"flipped": (("config", "seed"),
                                      np.array([[1.0, 0.0, 0.0], [0.0, 1.0, np.nan]]))})
    results = {"ch6/trot": flipped.assign_attrs(_ds().attrs),
               "ch6/walk": xr.Dataset({"flipped": ("seed", np.array([1.0, 0.0]))},
                                      attrs=_ds().attrs)}
    claims = [_claim("ch6.a", 6, "reproduced", perturbed={"status": "not_reproduced"},
                     fragile=True),
              _claim("ch6.b", 6, "inconclusive", native={"status": "inconclusive"}),
              _claim("ch6.c", 6, "not_run")]
    ch6 = next(s for s in status.chapter_status(results, claims) if s.chapter == "ch6")
    assert (ch6.runs_twinned, ch6.runs_flipped) == (7, 3)  # NaN: not run
    assert "the per-run twins change 3 of 7 run outcomes" in status._twin_words(ch6)
    md = "\n".join(status.twin_verdicts_md(claims))
    assert "| `ch6.a` | reproduced | not reproduced | — | fragile |" in md
    assert "| `ch6.b` | inconclusive | — | inconclusive | holds |" in md
    assert "ch6.c" not in md
    page = status.twin_verdicts_html(claims)
    assert "(2 claims)" in page and 'class="fragile">fragile' in page
    assert status.twin_verdicts_md([claims[2]]) == [] and status.twin_verdicts_html([]) == ""


def test_twin_runs_tables_stand_after_the_chapters(tmp_path, fake_chapter):  # noqa: F811
    """A chapter's tables are rendered from results/<profile>-native/ by its own table code
    (the numbers a native run moves), after the chapters, in the page and summary.md."""
    results, out = tmp_path / "results", tmp_path / "reports"
    _write_result(results)  # speeds 0.25, 0.35: mean 0.300
    twin = xr.Dataset({"speed": xr.DataArray(np.array([0.41, 0.43]), dims="seed",
                                             attrs={"units": "m s-1", "long_name": "speed"})},
                      coords={"seed": [0, 1]}, attrs={"thesis_ref": "Fig. 3.4", "seeds": [0, 1]})
    store.write_dataset(twin, results / "smoke-native" / "ch3" / "fig3_4.nc",
                        profile="smoke", experiment="ch3/fig3_4", config_slice={},
                        wall_seconds=1.0, started=datetime.now(timezone.utc))
    assert [(k, n, [s.chapter for s in secs]) for k, n, secs
            in render.twin_sections("smoke", results)] == [("native", "smoke-native", ["ch3"])]
    page = render.render_report("smoke", out, results_root=results).read_text()
    twins = page[page.index('<h2 id="twins-native">'):page.index('<h2 id="claims">')]
    assert "0.420" in twins and "0.300" not in twins and 'id="native-fig3_4"' in twins
    assert "0.420" not in page[:page.index('<h2 id="twins-native">')]
    assert "twins-perturbed" not in page  # no perturbed twin runs on disk
    summary = (out / "summary.md").read_text()
    tail = summary[summary.index("## Tables of the native twin runs"):]
    assert "results/smoke-native/" in tail and "| sine | 0.420 |" in tail
