"""docs/table_map.md: generated from the registry (thesis.report.table_map), complete, current."""

from __future__ import annotations

import re

from thesis import paper, registry
from thesis.report import table_map
from thesis.config import repo_root

ROOT = repo_root()


def test_committed_map_is_the_generated_one():
    committed = (ROOT / "docs" / "table_map.md").read_text()
    assert committed == table_map.table_map_md(ROOT), (
        "docs/table_map.md is stale: python -m thesis.report.table_map > docs/table_map.md")


def test_every_experiment_and_every_published_table_and_figure_is_in_the_map():
    text = table_map.table_map_md(ROOT)
    rows = {r["key"]: r for r in table_map.rows(ROOT)}
    assert list(rows) == list(registry.EXPERIMENTS)
    for key in registry.EXPERIMENTS:
        assert f"| `{key}` |" in text, key
        m = re.match(r"(table|fig)(\d+)_(\d+)$", key.split("/", 1)[1])
        if m:
            ref = f"{'Tab.' if m.group(1) == 'table' else 'Fig.'} {m.group(2)}.{m.group(3)}"
            assert rows[key]["thesis"] == ref, key
    published = {v.key.split("/", 1)[0] for v in paper.ALL}
    numbered = {p for p in published if re.match(r"(table|fig)\d+_\d+$", p)}
    assert {"table2_1", "table2_2", "table7_1", "fig4_10"} <= numbered
    for pid in numbered:
        assert f"/{pid}` |" in text or f"| `{pid}` |" in text, pid


def test_each_mapped_rule_runs_its_experiment():
    """The rule named beside a key is declared and runs that key (``run <key>`` or
    ``{params.key}`` set to it, its ``thesis bench`` name, or ``validate --only``)."""
    rules = table_map.declared_rules(ROOT)
    mapped = 0
    for r in table_map.rows(ROOT):
        if not r["rule"]:
            assert r["file"].startswith("thesis "), r
            continue
        mapped += 1
        where, block = rules[r["rule"]]
        assert where == r["file"]
        artifact = r["key"].split("/", 1)[1]
        bench = [b for b, k in registry.BENCHMARKS.items() if k == r["key"]]
        assert (f"run {r['key']} " in block or f'key="{r["key"]}"' in block
                or any(f"bench {b} " in block for b in bench)
                or (f'only="{artifact}"' in block or f"--only {artifact} " in block)), r["rule"]
    assert mapped >= 50


def test_thesis_reference_of_an_unnumbered_experiment_comes_from_its_rule_message():
    block = 'rule ch3_robustness:\n    message:\n        "Oncilla: perturbed optima (§3.3.1.1), "\n'
    assert table_map.thesis_ref("ch3/robustness", block) == "§3.3.1.1"
    assert table_map.thesis_ref("ch4/fig4_10") == "Fig. 4.10"
    assert table_map.thesis_ref("model/oncilla", "rule model_x:\n    output:\n") == "—"
