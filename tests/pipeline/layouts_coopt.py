"""Layouts of the smoke profile's §8.2 results (``coopt/``): dims, units and the relations
``thesis.claims.coopt`` and ``thesis.report.chapters.coopt`` rely on, derived from the smoke
configuration (checked on what the smoke pipeline wrote)."""

from __future__ import annotations

import numpy as np

from thesis.coopt import estimators, morphology


def arms(ds, cfg):
    c = cfg["coopt"]
    assert ds["arm"].values.tolist() == ["controller", "morphology", "joint"]
    assert ds["seed"].values.tolist() == c["seeds"]
    assert ds.sizes["evaluation"] == c["arms"]["evaluations"]
    assert ds.sizes["start"] == c["arms"]["perturbed_starts"]
    assert ds["param"].values.tolist() == list(morphology.NAMES)
    for var in ("speed", "final_speed", "perturbed_speed", "final_morphology"):
        assert ds[var].attrs["units"], var
    # every arm starts from the same controller and body
    first = ds["speed"].isel(evaluation=0).values
    np.testing.assert_allclose(first, first.flat[0], rtol=1e-5)
    # the frozen groups stay frozen; bodies stay within their bounds
    body = ds["final_morphology"]
    np.testing.assert_allclose(body.sel(arm="controller").values,
                               np.broadcast_to(ds["param_built"].values, body.shape[1:]),
                               rtol=1e-5)
    assert np.all(body.values >= ds["param_lo"].values) and np.all(
        body.values <= ds["param_hi"].values)


def gradients(ds, cfg):
    g = cfg["coopt"]["gradients"]
    assert ds["rollouts"].values.tolist() == estimators.log_grid(g["rollouts"]).tolist()
    assert ds["horizon"].values.tolist() == g["horizons_steps"]
    assert ds.sizes["block"] == g["repeats"] and ds.sizes["start"] == g["variance_starts"]
    cos = ds["cosine"].values
    assert np.all(np.abs(cos[np.isfinite(cos)]) <= 1 + 1e-9)
    # ES needs a pair: no single-rollout ES estimate
    assert np.all(np.isnan(ds["cosine"].sel(estimator="es", rollouts=1).values))
    need = ds["rollouts_to_threshold"].values
    assert np.all(np.isnan(need) | np.isin(need, ds["rollouts"].values))


CHECKS = {"coopt/arms": arms, "coopt/gradients": gradients}
