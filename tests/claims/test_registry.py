"""The claim registry: ids, thesis wording, paper keys, evaluate_all on empty/partial results."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from thesis import claims, paper


def _thesis_text() -> str | None:
    """The thesis's text (whitespace normalised) from a plain-text copy at ``$THESIS_TXT``
    (the repository does not ship it), or None."""
    c = os.environ.get("THESIS_TXT", "")
    if c and Path(c).is_file():
        return paper.normalise_ws(Path(c).read_text(encoding="utf-8"))
    return None


def test_ids_unique_and_well_formed():
    ids = [c.id for c in claims.CLAIMS]
    assert len(ids) == len(set(ids))
    for c in claims.CLAIMS:
        assert re.fullmatch(r"ch[2-8]\.[a-z0-9_]+", c.id), c.id
        assert c.id.startswith(f"ch{c.chapter}.")
        assert claims.get(c.id) is c


def test_paper_keys_exist():
    for c in claims.CLAIMS:
        for k in c.paper_keys:
            assert paper.get(k).key == k, (c.id, k)


def test_every_conclusion_section_has_claims():
    sections = {c.section for c in claims.CLAIMS}
    for s in ("§2.6", "§3.4", "§4.8", "§5.5", "§6.7", "§7.5", "§8.1"):
        assert s in sections, s
    assert sum(c.section == "§8.1" for c in claims.CLAIMS) >= 7


def test_quotes_are_verbatim():
    text = _thesis_text()
    if text is None:
        pytest.skip("thesis.txt not found (set THESIS_TXT)")
    bad = [c.id for c in claims.CLAIMS if paper.normalise_ws(c.quote) not in text]
    assert not bad, bad


def test_evaluate_all_on_nothing_is_all_not_run_and_json():
    out = claims.evaluate_all({})
    assert len(out) == len(claims.CLAIMS)
    assert {o["status"] for o in out} == {"not_run"}
    for o in out:
        assert o["detail"].startswith(("missing datasets: ", "not testable")), o["id"]
        assert len(o["paper"]) == len(claims.get(o["id"]).paper_keys)
    json.dumps(out, allow_nan=False)


def test_every_claim_is_implemented():
    assert [c.id for c in claims.CLAIMS if c.fn is None] == []


def test_a_placeholder_says_not_implemented_once_data_exist():
    from thesis.claims.types import Claim

    c = Claim(id="ch4.placeholder", chapter=4, section="§4.6", quote="q", summary="s",
              requires=("ch4/table4_2",))
    v = c.check({"ch4/table4_2": xr.Dataset()})
    assert v.status == "not_run" and v.detail == claims.NOT_IMPLEMENTED


def test_evaluate_all_carries_paper_and_measured_numbers():
    rng = np.random.default_rng(0)
    err = np.array([0.03, 0.035, 0.036, 0.08]) + 0.001 * rng.standard_normal((4, 2, 3, 4))
    ds = xr.Dataset({"test_error": xr.DataArray(
        err, dims=("seed", "model", "d", "transform"),
        coords={"model": ["ffn_spn", "rnn_spn"], "d": [1, 2, 3],
                "transform": ["bilinear", "bilinear_no_skew", "chirp_z", "none"]},
        attrs={"units": "1", "long_name": "per-digit test error"})})
    out = {o["id"]: o for o in claims.evaluate_all({"ch2/table2_2": ds})}
    row = out["ch2.spatial_transformers_beat_plain"]
    assert row["status"] == "reproduced"
    assert row["measured"]["n_seeds"] == 4.0 and row["measured"]["advantage_ci_low"] > 0
    assert {p["value"] for p in row["paper"]} >= {4.4, 7.8, 1.8}
    assert out["ch3.spline_fastest"]["status"] == "not_run"
    json.dumps(list(out.values()), allow_nan=False)


def test_a_verdict_the_perturbed_twin_runs_move_is_fragile():
    """``twin_runs`` (results/<profile>-perturbed/) decide every claim that reads them a
    second time; a claim whose verdict they change is marked fragile, one they leave alone
    is not, and a claim on results without twins carries neither."""
    coords = {"model": ["ffn_spn", "rnn_spn"], "d": [1, 2, 3],
              "transform": ["bilinear", "bilinear_no_skew", "chirp_z", "none"]}
    rng = np.random.default_rng(0)

    def table(none_error):
        err = np.array([0.03, 0.035, 0.036, none_error]) \
            + 0.001 * rng.standard_normal((4, 2, 3, 4))
        return xr.Dataset({"test_error": xr.DataArray(
            err, dims=("seed", "model", "d", "transform"), coords=coords,
            attrs={"units": "1", "long_name": "per-digit test error"})})

    run = {"ch2/table2_2": table(0.08)}
    same = {o["id"]: o for o in claims.evaluate_all(run, twin_runs={"ch2/table2_2": table(0.08)})}
    moved = {o["id"]: o for o in claims.evaluate_all(run, twin_runs={"ch2/table2_2": table(0.03)})}
    cid = "ch2.spatial_transformers_beat_plain"
    assert same[cid]["status"] == "reproduced" and same[cid]["fragile"] is False
    assert same[cid]["perturbed"]["status"] == "reproduced"
    assert moved[cid]["status"] == "reproduced" and moved[cid]["fragile"] is True
    assert moved[cid]["perturbed"]["status"] != "reproduced"
    # the twins' own numbers, beside the run's: the plain network's error moved to 0.03
    assert moved[cid]["perturbed"]["measured"] != moved[cid]["measured"]
    assert same[cid]["perturbed"]["measured"].keys() == same[cid]["measured"].keys()
    alone = {o["id"]: o for o in claims.evaluate_all(run)}
    assert "fragile" not in alone[cid] and "perturbed" not in alone[cid]
    assert "fragile" not in moved["ch3.spline_fastest"]
    # native twin runs (every CPU pin lifted) are a second, independent view
    both = {o["id"]: o for o in claims.evaluate_all(
        run, twin_runs={"ch2/table2_2": table(0.08)}, native_runs={"ch2/table2_2": table(0.03)})}
    assert both[cid]["fragile"] is False and both[cid]["isa_dependent"] is True
    assert both[cid]["native"]["status"] != "reproduced"
    assert "isa_dependent" not in same[cid] and "native" not in both["ch3.spline_fastest"]


def test_a_claim_is_twinned_only_when_every_input_it_requires_has_a_twin():
    """A claim needing ``x/a`` and ``x/b`` with only ``x/a`` rerun is neither fragile nor
    robust: its "twin" verdict would mix a twin with an original run. Only when every
    required input has a twin is ``fragile`` (and ``isa_dependent``) decided."""
    from thesis.claims.types import Claim, Verdict

    def ds(v):
        return xr.Dataset({"v": ("seed", np.full(3, float(v)), {"units": "1"})})

    claim = Claim(id="chx.two_inputs", chapter=2, section="§0", quote="q", summary="s",
                  requires=("x/a", "x/b"),
                  fn=lambda r: Verdict("reproduced" if float(r["x/a"]["v"].mean())
                                       + float(r["x/b"]["v"].mean()) > 1 else "not_reproduced"))
    run = {"x/a": ds(1), "x/b": ds(1)}
    half = claims.replaced_view(run, {"x/a": ds(-5)})
    out = claims.evaluate(claim, run, perturbed=half, native=half)
    assert "fragile" not in out and "perturbed" not in out
    assert "isa_dependent" not in out and "native" not in out
    full = claims.replaced_view(run, {"x/a": ds(-5), "x/b": ds(1)})
    out = claims.evaluate(claim, run, perturbed=full, native=full)
    assert out["fragile"] is True and out["isa_dependent"] is True
