# Chapter 7: the differentiable physics engine (thesis.diffphys; engine in thesis.physics).
#
# Five independent experiments (ball, arm_fixed, arm_random, quadruped_gait,
# pendulum_pixels), the engine benchmark of Tab. 7.1 (table7_1) and, outside the default
# target because MuJoCo/MJX are optional, the peers benchmark (table7_1_peers).

# (artifact, what, runtime [min], threads, GPU in the paper profile): every run uses one
# core (XLA runs one core per host device, docs/architecture.md#both-cores; arm_random
# vmaps its batch on one device because the engine's sharded batched_rollout fails under jax.grad), so two runs
# share the machine. The runtime is the declared upper estimate for a profile whose jobs
# were never measured (workflow/resources.yaml holds the measured ones).
_CH7_RUNS = [
    ("ball", "ball throw, BPTT gradient descent vs CMA-ES (§7.2.1)", 30, 1, False),
    ("arm_fixed", "4-DoF arm to a fixed point, BPTT vs CMA-ES (§7.3.2.1)", 60, 1, False),
    ("arm_random", "4-DoF arm to random points (§7.3.2.2)", 60, 1, True),
    ("quadruped_gait", "quadruped gait from a sine and cosine (§7.3.3)", 60, 1, True),
    ("pendulum_pixels", "cart-pole swing-up from camera pixels (§7.3.3.1)", 60, 1, True),
]

for _name, _what, _minutes, _threads, _gpu in _CH7_RUNS:

    rule:
        name:
            f"ch7_{_name}"
        message:
            f"Differentiable physics: {_what}, profile {PROFILE}"
        output:
            nc=result("ch7", _name),
        params:
            cfg=cfg_slice(f"ch7/{_name}"),
            code=code_of("ch7"),
            key=f"ch7/{_name}",
        log:
            log_path("ch7", _name),
        benchmark:
            bench_path("ch7", _name)
        threads: _threads
        resources:
            **res("ch7", _name, mem_mb=6000, runtime=_minutes, gpu=_gpu),
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


CHAPTER_TARGETS["ch7"] = [result("ch7", n) for n, *_ in _CH7_RUNS] + [
    result("ch7", "table7_1")
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
