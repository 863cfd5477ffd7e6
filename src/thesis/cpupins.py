"""Pin the CPU code paths that numpy and OpenBLAS choose at run time.

numpy dispatches its ufunc loops (``exp``, ``log``, ``sin``, ...; SVML on AVX-512) and
OpenBLAS its BLAS/LAPACK kernels (SkylakeX, Haswell, Zen, ...) by the instruction sets of
the host, and the kernels round differently. ch5's classifiers and CMA-ES searches carry a
last-bit difference into a different table: the smoke profile's Tab. 5.3-5.6 differed by
up to 0.027 in accuracy (12 points in Tab. 5.5) between an AVX2 host and an AVX-512 one.
With numpy's AVX-512 loops disabled and OpenBLAS held to its Haswell (AVX2 + FMA) kernels,
the AVX-512 host reproduced the AVX2 host's smoke results of ch5 bit for bit. JAX's code
is pinned separately, by the profile's ``jax.max_isa`` (:mod:`thesis.jaxsetup`).

Both libraries read these variables once, when they load, so :func:`pin` must run before
numpy is first imported in the process: ``thesis/__init__.py`` calls it, and every job of
the pipeline (``python -m thesis ...``) and the processes it starts inherit the variables.
A variable already set in the environment is left alone (an empty
``NPY_DISABLE_CPU_FEATURES`` keeps numpy's full dispatch; ``OPENBLAS_CORETYPE`` names any
OpenBLAS core), at the price of results that may differ from the committed references.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path

#: numpy (2.x) feature groups above AVX2; numpy ignores names it does not know, so the
#: value is harmless on hosts without AVX-512 or on other architectures.
NPY_ABOVE_AVX2 = "X86_V4 AVX512_ICL AVX512_SPR"
#: OpenBLAS core whose kernels need AVX2 and FMA (``OPENBLAS_CORETYPE``).
OPENBLAS_AVX2_CORE = "Haswell"
#: The environment variables this module pins.
VARIABLES = ("NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE")


def is_x86_64(machine: str | None = None) -> bool:
    """Whether ``machine`` (default: this one, ``platform.machine()``) is x86-64."""
    return (platform.machine() if machine is None else machine).lower() in ("x86_64", "amd64")


def cpu_flags(cpuinfo: str | Path = "/proc/cpuinfo") -> set[str]:
    """Instruction-set flags of the first CPU listed in ``cpuinfo`` (empty if unreadable,
    e.g. off Linux)."""
    try:
        text = Path(cpuinfo).read_text()
    except OSError:
        return set()
    for line in text.splitlines():
        if line.startswith("flags"):
            return set(line.partition(":")[2].split())
    return set()


def pins(machine: str | None = None, flags: set[str] | None = None) -> dict[str, str]:
    """Environment variables that hold numpy and OpenBLAS to AVX2-class code paths.

    Only on x86-64 ``machine`` (default: this one). ``OPENBLAS_CORETYPE`` only where
    ``flags`` (default: :func:`cpu_flags`) include AVX2 and FMA, whose instructions the
    Haswell kernels use; an older CPU keeps OpenBLAS's own choice.
    """
    if not is_x86_64(machine):
        return {}
    flags = cpu_flags() if flags is None else flags
    out = {"NPY_DISABLE_CPU_FEATURES": NPY_ABOVE_AVX2}
    if {"avx2", "fma"} <= flags:
        out["OPENBLAS_CORETYPE"] = OPENBLAS_AVX2_CORE
    return out


#: XLA's highest ``--xla_cpu_max_isa``: XLA then uses every feature the host has.
XLA_NO_CAP = "--xla_cpu_max_isa=AMX_FP16"
#: OpenBLAS core of the AVX-512 kernels (``OPENBLAS_CORETYPE``).
OPENBLAS_AVX512_CORE = "SkylakeX"


def native_env(machine: str | None = None, flags: set[str] | None = None) -> dict[str, str]:
    """Environment of a job that computes with this host's own code paths, every pin
    lifted: numpy's full dispatch (an empty ``NPY_DISABLE_CPU_FEATURES``, which
    :func:`pin` leaves alone), OpenBLAS's AVX-512 kernels where the CPU has AVX-512 (its
    AVX2 ones otherwise, as pinned), and no ISA cap on XLA (``XLA_FLAGS`` carries
    :data:`XLA_NO_CAP`, so :func:`thesis.jaxsetup.xla_flags` adds no ``jax.max_isa``).

    On an AVX-512 host such a run computes as an unpinned AVX-512 host would: the
    pipeline's "native" twin runs (Snakemake ``--config isa=native``), beside which
    ``thesis check`` marks a verdict that moves with the instruction set. On an AVX2 host
    it is the pinned run again. Empty off x86-64 (nothing is pinned there).
    """
    if not is_x86_64(machine):
        return {}
    flags = cpu_flags() if flags is None else flags
    out = {"NPY_DISABLE_CPU_FEATURES": "", "XLA_FLAGS": XLA_NO_CAP}
    if {"avx512f", "avx512bw", "avx512vl", "avx512dq"} <= flags:
        out["OPENBLAS_CORETYPE"] = OPENBLAS_AVX512_CORE
    elif {"avx2", "fma"} <= flags:
        out["OPENBLAS_CORETYPE"] = OPENBLAS_AVX2_CORE
    return out


def in_force(environ=os.environ) -> dict[str, str]:
    """The :data:`VARIABLES` set in ``environ`` and their values."""
    return {k: environ[k] for k in VARIABLES if k in environ}


def pin(environ=os.environ) -> dict[str, str]:
    """Set :func:`pins` in ``environ`` where not set already; returns :func:`in_force`."""
    for key, value in pins().items():
        environ.setdefault(key, value)
    return in_force(environ)
