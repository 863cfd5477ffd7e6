"""Workarounds for engine behaviour that blocks the ch7 experiments (documented, minimal).

* Dead band at exactly zero error: the engine switches a position servo on only where
  ``|q - q_cmd| > deadband`` (``thesis.physics.constraint``), so with a dead band of 0 the
  servo row -- and with it every gradient with respect to the command -- is exactly zero
  while the error is exactly zero. With the zero-output initial policy of §7.3.2 the
  commands equal the initial joint angles (0), so the very first gradient of every
  controller would be zero and training would never start. The thesis states no dead band
  (§7.3.2: gain, torque and velocity only), so :func:`without_deadband` sets a negative
  dead band, for which the test ``|error| > deadband`` always holds (no dead band, and the
  servo acts, with its gradient, at zero error too).
"""

from __future__ import annotations

import jax.numpy as jnp

__all__ = ["NO_DEADBAND", "without_deadband"]

#: A dead band below zero: ``|error| > NO_DEADBAND`` is always true.
NO_DEADBAND = -1.0


def without_deadband(model):
    """Copy of ``model`` whose position servos have no dead band (see module docstring)."""
    if model.n_servo == 0:
        return model
    return model.replace(servo_deadband=jnp.full_like(model.servo_deadband, NO_DEADBAND))
