# Chapter 4: transfer learning of Oncilla gaits with PSO (thesis.ch4.transfer_runs,
# thesis.ch4.transfer_artifacts).
#
# flat (PSO on flat ground from a random swarm, per seed) -> transfer_slopes,
# transfer_compliant and transfer_pebbly (each target condition twice per seed: the flat
# run's best particles transferred, and a random swarm; they run side by side) -> the cheap rules
# that derive the tables and figures of the chapter from those runs. tether re-runs the
# flat run's evaluations without the safety thread. Figures are drawn by
# report_figures_ch4 (report.smk).


def ch4_inputs(*runs):
    """The ``--input <run>=<path>`` arguments of a rule that derives a table or figure
    from the PSO runs ``runs`` (experiments of this chapter, e.g. "flat")."""
    return " ".join(f"--input {k}={result('ch4', k)}" for k in runs)


rule ch4_flat:
    message:
        "PSO of the spline trot on flat ground, every seed (§4.6.1 source run), profile {PROFILE}"
    output:
        nc=result("ch4", "flat"),
    params:
        cfg=cfg_slice("ch4/flat"),
        code=code_of("ch4"),
    log:
        log_path("ch4", "flat"),
    benchmark:
        bench_path("ch4", "flat")
    threads: 2
    resources:
        **res("ch4", "flat", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run ch4/flat --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule ch4_transfer_slopes:
    message:
        "PSO with and without transfer on the 9 % and 18 % grades (§4.6.1), profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
    output:
        nc=result("ch4", "transfer_slopes"),
    params:
        cfg=cfg_slice("ch4/transfer_slopes"),
        code=code_of("ch4"),
        key="ch4/transfer_slopes",
    log:
        log_path("ch4", "transfer_slopes"),
    benchmark:
        bench_path("ch4", "transfer_slopes")
    threads: 2
    resources:
        **res("ch4", "transfer_slopes", mem_mb=4000, runtime=120),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --input flat={input.flat} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_transfer_compliant:
    message:
        "PSO with and without transfer on softer front legs (§4.6.2), profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
    output:
        nc=result("ch4", "transfer_compliant"),
    params:
        cfg=cfg_slice("ch4/transfer_compliant"),
        code=code_of("ch4"),
        key="ch4/transfer_compliant",
    log:
        log_path("ch4", "transfer_compliant"),
    benchmark:
        bench_path("ch4", "transfer_compliant")
    threads: 2
    resources:
        **res("ch4", "transfer_compliant", mem_mb=4000, runtime=120),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --input flat={input.flat} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_transfer_pebbly:
    message:
        "PSO with and without transfer on a floor covered in 1 cm pebbles (§4.6.3), "
        "profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
    output:
        nc=result("ch4", "transfer_pebbly"),
    params:
        cfg=cfg_slice("ch4/transfer_pebbly"),
        code=code_of("ch4"),
        key="ch4/transfer_pebbly",
    log:
        log_path("ch4", "transfer_pebbly"),
    benchmark:
        bench_path("ch4", "transfer_pebbly")
    threads: 2
    resources:
        **res("ch4", "transfer_pebbly", mem_mb=4000, runtime=120),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --input flat={input.flat} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_tether:
    message:
        "The flat run's evaluations again without the safety thread (§4.5), profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
    output:
        nc=result("ch4", "tether"),
    params:
        cfg=cfg_slice("ch4/tether"),
        code=code_of("ch4"),
    log:
        log_path("ch4", "tether"),
    benchmark:
        bench_path("ch4", "tether")
    threads: 2
    resources:
        **res("ch4", "tether", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run ch4/tether --profile {PROFILE} --input flat={input.flat} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_table4_2:
    message:
        "Chapter 4: table4_2 from the PSO runs, profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
        transfer_slopes=rules.ch4_transfer_slopes.output.nc,
    output:
        nc=result("ch4", "table4_2"),
    params:
        cfg=cfg_slice("ch4/table4_2"),
        code=code_of("ch4"),
        key="ch4/table4_2",
        inputs=ch4_inputs("flat", "transfer_slopes"),
    log:
        log_path("ch4", "table4_2"),
    benchmark:
        bench_path("ch4", "table4_2")
    threads: 1
    resources:
        **res("ch4", "table4_2", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_table4_3:
    message:
        "Chapter 4: table4_3 from the PSO runs, profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
        transfer_compliant=rules.ch4_transfer_compliant.output.nc,
    output:
        nc=result("ch4", "table4_3"),
    params:
        cfg=cfg_slice("ch4/table4_3"),
        code=code_of("ch4"),
        key="ch4/table4_3",
        inputs=ch4_inputs("flat", "transfer_compliant"),
    log:
        log_path("ch4", "table4_3"),
    benchmark:
        bench_path("ch4", "table4_3")
    threads: 1
    resources:
        **res("ch4", "table4_3", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_table4_4:
    message:
        "Chapter 4: table4_4 from the PSO runs, profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
        transfer_pebbly=rules.ch4_transfer_pebbly.output.nc,
    output:
        nc=result("ch4", "table4_4"),
    params:
        cfg=cfg_slice("ch4/table4_4"),
        code=code_of("ch4"),
        key="ch4/table4_4",
        inputs=ch4_inputs("flat", "transfer_pebbly"),
    log:
        log_path("ch4", "table4_4"),
    benchmark:
        bench_path("ch4", "table4_4")
    threads: 1
    resources:
        **res("ch4", "table4_4", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_fig4_3:
    message:
        "Chapter 4: fig4_3 from the PSO runs, profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
    output:
        nc=result("ch4", "fig4_3"),
    params:
        cfg=cfg_slice("ch4/fig4_3"),
        code=code_of("ch4"),
        key="ch4/fig4_3",
        inputs=ch4_inputs("flat"),
    log:
        log_path("ch4", "fig4_3"),
    benchmark:
        bench_path("ch4", "fig4_3")
    threads: 1
    resources:
        **res("ch4", "fig4_3", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_fig4_5:
    message:
        "Chapter 4: fig4_5 from the PSO runs, profile {PROFILE}"
    input:
        transfer_slopes=rules.ch4_transfer_slopes.output.nc,
    output:
        nc=result("ch4", "fig4_5"),
    params:
        cfg=cfg_slice("ch4/fig4_5"),
        code=code_of("ch4"),
        key="ch4/fig4_5",
        inputs=ch4_inputs("transfer_slopes"),
    log:
        log_path("ch4", "fig4_5"),
    benchmark:
        bench_path("ch4", "fig4_5")
    threads: 1
    resources:
        **res("ch4", "fig4_5", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_fig4_6:
    message:
        "Chapter 4: fig4_6 from the PSO runs, profile {PROFILE}"
    input:
        flat=rules.ch4_flat.output.nc,
        transfer_slopes=rules.ch4_transfer_slopes.output.nc,
    output:
        nc=result("ch4", "fig4_6"),
    params:
        cfg=cfg_slice("ch4/fig4_6"),
        code=code_of("ch4"),
        key="ch4/fig4_6",
        inputs=ch4_inputs("flat", "transfer_slopes"),
    log:
        log_path("ch4", "fig4_6"),
    benchmark:
        bench_path("ch4", "fig4_6")
    threads: 1
    resources:
        **res("ch4", "fig4_6", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_fig4_7:
    message:
        "Chapter 4: fig4_7 from the PSO runs, profile {PROFILE}"
    input:
        transfer_compliant=rules.ch4_transfer_compliant.output.nc,
    output:
        nc=result("ch4", "fig4_7"),
    params:
        cfg=cfg_slice("ch4/fig4_7"),
        code=code_of("ch4"),
        key="ch4/fig4_7",
        inputs=ch4_inputs("transfer_compliant"),
    log:
        log_path("ch4", "fig4_7"),
    benchmark:
        bench_path("ch4", "fig4_7")
    threads: 1
    resources:
        **res("ch4", "fig4_7", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_fig4_8:
    message:
        "Chapter 4: fig4_8 from the PSO runs, profile {PROFILE}"
    input:
        transfer_pebbly=rules.ch4_transfer_pebbly.output.nc,
    output:
        nc=result("ch4", "fig4_8"),
    params:
        cfg=cfg_slice("ch4/fig4_8"),
        code=code_of("ch4"),
        key="ch4/fig4_8",
        inputs=ch4_inputs("transfer_pebbly"),
    log:
        log_path("ch4", "fig4_8"),
    benchmark:
        bench_path("ch4", "fig4_8")
    threads: 1
    resources:
        **res("ch4", "fig4_8", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_fig4_9:
    message:
        "Chapter 4: fig4_9 from the PSO runs, profile {PROFILE}"
    input:
        transfer_slopes=rules.ch4_transfer_slopes.output.nc,
    output:
        nc=result("ch4", "fig4_9"),
    params:
        cfg=cfg_slice("ch4/fig4_9"),
        code=code_of("ch4"),
        key="ch4/fig4_9",
        inputs=ch4_inputs("transfer_slopes"),
    log:
        log_path("ch4", "fig4_9"),
    benchmark:
        bench_path("ch4", "fig4_9")
    threads: 1
    resources:
        **res("ch4", "fig4_9", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch4_fig4_10:
    message:
        "Chapter 4: fig4_10 from the PSO runs, profile {PROFILE}"
    input:
        transfer_slopes=rules.ch4_transfer_slopes.output.nc,
        transfer_compliant=rules.ch4_transfer_compliant.output.nc,
        transfer_pebbly=rules.ch4_transfer_pebbly.output.nc,
    output:
        nc=result("ch4", "fig4_10"),
    params:
        cfg=cfg_slice("ch4/fig4_10"),
        code=code_of("ch4"),
        key="ch4/fig4_10",
        inputs=ch4_inputs("transfer_slopes", "transfer_compliant", "transfer_pebbly"),
    log:
        log_path("ch4", "fig4_10"),
    benchmark:
        bench_path("ch4", "fig4_10")
    threads: 1
    resources:
        **res("ch4", "fig4_10", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["ch4"] = [
    rules.ch4_flat.output.nc,
    rules.ch4_tether.output.nc,
    rules.ch4_transfer_slopes.output.nc,
    rules.ch4_transfer_compliant.output.nc,
    rules.ch4_transfer_pebbly.output.nc,
    rules.ch4_table4_2.output.nc,
    rules.ch4_table4_3.output.nc,
    rules.ch4_table4_4.output.nc,
    rules.ch4_fig4_3.output.nc,
    rules.ch4_fig4_5.output.nc,
    rules.ch4_fig4_6.output.nc,
    rules.ch4_fig4_7.output.nc,
    rules.ch4_fig4_8.output.nc,
    rules.ch4_fig4_9.output.nc,
    rules.ch4_fig4_10.output.nc,
]
FIGURES["ch4"] = ["fig4_3", "fig4_5", "fig4_6", "fig4_7", "fig4_8", "fig4_9", "fig4_10",
                  "tether"]
TABLES["ch4"] = ["table4_2", "table4_3", "table4_4", "ranksum", "falls", "choices", "simulation_rate"]
