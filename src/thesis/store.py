"""Results as xarray datasets on disk: atomic writes, provenance, loading a profile.

Layout: ``results/<profile>/<chapter>/<artifact>.nc`` (netCDF4/HDF5 through the
h5netcdf engine). A file is written to a temporary name in the same directory and
renamed into place, so an interrupted job never leaves a result file behind.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterator, Sequence
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from thesis import cpupins, provenance
from thesis.config import canonical_json, config_sha256

ENGINE = "h5netcdf"
RESULTS_DIR = Path("results")

#: Attributes every stored result carries (set by :func:`write_dataset`).
PROVENANCE_ATTRS = (
    "thesis_ref", "profile", "experiment", "config_sha256", "config_json", "git_commit",
    "git_dirty", "seeds", "python_version", "jax_version", "jaxlib_version",
    "numpy_version", "xarray_version", "package_versions", "host", "xla_flags", "cpu_pins",
    "started", "wall_seconds", "departures",
)


#: Attributes of a variable that is a wall-clock measurement (wall seconds, rates per
#: wall-second, memory): it depends on the machine and its load, so the smoke regression
#: records it but does not compare it (:mod:`thesis.regression`). Every other variable is
#: compared, simulated durations included.
WALL_CLOCK: dict[str, str] = {"measurement": "wall_clock"}


class ResultSchemaError(ValueError):
    """A dataset lacks what every result must carry (units, long_name, thesis_ref ...)."""


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` only on success.

    On an exception (or interruption) the temporary file is removed and ``path`` is
    untouched, so a half-written file never appears under its final name.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        os.replace(tmp_path, path)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def check_result(ds: xr.Dataset) -> None:
    """Raise :class:`ResultSchemaError` unless ``ds`` is a well-formed result."""
    problems = []
    if not ds.attrs.get("thesis_ref"):
        problems.append("attribute 'thesis_ref' is missing")
    if "seeds" not in ds.attrs:
        problems.append("attribute 'seeds' is missing")
    for name, var in {**ds.data_vars, **ds.coords}.items():
        if name in ds.data_vars or var.dims != (name,):
            for attr in ("units", "long_name"):
                if not var.attrs.get(attr):
                    problems.append(f"variable {name!r} has no {attr!r}")
    if not ds.data_vars:
        problems.append("dataset has no data variables")
    if problems:
        raise ResultSchemaError("result dataset is incomplete: " + "; ".join(problems))


def _attr_value(v: Any) -> Any:
    """Make an attribute storable by h5netcdf (ECOSYSTEM.md §2 "Attribute types")."""
    if isinstance(v, (bool, np.bool_)):
        return np.int8(v)
    if v is None:
        return "none"
    if isinstance(v, dict):
        return canonical_json(v)
    if isinstance(v, (list, tuple)) and v and all(isinstance(x, str) for x in v):
        return canonical_json(list(v))
    if isinstance(v, (list, tuple)):
        return np.asarray(v)
    return v


def provenance_attrs(*, profile: str, experiment: str, config_slice: Any,
                     seeds: Sequence[int], started: datetime,
                     wall_seconds: float) -> dict[str, Any]:
    """All provenance attributes of one result (DESIGN.md "Results, provenance")."""
    versions = provenance.package_versions()
    return {
        "profile": profile,
        "experiment": experiment,
        "config_sha256": config_sha256(config_slice),
        "config_json": canonical_json(config_slice),
        "git_commit": provenance.git_commit(),
        "git_dirty": np.int8(provenance.git_dirty()),
        "seeds": np.asarray(list(seeds), dtype=np.int64),
        "python_version": versions["python"],
        "jax_version": versions["jax"],
        "jaxlib_version": versions["jaxlib"],
        "numpy_version": versions["numpy"],
        "xarray_version": versions["xarray"],
        "package_versions": canonical_json(versions),
        "host": provenance.host(),
        # the ISA and reduction flags change the last bits of every XLA result
        "xla_flags": os.environ.get("XLA_FLAGS", ""),
        # numpy's and OpenBLAS's CPU code paths (thesis.cpupins) change ch5's last bits
        "cpu_pins": canonical_json({k: os.environ.get(k, "") for k in cpupins.VARIABLES}),
        "started": started.astimezone(timezone.utc).isoformat(timespec="seconds"),
        "wall_seconds": float(wall_seconds),
        "Conventions": "CF-1.10",
    }


def write_dataset(ds: xr.Dataset, path: str | Path, *, profile: str, experiment: str,
                  config_slice: Any, started: datetime, wall_seconds: float,
                  seeds: Sequence[int] | None = None,
                  departures: Sequence[dict] = ()) -> Path:
    """Check ``ds``, stamp provenance onto a copy, and write it atomically.

    Args:
        ds: the result; must carry ``thesis_ref`` and ``seeds`` attributes and
            ``units`` + ``long_name`` on every variable.
        path: destination ``.nc`` file.
        profile: scale profile name.
        experiment: registry key, e.g. ``"ch2/table2_2"``.
        config_slice: the part of the configuration the experiment read (stored as JSON
            and hashed).
        started: when the computation started (timezone-aware).
        wall_seconds: wall time of the computation [s].
        seeds: overrides ``ds.attrs["seeds"]``.
        departures: the declared departures from the thesis this result rests on, with
            the run's config values (:func:`thesis.departures.records`); stored as the
            JSON attribute ``departures`` (``[]`` when there are none).

    Returns:
        The final path.
    """
    check_result(ds)
    seeds = list(np.atleast_1d(ds.attrs["seeds"] if seeds is None else seeds).tolist())
    out = ds.copy()
    out.attrs = {k: _attr_value(v) for k, v in ds.attrs.items()}
    out.attrs.update(provenance_attrs(profile=profile, experiment=experiment,
                                      config_slice=config_slice, seeds=seeds,
                                      started=started, wall_seconds=wall_seconds))
    out.attrs["departures"] = canonical_json(list(departures))
    for name in list(out.variables):
        out[name].attrs = {k: _attr_value(v) for k, v in out[name].attrs.items()}
    path = Path(path)
    with atomic_path(path) as tmp:
        out.to_netcdf(tmp, engine=ENGINE)
    return path


def read_dataset(path: str | Path) -> xr.Dataset:
    """Load a result fully into memory and close the file (``xr.load_dataset``)."""
    return xr.load_dataset(path, engine=ENGINE)


def result_path(profile: str, key: str, root: str | Path = RESULTS_DIR) -> Path:
    """``results/<profile>/<chapter>/<artifact>.nc`` for key ``"<chapter>/<artifact>"``."""
    chapter, artifact = key.split("/", 1)
    return Path(root) / profile / chapter / f"{artifact}.nc"


#: Suffix of the results directory of a profile's perturbed twin runs (``thesis --perturb``).
PERTURBED_SUFFIX = "-perturbed"
#: Suffix of the results directory of a profile's native twin runs (every CPU pin lifted,
#: :func:`thesis.cpupins.native_env`).
NATIVE_SUFFIX = "-native"


def results_name(profile: str, perturbed: bool = False, native: bool = False) -> str:
    """Directory name under ``results/`` of a profile's runs: ``<profile>``,
    ``<profile>-perturbed`` for its perturbed twin runs (``thesis --perturb``,
    :mod:`thesis.physics.perturbation`) or ``<profile>-native`` for its native twin runs
    (the host's own code paths, :func:`thesis.cpupins.native_env`)."""
    if perturbed and native:
        raise ValueError("a twin run is perturbed or native, not both")
    return profile + (PERTURBED_SUFFIX if perturbed else NATIVE_SUFFIX if native else "")


def load_results(profile: str, root: str | Path = RESULTS_DIR) -> dict[str, xr.Dataset]:
    """Every result of a profile, keyed ``"<chapter>/<artifact>"`` (e.g. ``"ch2/table2_2"``).

    Hidden and temporary files are ignored; a profile with no results gives ``{}``.
    """
    base = Path(root) / profile
    out: dict[str, xr.Dataset] = {}
    if not base.exists():
        return out
    for f in sorted(base.glob("*/*.nc")):
        if f.name.startswith("."):
            continue
        out[f"{f.parent.name}/{f.stem}"] = read_dataset(f)
    return out


def provenance_of(ds: xr.Dataset) -> dict[str, Any]:
    """The provenance attributes of a stored result, JSON-ready."""
    out = {}
    for k in PROVENANCE_ATTRS:
        v = ds.attrs.get(k)
        if isinstance(v, np.ndarray):
            v = v.tolist()
        elif isinstance(v, np.generic):
            v = v.item()
        out[k] = v
    for k in ("package_versions", "departures", "cpu_pins"):
        if isinstance(out.get(k), str):
            out[k] = json.loads(out[k])
    return out


def departures_of(ds: xr.Dataset) -> list[dict] | None:
    """The departure records stored with a result (``None`` if it predates them)."""
    raw = ds.attrs.get("departures")
    if raw is None:
        return None
    return json.loads(raw) if isinstance(raw, str) else list(raw)


def now() -> datetime:
    """Timezone-aware current time (UTC)."""
    return datetime.now(timezone.utc)
