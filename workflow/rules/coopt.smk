# §8.2 made real (thesis.coopt): the chapter-7 quadruped's controller and body co-optimised
# by gradient through the engine (coopt/arms), and the engine's gradients beside REINFORCE
# and ES estimates (coopt/gradients). Two independent one-core jobs, so the two run side by
# side on two cores.


rule coopt_arms:
    message:
        "Co-optimisation: controller, morphology and both co-optimised (§8.2), profile {PROFILE}"
    output:
        nc=result("coopt", "arms"),
    params:
        cfg=cfg_slice("coopt/arms"),
        code=code_of("coopt"),
        key="coopt/arms",
    log:
        log_path("coopt", "arms"),
    benchmark:
        bench_path("coopt", "arms")
    threads: 1
    resources:
        **res("coopt", "arms", mem_mb=6000, runtime=30, gpu=True),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule coopt_gradients:
    message:
        "Co-optimisation: analytic gradients beside REINFORCE and ES estimates (§8.2), "
        "profile {PROFILE}"
    output:
        nc=result("coopt", "gradients"),
    params:
        cfg=cfg_slice("coopt/gradients"),
        code=code_of("coopt"),
        key="coopt/gradients",
    log:
        log_path("coopt", "gradients"),
    benchmark:
        bench_path("coopt", "gradients")
    threads: 1
    resources:
        **res("coopt", "gradients", mem_mb=6000, runtime=30, gpu=True),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["coopt"] = [
    rules.coopt_arms.output.nc,
    rules.coopt_gradients.output.nc,
]
FIGURES["coopt"] = ["learning", "bodies", "estimators", "spread"]
TABLES["coopt"] = ["arms", "gradients"]
