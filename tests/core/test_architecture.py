"""The architecture rules of docs/architecture.md#imports as tests, from the imports that
``ast`` finds in every module under src/thesis (top-level and function-local imports,
``import thesis.x``, ``from thesis.x import y``, ``from thesis import x`` and relative
imports alike).

* Only ``thesis.claims`` and ``thesis.report`` import ``thesis.paper``: experiment code
  never sees the numbers it is compared with.
* The engine ``thesis.physics`` imports no chapter package (and nothing of the project
  outside itself but the error types).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import thesis

SRC = Path(thesis.__file__).resolve().parent

#: Packages of the chapters' experiment code (docs/architecture.md#layout): thesis.chN for
#: chapter N, and the gait library thesis.gaits that chapters 3, 4 and 6 share. Listed
#: explicitly so that the rule does not depend on which of them exist yet in a checkout.
CHAPTER_PACKAGES = ("thesis.ch2", "thesis.ch3", "thesis.ch4", "thesis.ch5", "thesis.ch6",
                    "thesis.ch7", "thesis.gaits")
#: What the engine may import of the project besides itself.
PHYSICS_MAY_IMPORT = ("thesis.physics", "thesis.errors")
#: The only packages that may import the thesis's published numbers; and the model's
#: validation targets (docs/architecture.md#engine-rules: a robot model's targets are
#: published measurements from ``thesis.paper``), which decide the model, never a chapter's experiment.
PAPER_READERS = ("thesis.claims", "thesis.report", "thesis.paper",
                 "thesis.modelcheck.targets")


def _module_name(path: Path, root: Path = SRC) -> str:
    parts = ("thesis",) + path.relative_to(root).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported_modules(path: Path, root: Path = SRC) -> set[str]:
    """Absolute names of every module a source file imports; ``from a import b`` counts
    as importing both ``a`` and ``a.b`` (``b`` may be a submodule)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    here = _module_name(path, root)
    package = here if path.name == "__init__.py" else here.rpartition(".")[0]
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            names.add(mod)
            names.update(f"{mod}.{a.name}" for a in node.names)
    return names


def _within(name: str, packages) -> bool:
    return any(name == p or name.startswith(p + ".") for p in packages)


def _sources():
    return sorted(SRC.rglob("*.py"))


def _violations(select, forbidden) -> list[str]:
    out = []
    for path in _sources():
        mod = _module_name(path)
        if not select(mod):
            continue
        bad = sorted(n for n in imported_modules(path) if forbidden(n))
        out += [f"{mod} imports {n}" for n in bad]
    return out


def test_only_claims_and_report_import_the_paper():
    v = _violations(lambda m: not _within(m, PAPER_READERS),
                    lambda n: _within(n, ("thesis.paper",)))
    assert not v, "\n".join(v)


def test_physics_imports_no_chapter_package():
    v = _violations(lambda m: _within(m, ("thesis.physics",)),
                    lambda n: _within(n, CHAPTER_PACKAGES))
    assert not v, "\n".join(v)


def test_physics_imports_nothing_else_of_the_project():
    v = _violations(lambda m: _within(m, ("thesis.physics",)),
                    lambda n: _within(n, ("thesis",)) and n != "thesis"
                    and not _within(n, PHYSICS_MAY_IMPORT))
    assert not v, "\n".join(v)


@pytest.mark.parametrize("source, module, found", [
    ("from thesis import paper\n", "thesis.optim.pso", True),
    ("import thesis.paper.ch3 as p\n", "thesis.optim.pso", True),
    ("def f():\n    from thesis.paper import table\n", "thesis.optim.pso", True),
    ("from ..paper import x\n", "thesis.optim.pso", True),
    ("from thesis import store\n", "thesis.optim.pso", False),
    ("import thesis.papers_unrelated\n", "thesis.optim.pso", False),
])
def test_import_parser_finds_every_form(tmp_path, source, module, found):
    """The checks above see function-local, aliased, ``from thesis import x`` and
    relative imports (so a passing rule test is not a blind one)."""
    root = tmp_path / "thesis"
    path = root.joinpath(*module.split(".")[1:]).with_suffix(".py")
    path.parent.mkdir(parents=True)
    path.write_text(source)
    hit = any(_within(n, ("thesis.paper",)) for n in imported_modules(path, root))
    assert hit == found


def import_cycles(root: Path = SRC) -> list[list[str]]:
    """The import circles among the modules under ``root``: strongly connected components
    (more than one module) of the graph "module -> module it imports", function-local
    imports included. A package's ``__init__`` is left out (it hands its submodules' names
    on; importing a name from a package is no tie between two modules' code)."""
    files = {_module_name(p, root): p for p in sorted(root.rglob("*.py"))
             if p.name != "__init__.py"}
    graph = {m: sorted(n for n in imported_modules(p, root) if n in files and n != m)
             for m, p in files.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    cycles = []

    def visit(v: str) -> None:  # Tarjan's algorithm
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = [stack.pop()]
            while comp[-1] != v:
                comp.append(stack.pop())
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    return cycles


def test_no_import_circle():
    assert import_cycles() == []


def test_an_import_circle_is_found(tmp_path):
    """A local import that closes a loop (``a`` -> ``b`` at the top, ``b`` -> ``a`` inside
    a function) is a circle; a package ``__init__`` that re-exports its modules is not."""
    root = tmp_path / "thesis"
    (root / "pkg").mkdir(parents=True)
    (root / "pkg" / "__init__.py").write_text("from thesis.pkg.a import f\n")
    (root / "pkg" / "a.py").write_text("from thesis.pkg.b import g\n\ndef f():\n    pass\n")
    (root / "pkg" / "b.py").write_text("def g():\n    from thesis.pkg import a\n")
    (root / "pkg" / "c.py").write_text("from thesis.pkg import f\n")
    assert import_cycles(root) == [["thesis.pkg.a", "thesis.pkg.b"]]
