"""The Oncilla's opt-in foot plates (thesis.physics.models.oncilla, ``feet="plate"``): the
contact points where the render's plates have their corners, the robot's mass unchanged,
and a standing robot carried by its feet."""

from __future__ import annotations

import importlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics import rollout
from thesis.physics.collision import sphere_centres
from thesis.physics.models.oncilla_config import oncilla_kwargs
from thesis.physics.sensors import contact_normal_force

O = importlib.import_module("thesis.physics.models.oncilla")


@pytest.fixture(scope="module")
def plates():
    return O.oncilla(feet="plate")


@pytest.fixture(scope="module")
def spheres():
    return O.oncilla()


def test_plate_corners_are_the_measured_plate_around_the_toe():
    c = O.plate_corners()  # 72 x 38 mm, the toe 40 mm behind the front edge
    np.testing.assert_allclose(c[:, 0], [0.040, 0.040, -0.032, -0.032], atol=1e-12)
    np.testing.assert_allclose(c[:, 1], [0.019, -0.019, 0.019, -0.019], atol=1e-12)
    np.testing.assert_allclose(c[:, 2], O.PLATE_RADIUS - O.TOE_RADIUS)
    np.testing.assert_allclose(O.plate_corners(0.06, 0.05, 0.02)[:, 0], [0.02, 0.02, -0.04, -0.04])
    with pytest.raises(ValueError, match="plate under its toe"):
        O.plate_corners(0.06, 0.04, 0.07)


def test_plates_add_four_corner_spheres_per_foot_and_keep_the_toes(plates, spheres):
    mp, _ = plates
    ms, _ = spheres
    assert mp.n_csphere == ms.n_csphere + 16 == 24
    assert O.plate_spheres("plate") == tuple(range(8, 24)) and O.plate_spheres() == ()
    for i in O.toe_spheres():
        assert int(mp.csphere_body[i]) == int(ms.csphere_body[i])
        assert float(mp.csphere_radius[i]) == pytest.approx(O.TOE_RADIUS)
    for k, i in enumerate(O.plate_spheres("plate")):
        assert int(mp.csphere_body[i]) == int(mp.csphere_body[O.toe_spheres()[k // 4]])
        assert float(mp.csphere_radius[i]) == pytest.approx(O.PLATE_RADIUS)
    with pytest.raises(ValueError, match="feet"):
        O.oncilla(feet="hoof")


def test_contact_points_sit_at_the_plate_corners_in_the_leg_frame(plates, spheres):
    """In the build pose (trunk level: leg frame = world axes) each corner sphere lies at
    plate_corners() from its toe, and the toes where the sphere model has them."""
    mp, sp = plates
    ms, ss = spheres
    cp = np.asarray(sphere_centres(mp, sp.pos, sp.rot), np.float64)
    cs = np.asarray(sphere_centres(ms, ss.pos, ss.rot), np.float64)
    toes = list(O.toe_spheres())
    np.testing.assert_allclose(cp[toes], cs[toes], atol=1e-6)
    corners = cp[list(O.plate_spheres("plate"))].reshape(4, 4, 3)
    for leg in range(4):
        np.testing.assert_allclose(corners[leg] - cp[toes[leg]], O.plate_corners(), atol=1e-6)
    # the plate's underside is the toe sphere's lowest point: the floor
    radius = np.asarray(mp.csphere_radius, np.float64)
    low = cp[:, 2] - radius
    np.testing.assert_allclose(low[toes + list(O.plate_spheres("plate"))], 0.0, atol=1e-6)


def test_the_plate_s_mass_comes_from_the_foot_segment(plates, spheres):
    mp, _ = plates
    ms, _ = spheres
    assert float(mp.body_mass.sum()) == pytest.approx(float(ms.body_mass.sum()), abs=1e-5)
    assert float(mp.body_mass.sum()) == pytest.approx(O.MASS, abs=1e-4)
    foot = mp.body("LF_foot")
    assert float(mp.body_mass[foot]) == pytest.approx(O.LEG_MASSES[3])
    # the plate moves the foot's centre of mass toward the toe and raises its inertia about
    # the vertical (the plate is 72 mm long, the segment 12 mm thick)
    assert not np.allclose(np.asarray(mp.body_inertia[foot]), np.asarray(ms.body_inertia[foot]))
    with pytest.raises(ValueError, match="plate_mass"):
        O.oncilla(feet="plate", plate_mass=0.06)


def test_config_passes_the_plates_on_only_when_chosen():
    base = dict(dt=0.0025, solver_iterations=30, knee_spring=2.0, warm_start=0.85,
                relaxation=0.3, sweep_order="jacobi", contact_relaxation=None)
    kw = oncilla_kwargs({**base, "feet": "sphere", "foot_length": 0.08, "foot_width": 0.03})
    assert "feet" not in kw and "foot_length" not in kw  # the sphere model, as before
    kw = oncilla_kwargs({**base, "feet": "plate", "foot_length": 0.08, "foot_width": 0.03})
    assert kw["feet"] == "plate" and kw["foot_length"] == 0.08 and kw["foot_width"] == 0.03


def test_a_standing_robot_on_plates_stays_up_and_its_feet_carry_its_weight(plates):
    model, state = plates
    act = O.commands_to_action(jnp.asarray(O.build_offsets()))

    def ctrl(p, sens, mem, t):
        return act, mem

    n = int(round(0.5 / float(model.dt)))
    final, traj = jax.jit(lambda s: rollout(model, s, ctrl, None, n,
                                            record=("body_pos",)))(state)
    trunk = O.trunk_index(model)
    z0 = float(state.pos[trunk, 2])
    z = np.asarray(traj["body_pos"])[:, trunk, 2]
    assert np.isfinite(z).all() and abs(z[-1] - z0) < 0.03
    up = np.asarray(final.rot)[trunk][:, 2]  # the trunk's z axis in the world
    assert up[2] > np.cos(np.radians(5.0))
    force = np.asarray(contact_normal_force(model, final), np.float64)
    weight = float(model.body_mass.sum()) * 9.81
    feet = list(O.toe_spheres()) + list(O.plate_spheres("plate"))
    assert force[feet].sum() == pytest.approx(weight, rel=0.1)
    assert force[:4].sum() < 0.01 * weight  # the trunk's bumpers stay off the floor
    assert force[list(O.plate_spheres("plate"))].sum() > 0.1 * weight  # the plates bear
