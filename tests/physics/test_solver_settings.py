"""Solver settings applied to a built model (thesis.physics.solver_settings)."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics.models.quadruped import quadruped
from thesis.physics.solver_settings import solver_fields, with_solver


def test_empty_settings_keep_the_model():
    m, _ = quadruped()
    assert solver_fields({}) == {}
    m2 = with_solver(m, {})
    assert (m2.sweep_order, m2.solver_iterations, m2.row_relaxation) == (
        m.sweep_order, m.solver_iterations, m.row_relaxation)
    assert float(m2.relaxation) == float(m.relaxation)


def test_momentum_settings_reach_the_model_in_its_float_type():
    m, _ = quadruped()
    m2 = with_solver(m, {"sweep_order": "momentum", "relaxation": 0.65, "row_relaxation": 0.8,
                         "contact_relaxation": 0.5, "momentum": 0.9, "restart": False,
                         "solver_iterations": 40})
    assert m2.sweep_order == "momentum" and m2.solver_iterations == 40
    assert (m2.row_relaxation, m2.contact_relaxation, m2.momentum) == (0.8, 0.5, 0.9)
    assert m2.momentum_restart is False
    assert m2.relaxation.dtype == m.body_mass.dtype == jnp.float32
    np.testing.assert_allclose(float(m2.relaxation), 0.65, rtol=1e-6)
    # the factors that take None clear the model's value
    assert with_solver(m2, {"row_relaxation": None}).row_relaxation is None


@pytest.mark.parametrize("bad", [{"sweep_order": "gauss"}, {"relaxation": 1.5}])
def test_a_bad_setting_is_refused_by_the_profile_schema(bad):
    from thesis.config import load_config
    from thesis.errors import ConfigError

    with pytest.raises(ConfigError) as e:
        load_config("smoke", overrides={f"physics.bench.solver.{k}": v for k, v in bad.items()})
    assert "physics.bench.solver" in str(e.value)


def test_the_benchmark_default_keeps_tab_7_1s_model():
    """physics.bench.solver at its defaults (all null) leaves the quadruped as built."""
    from thesis.config import load_config

    m, _ = quadruped()
    cfg = load_config("default")["physics"]["bench"]["solver"]
    assert set(cfg) >= {"sweep_order", "row_relaxation"} and all(v is None for v in cfg.values())
    assert solver_fields({k: v for k, v in cfg.items() if v is not None}) == {}
