"""jaxsetup.xla_flags: the XLA flags a profile's ``jax`` section asks for."""

import pytest

from thesis.config import validate_config
from thesis.errors import ConfigError
from thesis.jaxsetup import MAX_ISAS, YNN_REDUCE_OFF, xla_flags


def test_defaults_add_the_device_split_ynn_reductions_off_and_avx2():
    flags = xla_flags({"host_devices": 2}, machine="x86_64").split()
    assert "--xla_force_host_platform_device_count=2" in flags
    assert YNN_REDUCE_OFF in flags
    assert "--xla_cpu_max_isa=AVX2" in flags


def test_one_device_ynn_reductions_on_and_host_isa_add_nothing():
    cfg = {"host_devices": 1, "ynn_reduce_fusion": True, "max_isa": None}
    assert xla_flags(cfg, machine="x86_64") == ""


def test_max_isa_only_on_x86_64():
    assert "xla_cpu_max_isa" not in xla_flags({"max_isa": "AVX2"}, machine="aarch64")
    assert "--xla_cpu_max_isa=AVX512" in xla_flags({"max_isa": "AVX512"}, machine="AMD64")


def test_flags_the_user_set_win():
    user = ("--xla_force_host_platform_device_count=4 "
            "--xla_cpu_experimental_ynn_fusion_type=+dot --xla_cpu_max_isa=AVX512")
    assert xla_flags({"host_devices": 2}, user, machine="x86_64").split() == user.split()


def test_other_user_flags_are_kept():
    out = xla_flags({"host_devices": 1}, "--xla_dump_to=/tmp/x", machine="x86_64").split()
    assert out == ["--xla_dump_to=/tmp/x", YNN_REDUCE_OFF, "--xla_cpu_max_isa=AVX2"]


def test_unknown_isa_is_refused_by_the_schema_and_by_xla_flags():
    with pytest.raises(ConfigError) as e:
        validate_config({"profile": "smoke", "jax": {"max_isa": "AVX3"}})
    assert "jax.max_isa" in str(e.value) and "AVX2" in str(e.value)
    with pytest.raises(ValueError, match="jax.max_isa"):
        xla_flags({"max_isa": "AVX3"}, machine="x86_64")


def test_schema_enum_matches_the_flag_values():
    cfg = validate_config({"profile": "smoke"})
    assert cfg["jax"]["max_isa"] == "AVX2"
    for isa in MAX_ISAS:
        validate_config({"profile": "smoke", "jax": {"max_isa": isa}})
