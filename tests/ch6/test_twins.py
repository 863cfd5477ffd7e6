"""Perturbed twins of chapter 6: twin variables, flips and the regression policy they set."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from thesis import regression
from thesis.ch6 import twins


def _sweep(outcome, amplitude, wall=1.0):
    outcome = np.asarray(outcome, str)
    dims = ("config", "seed")
    return xr.Dataset(
        dict(outcome=(dims, outcome, dict(units="1")),
             success=(dims, (outcome == "stable").astype(float), dict(units="1")),
             amplitude=(dims, np.asarray(amplitude, float), dict(units="1")),
             hidden=(("config",), np.array([50, 12])),
             rollout_wall_seconds=((), wall, dict(units="s", measurement="wall_clock"))),
        coords=dict(config=["a", "b"], seed=np.arange(4)))


RUN = _sweep([["stable", "stable", "erratic", "stable"], ["dies_out"] * 4],
             [[1.0, 0.9, 0.3, 1.1], [0.01, 0.02, 0.01, 0.0]])
TWIN = _sweep([["stable", "erratic", "erratic", "stable"], ["dies_out"] * 4],
              [[1.0, 0.35, 0.3, 1.1], [0.01, 0.02, 0.01, 0.0]])


def test_attach_stores_twins_flips_and_chaos_tolerances():
    ds = twins.attach(RUN, TWIN, 1e-7)
    assert ds.attrs["perturbation_relative"] == 1e-7
    np.testing.assert_array_equal(ds["success_perturbed"], TWIN["success"])
    np.testing.assert_array_equal(ds["flipped"], [[0, 1, 0, 0], [0, 0, 0, 0]])
    np.testing.assert_allclose(ds["flipped"].mean("seed"), [0.25, 0.0])
    assert "hidden_perturbed" not in ds and "rollout_wall_seconds_perturbed" not in ds
    # one of 8 runs flipped: d^2 = 1/8, tolerance 4 sqrt(d^2 / 4 seeds)
    assert ds["success"].attrs["regression_over"] == "seed"
    assert ds["success"].attrs["regression_atol"] == pytest.approx(4 * np.sqrt(1 / 8 / 4))
    assert ds["flipped"].attrs["regression_atol"] == ds["outcome"].attrs["regression_atol"]
    d2 = 0.55 ** 2 / 8
    assert ds["amplitude"].attrs["regression_atol"] == pytest.approx(4 * np.sqrt(d2 / 4))
    assert ds["amplitude_perturbed"].attrs["regression_atol"] == pytest.approx(
        ds["amplitude"].attrs["regression_atol"])
    assert "regression_over" not in ds["hidden"].attrs


def test_identical_twins_leave_the_rounding_guard():
    ds = twins.attach(RUN, RUN, 1e-7)
    assert ds["success"].attrs["regression_atol"] == regression.DEFAULT_ATOL
    assert float(ds["flipped"].sum()) == 0


def test_chaotic_variables_regress_through_their_mean_over_seeds():
    """A host on which one seed's outcome flips passes when the twins measured such flips,
    and fails when they measured none; a shifted mean beyond the tolerance fails."""
    ref = regression.to_reference(twins.attach(RUN, TWIN, 1e-7))
    assert ref["variables"]["success"]["over"] == "seed"
    other = RUN.copy(deep=True)  # seeds 1 and 2 swap their outcomes: same rates
    other["outcome"][0, 1:3] = ["erratic", "stable"]
    other["success"][0, 1:3] = [0.0, 1.0]
    other["amplitude"][0, 1:3] = [0.3, 0.9]
    assert regression.compare(twins.attach(other, TWIN, 1e-7), ref) == []
    flipped = RUN.copy(deep=True)
    flipped["outcome"][0, 0] = "erratic"
    flipped["success"][0, 0] = 0.0
    assert regression.compare(twins.attach(flipped, TWIN, 1e-7), ref) == []  # 1/4 < 0.71
    calm = regression.to_reference(twins.attach(RUN, RUN, 1e-7))
    problems = regression.compare(twins.attach(flipped, flipped, 1e-7), calm)
    assert any("'success': mean over seed differs" in p for p in problems)
    assert any("'outcome': mean over seed differs" in p for p in problems)
    shifted, shifted_twin = RUN.copy(deep=True), TWIN.copy(deep=True)  # the code changed
    for d in (shifted, shifted_twin):
        d["amplitude"][1] = d["amplitude"][1] + 5.0
    problems = regression.compare(twins.attach(shifted, shifted_twin, 1e-7), ref)
    assert problems == ["variable 'amplitude': mean over seed differs beyond rtol=0.001, "
                        "atol=0.3889 (max abs diff 5)", "variable 'amplitude_perturbed': mean "
                        "over seed differs beyond rtol=0.001, atol=0.3889 (max abs diff 5)"]


def test_a_reference_recorded_run_by_run_is_stale_for_a_chaotic_result():
    ref = regression.to_reference(RUN)
    problems = regression.compare(twins.attach(RUN, TWIN, 1e-7), ref)
    assert any("'success': the reference records" in p for p in problems)
