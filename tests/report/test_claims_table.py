"""The claims table a reader can read: numbers in words and units with their intervals,
raw dataset keys only behind a fold-out, a fixed-layout table that wraps instead of
widening the page; the method section with the rules' power table; ``thesis check``
writing that table. All on synthetic claims built here."""

from __future__ import annotations

import json
import re

from thesis import claims, cli
from thesis.claims import calibration
from thesis.report import render
from thesis.report import verdicts as V

RAW_KEY = "table2_2/model=ffn_spn/d=1/transform=bilinear/test_error"


def _claim(**kw) -> dict:
    base = {
        "id": "ch2.chirpz_similar_to_bilinear", "chapter": 2, "section": "§2.6",
        "quote": "works similarly well as the now common bilinear transform",
        "summary": "relative difference within +-25 % (rule 5)",
        "paper": [{"key": RAW_KEY, "table": "Tab. 2.2", "row": "FFN-SPN d=1",
                   "column": "bilinear", "value": 4.4, "unit": "percent"}],
        "units": {"ch2/table2_2:test_error": "1"},
        "measured": {"relative_difference_mean": 0.12, "relative_difference_ci_low": -0.05,
                     "relative_difference_ci_high": 0.29, "margin": 0.25, "n_seeds": 5.0},
        "statistic": "per-seed relative difference: mean with 95 % Student t interval",
        "status": "inconclusive", "reading": "inconclusive as stated",
        "detail": "interval straddles the margin", "departures": [],
    }
    return {**base, **kw}


def _visible(html_text: str) -> str:
    """The page without its <details> fold-outs."""
    return re.sub(r"<details>.*?</details>", "", html_text, flags=re.S)


def test_numbers_in_words_and_units_with_the_interval():
    page = V.claims_html([_claim()])
    assert "Tab. 2.2 FFN-SPN d=1, bilinear: 4.4 %" in page
    assert "relative difference: 0.12, 95 % interval [-0.05, 0.29]" in page
    assert "5 seeds" in page and "margin 0.25" in page
    assert "interval straddles the margin" in page and "inconclusive as stated" in page


def test_raw_keys_only_behind_a_fold_out():
    page = V.claims_html([_claim()])
    assert RAW_KEY in page and "<details>" in page
    assert RAW_KEY not in _visible(page)
    assert "relative_difference_ci_low" not in _visible(page)


def test_claims_table_has_fixed_layout_and_four_columns():
    page = V.claims_html([_claim(), _claim(id="ch2.other", chapter=2)])
    assert '<table class="claims">' in page
    assert page.count("<col ") == 4 and page.count("<th>") == 4
    assert "table.claims{table-layout:fixed;width:100%}" in render.CSS
    assert "overflow-wrap:anywhere" in render.CSS
    assert V.claims_html([_claim()], chapter=5) == ""


def test_combined_parts_are_grouped_in_words():
    measured = {"t53_useful.advantage_mean": 3.0, "t53_useful.advantage_ci_low": 1.0,
                "t53_useful.advantage_ci_high": 5.0, "t53_useful.n_seeds": 5.0,
                "baseline.rc.advantage_mean": 20.0}
    words = V.measured_words(measured)
    assert words[0] == "t53 useful: advantage: 3, 95 % interval [1, 5]; 5 seeds"
    assert any(w.startswith("baseline.rc:") or w.startswith("baseline rc:") for w in words)


def test_method_section_shows_the_power_table_and_says_when_missing():
    power = calibration.power_table(reps=50, ns=(3, 5), effects=(1.0,), rates=(0.9,),
                                    rate_ns=(5, 40), works_rates=(0.6,), fails_rates=(0.2,),
                                    failure_ns=(), existence_ns=())
    page = V.method_html(power)
    assert 'id="method"' in page and "Student t" in page
    assert "A beats B" in page and "advantage of 1 sd" in page and "in most runs" in page
    assert "a configuration works (ch. 6)" in page and "success rate 0.6" in page
    # header and one row per rule and truth: rules 4, 5, 10 and the rate rule's two
    assert page[page.index("<h3>Power"):].count("<tr>") == 1 + 5
    # the decidability test's seed counts come before it, one row per claim
    assert "Seeds a claim needs" in page and "ch7.arm_fixed_point_learned_quickly" in page
    table = page[page.index("Seeds a claim needs"):page.index("<h3>Power")]
    assert table.count("<tr><td><code>") == len(claims.CLAIMS)
    row = table[table.index("ch4.speedup_from_reduced_search_space"):].split("</tr>")[0]
    assert "none up to 100" in row and "intervention" in row
    assert [h for h in ("3 seeds", "5 seeds", "40 seeds") if h in page] == [
        "3 seeds", "5 seeds", "40 seeds"]
    # the rate rule was computed at 5 and 40 seeds, the others at 3 and 5: "—" elsewhere
    works = page[page.index("a configuration works (ch. 6)"):].split("</tr>")[0]
    assert works.count("—") == 1 and "98 %" in works  # 40 seeds at rate 0.6: 18 or more
    beats = page[page.index("<td>A beats B</td>"):].split("</tr>")[0]
    assert beats.endswith("<td>—</td>")
    assert "not computed" in V.method_html(None)


def test_check_writes_the_power_table_beside_the_claims(tmp_path, monkeypatch):
    monkeypatch.setattr(calibration, "power_table",
                        lambda: {"nominal": 0.025, "reps": 1, "rows": []})
    out = tmp_path / "smoke" / "claims.json"
    assert cli.main(["check", "--profile", "smoke", "--results", str(tmp_path),
                     "--output", str(out)]) == 0
    assert json.loads(out.read_text())["profile"] == "smoke"
    power = json.loads((tmp_path / "smoke" / cli.POWER_FILE).read_text())
    assert power["nominal"] == 0.025
    assert render.read_power("smoke", tmp_path) == power


def test_report_page_and_summary_carry_the_method_section(tmp_path):
    results, out = tmp_path / "results", tmp_path / "reports"
    (results / "smoke").mkdir(parents=True)
    (results / "smoke" / "claims.json").write_text(json.dumps({"claims": [_claim()]}))
    power = calibration.power_table(reps=50, ns=(3,), effects=(1.0,), rates=(0.9,))
    (results / "smoke" / cli.POWER_FILE).write_text(json.dumps(power))
    page = render.render_report("smoke", out, results_root=results,
                                bench_root=tmp_path / "bench").read_text()
    assert page.index('id="method"') < page.index('id="claims"')
    assert "Power: probability of" in page and "<a href=#method>" in page
    assert RAW_KEY not in _visible(page)
    summary = (out / "summary.md").read_text()
    assert "## Method" in summary and "| rule4_beats | advantage of 1 sd |" in summary


def test_fragility_section_counts_twin_verdicts_per_chapter():
    claims = [
        {"id": "ch3.a", "chapter": 3, "status": "reproduced",
         "perturbed": {"status": "inconclusive"}, "fragile": True},
        {"id": "ch3.b", "chapter": 3, "status": "reproduced",
         "perturbed": {"status": "reproduced"}, "fragile": False},
        {"id": "ch3.c", "chapter": 3, "status": "inconclusive"},
        {"id": "ch5.a", "chapter": 5, "status": "reproduced"},
    ]
    claims[2].update(native={"status": "reproduced"}, isa_dependent=True)
    claims[1].update(native={"status": "reproduced"}, isa_dependent=False)
    page = V.fragility_html(claims, ["ch3/table3_1", "ch3/fig3_4"], ["ch3/table3_1"])
    assert "2 of 3 claims decided on twins, 1 fragile: ch3.a" in page
    assert "2 of 3 claims decided on twins, 1 moved: ch3.c" in page
    assert "<td>5</td><td>no twin runs</td><td>no twin runs</td>" in page
    assert "Perturbed twin runs read: 2 results (ch3)" in page
    assert "Native twin runs read: 1 results (ch3)" in page
    assert "Native twin runs" not in V.fragility_html(claims, ["ch3/table3_1"])


def test_measured_numbers_carry_their_own_units_not_the_variables():
    """A check that reports transformed numbers (a log10 ratio of an MSE in rad^2) must not
    show them as rad^2: without declared units the note names the units of the variables
    *read*; with declared units (``measured_units``) those label the numbers."""
    plain = _claim(units={"ch6/trot:mse_curve": "rad2"},
                   measured={"log10_mse_ratio_mean": -1.2, "n_seeds": 5.0})
    page = _visible(V.claims_html([plain]))
    assert "read from: mse curve in rad2" in page
    assert "(mse curve in rad2)" not in page
    declared = _claim(measured_units={"error": "percent", "ratio": "1"})
    page = _visible(V.claims_html([declared]))
    assert "numbers in: error in %; ratio in units of 1" in page
    assert "test error in units of 1" not in page
