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
numpy's and OpenBLAS's). ch2's training did not: some of XLA's kernels still round
differently on the AVX-512 host, and training carries a last-bit difference into other
error rates. ch6's closed loops carry it into other gait outcomes, and are regressed
through means over seeds (below).
The references under ``tests/regression/<profile>/`` are those of :data:`CANONICAL_HOST`
hosts; a result that differs on hosts of another class (:func:`host_class`) has its own
reference under ``tests/regression/<profile>-<class>/``, which is used there instead
(:func:`reference_file`), and ``update`` on such a host writes only those
(:func:`update_references`).

Chaotic results. ch6's closed loops amplify a rounding-level difference until a run's
outcome can flip (measured by its perturbed twin runs, :mod:`thesis.embodied.twins`), so
a single run's numbers are no property of its seed and cannot be regressed one by one
across hosts. A variable marked ``regression_over=<dim>`` (e.g. ``"seed"``) is compared
through its mean over that dimension (for labels: the share of each label), within the
larger of the result's and the reference's ``regression_atol``; that tolerance is not part
of the recorded policy, because it is measured by the run itself (:func:`chaos_tolerance`).
"""

from __future__ import annotations

import json
import platform
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from thesis.cpupins import cpu_flags, is_x86_64

DEFAULT_RTOL = 1e-3
DEFAULT_ATOL = 1e-6
#: Standard deviations of the host-to-host difference of a mean over seeds that a
#: chaotic variable's tolerance allows (:func:`chaos_tolerance`): two-sided 6e-5 per
#: comparison under a normal law, so a run of a few hundred compared means fails by chance
#: in about 1 % of hosts.
CHAOS_Z = 4.0


def is_wall_clock(var: xr.DataArray) -> bool:
    """Whether a variable is marked as a wall-clock measurement."""
    return str(var.attrs.get("measurement", "")) == "wall_clock"


def default_tolerance(name: str, var: xr.DataArray) -> dict:
    """Tolerance of one variable; wall-clock measurements are recorded but not compared.
    A variable compared through its mean over a dimension also records that dimension
    (``over``, from the attribute ``regression_over``)."""
    policy = {
        "compare": not is_wall_clock(var),
        "rtol": float(var.attrs.get("regression_rtol", DEFAULT_RTOL)),
        "atol": float(var.attrs.get("regression_atol", DEFAULT_ATOL)),
    }
    if var.attrs.get("regression_over"):
        policy["over"] = str(var.attrs["regression_over"])
    return policy


def chaos_tolerance(values, twin, n_over: int, z: float = CHAOS_Z) -> float:
    """Tolerance of the mean over ``n_over`` runs of a chaotic quantity, from twin runs.

    ``values`` and ``twin`` hold the quantity for the same runs, the twin started from a
    state perturbed at the rounding level. Another host is another such perturbation, so
    the difference of a run's value between hosts has the mean square of the twins'
    difference, d² (pooled over every run and element; labels: 1 where they differ), and
    a mean over ``n_over`` runs differs by about sqrt(d² / n_over). Returns
    ``max(DEFAULT_ATOL, z sqrt(d² / n_over))``: no twin differing gives the rounding guard.
    """
    a, b = np.asarray(values), np.asarray(twin)
    if a.shape != b.shape:
        raise ValueError(f"twin shape {b.shape} != {a.shape}")
    if _is_text(a) or _is_text(b):
        sq = (a.astype(str) != b.astype(str)).astype(float)
    else:
        a, b = a.astype(float), b.astype(float)
        both = np.isfinite(a) & np.isfinite(b)
        sq = np.where(both, (a - b) ** 2, np.where(np.isfinite(a) == np.isfinite(b), 0.0,
                                                   np.nan))
    d2 = float(np.nanmean(sq)) if np.isfinite(sq).any() else 0.0
    if not np.isfinite(sq).all():
        # a value finite in one twin and NaN in the other: the quantity's own spread
        spread = np.nanmax(np.abs(np.concatenate([a.ravel(), b.ravel()]))) if a.size else 0
        d2 = max(d2, float(spread) ** 2 * float(np.mean(~np.isfinite(sq))))
    return max(DEFAULT_ATOL, z * float(np.sqrt(d2 / max(int(n_over), 1))))


def _means_over(values, dims: list[str], over: str, labels: list[str]) -> np.ndarray:
    """Mean over the dimension ``over`` of reference or result values: NaN-aware for
    numbers; for labels, the share of each of ``labels`` (stacked on a leading axis)."""
    a = np.asarray(values)
    axis = dims.index(over)
    if _is_text(a):
        return np.stack([(a.astype(str) == n).mean(axis=axis) for n in labels])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN slices stay NaN
        return np.nanmean(a.astype(float), axis=axis)


def _compare_over(name: str, var: xr.DataArray, spec: dict, policy: dict) -> list[str]:
    """Compare a ``regression_over`` variable through its mean (label shares) over a dim."""
    over = policy["over"]
    if over not in var.dims:
        return [f"variable {name!r} has no dimension {over!r} to compare over"]
    if _is_text(var.values) != _is_text(spec["values"]):
        return [f"variable {name!r}: labels against numbers"]
    atol = max(float(policy["atol"]), float(spec.get("atol", DEFAULT_ATOL)))
    labels = sorted(set(np.asarray(var.values).astype(str).ravel())
                    | set(np.asarray(spec["values"]).astype(str).ravel())) \
        if _is_text(var.values) else []
    got = _means_over(var.values, list(var.dims), over, labels)
    want = _means_over(spec["values"], spec["dims"], over, labels)
    if got.shape != want.shape:
        return [f"variable {name!r} mean over {over} shape {got.shape} != {want.shape}"]
    if np.allclose(got, want, rtol=policy["rtol"], atol=atol, equal_nan=True):
        return []
    with np.errstate(invalid="ignore"):
        err = np.nanmax(np.abs(got - want)) if got.size else 0.0
    return [f"variable {name!r}: mean over {over} differs beyond rtol={policy['rtol']}, "
            f"atol={atol:.4g} (max abs diff {err:.4g})"]


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
        if "over" in policy:  # the tolerance is measured by each run, not a policy
            recorded["atol"] = policy["atol"]
        if recorded != policy or ("over" in spec) != ("over" in policy):
            problems.append(f"variable {name!r}: the reference records {recorded}, the "
                            f"result asks for {policy} (stale reference)")
        if not policy["compare"]:
            continue
        if "over" in policy:
            problems += _compare_over(name, var, spec, policy)
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
