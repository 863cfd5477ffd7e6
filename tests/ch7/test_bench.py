"""Tab. 7.1 benchmark: controller sizes, the MJCF peer model, the servo law, the batch split.

The dataset's layout is checked on the smoke pipeline's result
(tests/pipeline/layouts_ch7.py), not on a run of its own."""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.ch7 import bench_engine as be
from thesis.ch7.quadruped_mjcf import model_to_mjcf, quadruped_mjcf, servo_ctrl
from thesis.physics import Builder, sensors


@pytest.fixture(scope="module")
def quad():
    return be.quadruped()


def test_controller_sizes_are_the_thesis_counts(quad):
    model, state = quad
    n_sensors = int(be.sensor_vector(model, sensors(model, state)).shape[0])
    small = be.controller_sizes(n_sensors, model.n_servo, 8, [])
    large = be.controller_sizes(n_sensors, model.n_servo, 8, [1024, 1024])
    assert be.count_params(small) == 1296
    assert be.count_params(large) == 1147904
    # the initialised pytrees really have that many weights
    for sizes in (small, large):
        w = be.init_controller(jax.random.key(0), sizes)
        assert sum(int(x.size) for x in w) == be.count_params(sizes)
        assert [x.shape for x in w] == list(zip(sizes[1:], sizes[:-1]))  # (out, in)


def test_sensor_vector_reads_the_chosen_imu(quad):
    model, state = quad
    sens = sensors(model, state)
    bodies = be.sensor_bodies(model)
    n = 2 * model.n_servo
    for imu, key in (("attitude", "imu_up"), ("accelerometer", "imu_acc")):
        x = np.asarray(be.sensor_vector(model, sens, imu))
        np.testing.assert_array_equal(x[n:n + 3 * len(bodies)],
                                      np.asarray(sens[key])[bodies].reshape(-1))
    # the standing torso is level: its up axis is the body z axis
    np.testing.assert_allclose(np.asarray(sens["imu_up"])[bodies[0]], [0, 0, 1], atol=1e-6)
    with pytest.raises(ValueError, match="imu must be one of"):
        be.sensor_vector(model, sens, "magnetometer")


def test_controller_outputs_targets_and_memory(quad):
    model, state = quad
    n_in = int(be.sensor_vector(model, sensors(model, state)).shape[0])
    w = be.init_controller(jax.random.key(1), be.controller_sizes(n_in, 8, 8, [16]),
                           output_gain=1.0)
    ctrl = be.make_controller(model, 8)
    action, mem = ctrl(w, sensors(model, state), jnp.ones(8), 0.0)
    assert action.shape == (8,) and mem.shape == (8,)
    assert float(jnp.max(jnp.abs(mem))) < 1.0  # tanh memory
    # the memory is an input: changing it changes the action
    action2, _ = ctrl(w, sensors(model, state), -jnp.ones(8), 0.0)
    assert float(jnp.max(jnp.abs(action - action2))) > 1e-4


def _bodies(xml):
    out = {}
    for b in ET.fromstring(xml).iter("body"):
        inertial = b.find("inertial")
        joint = b.find("joint")
        out[b.get("name")] = dict(
            mass=float(inertial.get("mass")),
            inertia=[float(v) for v in inertial.get("fullinertia").split()],
            joint=None if joint is None else joint.get("name"),
            range=None if joint is None or joint.get("range") is None
            else [float(v) for v in joint.get("range").split()])
    return out


def test_mjcf_has_the_engine_bodies_masses_and_servos(quad):
    model, _ = quad
    xml = quadruped_mjcf(servo_kv=50.0)
    bodies = _bodies(xml)
    assert sorted(bodies) == sorted(model.body_names)
    assert len(bodies) == 17
    for i, name in enumerate(model.body_names):
        np.testing.assert_allclose(bodies[name]["mass"], float(model.body_mass[i]), rtol=1e-6)
        inertia = np.asarray(model.body_inertia[i])
        np.testing.assert_allclose(bodies[name]["inertia"][:3], np.diag(inertia), rtol=1e-6)
    hinges = {j for j, t in zip(model.joint_names, model.joint_type) if t == 0}
    assert {b["joint"] for b in bodies.values() if b["joint"]} == hinges
    root = ET.fromstring(xml)
    assert float(root.find("option").get("timestep")) == pytest.approx(float(model.dt))
    acts = root.find("actuator").findall("velocity")
    assert [a.get("name") for a in acts] == list(model.servo_names)
    for a, tq in zip(acts, np.asarray(model.servo_max_torque)):
        assert [float(v) for v in a.get("forcerange").split()] == pytest.approx([-tq, tq])
        assert float(a.get("kv")) == 50.0


def _chain():
    b = Builder("chain", dt=0.005)
    b.add_plane("floor", (0, 0, 1), 0.0)
    b.add_box("base", (0.4, 0.2, 0.1), (0, 0, 0.5), mass=3.0)
    b.add_box("link", (0.05, 0.05, 0.3), (0.2, 0, 0.35),
              rot=(np.cos(0.2), 0, np.sin(0.2), 0))
    b.add_sphere("tip", 0.04, (0.2, 0, 0.2))
    b.add_hinge("elbow", "base", "link", (0.2, 0, 0.5), (0, 1, 1), limits=(-0.3, 0.7))
    b.add_fixed("weld", "link", "tip", (0.2, 0, 0.2))
    b.add_contact_sphere("tip", 0.04)
    b.add_position_servo("elbow", 20.0, 3.0, 2.0, name="elbow")
    return b.build()


def _mujoco():
    """MuJoCo from the optional ``bench`` extra (``make test`` installs it; CI must have it)."""
    try:
        import mujoco
    except ImportError:
        if os.environ.get("CI"):
            pytest.fail("mujoco is missing: make test installs the bench extra")
        pytest.skip("the bench extra is not installed here: uv sync --locked --extra bench")
    return mujoco


def test_mjcf_of_a_tilted_limited_chain_matches_the_engine():
    mujoco = _mujoco()
    model, state = _chain()
    xml = model_to_mjcf(model, state, imu_bodies=[0, 1])
    bodies = _bodies(xml)
    assert bodies["link"]["range"] == pytest.approx([-0.3, 0.7])
    mm = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(mm)
    mujoco.mj_forward(mm, d)
    for i, name in enumerate(model.body_names):
        bid = mujoco.mj_name2id(mm, mujoco.mjtObj.mjOBJ_BODY, name)
        np.testing.assert_allclose(mm.body_mass[bid], float(model.body_mass[i]), rtol=1e-6)
        np.testing.assert_allclose(d.xpos[bid], np.asarray(state.pos[i]), atol=1e-5)
        np.testing.assert_allclose(d.xmat[bid].reshape(3, 3), np.asarray(state.rot[i]),
                                   atol=1e-5)
    jid = mujoco.mj_name2id(mm, mujoco.mjtObj.mjOBJ_JOINT, "elbow")
    np.testing.assert_allclose(d.xaxis[jid], np.array([0, 1, 1]) / np.sqrt(2), atol=1e-5)
    np.testing.assert_allclose(d.xanchor[jid], [0.2, 0, 0.5], atol=1e-5)
    assert mm.nsensordata == 2 * 1 + 6 * 2 + 3
    # attitude channels (after jointpos, jointvel) = the engine's imu_up of both bodies
    up = np.asarray(sensors(model, state)["imu_up"])[[0, 1]].reshape(-1)
    np.testing.assert_allclose(d.sensordata[2:8], up, atol=1e-5)
    assert abs(up[3:] - [0, 0, 1]).max() > 0.1  # the tilted link reads a tilt
    acc = mujoco.MjModel.from_xml_string(
        model_to_mjcf(model, state, imu_bodies=[0, 1], imu="accelerometer"))
    acc_type = int(mujoco.mjtSensor.mjSENS_ACCELEROMETER)
    assert [int(t) for t in acc.sensor_type[2:4]] == [acc_type] * 2
    with pytest.raises(ValueError, match="imu must be"):
        model_to_mjcf(model, state, imu_bodies=[0], imu="magnetometer")


def test_servo_ctrl_is_the_engine_servo_law():
    q = np.array([0.0, 0.5, -0.2, 0.1], np.float32)
    cmd = np.array([0.1, 2.0, -0.2, 0.3], np.float32)
    kind = np.array([0, 0, 0, 1])
    out = servo_ctrl(q, cmd, 50.0, 3.0, -0.7, 0.7, 0.01, kind)
    # rate -clip(50 (q - clip(cmd, +-0.7)), +-3): saturated, saturated after clipping the
    # command, inside the dead band, and a velocity servo passing its command through
    np.testing.assert_allclose(out, [3.0, 3.0, 0.0, 0.3], rtol=1e-6)
    assert servo_ctrl(np.array([0.0]), np.array([0.05]), 10.0, 3.0, -1, 1, 0.0,
                      np.array([0]))[0] == pytest.approx(0.5)


_SPLIT = """
import jax, numpy as np
from thesis.ch7 import bench_engine as be
m, s0 = be.quadruped()
dist = be.distance_fn(m, be.make_controller(m, 8), 5, 8, grad_decay=1.0, remat=False)
w = be.init_controller(jax.random.key(0), be.controller_sizes(73, 8, 8, [4]), output_gain=1.0)
st = be.initial_states(s0, 2, jax.random.key(1), 0.3)
res = []
for devs in (jax.devices()[:1], jax.devices()):
    fn, rep, sh, n = be.build_bench_fn(dist, devs, 2, True)
    d, g = jax.jit(fn)(jax.device_put(w, rep), jax.device_put(st, sh))
    res.append((n, np.asarray(d), [np.asarray(x) for x in g]))
(n1, d1, g1), (n2, d2, g2) = res
assert (n1, n2) == (1, 2), (n1, n2)
np.testing.assert_allclose(d2, d1, rtol=1e-4, atol=1e-7)
for a, b in zip(g2, g1):
    np.testing.assert_allclose(a, b, rtol=1e-3, atol=1e-7)
print("OK")
"""


@pytest.mark.slow
def test_batch_split_over_two_host_devices_gives_the_same_gradient():
    import os
    import subprocess
    import sys

    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2")
    out = subprocess.run([sys.executable, "-c", _SPLIT], env=env, capture_output=True,
                         text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    assert out.stdout.strip().endswith("OK")


@pytest.mark.slow
def test_closed_loop_gradient_matches_float64_differences(x64):
    """The Tab. 7.1 gradient (§7.3.1) through servos, contacts and the sensor feedback
    of the controller (eq. 7.3) is the derivative of the rollout: a directional
    derivative of the torso displacement w.r.t. the 1,296 weights equals central
    differences in float64 over 10 steps, at two step sizes. The accelerometer IMU, whose
    loop is the stiffest, is the hard case. Longer windows test the differences, not the
    gradient: this random closed loop is so sensitive (the directional derivative grows
    by orders of magnitude within 25 steps) that central differences stop converging in
    eps there (eps 1e-6, 1e-8 and 1e-9 give values of different sign), while over 10
    steps eps 1e-8 and 1e-9 agree with each other and with the gradient."""
    model, s0 = be.quadruped(dtype=jnp.float64)
    ctrl = be.make_controller(model, 8, imu="accelerometer")
    n_s = int(be.sensor_vector(model, sensors(model, s0), "accelerometer").shape[0])
    sizes = be.controller_sizes(n_s, model.n_servo, 8, [])
    k_w, k_s, k_d = jax.random.split(jax.random.PRNGKey(0), 3)
    w = be.init_controller(k_w, sizes, output_gain=0.1, dtype=jnp.float64)
    st = jax.tree.map(lambda x: x[0], be.initial_states(s0, 1, k_s, 0.05))
    dirn = [jax.random.normal(k, x.shape, jnp.float64)
            for k, x in zip(jax.random.split(k_d, len(w)), w)]
    dist = be.distance_fn(model, ctrl, 10, 8, grad_decay=1.0, remat=False)
    f = jax.jit(lambda a: dist([x + a * d for x, d in zip(w, dirn)], st))
    g = jax.grad(dist)(w, st)
    ad = float(sum(jnp.sum(gi * d) for gi, d in zip(g, dirn)))
    assert abs(ad) > 1e-3
    for eps in (1e-8, 1e-9):
        fd = (float(f(eps)) - float(f(-eps))) / (2 * eps)
        np.testing.assert_allclose(ad, fd, rtol=1e-6, err_msg=f"eps {eps}")
