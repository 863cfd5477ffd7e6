"""Configure JAX for a job before it is imported (XLA flags, x64, compilation cache).

XLA reads ``XLA_FLAGS`` once, when JAX initialises its backend, so :func:`configure`
must run before the first ``import jax`` of the process (the CLI does this).
"""

from __future__ import annotations

import os
from pathlib import Path

from thesis.cpupins import is_x86_64


YNN_REDUCE_OFF = "--xla_cpu_experimental_ynn_fusion_type=-reduce"

#: Values of XLA's ``--xla_cpu_max_isa`` (x86-64 only; jaxlib 0.10 warns and ignores others).
MAX_ISAS = ("SSE4_2", "AVX", "AVX2", "AVX512", "AVX512_VNNI", "AVX512_BF16", "AMX", "AMX_FP16")


def xla_flags(jax_config: dict, flags: str = "", machine: str | None = None) -> str:
    """``XLA_FLAGS`` for the ``jax`` section, extending the user's ``flags``.

    ``host_devices`` > 1 adds ``--xla_force_host_platform_device_count``;
    ``ynn_reduce_fusion: false`` (the default) adds :data:`YNN_REDUCE_OFF`: jaxlib 0.10's
    CPU backend lowers reductions into YNNPACK fusions, which on the engine's vmapped
    solver (reductions over axes of 3-6 entries) cost ~4.5x XLA's own loops (measured on
    the Tab. 7.1 quadruped, 64 robots per core: 423 -> 91 us per robot-step; a single
    robot is unchanged at 128 us; ch2's training steps unchanged).

    ``max_isa`` (default ``"AVX2"``; null: every feature of the host) adds
    ``--xla_cpu_max_isa`` on an x86-64 ``machine`` (default: this one), so that XLA
    generates the same code, and the engine's chaotic rollouts the same numbers, on every
    x86-64 CPU that has that ISA: the smoke profile's ch3 results differed beyond 1e-3
    between an AVX2 machine and an AVX-512 one (a turning gait's yaw by 5.6 degrees) and
    agree to 1e-6 relative with ``AVX2`` on both. AVX2 is also faster for the engine here (64
    quadrupeds on one core: forward 3.96 -> 3.25 s, gradient 16.0 -> 15.5 s per
    10 simulated seconds) and ~5 % slower for ch2's convolutions. A flag the user already
    set is left alone.
    """
    out = flags.split()
    n = int(jax_config.get("host_devices", 1))
    if n > 1 and not any("xla_force_host_platform_device_count" in f for f in out):
        out.append(f"--xla_force_host_platform_device_count={n}")
    if not jax_config.get("ynn_reduce_fusion", False) and not any(
            "xla_cpu_experimental_ynn_fusion_type" in f for f in out):
        out.append(YNN_REDUCE_OFF)
    isa = jax_config.get("max_isa", "AVX2")
    if isa and is_x86_64(machine) and not any(
            "xla_cpu_max_isa" in f for f in out):
        if isa not in MAX_ISAS:
            raise ValueError(f"jax.max_isa must be one of {list(MAX_ISAS)} or null, got {isa!r}")
        out.append(f"--xla_cpu_max_isa={isa}")
    return " ".join(out)


def configure(jax_config: dict) -> None:
    """Apply the ``jax`` section of a profile configuration.

    ``host_devices`` > 1 exposes that many XLA CPU devices so batched rollouts can split
    their batch over both cores (docs/architecture.md#both-cores); ``enable_x64`` switches to
    float64; ``compilation_cache`` enables JAX's persistent compilation cache there;
    ``ynn_reduce_fusion`` and ``max_isa`` (see :func:`xla_flags`).
    """
    os.environ["XLA_FLAGS"] = xla_flags(jax_config, os.environ.get("XLA_FLAGS", ""))
    import jax

    if jax_config.get("enable_x64", False):
        jax.config.update("jax_enable_x64", True)
    cache = jax_config.get("compilation_cache")
    if cache:
        Path(cache).mkdir(parents=True, exist_ok=True)
        jax.config.update("jax_compilation_cache_dir", str(Path(cache).resolve()))
        jax.config.update("jax_persistent_cache_min_compile_time_secs", 1.0)
