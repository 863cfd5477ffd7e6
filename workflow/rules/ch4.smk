# Chapter 4: transfer learning of Oncilla gaits with PSO (thesis.gaits.transfer_runs,
# thesis.gaits.transfer_artifacts).
#
# flat (PSO on flat ground from a random swarm, per seed) -> transfer_slopes,
# transfer_compliant and transfer_pebbly (each target condition twice per seed: the flat
# run's best particles transferred, and a random swarm; they run side by side) -> the cheap rules
# that derive the tables and figures of the chapter from those runs. tether re-runs the
# flat run's evaluations without the safety thread. Figures are drawn by
# report_figures_ch4 (report.smk).

CH4_GROUPS = {
    "slopes": "the 9 % and 18 % grades (§4.6.1)",
    "compliant": "softer front legs (§4.6.2)",
    "pebbly": "a floor covered in 1 cm pebbles (§4.6.3)",
}
# derived artifact -> the runs it reads (input name -> experiment of the producing rule)
CH4_DERIVED = {
    "table4_2": ["flat", "transfer_slopes"],
    "table4_3": ["flat", "transfer_compliant"],
    "table4_4": ["flat", "transfer_pebbly"],
    "fig4_3": ["flat"],
    "fig4_5": ["transfer_slopes"],
    "fig4_6": ["flat", "transfer_slopes"],
    "fig4_7": ["transfer_compliant"],
    "fig4_8": ["transfer_pebbly"],
    "fig4_9": ["transfer_slopes"],
    "fig4_10": [f"transfer_{g}" for g in CH4_GROUPS],
}


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


for _group, _what in CH4_GROUPS.items():

    rule:
        name:
            f"ch4_transfer_{_group}"
        message:
            f"PSO with and without transfer on {_what}, profile {PROFILE}"
        input:
            flat=rules.ch4_flat.output.nc,
        output:
            nc=result("ch4", f"transfer_{_group}"),
        params:
            cfg=cfg_slice(f"ch4/transfer_{_group}"),
            code=code_of("ch4"),
            key=f"ch4/transfer_{_group}",
        log:
            log_path("ch4", f"transfer_{_group}"),
        benchmark:
            bench_path("ch4", f"transfer_{_group}")
        threads: 2
        resources:
            **res("ch4", f"transfer_{_group}", mem_mb=4000, runtime=120),
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


for _name, _inputs in CH4_DERIVED.items():

    rule:
        name:
            f"ch4_{_name}"
        message:
            f"Chapter 4: {_name} from the PSO runs, profile {PROFILE}"
        input:
            **{k: result("ch4", k) for k in _inputs},
        output:
            nc=result("ch4", _name),
        params:
            cfg=cfg_slice(f"ch4/{_name}"),
            code=code_of("ch4"),
            key=f"ch4/{_name}",
            inputs=" ".join(f"--input {k}={result('ch4', k)}" for k in _inputs),
        log:
            log_path("ch4", _name),
        benchmark:
            bench_path("ch4", _name)
        threads: 1
        resources:
            **res("ch4", _name, mem_mb=2000, runtime=10),
        shell:
            "{THESIS} run {params.key} --profile {PROFILE} {params.inputs} "
            "--output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["ch4"] = [result("ch4", "flat"), result("ch4", "tether")] + [
    result("ch4", f"transfer_{g}") for g in CH4_GROUPS
] + [result("ch4", n) for n in CH4_DERIVED]
FIGURES["ch4"] = ["fig4_3", "fig4_5", "fig4_6", "fig4_7", "fig4_8", "fig4_9", "fig4_10",
                  "tether"]
TABLES["ch4"] = ["table4_2", "table4_3", "table4_4", "ranksum", "falls", "choices", "simulation_rate"]
