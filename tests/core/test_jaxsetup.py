"""jaxsetup.xla_flags: the XLA flags a profile's ``jax`` section asks for."""

from thesis.jaxsetup import YNN_REDUCE_OFF, xla_flags


def test_defaults_add_the_device_split_and_turn_ynn_reductions_off():
    flags = xla_flags({"host_devices": 2}).split()
    assert "--xla_force_host_platform_device_count=2" in flags
    assert YNN_REDUCE_OFF in flags


def test_one_device_and_ynn_reductions_on_add_nothing():
    assert xla_flags({"host_devices": 1, "ynn_reduce_fusion": True}) == ""


def test_flags_the_user_set_win():
    user = "--xla_force_host_platform_device_count=4 --xla_cpu_experimental_ynn_fusion_type=+dot"
    assert xla_flags({"host_devices": 2}, user).split() == user.split()


def test_other_user_flags_are_kept():
    out = xla_flags({"host_devices": 1}, "--xla_dump_to=/tmp/x").split()
    assert out == ["--xla_dump_to=/tmp/x", YNN_REDUCE_OFF]
