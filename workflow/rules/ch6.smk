# Chapter 6: an embodied trot and walk learned online on the simulated Oncilla
# (thesis.ch6.experiments).
#
# teacher (the configured trot and walk run open loop as a check, or with
# ch6.teacher.source = screen a screen of chapter 3's optima, input table3_1) -> its trot
# and walk teachers feed the controller sweeps (trot with its phase-1-only ablation and
# power-off sweep, walk, linear_feedback, minimal_hidden, minimal_buffer,
# minimal_training), each one batched closed-loop simulation; fig6_4 / fig6_5 extract the
# joint-space trajectories of trot / walk and fig6_6 joins the training MSE and outcomes
# of the sweeps with the profile's stage length.

# Only a screen reads chapter 3's optima; fixed teachers do not wait for (or rerun) ch3.
_SCREEN = config["ch6"]["teacher"]["source"] == "screen"


rule ch6_teacher:
    message:
        "Oncilla: screening open-loop trot and walk teachers (§6.4), profile {PROFILE}"
    input:
        **({"table3_1": rules.ch3_table3_1.output.nc} if _SCREEN else {}),
    output:
        nc=result("ch6", "teacher"),
    params:
        cfg=cfg_slice("ch6/teacher"),
        code=code_of("ch6"),
    log:
        log_path("ch6", "teacher"),
    benchmark:
        bench_path("ch6", "teacher")
    threads: 2
    resources:
        **res("ch6", "teacher", mem_mb=4000, runtime=30),
    shell:
        "{THESIS} run ch6/teacher --profile {PROFILE} "
        + ("--input table3_1={input.table3_1} " if _SCREEN else "")
        + "--output {output.nc} > {log} 2>&1"


rule ch6_trot:
    message:
        "Oncilla closed loop: the trot with H = 50, B = 5, phase 1 alone, power-off sweep "
        "(§6.4-6.5), "
        "profile {PROFILE}"
    input:
        teacher=rules.ch6_teacher.output.nc,
    output:
        nc=result("ch6", "trot"),
    params:
        cfg=cfg_slice("ch6/trot"),
        code=code_of("ch6"),
        key="ch6/trot",
    log:
        log_path("ch6", "trot"),
    benchmark:
        bench_path("ch6", "trot")
    threads: 2
    resources:
        **res("ch6", "trot", mem_mb=6000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input teacher={input.teacher} --output {output.nc} > {log} 2>&1"


rule ch6_walk:
    message:
        "Oncilla closed loop: the walk with H = 50, B = 12 and its control (§6.5, Fig. 6.5), "
        "profile {PROFILE}"
    input:
        teacher=rules.ch6_teacher.output.nc,
    output:
        nc=result("ch6", "walk"),
    params:
        cfg=cfg_slice("ch6/walk"),
        code=code_of("ch6"),
        key="ch6/walk",
    log:
        log_path("ch6", "walk"),
    benchmark:
        bench_path("ch6", "walk")
    threads: 2
    resources:
        **res("ch6", "walk", mem_mb=6000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input teacher={input.teacher} --output {output.nc} > {log} 2>&1"


rule ch6_linear_feedback:
    message:
        "Oncilla closed loop: linear feedback without hidden layer (§6.3.1), profile {PROFILE}"
    input:
        teacher=rules.ch6_teacher.output.nc,
    output:
        nc=result("ch6", "linear_feedback"),
    params:
        cfg=cfg_slice("ch6/linear_feedback"),
        code=code_of("ch6"),
        key="ch6/linear_feedback",
    log:
        log_path("ch6", "linear_feedback"),
    benchmark:
        bench_path("ch6", "linear_feedback")
    threads: 2
    resources:
        **res("ch6", "linear_feedback", mem_mb=6000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input teacher={input.teacher} --output {output.nc} > {log} 2>&1"


rule ch6_minimal_hidden:
    message:
        "Oncilla closed loop: the sweep of H at B = 0 (§6.5), profile {PROFILE}"
    input:
        teacher=rules.ch6_teacher.output.nc,
    output:
        nc=result("ch6", "minimal_hidden"),
    params:
        cfg=cfg_slice("ch6/minimal_hidden"),
        code=code_of("ch6"),
        key="ch6/minimal_hidden",
    log:
        log_path("ch6", "minimal_hidden"),
    benchmark:
        bench_path("ch6", "minimal_hidden")
    threads: 2
    resources:
        **res("ch6", "minimal_hidden", mem_mb=6000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input teacher={input.teacher} --output {output.nc} > {log} 2>&1"


rule ch6_minimal_buffer:
    message:
        "Oncilla closed loop: the sweep of B at H = 12 (§6.5), profile {PROFILE}"
    input:
        teacher=rules.ch6_teacher.output.nc,
    output:
        nc=result("ch6", "minimal_buffer"),
    params:
        cfg=cfg_slice("ch6/minimal_buffer"),
        code=code_of("ch6"),
        key="ch6/minimal_buffer",
    log:
        log_path("ch6", "minimal_buffer"),
    benchmark:
        bench_path("ch6", "minimal_buffer")
    threads: 2
    resources:
        **res("ch6", "minimal_buffer", mem_mb=6000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input teacher={input.teacher} --output {output.nc} > {log} 2>&1"


rule ch6_minimal_training:
    message:
        "Oncilla closed loop: the sweep of the training-stage length (§6.5), profile {PROFILE}"
    input:
        teacher=rules.ch6_teacher.output.nc,
    output:
        nc=result("ch6", "minimal_training"),
    params:
        cfg=cfg_slice("ch6/minimal_training"),
        code=code_of("ch6"),
        key="ch6/minimal_training",
    log:
        log_path("ch6", "minimal_training"),
    benchmark:
        bench_path("ch6", "minimal_training")
    threads: 2
    resources:
        **res("ch6", "minimal_training", mem_mb=6000, runtime=60),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input teacher={input.teacher} --output {output.nc} > {log} 2>&1"


rule ch6_fig6_4:
    message:
        "Joint-space trajectories of the right hind leg from trot, profile {PROFILE}"
    input:
        src=rules.ch6_trot.output.nc,
    output:
        nc=result("ch6", "fig6_4"),
    params:
        cfg=cfg_slice("ch6/fig6_4"),
        code=code_of("ch6"),
        key="ch6/fig6_4",
        src="trot",
    log:
        log_path("ch6", "fig6_4"),
    benchmark:
        bench_path("ch6", "fig6_4")
    threads: 1
    resources:
        **res("ch6", "fig6_4", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input {params.src}={input.src} --output {output.nc} > {log} 2>&1"


rule ch6_fig6_5:
    message:
        "Joint-space trajectories of the right hind leg from walk, profile {PROFILE}"
    input:
        src=rules.ch6_walk.output.nc,
    output:
        nc=result("ch6", "fig6_5"),
    params:
        cfg=cfg_slice("ch6/fig6_5"),
        code=code_of("ch6"),
        key="ch6/fig6_5",
        src="walk",
    log:
        log_path("ch6", "fig6_5"),
    benchmark:
        bench_path("ch6", "fig6_5")
    threads: 1
    resources:
        **res("ch6", "fig6_5", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} "
        "--input {params.src}={input.src} --output {output.nc} > {log} 2>&1"


rule ch6_fig6_6:
    message:
        "Training MSE against the number of signals and outcome (Fig. 6.6), profile {PROFILE}"
    input:
        linear_feedback=rules.ch6_linear_feedback.output.nc,
        trot=rules.ch6_trot.output.nc,
        minimal_hidden=rules.ch6_minimal_hidden.output.nc,
        minimal_buffer=rules.ch6_minimal_buffer.output.nc,
    output:
        nc=result("ch6", "fig6_6"),
    params:
        cfg=cfg_slice("ch6/fig6_6"),
        code=code_of("ch6"),
    log:
        log_path("ch6", "fig6_6"),
    benchmark:
        bench_path("ch6", "fig6_6")
    threads: 1
    resources:
        **res("ch6", "fig6_6", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} run ch6/fig6_6 --profile {PROFILE} "
        "--input linear_feedback={input.linear_feedback} --input trot={input.trot} "
        "--input minimal_hidden={input.minimal_hidden} "
        "--input minimal_buffer={input.minimal_buffer} --output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["ch6"] = [
    rules.ch6_teacher.output.nc,
    rules.ch6_trot.output.nc,
    rules.ch6_walk.output.nc,
    rules.ch6_linear_feedback.output.nc,
    rules.ch6_minimal_hidden.output.nc,
    rules.ch6_minimal_buffer.output.nc,
    rules.ch6_minimal_training.output.nc,
    rules.ch6_fig6_4.output.nc,
    rules.ch6_fig6_5.output.nc,
    rules.ch6_fig6_6.output.nc,
]
FIGURES["ch6"] = ["fig6_4", "fig6_5", "fig6_6", "success_rates"]
TABLES["ch6"] = ["success", "minimal", "teacher", "criteria"]
