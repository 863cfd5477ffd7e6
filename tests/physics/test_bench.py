"""bench.py (thesis bench field) and the Oncilla's optional pebble field."""

import importlib
import logging
from types import SimpleNamespace

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis import registry
from thesis.physics import bench, rollout

O = importlib.import_module("thesis.physics.models.oncilla")


def test_pebble_strip_lies_in_its_lanes_on_the_floor():
    c = bench.pebble_strip(1000, 0.005, 40.0, [-0.08, 0.08], 0.08)
    assert c.shape == (1000, 3)
    np.testing.assert_allclose(c[:, 2], 0.005)
    assert c[:, 0].min() >= -0.5 and c[:, 0].max() <= 39.5
    lane = np.where(c[:, 1] > 0, 0.08, -0.08)
    assert np.abs(c[:, 1] - lane).max() <= 0.04
    assert (c[:, 1] > 0).sum() == 500  # lanes in turn
    # evenly spread: every metre of the strip holds about its share
    counts = np.histogram(c[:, 0], bins=40, range=(-0.5, 39.5))[0]
    assert counts.min() >= 20 and counts.max() <= 30
    np.testing.assert_array_equal(c, bench.pebble_strip(1000, 0.005, 40.0, [-0.08, 0.08], 0.08))


def test_oncilla_on_pebbles_stands_and_queries_its_toes():
    centres = bench.pebble_strip(2000, 0.005, 4.0, [-0.08, 0.08], 0.08)
    m, s = O.oncilla(field=dict(centres=centres, radii=0.005))
    toes = [m.body(f"{leg}_foot") for leg in ("LF", "RF", "LH", "RH")]
    assert list(m.csphere_body[list(O.toe_spheres())]) == toes
    assert tuple(m.field_query) == O.toe_spheres() and m.field_k == 2
    assert m.n_rows == O.oncilla()[0].n_rows + 3 * 4 * 2
    m_all, _ = O.oncilla(field=dict(centres=centres, radii=0.005, spheres="all"))
    assert m_all.field_query.shape == (8,)
    hold = jnp.asarray(O.commands_to_action(O.build_offsets()), jnp.float32)
    ctrl = lambda p, sens, mem, t: (hold, mem)  # noqa: E731
    fin, tr = jax.jit(lambda s: rollout(m, s, ctrl, None, 200,
                                        record=("body_pos", "contact_force")))(s)
    trunk = np.asarray(tr["body_pos"])[:, m.body("trunk")]
    assert np.all(np.isfinite(trunk)) and trunk[:, 2].min() > 0.12  # standing
    weight = float(jnp.sum(m.body_mass)) * 9.81
    # the floor and the pebbles carry the weight: the normal forces' magnitudes add up to
    # at least the weight (more where a toe is wedged against a pebble's slanted surface)
    support = np.asarray(tr["contact_force"])[-100:].sum(axis=1).mean()
    assert weight * 0.98 < support < 1.3 * weight
    assert float(jnp.abs(fin.vel[m.body("trunk")]).max()) < 0.05  # at rest
    with pytest.raises(ValueError, match="'toes'"):
        O.oncilla(field=dict(centres=centres, radii=0.005, spheres="feet"))


@pytest.mark.slow
def test_field_benchmark_writes_its_dataset():
    assert registry.BENCHMARKS["field"] == "physics/sphere_field"
    assert registry.resolve("physics/sphere_field") is bench.sphere_field
    cfg = dict(pebbles=300, radius=0.005, k=2, strip_length=2.0, lanes=[-0.08, 0.08],
               lane_width=0.08, query=["toes"], batch=jax.device_count(),
               simulated_seconds=0.05, repeats=1)
    ctx = SimpleNamespace(full_config={"physics": {"sphere_field": cfg}},
                          key="physics/sphere_field", log=logging.getLogger("test"))
    ds = bench.sphere_field(ctx)
    assert list(ds["condition"].values) == ["none", "toes"]
    assert ds["scalar_rows"].values.tolist() == [60, 84]
    for name in ("robot_seconds_per_wall_second", "wall_seconds", "compile_seconds",
                 "slowdown", "cpu_seconds", "cpu_slowdown"):
        assert ds[name].attrs["measurement"] == "wall_clock"
        assert np.all(np.isfinite(ds[name].values)) and np.all(ds[name].values > 0)
    assert "measurement" not in ds["final_height"].attrs
    assert float(ds["slowdown"].sel(condition="none")) == 1.0
    assert np.all(ds["final_height"].values > 0.1)
