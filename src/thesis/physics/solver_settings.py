"""Solver settings of a built model from a config mapping: the sweep order and its factors
(thesis.physics.solver; docs/architecture.md#engine-rules), so that a bench or a chapter
can run any model under another order without rebuilding it.
"""

from __future__ import annotations

from collections.abc import Mapping

import jax.numpy as jnp

__all__ = ["solver_fields", "with_solver"]


def solver_fields(settings: Mapping[str, object], dtype=jnp.float32) -> dict:
    """:class:`~thesis.physics.types.Model` fields of ``settings``, a mapping with any of
    ``sweep_order``, ``relaxation``, ``contact_relaxation``, ``row_relaxation`` (None:
    the model's relaxation), ``momentum``, ``restart`` and ``solver_iterations``; keys
    absent or None (except the two factors that take None) keep the model's value.
    ``relaxation`` becomes an array of ``dtype`` (a traced field of the model)."""
    kw: dict = {}
    if settings.get("sweep_order") is not None:
        kw["sweep_order"] = str(settings["sweep_order"])
    if settings.get("relaxation") is not None:
        kw["relaxation"] = jnp.asarray(float(settings["relaxation"]), dtype)
    for key in ("contact_relaxation", "row_relaxation"):
        if key in settings:
            v = settings[key]
            kw[key] = None if v is None else float(v)
    if settings.get("momentum") is not None:
        kw["momentum"] = float(settings["momentum"])
    if settings.get("restart") is not None:
        kw["momentum_restart"] = bool(settings["restart"])
    if settings.get("solver_iterations") is not None:
        kw["solver_iterations"] = int(settings["solver_iterations"])
    return kw


def with_solver(model, settings: Mapping[str, object]):
    """``model`` with the solver fields of ``settings`` (:func:`solver_fields`), the
    relaxation in the model's own float type."""
    return model.replace(**solver_fields(settings, model.body_mass.dtype))
