"""Results as xarray datasets on disk: atomic writes, provenance, loading a profile.

Layout: ``results/<profile>/<chapter>/<artifact>.nc`` (netCDF4/HDF5 through the
h5netcdf engine). A file is written to a temporary name in the same directory and
renamed into place, so an interrupted job never leaves a result file behind.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import tempfile
from collections.abc import Iterator, Sequence
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from thesis import cpupins, provenance
from thesis.config import canonical_json, config_sha256
from thesis.errors import DamagedFileError, MissingInputError

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
    """Make an attribute storable by h5netcdf, which refuses ``None``, dicts and bools
    (xarray ``_validate_attrs``; h5netcdf README, "Invalid netCDF files")."""
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
    """All provenance attributes of one result (docs/architecture.md#results)."""
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
    """Load a result fully into memory and close the file (``xr.load_dataset``).

    No check of what the file holds: the pipeline reads results through
    :func:`open_result` (and experiments' inputs are checked by :func:`check_input`)."""
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


def scan_results(profile: str, root: str | Path = RESULTS_DIR
                 ) -> tuple[dict[str, xr.Dataset], dict[str, DamagedFileError]]:
    """(every readable result of a profile's runs, every damaged one), both keyed
    ``"<chapter>/<artifact>"`` (e.g. ``"ch3/table3_1"``).

    ``profile`` names the directory under ``root``: a profile (``default``) or its twin
    runs (``default-perturbed``, ``default-native``; :func:`results_name`). Each file is
    read through :func:`open_result`; a damaged one (unreadable, truncated, empty, of a
    foreign format, or holding another artifact's dataset) is set aside with its
    :class:`thesis.errors.DamagedFileError`, so that one bad file costs only the claims and
    tables that read it. Hidden and temporary files are ignored.
    """
    base = Path(root) / profile
    out: dict[str, xr.Dataset] = {}
    damaged: dict[str, DamagedFileError] = {}
    if not base.exists():
        return out, damaged
    files = [f for f in sorted(base.glob("*/*.nc")) if not f.name.startswith(".")]
    for f in files:
        key = f"{f.parent.name}/{f.stem}"
        try:
            out[key] = open_result(f, key, runs=profile)
        except DamagedFileError as err:
            damaged[key] = err
    if damaged and split_runs(profile)[1] == "perturbed":  # the twins' size, as read
        size = _twin_size(out)
        damaged = {k: DamagedFileError(e.path, e.role, e.cause, remake_command(
            result_path(profile, k), profile, size)) for k, e in damaged.items()}
    return out, damaged


def load_results(profile: str, root: str | Path = RESULTS_DIR) -> dict[str, xr.Dataset]:
    """Every result of a profile, keyed ``"<chapter>/<artifact>"`` (e.g. ``"ch2/table2_2"``).

    Hidden and temporary files are ignored; a profile with no results gives ``{}``.

    Raises:
        DamagedFileError: a result file is damaged (the first one, in path order; the
            message names it, its role and the command that remakes it). Use
            :func:`scan_results` to read every other result regardless.
    """
    out, damaged = scan_results(profile, root)
    if damaged:
        raise next(iter(damaged.values()))
    return out


# ------------------------------------------------------------------ damaged files
#
# Every result and every experiment input is opened here, so that an unreadable,
# truncated, empty or foreign file (a dataset of another artifact) ends in one line naming
# the path, its role, the cause and the Snakemake command that remakes it
# (:class:`thesis.errors.DamagedFileError`), never in a library's traceback.

#: Generated inputs (not results: HDF5 files their generator writes itself): registry key
#: -> (name under ``data/synthetic/``, as ``data_path(name)`` in
#: ``workflow/rules/common.smk``; the ``thesis_ref`` attribute the generator stamps).
GENERATED_INPUTS: dict[str, tuple[str, str]] = {
    "ch2/cluttered_mnist": ("cluttered_mnist", "§2.5"),
    "ch5/puppy_recordings": ("puppy", "§5.3.1"),
}
DATA_DIR = Path("data/synthetic")
#: Relative perturbation of the remaking command of a perturbed twin's file when no
#: intact twin result records its size (``perturbation_relative``): the README's twin size.
DEFAULT_TWIN_PERTURB = 1e-7


def split_runs(runs: str) -> tuple[str, str]:
    """(profile, twin kind) of a results directory name: ``"default"`` -> ``("default",
    "")``, ``"default-perturbed"`` -> ``("default", "perturbed")``, ``"default-native"``
    -> ``("default", "native")`` (the inverse of :func:`results_name`)."""
    for suffix, kind in ((PERTURBED_SUFFIX, "perturbed"), (NATIVE_SUFFIX, "native")):
        if runs.endswith(suffix):
            return runs.removesuffix(suffix), kind
    return runs, ""


def remake_command(target: str | Path, runs: str, perturb: float | None = None) -> str:
    """The command that remakes Snakemake target ``target`` (a path relative to the
    repository, e.g. ``results/default/ch3/table3_1.nc``) of the runs ``runs``
    (``default``, ``default-perturbed``, ``default-native``). ``--force``: a damaged file
    can be newer than its inputs, and Snakemake would otherwise take it as up to date.
    ``perturb``: a perturbed twin's size (default :data:`DEFAULT_TWIN_PERTURB`)."""
    profile, twin = split_runs(runs)
    extra = {"perturbed": f" perturb={perturb or DEFAULT_TWIN_PERTURB!r}",
             "native": " isa=native"}.get(twin, "")
    return (f"uv run snakemake {Path(target).as_posix()} --force "
            f"--config profile={profile}{extra} --cores 2")


def _twin_size(results: dict[str, xr.Dataset]) -> float | None:
    """A perturbed twin's relative size, from any result that records it."""
    for ds in results.values():
        if "perturbation_relative" in ds.attrs:
            return float(ds.attrs["perturbation_relative"])
    return None


def _area(key: str) -> str:
    """``"chapter 3"`` for ``ch3/...``, ``"§8.2"`` for ``coopt/...``; else the folder."""
    folder = key.split("/", 1)[0]
    if folder.startswith("ch") and folder[2:].isdigit():
        return f"chapter {folder[2:]}"
    return {"coopt": "§8.2"}.get(folder, folder)


def _begins(path: Path) -> str:
    """The first bytes of a file, for a message about its format."""
    with open(path, "rb") as fh:
        head = fh.read(24)
    return repr(head.decode("ascii", errors="replace")) if head.isascii() else repr(head)


def _cause(path: Path, err: BaseException) -> str:
    """What an exception raised while opening ``path`` says about the file, in words."""
    msg = " ".join(str(err).split())
    size = path.stat().st_size
    m = re.search(r"truncated file: eof = (\d+).*stored_eof = (\d+)", msg)
    if m:
        return f"truncated: {int(m[1]):,} of its {int(m[2]):,} bytes are on disk"
    if "file signature not found" in msg:
        return (f"not an HDF5/netCDF-4 file ({size:,} bytes beginning {_begins(path)})")
    return f"unreadable ({type(err).__name__}: {msg})"


def _damaged(path: Path, role: str, remake: str, cause: str | None = None,
             err: BaseException | None = None) -> DamagedFileError:
    return DamagedFileError(path, role, cause or _cause(path, err), remake)


def _result_role(key: str, runs: str) -> str:
    return f"result {key} of {_area(key)}, results/{runs}/"


def damaged_result(runs: str, key: str, cause: str, root: str | Path = RESULTS_DIR
                   ) -> DamagedFileError:
    """The :class:`DamagedFileError` of result ``key`` of the runs ``runs`` under ``root``
    for ``cause`` (e.g. a readable file that lacks a variable its readers need), with the
    role and remaking command :func:`open_result` names."""
    return DamagedFileError(result_path(runs, key, root), _result_role(key, runs), cause,
                            remake_command(result_path(runs, key), runs))


def open_result(path: str | Path, key: str, *, runs: str = "default",
                role: str | None = None, remake: str | None = None,
                perturb: float | None = None) -> xr.Dataset:
    """Load result ``key`` (``"ch3/table3_1"``) from ``path`` fully into memory, checking
    that the file is what it should be.

    Args:
        path: the ``.nc`` file.
        key: the registry key of the experiment whose result it must hold; a file whose
            ``experiment`` attribute names another, or none, is refused. ``None``: any
            result of ``thesis run``.
        runs: the results directory it belongs to (``default``, ``default-perturbed``,
            ...), for the remaking command.
        role: the file's role in messages (default: ``"result <key> of <chapter>,
            results/<runs>/"``).
        remake: the remaking command in messages (default: :func:`remake_command` of
            ``results/<runs>/<key>.nc``).
        perturb: a perturbed twin's size, for the remaking command.

    Raises:
        DamagedFileError: empty, truncated, unreadable or foreign (not HDF5/netCDF-4), or
            not a result of ``key`` (another or no ``experiment``, no ``thesis_ref``, no
            data variable; e.g. a generated HDF5 input); the one-line message names
            ``path``, its role, the cause and the command that remakes it.
    """
    path = Path(path)
    role = role or _result_role(key, runs)
    remake = remake or remake_command(result_path(runs, key), runs, perturb)
    if path.stat().st_size == 0:
        raise _damaged(path, role, remake, cause="empty (0 bytes)")
    try:
        # phony_dims: how h5netcdf names the dimensions of a plain HDF5 file (no netCDF
        # dimension scales), stated so that reading one (to refuse it) warns of nothing
        ds = xr.load_dataset(path, engine=ENGINE, phony_dims="access")
    except MemoryError:
        raise
    except Exception as err:  # noqa: BLE001 -- a damaged file can trip any of the readers
        raise _damaged(path, role, remake, err=err) from err
    problems = []
    got = ds.attrs.get("experiment")
    if got is None:  # every result thesis run writes names its experiment
        problems.append("attribute 'experiment' is missing (not a result of thesis run)")
    elif key is not None and str(got) != key:
        problems.append(f"it holds the result of {got} (its 'experiment' attribute), "
                        f"not of {key}")
    if not ds.attrs.get("thesis_ref"):
        problems.append("attribute 'thesis_ref' is missing")
    if not ds.data_vars:
        problems.append("no data variables")
    if problems:
        raise _damaged(path, role, remake, cause="wrong content: " + "; ".join(problems))
    return ds


def _check_generated(path: Path, key: str | None, role: str, remake: str) -> None:
    """Check that ``path`` is the HDF5 file generator ``key`` writes (readable, and its
    ``thesis_ref`` the one :data:`GENERATED_INPUTS` declares; ``key`` None: any readable
    HDF5 file that is no result); never loads its data."""
    import h5py

    if path.stat().st_size == 0:
        raise _damaged(path, role, remake, cause="empty (0 bytes)")
    try:
        with h5py.File(path, "r") as f:
            attrs = {k: f.attrs[k] for k in ("experiment", "thesis_ref") if k in f.attrs}
    except MemoryError:
        raise
    except Exception as err:  # noqa: BLE001
        raise _damaged(path, role, remake, err=err) from err
    if "experiment" in attrs:
        raise _damaged(path, role, remake, cause=(
            f"wrong content: it holds the result of {_text(attrs['experiment'])}, "
            f"not the generated input {key or 'it should be'}"))
    if key is None:
        return
    want = GENERATED_INPUTS[key][1]
    got = _text(attrs.get("thesis_ref", ""))
    if got != want:
        raise _damaged(path, role, remake, cause=(
            f"wrong content: its thesis_ref is {got!r}, not {want!r} as {key} writes"))


def _text(v: Any) -> str:
    return v.decode() if isinstance(v, bytes) else str(v)


def _producer_of_path(path: Path) -> tuple[str | None, str | None, str | None]:
    """(registry key, Snakemake target, runs) of a file in the pipeline's layout:
    ``.../results/<runs>/<ch>/<artifact>.nc``, ``.../results/<runs>/ch2/parts/
    <artifact>_<model>_seed<s>.nc`` or ``.../data/synthetic/<name>/<runs>.h5``; Nones
    elsewhere."""
    from thesis import registry

    parts = path.parts
    for i in range(len(parts) - 4, -1, -1):
        if parts[i] == "results" and path.suffix == ".nc":
            runs, rest = parts[i + 1], parts[i + 2:]
            key = f"{rest[0]}/{Path(*rest[1:]).with_suffix('').as_posix()}"
            if len(rest) == 3 and rest[1] == "parts":
                m = re.fullmatch(r"(.+)_seed\d+", Path(rest[2]).stem)
                key = f"{rest[0]}/{m[1]}" if m else key
            known = key in registry.EXPERIMENTS
            return (key if known else None), Path(*parts[i:]).as_posix(), runs
        if parts[i:i + 2] == ("data", "synthetic") and len(parts) == i + 4:
            gen = {name: k for k, (name, _) in GENERATED_INPUTS.items()}.get(parts[i + 2])
            return gen, Path(*parts[i:]).as_posix(), path.stem
    return None, None, None


def input_producer(key: str, name: str, runs: str) -> tuple[str | None, str | None]:
    """(registry key, Snakemake target) of what input ``name`` of experiment ``key`` must
    hold, as the rules pass it: the result of the same name in the chapter
    (``teacher`` of ``ch6/trot`` -> ``ch6/teacher``), a part of ``key`` by seed
    (``ffn_spn_seed0`` of ``ch2/table2_2`` -> ``ch2/table2_2_ffn_spn``), the one result of
    that name in another chapter (``table3_1`` of ``ch6/teacher``), or the chapter's
    generated input (``data`` of ``ch2/...``, ``recordings`` of ``ch5/...``).
    ``(None, None)`` when none fits."""
    from thesis import registry

    chapter, artifact = key.split("/", 1)
    if f"{chapter}/{name}" in registry.EXPERIMENTS and f"{chapter}/{name}" not in GENERATED_INPUTS:
        k = f"{chapter}/{name}"
        return k, result_path(runs, k).as_posix()
    m = re.fullmatch(r"(.+)_seed(\d+)", name)
    if m and f"{key}_{m[1]}" in registry.EXPERIMENTS:
        return (f"{key}_{m[1]}", result_path(
            runs, f"{chapter}/parts/{artifact}_{m[1]}_seed{m[2]}").as_posix())
    same = [k for k in registry.EXPERIMENTS
            if k.split("/", 1)[1] == name and k not in GENERATED_INPUTS]
    if len(same) == 1:
        return same[0], result_path(runs, same[0]).as_posix()
    gens = [k for k in GENERATED_INPUTS if k.startswith(chapter + "/")]
    if len(gens) == 1:
        return gens[0], (DATA_DIR / GENERATED_INPUTS[gens[0]][0] / f"{runs}.h5").as_posix()
    return None, None


def check_input(key: str, name: str, path: str | Path, *, runs: str = "default",
                perturb: float | None = None) -> None:
    """Check input ``name`` of experiment ``key`` before it runs (``thesis run ...
    --input name=path``), so that a damaged input ends in one line and nothing is written.

    A result input (``.nc``) is loaded through :func:`open_result` and must hold the
    result :func:`input_producer` names; a generated input (``.h5``) must open and carry
    its generator's ``thesis_ref``. The remaking command names the file's own Snakemake
    target when it lies in the pipeline's layout and holds what the input needs, else the
    target that makes what the input needs.

    Raises:
        MissingInputError: ``path`` does not exist.
        DamagedFileError: ``path`` is damaged or holds something else.
    """
    path = Path(path)
    role = f"input {name!r} of experiment {key}"
    want, want_target = input_producer(key, name, runs)
    own, own_target, own_runs = _producer_of_path(path)
    if want is None:
        want = own
    if own_target is not None and (own == want or want_target is None):
        target, target_runs = own_target, own_runs
    else:
        target, target_runs = want_target, runs
    if target is None:
        remake = (f"the Snakemake rule that passes --input {name}=... to "
                  f"{key} (workflow/rules/{key.split('/', 1)[0]}.smk)")
    else:
        remake = remake_command(target, target_runs, perturb)
    if not path.exists():
        raise MissingInputError(f"{path} ({role}) does not exist; make it with: {remake}")
    if want in GENERATED_INPUTS or (want is None and path.suffix == ".h5"):
        _check_generated(path, want, role, remake)
        return
    open_result(path, want, runs=target_runs, role=role, remake=remake)


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
