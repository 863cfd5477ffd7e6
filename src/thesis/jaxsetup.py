"""Configure JAX for a job before it is imported (XLA flags, x64, compilation cache).

XLA reads ``XLA_FLAGS`` once, when JAX initialises its backend, so :func:`configure`
must run before the first ``import jax`` of the process (the CLI does this).
"""

from __future__ import annotations

import os
from pathlib import Path


def configure(jax_config: dict) -> None:
    """Apply the ``jax`` section of a profile configuration.

    ``host_devices`` > 1 exposes that many XLA CPU devices so batched rollouts can split
    their batch over both cores (FACTS §8); ``enable_x64`` switches to float64;
    ``compilation_cache`` enables JAX's persistent compilation cache there.
    """
    n = int(jax_config.get("host_devices", 1))
    flags = os.environ.get("XLA_FLAGS", "")
    if n > 1 and "xla_force_host_platform_device_count" not in flags:
        os.environ["XLA_FLAGS"] = f"{flags} --xla_force_host_platform_device_count={n}".strip()
    import jax

    if jax_config.get("enable_x64", False):
        jax.config.update("jax_enable_x64", True)
    cache = jax_config.get("compilation_cache")
    if cache:
        Path(cache).mkdir(parents=True, exist_ok=True)
        jax.config.update("jax_compilation_cache_dir", str(Path(cache).resolve()))
        jax.config.update("jax_persistent_cache_min_compile_time_secs", 1.0)
