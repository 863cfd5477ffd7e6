"""The environments of chapter 4 (§4.6) as changes of the Oncilla model's leaves.

One compiled rollout serves every condition whose topology is the flat Oncilla's: the
slopes and the softer front legs change only model leaves (gravity, spring constants),
so the batched simulation of :mod:`thesis.gaits.runner` is compiled once for all of them.

* **Slopes** (§4.6.1, "a 9% and an 18% grade, or a 5.14° and a 10.2° slope"): gravity
  rotated by θ = atan(grade), uphill along +x (:func:`thesis.physics.terrain.incline`).
  For the single infinite floor plane this is the physics of an inclined treadmill seen
  in the belt's frame; the fall test (trunk height above the plane, tilt of the trunk
  against the plane's normal) keeps its meaning.
* **Safety thread** (§4.5): every condition runs with the thread from the head to an
  overhead rail (``tether`` config; :func:`untethered` removes it).
* **Pebbles** (§4.6.3, "a flat surface covered in pebbles ... with a diameter of
  approximately 1 cm"): the engine's static sphere field (``oncilla(field=...)``) of
  equal spheres resting on the floor, scattered uniformly over a strip along x
  (:func:`pebble_layout`); each evaluation starts at its own random place along the strip
  (:func:`start_range`), so every particle meets another arrangement. A different
  topology from the other conditions: compiled once more. The robot starts set down on
  the pebbles from just above them (:func:`above_pebbles`), as the assistant put it on the
  treadmill by hand. Its contact rows take the field's own relaxation
  (``pebbles.contact_relaxation``): the model's diverges where a foot touches the floor
  and several pebbles at once.
* **Softer front legs** (§4.6.2, "removing one of the two springs in each of the robot's
  front legs"): the extension spring of the front knees (``LF_cable``, ``RF_cable``, the
  knee springs of :mod:`thesis.physics.models.oncilla`) scaled by ``front_spring_factor``
  (two equal springs in parallel lose half their stiffness when one is removed).
"""

from __future__ import annotations

import functools
import importlib
import json

import jax
import jax.numpy as jnp
import numpy as np

from thesis import seeding
from thesis.gaits import runner as R
from thesis.physics import terrain
from thesis.physics.models.oncilla_config import oncilla_from_config, oncilla_kwargs
from thesis.physics.step import tether_geometry

# the module (the package re-exports the constructor under the same name)
O = importlib.import_module("thesis.physics.models.oncilla")

#: Knee-spring joints of the front legs (LEGS order LF, RF).
FRONT_KNEE_SPRINGS = ("LF_cable", "RF_cable")


def grade_name(grade: float) -> str:
    """Condition name of a slope given as a grade [percent]: 9 -> ``"grade9"``."""
    return f"grade{float(grade):g}"


def condition_names(cfg) -> tuple[str, ...]:
    """Target conditions of the ``ch4`` config section, in thesis order: the slopes,
    the softer front legs (``"compliant"``) and the pebbles (``"pebbly"``)."""
    return tuple(grade_name(g) for g in cfg["conditions"]["grades"]) + ("compliant", "pebbly")


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


def base_model(cfg):
    """(Model, State) of the flat-ground Oncilla of the ``ch4`` config section, with the
    safety thread of §4.5 (``tether``;
    :func:`thesis.physics.models.oncilla_config.oncilla_from_config`)."""
    return oncilla_from_config(cfg["model"], cfg["tether"])


#: Slack [m] of a thread that never tightens (the robot cannot get this far from the rail).
NEVER_TAUT = 1.0e3


def untethered(model):
    """``model`` with its safety thread never taut (a slack tether applies exactly no
    impulse; same compiled rollout). Zero stiffness is not used: the engine's implicit
    spring row divides by it."""
    return model.replace(tether_slack=jnp.full_like(model.tether_slack, NEVER_TAUT))


def thread_load(model, sim, t_start, t_end) -> dict:
    """How much the safety threads carried each robot over its window (§4.5: the thread
    "is loose during normal operation"), from the poses of a
    :func:`thesis.gaits.runner.simulate` result.

    Each thread's distance d from its rail (the engine's
    :func:`thesis.physics.step.tether_geometry`) is taken at every 10-ms pose; its
    tension is estimated as ``k (d - slack) + c d'`` (``d'`` by finite differences of
    the poses), clipped at 0 and counted only while ``d > slack``: the quasi-static
    spring-damper force, not the solver's impulse.

    Args:
        model: the tethered Oncilla (any number of threads; none gives zeros).
        sim: a ``simulate`` result (``pos`` (B, K, n_body, 3), ``rot``, ``t`` (K,)).
        t_start, t_end: scalars or (B,) window bounds [s].

    Returns:
        dict of (B,) arrays: ``taut`` [1] (fraction of the window's poses with any thread
        taut) and ``thread_force`` [N] (window mean of the threads' summed tension).
    """
    pos, rot, t = sim["pos"], sim["rot"], sim["t"]
    B = pos.shape[0]
    if not model.tether_names:
        return dict(taut=np.zeros(B), thread_force=np.zeros(B))
    distance = jax.vmap(jax.vmap(lambda p, r: tether_geometry(model, p, r)[1]))
    d = np.asarray(distance(pos, rot), np.float64)  # (B, K, n_tether)
    slack = np.asarray(model.tether_slack, np.float64)
    rate = np.gradient(d, t, axis=1)
    taut = d > slack
    force = np.where(taut, np.maximum(np.asarray(model.tether_k, np.float64) * (d - slack)
                                      + np.asarray(model.tether_c, np.float64) * rate, 0.0),
                     0.0).sum(-1)
    w = R.window(t, t_start, t_end, B)
    n = np.maximum(w.sum(1), 1)
    with np.errstate(invalid="ignore"):
        return dict(taut=(taut.any(-1) & w).sum(1) / n,
                    thread_force=np.where(w, force, 0.0).sum(1) / n)


#: Fastest walk [m/s] a pebble strip must leave room for (twice the thesis's fastest gait).
MAX_WALK_SPEED = 1.5


def pebble_layout(cfg, root_seed: int) -> tuple[np.ndarray, float]:
    """Pebble centres (N, 3) [m] and radius [m] of the ``pebbles`` config: N spheres of
    the configured diameter resting on the floor (centre height = radius), uniformly
    scattered over x in [0, strip_length], |y| <= strip_width / 2, with N the expected
    count of the configured coverage (footprint area over strip area, overlaps allowed).
    One layout per profile, from the stream ``ch4/pebbles/layout`` of the root seed."""
    pc = cfg["pebbles"]
    r = 0.5 * float(pc["diameter"])
    L, W = float(pc["strip_length"]), float(pc["strip_width"])
    n = int(round(float(pc["coverage"]) * L * W / (np.pi * r * r)))
    rng = seeding.rng(root_seed, "ch4/pebbles/layout", 0)
    centres = np.column_stack([rng.uniform(0.0, L, n), rng.uniform(-W / 2, W / 2, n),
                               np.full(n, r)])
    return centres, r


def start_range(cfg, name: str, duration: float):
    """(lo, hi) [m] of the random start along x of an evaluation of ``duration`` [s] on
    condition ``name``, or None where the floor is the same everywhere. The robot starts
    at least ``start_margin`` into the strip and keeps that margin ahead of a walk at
    :data:`MAX_WALK_SPEED`."""
    if name != "pebbly":
        return None
    pc = cfg["pebbles"]
    lo = float(pc["start_margin"])
    hi = float(pc["strip_length"]) - lo - MAX_WALK_SPEED * float(duration)
    if hi <= lo:
        raise ValueError(f"config ch4.pebbles.strip_length = {pc['strip_length']} leaves no "
                         f"room for random starts of a {duration:g} s evaluation; it must "
                         f"exceed {2 * lo + MAX_WALK_SPEED * float(duration):g} m")
    return lo, hi


def above_pebbles(state, diameter: float):
    """``state`` with every body raised by the pebbles' ``diameter`` [m].

    The Oncilla's start pose stands on the bare floor. Moved to a start among the pebbles
    its feet would overlap pebbles by up to their diameter, which no robot put on the belt
    does, and the solver would push them out within the first steps. Raised by the
    diameter, no contact sphere can overlap a pebble resting on the floor, whatever its
    start; the robot then settles onto the pebbles, a drop of at most one diameter, during
    the protocol's settle time."""
    return state.replace(pos=state.pos.at[..., 2].add(jnp.asarray(diameter, state.pos.dtype)))


@functools.lru_cache(maxsize=2)
def _pebbly(key: str, root_seed: int):
    cfg = json.loads(key)
    centres, r = pebble_layout(cfg, root_seed)
    kw = oncilla_kwargs(cfg["model"], cfg["tether"])
    kw["contact_relaxation"] = float(cfg["pebbles"]["contact_relaxation"])
    model, state = O.oncilla(**kw, field=dict(name="pebbles", centres=centres, radii=r,
                                              k=int(cfg["pebbles"]["k"])))
    return model, above_pebbles(state, 2.0 * r)


def condition_model(cfg, name: str, root_seed: int | None = None):
    """(Model, State) of condition ``name``: ``"flat"``, a slope (``grade_name``),
    ``"compliant"`` or ``"pebbly"`` (which needs the profile's ``root_seed`` for its
    layout); see the module docstring."""
    if name == "pebbly":
        if root_seed is None:
            raise ValueError("the pebbly condition needs the root seed of its layout")
        key = json.dumps({k: cfg[k] for k in ("model", "tether", "pebbles")}, sort_keys=True)
        return _pebbly(key, int(root_seed))
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
