"""The §8.2 experiments are wired like a chapter: config keys validated with errors naming
the key, registry entries reading their config slice, departures shown with results."""

from __future__ import annotations

import pytest

from thesis import departures, registry
from thesis.config import load_config
from thesis.errors import ConfigError


def test_bad_coopt_key_names_the_key():
    with pytest.raises(ConfigError, match=r"coopt\.arms\.bogus"):
        load_config("smoke", overrides={"coopt": {"arms": {"bogus": 1}}})
    with pytest.raises(ConfigError, match=r"coopt\.gradients\.sigma"):
        load_config("smoke", overrides={"coopt": {"gradients": {"sigma": -1.0}}})


@pytest.mark.parametrize("profile", ["smoke", "default", "paper"])
def test_profiles_define_coopt(profile):
    cfg = load_config(profile)["coopt"]
    g = cfg["gradients"]
    assert g["rollouts"] % g["chunk"] == 0  # the experiment refuses anything else
    assert cfg["arms"]["evaluations"] >= 1 and len(cfg["seeds"]) >= 1


def test_registry_and_departures():
    for key in ("coopt/arms", "coopt/gradients"):
        registry.resolve(key)
        assert all(r.startswith("coopt.") for r in registry.reads(key))
        ids = {d.id for d in departures.for_result(key)}
        assert {"ch8.coopt_servo_torque", "ch8.coopt_controller",
                "ch8.coopt_morphology"} <= ids
