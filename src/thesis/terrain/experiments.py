"""Registered experiments of chapter 5 (thesis.registry): recordings, Tab. 5.3-5.6, Fig. 5.3.

``ch5/puppy_recordings`` simulates the trials once per profile into
``data/synthetic/puppy/<profile>.h5``; every other experiment reads that file
(``--input recordings=...``) and the selection, tuning and verification protocol of
:mod:`thesis.terrain.protocol` and :mod:`thesis.terrain.tuning`:

* ``table5_3``: LR and RC on the 8 sensor groups (train and test accuracy), each tuned
  per seed and group; also the tuned hyper-parameters (read by ``fig5_3``);
* ``table5_4``: LR, leaky ELM and RC over hidden-node counts on touch and minimal;
* ``table5_5``: SFA2 and RC-SFA on the 8 groups;
* ``table5_6``: SFA2, ELM-SFA and RC-SFA over node counts, minimal, bound-right trials;
* ``fig5_3``: RC trained on bound right at 1 Hz, confusion matrices on the other
  frequencies (bound right) and on the other gaits (1 Hz).

Seeds: seed s draws its selections from stream ``"ch5/<artifact>/selection"``, its hidden
layers from ``"ch5/<artifact>/weights/<nodes>"``, its CMA-ES and FastICA seeds from
``"ch5/<artifact>/cma/..."`` (thesis.seeding), so artifacts never share random numbers.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.runctx import RunContext
from thesis.terrain import methods as M
from thesis.terrain import protocol as P
from thesis.terrain import recordings as REC
from thesis.terrain import sensors as S
from thesis.terrain import tuning as T

SELECTIONS = tuple(S.GROUPS)
SPLITS = ("train", "test")


# --------------------------------------------------------------------------- data
def puppy_recordings(ctx: RunContext) -> None:
    """Simulate the trials of Tab. 5.1 into ``ctx.output`` (HDF5, atomic)."""
    from thesis.store import atomic_path

    recs, info = REC.generate(ctx.config, ctx.root_seed, log=ctx.log, experiment=ctx.key)
    attrs = {"profile": ctx.profile, "root_seed": ctx.root_seed, "thesis_ref": "§5.3.1",
             "sample_rate": float(ctx.config["recordings"]["sample_rate"]),
             "config_json": json.dumps(ctx.config, sort_keys=True), **info}
    ctx.log.info("ch5/puppy_recordings: %d trials, %d samples, %.0f robot-s in %.0f s "
                 "(%.1f robot-s per wall-s)", recs.n_trials, len(recs.signals),
                 info["robot_seconds"], info["wall_seconds"],
                 info["robot_seconds_per_wall_second"])
    with atomic_path(ctx.output) as tmp:
        REC.write(tmp, recs, attrs)
    return None
