"""The environments of chapter 4 (§4.6) as changes of the Oncilla model's leaves.

One compiled rollout serves every condition whose topology is the flat Oncilla's: the
slopes and the softer front legs change only model leaves (gravity, spring constants),
so the batched simulation of :mod:`thesis.gaits.runner` is compiled once for all of them.

* **Slopes** (§4.6.1, "a 9% and an 18% grade, or a 5.14° and a 10.2° slope"): gravity
  rotated by θ = atan(grade), uphill along +x (:func:`thesis.physics.terrain.incline`).
  For the single infinite floor plane this is the physics of an inclined treadmill seen
  in the belt's frame; the fall test (trunk height above the plane, tilt of the trunk
  against the plane's normal) keeps its meaning.
* **Safety thread** (§4.5): every condition runs with the thread from the robot's head
  to an overhead rail (``tether`` config; :func:`untethered` removes it).
* **Softer front legs** (§4.6.2, "removing one of the two springs in each of the robot's
  front legs"): the extension spring of the front knees (``LF_cable``, ``RF_cable``, the
  knee springs of :mod:`thesis.physics.models.oncilla`) scaled by ``front_spring_factor``
  (two equal springs in parallel lose half their stiffness when one is removed).
"""

from __future__ import annotations

import functools
import importlib

import jax.numpy as jnp
import numpy as np

from thesis.physics import terrain

# the module (the package re-exports the constructor under the same name)
O = importlib.import_module("thesis.physics.models.oncilla")

#: Knee-spring joints of the front legs (LEGS order LF, RF).
FRONT_KNEE_SPRINGS = ("LF_cable", "RF_cable")


def grade_name(grade: float) -> str:
    """Condition name of a slope given as a grade [percent]: 9 -> ``"grade9"``."""
    return f"grade{float(grade):g}"


def condition_names(cfg) -> tuple[str, ...]:
    """Target conditions of the ``ch4`` config section, in thesis order: the slopes,
    then the softer front legs (``"compliant"``)."""
    return tuple(grade_name(g) for g in cfg["conditions"]["grades"]) + ("compliant",)


def slope_angle(grade: float) -> float:
    """Inclination [rad] of a grade given in percent: atan(grade / 100)."""
    return float(terrain.grade_angle(float(grade) / 100.0))


def on_slope(model, grade: float):
    """``model`` on a slope of ``grade`` percent, uphill along +x (gravity rotated)."""
    return terrain.incline(model, slope_angle(grade))


def front_spring_index(model) -> np.ndarray:
    """Indices into ``model.jspring_k`` of the front knees' extension springs."""
    names = [model.dof_names[int(d)].split(":")[0] for d in model.jspring_dof]
    missing = [j for j in FRONT_KNEE_SPRINGS if j not in names]
    if missing:
        raise ValueError(f"model has no joint spring on {missing}; springs on {names}")
    return np.array([names.index(j) for j in FRONT_KNEE_SPRINGS])


def soft_front_legs(model, factor: float):
    """``model`` with the front knees' extension-spring constants multiplied by ``factor``."""
    idx = front_spring_index(model)
    return model.replace(jspring_k=jnp.asarray(model.jspring_k).at[idx].multiply(factor))


@functools.lru_cache(maxsize=4)
def _oncilla(dt: float, iterations: int, rail: float, slack: float, k: float, c: float):
    return O.oncilla(dt=dt, solver_iterations=iterations, tether_rail_height=rail,
                     tether_slack=slack, tether_stiffness=k, tether_damping=c)


def base_model(cfg):
    """(Model, State) of the flat-ground Oncilla of the ``ch4`` config section, with the
    safety thread of §4.5 (``tether``)."""
    m, t = cfg["model"], cfg["tether"]
    return _oncilla(float(m["dt"]), int(m["solver_iterations"]), float(t["rail_height"]),
                    float(t["slack"]), float(t["stiffness"]), float(t["damping"]))


#: Slack [m] of a thread that never tightens (the robot cannot get this far from the rail).
NEVER_TAUT = 1.0e3


def untethered(model):
    """``model`` with its safety thread never taut (a slack tether applies exactly no
    impulse; same compiled rollout). Zero stiffness is not used: the engine's implicit
    spring row divides by it."""
    return model.replace(tether_slack=jnp.full_like(model.tether_slack, NEVER_TAUT))


def condition_model(cfg, name: str):
    """(Model, State) of condition ``name``: ``"flat"``, a slope (``grade_name``) or
    ``"compliant"`` (see the module docstring)."""
    model, state = base_model(cfg)
    if name == "flat":
        return model, state
    if name == "compliant":
        return soft_front_legs(model, float(cfg["conditions"]["front_spring_factor"])), state
    for g in cfg["conditions"]["grades"]:
        if name == grade_name(g):
            return on_slope(model, g), state
    raise ValueError(f"unknown ch4 condition {name!r}; known: flat, "
                     f"{', '.join(condition_names(cfg))}")
