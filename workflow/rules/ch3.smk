# Chapter 3: Oncilla trotting and turning gaits (thesis.ch3.experiments).
#
# table3_1_part (PSO of the sine, half-ellipse and spline trots, one job per seed; parts/
# holds them) -> table3_1 (joined along `seed`) -> its optima feed fig3_4 (speed vs
# frequency), robustness (perturbed optima), table3_2 (the five turning strategies of
# §3.3.2) and fig3_5 (LED tracking), which run side by side.
#
# One job per seed: the PSO of a seed is the chapter's longest computation, and a seed
# involves no other (its swarm's stream and evaluations are its own), so the seeds run side
# by side on two cores or on a cluster's nodes (profiles/slurm), an interrupted run resumes
# at the seeds not yet done, and adding a seed reruns only that seed (a part's params leave
# `ch3.seeds` out; its seed is in its path).

CH3_SEEDS = [int(s) for s in config["ch3"]["seeds"]]


def ch3_part(seed):
    """results/<profile>/ch3/parts/table3_1_part_seed<seed>.nc (not a result of its own:
    the claims, report and regression read the joined table)."""
    return result("ch3", f"parts/table3_1_part_seed{seed}")


def ch3_part_cfg():
    """cfg_slice of a Tab. 3.1 part without the seed list (each job names its own seed)."""
    c = config_slice(config, "ch3/table3_1_part")
    c["ch3"].pop("seeds", None)
    return json.dumps(c, sort_keys=True)


rule ch3_table3_1_part:
    message:
        "PSO of the three trot families on the simulated Oncilla (Tab. 3.1), seed "
        "{wildcards.seed}, profile {PROFILE}"
    output:
        nc=ch3_part("{seed}"),
    wildcard_constraints:
        seed=r"\d+",
    params:
        cfg=ch3_part_cfg(),
        code=code_of("ch3"),
    log:
        log_path("ch3", "table3_1_part_seed{seed}"),
    benchmark:
        bench_path("ch3", "table3_1_part_seed{seed}")
    threads: 1
    resources:
        **res("ch3", "table3_1_part_seed{seed}", mem_mb=4000, runtime=120),
    shell:
        "{THESIS} run ch3/table3_1_part --profile {PROFILE} --set 'ch3.seeds=[{wildcards.seed}]' "
        "--output {output.nc} > {log} 2>&1"


rule ch3_table3_1:
    message:
        "Joining the seeds of Tab. 3.1, profile {PROFILE}"
    input:
        **{f"part_seed{s}": ch3_part(s) for s in CH3_SEEDS},
    output:
        nc=result("ch3", "table3_1"),
    params:
        cfg=cfg_slice("ch3"),
        code=code_of("ch3"),
        inputs=lambda wc, input: " ".join(f"--input {k}={v}" for k, v in input.items()),
    log:
        log_path("ch3", "table3_1"),
    benchmark:
        bench_path("ch3", "table3_1")
    threads: 1
    resources:
        **res("ch3", "table3_1", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run ch3/table3_1 --profile {PROFILE} {params.inputs} "
        "--output {output.nc} > {log} 2>&1"


rule ch3_fig3_4:
    message:
        "Oncilla: speed against gait frequency (Fig. 3.4), profile {PROFILE}"
    input:
        table3_1=rules.ch3_table3_1.output.nc,
    output:
        nc=result("ch3", "fig3_4"),
    params:
        cfg=cfg_slice("ch3"),
        code=code_of("ch3"),
        key="ch3/fig3_4",
    log:
        log_path("ch3", "fig3_4"),
    benchmark:
        bench_path("ch3", "fig3_4")
    threads: 1
    resources:
        **res("ch3", "fig3_4", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input table3_1={input.table3_1} --output {output.nc} > {log} 2>&1"


rule ch3_robustness:
    message:
        "Oncilla: perturbed optima (§3.3.1.1), profile {PROFILE}"
    input:
        table3_1=rules.ch3_table3_1.output.nc,
    output:
        nc=result("ch3", "robustness"),
    params:
        cfg=cfg_slice("ch3"),
        code=code_of("ch3"),
        key="ch3/robustness",
    log:
        log_path("ch3", "robustness"),
    benchmark:
        bench_path("ch3", "robustness")
    threads: 1
    resources:
        **res("ch3", "robustness", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input table3_1={input.table3_1} --output {output.nc} > {log} 2>&1"


rule ch3_table3_2:
    message:
        "Oncilla: the five turning strategies (Tab. 3.2), profile {PROFILE}"
    input:
        table3_1=rules.ch3_table3_1.output.nc,
    output:
        nc=result("ch3", "table3_2"),
    params:
        cfg=cfg_slice("ch3"),
        code=code_of("ch3"),
        key="ch3/table3_2",
    log:
        log_path("ch3", "table3_2"),
    benchmark:
        bench_path("ch3", "table3_2")
    threads: 1
    resources:
        **res("ch3", "table3_2", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input table3_1={input.table3_1} --output {output.nc} > {log} 2>&1"


rule ch3_fig3_5:
    message:
        "Oncilla: LED tracking by step size and scapulae (Fig. 3.5), profile {PROFILE}"
    input:
        table3_1=rules.ch3_table3_1.output.nc,
    output:
        nc=result("ch3", "fig3_5"),
    params:
        cfg=cfg_slice("ch3"),
        code=code_of("ch3"),
        key="ch3/fig3_5",
    log:
        log_path("ch3", "fig3_5"),
    benchmark:
        bench_path("ch3", "fig3_5")
    threads: 1
    resources:
        **res("ch3", "fig3_5", mem_mb=4000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input table3_1={input.table3_1} --output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["ch3"] = [
    rules.ch3_table3_1.output.nc,
    rules.ch3_fig3_4.output.nc,
    rules.ch3_robustness.output.nc,
    rules.ch3_table3_2.output.nc,
    rules.ch3_fig3_5.output.nc,
]
FIGURES["ch3"] = ["fig3_4", "fig3_5", "pso_convergence"]
TABLES["ch3"] = ["table3_1", "table3_2", "robustness"]
