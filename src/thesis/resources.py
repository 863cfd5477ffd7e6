"""What each rule's job needs on a cluster, measured from Snakemake's benchmark files.

Every rule that runs a job writes ``benchmarks/<profile>/<chapter>/<name>.tsv`` (Snakemake's
``benchmark:`` directive: wall seconds ``s``, peak resident memory ``max_rss`` [MB] of the
job's process tree, ``cpu_time`` [s]). :func:`update` turns the benchmarks of a profile
into ``workflow/resources.yaml`` (one section per profile, one entry per benchmark name),
and the rules request exactly those values (``workflow/rules/common.smk: res``), so a
cluster job is neither killed for exceeding its request nor holding a node it does not use:

* ``mem_mb`` = :data:`MEM_FACTOR` x the largest ``max_rss`` seen + :data:`MEM_EXTRA_MB`,
  rounded up to 100 MB (JAX's allocations vary a little between runs; the extra covers the
  Snakemake job step that wraps the command on a cluster node);
* ``runtime`` [min] = :data:`RUNTIME_FACTOR` x the longest ``s`` seen, rounded up, at least
  :data:`RUNTIME_FLOOR_MIN` (a node slower than the measuring machine, a cold JAX
  compilation cache);
* ``cores_used`` = ``cpu_time / s``, recorded beside the rule's ``threads`` so a rule that
  asks for more cores than it keeps busy shows up (not a request).

A profile never run here (``paper``) has no section; its rules then request the values
they declare themselves, which are upper estimates, not measurements
(:func:`lookup` returns ``None``). ``python -m thesis.resources update <profile>`` after a
run rewrites the profile's section and prints what changed (``--replace ch2`` after a
chapter was rerun whole drops its entries that no job of the rerun measured).
"""

from __future__ import annotations

import csv
import math
import re
import sys
from pathlib import Path

import yaml

#: The file the rules read (relative to the repository root).
RESOURCES_FILE = Path("workflow/resources.yaml")
MEM_FACTOR = 1.5
MEM_EXTRA_MB = 500
RUNTIME_FACTOR = 3.0
RUNTIME_FLOOR_MIN = 5

_HEADER = """\
# What each rule's job needs, per profile and benchmark name (chapter/name), measured from
# benchmarks/<profile>/ by `python -m thesis.resources update <profile>` (thesis.resources
# says how: mem_mb from the peak resident memory, runtime [min] from the wall time, each
# with a margin). Rules request these on a cluster (workflow/rules/common.smk: res);
# `measured` is what the benchmark files held. Do not edit by hand: rerun the profile and
# update.
"""


def read_benchmark(path: str | Path) -> dict[str, float]:
    """The worst case over the rows (repeated runs) of one Snakemake benchmark file.

    Returns ``{"s", "max_rss", "cpu_time", "runs"}`` (seconds, MB, seconds, count).
    Raises ValueError naming the file if it has no rows or lacks a column.
    """
    path = Path(path)
    with path.open() as fh:
        rows = list(csv.DictReader(fh, delimiter="\t"))
    if not rows:
        raise ValueError(f"benchmark file {path} has no rows")
    try:
        s = max(float(r["s"]) for r in rows)
        rss = max(float(r["max_rss"]) for r in rows)
        cpu = max(float(r["cpu_time"]) for r in rows)
    except (KeyError, ValueError) as err:
        raise ValueError(f"benchmark file {path}: {err}") from err
    return {"s": s, "max_rss": rss, "cpu_time": cpu, "runs": float(len(rows))}


def requirement(measured: dict[str, float]) -> dict[str, object]:
    """``mem_mb`` and ``runtime`` [min] to request for a job measured as ``measured``."""
    mem = math.ceil((MEM_FACTOR * measured["max_rss"] + MEM_EXTRA_MB) / 100.0) * 100
    runtime = max(RUNTIME_FLOOR_MIN, math.ceil(RUNTIME_FACTOR * measured["s"] / 60.0))
    cores = measured["cpu_time"] / measured["s"] if measured["s"] > 0 else 0.0
    return {"mem_mb": int(mem), "runtime": int(runtime),
            "measured": {"wall_seconds": round(measured["s"], 1),
                         "max_rss_mb": round(measured["max_rss"], 1),
                         "cores_used": round(cores, 2)}}


def measure(bench_dir: str | Path) -> dict[str, dict[str, object]]:
    """``{"<chapter>/<name>": requirement}`` for every benchmark file under ``bench_dir``."""
    bench_dir = Path(bench_dir)
    out = {}
    for path in sorted(bench_dir.glob("*/*.tsv")):
        out[f"{path.parent.name}/{path.stem}"] = requirement(read_benchmark(path))
    return out


def load(path: str | Path = RESOURCES_FILE) -> dict[str, dict]:
    """The whole resources file (profile -> name -> entry); empty if there is none."""
    path = Path(path)
    if not path.exists():
        return {}
    return yaml.safe_load(path.read_text()) or {}


def lookup(table: dict, profile: str, name: str) -> dict[str, int] | None:
    """``{"mem_mb", "runtime"}`` measured for ``name`` (``"ch3/table3_1"``) in ``profile``,
    or ``None`` where that profile or name was never measured.

    A name with wildcards (``"ch2/table2_2_ffn_spn_seed{seed}"``) matches every measured
    instance (any text in place of each ``{...}``) and gets the largest of their values.
    """
    section = table.get(profile, {})
    pattern = re.compile("^" + "".join(
        ".+" if part.startswith("{") else re.escape(part)
        for part in re.split(r"(\{[^}]*\})", name)) + "$")
    entries = [e for n, e in section.items() if pattern.match(n)]
    if not entries:
        return None
    return {"mem_mb": max(int(e["mem_mb"]) for e in entries),
            "runtime": max(int(e["runtime"]) for e in entries)}


def update(profile: str, bench_root: str | Path = "benchmarks",
           path: str | Path = RESOURCES_FILE, replace: tuple[str, ...] = ()) -> list[str]:
    """Rewrite ``profile``'s section of the resources file from ``bench_root/<profile>``.

    Names measured before but absent now keep their entry (a partial run does not forget
    the rest), except under the chapters named in ``replace`` (e.g. ``("ch2",)``), which
    were rerun whole: there an entry without a benchmark now (a seed the profile no longer
    runs) is dropped. Returns one line per change.
    """
    path = Path(path)
    table = load(path)
    new = measure(Path(bench_root) / profile)
    if not new:
        raise ValueError(f"no benchmark files under {Path(bench_root) / profile}")
    old = dict(table.get(profile, {}))
    changes = []
    for name in sorted(old):
        if name.split("/", 1)[0] in replace and name not in new:
            del old[name]
            changes.append(f"{profile} {name}: dropped (no benchmark in a rerun chapter)")
    for name, entry in sorted(new.items()):
        before = old.get(name)
        was = "new" if before is None else f"{before['mem_mb']} MB, {before['runtime']} min"
        now = f"{entry['mem_mb']} MB, {entry['runtime']} min"
        if was != now:
            changes.append(f"{profile} {name}: {was} -> {now}")
    table[profile] = {**old, **new}
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(_HEADER + yaml.safe_dump(table, sort_keys=True))
    return changes


def main(argv: list[str] | None = None) -> int:
    """``python -m thesis.resources update <profile> [benchmarks dir] [--replace ch2 ...]``
    (``--replace``: chapters rerun whole, see :func:`update`)."""
    args = list(sys.argv[1:] if argv is None else argv)
    replace: tuple[str, ...] = ()
    if "--replace" in args:
        i = args.index("--replace")
        args, replace = args[:i], tuple(args[i + 1:])
    if len(args) < 2 or args[0] != "update":
        print("usage: python -m thesis.resources update <profile> [benchmarks dir] "
              "[--replace CHAPTER ...]")
        return 2
    bench = args[2] if len(args) > 2 else "benchmarks"
    for line in update(args[1], bench, replace=replace) or ["unchanged"]:
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
