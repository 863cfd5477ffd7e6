"""Regression of the smoke profile's numbers against committed references.

A reference is ``tests/regression/smoke/<chapter>/<artifact>.json``: per data variable
its dims, coords, values and a tolerance (``rtol``, ``atol``). Exactly the variables the
dataset marks as wall-clock measurements (attribute ``measurement="wall_clock"``,
:data:`thesis.store.WALL_CLOCK`: wall seconds, rates per wall-second, memory) are
recorded with ``compare: false`` and skipped, and so are text renderings of numbers the
dataset holds as variables of their own (attribute ``renders``, naming them: a rounding
boundary flips the text, e.g. -0.0775 m/s as "-0.077" or "-0.078", where the number itself
passes its tolerance); nothing is guessed from units or names, so a simulated duration in
seconds is compared like any other number. The policy is read
from the result's attributes at comparison time (the reference records it too, and a
difference is reported as a stale reference). Tolerances default to
``rtol=1e-3, atol=1e-6``; a variable may set its own with the attributes
``regression_rtol`` and ``regression_atol``, which must stay below the quantity's spread
(``tests/core/test_regression.py`` checks the committed references).

``make update-reference`` rewrites the references from ``results/smoke`` on purpose and
prints what changed.

Chaotic results. PSO, CMA-ES, training and closed loops turn a last-bit difference
(another CPU model, another instruction set, another library build) into another
trajectory, so many smoke numbers are no property of the code alone and cannot be
regressed bit for bit across hosts. Which ones, and by how much, is measured, not
guessed: ``make update-reference`` runs the smoke profile with its two twin runs, the
perturbed twins (every simulation and initial weight moved by about one float32 ulp,
``--config perturb=1e-7``) and the native twins (every CPU pin lifted,
``--config isa=native``: the host's own kernels, a stand-in for another CPU model), and
:func:`measure_sensitivity` compares each variable with its twins:

* a variable every twin reproduces within the default tolerance is **deterministic** and
  stays compared value by value at ``rtol=1e-3, atol=1e-6`` (data synthesis, closed
  forms, engine validation, timings' sizes);
* a variable some twin moves is **chaotic**: it is compared through a statistic that is
  stable under such a move, its mean over the runs' ``seed`` dimension where it has one
  (independent runs: the mean's host-to-host difference shrinks as 1/sqrt(n)), else its
  mean over all its elements (for labels: the share of each label), within
  ``CHAOS_Z`` times the difference the twins measured (:func:`chaos_tolerance`). The
  reference records the twins' measurements beside the tolerance (``chaos``), and
  ``tests/core/test_regression.py`` recomputes the tolerance from them, so no tolerance
  is typed or widened by hand.

Twins of one host do not see everything another host does: a trajectory that stayed
together under both twins can part on another CPU. So another host's run of the same
code counts as a twin too: ``update ... --host-twin NAME=DIR`` reads that host's
references (``DIR``) as its results, and every twin measurement a reference records under
a name not measured again (another host's) is carried over when the references are
rewritten on this host, as long as the variable keeps its shape. Measurements accumulate
over hosts; deleting a reference forgets them.

A twin run need not be a new smoke run: ``python -m thesis.regression twin smoke
tests/regression/smoke --twin-run NAME=DIR`` measures another run of the same code (another
host's ``results/smoke``, a twin made later) against the committed references as they
are (:func:`add_twin_runs`): values and coordinates stay, tolerances follow from the
measurement. ``--forget NAME:KEYPREFIX`` drops a recorded measurement that was no twin.

A twin must reach the computation it measures. A loop of physics steps written outside
:func:`thesis.physics.rollout` starts from :func:`thesis.physics.perturbation.at_start`
as the rollout does (the model checks' :func:`thesis.modelcheck.checks.simulate_runs`),
and every command that runs an experiment passes ``--perturb`` on (``thesis validate``
too); otherwise the perturbed twin is the same run bit for bit, and a variable that only
another host's last bits move stays compared tightly and fails there. Hosts of other
CPU models differ in the last bits of the float32 rollouts even with the instruction
set pinned, and a rounding-level start moves the same variables by as much. Three kinds
of variable carry such a difference past the default tolerance, and are compared as
the chaotic statistics they are: a **mean over few starts** (``model/convergence``'s
``case_speed``: the starts of a case that stayed up, 3 at smoke), a **share past a
threshold** (``stance_knee_stop``: the stance samples with a knee on its stop, where one
sample of 141 is 0.7 points), and a **difference of nearly equal numbers** compared
relatively (``model/puppy_convergence``'s ``followup_speed_change``, its ``_lower_k``,
``touch_change``: changes of a speed or a touch spread between dt and dt/2 of 1e-2 or
less, whose relative tolerance of 1e-3 lies below the float32 noise of either term).

ch6's runs carry their own perturbed twins and mark their per-run variables
``regression_over="seed"`` with the tolerance those twins measure in the run itself;
they are compared within the larger of that and the reference's twin-measured tolerance.

Hosts. With chaotic variables compared through such statistics, one canonical reference
set serves every host. A host class (:func:`host_class`) may still have its own
reference for a result under ``tests/regression/<profile>-<class>/``
(:func:`reference_file`), where a measured reason requires it; none does today.
"""

from __future__ import annotations

import json
import platform
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from thesis.cpupins import cpu_flags, is_x86_64
from thesis.registry import MEASUREMENTS

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
    """Tolerance of one variable; wall-clock measurements and text renderings of other
    variables (attribute ``renders``) are recorded but not compared. A variable compared
    through its mean over a dimension also records that dimension (``over``, from the
    attribute ``regression_over``)."""
    policy = {
        "compare": not is_wall_clock(var) and not var.attrs.get("renders"),
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
    sq = _squared_differences(a, b)
    d2 = float(np.nanmean(sq)) if np.isfinite(sq).any() else 0.0
    if not np.isfinite(sq).all():
        # a value finite in one twin and NaN in the other: the quantity's own spread
        ab = np.concatenate([a.ravel(), b.ravel()]).astype(float)
        spread = np.nanmax(np.abs(ab)) if a.size else 0
        d2 = max(d2, float(spread) ** 2 * float(np.mean(~np.isfinite(sq))))
    return chaos_tolerance_from_rms(np.sqrt(d2), n_over, z)


def _squared_differences(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Per-element squared difference of a variable and its twin: labels 1 where they
    differ; numbers (a - b)^2 where both are finite, 0 where neither is, NaN where exactly
    one is (each caller prices such a flip by the quantity's magnitude)."""
    if _is_text(a) or _is_text(b):
        return (a.astype(str) != b.astype(str)).astype(float)
    a, b = a.astype(float), b.astype(float)
    fa, fb = np.isfinite(a), np.isfinite(b)
    with np.errstate(invalid="ignore"):  # inf - inf where both are infinite: not used
        return np.where(fa & fb, (a - b) ** 2, np.where(fa == fb, 0.0, np.nan))


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


#: The dimension of independent runs over which a chaotic variable is averaged.
RUNS_DIM = "seed"


def _chaos_over(var: xr.DataArray) -> str | None:
    """The dimension a chaotic variable is averaged over: its own ``regression_over``, else
    :data:`RUNS_DIM` where it has it, else ``None`` (the mean over all its elements)."""
    over = var.attrs.get("regression_over") or (RUNS_DIM if RUNS_DIM in var.dims else None)
    return str(over) if over else None


def measure_sensitivity(var: xr.DataArray, twins: dict[str, xr.DataArray],
                        z: float = CHAOS_Z, carried: dict[str, float] | None = None
                        ) -> dict | None:
    """How far rounding-level twins move a variable; ``None`` when none moves it.

    ``twins`` maps a twin run's name to the same variable made by that run. A twin moves
    the variable when it differs beyond the default tolerance (a twin of another shape
    moves it by definition). For each twin the root-mean-square difference per run is
    recorded (:func:`_twin_rms`: the largest over the statistic's elements); the tolerance
    of the statistic compared is :func:`chaos_tolerance_from_rms` of the largest twin's,
    over ``n`` runs: the number of seeds where the variable is averaged over seeds, else
    1 (the mean over all elements moves by at most the pooled RMS difference,
    Cauchy-Schwarz, whatever the elements' correlation).

    ``carried`` holds twin measurements recorded earlier and not repeated now (another
    host's run, :func:`update_references`): they count like the twins measured now.

    Returns ``{"over": dim or None, "n": n, "z": z, "twins": {name: rms}, "atol": tol}``.
    """
    carried = {k: float(v) for k, v in (carried or {}).items() if k not in twins}
    moved, rms = any(v > 0 for v in carried.values()), dict(carried)
    over = _chaos_over(var)
    for name, twin in sorted(twins.items()):
        a, b = np.asarray(var.values), np.asarray(twin.values)
        if a.shape != b.shape:
            raise ValueError(f"twin {name!r} of {var.name!r} has shape {b.shape}, "
                             f"not {a.shape}: the twin run is of another configuration")
        if not _close(a, b, DEFAULT_RTOL, DEFAULT_ATOL):
            moved = True
        rms[name] = _twin_rms(a, b, var.dims.index(over) if over else None)
    if not moved:
        return None
    n = int(var.sizes[over]) if over else 1
    worst = max(rms.values())
    return {"over": over, "n": n, "z": float(z), "twins": rms,
            "atol": chaos_tolerance_from_rms(worst, n, z)}


def _twin_rms(a: np.ndarray, b: np.ndarray, axis: int | None = None) -> float:
    """Root-mean-square difference of a variable and its twin, per element of the
    statistic compared: over ``axis`` (the runs) for each other element, the largest of
    those (chaos concentrates where trajectories part: a pooled RMS would understate it
    there); ``axis=None``: pooled over every element, which bounds the move of the mean
    over all elements. Labels count 1 where they differ; a value finite in one and not in
    the other counts the quantity's largest magnitude (as :func:`chaos_tolerance`)."""
    sq = _squared_differences(a, b)
    if np.isnan(sq).any():  # a flip finite <-> not: the largest finite magnitude
        a, b = a.astype(float), b.astype(float)
        big = np.nanmax(np.abs(np.where(np.isfinite(a), a, b)[np.isfinite(a) | np.isfinite(b)]))
        sq = np.where(np.isnan(sq), big ** 2, sq)
    if sq.size == 0:
        return 0.0
    d2 = float(np.mean(sq)) if axis is None else float(np.max(np.mean(sq, axis=axis)))
    return float(np.sqrt(d2))


def chaos_tolerance_from_rms(rms: float, n_over: int, z: float = CHAOS_Z) -> float:
    """``max(DEFAULT_ATOL, z rms / sqrt(n_over))``: the tolerance of a mean over
    ``n_over`` independent runs whose per-run twin difference has RMS ``rms``."""
    return max(DEFAULT_ATOL, z * float(rms) / float(np.sqrt(max(int(n_over), 1))))


def _compare_chaotic(name: str, var: xr.DataArray, spec: dict) -> list[str]:
    """Compare a chaotic variable through its mean over runs (or over all elements, for
    labels the share of each label) within the twin-measured ``spec["chaos"]["atol"]`` (and
    the larger of the run's own ``regression_atol`` where it has one)."""
    chaos = spec["chaos"]
    over = chaos["over"]
    if _is_text(var.values) != _is_text(spec["values"]):
        return [f"variable {name!r}: labels against numbers"]
    a, b = np.asarray(var.values), np.asarray(spec["values"], dtype=object)
    if a.shape != b.shape:
        return [f"variable {name!r} shape {a.shape} != {b.shape}"]
    if over is not None and over not in var.dims:
        return [f"variable {name!r} has no dimension {over!r} to compare over"]
    atol = max(float(chaos["atol"]), float(var.attrs.get("regression_atol", DEFAULT_ATOL))
               if var.attrs.get("regression_over") else DEFAULT_ATOL)
    labels = sorted(set(a.astype(str).ravel()) | set(b.astype(str).ravel())) \
        if _is_text(a) else []
    if over is None:  # one mean over every element: flatten onto a single "run" axis
        got = _means_over(a.reshape(-1), ["all"], "all", labels)
        want = _means_over(np.asarray(spec["values"]).reshape(-1), ["all"], "all", labels)
    else:
        got = _means_over(a, list(var.dims), over, labels)
        want = _means_over(spec["values"], spec["dims"], over, labels)
    got, want = np.asarray(got, float), np.asarray(want, float)
    fg, fw = np.isfinite(got), np.isfinite(want)
    # a mean finite on one side only (every run censored or failed on the other) differs
    # by the quantity's largest magnitude, as the twins' differences were measured
    big = float(np.max(np.abs(np.concatenate([got[fg], want[fw]])))) if (fg | fw).any() \
        else 0.0
    diff = np.where(fg & fw, np.abs(np.where(fg, got, 0) - np.where(fw, want, 0)),
                    np.where(fg == fw, 0.0, big))
    bound = atol + DEFAULT_RTOL * np.abs(np.where(fw, want, 0.0))
    if np.all(diff <= bound):
        return []
    err = float(np.max(diff))
    what = f"mean over {over}" if over else "mean over all elements"
    return [f"variable {name!r} (chaotic): {what} differs beyond the twin-measured "
            f"atol={atol:.4g} (max abs diff {err:.4g})"]


def _jsonable(a) -> list | float | str:
    a = np.asarray(a)
    if a.dtype.kind in "US O":
        return a.astype(str).tolist()
    if a.dtype.kind == "M":
        return a.astype(str).tolist()
    # infinities are kept (JSON's Infinity, as Python's json writes and reads it): a result
    # whose value is inf (e.g. a speed change from zero) must not compare against NaN
    return a.astype(float).tolist() if a.dtype.kind in "fc" else a.tolist()


def to_reference(ds: xr.Dataset, twins: dict[str, xr.Dataset] | None = None,
                 previous: dict | None = None) -> dict:
    """The JSON-ready reference of a result dataset.

    ``twins`` maps a twin run's name (``"perturbed"``, ``"native"``, ``"host-avx2"``) to the
    same result made by that run; each variable some twin moves is recorded as chaotic
    with the tolerance its twins measured (:func:`measure_sensitivity`). ``previous`` is
    the reference being replaced: the twin measurements it records under names not
    measured now (another host's) are carried over for each variable whose dimensions
    and shape are unchanged, so what one host measured is not forgotten on the next.
    """
    variables = {}
    old = (previous or {}).get("variables", {})
    for name, var in ds.data_vars.items():
        variables[name] = {"dims": list(var.dims), "values": _jsonable(var.values),
                           **default_tolerance(name, var)}
        before = old.get(name, {})
        carried = before.get("chaos", {}).get("twins", {}) \
            if before.get("dims") == list(var.dims) and \
            np.asarray(before.get("values"), dtype=object).shape == var.shape else {}
        if variables[name]["compare"] and (twins or carried):
            chaos = measure_sensitivity(var, {k: t[name] for k, t in (twins or {}).items()
                                              if name in t.data_vars}, carried=carried)
            if chaos is not None:
                variables[name]["chaos"] = chaos
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
        if "chaos" in spec:
            problems += _compare_chaotic(name, var, spec)
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


#: Host classes (:func:`host_class`) that the canonical references under
#: ``tests/regression/<profile>/`` serve: all of them, through the chaotic variables'
#: twin-measured tolerances (module docstring).
CANONICAL_HOST = "any"


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


def reference_as_dataset(ref: dict) -> xr.Dataset:
    """A reference's recorded values as a result dataset (every variable with the policy
    attributes it was recorded with): another host's run of the same code, to measure
    the host-to-host sensitivity with (``update ... --host-twin NAME=DIR``)."""
    data = {}
    for name, spec in ref["variables"].items():
        values = np.asarray(spec["values"], dtype=object)
        try:
            values = values.astype(float)
        except (TypeError, ValueError):
            values = values.astype(str)
        attrs = {} if spec["compare"] else {"measurement": "wall_clock"}
        if "over" in spec:
            attrs.update(regression_over=spec["over"], regression_atol=spec["atol"])
        elif (spec["rtol"], spec["atol"]) != (DEFAULT_RTOL, DEFAULT_ATOL):
            attrs.update(regression_rtol=spec["rtol"], regression_atol=spec["atol"])
        data[name] = xr.DataArray(values, dims=spec["dims"], attrs=attrs)
    coords = {k: v for k, v in ref["coords"].items()
              if any(k in s["dims"] for s in ref["variables"].values())}
    return xr.Dataset(data, coords=coords, attrs={"thesis_ref": ref.get("thesis_ref", "")})


def host_twin(directory: Path, keys) -> dict[str, xr.Dataset]:
    """The references under ``directory`` (another host's, of the same code) as twin
    results, by key, for the ``keys`` they hold."""
    out = {}
    for key in keys:
        path = reference_path(Path(directory), key)
        if path.exists():
            out[key] = reference_as_dataset(json.loads(path.read_text()))
    return out


def update_references(results: dict[str, xr.Dataset], root: Path,
                      twins: dict[str, dict[str, xr.Dataset]] | None = None) -> list[str]:
    """Rewrite the canonical references from ``results``; returns what changed.

    ``twins`` maps a twin run's name (``"perturbed"``, ``"native"``) to its results, by key;
    each result is recorded with the sensitivity its twins measure (:func:`to_reference`).
    A result no twin run made is recorded as deterministic, except for its variables that
    carry their own twins (``regression_over``). The references of host classes beside
    ``root`` are listed, not rewritten: each needs a measured reason (module docstring).
    """
    root = Path(root)
    twins = twins or {}
    changes = write_references(results, root, twins)
    for name, runs in sorted(twins.items()):
        missing = sorted(set(results) - set(runs))
        if missing:
            changes.append(f"no {name} twin of {', '.join(missing)}")
    others = sorted(p for p in root.parent.glob(f"{root.name}-*") if p.is_dir())
    return changes + [f"references of {p.name.removeprefix(root.name + '-')} hosts ({p}) "
                      f"are kept as they are: delete them where the canonical ones serve"
                      for p in others]


def write_references(results: dict[str, xr.Dataset], root: Path,
                     twins: dict[str, dict[str, xr.Dataset]] | None = None) -> list[str]:
    """Rewrite every reference from ``results`` (with the sensitivity measured against
    ``twins``, :func:`update_references`); returns a human-readable diff summary."""
    changes = []
    twins = twins or {}
    for key, ds in sorted(results.items()):
        path = reference_path(root, key)
        old = json.loads(path.read_text()) if path.exists() else None
        new = to_reference(ds, {name: runs[key] for name, runs in twins.items()
                                if key in runs}, previous=old)
        chaotic = sorted(n for n, v in new["variables"].items() if "chaos" in v)
        if old is not None:
            diff = compare(ds, old)
            changes += [f"{key}: {d}" for d in diff] or [f"{key}: unchanged"]
        else:
            changes.append(f"{key}: new reference")
        if chaotic:
            changes.append(f"{key}: chaotic under its twins: {', '.join(chaotic)}")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(new, indent=1) + "\n")
    return changes


def add_twins(ref: dict, twins: dict[str, xr.Dataset],
              forget: frozenset[str] | set[str] = frozenset()) -> tuple[dict, list[str]]:
    """A reference with twin runs measured against its own recorded values; the values,
    coordinates and policies stay as they are.

    The reference is the run the canonical host made (:func:`reference_as_dataset`), so
    another run of the same code (another host's results, a twin run made later) is
    measured against it exactly as :func:`to_reference` measures a twin against a fresh
    result, and the run need not be repeated. ``twins`` maps a twin's name to its result
    dataset; a name already recorded is measured again, every other recorded measurement
    is carried (:func:`measure_sensitivity`) except those named in ``forget`` (a
    measurement found to be no twin, e.g. a rerun that the perturbation never reached).

    Returns ``(new reference, lines saying which variables' comparison changed)``.
    """
    base = reference_as_dataset(ref)
    new = json.loads(json.dumps(ref))
    lines = []
    for name, spec in new["variables"].items():
        if not spec["compare"]:
            continue
        before = spec.get("chaos")
        carried = {k: v for k, v in (before or {}).get("twins", {}).items() if k not in forget}
        chaos = measure_sensitivity(base[name], {k: t[name] for k, t in twins.items()
                                                 if name in t.data_vars}, carried=carried)
        if chaos is None:
            spec.pop("chaos", None)
        else:
            spec["chaos"] = chaos
        was = "tight" if before is None else f"chaotic atol {before['atol']:.4g}"
        now = "tight" if chaos is None else f"chaotic atol {chaos['atol']:.4g}"
        if was != now:
            lines.append(f"{name}: {was} -> {now}")
    return new, lines


def add_twin_runs(root: Path, twins: dict[str, dict[str, xr.Dataset]],
                  forget: dict[str, set[str]] | None = None) -> list[str]:
    """:func:`add_twins` for every reference under ``root`` that some twin run made
    (``twins``: name -> {key: dataset}); ``forget`` maps a key prefix (``"model/"``) to the
    recorded twin names to drop from its references. Rewrites the files; returns what
    changed, and the references no twin run made."""
    root = Path(root)
    out = []
    for path in sorted(root.glob("*/*.json")):
        key = f"{path.parent.name}/{path.stem}"
        runs = {name: r[key] for name, r in twins.items() if key in r}
        drop = set().union(*[v for p, v in (forget or {}).items() if key.startswith(p)])
        if not runs and not drop:
            out.append(f"{key}: no twin run made it; kept")
            continue
        ref = json.loads(path.read_text())
        new, lines = add_twins(ref, runs, frozenset(drop))
        path.write_text(json.dumps(new, indent=1) + "\n")
        out += [f"{key}: {line}" for line in lines] or [f"{key}: comparison unchanged"]
    return out


def main(argv: list[str] | None = None) -> int:
    """``python -m thesis.regression update [profile] [refdir]``: rewrite the canonical
    references from ``results/<profile>`` with the sensitivity that its twin runs
    ``results/<profile>-perturbed`` and ``results/<profile>-native`` measure
    (:func:`update_references`); ``make update-reference`` makes all three first."""
    import sys

    from thesis import store

    args = list(sys.argv[1:] if argv is None else argv)
    hosts, runs_extra, forget = {}, {}, {}
    while "--forget" in args:  # --forget NAME:KEYPREFIX: drop a recorded twin (twin ...)
        i = args.index("--forget")
        name, _, prefix = args[i + 1].partition(":")
        forget.setdefault(prefix, set()).add(name)
        del args[i:i + 2]
    for flag, into, prefix in (("--host-twin", hosts, "host-"), ("--twin-run", runs_extra, "")):
        while flag in args:  # --host-twin NAME=DIR: another host's references;
            i = args.index(flag)  # --twin-run NAME=DIR: another twin run's results
            name, _, directory = args[i + 1].partition("=")
            into[prefix + name] = Path(directory)
            del args[i:i + 2]
    if not args or args[0] not in ("update", "twin"):
        print("usage: python -m thesis.regression update [profile] [refdir] "
              "[--host-twin NAME=REFDIR ...] [--twin-run NAME=RESULTSDIR ...]\n"
              "       python -m thesis.regression twin [profile] [refdir] "
              "[--twin-run NAME=RESULTSDIR ...] [--forget NAME:KEYPREFIX ...]")
        return 2
    profile = args[1] if len(args) > 1 else "smoke"
    root = Path(args[2]) if len(args) > 2 else Path("tests/regression") / profile
    if args[0] == "twin":  # measure twin runs against the references as they are
        runs = {name: store.load_results(d.name, d.parent) for name, d in runs_extra.items()}
        runs.update({name: host_twin(d, [f"{p.parent.name}/{p.stem}"
                                          for p in Path(root).glob("*/*.json")])
                     for name, d in hosts.items()})
        print(f"twins: {', '.join(runs) or 'none'}; forgotten: {forget or 'none'}")
        for line in add_twin_runs(root, runs, forget):
            print(line)
        return 0
    results = {k: ds for k, ds in store.load_results(profile).items()
               if k not in MEASUREMENTS}  # made outside the default target
    if not results:
        print(f"no results under results/{profile}: run the {profile} pipeline first")
        return 1
    twins = {}
    for name, kw in (("perturbed", {"perturbed": True}), ("native", {"native": True})):
        runs = store.load_results(store.results_name(profile, **kw))
        if not runs:
            print(f"no results under results/{store.results_name(profile, **kw)}: run "
                  f"`snakemake --config profile={profile} "
                  f"{'perturb=1e-7' if name == 'perturbed' else 'isa=native'}` first")
            return 1
        twins[name] = runs
    for name, directory in hosts.items():
        twins[name] = host_twin(directory, results)
    for name, directory in runs_extra.items():
        twins[name] = store.load_results(directory.name, directory.parent)
    print(f"host class {host_class()}; twins: {', '.join(twins)}")
    for line in update_references(results, root, twins):
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
