# Chapter 5: terrain classification from simulated Puppy II recordings (thesis.ch5).
#
# ch5_puppy_recordings simulates the trials of Tab. 5.1 once per profile into
# data/synthetic/puppy/<profile>.h5; the four tables and the separability measurement
# read them side by side (one BLAS thread each); fig5_3 also reads table5_3's tuned
# reservoir hyper-parameters. The two selection-protocol variants of Tab. 5.3
# (table5_3_blocks, table5_3_parts) are the optional target ch5_variants: at default they
# would push ch5 past its 40-minute budget on 2 cores (README).

CH5_DATA_CODE = code_version(
    *CORE_CODE, "physics", "ch5/data.py", "ch5/recordings.py", "ch5/gaits.py",
    "ch5/sensors.py"
)


rule ch5_puppy_recordings:
    message:
        "Simulating the Puppy II trials of Tab. 5.1 on five terrains, profile {PROFILE}"
    output:
        data=data_path("puppy"),
    params:
        cfg=cfg_slice("ch5/puppy_recordings"),
        code=CH5_DATA_CODE,
    log:
        log_path("ch5", "puppy_recordings"),
    benchmark:
        bench_path("ch5", "puppy_recordings")
    threads: 2
    resources:
        **res("ch5", "puppy_recordings", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run ch5/puppy_recordings --profile {PROFILE} --output {output.data} "
        "> {log} 2>&1"


# priority: the two longest tables first, so that two cores stay busy to the end (with the
# longest started last, one core idles while it finishes alone)


rule ch5_table5_3:
    message:
        "Puppy II terrain classification: LR and RC on the 8 sensor groups (Tab. 5.3), "
        "profile {PROFILE}"
    input:
        recordings=rules.ch5_puppy_recordings.output.data,
    output:
        nc=result("ch5", "table5_3"),
    params:
        cfg=cfg_slice("ch5"),
        code=code_of("ch5"),
        key="ch5/table5_3",
    log:
        log_path("ch5", "table5_3"),
    benchmark:
        bench_path("ch5", "table5_3")
    threads: 1
    priority: 0
    resources:
        **res("ch5", "table5_3", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input recordings={input.recordings} --output {output.nc} > {log} 2>&1"


rule ch5_table5_4:
    message:
        "Puppy II terrain classification: LR, ELM and RC over hidden-node counts (Tab. 5.4), "
        "profile {PROFILE}"
    input:
        recordings=rules.ch5_puppy_recordings.output.data,
    output:
        nc=result("ch5", "table5_4"),
    params:
        cfg=cfg_slice("ch5"),
        code=code_of("ch5"),
        key="ch5/table5_4",
    log:
        log_path("ch5", "table5_4"),
    benchmark:
        bench_path("ch5", "table5_4")
    threads: 1
    priority: 1
    resources:
        **res("ch5", "table5_4", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input recordings={input.recordings} --output {output.nc} > {log} 2>&1"


rule ch5_table5_5:
    message:
        "Puppy II terrain classification: SFA2 and RC-SFA on the 8 sensor groups (Tab. 5.5), "
        "profile {PROFILE}"
    input:
        recordings=rules.ch5_puppy_recordings.output.data,
    output:
        nc=result("ch5", "table5_5"),
    params:
        cfg=cfg_slice("ch5"),
        code=code_of("ch5"),
        key="ch5/table5_5",
    log:
        log_path("ch5", "table5_5"),
    benchmark:
        bench_path("ch5", "table5_5")
    threads: 1
    priority: 2
    resources:
        **res("ch5", "table5_5", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input recordings={input.recordings} --output {output.nc} > {log} 2>&1"


rule ch5_table5_6:
    message:
        "Puppy II terrain classification: ELM-SFA and RC-SFA on bound-right trials (Tab. 5.6), "
        "profile {PROFILE}"
    input:
        recordings=rules.ch5_puppy_recordings.output.data,
    output:
        nc=result("ch5", "table5_6"),
    params:
        cfg=cfg_slice("ch5"),
        code=code_of("ch5"),
        key="ch5/table5_6",
    log:
        log_path("ch5", "table5_6"),
    benchmark:
        bench_path("ch5", "table5_6")
    threads: 1
    priority: 0
    resources:
        **res("ch5", "table5_6", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input recordings={input.recordings} --output {output.nc} > {log} 2>&1"


rule ch5_separability:
    message:
        "Puppy II terrain classification: leave-one-trial-out accuracy per gait and frequency, "
        "profile {PROFILE}"
    input:
        recordings=rules.ch5_puppy_recordings.output.data,
    output:
        nc=result("ch5", "separability"),
    params:
        cfg=cfg_slice("ch5"),
        code=code_of("ch5"),
        key="ch5/separability",
    log:
        log_path("ch5", "separability"),
    benchmark:
        bench_path("ch5", "separability")
    threads: 1
    priority: 0
    resources:
        **res("ch5", "separability", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input recordings={input.recordings} --output {output.nc} > {log} 2>&1"


rule ch5_table5_3_blocks:
    message:
        "Puppy II terrain classification: Tab. 5.3 with the previous block selections (variant), "
        "profile {PROFILE}"
    input:
        recordings=rules.ch5_puppy_recordings.output.data,
    output:
        nc=result("ch5", "table5_3_blocks"),
    params:
        cfg=cfg_slice("ch5"),
        code=code_of("ch5"),
        key="ch5/table5_3_blocks",
    log:
        log_path("ch5", "table5_3_blocks"),
    benchmark:
        bench_path("ch5", "table5_3_blocks")
    threads: 1
    priority: 0
    resources:
        **res("ch5", "table5_3_blocks", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input recordings={input.recordings} --output {output.nc} > {log} 2>&1"


rule ch5_table5_3_parts:
    message:
        "Puppy II terrain classification: Tab. 5.3 with selections of parts across trials "
        "(variant), "
        "profile {PROFILE}"
    input:
        recordings=rules.ch5_puppy_recordings.output.data,
    output:
        nc=result("ch5", "table5_3_parts"),
    params:
        cfg=cfg_slice("ch5"),
        code=code_of("ch5"),
        key="ch5/table5_3_parts",
    log:
        log_path("ch5", "table5_3_parts"),
    benchmark:
        bench_path("ch5", "table5_3_parts")
    threads: 1
    priority: 0
    resources:
        **res("ch5", "table5_3_parts", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input recordings={input.recordings} --output {output.nc} > {log} 2>&1"


rule ch5_fig5_3:
    message:
        "Puppy II: RC generalisation over gait frequencies and gaits (Fig. 5.3), profile {PROFILE}"
    input:
        recordings=rules.ch5_puppy_recordings.output.data,
        table5_3=rules.ch5_table5_3.output.nc,
    output:
        nc=result("ch5", "fig5_3"),
    params:
        cfg=cfg_slice("ch5"),
        code=code_of("ch5"),
    log:
        log_path("ch5", "fig5_3"),
    benchmark:
        bench_path("ch5", "fig5_3")
    threads: 1
    resources:
        **res("ch5", "fig5_3", mem_mb=4000, runtime=30),
    shell:
        "{THESIS} run ch5/fig5_3 --profile {PROFILE} --input recordings={input.recordings} "
        "--input table5_3={input.table5_3} --output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["ch5"] = [
    rules.ch5_table5_3.output.nc,
    rules.ch5_table5_4.output.nc,
    rules.ch5_table5_5.output.nc,
    rules.ch5_table5_6.output.nc,
    rules.ch5_fig5_3.output.nc,
    rules.ch5_separability.output.nc,
]
FIGURES["ch5"] = ["fig5_3"]
TABLES["ch5"] = [
    "table5_3",
    "table5_4",
    "table5_5",
    "table5_6",
    "table5_3_protocols",
    "generalisation",
    "separability",
]


if config["targets"]["ch5_variants"]:  # smoke: every rule runs, the variants regressed too
    CHAPTER_TARGETS["ch5"] += [rules.ch5_table5_3_blocks.output.nc,
                               rules.ch5_table5_3_parts.output.nc]


rule ch5_variants:
    input:
        rules.ch5_table5_3_blocks.output.nc,
        rules.ch5_table5_3_parts.output.nc,
