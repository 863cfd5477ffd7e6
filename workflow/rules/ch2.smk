# Chapter 2: chirp-Z spatial transformer networks on cluttered MNIST sequences.
#
# cluttered_mnist -> table2_2_{ffn_spn,rnn_spn} (one job per model, every d, transform
# and seed; the two halves run side by side) -> table2_2 (joined along `model`).
# chirpz_scaling is the §2.4 benchmark (also `thesis bench chirpz`).

from thesis.chirpz.data import training_memory_mb


rule ch2_cluttered_mnist:
    message:
        "Synthesising cluttered MNIST sequences (§2.5), profile {PROFILE}"
    output:
        data=data_path("cluttered_mnist", f"{PROFILE}.h5"),
    params:
        cfg=cfg_slice("ch2/cluttered_mnist"),
        code=code_of("ch2"),
    log:
        log_path("ch2", "cluttered_mnist"),
    benchmark:
        bench_path("ch2", "cluttered_mnist")
    threads: 1
    resources:
        mem_mb=8000,
        runtime=30,
    shell:
        "{THESIS} run ch2/cluttered_mnist --profile {PROFILE} --output {output.data} > {log} 2>&1"


for _model in ["ffn_spn", "rnn_spn"]:

    rule:
        name:
            f"ch2_table2_2_{_model}"
        message:
            f"Training {_model} for every cell of Tab. 2.2, profile {PROFILE}"
        input:
            data=rules.ch2_cluttered_mnist.output.data,
        output:
            nc=result("ch2", f"table2_2_{_model}"),
        params:
            cfg=cfg_slice(f"ch2/table2_2_{_model}"),
            code=code_of("ch2"),
            key=f"ch2/table2_2_{_model}",
        log:
            log_path("ch2", f"table2_2_{_model}"),
        benchmark:
            bench_path("ch2", f"table2_2_{_model}")
        threads: 1
        resources:
            mem_mb=training_memory_mb(config["ch2"]["data"]),
            runtime=600,
        shell:
            "{THESIS} run {params.key} --profile {PROFILE} "
            "--input data={input.data} --output {output.nc} > {log} 2>&1"


rule ch2_table2_2:
    message:
        "Joining the two halves of Tab. 2.2, profile {PROFILE}"
    input:
        ffn_spn=result("ch2", "table2_2_ffn_spn"),
        rnn_spn=result("ch2", "table2_2_rnn_spn"),
    output:
        nc=result("ch2", "table2_2"),
    params:
        cfg=cfg_slice("ch2/table2_2"),
        code=code_of("ch2"),
    log:
        log_path("ch2", "table2_2"),
    benchmark:
        bench_path("ch2", "table2_2")
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    shell:
        "{THESIS} run ch2/table2_2 --profile {PROFILE} --input ffn_spn={input.ffn_spn} "
        "--input rnn_spn={input.rnn_spn} --output {output.nc} > {log} 2>&1"


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
        mem_mb=4000,
        runtime=30,
    shell:
        "{THESIS} run ch2/chirpz_scaling --profile {PROFILE} --output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["ch2"] = [
    rules.ch2_table2_2.output.nc,
    rules.ch2_chirpz_scaling.output.nc,
]
FIGURES["ch2"] = ["training_curves", "chirpz_scaling"]
TABLES["ch2"] = ["table2_2"]
