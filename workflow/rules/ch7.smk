# Chapter 7: the differentiable physics engine (thesis.ch7; engine in thesis.physics).
#
# Five independent experiments (ball, arm_fixed, arm_random, quadruped_gait,
# pendulum_pixels), the engine benchmark of Tab. 7.1 (table7_1) and, outside the default
# target because MuJoCo/MJX are optional, the peers benchmark (table7_1_peers).

# Every run uses one core (XLA runs one core per host device,
# docs/architecture.md#both-cores; arm_random vmaps its batch on
# one device because the engine's sharded batched_rollout fails under jax.grad), so two runs
# share the machine. ``runtime`` is the declared upper estimate [min] for a profile whose
# jobs were never measured (workflow/resources.yaml holds the measured ones); ``gpu``: the
# run takes a GPU in the paper and gpu profiles.


rule ch7_ball:
    message:
        "Differentiable physics: ball throw, BPTT gradient descent vs CMA-ES (§7.2.1), "
        "profile {PROFILE}"
    output:
        nc=result("ch7", "ball"),
    params:
        cfg=cfg_slice("ch7/ball"),
        code=code_of("ch7"),
        key="ch7/ball",
    log:
        log_path("ch7", "ball"),
    benchmark:
        bench_path("ch7", "ball")
    threads: 1
    resources:
        **res("ch7", "ball", mem_mb=6000, runtime=30, gpu=False),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule ch7_arm_fixed:
    message:
        "Differentiable physics: 4-DoF arm to a fixed point, BPTT vs CMA-ES (§7.3.2.1), "
        "profile {PROFILE}"
    output:
        nc=result("ch7", "arm_fixed"),
    params:
        cfg=cfg_slice("ch7/arm_fixed"),
        code=code_of("ch7"),
        key="ch7/arm_fixed",
    log:
        log_path("ch7", "arm_fixed"),
    benchmark:
        bench_path("ch7", "arm_fixed")
    threads: 1
    resources:
        **res("ch7", "arm_fixed", mem_mb=6000, runtime=60, gpu=False),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule ch7_arm_random:
    message:
        "Differentiable physics: 4-DoF arm to random points (§7.3.2.2), profile {PROFILE}"
    output:
        nc=result("ch7", "arm_random"),
    params:
        cfg=cfg_slice("ch7/arm_random"),
        code=code_of("ch7"),
        key="ch7/arm_random",
    log:
        log_path("ch7", "arm_random"),
    benchmark:
        bench_path("ch7", "arm_random")
    threads: 1
    resources:
        **res("ch7", "arm_random", mem_mb=6000, runtime=60, gpu=True),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule ch7_quadruped_gait:
    message:
        "Differentiable physics: quadruped gait from a sine and cosine (§7.3.3), profile {PROFILE}"
    output:
        nc=result("ch7", "quadruped_gait"),
    params:
        cfg=cfg_slice("ch7/quadruped_gait"),
        code=code_of("ch7"),
        key="ch7/quadruped_gait",
    log:
        log_path("ch7", "quadruped_gait"),
    benchmark:
        bench_path("ch7", "quadruped_gait")
    threads: 1
    resources:
        **res("ch7", "quadruped_gait", mem_mb=6000, runtime=60, gpu=True),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule ch7_pendulum_pixels:
    message:
        "Differentiable physics: cart-pole swing-up from camera pixels (§7.3.3.1), "
        "profile {PROFILE}"
    output:
        nc=result("ch7", "pendulum_pixels"),
    params:
        cfg=cfg_slice("ch7/pendulum_pixels"),
        code=code_of("ch7"),
        key="ch7/pendulum_pixels",
    log:
        log_path("ch7", "pendulum_pixels"),
    benchmark:
        bench_path("ch7", "pendulum_pixels")
    threads: 1
    resources:
        **res("ch7", "pendulum_pixels", mem_mb=6000, runtime=60, gpu=True),
    shell:
        "{THESIS} run {params.key} --profile {PROFILE} --output {output.nc} > {log} 2>&1"


rule ch7_table7_1:
    message:
        "Engine speed with and without gradient, batch 1 and 128 (Tab. 7.1), profile {PROFILE}"
    output:
        nc=result("ch7", "table7_1"),
    params:
        cfg=cfg_slice("ch7/table7_1"),
        code=code_of("ch7"),
    log:
        log_path("ch7", "table7_1"),
    benchmark:
        bench_path("ch7", "table7_1")
    threads: 2
    resources:
        **res("ch7", "table7_1", mem_mb=8000, runtime=60, gpu=True),
    shell:
        "{THESIS} bench physics --profile {PROFILE} --output {output.nc} > {log} 2>&1"


# Optional (MuJoCo C / MJX peers of Tab. 7.1): not part of the chapter target.
rule ch7_table7_1_peers:
    message:
        "MuJoCo and MJX on the same quadruped (Tab. 7.1 peers), profile {PROFILE}"
    output:
        nc=result("ch7", "table7_1_peers"),
    params:
        cfg=cfg_slice("ch7/table7_1_peers"),
        code=code_of("ch7"),
    log:
        log_path("ch7", "table7_1_peers"),
    benchmark:
        bench_path("ch7", "table7_1_peers")
    threads: 2
    resources:
        **res("ch7", "table7_1_peers", mem_mb=8000, runtime=60, gpu=True),
    shell:
        "{THESIS} bench mjx --profile {PROFILE} --output {output.nc} > {log} 2>&1"


CHAPTER_TARGETS["ch7"] = [
    rules.ch7_ball.output.nc,
    rules.ch7_arm_fixed.output.nc,
    rules.ch7_arm_random.output.nc,
    rules.ch7_quadruped_gait.output.nc,
    rules.ch7_pendulum_pixels.output.nc,
    rules.ch7_table7_1.output.nc,
]
FIGURES["ch7"] = [
    "ball_loss",
    "arm_learning",
    "gait_learning",
    "gait_frames",
    "pendulum_learning",
    "pendulum_frames",
]
TABLES["ch7"] = ["ball", "table7_1", "arm_fixed", "arm_random", "quadruped_gait", "pendulum_pixels"]
