# Chapter 3: Oncilla trotting and turning gaits (thesis.gaits.experiments).
#
# table3_1 (PSO of the sine, half-ellipse and spline trots, per seed) -> its optima feed
# fig3_4 (speed vs frequency), robustness (perturbed optima), table3_2 (the five turning
# strategies of §3.3.2) and fig3_5 (LED tracking), which run side by side.


rule ch3_table3_1:
    message:
        "PSO of the three trot families on the simulated Oncilla (Tab. 3.1), profile {PROFILE}"
    output:
        nc=result("ch3", "table3_1"),
    params:
        cfg=cfg_slice("ch3"),
        code=code_of("ch3"),
    log:
        log_path("ch3", "table3_1"),
    benchmark:
        bench_path("ch3", "table3_1")
    threads: 2
    resources:
        **res("ch3", "table3_1", mem_mb=4000, runtime=120),
    shell:
        "{THESIS} run ch3/table3_1 --profile {PROFILE} --output {output.nc} > {log} 2>&1"


for _name, _what in [
    ("fig3_4", "speed against gait frequency (Fig. 3.4)"),
    ("robustness", "perturbed optima (§3.3.1.1)"),
    ("table3_2", "the five turning strategies (Tab. 3.2)"),
    ("fig3_5", "LED tracking by step size and scapulae (Fig. 3.5)"),
]:

    rule:
        name:
            f"ch3_{_name}"
        message:
            f"Oncilla: {_what}, profile {PROFILE}"
        input:
            table3_1=rules.ch3_table3_1.output.nc,
        output:
            nc=result("ch3", _name),
        params:
            cfg=cfg_slice("ch3"),
            code=code_of("ch3"),
            key=f"ch3/{_name}",
        log:
            log_path("ch3", _name),
        benchmark:
            bench_path("ch3", _name)
        threads: 1
        resources:
            **res("ch3", _name, mem_mb=4000, runtime=60),
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
