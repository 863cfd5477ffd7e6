"""Puppy II on the engine: the bound gait moves it forward on every terrain; the paws' skin
grips less forward than backward (§5.3.1)."""

import numpy as np
import pytest

from thesis.config import load_config
from thesis.ch5 import gaits as G
from thesis.ch5 import recordings as R


def test_bound_moves_forward_upright_on_every_terrain():
    cfg = load_config("smoke")["ch5"]
    mcfg = cfg["model"]
    model, state0 = R.puppy_model(cfg)
    key = (mcfg["dt"], mcfg["solver_iterations"], mcfg["skin_ratio"], "puppy_model")
    R._MODELS[key] = model
    rate = float(cfg["recordings"]["sample_rate"])
    steps = int(round(1.0 / rate / float(mcfg["dt"])))
    n = int(6 * rate)  # 6 s of the 1 Hz bound: ramp plus four periods
    mats = np.array([[cfg["terrains"][t][k] for k in R._MATERIAL_KEYS] for t in R.TERRAINS])
    cmd = G.commands("bound_right", 1.0, n, rate, cfg["gaits"], np.random.default_rng(0))
    states = R._initial_states(state0, np.zeros(len(mats)), np.zeros((len(mats), 2)))
    dtype = state0.pos.dtype
    _, raw = R._chunk_fn(key, n, steps, 1)(np.asarray(mats, dtype), states,
                                           np.broadcast_to(cmd, (len(mats),) + cmd.shape
                                                           ).astype(dtype))
    pos, rot = np.asarray(raw["pos"], float), np.asarray(raw["rot"], float)
    assert np.all(np.isfinite(pos))
    head = np.arctan2(rot[:, :, 1, 0], rot[:, :, 0, 0])
    step = np.diff(pos[:, :, :2], axis=1)
    forward = np.sum(step[..., 0] * np.cos(head[:, 1:]) + step[..., 1] * np.sin(head[:, 1:]),
                     axis=1)
    speed = forward / (n / rate)
    assert np.all(rot[:, :, 2, 2] > 0.5), "turned over"
    assert np.all(speed > 0.01), dict(zip(R.TERRAINS, speed))  # [m/s] forward on average


def test_paw_skin_grips_less_forward_than_backward():
    """The paws are directional contact spheres whose grain is the robot's forward axis;
    the floor material bounds forward sliding by skin_ratio * mu, backward by mu."""
    pup = R._puppy()
    model, state0 = pup.puppy(friction=0.6, skin_ratio=0.5)
    assert model.directional
    assert float(model.material_friction[0]) == pytest.approx(0.6)
    assert float(model.material_friction_forward[0]) == pytest.approx(0.3)
    assert float(model.material_friction_backward[0]) == pytest.approx(0.6)
    # the grain of every paw, seen from the world at the build pose, points along +x
    paws = pup.paw_spheres(model)
    body = np.asarray(model.csphere_body)[paws]
    grain = np.asarray(model.csphere_direction)[paws]
    rot = np.asarray(state0.rot)[body]
    world = np.einsum("bij,bj->bi", rot, grain)
    np.testing.assert_allclose(world, np.tile([1.0, 0.0, 0.0], (4, 1)), atol=1e-6)
    with pytest.raises(ValueError, match="skin_ratio"):
        pup.puppy(skin_ratio=0.0)
