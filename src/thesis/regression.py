"""Regression of the smoke profile's numbers against committed references.

A reference is ``tests/regression/smoke/<chapter>/<artifact>.json``: per data variable
its dims, coords, values and a tolerance (``rtol``, ``atol``) or ``compare: false`` for
quantities that depend on the machine (wall times, memory). Defaults come from
:func:`default_tolerance`; a variable may override them with the attributes
``regression_rtol``, ``regression_atol`` or ``regression_compare`` (0/1).

``make update-reference`` rewrites the references from ``results/smoke`` on purpose and
prints what changed.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

MACHINE_DEPENDENT_UNITS = {"s", "ms", "bytes", "B", "seconds", "1/s", "s-1"}
MACHINE_DEPENDENT_WORDS = ("seconds", "time", "memory", "bytes", "ms_per", "per_wall")


def default_tolerance(name: str, var: xr.DataArray) -> dict:
    """Tolerance of one variable: machine-dependent ones are recorded but not compared."""
    units = str(var.attrs.get("units", ""))
    compare = int(var.attrs.get("regression_compare",
                                0 if (units in MACHINE_DEPENDENT_UNITS
                                      or any(w in name for w in MACHINE_DEPENDENT_WORDS))
                                else 1))
    return {
        "compare": bool(compare),
        "rtol": float(var.attrs.get("regression_rtol", 1e-3)),
        "atol": float(var.attrs.get("regression_atol", 1e-6)),
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
    """Differences between a result and its reference (empty list: they agree)."""
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
        if not spec.get("compare", True):
            continue
        got = np.asarray(_jsonable(var.values), dtype=object)
        want = np.asarray(spec["values"], dtype=object)
        if got.shape != want.shape:
            problems.append(f"variable {name!r} shape {got.shape} != {want.shape}")
            continue
        if not _close(var.values, spec["values"], spec["rtol"], spec["atol"]):
            a = np.asarray(var.values, dtype=float)
            b = np.asarray(spec["values"], dtype=float)
            with np.errstate(invalid="ignore"):
                err = np.nanmax(np.abs(a - b)) if a.size else 0.0
            problems.append(f"variable {name!r} differs beyond rtol={spec['rtol']}, "
                            f"atol={spec['atol']} (max abs diff {err:.4g})")
    for name in ds.data_vars:
        if name not in ref["variables"]:
            problems.append(f"variable {name!r} is new (not in the reference)")
    return problems


def _close(a, b, rtol, atol) -> bool:
    a = np.asarray(a)
    b = np.asarray(b)
    if a.dtype.kind in "US O" or b.dtype.kind in "US O":
        return a.astype(str).tolist() == b.astype(str).tolist()
    a = a.astype(float)
    b = b.astype(float)
    return a.shape == b.shape and bool(np.allclose(a, b, rtol=rtol, atol=atol, equal_nan=True))


def reference_path(root: Path, key: str) -> Path:
    ch, art = key.split("/", 1)
    return Path(root) / ch / f"{art}.json"


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
    """``python -m thesis.regression update [profile] [refdir]``: rewrite references."""
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
    for line in write_references(results, root):
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
