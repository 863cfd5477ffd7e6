"""The workflow's rules are declared where grep finds them: every rule is a ``rule <name>:``
block in the Snakefile or in workflow/rules/*.smk (none built in a loop from a name
computed at parse time), and every ``rules.<name>`` reference names a declared rule."""

from __future__ import annotations

import re

from thesis import config

ROOT = config.repo_root()
WORKFLOW = [ROOT / "Snakefile", *sorted((ROOT / "workflow" / "rules").glob("*.smk"))]


def declared_rules() -> dict[str, str]:
    """Rule name -> file (relative to the repository) of every ``rule <name>:`` line."""
    out = {}
    for path in WORKFLOW:
        for name in re.findall(r"^rule\s+(\w+)\s*:", path.read_text(), flags=re.M):
            assert name not in out, f"rule {name} declared twice"
            out[name] = str(path.relative_to(ROOT))
    return out


def test_no_rule_is_built_from_a_computed_name():
    """An anonymous ``rule:`` (its name from a ``name:`` directive, e.g. in a loop) cannot
    be found by grepping for ``rule <name>``."""
    for path in WORKFLOW:
        text = path.read_text()
        assert not re.search(r"^[ \t]*rule[ \t]*:", text, flags=re.M), path.name
        assert not re.search(r"^[ \t]+name[ \t]*:", text, flags=re.M), path.name
        assert not re.search(r"^[ \t]+rule[ \t]+\w+[ \t]*:", text, flags=re.M), (
            f"{path.name}: a rule declared inside a block (a loop or a condition)")


def test_every_rule_reference_names_a_declared_rule():
    declared = declared_rules()
    assert {"all", "ch2_table2_2", "ch4_table4_2", "report"} <= set(declared)
    for path in WORKFLOW:
        for name in re.findall(r"\brules\.(\w+)\.", path.read_text()):
            assert name in declared, f"{path.name} refers to rules.{name}, declared nowhere"


def hashed_code() -> set[str]:
    """Every subpackage or file of ``thesis`` that the workflow's code hashes name: the
    ``CORE_CODE`` and ``CHAPTER_CODE`` lists and the quoted arguments of each
    ``code_version(...)`` call in the Snakefile and workflow/rules/*.smk."""
    names: set[str] = set()
    for path in WORKFLOW:
        text = path.read_text()
        blocks = re.findall(r"^CORE_CODE = \[(.*?)\]", text, flags=re.M | re.S)
        blocks += re.findall(r"^CHAPTER_CODE = \{(.*?)^\}", text, flags=re.M | re.S)
        blocks += re.findall(r"\bcode_version\(([^)]*)\)", text)
        for block in blocks:
            names.update(re.findall(r"\"([^\"]+)\"", block))
    return names


def test_every_hashed_package_exists():
    """provenance.code_version skips a path that does not exist, so a subpackage renamed
    or moved without its workflow entry would silently leave a chapter's code out of the
    hash that reruns it."""
    names = hashed_code()
    assert {"store.py", "physics", "gaits", "ch2", "ch5/data.py", "modelcheck"} <= names
    package = ROOT / "src" / "thesis"
    missing = sorted(n for n in names if not (package / n).exists())
    assert not missing, missing
