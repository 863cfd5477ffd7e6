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
    "ch2/cluttered_mnist": "thesis.ch2.experiments:cluttered_mnist",
    "ch2/table2_2_ffn_spn": "thesis.ch2.experiments:table2_2_ffn_spn",
    "ch2/table2_2_rnn_spn": "thesis.ch2.experiments:table2_2_rnn_spn",
    "ch2/table2_2": "thesis.ch2.experiments:table2_2",
    "ch2/chirpz_scaling": "thesis.ch2.experiments:chirpz_scaling",
    "ch2/train_step": "thesis.ch2.train_bench:train_step",
    "ch2/width_pilot": "thesis.ch2.width_pilot:width_pilot",
    # ch3: Oncilla gaits and turning
    "ch3/table3_1_part": "thesis.ch3.experiments:table3_1_part",
    "ch3/table3_1": "thesis.ch3.experiments:table3_1",
    "ch3/fig3_4": "thesis.ch3.experiments:fig3_4",
    "ch3/robustness": "thesis.ch3.experiments:robustness",
    "ch3/table3_2": "thesis.ch3.experiments:table3_2",
    "ch3/fig3_5": "thesis.ch3.experiments:fig3_5",
    # ch4: transfer learning of gaits with PSO
    "ch4/flat": "thesis.ch4.transfer_runs:flat",
    "ch4/transfer_slopes": "thesis.ch4.transfer_runs:transfer_slopes",
    "ch4/transfer_compliant": "thesis.ch4.transfer_runs:transfer_compliant",
    "ch4/transfer_pebbly": "thesis.ch4.transfer_runs:transfer_pebbly",
    "ch4/tether": "thesis.ch4.transfer_runs:tether",
    "ch4/table4_2": "thesis.ch4.transfer_artifacts:table4_2",
    "ch4/table4_3": "thesis.ch4.transfer_artifacts:table4_3",
    "ch4/table4_4": "thesis.ch4.transfer_artifacts:table4_4",
    "ch4/fig4_3": "thesis.ch4.transfer_artifacts:fig4_3",
    "ch4/fig4_5": "thesis.ch4.transfer_artifacts:fig4_5",
    "ch4/fig4_6": "thesis.ch4.transfer_artifacts:fig4_6",
    "ch4/fig4_7": "thesis.ch4.transfer_artifacts:fig4_7",
    "ch4/fig4_8": "thesis.ch4.transfer_artifacts:fig4_8",
    "ch4/fig4_9": "thesis.ch4.transfer_artifacts:fig4_9",
    "ch4/fig4_10": "thesis.ch4.transfer_artifacts:fig4_10",
    # ch6: embodied gait (ELM + delay buffer + RLS) on the Oncilla
    "ch6/teacher": "thesis.ch6.experiments:teacher",
    "ch6/trot": "thesis.ch6.experiments:trot",
    "ch6/walk": "thesis.ch6.experiments:walk",
    "ch6/linear_feedback": "thesis.ch6.experiments:linear_feedback",
    "ch6/minimal_hidden": "thesis.ch6.experiments:minimal_hidden",
    "ch6/minimal_buffer": "thesis.ch6.experiments:minimal_buffer",
    "ch6/minimal_training": "thesis.ch6.experiments:minimal_training",
    "ch6/fig6_4": "thesis.ch6.experiments:fig6_4",
    "ch6/fig6_5": "thesis.ch6.experiments:fig6_5",
    "ch6/fig6_6": "thesis.ch6.experiments:fig6_6",
    # ch5: terrain classification on simulated Puppy II recordings
    "ch5/puppy_recordings": "thesis.ch5.data:puppy_recordings",
    "ch5/table5_3": "thesis.ch5.experiments:table5_3",
    "ch5/table5_4": "thesis.ch5.experiments:table5_4",
    "ch5/table5_5": "thesis.ch5.experiments:table5_5",
    "ch5/table5_6": "thesis.ch5.experiments:table5_6",
    "ch5/fig5_3": "thesis.ch5.experiments:fig5_3",
    "ch5/separability": "thesis.ch5.separability:separability",
    "ch5/table5_3_blocks": "thesis.ch5.experiments:table5_3_blocks",
    "ch5/table5_3_parts": "thesis.ch5.experiments:table5_3_parts",
    # ch7: differentiable physics engine
    "ch7/ball": "thesis.ch7.ball:ball",
    "ch7/arm_fixed": "thesis.ch7.arm:arm_fixed",
    "ch7/arm_random": "thesis.ch7.arm:arm_random",
    "ch7/quadruped_gait": "thesis.ch7.gait:gait",
    "ch7/pendulum_pixels": "thesis.ch7.pendulum:pendulum",
    "ch7/table7_1": "thesis.ch7.bench_engine:table7_1",
    "ch7/table7_1_peers": "thesis.ch7.bench_mjx:table7_1_peers",
    # §8.2: controller and morphology co-optimised; analytic vs estimated gradients
    "coopt/arms": "thesis.coopt.experiments:arms",
    "coopt/gradients": "thesis.coopt.experiments:gradients",
    # the engine's own benchmarks (results/<profile>/physics/)
    "physics/sphere_field": "thesis.physics.bench:sphere_field",
    # model-level checks of the Oncilla (results/<profile>/model/)
    "model/oncilla": "thesis.modelcheck.bench:oncilla",
    "model/solver": "thesis.modelcheck.solver_bench:solver",
    "model/validation": "thesis.modelcheck.validation:validation",
    "model/convergence": "thesis.modelcheck.validation:convergence",
    "model/calibration": "thesis.modelcheck.calibration:calibration",
    "model/fit": "thesis.modelcheck.fit:fit",
    "model/pebbles": "thesis.modelcheck.pebbles:pebbles",
    "model/puppy_convergence": "thesis.modelcheck.puppy_convergence:convergence",
    "model/puppy_contact": "thesis.modelcheck.puppy_contact:puppy_contact",
    "model/puppy_heldout": "thesis.modelcheck.puppy_heldout:puppy_heldout",
}

#: ``thesis validate <robot>`` -> registry keys it runs (the Oncilla's validation,
#: convergence table, calibration and pebble target V7; the Puppy II's convergence table).
VALIDATIONS: dict[str, tuple[str, ...]] = {
    "oncilla": ("model/validation", "model/convergence", "model/calibration", "model/pebbles"),
    "puppy": ("model/puppy_convergence",),
}

#: ``thesis validate <robot> --only <name>`` -> further registry keys that run only when
#: named (the Oncilla's fit of its unsourced values: many rollouts, no claim reads it).
OPTIONAL_VALIDATIONS: dict[str, tuple[str, ...]] = {
    "oncilla": ("model/fit",),
}

#: ``thesis bench <name>`` -> registry key of the benchmark it runs.
BENCHMARKS: dict[str, str] = {
    "chirpz": "ch2/chirpz_scaling",
    "chirpz-train": "ch2/train_step",
    "chirpz-widths": "ch2/width_pilot",
    "physics": "ch7/table7_1",
    "mjx": "ch7/table7_1_peers",
    "field": "physics/sphere_field",
    "oncilla": "model/oncilla",
    "solver": "model/solver",
    "puppy-contact": "model/puppy_contact",
    "puppy-heldout": "model/puppy_heldout",
}

#: Measurements behind the configuration's sizes, made outside the default target
#: (``snakemake ch2_pilot``): no claim reads them, and the smoke regression leaves them
#: out, so that a checkout that made them still matches references made without them.
MEASUREMENTS: tuple[str, ...] = ("ch2/width_pilot", "ch2/train_step")


#: What every chapter 6 sweep reads, and each sweep's own section (thesis.ch6).
_CH6_RUN = ("ch6.seeds", "ch6.model", "ch6.control", "ch6.protocol", "ch6.criteria",
            "ch6.record", "ch6.perturbation")
_CH6_SWEEPS = {"trot": ("ch6.trot", "ch6.power_off"), "walk": ("ch6.walk",),
               "linear_feedback": (), "minimal_hidden": ("ch6.minimal_hidden",),
               "minimal_buffer": ("ch6.minimal_buffer",),
               "minimal_training": ("ch6.minimal_training",)}

#: Configuration each experiment reads, as dotted paths, where it is narrower than its
#: chapter's section (the default). Provenance records exactly these, Snakemake reruns
#: an experiment only when they change, and the experiment's ``ctx.config`` holds only
#: these keys of its chapter (reading an undeclared key fails instead of going stale).
#: The engine's experiments read no ``physics`` key: that section holds the engine's
#: benchmarks only (Tab. 7.1, the sphere field).
READS: dict[str, tuple[str, ...]] = {
    "ch2/cluttered_mnist": ("ch2.data",),
    "ch2/table2_2_ffn_spn": ("ch2.seeds", "ch2.grid", "ch2.train", "ch2.chirpz_output",
                             "ch2.ffn_spn"),
    "ch2/table2_2_rnn_spn": ("ch2.seeds", "ch2.grid", "ch2.train", "ch2.chirpz_output",
                             "ch2.rnn_spn"),
    "ch2/table2_2": ("ch2.seeds", "ch2.train", "ch2.ffn_spn", "ch2.rnn_spn"),
    "ch2/chirpz_scaling": ("ch2.bench", "ch2.chirpz_output"),
    "ch2/train_step": ("ch2.train_bench", "ch2.chirpz_output", "ch2.ffn_spn", "ch2.rnn_spn",
                       "ch2.train", "ch2.data.canvas", "ch2.data.n_digits"),
    "ch2/width_pilot": ("ch2.width_pilot", "ch2.train", "ch2.chirpz_output", "ch2.data.canvas",
                        "ch2.data.n_digits", "ch2.data.n_clutter", "ch2.data.clutter_size",
                        "ch2.data.max_slope_deg", "ch2.data.mnist_idx",
                        "ch2.data.idx_valid_pool", "ch2.data.embedded_test_fraction"),
    # ch4: a simulation reruns only when its protocol, swarm or condition changes, not
    # when a table or figure setting does
    "ch4/flat": ("ch4.seeds", "ch4.model", "ch4.tether", "ch4.protocol", "ch4.pso",
                 "ch4.reeval"),
    "ch4/transfer_slopes": ("ch4.seeds", "ch4.model", "ch4.tether", "ch4.protocol", "ch4.pso",
                            "ch4.reeval", "ch4.transfer", "ch4.conditions.grades"),
    "ch4/transfer_compliant": ("ch4.seeds", "ch4.model", "ch4.tether", "ch4.protocol",
                               "ch4.pso", "ch4.reeval", "ch4.transfer",
                               "ch4.conditions.front_spring_factor"),
    "ch4/transfer_pebbly": ("ch4.seeds", "ch4.model", "ch4.tether", "ch4.protocol", "ch4.pso",
                            "ch4.reeval", "ch4.transfer", "ch4.pebbles"),
    "ch4/tether": ("ch4.model", "ch4.tether", "ch4.protocol"),
    "ch4/table4_2": ("ch4.conditions.grades",),
    "ch4/table4_3": ("ch4.conditions.front_spring_factor",),
    "ch4/table4_4": ("ch4.pebbles",),
    "ch4/fig4_3": ("ch4.fig4_3",),
    "ch4/fig4_5": ("ch4.conditions.grades",),
    "ch4/fig4_6": ("ch4.conditions.grades", "ch4.fig4_6"),
    "ch4/fig4_7": (),
    "ch4/fig4_8": (),
    "ch4/fig4_9": ("ch4.conditions.grades",),
    "ch4/fig4_10": (),
    **{f"ch6/{name}": _CH6_RUN + extra for name, extra in _CH6_SWEEPS.items()},
    "ch6/teacher": ("ch6.model", "ch6.control", "ch6.protocol", "ch6.criteria",
                    "ch6.teacher", "ch6.walk", "ch6.perturbation"),
    "ch6/fig6_4": ("ch6.seeds",),
    "ch6/fig6_5": ("ch6.seeds",),
    "ch6/fig6_6": ("ch6.fig6_6",),
    "ch5/puppy_recordings": ("ch5.model", "ch5.recordings", "ch5.gaits", "ch5.terrains",
                             "ch5.jitter", "ch5.noise", "ch5.touch"),
    "ch7/ball": ("ch7.ball",),
    "ch7/arm_fixed": ("ch7.arm_fixed",),
    "ch7/arm_random": ("ch7.arm_random",),
    "ch7/quadruped_gait": ("ch7.gait",),
    "ch7/pendulum_pixels": ("ch7.pendulum",),
    "ch7/table7_1": ("physics.bench",),
    "ch7/table7_1_peers": ("physics.bench",),
    "coopt/arms": ("coopt.seeds", "coopt.hidden", "coopt.body", "coopt.trot", "coopt.arms"),
    "coopt/gradients": ("coopt.hidden", "coopt.body", "coopt.trot", "coopt.gradients"),
    "physics/sphere_field": ("physics.sphere_field",),
    "model/oncilla": ("physics.oncilla_model", "ch4.model", "ch4.protocol.settle",
                      "ch4.protocol.fall_height"),
    "model/solver": ("physics.solver_bench", "ch4.model", "ch4.protocol.settle",
                     "ch5.model", "ch5.gaits", "ch5.recordings.sample_rate"),
    "model/validation": ("physics.oncilla_validation", "ch4.model", "ch4.tether",
                         "ch4.protocol.settle", "ch4.protocol.fall_height"),
    "model/convergence": ("physics.oncilla_validation", "ch4.model", "ch4.tether",
                          "ch4.protocol.settle", "ch4.protocol.fall_height"),
    "model/puppy_convergence": ("physics.puppy_convergence", "ch5"),
    "model/puppy_contact": ("physics.puppy_contact", "ch5.model", "ch5.terrains", "ch5.gaits",
                            "ch5.recordings.sample_rate", "ch5.recordings.fallen_up"),
    "model/puppy_heldout": ("physics.puppy_heldout", "ch5.model", "ch5.recordings", "ch5.gaits",
                            "ch5.terrains", "ch5.jitter", "ch5.noise", "ch5.touch",
                            "ch5.protocol.part_target", "ch5.methods.nodes", "ch5.search"),
    "model/calibration": ("physics.oncilla_calibration", "physics.oncilla_validation",
                          "ch4.model", "ch4.tether", "ch4.protocol.settle",
                          "ch4.protocol.fall_height"),
    "model/fit": ("physics.oncilla_fit", "physics.oncilla_validation", "ch4.model",
                  "ch4.tether", "ch4.protocol.settle", "ch4.protocol.fall_height"),
    "model/pebbles": ("physics.oncilla_pebbles", "ch4.model", "ch4.tether", "ch4.protocol",
                      "ch4.pebbles", "ch4.reeval.heading_deg"),
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
