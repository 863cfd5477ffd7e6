"""The registered generator of chapter 5's input: ``ch5/puppy_recordings`` (§5.3.1).

Kept apart from the classifier experiments so that Snakemake regenerates the
recordings only when the simulation's code changes (its rule hashes this module,
:mod:`thesis.ch5.recordings`, ``gaits``, ``sensors`` and the engine).
"""

from __future__ import annotations

import json

from thesis.runctx import RunContext
from thesis.ch5 import recordings as REC


def puppy_recordings(ctx: RunContext) -> None:
    """Simulate the trials of Tab. 5.1 into ``ctx.output`` (HDF5, atomic)."""
    from thesis.store import atomic_path

    recs, info = REC.generate(ctx.config, ctx.root_seed, log=ctx.log, experiment=ctx.key)
    attrs = {"profile": ctx.profile, "root_seed": ctx.root_seed, "thesis_ref": "§5.3.1",
             "sample_rate": float(ctx.config["recordings"]["sample_rate"]),
             "config_json": json.dumps(ctx.config, sort_keys=True), **info}
    ctx.log.info("ch5/puppy_recordings: %d trials, %d samples, %.0f robot-s in %.0f s "
                 "(%.1f robot-s per wall-s); stopped when turned over: trials %s",
                 recs.n_trials, len(recs.signals), info["robot_seconds"],
                 info["wall_seconds"], info["robot_seconds_per_wall_second"],
                 info["stopped_trials"])
    with atomic_path(ctx.output) as tmp:
        REC.write(tmp, recs, attrs)
    return None
