"""The simulated Oncilla of a configuration section: the one mapping of its keys to
:func:`thesis.physics.models.oncilla.oncilla` arguments.

Chapters 3, 4 and 6 (and the model's validation) configure the robot in a ``model``
section (config/schema.yaml: ``dt``, ``solver_iterations``, ``knee_spring``,
``warm_start``, ``relaxation``, ``sweep_order``, ``contact_relaxation``,
``row_relaxation``, the momentum order's ``momentum`` and ``restart``, in ch6 the
constraint softness ``joint_hz`` / ``contact_hz``, the feet: ``feet`` (``sphere`` or
``plate``) with the plates' ``foot_length`` and ``foot_width``, and the drives'
``drive_stiffness``, their damping following at ``DRIVE_DAMPING_RATIO``) and
chapter 4 its safety thread in a ``tether`` section (§4.5). A key a section does not
have keeps :func:`oncilla`'s default.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping

from thesis.physics.models.oncilla import DRIVE_DAMPING_RATIO, oncilla

__all__ = ["oncilla_from_config", "oncilla_kwargs"]

#: ``model`` keys passed on when present, with :func:`oncilla`'s default otherwise.
_OPTIONAL_FLOATS = ("joint_hz", "contact_hz", "momentum")
#: The foot plates' keys, passed on only with ``feet: plate`` (the sphere feet have none).
_PLATE_FLOATS = ("foot_length", "foot_width")


def oncilla_kwargs(model: Mapping, tether: Mapping | None = None) -> dict:
    """:func:`oncilla` keyword arguments of a ``model`` config section and, when given,
    a ``tether`` section (``rail_height`` [m], ``slack`` [m], ``stiffness`` [N/m],
    ``damping`` [N s/m], ``width`` [m]). ``contact_relaxation`` (``row_relaxation``)
    null or absent: None (the contact rows (the other scalar rows) take ``relaxation``);
    ``restart`` is the momentum order's ``momentum_restart``; ``drive_stiffness`` [N m/rad]
    sets ``drive_damping`` to ``drive_stiffness / DRIVE_DAMPING_RATIO`` [N m s/rad]."""
    cr = model.get("contact_relaxation")
    rr = model.get("row_relaxation")
    kw = dict(dt=float(model["dt"]), solver_iterations=int(model["solver_iterations"]),
              knee_spring=float(model["knee_spring"]), warm_start=float(model["warm_start"]),
              relaxation=float(model["relaxation"]), sweep_order=str(model["sweep_order"]),
              contact_relaxation=None if cr is None else float(cr),
              row_relaxation=None if rr is None else float(rr))
    if "drive_stiffness" in model:  # the damping keeps the drives' time constant
        kw["drive_stiffness"] = float(model["drive_stiffness"])
        kw["drive_damping"] = kw["drive_stiffness"] / DRIVE_DAMPING_RATIO
    if "restart" in model:
        kw["momentum_restart"] = bool(model["restart"])
    kw.update({k: float(model[k]) for k in _OPTIONAL_FLOATS if k in model})
    if model.get("feet", "sphere") != "sphere":
        kw["feet"] = str(model["feet"])
        kw.update({k: float(model[k]) for k in _PLATE_FLOATS if k in model})
    if tether is not None:
        kw.update(tether_rail_height=float(tether["rail_height"]),
                  tether_slack=float(tether["slack"]),
                  tether_stiffness=float(tether["stiffness"]),
                  tether_damping=float(tether["damping"]), tether_width=float(tether["width"]))
    return kw


@functools.lru_cache(maxsize=8)
def _build(kwargs: tuple):
    return oncilla(**dict(kwargs))


def oncilla_from_config(model: Mapping, tether: Mapping | None = None):
    """``(Model, State)`` of the Oncilla that a ``model`` (and ``tether``) config section
    describe (:func:`oncilla_kwargs`); built once per distinct configuration and process
    (a model is immutable, so callers share it)."""
    return _build(tuple(sorted(oncilla_kwargs(model, tether).items())))
