"""``docs/table_map.md``: where each thesis table and figure is made, checked and tested.

Generated, never typed: ``python -m thesis.report.table_map > docs/table_map.md``. One row per
experiment of :data:`thesis.registry.EXPERIMENTS` (a result ``results/<profile>/<key>.nc``):

- thesis: the table or figure it reproduces (``tableX_Y`` -> Tab. X.Y, ``figX_Y`` -> Fig.
  X.Y), else the section its rule's message names (``§...``);
- rule: the Snakemake rule that makes it (``rule <chapter>_<artifact>:`` in the file of
  ``workflow/rules/`` named beside it), or the ``thesis`` command where no rule does;
- experiment: the registered ``module:function``;
- claims: the ids of the claims (:data:`thesis.claims.CLAIMS`) whose check requires it;
- tests: the test module of the experiment's module and the chapter, claim and report
  tests that name the key.

Then one row per thesis table or figure whose published numbers (:mod:`thesis.paper`)
have no experiment of their own (a setup table such as Tab. 2.1): the claims resting on
them and the experiments those claims read.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from thesis import registry
from thesis.config import repo_root

__all__ = ["declared_rules", "rows", "table_map_md", "thesis_ref", "main"]

#: Where the rules are declared, relative to the repository root.
WORKFLOW_FILES = ("Snakefile", "workflow/rules")


def declared_rules(root: Path) -> dict[str, tuple[str, str]]:
    """Rule name -> (file relative to ``root``, the rule's text up to the next rule) for
    every ``rule <name>:`` of the Snakefile and ``workflow/rules/*.smk``."""
    files = [root / "Snakefile", *sorted((root / "workflow" / "rules").glob("*.smk"))]
    out = {}
    for path in files:
        text = path.read_text()
        heads = list(re.finditer(r"^rule\s+(\w+)\s*:", text, flags=re.M))
        for i, m in enumerate(heads):
            end = heads[i + 1].start() if i + 1 < len(heads) else len(text)
            out[m.group(1)] = (str(path.relative_to(root)), text[m.start():end])
    return out


_NUMBERED = re.compile(r"^(table|fig)(\d+)_(\d+)$")
_SECTION = re.compile(r"(§\d+(?:\.\d+)*(?:-\d+(?:\.\d+)*)?|Tab\. \d+\.\d+|Fig\. \d+\.\d+)")


def thesis_ref(key: str, rule_text: str = "") -> str:
    """The thesis table or figure of registry ``key`` (``"ch4/table4_2"`` -> ``"Tab.
    4.2"``), else the first section, table or figure the rule's message names, else "—"."""
    m = _NUMBERED.match(key.split("/", 1)[1])
    if m:
        return f"{'Tab.' if m.group(1) == 'table' else 'Fig.'} {m.group(2)}.{m.group(3)}"
    message = re.search(r"message:\s*((?:\s*[f]?\"[^\"]*\"\s*)+)", rule_text)
    found = _SECTION.search(message.group(1)) if message else None
    return found.group(1) if found else "—"


def _rule_of(key: str, rules: dict[str, tuple[str, str]]) -> tuple[str, str]:
    """(rule name, its file) that makes ``key``, or ("", the command) where no rule does."""
    name = key.replace("/", "_")
    if name in rules:
        return name, rules[name][0]
    bench = [b for b, k in registry.BENCHMARKS.items() if k == key]
    if bench:
        return "", f"thesis bench {bench[0]}"
    return "", f"thesis run {key}"


#: Test folders of the whole pipeline's machinery, left out of the per-experiment lists
#: (they name keys as examples; tests/pipeline runs every result of the default target).
_GENERIC_TESTS = ("core", "pipeline")


def _tests_of(key: str, root: Path) -> list[str]:
    """Test files (relative to ``root``) of the experiment: the test module of its own
    module (``thesis.<package>.<module>`` -> ``tests/<package>/test_<module>.py``) and the
    chapter, claim and report tests that name ``key`` in quotes."""
    package, module = registry.EXPERIMENTS[key].partition(":")[0].split(".")[1:3]
    own = root / "tests" / package / f"test_{module}.py"
    out = {str(own.relative_to(root))} if own.exists() else set()
    for path in sorted((root / "tests").rglob("test_*.py")):
        if path.parent.name in _GENERIC_TESTS:
            continue
        if re.search(rf"[\"']{re.escape(key)}[\"']", path.read_text()):
            out.add(str(path.relative_to(root)))
    return sorted(out)


def _claims_of(key: str) -> list[str]:
    from thesis.claims import CLAIMS

    return [c.id for c in CLAIMS if key in c.requires]


def rows(root: Path | None = None) -> list[dict]:
    """One dict per registry experiment (``thesis``, ``key``, ``rule``, ``file``,
    ``experiment``, ``claims``, ``tests``), in registry order."""
    root = Path(root or repo_root())
    rules = declared_rules(root)
    out = []
    for key, target in registry.EXPERIMENTS.items():
        rule, where = _rule_of(key, rules)
        out.append(dict(thesis=thesis_ref(key, rules.get(rule, ("", ""))[1]), key=key,
                        rule=rule, file=where, experiment=target, claims=_claims_of(key),
                        tests=_tests_of(key, root)))
    return out


def _paper_only() -> list[dict]:
    """Thesis tables and figures with published numbers but no experiment named after
    them: (``id``, ``thesis``, ``claims`` resting on them, ``reads``: what those claims
    require, ``departures``: the declared departures from them and the results they
    concern)."""
    from thesis import paper
    from thesis.claims import CLAIMS
    from thesis.departures import DEPARTURES

    artifacts = {k.split("/", 1)[1] for k in registry.EXPERIMENTS}
    ids = sorted({v.key.split("/", 1)[0] for v in paper.ALL}, key=_natural)
    out = []
    for pid in ids:
        if pid in artifacts or not _NUMBERED.match(pid):
            continue
        claims = [c for c in CLAIMS if any(k.startswith(pid + "/") for k in c.paper_keys)]
        deps = [d for d in DEPARTURES if any(k.startswith(pid + "/") for k in d.paper_keys)]
        out.append(dict(id=pid, thesis=thesis_ref(f"x/{pid}"), claims=[c.id for c in claims],
                        reads=sorted({r for c in claims for r in c.requires}
                                     | {r for d in deps for r in d.results}),
                        departures=[d.id for d in deps]))
    return out


def _natural(s: str) -> list:
    return [int(p) if p.isdigit() else p for p in re.split(r"(\d+)", s)]


def _cell(items: list[str], fmt: str = "`{}`") -> str:
    return ", ".join(fmt.format(i) for i in items) or "—"


def table_map_md(root: Path | None = None) -> str:
    """The whole ``docs/table_map.md`` as text."""
    lines = [
        "# Where each thesis table and figure is made",
        "",
        "Generated from the registry (`src/thesis/registry.py`), the rules "
        "(`workflow/rules/`), the claims (`src/thesis/claims/`) and the published numbers "
        "(`src/thesis/paper/`) by `python -m thesis.report.table_map > docs/table_map.md`; "
        "`tests/core/test_table_map.py` fails when this page is stale. A result is "
        "`results/<profile>/<key>.nc`; `snakemake <rule> --config profile=<profile>` makes "
        "it, and `tests/pipeline/test_smoke.py` runs every result of the default target "
        "end to end (smoke profile) against `tests/regression/smoke/`.",
        "",
        "## Experiments",
        "",
        "| thesis | key | rule | experiment | claims | tests |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows(root):
        rule = f"`{r['rule']}` ({r['file']})" if r["rule"] else f"none: `{r['file']}`"
        lines.append(f"| {r['thesis']} | `{r['key']}` | {rule} | `{r['experiment']}` | "
                     f"{_cell(r['claims'])} | {_cell(r['tests'])} |")
    lines += ["", "## Tables and figures without an experiment of their own", "",
              "Their published numbers (`src/thesis/paper/`) are the set-up the experiments "
              "above follow, or depart from as declared (`src/thesis/departures/`).", "",
              "| thesis | paper id | claims | departures | results concerned |",
              "|---|---|---|---|---|"]
    for r in _paper_only():
        lines.append(f"| {r['thesis']} | `{r['id']}` | {_cell(r['claims'])} | "
                     f"{_cell(r['departures'])} | {_cell(r['reads'])} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Print the map (``python -m thesis.report.table_map > docs/table_map.md``)."""
    sys.stdout.write(table_map_md())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
