"""Command line: ``thesis run|bench|check|report`` (also ``python -m thesis``).

- ``thesis run ch2/table2_2 --profile smoke``: run one registered experiment and write
  its dataset (with provenance) to ``results/<profile>/<chapter>/<artifact>.nc``.
- ``thesis bench physics --profile smoke``: run a registered benchmark the same way.
- ``thesis validate oncilla --profile smoke``: the Oncilla model's validation on the
  thesis's published gaits (V1-V6), its convergence table and the knee spring's
  calibration to V1, into ``results/<profile>/model/validation.nc``, ``convergence.nc``
  and ``calibration.nc``, and V7, Tab. 4.4's pebble optima on the pebble field, into
  ``pebbles.nc``; ``--only fit`` (only when named) the fit of its unsourced values
  (``model/fit.nc``, :mod:`thesis.modelcheck.fit`); ``thesis validate puppy``: the Puppy
  II's recordings in dt and sweeps, into ``model/puppy_convergence.nc``.
- ``thesis check --profile smoke``: decide every claim from the profile's results and
  write ``results/<profile>/claims.json``, and the decision rules' power table beside it
  (``claims_power.json``).
- ``thesis report --profile smoke``: render ``reports/<profile>/index.html`` and
  ``summary.md``; ``--figures ch3`` renders only that chapter's figures.

Exit status: 0 done; 2 a configuration error or an unknown key (an experiment, a
config key, an input the experiment needs but was not given); 3 a simulation diverged
(nothing written); 4 (:data:`EXIT_DAMAGED`) a result or input file is damaged or
missing: ``run`` writes nothing, ``check`` and ``report`` first decide and render
everything that does not need it. Each error is one line on stderr naming the file, its
role and the command that remakes it.
"""

from __future__ import annotations

import argparse
import json
import logging
import signal
import sys
import time
from pathlib import Path

from thesis import departures, registry, store
from thesis.config import PROFILES, load_config, merge, parse_scalar
from thesis.errors import ConfigError, DamagedFileError, MissingInputError, SimulationDiverged
from thesis.runctx import RunContext

log = logging.getLogger("thesis")


def _kv(items: list[str] | None, what: str) -> dict[str, str]:
    out = {}
    for item in items or []:
        if "=" not in item:
            raise SystemExit(f"--{what} expects NAME=VALUE, got {item!r}")
        k, v = item.split("=", 1)
        out[k] = v
    return out


def _overrides(args) -> dict:
    """The overrides of a command: ``thesis --config-json '{...}'`` (the pipeline's nested
    ``snakemake --config`` values, passed on to every job), then each ``--set ch2.epochs=3``
    over it (values parsed by :func:`thesis.config.parse_scalar`)."""
    out: dict = {}
    if args.config_json:
        try:
            out = json.loads(args.config_json)
        except json.JSONDecodeError as e:
            raise SystemExit(f"--config-json is not JSON: {e}") from None
        if not isinstance(out, dict):
            raise SystemExit(f"--config-json must be a JSON object, got {args.config_json!r}")
    sets: dict = {}
    for k, v in _kv(args.set, "set").items():
        node = sets
        parts = k.split(".")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        node[parts[-1]] = parse_scalar(v)
    return merge(out, sets)


def config_slice(config: dict, key: str) -> dict:
    """The part of the configuration experiment ``key`` depends on (provenance, params).

    The root seed, the JAX settings and the subtrees :func:`thesis.registry.reads` names
    for ``key`` (an experiment key such as ``"ch7/ball"`` or a chapter such as ``"ch3"``),
    nested as in the configuration: ``{"root_seed", "jax", "ch7": {"ball": {...}}}``.
    """
    out = {"root_seed": config["root_seed"], "jax": config["jax"]}
    for path in registry.reads(key):
        parts = path.split(".")
        src, dst = config, out
        for p in parts[:-1]:
            src = src.get(p, {})
            dst = dst.setdefault(p, {})
        dst[parts[-1]] = src.get(parts[-1], {})
    return out


def run_experiment(key: str, profile: str, *, inputs: dict[str, str] | None = None,
                   output: str | Path | None = None, overrides: dict | None = None,
                   config_file: str | None = None, perturb: float = 0.0) -> Path:
    """Run registered experiment ``key`` and write its result atomically.

    ``perturb`` > 0 runs it as a perturbed twin (:mod:`thesis.physics.perturbation`: every
    rollout's initial state, chapter 2's initial weights, moved by that relative size);
    its default output is then under ``results/<profile>-perturbed/`` and the dataset
    records the size in ``perturbation_relative``.

    Returns:
        The path of the written result (or of the generated input file).

    Raises:
        SimulationDiverged: the experiment produced NaN; nothing is written.
        MissingInputError, DamagedFileError: an input is missing, damaged or holds
            another artifact (:func:`thesis.store.check_input`); checked before the
            experiment starts, so nothing is written.
    """
    config = load_config(profile, config_file, overrides)
    from thesis import jaxsetup

    jaxsetup.configure(config["jax"])
    from thesis.physics import perturbation

    chapter = key.split("/", 1)[0]
    fn = registry.resolve(key)
    name = store.results_name(profile, perturbed=perturb > 0)
    out = Path(output) if output else store.result_path(name, key)
    for input_name, path in (inputs or {}).items():
        store.check_input(key, input_name, path, runs=name, perturb=perturb or None)
    # the chapter's part of the declared slice: an undeclared key is a KeyError, not a
    # setting whose change Snakemake would miss (thesis.registry.READS)
    ctx = RunContext(key=key, profile=profile,
                     config=config_slice(config, key).get(chapter, {}),
                     full_config=config,
                     inputs={k: Path(v) for k, v in (inputs or {}).items()},
                     output=out, log=log)
    started = store.now()
    t0 = time.perf_counter()
    log.info("running %s (profile %s) -> %s", key, profile, out)
    with perturbation.scope(perturb):
        ds = fn(ctx)
    wall = time.perf_counter() - t0
    if ds is None:
        if not out.exists():
            raise RuntimeError(f"generator {key} returned without writing {out}")
        log.info("%s wrote %s in %.1f s", key, out, wall)
        return out
    if perturb:
        ds = ds.assign_attrs(perturbation_relative=float(perturb))
    store.write_dataset(ds, out, profile=profile, experiment=key,
                        config_slice=config_slice(config, key), started=started,
                        wall_seconds=wall, departures=departures.records(key, config))
    log.info("%s wrote %s in %.1f s", key, out, wall)
    return out


def _cmd_run(args) -> int:
    run_experiment(args.key, args.profile, inputs=_kv(args.input, "input"),
                   output=args.output, overrides=_overrides(args),
                   config_file=args.config_file, perturb=args.perturb)
    return 0


def _cmd_bench(args) -> int:
    if args.name not in registry.BENCHMARKS:
        known = ", ".join(sorted(registry.BENCHMARKS)) or "none yet"
        raise SystemExit(f"unknown benchmark {args.name!r}; available: {known}")
    run_experiment(registry.BENCHMARKS[args.name], args.profile, output=args.output,
                   overrides=_overrides(args), config_file=args.config_file,
                   perturb=args.perturb)
    return 0


def _cmd_validate(args) -> int:
    """``thesis validate oncilla``: the model's validation (V1-V6), its convergence
    table, calibration and pebble target (V7), written to ``results/<profile>/model/``
    (``--only`` one of them)."""
    if args.robot not in registry.VALIDATIONS:
        known = ", ".join(sorted(registry.VALIDATIONS))
        raise SystemExit(f"unknown robot {args.robot!r} to validate; available: {known}")
    keys = registry.VALIDATIONS[args.robot]
    if args.only:  # an optional check (the Oncilla's fit) runs only when named
        named = keys + registry.OPTIONAL_VALIDATIONS.get(args.robot, ())
        keys = tuple(k for k in named if k.endswith("/" + args.only))
        if not keys:
            raise SystemExit(f"--only {args.only!r}: not one of "
                             f"{', '.join(k.split('/')[1] for k in named)}")
    if args.output and len(keys) != 1:
        raise SystemExit("--output needs --only (one dataset per output path)")
    for key in keys:  # a twin run perturbs the model checks like every other job
        run_experiment(key, args.profile, output=args.output, overrides=_overrides(args),
                       config_file=args.config_file, perturb=args.perturb)
    return 0


#: Exit status of a command that met a damaged or missing result or input file (``thesis
#: check`` and ``thesis report`` still decide and render everything else first).
EXIT_DAMAGED = 4


def _cmd_check(args) -> int:
    from thesis.claims import evaluate_all

    load_config(args.profile, args.config_file, _overrides(args))  # a broken profile too
    # a damaged file is set aside (store.scan_results): the claims that need it are
    # not_run naming it, every other claim is decided as usual
    results, damaged = store.scan_results(args.profile, args.results)
    # the perturbed twin runs of some chapters, where they were made (thesis --perturb)
    twins, damaged_twins = store.scan_results(
        store.results_name(args.profile, perturbed=True), args.results)
    # and its native twin runs (every CPU pin lifted, snakemake --config isa=native)
    native, damaged_native = store.scan_results(
        store.results_name(args.profile, native=True), args.results)
    verdicts = evaluate_all(results, twin_runs=twins, native_runs=native,
                            unreadable={k: e.to_dict() for k, e in damaged.items()})
    out = Path(args.output or Path(args.results) / args.profile / "claims.json")
    counts: dict[str, int] = {}
    for v in verdicts:
        counts[v["reading"]] = counts.get(v["reading"], 0) + 1
    bad = [*damaged.values(), *damaged_twins.values(), *damaged_native.values()]
    payload = {"profile": args.profile, "n_results": len(results), "readings": counts,
               "twin_runs": sorted(twins), "native_runs": sorted(native),
               "damaged": [e.to_dict() for e in bad], "claims": verdicts}
    with store.atomic_path(out) as tmp:
        tmp.write_text(json.dumps(payload, indent=2, default=_json_default))
    log.info("claims: %s -> %s", counts, out)
    _write_power(out.with_name(POWER_FILE))
    if bad:
        undecided = sum(1 for v in verdicts if v.get("unreadable"))
        print(f"thesis: {_damaged_summary(bad)}; the {undecided} claim(s) that need it not "
              f"decided, the other {len(verdicts) - undecided} as usual -> {out}",
              file=sys.stderr)
        return EXIT_DAMAGED
    return 0


def _damaged_summary(bad: list[DamagedFileError]) -> str:
    """One line on damaged files: how many, then each one's path, cause and remaking
    command (the role is implied by the path)."""
    return (f"{len(bad)} damaged file(s): "
            + "; ".join(f"{e.path} ({e.cause}; remake: {e.remake})" for e in bad))


#: The decision rules' power table, written beside ``claims.json`` (read by the report).
POWER_FILE = "claims_power.json"


def _write_power(path: Path) -> None:
    """Write :func:`thesis.claims.calibration.power_table` (deterministic) to ``path``."""
    from thesis.claims import calibration

    with store.atomic_path(path) as tmp:
        tmp.write_text(json.dumps(calibration.power_table(), indent=2,
                                  default=_json_default))
    log.info("power of the decision rules -> %s", path)


def _json_default(o):
    import numpy as np

    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def _cmd_report(args) -> int:
    from thesis.report import render

    config = load_config(args.profile, args.config_file, _overrides(args))
    outdir = Path(args.outdir or Path("reports") / args.profile)
    # a damaged result is set aside: everything else is rendered, the page names it
    scanned = store.scan_results(args.profile, args.results)
    aside: dict = {}  # readable results lacking a variable the report reads
    if args.figures:
        render.render_figures(args.figures, args.profile, outdir, config=config,
                              results_root=Path(args.results), scanned=scanned,
                              set_aside=aside)
        bad = [e for k, e in scanned[1].items() if k.startswith(args.figures + "/")]
        done = f"the chapter's other figures rendered -> {outdir / 'figures' / args.figures}"
    else:
        index = render.render_report(args.profile, outdir, config=config,
                                     results_root=Path(args.results), scanned=scanned,
                                     set_aside=aside)
        bad = render.damaged_files(args.profile, Path(args.results), scanned[1])
        done = f"everything else rendered -> {index}"
    bad = bad + [e for e in aside.values() if e.path not in {b.path for b in bad}]
    if bad:
        print(f"thesis: {_damaged_summary(bad)}; {done}", file=sys.stderr)
        return EXIT_DAMAGED
    return 0


def _perturb_size(text: str) -> float:
    """``--perturb``'s value: a relative size from 0 to 1e-3."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0.0 <= value <= 1e-3:
        raise argparse.ArgumentTypeError(
            f"--perturb = {text!r} is not allowed; allowed values: 0 (off) to 1e-3 "
            "(rounding level: 1e-7)")
    return value


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="thesis", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("-v", "--verbose", action="store_true", help="debug logging")
    p.add_argument("--perturb", type=_perturb_size, default=0.0, metavar="REL",
                   help="run as a perturbed twin: initial states (and ch2's initial weights) "
                        "moved by this relative size, e.g. 1e-7 (about one float32 ulp); "
                        "results go to results/<profile>-perturbed/ (0: off)")
    p.add_argument("--config-json", default=None, metavar="JSON",
                   help="nested overrides merged over the profile, as a JSON object; the "
                        "pipeline passes snakemake's --config values on this way")
    sub = p.add_subparsers(dest="command", required=True)

    def common(sp):
        sp.add_argument("--profile", default="default", choices=PROFILES,
                        help="scale profile (config/<profile>.yaml)")
        sp.add_argument("--config-file", default=None,
                        help="read this YAML instead of config/<profile>.yaml")
        sp.add_argument("--set", action="append", metavar="KEY=VALUE",
                        help="override a config value, e.g. --set ch2.epochs=3")

    r = sub.add_parser("run", help="run one experiment and write its result")
    r.add_argument("key", help="registry key, e.g. ch2/table2_2")
    common(r)
    r.add_argument("--input", action="append", metavar="NAME=PATH", help="named input file")
    r.add_argument("--output", default=None, help="result path (default results/<profile>/...)")
    r.set_defaults(func=_cmd_run)

    b = sub.add_parser("bench", help="run a benchmark (physics, chirpz, ...)")
    b.add_argument("name")
    common(b)
    b.add_argument("--output", default=None)
    b.set_defaults(func=_cmd_bench)

    v = sub.add_parser("validate", help="validate a robot model on the thesis's published "
                                        "gaits (results/<profile>/model/)")
    v.add_argument("robot", help="oncilla or puppy")
    common(v)
    v.add_argument("--only", default=None, choices=("validation", "convergence", "calibration",
                                               "pebbles", "fit", "puppy_convergence"),
                   help="run only the validation, the convergence table, the "
                        "calibration, the pebble target or the fit of the unsourced values "
                        "(oncilla; the fit runs only when named), or the convergence table "
                        "(puppy)")
    v.add_argument("--output", default=None,
                   help="result path, with --only (default results/<profile>/model/<only>.nc)")
    v.set_defaults(func=_cmd_validate)

    c = sub.add_parser("check", help="decide every claim from a profile's results")
    common(c)
    c.add_argument("--results", default=str(store.RESULTS_DIR), help="results root")
    c.add_argument("--output", default=None, help="default results/<profile>/claims.json")
    c.set_defaults(func=_cmd_check)

    rep = sub.add_parser("report", help="render reports/<profile>/index.html")
    common(rep)
    rep.add_argument("--results", default=str(store.RESULTS_DIR), help="results root")
    rep.add_argument("--outdir", default=None, help="default reports/<profile>")
    rep.add_argument("--figures", default=None, metavar="CHAPTER",
                     help="only render this chapter's figures (e.g. ch3)")
    rep.set_defaults(func=_cmd_report)
    return p


def _terminate(signum, _frame):
    """SIGTERM (a scheduler's kill, ``scancel``, the end of a job's time limit) as an
    exception, so that an atomic write in progress removes its temporary file."""
    raise SystemExit(128 + signum)


def main(argv: list[str] | None = None) -> int:
    signal.signal(signal.SIGTERM, _terminate)
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=logging.DEBUG if args.verbose else logging.INFO,
                        format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    try:
        return args.func(args)
    except (ConfigError, KeyError) as e:
        print(f"thesis: {e.args[0] if isinstance(e, KeyError) else e}", file=sys.stderr)
        return 2
    except SimulationDiverged as e:
        print(f"thesis: {e}", file=sys.stderr)
        return 3
    except (DamagedFileError, MissingInputError) as e:
        print(f"thesis: {e}", file=sys.stderr)
        return EXIT_DAMAGED


if __name__ == "__main__":
    sys.exit(main())
