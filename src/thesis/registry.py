"""Every experiment of the pipeline: registry key -> ``module:function``.

Keys are ``"<chapter>/<artifact>"`` and name the result file
``results/<profile>/<chapter>/<artifact>.nc``. Functions take a
:class:`thesis.runctx.RunContext` and return an ``xarray.Dataset`` (or ``None`` for
generators of inputs, which write ``ctx.output`` themselves). Modules are imported only
when their experiment runs, so a chapter's dependencies never slow another chapter.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

EXPERIMENTS: dict[str, str] = {
    # ch2: chirp-Z spatial transformer networks
    "ch2/cluttered_mnist": "thesis.chirpz.experiments:cluttered_mnist",
    "ch2/table2_2_ffn_spn": "thesis.chirpz.experiments:table2_2_ffn_spn",
    "ch2/table2_2_rnn_spn": "thesis.chirpz.experiments:table2_2_rnn_spn",
    "ch2/table2_2": "thesis.chirpz.experiments:table2_2",
    "ch2/chirpz_scaling": "thesis.chirpz.experiments:chirpz_scaling",
    # ch3: Oncilla gaits and turning
    "ch3/table3_1": "thesis.gaits.experiments:table3_1",
    "ch3/fig3_4": "thesis.gaits.experiments:fig3_4",
    "ch3/robustness": "thesis.gaits.experiments:robustness",
    "ch3/table3_2": "thesis.gaits.experiments:table3_2",
    "ch3/fig3_5": "thesis.gaits.experiments:fig3_5",
    # ch6: embodied gait (ELM + delay buffer + RLS) on the Oncilla
    "ch6/teacher": "thesis.embodied.experiments:teacher",
    "ch6/trot": "thesis.embodied.experiments:trot",
    "ch6/walk": "thesis.embodied.experiments:walk",
    "ch6/linear_feedback": "thesis.embodied.experiments:linear_feedback",
    "ch6/minimal_hidden": "thesis.embodied.experiments:minimal_hidden",
    "ch6/minimal_buffer": "thesis.embodied.experiments:minimal_buffer",
    "ch6/minimal_training": "thesis.embodied.experiments:minimal_training",
    "ch6/fig6_4": "thesis.embodied.experiments:fig6_4",
    "ch6/fig6_5": "thesis.embodied.experiments:fig6_5",
    "ch6/fig6_6": "thesis.embodied.experiments:fig6_6",
    # ch5: terrain classification on simulated Puppy II recordings
    "ch5/puppy_recordings": "thesis.terrain.data:puppy_recordings",
    "ch5/table5_3": "thesis.terrain.experiments:table5_3",
    "ch5/table5_4": "thesis.terrain.experiments:table5_4",
    "ch5/table5_5": "thesis.terrain.experiments:table5_5",
    "ch5/table5_6": "thesis.terrain.experiments:table5_6",
    "ch5/fig5_3": "thesis.terrain.experiments:fig5_3",
    # ch7: differentiable physics engine
    "ch7/ball": "thesis.diffphys.ball:ball",
    "ch7/arm_fixed": "thesis.diffphys.arm:arm_fixed",
    "ch7/arm_random": "thesis.diffphys.arm:arm_random",
    "ch7/quadruped_gait": "thesis.diffphys.gait:gait",
    "ch7/pendulum_pixels": "thesis.diffphys.pendulum:pendulum",
    "ch7/table7_1": "thesis.diffphys.bench_engine:table7_1",
    "ch7/table7_1_peers": "thesis.diffphys.bench_mjx:table7_1_peers",
}

#: ``thesis bench <name>`` -> registry key of the benchmark it runs.
BENCHMARKS: dict[str, str] = {
    "chirpz": "ch2/chirpz_scaling",
    "physics": "ch7/table7_1",
    "mjx": "ch7/table7_1_peers",
}


#: What every chapter 6 sweep reads, and each sweep's own section (thesis.embodied).
_CH6_RUN = ("ch6.seeds", "ch6.model", "ch6.control", "ch6.protocol", "ch6.criteria",
            "ch6.record")
_CH6_SWEEPS = {"trot": ("ch6.trot", "ch6.power_off"), "walk": ("ch6.walk",),
               "linear_feedback": (), "minimal_hidden": ("ch6.minimal_hidden",),
               "minimal_buffer": ("ch6.minimal_buffer",),
               "minimal_training": ("ch6.minimal_training",)}

#: Configuration each experiment reads, as dotted paths, where it is narrower than its
#: chapter's section (the default). Provenance records exactly these, Snakemake reruns
#: an experiment only when they change, and the experiment's ``ctx.config`` holds only
#: these keys of its chapter (reading an undeclared key fails instead of going stale).
#: The engine's experiments read no ``physics`` key: that section holds the Tab. 7.1
#: benchmark only.
READS: dict[str, tuple[str, ...]] = {
    "ch2/cluttered_mnist": ("ch2.data",),
    "ch2/table2_2_ffn_spn": ("ch2.seeds", "ch2.grid", "ch2.train", "ch2.chirpz_output",
                             "ch2.ffn_spn"),
    "ch2/table2_2_rnn_spn": ("ch2.seeds", "ch2.grid", "ch2.train", "ch2.chirpz_output",
                             "ch2.rnn_spn"),
    "ch2/table2_2": ("ch2.seeds", "ch2.train", "ch2.ffn_spn", "ch2.rnn_spn"),
    "ch2/chirpz_scaling": ("ch2.bench", "ch2.chirpz_output"),
    **{f"ch6/{name}": _CH6_RUN + extra for name, extra in _CH6_SWEEPS.items()},
    "ch6/teacher": ("ch6.model", "ch6.control", "ch6.protocol", "ch6.criteria",
                    "ch6.teacher", "ch6.walk"),
    "ch6/fig6_4": ("ch6.seeds",),
    "ch6/fig6_5": ("ch6.seeds",),
    "ch6/fig6_6": ("ch6.fig6_6",),
    "ch5/puppy_recordings": ("ch5.model", "ch5.recordings", "ch5.gaits", "ch5.terrains",
                             "ch5.jitter", "ch5.noise"),
    "ch7/ball": ("ch7.ball",),
    "ch7/arm_fixed": ("ch7.arm_fixed",),
    "ch7/arm_random": ("ch7.arm_random",),
    "ch7/quadruped_gait": ("ch7.gait",),
    "ch7/pendulum_pixels": ("ch7.pendulum",),
    "ch7/table7_1": ("physics.bench",),
    "ch7/table7_1_peers": ("physics.bench",),
}


def reads(key: str) -> tuple[str, ...]:
    """Dotted config paths experiment ``key`` (or a bare chapter/section name) reads.

    ``"ch7/ball"`` -> ``("ch7.ball",)``; an experiment without an entry in :data:`READS`
    reads its chapter's section (``"ch3/fig3_4"`` -> ``("ch3",)``); ``"ch2"`` -> ``("ch2",)``.
    """
    return READS.get(key, (key.split("/", 1)[0],))


def resolve(key: str) -> Callable:
    """Import and return the experiment function registered under ``key``."""
    if key not in EXPERIMENTS:
        known = ", ".join(sorted(EXPERIMENTS)) or "none yet"
        raise KeyError(f"unknown experiment {key!r}; registered: {known}")
    module, _, name = EXPERIMENTS[key].partition(":")
    return getattr(importlib.import_module(module), name)
