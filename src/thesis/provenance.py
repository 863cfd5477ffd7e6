"""Where a result came from: git state, code version, package versions, host.

Computed in one place so every dataset carries the same attributes
(docs/architecture.md#results). Nothing here imports JAX at module import time.
"""

from __future__ import annotations

import ast
import hashlib
import os
import platform
import socket
import subprocess
import sys
import zlib
from functools import lru_cache
from importlib import metadata
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent

#: Packages whose versions are recorded on every result.
VERSIONED_PACKAGES = ("jax", "jaxlib", "numpy", "xarray", "scipy", "optax", "h5netcdf",
                      "scikit-learn", "cma")


def _git(*args: str) -> str | None:
    try:
        out = subprocess.run(["git", *args], cwd=PACKAGE_DIR, capture_output=True,
                             text=True, timeout=10)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return out.stdout.strip() if out.returncode == 0 else None


@lru_cache(maxsize=1)
def git_commit() -> str:
    """HEAD commit of the repository, or ``"unknown"`` outside a git checkout."""
    return _git("rev-parse", "HEAD") or "unknown"


@lru_cache(maxsize=1)
def git_dirty() -> int:
    """1 if tracked files differ from HEAD or untracked source files exist, else 0."""
    status = _git("status", "--porcelain", "--untracked-files=normal")
    if status is None:
        return 1
    return int(bool(status.strip()))


def package_versions() -> dict[str, str]:
    """Installed versions of :data:`VERSIONED_PACKAGES` plus python."""
    out = {"python": platform.python_version()}
    for name in VERSIONED_PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "absent"
    return out


def source_digest(path: Path) -> bytes:
    """What of one Python source file decides a rerun: its syntax tree without docstrings.

    Comments, docstrings and layout do not change what a rule computes, so editing them
    does not rerun the hours of chapter jobs that read the file; any change of code
    does. A file that does not parse is taken byte for byte. The digest is kept per file
    content: every rule of the workflow hashes the shared core packages, and parsing each
    file once instead of once per rule is what keeps the Snakefile's parse in seconds.
    Across processes it is kept on disk by the SHA-256 of the file's bytes
    (:func:`digest_cache_dir`): the syntax trees of the package's ~200 files cost about
    1.5 s of every Snakefile parse (a dry run, each test that plans a workflow).
    """
    return _text_digest(path.read_bytes())


def digest_cache_dir() -> Path:
    """Where :func:`source_digest` keeps its digests between processes:
    ``$THESIS_DIGEST_CACHE``, else ``~/.cache/thesis/source-digests``, in a subfolder per
    Python version (the syntax tree's dump is Python's own and may differ between
    versions). Content-addressed, so one folder serves every checkout."""
    root = os.environ.get("THESIS_DIGEST_CACHE")
    if not root:
        home = Path.home()  # Python 3.11 leaves "~" as is where it finds no home
        if not home.is_absolute():
            raise RuntimeError("no home directory")
        root = home / ".cache" / "thesis" / "source-digests"
    return Path(root) / f"py{sys.version_info[0]}.{sys.version_info[1]}"


@lru_cache(maxsize=None)
def _text_digest(text: bytes) -> bytes:
    """:func:`source_digest` of one file's bytes, from the disk cache where it holds it
    (zlib-compressed; a cache that cannot be read or written is computed around)."""
    try:
        path = digest_cache_dir() / hashlib.sha256(text).hexdigest()
    except RuntimeError:  # no home directory to keep it in
        return _syntax_digest(text)
    try:
        return zlib.decompress(path.read_bytes())
    except (OSError, zlib.error):
        pass
    digest = _syntax_digest(text)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(zlib.compress(digest))
        os.replace(tmp, path)  # atomic: a parallel parse reads the whole entry or none
    except OSError:
        pass
    return digest


def _syntax_digest(text: bytes) -> bytes:
    """The syntax tree of ``text`` without docstrings, dumped without positions (the bytes
    themselves where it does not parse)."""
    try:
        tree = ast.parse(text)
    except (SyntaxError, ValueError):
        return text
    for node in ast.walk(tree):
        if (isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
                and ast.get_docstring(node, clean=False) is not None):
            node.body = node.body[1:] or [ast.Pass()]
    return ast.dump(tree, include_attributes=False).encode()


def code_version(*subpackages: str) -> str:
    """SHA-256 (16 hex digits) over the code of the given subpackages of ``thesis``.

    With no argument, hashes the whole package. Each file enters by its path and its
    :func:`source_digest` (docstrings and comments left out). Snakemake passes this
    through ``params:`` so a change of the code a rule runs triggers a rerun (Snakemake
    does not track the modules a rule imports: snakemake/snakemake#1694, #3213).
    """
    roots = [PACKAGE_DIR / s for s in subpackages] if subpackages else [PACKAGE_DIR]
    h = hashlib.sha256()
    for root in roots:
        files = [root] if root.is_file() else sorted(root.rglob("*.py"))
        for f in files:
            if f.exists():
                h.update(str(f.relative_to(PACKAGE_DIR)).encode())
                h.update(source_digest(f))
    return h.hexdigest()[:16]


def host() -> str:
    """Host name and CPU architecture."""
    return f"{socket.gethostname()} ({platform.machine()}, {sys.platform})"
