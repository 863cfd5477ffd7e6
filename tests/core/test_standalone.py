"""The repository stands alone: what its code and pages cite, a clone contains.

* No file cites a document outside the repository: the team's notes (their file names),
  a folder beside the checkout or an absolute path of one machine. The
  architecture is ``docs/architecture.md``; where a physical value comes from is
  ``docs/sources.md`` or the primary source itself.
* Every ``docs/<page>.md`` a file cites exists, and so does every ``#anchor`` it cites
  in that page (an explicit ``<a id="...">`` or a heading's GitHub slug).
* No code, configuration or page names an issue number: how the code came to be is in
  the commit messages, the files say what it is and why.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve()

#: Where the project's own text lives: code, rules, configuration, tests and pages.
SCANNED = ("src", "tests", "workflow", "config", "docs", "profiles")
SCANNED_FILES = ("README.md", "CONTRIBUTING.md", "Snakefile", "Makefile", "pyproject.toml")
SUFFIXES = {".py", ".smk", ".yaml", ".yml", ".md", ".rst", ".sh", ".toml", ".txt", ""}

#: A reference to a file outside the repository. The names are split so that this file
#: does not match them itself.
OUTSIDE = re.compile("|".join([
    r"\b" + "FA" + r"CTS\b",                       # the team's fact sheet
    r"\b" + "DES" + r"IGN\b",                      # the team's design note
    r"\b" + "ECO" + r"SYSTEM\b",                   # the team's tool conventions
    r"\b" + "ONC" + r"ILLA\.md\b",                 # the team's Oncilla note
    r"\b" + "CH" + r"456\b",                       # the team's chapter 4-6 notes
    r"\b" + "STY" + r"LE\.md\b",                   # the team's style guide
    r"\.\./" + "sha" + r"red\b",                   # the folder beside the checkout
    r"/" + "wo" + r"rk/",                          # one machine's absolute paths
    "sha" + r"red folder",
]))

#: Markdown pages the pipeline writes into reports/<profile>/ (thesis.report), which a
#: clone does not contain until it runs.
GENERATED_PAGES = {"summary.md", "measurements.md"}

#: A Markdown file named in text.
MD_NAME = re.compile(r"(?<![\w.-])([A-Za-z0-9_-]+\.md)\b")

#: An issue number (history belongs in commit messages).
ISSUE = re.compile(r"\bissues?\s+#?[0-9]", re.IGNORECASE)

#: A cited page of docs/ and its optional anchor.
DOCS_CITE = re.compile(r"\bdocs/([A-Za-z0-9_.-]+\.md)(?:#([A-Za-z0-9_-]+))?")


def project_files() -> list[Path]:
    """Every text file of the project that :data:`SCANNED` and :data:`SCANNED_FILES` name
    (caches and this test aside)."""
    out = [ROOT / f for f in SCANNED_FILES if (ROOT / f).is_file()]
    for d in SCANNED:
        for p in sorted((ROOT / d).rglob("*")):
            if (p.is_file() and p.suffix in SUFFIXES and "__pycache__" not in p.parts
                    and p.resolve() != HERE):
                out.append(p)
    return out


def matches(pattern: re.Pattern, files: list[Path]) -> list[str]:
    """``"path:line: text"`` of every line of ``files`` that ``pattern`` matches."""
    found = []
    for p in files:
        try:
            lines = p.read_text(encoding="utf-8").splitlines()
        except UnicodeDecodeError:
            continue
        for i, line in enumerate(lines, 1):
            if pattern.search(line):
                found.append(f"{p.relative_to(ROOT)}:{i}: {line.strip()[:120]}")
    return found


def anchors(page: Path) -> set[str]:
    """The anchors of a Markdown page: explicit ``id="..."`` and GitHub heading slugs."""
    text = page.read_text(encoding="utf-8")
    ids = set(re.findall(r"""\bid=["']([A-Za-z0-9_-]+)["']""", text))
    for heading in re.findall(r"^#{1,6}\s+(.+?)\s*$", text, re.M):
        slug = re.sub(r"[^\w\- ]", "", heading.lower()).replace(" ", "-")
        ids.add(slug)
    return ids


def dangling_doc_citations(files: list[Path], root: Path = ROOT) -> list[str]:
    """Citations ``docs/<page>.md[#anchor]`` in ``files`` whose page or anchor is missing
    from ``root/docs``."""
    bad = []
    cache: dict[str, set[str] | None] = {}
    for p in files:
        try:
            text = p.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        for m in DOCS_CITE.finditer(text):
            page, anchor = m.group(1), m.group(2)
            if page not in cache:
                path = root / "docs" / page
                cache[page] = anchors(path) if path.is_file() else None
            if cache[page] is None:
                bad.append(f"{p.relative_to(root)}: docs/{page} does not exist")
            elif anchor and anchor not in cache[page]:
                bad.append(f"{p.relative_to(root)}: docs/{page} has no anchor #{anchor}")
    return bad


def test_the_scan_sees_the_project():
    files = {p.relative_to(ROOT).as_posix() for p in project_files()}
    for f in ("README.md", "CONTRIBUTING.md", "src/thesis/physics/models/oncilla.py",
              "workflow/rules/common.smk", "config/schema.yaml", "docs/architecture.md",
              "docs/sources.md"):
        assert f in files, f


def test_no_reference_outside_the_repository():
    found = matches(OUTSIDE, project_files())
    assert not found, "cite docs/ or the primary source instead:\n" + "\n".join(found)


def test_no_issue_numbers():
    found = matches(ISSUE, project_files())
    assert not found, "history belongs in commit messages:\n" + "\n".join(found)


def test_every_named_markdown_page_exists():
    """A page named anywhere (``README.md``, ``docs/sources.md``, ``summary.md``) is one
    of the repository's own or one the pipeline generates."""
    own = {p.name for p in ROOT.rglob("*.md")
           if not {".venv", ".git", "results", "reports"} & set(p.relative_to(ROOT).parts)}
    bad = []
    for p in project_files():
        for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1):
            for name in MD_NAME.findall(line):
                if name not in own | GENERATED_PAGES:
                    bad.append(f"{p.relative_to(ROOT)}:{i}: {name}")
    assert not bad, "pages that a clone does not have:\n" + "\n".join(bad)


def test_every_cited_docs_page_and_anchor_exists():
    bad = dangling_doc_citations(project_files())
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("text, outside", [
    ("see " + "FA" + "CTS §5", True), ("(" + "DES" + "IGN.md)", True),
    ("../" + "shared/thesis/thesis.txt", True), ("/" + "work/shared", True),
    ("the team's " + "shared folder", True), ("ONC" + "ILLA.md HW", True),
    ("docs/sources.md#oncilla-mass", False), ("facts of the engine", False),
    ("shared by ch3 and ch4", False)])
def test_the_outside_pattern(text, outside):
    assert bool(OUTSIDE.search(text)) is outside, text


@pytest.mark.parametrize("text, issue", [
    ("(iss" "ue 43)", True), ("Iss" "ue 55 items 1 and 5", True), ("iss" "ues 3 and 4", True),
    ("iss" "ue #12", True), ("an issue of the solver", False), ("no issue: 3 seeds", False)])
def test_the_issue_pattern(text, issue):
    assert bool(ISSUE.search(text)) is issue, text


def test_a_dangling_citation_is_caught(tmp_path):
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "page.md").write_text('# A page\n\n<a id="kept"></a>\n## Second part\n')
    code = tmp_path / "code.py"
    code.write_text("# docs/page.md#kept docs/page.md#second-part docs/page.md "
                    "docs/page.md#gone docs/none.md\n")
    bad = dangling_doc_citations([code], root=tmp_path)
    assert bad == ["code.py: docs/page.md has no anchor #gone",
                   "code.py: docs/none.md does not exist"]
