"""Regression of the smoke profile's numbers against committed references.

A reference is ``tests/regression/smoke/<chapter>/<artifact>.json``: per data variable
its dims, coords, values and a tolerance (``rtol``, ``atol``). Exactly the variables the
dataset marks as wall-clock measurements (attribute ``measurement="wall_clock"``,
:data:`thesis.store.WALL_CLOCK`: wall seconds, rates per wall-second, memory) are
recorded with ``compare: false`` and skipped; nothing is guessed from units or names, so
a simulated duration in seconds is compared like any other number. The policy is read
from the result's attributes at comparison time (the reference records it too, and a
difference is reported as a stale reference). Tolerances default to
``rtol=1e-3, atol=1e-6``; a variable may set its own with the attributes
``regression_rtol`` and ``regression_atol``, which must stay below the quantity's spread
(``tests/core/test_regression.py`` checks the committed references).

``make update-reference`` rewrites the references from ``results/smoke`` on purpose and
prints what changed.

Hosts. The engine's chapters (ch3, ch4, ch7) and ch5 gave the same smoke numbers on the
AVX2 and the AVX-512 hosts measured (``jax.max_isa`` pins XLA's code, :mod:`thesis.cpupins`
numpy's and OpenBLAS's). ch2's training and ch6's closed loops did not: some of XLA's
kernels still round differently on the AVX-512 host, and training and a chaotic closed
loop carry a last-bit difference into other error rates and gait outcomes.
The references under ``tests/regression/<profile>/`` are those of :data:`CANONICAL_HOST`
hosts; a result that differs on hosts of another class (:func:`host_class`) has its own
reference under ``tests/regression/<profile>-<class>/``, which is used there instead
(:func:`reference_file`), and ``update`` on such a host writes only those
(:func:`update_references`).
"""

from __future__ import annotations

import json
import platform
from pathlib import Path

import numpy as np
import xarray as xr

from thesis.cpupins import cpu_flags, is_x86_64

DEFAULT_RTOL = 1e-3
DEFAULT_ATOL = 1e-6


def is_wall_clock(var: xr.DataArray) -> bool:
    """Whether a variable is marked as a wall-clock measurement."""
    return str(var.attrs.get("measurement", "")) == "wall_clock"


def default_tolerance(name: str, var: xr.DataArray) -> dict:
    """Tolerance of one variable; wall-clock measurements are recorded but not compared."""
    return {
        "compare": not is_wall_clock(var),
        "rtol": float(var.attrs.get("regression_rtol", DEFAULT_RTOL)),
        "atol": float(var.attrs.get("regression_atol", DEFAULT_ATOL)),
    }


def _jsonable(a) -> list | float | str:
    a = np.asarray(a)
    if a.dtype.kind in "US O":
        return a.astype(str).tolist()
    if a.dtype.kind == "M":
        return a.astype(str).tolist()
    return np.where(np.isfinite(a.astype(float)), a.astype(float), np.nan).tolist() \
        if a.dtype.kind in "fc" else a.tolist()


def to_reference(ds: xr.Dataset) -> dict:
    """The JSON-ready reference of a result dataset."""
    variables = {}
    for name, var in ds.data_vars.items():
        variables[name] = {"dims": list(var.dims), "values": _jsonable(var.values),
                           **default_tolerance(name, var)}
    coords = {name: _jsonable(c.values) for name, c in ds.coords.items()}
    return {"thesis_ref": str(ds.attrs.get("thesis_ref", "")), "coords": coords,
            "variables": variables}


def compare(ds: xr.Dataset, ref: dict) -> list[str]:
    """Differences between a result and its reference (empty list: they agree).

    Whether a variable is compared, and how closely, is decided by the result's own
    attributes (:func:`default_tolerance`): a variable is skipped exactly when the result
    marks it ``measurement="wall_clock"``. The reference supplies the values; a reference
    whose recorded policy differs from the result's is reported as stale, so that a
    changed tolerance is rewritten on purpose (``make update-reference``).
    """
    problems = []
    for name, c in ref["coords"].items():
        if name not in ds.coords:
            problems.append(f"coordinate {name!r} missing")
            continue
        got = _jsonable(ds.coords[name].values)
        if got != c and not _close(got, c, 1e-9, 1e-12):
            problems.append(f"coordinate {name!r} differs: {got} != {c}")
    for name, spec in ref["variables"].items():
        if name not in ds.data_vars:
            problems.append(f"variable {name!r} missing")
            continue
        var = ds[name]
        if list(var.dims) != spec["dims"]:
            problems.append(f"variable {name!r} dims {list(var.dims)} != {spec['dims']}")
            continue
        policy = default_tolerance(name, var)
        recorded = {k: spec.get(k) for k in policy}
        if recorded != policy:
            problems.append(f"variable {name!r}: the reference records {recorded}, the "
                            f"result asks for {policy} (stale reference)")
        if not policy["compare"]:
            continue
        got = np.asarray(_jsonable(var.values), dtype=object)
        want = np.asarray(spec["values"], dtype=object)
        if got.shape != want.shape:
            problems.append(f"variable {name!r} shape {got.shape} != {want.shape}")
            continue
        if not _close(var.values, spec["values"], policy["rtol"], policy["atol"]):
            if _is_text(var.values) or _is_text(spec["values"]):
                problems.append(f"variable {name!r} labels differ: {got.tolist()} != "
                                f"{want.tolist()}")
                continue
            a = np.asarray(var.values, dtype=float)
            b = np.asarray(spec["values"], dtype=float)
            with np.errstate(invalid="ignore"):
                err = np.nanmax(np.abs(a - b)) if a.size else 0.0
            problems.append(f"variable {name!r} differs beyond rtol={policy['rtol']}, "
                            f"atol={policy['atol']} (max abs diff {err:.4g})")
    for name in ds.data_vars:
        if name not in ref["variables"]:
            problems.append(f"variable {name!r} is new (not in the reference)")
    return problems


def _is_text(values) -> bool:
    return np.asarray(values).dtype.kind in "USO"


def _close(a, b, rtol, atol) -> bool:
    a = np.asarray(a)
    b = np.asarray(b)
    if _is_text(a) or _is_text(b):
        return a.astype(str).tolist() == b.astype(str).tolist()
    a = a.astype(float)
    b = b.astype(float)
    return a.shape == b.shape and bool(np.allclose(a, b, rtol=rtol, atol=atol, equal_nan=True))


def reference_path(root: Path, key: str) -> Path:
    ch, art = key.split("/", 1)
    return Path(root) / ch / f"{art}.json"


#: Class of the hosts on which the references under ``tests/regression/<profile>/`` are
#: recorded (:func:`host_class`).
CANONICAL_HOST = "avx2"


def host_class(machine: str | None = None, flags: set[str] | None = None) -> str:
    """Numerics class of a host for the references: on x86-64, ``"avx512"`` where the CPU
    has AVX-512 (``avx512f``), ``"avx2"`` where it has AVX2 but not AVX-512, ``"x86-64"``
    below that; elsewhere the lower-case machine name (e.g. ``"arm64"``).

    ``machine`` defaults to this one, ``flags`` to :func:`thesis.cpupins.cpu_flags`.
    """
    if not is_x86_64(machine):
        return (platform.machine() if machine is None else machine).lower()
    flags = cpu_flags() if flags is None else flags
    if "avx512f" in flags:
        return "avx512"
    return "avx2" if "avx2" in flags else "x86-64"


def host_root(root: Path, host: str) -> Path:
    """Directory of the references of ``host``'s class beside the canonical ``root``."""
    root = Path(root)
    return root if host == CANONICAL_HOST else root.parent / f"{root.name}-{host}"


def reference_file(root: Path, key: str, host: str) -> Path:
    """The reference a result of ``key`` is compared with on a ``host``-class host: that
    class's own where it has one, else the canonical one."""
    own = reference_path(host_root(root, host), key)
    return own if own.exists() else reference_path(root, key)


def update_references(results: dict[str, xr.Dataset], root: Path, host: str) -> list[str]:
    """Rewrite the references of ``host``'s class from ``results``; returns what changed.

    On a :data:`CANONICAL_HOST` host: every canonical reference (:func:`write_references`),
    plus a reminder of the other classes' references, which only their hosts can rewrite.
    Elsewhere: a result within tolerance of its canonical reference needs none of its own
    (a stale one is deleted); a result that differs gets its own; a result without a
    canonical reference (a new artifact) writes the canonical one, flagged as recorded on a
    ``host`` host.
    """
    root = Path(root)
    if host == CANONICAL_HOST:
        changes = write_references(results, root)
        others = sorted(p for p in root.parent.glob(f"{root.name}-*") if p.is_dir())
        return changes + [f"references of {p.name.removeprefix(root.name + '-')} hosts "
                          f"({p}) are not rewritten here: rerun on such a host"
                          for p in others]
    own_root = host_root(root, host)
    changes = []
    for key, ds in sorted(results.items()):
        canonical, own = reference_path(root, key), reference_path(own_root, key)
        if not canonical.exists():
            write_references({key: ds}, root)
            changes.append(f"{key}: new reference, recorded on a {host} host, not on a "
                           f"{CANONICAL_HOST} one")
            continue
        diff = compare(ds, json.loads(canonical.read_text()))
        if not diff:
            if own.exists():
                own.unlink()
                changes.append(f"{key}: matches the canonical reference; {own} removed")
            continue
        changes.append(f"{key}: differs from the canonical reference on {host} hosts "
                       f"({len(diff)} differences): own reference {own}")
        changes += write_references({key: ds}, own_root)
    return changes


def write_references(results: dict[str, xr.Dataset], root: Path) -> list[str]:
    """Rewrite every reference from ``results``; returns a human-readable diff summary."""
    changes = []
    for key, ds in sorted(results.items()):
        path = reference_path(root, key)
        new = to_reference(ds)
        if path.exists():
            old = json.loads(path.read_text())
            diff = compare(ds, old)
            changes += [f"{key}: {d}" for d in diff] or [f"{key}: unchanged"]
        else:
            changes.append(f"{key}: new reference")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(new, indent=1) + "\n")
    return changes


def main(argv: list[str] | None = None) -> int:
    """``python -m thesis.regression update [profile] [refdir]``: rewrite the references of
    this host's class (:func:`update_references`)."""
    import sys

    from thesis import store

    args = list(sys.argv[1:] if argv is None else argv)
    if not args or args[0] != "update":
        print("usage: python -m thesis.regression update [profile] [refdir]")
        return 2
    profile = args[1] if len(args) > 1 else "smoke"
    root = Path(args[2]) if len(args) > 2 else Path("tests/regression") / profile
    results = store.load_results(profile)
    if not results:
        print(f"no results under results/{profile}: run the {profile} pipeline first")
        return 1
    host = host_class()
    print(f"host class {host} (canonical: {CANONICAL_HOST})")
    for line in update_references(results, root, host):
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
