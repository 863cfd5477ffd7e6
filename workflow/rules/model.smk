# The simulated Oncilla's validation (thesis.modelcheck.validation; `thesis validate
# oncilla`): the thesis's published gaits on the model, decided against V1-V6
# (thesis.modelcheck.targets), and the same runs at dt / 2 and with twice the solver sweeps
# (the convergence table), and the committed calibration of the knee spring to V1 alone
# (thesis.modelcheck.calibration), and Tab. 4.4's pebble optima on chapter 4's pebble field
# (V7, thesis.modelcheck.pebbles); the Puppy II's recordings in dt and sweeps
# (thesis.modelcheck.puppy_convergence). Not a chapter: the claims of ch3, ch4 and ch6 read the
# validation to mark verdicts decided on an unvalidated model, so both come before claims.

MODEL_CODE = code_version(*CORE_CODE, "modelcheck", "gaits", "physics")


rule model_validation:
    message:
        "Oncilla model: the published gaits against V1-V6, profile {PROFILE}"
    output:
        nc=result("model", "validation"),
    params:
        cfg=cfg_slice("model/validation"),
        code=MODEL_CODE,
        only="validation",
    log:
        log_path("model", "validation"),
    benchmark:
        bench_path("model", "validation")
    threads: 2
    resources:
        **res("model", "validation", mem_mb=4000, runtime=30),
    shell:
        "{THESIS} validate oncilla --only {params.only} --profile {PROFILE} "
        "--output {output.nc} > {log} 2>&1"


rule model_convergence:
    message:
        "Oncilla model: the validation at dt, dt/2 and twice the sweeps, profile {PROFILE}"
    output:
        nc=result("model", "convergence"),
    params:
        cfg=cfg_slice("model/convergence"),
        code=MODEL_CODE,
        only="convergence",
    log:
        log_path("model", "convergence"),
    benchmark:
        bench_path("model", "convergence")
    threads: 2
    resources:
        **res("model", "convergence", mem_mb=4000, runtime=90),
    shell:
        "{THESIS} validate oncilla --only {params.only} --profile {PROFILE} "
        "--output {output.nc} > {log} 2>&1"


rule model_calibration:
    message:
        "Oncilla model: the knee spring's fit to V1 alone and its residual, profile {PROFILE}"
    output:
        nc=result("model", "calibration"),
    params:
        cfg=cfg_slice("model/calibration"),
        code=MODEL_CODE,
        only="calibration",
    log:
        log_path("model", "calibration"),
    benchmark:
        bench_path("model", "calibration")
    threads: 2
    resources:
        **res("model", "calibration", mem_mb=4000, runtime=30),
    shell:
        "{THESIS} validate oncilla --only {params.only} --profile {PROFILE} "
        "--output {output.nc} > {log} 2>&1"


rule model_pebbles:
    message:
        "Oncilla model: Tab. 4.4's pebble optima on the pebble field (V7), profile {PROFILE}"
    output:
        nc=result("model", "pebbles"),
    params:
        cfg=cfg_slice("model/pebbles"),
        # it evaluates as chapter 4 does (thesis.ch4.transfer_runs)
        code=code_version(*CORE_CODE, "modelcheck", "ch4", "gaits", "optim", "physics"),
        only="pebbles",
    log:
        log_path("model", "pebbles"),
    benchmark:
        bench_path("model", "pebbles")
    threads: 2
    resources:
        **res("model", "pebbles", mem_mb=2000, runtime=20),
    shell:
        "{THESIS} validate oncilla --only {params.only} --profile {PROFILE} "
        "--output {output.nc} > {log} 2>&1"


# The fit of the Oncilla's unsourced values (thesis.modelcheck.fit, split.PROCEDURE): an
# optional model check, run by name (snakemake model_fit), outside MODEL_TARGETS: no claim
# or report reads it, and it has no smoke regression reference.
rule model_fit:
    message:
        "Oncilla model: the fit of the unsourced values to Tab. 3.1a and 3.1b at 1.5 Hz, profile {PROFILE}"
    output:
        nc=result("model", "fit"),
    params:
        cfg=cfg_slice("model/fit"),
        code=MODEL_CODE,
        only="fit",
    log:
        log_path("model", "fit"),
    benchmark:
        bench_path("model", "fit")
    threads: 2
    resources:
        **res("model", "fit", mem_mb=4000, runtime=600),
    shell:
        "{THESIS} validate oncilla --only {params.only} --profile {PROFILE} "
        "--output {output.nc} > {log} 2>&1"


rule model_puppy_convergence:
    message:
        f"Puppy II model: the recordings at dt, dt/2 and twice the sweeps, profile {PROFILE}"
    output:
        nc=result("model", "puppy_convergence"),
    params:
        cfg=cfg_slice("model/puppy_convergence"),
        code=code_version(*CORE_CODE, "modelcheck", "ch5", "physics"),
    log:
        log_path("model", "puppy_convergence"),
    benchmark:
        bench_path("model", "puppy_convergence")
    threads: 2
    resources:
        **res("model", "puppy_convergence", mem_mb=4000, runtime=30),
    shell:
        "{THESIS} validate puppy --only puppy_convergence --profile {PROFILE} "
        "--output {output.nc} > {log} 2>&1"


MODEL_TARGETS = [
    rules.model_puppy_convergence.output.nc,
    rules.model_validation.output.nc,
    rules.model_convergence.output.nc,
    rules.model_calibration.output.nc,
    rules.model_pebbles.output.nc,
]


rule model:
    input:
        MODEL_TARGETS,
