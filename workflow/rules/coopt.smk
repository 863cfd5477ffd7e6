# §8.2 made real (thesis.coopt): the chapter-7 quadruped's controller and body co-optimised
# by gradient through the engine (coopt/arms), and the engine's gradients beside REINFORCE
# and ES estimates (coopt/gradients). Two independent one-core jobs, so the two run side by
# side on two cores.

# (artifact, what, runtime [min], threads, GPU in the paper profile)
_COOPT_RUNS = [
    ("arms", "controller, morphology and both co-optimised (§8.2)", 30, 1, True),
    ("gradients", "analytic gradients beside REINFORCE and ES estimates (§8.2)", 30, 1, True),
]

for _name, _what, _minutes, _threads, _gpu in _COOPT_RUNS:

    rule:
        name:
            f"coopt_{_name}"
        message:
            f"Co-optimisation: {_what}, profile {PROFILE}"
        output:
            nc=result("coopt", _name),
        params:
            cfg=cfg_slice(f"coopt/{_name}"),
            code=code_of("coopt"),
            key=f"coopt/{_name}",
        log:
            log_path("coopt", _name),
        benchmark:
            bench_path("coopt", _name)
        threads: _threads
        resources:
            **res("coopt", _name, mem_mb=6000, runtime=_minutes, gpu=_gpu),
        shell:
            "{THESIS} run {params.key} --profile {PROFILE} --output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["coopt"] = [result("coopt", n) for n, *_ in _COOPT_RUNS]
FIGURES["coopt"] = ["learning", "bodies", "estimators", "spread"]
TABLES["coopt"] = ["arms", "gradients"]
