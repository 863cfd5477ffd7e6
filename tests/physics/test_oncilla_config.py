"""thesis.physics.models.oncilla_config: the one config -> Oncilla adapter builds, for every
caller (ch3 gaits, ch4 conditions with the safety thread, ch6 sweeps) and the smoke and
default profiles, the model that ``oncilla()`` gives with the keyword arguments those
callers spelled out by hand, leaf for leaf and bit for bit."""

import jax
import numpy as np
import pytest
import yaml

from thesis.config import ConfigError, load_config, repo_root
from thesis.ch6 import sweep as S
from thesis.gaits import conditions as C
from thesis.ch3 import experiments as E
from thesis.physics.models.oncilla import oncilla
from thesis.physics.models.oncilla_config import oncilla_kwargs


def _by_hand(ch: str, cfg: dict) -> dict:
    """The ``oncilla()`` arguments each chapter's own adapter passed (ch3 and ch4: the
    solver, its momentum and the knee spring; ch4 also the tether; ch6 also the
    constraint softness)."""
    m = cfg["model"]
    cr = m.get("contact_relaxation")
    kw = dict(dt=float(m["dt"]), solver_iterations=int(m["solver_iterations"]),
              knee_spring=float(m["knee_spring"]), warm_start=float(m["warm_start"]),
              relaxation=float(m["relaxation"]), sweep_order=str(m["sweep_order"]),
              contact_relaxation=None if cr is None else float(cr))
    if "momentum" in m:  # the momentum order's extrapolation factor (schema default 0.85)
        kw.update(momentum=float(m["momentum"]))
    rr = m.get("row_relaxation")
    kw.update(row_relaxation=None if rr is None else float(rr))
    if "restart" in m:
        kw.update(momentum_restart=bool(m["restart"]))
    if ch == "ch6":
        kw.update(joint_hz=float(m["joint_hz"]), contact_hz=float(m["contact_hz"]))
    # the drives' damping keeps their time constant; plates carry their two dimensions
    kw.update(drive_stiffness=float(m["drive_stiffness"]),
              drive_damping=float(m["drive_stiffness"]) / 50.0)
    if m["feet"] == "plate":
        kw.update(feet="plate", foot_length=float(m["foot_length"]),
                  foot_width=float(m["foot_width"]))
    if ch == "ch4":
        t = cfg["tether"]
        kw.update(tether_rail_height=float(t["rail_height"]), tether_slack=float(t["slack"]),
                  tether_stiffness=float(t["stiffness"]), tether_damping=float(t["damping"]),
                  tether_width=float(t["width"]))
    return kw


def _assert_same(got, want):
    (gl, gt), (wl, wt) = (jax.tree_util.tree_flatten(x) for x in (got, want))
    assert gt == wt  # the static metadata (topology, names) too
    assert len(gl) == len(wl)
    for i, (g, w) in enumerate(zip(gl, wl)):
        g, w = np.asarray(g), np.asarray(w)
        assert g.dtype == w.dtype and g.shape == w.shape, i
        np.testing.assert_array_equal(g, w, err_msg=f"leaf {i}")


CALLERS = {"ch3": E.model_of, "ch4": C.base_model, "ch6": S.model_of}


@pytest.mark.parametrize("profile", ["smoke", "default"])
@pytest.mark.parametrize("ch", ["ch3", "ch4", "ch6"])
def test_every_caller_builds_the_model_its_keys_spell(profile, ch):
    cfg = load_config(profile)[ch]
    want = _by_hand(ch, cfg)
    tether = cfg["tether"] if ch == "ch4" else None
    assert oncilla_kwargs(cfg["model"], tether) == want
    _assert_same(CALLERS[ch](cfg), oncilla(**want))


def test_a_changed_key_changes_the_model():
    """The adapter reads the keys (a different spring or softness is another model)."""
    m = dict(load_config("smoke")["ch6"]["model"])
    base = oncilla_kwargs(m)
    assert oncilla_kwargs({**m, "knee_spring": 3.0})["knee_spring"] == 3.0
    assert oncilla_kwargs({**m, "joint_hz": 50.0})["joint_hz"] == 50.0
    assert "joint_hz" not in oncilla_kwargs({k: v for k, v in m.items() if k != "joint_hz"})
    assert base["contact_relaxation"] is None
    assert oncilla_kwargs({**m, "contact_relaxation": 0.3})["contact_relaxation"] == 0.3
    assert base["row_relaxation"] is None
    got = oncilla_kwargs({**m, "row_relaxation": 0.8, "restart": False})
    assert got["row_relaxation"] == 0.8 and got["momentum_restart"] is False
    model, _ = oncilla(**{**got, "sweep_order": "momentum"})
    assert model.row_relaxation == 0.8 and model.momentum_restart is False
    drive = oncilla_kwargs({**m, "drive_stiffness": 30.0})
    assert (drive["drive_stiffness"], drive["drive_damping"]) == (30.0, 0.6)
    plate = oncilla_kwargs({**m, "feet": "plate", "foot_length": 0.08})
    assert (plate["feet"], plate["foot_length"], plate["foot_width"]) == ("plate", 0.08,
                                                                          m["foot_width"])
    assert "foot_length" not in oncilla_kwargs({**m, "feet": "sphere", "foot_length": 0.08})


@pytest.mark.parametrize("ch", ["ch3", "ch4", "ch6"])
@pytest.mark.parametrize("key, bad", [("row_relaxation", 1.5), ("row_relaxation", 0.0),
                                      ("restart", "yes")])
def test_the_solver_keys_are_validated(ch, key, bad):
    """Every chapter's solver key is a schema key with its range: a bad value is refused
    with an error that names it."""
    with pytest.raises(ConfigError, match=key):
        load_config("smoke", overrides={ch: {"model": {key: bad}}})


@pytest.mark.parametrize("ch, dt", [("ch3", 0.0025), ("ch4", 0.0025), ("ch6", 0.00205)])
def test_the_smoke_models_pin_their_step_and_rows(ch, dt):
    """The smoke profile spells its Oncilla's step and row relaxation itself, so a new
    schema default of the chapters' solver does not move its numbers."""
    with open(repo_root() / "config" / "smoke.yaml") as f:
        model = yaml.safe_load(f)[ch]["model"]
    assert model["dt"] == dt and model["row_relaxation"] is None
    assert model["sweep_order"] == "jacobi"
    # the unfitted robot: point feet and the drives' unfitted stiffness
    assert model["feet"] == "sphere" and model["drive_stiffness"] == 20.0
