"""Profile configurations: load ``config/<profile>.yaml``, validate, fill defaults.

The same ``config/schema.yaml`` is used by Snakemake (``validate`` in the Snakefile) and
by Python (:func:`load_config`), so a run started either way sees the same values.
Errors name the offending key and what the schema allows, before anything runs.
"""

from __future__ import annotations

import copy
import hashlib
import json
from pathlib import Path
from typing import Any

import jsonschema
import yaml

from thesis.errors import ConfigError

PROFILES = ("smoke", "default", "paper", "gpu")


def repo_root() -> Path:
    """The repository root (the directory holding ``config/`` and ``Snakefile``)."""
    here = Path(__file__).resolve()
    for parent in here.parents:
        if (parent / "config" / "schema.yaml").exists():
            return parent
    return Path.cwd()


def schema_path() -> Path:
    return repo_root() / "config" / "schema.yaml"


#: libyaml's safe loader where PyYAML was built with it (its wheels are), else the
#: pure-Python one: the same documents, parsed about 7x faster (the 3,600-line schema in
#: 0.05 s instead of 0.4 s), which every job, Snakefile parse and test pays.
_SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def read_yaml(path: str | Path) -> Any:
    """The YAML document at ``path``, safely loaded (no Python objects)."""
    with open(path) as f:
        return yaml.load(f, Loader=_SAFE_LOADER)


def load_schema() -> dict:
    return read_yaml(schema_path())


def _path_of(error: jsonschema.ValidationError) -> str:
    parts = [str(p) for p in error.absolute_path]
    return ".".join(parts) if parts else "<top level>"


def _describe(error: jsonschema.ValidationError) -> str:
    where = _path_of(error)
    schema = error.schema if isinstance(error.schema, dict) else {}
    if error.validator == "additionalProperties":
        allowed = sorted(schema.get("properties", {}))
        extra = sorted(set(error.instance) - set(allowed)) if isinstance(error.instance, dict) else []
        prefix = "" if where == "<top level>" else where + "."
        keys = ", ".join(prefix + k for k in extra)
        return f"unknown config key {keys!s}; allowed keys here: {', '.join(allowed)}"
    if error.validator == "enum":
        return (f"config key {where!r} = {error.instance!r} is not allowed; "
                f"allowed values: {', '.join(map(repr, error.validator_value))}")
    if error.validator == "type":
        return (f"config key {where!r} = {error.instance!r} has the wrong type; "
                f"expected {error.validator_value}")
    if error.validator in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
        return (f"config key {where!r} = {error.instance!r} violates "
                f"{error.validator} {error.validator_value}")
    if error.validator == "required":
        return f"config section {where!r}: {error.message}"
    return f"config key {where!r}: {error.message}"


def _fill_defaults(instance: Any, schema: dict) -> Any:
    """Recursively insert ``default`` values of object properties that are absent."""
    if not isinstance(schema, dict):
        return instance
    if schema.get("type") == "object" and isinstance(instance, dict):
        for name, sub in schema.get("properties", {}).items():
            if name not in instance and isinstance(sub, dict) and "default" in sub:
                instance[name] = copy.deepcopy(sub["default"])
            if name in instance:
                instance[name] = _fill_defaults(instance[name], sub)
    if schema.get("type") == "array" and isinstance(instance, list) and "items" in schema:
        instance = [_fill_defaults(x, schema["items"]) for x in instance]
    return instance


def validate_config(config: dict, schema: dict | None = None) -> dict:
    """Validate ``config`` against the schema and return a default-filled deep copy.

    Raises:
        ConfigError: listing every violation, each naming the key and what is allowed.
    """
    schema = load_schema() if schema is None else schema
    filled = _fill_defaults(copy.deepcopy(config), schema)
    validator = jsonschema.Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(filled), key=lambda e: list(map(str, e.absolute_path)))
    if errors:
        msg = "\n".join("  - " + _describe(e) for e in errors)
        raise ConfigError(f"invalid configuration:\n{msg}")
    return filled


def load_config(profile: str, path: str | Path | None = None,
                overrides: dict | None = None) -> dict:
    """Load, merge overrides into, validate and default-fill a profile's configuration.

    Args:
        profile: one of :data:`PROFILES`.
        path: a YAML file to read instead of ``config/<profile>.yaml``.
        overrides: nested dict merged over the file's values (like ``--config``).
    """
    if path is None and profile not in PROFILES:
        raise ConfigError(f"unknown profile {profile!r}; allowed values: {', '.join(PROFILES)}")
    path = Path(path) if path is not None else repo_root() / "config" / f"{profile}.yaml"
    config = read_yaml(path) or {}
    if overrides:
        config = merge(config, overrides)
    config.setdefault("profile", profile)
    if config["profile"] != profile:
        raise ConfigError(
            f"config key 'profile' = {config['profile']!r} in {path} does not match the "
            f"requested profile {profile!r}")
    return validate_config(config)


def parse_scalar(text: str) -> Any:
    """A command-line value as the YAML scalar it spells (``3`` -> 3, ``true`` -> True,
    ``[0, 1]`` -> [0, 1], ``screen`` -> "screen"), with YAML 1.1's gap filled: a float
    without a dot (``1e-7``) is a number, not a string (words such as ``nan`` stay
    strings). Used by ``thesis --set`` and for Snakemake's nested ``--config`` values
    (:func:`typed_overrides`)."""
    value = yaml.safe_load(text)
    if isinstance(value, str) and any(c.isdigit() for c in text):
        try:
            return float(text)
        except ValueError:
            return value
    return value


def typed_overrides(over: Any) -> Any:
    """Snakemake's ``--config`` overrides with every string leaf parsed by
    :func:`parse_scalar`.

    Snakemake parses a top-level ``--config key=value`` as int, float or bool, but loads a
    nested one (``'ch3={"model": {"solver_iterations": 60}}'``) with YAML's base loader,
    which leaves every scalar a string; the schema would then refuse the number.
    """
    if isinstance(over, dict):
        return {k: typed_overrides(v) for k, v in over.items()}
    if isinstance(over, list):
        return [typed_overrides(v) for v in over]
    if isinstance(over, str):
        return parse_scalar(over)
    return over


def merge(base: dict, over: dict) -> dict:
    """Deep merge ``over`` into a copy of ``base`` (dicts merge, everything else replaces)."""
    out = copy.deepcopy(base)
    for k, v in over.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = merge(out[k], v)
        else:
            out[k] = copy.deepcopy(v)
    return out


def canonical_json(obj: Any) -> str:
    """Canonical JSON (sorted keys, no whitespace) used for hashing and attributes."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str)


def config_sha256(obj: Any) -> str:
    """SHA-256 of the canonical JSON of a (slice of a) configuration."""
    return hashlib.sha256(canonical_json(obj).encode()).hexdigest()
