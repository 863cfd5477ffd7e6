"""thesis.store: round trip with provenance, schema checks, atomic writes, loader."""

from __future__ import annotations

import json
from datetime import datetime, timezone

import numpy as np
import pytest
import xarray as xr

from thesis import store


def _result(seeds=(0, 1, 2)) -> xr.Dataset:
    speed = xr.DataArray(np.arange(6.0).reshape(2, 3), dims=("gait", "seed"),
                         coords={"gait": ["sine", "spline"], "seed": list(seeds)},
                         attrs={"units": "m s-1", "long_name": "forward speed"})
    return xr.Dataset({"speed": speed}, attrs={"thesis_ref": "Fig. 3.4",
                                               "seeds": list(seeds)})


def _write(ds, path, **kw):
    args = dict(profile="smoke", experiment="ch3/fig3_4", config_slice={"ch3": {"n": 1}},
                started=datetime(2026, 1, 2, 3, 4, 5, tzinfo=timezone.utc), wall_seconds=1.5)
    args.update(kw)
    return store.write_dataset(ds, path, **args)


def test_round_trip_keeps_values_and_provenance(tmp_path):
    path = _write(_result(), tmp_path / "ch3" / "fig3_4.nc")
    back = store.read_dataset(path)
    xr.testing.assert_identical(back["speed"].reset_coords(drop=True),
                                _result()["speed"].reset_coords(drop=True))
    prov = store.provenance_of(back)
    assert prov["thesis_ref"] == "Fig. 3.4"
    assert prov["profile"] == "smoke"
    assert prov["experiment"] == "ch3/fig3_4"
    assert prov["seeds"] == [0, 1, 2]
    assert prov["wall_seconds"] == pytest.approx(1.5)
    assert prov["started"] == "2026-01-02T03:04:05+00:00"
    assert json.loads(back.attrs["config_json"]) == {"ch3": {"n": 1}}
    assert len(prov["config_sha256"]) == 64
    assert prov["git_dirty"] in (0, 1)
    assert len(prov["git_commit"]) >= 7
    for k in ("jax", "jaxlib", "numpy", "xarray", "python"):
        assert prov["package_versions"][k]
    assert prov["host"]
    assert set(prov["cpu_pins"]) == {"NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE"}


def test_config_hash_changes_with_config(tmp_path):
    a = store.read_dataset(_write(_result(), tmp_path / "a.nc"))
    b = store.read_dataset(_write(_result(), tmp_path / "b.nc", config_slice={"ch3": {"n": 2}}))
    assert a.attrs["config_sha256"] != b.attrs["config_sha256"]


@pytest.mark.parametrize("breakage, message", [
    (lambda ds: ds["speed"].attrs.pop("units"), "no 'units'"),
    (lambda ds: ds["speed"].attrs.pop("long_name"), "no 'long_name'"),
    (lambda ds: ds.attrs.pop("thesis_ref"), "thesis_ref"),
    (lambda ds: ds.attrs.pop("seeds"), "seeds"),
])
def test_incomplete_result_is_refused_and_nothing_written(tmp_path, breakage, message):
    ds = _result()
    breakage(ds)
    path = tmp_path / "x.nc"
    with pytest.raises(store.ResultSchemaError, match=message):
        _write(ds, path)
    assert not path.exists()
    assert list(tmp_path.iterdir()) == []


def test_interrupted_write_leaves_no_file(tmp_path):
    path = tmp_path / "r.nc"
    with pytest.raises(KeyboardInterrupt):
        with store.atomic_path(path) as tmp:
            tmp.write_text("half")
            raise KeyboardInterrupt
    assert not path.exists()
    assert list(tmp_path.iterdir()) == []


def test_atomic_path_replaces_existing_only_on_success(tmp_path):
    path = tmp_path / "r.txt"
    path.write_text("old")
    with pytest.raises(RuntimeError):
        with store.atomic_path(path) as tmp:
            tmp.write_text("new")
            raise RuntimeError("boom")
    assert path.read_text() == "old"
    with store.atomic_path(path) as tmp:
        tmp.write_text("new")
    assert path.read_text() == "new"


def test_load_results_keys_by_chapter_and_artifact(tmp_path):
    _write(_result(), tmp_path / "smoke" / "ch3" / "fig3_4.nc")
    _write(_result(), tmp_path / "smoke" / "ch7" / "ball.nc", experiment="ch7/ball")
    (tmp_path / "smoke" / "ch7" / ".ball.nc.123.tmp").write_text("partial")
    got = store.load_results("smoke", tmp_path)
    assert sorted(got) == ["ch3/fig3_4", "ch7/ball"]
    assert store.load_results("paper", tmp_path) == {}
    assert store.result_path("smoke", "ch7/ball", tmp_path) == tmp_path / "smoke/ch7/ball.nc"
