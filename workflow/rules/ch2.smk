# Chapter 2: chirp-Z spatial transformer networks on cluttered MNIST sequences.
#
# cluttered_mnist -> table2_2_{ffn_spn,rnn_spn} (one job per model and seed, every d and
# transform; parts/ holds them) -> table2_2 (joined along `seed` and `model`).
# chirpz_scaling is the §2.4 benchmark (also `thesis bench chirpz`).
#
# One job per model and seed, each training every d and transform of its model (10 cells;
# "none" is trained once and stored under every d, so a finer split per d would have to
# hand it over between jobs): the six default-profile jobs pack onto two cores (the
# RNN-SPN jobs first, `priority`) instead of one FFN-SPN and one RNN-SPN job that end far
# apart, spread over a cluster's nodes (profiles/slurm), and adding a seed reruns only that
# seed (a part's params leave `ch2.seeds` out; its seed is in its path). The default
# profile's updates per model are chosen so that its FFN-SPN and RNN-SPN jobs take about the
# same time, three per core (per-update cost: ch2_train_step below; the jobs' own times:
# benchmarks/<profile>/ch2/, reports/<profile>/measurements.md).

from thesis.ch2.data import training_memory_mb
from thesis.ch2.experiments import MODELS as CH2_MODELS

CH2_SEEDS = [int(s) for s in config["ch2"]["seeds"]]


def ch2_part(model, seed):
    """results/<profile>/ch2/parts/table2_2_<model>_seed<seed>.nc (not a result of its own:
    the claims, report and regression read the joined table)."""
    return result("ch2", f"parts/table2_2_{model}_seed{seed}")


def ch2_part_cfg(model):
    """cfg_slice of a model part without the seed list (each job names its own seed)."""
    c = config_slice(config, f"ch2/table2_2_{model}")
    c["ch2"].pop("seeds", None)
    return json.dumps(c, sort_keys=True)


rule ch2_cluttered_mnist:
    message:
        "Synthesising cluttered MNIST sequences (§2.5), profile {PROFILE}"
    output:
        data=data_path("cluttered_mnist"),
    params:
        cfg=cfg_slice("ch2/cluttered_mnist"),
        code=code_of("ch2"),
    log:
        log_path("ch2", "cluttered_mnist"),
    benchmark:
        bench_path("ch2", "cluttered_mnist")
    threads: 1
    resources:
        # upper estimate (profiles never measured here, e.g. paper): one block of float32
        # canvases at a time (what a run took: benchmarks/<profile>/ch2/cluttered_mnist.tsv)
        **res("ch2", "cluttered_mnist", mem_mb=2000, runtime=15),
    shell:
        "{THESIS} run ch2/cluttered_mnist --profile {PROFILE} --output {output.data} > {log} 2>&1"


rule ch2_table2_2_ffn_spn:
    message:
        "Training ffn_spn for every d and transform of Tab. 2.2, seed {wildcards.seed}, "
        "profile {PROFILE}"
    input:
        data=rules.ch2_cluttered_mnist.output.data,
    output:
        nc=ch2_part("ffn_spn", "{seed}"),
    wildcard_constraints:
        seed=r"\d+",
    params:
        cfg=ch2_part_cfg("ffn_spn"),
        code=code_of("ch2"),
        key="ch2/table2_2_ffn_spn",
    log:
        log_path("ch2", "table2_2_ffn_spn_seed{seed}"),
    benchmark:
        bench_path("ch2", "table2_2_ffn_spn_seed{seed}")
    threads: 1
    resources:
        **res(
            "ch2",
            "table2_2_ffn_spn_seed{seed}",
            mem_mb=training_memory_mb(config["ch2"]["data"]),
            runtime=600,
            gpu=True,
        ),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --set 'ch2.seeds=[{wildcards.seed}]' "
        "--input data={input.data} --output {output.nc} > {log} 2>&1"


rule ch2_table2_2_rnn_spn:
    message:
        "Training rnn_spn for every d and transform of Tab. 2.2, seed {wildcards.seed}, "
        "profile {PROFILE}"
    input:
        data=rules.ch2_cluttered_mnist.output.data,
    output:
        nc=ch2_part("rnn_spn", "{seed}"),
    wildcard_constraints:
        seed=r"\d+",
    params:
        cfg=ch2_part_cfg("rnn_spn"),
        code=code_of("ch2"),
        key="ch2/table2_2_rnn_spn",
    log:
        log_path("ch2", "table2_2_rnn_spn_seed{seed}"),
    benchmark:
        bench_path("ch2", "table2_2_rnn_spn_seed{seed}")
    # RNN-SPN's jobs are the longer ones (benchmarks/<profile>/ch2/): started first, the
    # jobs end together
    priority: 1
    threads: 1
    resources:
        **res(
            "ch2",
            "table2_2_rnn_spn_seed{seed}",
            mem_mb=training_memory_mb(config["ch2"]["data"]),
            runtime=600,
            gpu=True,
        ),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --set 'ch2.seeds=[{wildcards.seed}]' "
        "--input data={input.data} --output {output.nc} > {log} 2>&1"


rule ch2_table2_2:
    message:
        "Joining the parts of Tab. 2.2 (every model and seed), profile {PROFILE}"
    input:
        **{f"{m}_seed{s}": ch2_part(m, s) for m in CH2_MODELS for s in CH2_SEEDS},
    output:
        nc=result("ch2", "table2_2"),
    params:
        cfg=cfg_slice("ch2/table2_2"),
        code=code_of("ch2"),
        inputs=lambda wc, input: " ".join(f"--input {k}={v}" for k, v in input.items()),
    log:
        log_path("ch2", "table2_2"),
    benchmark:
        bench_path("ch2", "table2_2")
    threads: 1
    resources:
        **res("ch2", "table2_2", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run ch2/table2_2 --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch2_chirpz_scaling:
    message:
        "Timing the chirp-Z layer against the bilinear sampler (§2.4), profile {PROFILE}"
    output:
        nc=result("ch2", "chirpz_scaling"),
    params:
        cfg=cfg_slice("ch2/chirpz_scaling"),
        code=code_of("ch2"),
    log:
        log_path("ch2", "chirpz_scaling"),
    benchmark:
        bench_path("ch2", "chirpz_scaling")
    threads: 2
    resources:
        **res("ch2", "chirpz_scaling", mem_mb=4000, runtime=30, gpu=True),
    shell:
        "{THESIS} run ch2/chirpz_scaling --profile {PROFILE} --output {output.nc} > {log} 2>&1"


# The measurements behind the ch2 sizes of config/<profile>.yaml (outside the chapter
# target and `make all`: they time training, minutes to hours): the width pilot (error
# against CPU time at several widths and run lengths) and the cost of one training step
# per model, transform and d. The report renders both when present (thesis.report.pilots).


rule ch2_width_pilot:
    message:
        "Width pilot (§2.5): per-digit error against CPU time of one Tab. 2.2 cell at "
        "several widths and run lengths (ch2.width_pilot), profile {PROFILE}"
    output:
        nc=result("ch2", "width_pilot"),
    params:
        cfg=cfg_slice("ch2/width_pilot"),
        code=code_of("ch2"),
    log:
        log_path("ch2", "width_pilot"),
    benchmark:
        bench_path("ch2", "width_pilot")
    threads: 1
    resources:
        **res("ch2", "width_pilot", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} bench chirpz-widths --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule ch2_train_step:
    message:
        "Training-step bench (§2.5): forward, backward and update of every Tab. 2.2 "
        "cell (ch2.train_bench), profile {PROFILE}"
    output:
        nc=result("ch2", "train_step"),
    params:
        cfg=cfg_slice("ch2/train_step"),
        code=code_of("ch2"),
    log:
        log_path("ch2", "train_step"),
    benchmark:
        bench_path("ch2", "train_step")
    threads: 1
    resources:
        **res("ch2", "train_step", mem_mb=6000, runtime=30, gpu=True),
    shell:
        "{THESIS} bench chirpz-train --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule ch2_pilot:
    input:
        rules.ch2_width_pilot.output.nc,
        rules.ch2_train_step.output.nc,


CHAPTER_TARGETS["ch2"] = [
    rules.ch2_table2_2.output.nc,
    rules.ch2_chirpz_scaling.output.nc,
]
FIGURES["ch2"] = ["training_curves", "chirpz_scaling"]
TABLES["ch2"] = ["table2_2", "width_pilot", "train_step"]
