"""Perturbed twins: how much of a chapter 6 outcome is a property of its seed.

The closed loops of §6.4 are chaotic at the rounding level: a last-bit difference in the
initial state (or a CPU whose kernels round differently) can change a run's outcome.
Every run therefore has a twin, identical but for its initial body positions perturbed at
``ch6.perturbation.relative`` (:func:`thesis.ch6.loop.perturbed`). The twin's values
are stored beside the run's as ``<name>_perturbed`` (the claims are decided on both,
:func:`thesis.claims.perturbed_view`, and a verdict that moves is flagged fragile), each
run's ``flipped`` says whether its outcome changed, and the per-run variables are
regressed across hosts through their mean over seeds within the tolerance the twins
measure (:func:`thesis.regression.chaos_tolerance`), not one run at a time.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from thesis import regression

#: Suffix of a twin's variable.
SUFFIX = "_perturbed"


def per_run(ds: xr.Dataset, dim: str = "seed") -> list[str]:
    """Names of the variables of ``ds`` that hold one value (or curve) per run: those with
    the ``dim`` dimension that are not wall-clock measurements."""
    return [n for n, v in ds.data_vars.items()
            if dim in v.dims and not regression.is_wall_clock(v)]


def attach(ds: xr.Dataset, twin: xr.Dataset, relative: float, *,
           dim: str = "seed") -> xr.Dataset:
    """``ds`` with its twin's value of every per-run variable (:func:`per_run`) as
    ``<name>_perturbed``, the per-run ``flipped`` (outcome differs from the twin's; its
    mean over seeds is a configuration's flip rate), and the
    regression policy of every per-run variable (``regression_over=dim`` with the twin's
    :func:`thesis.regression.chaos_tolerance`).

    Args:
        ds, twin: datasets of the same runs (same dims and coords), the twin's started
            from the perturbed state.
        relative: the perturbation's relative size (recorded in the attributes).
    """
    out = ds.copy()
    twinned = per_run(ds, dim)
    for name in twinned:
        v = twin[name]
        out[name + SUFFIX] = v.assign_attrs(
            v.attrs, long_name=f"{v.attrs.get('long_name', name)} (perturbed twin)")
    flipped = (ds["outcome"].values.astype(str) != twin["outcome"].values.astype(str))
    out["flipped"] = (ds["outcome"].dims, flipped.astype(float), dict(
        units="1", long_name="1 if the perturbed twin's outcome differs from the run's"))
    out.attrs.update(perturbation_relative=float(relative))
    return tolerances(out, dim)


def tolerances(ds: xr.Dataset, dim: str = "seed") -> xr.Dataset:
    """Set the regression policy of every per-run variable of a dataset that carries its
    twins: ``regression_over=dim`` and ``regression_atol`` from the run-twin differences
    (:func:`thesis.regression.chaos_tolerance`; a twin variable and ``flipped`` take their
    run variable's, respectively the outcome's). A dataset without twins is returned as it
    is (compared run by run). Modifies and returns ``ds``."""
    if "outcome" + SUFFIX not in ds:
        return ds
    n = ds.sizes[dim]
    for name in per_run(ds, dim):
        base = name.removesuffix(SUFFIX)
        if base + SUFFIX in ds and base != "flipped":
            a, b = ds[base].values, ds[base + SUFFIX].values
        else:  # flipped, or a variable without a twin: the outcome's
            a, b = ds["outcome"].values, ds["outcome" + SUFFIX].values
        ds[name].attrs.update(regression_over=dim,
                              regression_atol=regression.chaos_tolerance(a, b, n))
    return ds
