"""Profiles validate against config/schema.yaml; errors name the key and what is allowed."""

from __future__ import annotations

import pytest
import yaml

from thesis.config import PROFILES, load_config, load_schema, validate_config
from thesis.errors import ConfigError


@pytest.mark.parametrize("profile", PROFILES)
def test_every_profile_validates(profile):
    cfg = load_config(profile)
    assert cfg["profile"] == profile
    assert cfg["jax"]["host_devices"] >= 1


def _walk(schema, path="<root>", required=False):
    yield path, schema, required
    for k, sub in schema.get("properties", {}).items():
        yield from _walk(sub, f"{path}.{k}", k in schema.get("required", ()))


def test_every_key_has_description_and_default():
    """Every key is described; every optional key has a default (a key that is required
    inside an optional object, e.g. the four paths of ``ch2.data.mnist_idx``, has none)."""
    schema = load_schema()
    missing = [p for p, s, req in _walk(schema) if p != "<root>"
               and ("description" not in s or ("default" not in s and not req))]
    assert missing == []


def test_every_object_forbids_unknown_keys():
    """Every object lists its keys, or (a mapping such as a teacher's parameters) names
    the allowed ones in ``propertyNames``."""
    schema = load_schema()
    open_objects = [p for p, s, _ in _walk(schema)
                    if s.get("type") == "object" and s.get("additionalProperties") is not False
                    and "enum" not in s.get("propertyNames", {})]
    assert open_objects == []


def test_a_mapping_names_the_unknown_key_and_the_allowed_ones():
    bad = {"trot": {"family": "half_ellipse", "params": {"x1": 1.0}}}
    with pytest.raises(ConfigError) as e:
        validate_config({"profile": "smoke", "ch6": {"teacher": {"fixed": bad}}})
    assert "ch6.teacher.fixed.trot.params" in str(e.value) and "'x1'" in str(e.value)
    assert "'y0_fore'" in str(e.value)


def test_unknown_key_is_named_with_allowed_keys():
    with pytest.raises(ConfigError) as e:
        validate_config({"profile": "smoke", "ch3": {"no_such_key": 1}})
    assert "ch3.no_such_key" in str(e.value)
    assert "allowed keys" in str(e.value)


def test_bad_enum_value_lists_allowed_values():
    with pytest.raises(ConfigError) as e:
        validate_config({"profile": "huge"})
    assert "'profile'" in str(e.value) and "smoke" in str(e.value) and "paper" in str(e.value)


def test_wrong_type_is_named():
    with pytest.raises(ConfigError, match="jax.host_devices"):
        validate_config({"profile": "smoke", "jax": {"host_devices": "two"}})


def test_defaults_are_filled():
    cfg = validate_config({"profile": "smoke"})
    assert cfg["root_seed"] == load_schema()["properties"]["root_seed"]["default"]
    assert "enable_x64" in cfg["jax"]


def test_unknown_profile_and_mismatch(tmp_path):
    with pytest.raises(ConfigError, match="allowed values"):
        load_config("huge")
    f = tmp_path / "c.yaml"
    f.write_text(yaml.safe_dump({"profile": "paper"}))
    with pytest.raises(ConfigError, match="does not match"):
        load_config("smoke", f)


def test_overrides_merge_and_validate():
    cfg = load_config("smoke", overrides={"root_seed": 7})
    assert cfg["root_seed"] == 7
    with pytest.raises(ConfigError, match="root_seed"):
        load_config("smoke", overrides={"root_seed": -1})


def test_command_line_scalars_parse_as_what_they_spell():
    """Nested ``snakemake --config`` values arrive as strings (YAML's base loader):
    numbers, booleans and lists come back typed, words stay strings, ``1e-7`` (a float
    to YAML 1.1 only with a dot) is a number."""
    from thesis.config import parse_scalar, typed_overrides

    assert parse_scalar("30") == 30 and isinstance(parse_scalar("30"), int)
    assert parse_scalar("1e-7") == pytest.approx(1e-7)
    assert parse_scalar("true") is True
    assert parse_scalar("screen") == "screen" and parse_scalar("nan") == "nan"
    assert parse_scalar("[0, 1]") == [0, 1]
    raw = {"ch3": {"model": {"solver_iterations": "30", "knee_spring": "1.944"}},
           "ch6": {"seeds": ["0", "1"], "teacher": {"source": "screen"}}, "root_seed": 4}
    typed = typed_overrides(raw)
    assert typed == {"ch3": {"model": {"solver_iterations": 30, "knee_spring": 1.944}},
                     "ch6": {"seeds": [0, 1], "teacher": {"source": "screen"}},
                     "root_seed": 4}
    assert load_config("smoke", overrides=typed)["ch3"]["model"]["solver_iterations"] == 30
    with pytest.raises(ConfigError, match="solver_iterations"):
        load_config("smoke", overrides=raw)
