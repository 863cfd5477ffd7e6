"""Tab. 3.1 from one job per seed (thesis.ch3.experiments.table3_1): the parts joined along
``seed`` in the profile's order, each part checked to hold the seed its name says. That a
part's optimum equals the same seed's in a run over every seed is what the smoke
pipeline's regression shows (its reference was made by the single run)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from thesis.ch3 import experiments as E
from thesis.runctx import RunContext


def _part(seed: int, rate: float) -> xr.Dataset:
    """A stand-in part of one seed, in table3_1_part's layout."""
    rng = np.random.default_rng(seed)
    G, P, T, K = len(E.GAITS), 3, 2, 4
    return xr.Dataset(
        dict(value=(("gait", "parameter", "seed"), rng.normal(size=(G, P, 1))),
             best_fitness=(("gait", "seed", "generation"), rng.normal(size=(G, 1, T))),
             fallen=(("gait", "seed", "generation", "particle"),
                     rng.integers(0, 2, (G, 1, T, K)).astype(float)),
             n_exploded=(("gait", "seed"), np.zeros((G, 1))),
             parameter_unit=("parameter", ["Hz", "rad", "1"]),
             robot_seconds_per_wall_second=((), rate, dict(units="1", long_name="rate"))),
        coords=dict(gait=list(E.GAITS), parameter=["f", "a", "d"], seed=[seed],
                    generation=np.arange(T), particle=np.arange(K)),
        attrs=dict(thesis_ref="Tab. 3.1", seeds=[seed]))


def _ctx(tmp_path: Path, seeds, written) -> RunContext:
    inputs = {}
    for name, ds in written.items():
        path = tmp_path / f"{name}.nc"
        ds.to_netcdf(path, engine="h5netcdf")
        inputs[name] = path
    return RunContext(key="ch3/table3_1", profile="smoke", config={"seeds": seeds},
                      full_config={"root_seed": 0}, inputs=inputs)


def test_parts_join_along_seed_in_the_profile_s_order(tmp_path):
    parts = {f"part_seed{s}": _part(s, r) for s, r in ((2, 10.0), (0, 30.0), (1, 20.0))}
    ds = E.table3_1(_ctx(tmp_path, [0, 1, 2], parts))
    assert ds["seed"].values.tolist() == [0, 1, 2] and ds.attrs["seeds"] == [0, 1, 2]
    for s in (0, 1, 2):
        np.testing.assert_array_equal(ds["value"].sel(seed=s).values,
                                      parts[f"part_seed{s}"]["value"].isel(seed=0).values)
        np.testing.assert_array_equal(ds["fallen"].sel(seed=s).values,
                                      parts[f"part_seed{s}"]["fallen"].isel(seed=0).values)
    assert ds["parameter_unit"].dims == ("parameter",)
    assert float(ds["robot_seconds_per_wall_second"]) == 20.0  # the median of the jobs'


def test_a_part_holding_another_seed_is_refused(tmp_path):
    parts = {"part_seed0": _part(0, 1.0), "part_seed1": _part(3, 1.0)}
    with pytest.raises(ValueError, match="part_seed1 holds seeds \\[3\\]"):
        E.table3_1(_ctx(tmp_path, [0, 1], parts))


def test_a_missing_seed_names_the_input(tmp_path):
    with pytest.raises(Exception, match="part_seed1"):
        E.table3_1(_ctx(tmp_path, [0, 1], {"part_seed0": _part(0, 1.0)}))
