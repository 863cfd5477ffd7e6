"""thesis.cpupins: numpy and OpenBLAS held to AVX2-class code paths on x86-64 hosts."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from thesis import cpupins


def test_pins_on_x86_64_with_and_without_avx2():
    full = cpupins.pins("x86_64", {"avx2", "fma", "avx512f"})
    assert full == {"NPY_DISABLE_CPU_FEATURES": cpupins.NPY_ABOVE_AVX2,
                    "OPENBLAS_CORETYPE": "Haswell"}
    # a CPU without FMA cannot run OpenBLAS's Haswell kernels: OpenBLAS keeps its choice
    assert "OPENBLAS_CORETYPE" not in cpupins.pins("AMD64", {"avx2"})
    assert cpupins.pins("aarch64", {"asimd"}) == {}


def test_pin_leaves_a_variable_the_user_set(monkeypatch):
    env = {"OPENBLAS_CORETYPE": "SkylakeX"}
    monkeypatch.setattr(cpupins, "pins", lambda: {"NPY_DISABLE_CPU_FEATURES": "X86_V4",
                                                  "OPENBLAS_CORETYPE": "Haswell"})
    assert cpupins.pin(env) == {"NPY_DISABLE_CPU_FEATURES": "X86_V4",
                                "OPENBLAS_CORETYPE": "SkylakeX"}


def test_cpu_flags_reads_the_first_flags_line(tmp_path):
    info = tmp_path / "cpuinfo"
    info.write_text("processor\t: 0\nflags\t\t: fpu sse2 avx2 fma\n\nflags\t: other\n")
    assert cpupins.cpu_flags(info) == {"fpu", "sse2", "avx2", "fma"}
    assert cpupins.cpu_flags(tmp_path / "missing") == set()


def _job_sees(extra_env: dict[str, str]) -> dict:
    """What a pipeline job's numpy and OpenBLAS run with: a fresh interpreter that imports
    ``thesis`` before numpy (as ``python -m thesis`` does), without this process's pins,
    with ``extra_env``."""
    env = {**{k: v for k, v in os.environ.items()
              if k not in ("NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE")}, **extra_env}
    code = ("import thesis, json, numpy, scipy.linalg, threadpoolctl; "
            "f = numpy._core._multiarray_umath.__cpu_features__; "
            "print(json.dumps({'x86_v4': f.get('X86_V4', False), "
            "'spr': f.get('AVX512_SPR', False), 'skx': f.get('AVX512_SKX', False), "
            "'avx2': f.get('AVX2'), "
            "'blas': sorted({i.get('architecture') for i in threadpoolctl.threadpool_info() "
            "if i['internal_api'] == 'openblas'})}))")
    return json.loads(subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                     capture_output=True, text=True).stdout)


@pytest.mark.skipif(not cpupins.pins(), reason="numpy and OpenBLAS are pinned on x86-64 only")
def test_importing_thesis_first_pins_numpy_and_openblas():
    """What a pipeline job sees: ``python -m thesis`` imports the package before numpy."""
    out = _job_sees({})
    # numpy's AVX-512 loops are off, its AVX2 loops stay; every OpenBLAS loaded (numpy's,
    # scipy's) runs the Haswell kernels
    assert out["x86_v4"] is False and out["spr"] is False
    flags = cpupins.cpu_flags()
    if {"avx2", "fma"} <= flags:
        assert out["avx2"] is True
        assert out["blas"] == ["Haswell"]


def test_native_env_lifts_every_pin():
    """The native twin runs' environment: numpy's full dispatch, OpenBLAS's own class of
    kernels, no ISA cap on XLA (the jax section then adds none)."""
    from thesis import jaxsetup

    avx512 = {"avx2", "fma", "avx512f", "avx512bw", "avx512vl", "avx512dq"}
    env = cpupins.native_env("x86_64", avx512)
    assert env == {"NPY_DISABLE_CPU_FEATURES": "", "XLA_FLAGS": cpupins.XLA_NO_CAP,
                   "OPENBLAS_CORETYPE": "SkylakeX"}
    assert cpupins.native_env("x86_64", {"avx2", "fma"})["OPENBLAS_CORETYPE"] == "Haswell"
    assert cpupins.native_env("aarch64", {"asimd"}) == {}
    flags = jaxsetup.xla_flags({}, env["XLA_FLAGS"], machine="x86_64").split()
    assert [f for f in flags if "max_isa" in f] == [cpupins.XLA_NO_CAP]
    assert "--xla_cpu_max_isa=AVX2" in jaxsetup.xla_flags({}, "", machine="x86_64").split()


@pytest.mark.skipif("avx512f" not in cpupins.cpu_flags(),
                    reason="a native run differs from a pinned one on AVX-512 hosts only")
def test_native_env_reaches_numpy_and_openblas():
    out = _job_sees(cpupins.native_env())
    assert out["skx"] is True
    assert out["blas"] == [cpupins.native_env()["OPENBLAS_CORETYPE"]]
