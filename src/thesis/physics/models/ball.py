"""The giant soccer ball of thesis §7.2.1 (Fig. 7.3a).

Sources: thesis §7.2.1 ("1 m diameter, a friction of mu = 1.0 and restitution e = 0.5",
starts at (0, 0)); [TPX] ``robotmodel/ball.json`` (docs/sources.md#tpx-ball) (centre height 1.5 m,
density 1000 kg/m^3 -> 523.6 kg, dt 0.01 s, 1 solver iteration, warm start 0.85, no
torsional friction). Contact softness is ours: 25 Hz, critically damped
(``CONTACT_HZ`` of :mod:`thesis.physics.builder`; a physical constant, 0.25 / dt at the
default dt 0.01 s): the original's f/zeta values do not transfer because its
soft-constraint formula differs by a factor dt (docs/sources.md#tpx-step quirk, see
``constraint.py``).
"""

from __future__ import annotations

import jax.numpy as jnp

from thesis.physics.builder import CONTACT_HZ, Builder


def ball(*, dt=0.01, solver_iterations=1, radius=0.5, height=1.5, friction=1.0,
         restitution=0.5, warm_start=0.85, velocity=(0.0, 0.0, 0.0),
         angular_velocity=(0.0, 0.0, 0.0), inertia="solid", gravity=(0.0, 0.0, -9.81),
         contact_hz=None, contact_zeta=1.0, toi_correction=False, dtype=jnp.float32):
    """Ball on a ground plane; returns ``(Model, State)``.

    Args (defaults cited in the module docstring): dt [s]; solver_iterations; radius [m]
    (§7.2.1: 1 m diameter); height of the centre [m] (ball.json); friction, restitution
    (§7.2.1); warm_start; initial velocity [m/s] and angular velocity [rad/s];
    inertia "solid" or "tpx_quirk" (docs/sources.md#tpx-bodies); gravity; contact softness
    ``contact_hz`` [Hz] (None: ``CONTACT_HZ``, 25 Hz, whatever dt) and ``contact_zeta``;
    toi_correction: time-of-impact position correction (``physics.step.toi_correction``;
    not in the original engine); dtype.
    """
    # a single body: its contact rows are decoupled, so no under-relaxation is needed
    b = Builder("ball", dt=dt, solver_iterations=solver_iterations, gravity=gravity,
                warm_start=warm_start, relaxation=1.0, toi_correction=toi_correction)
    hz = CONTACT_HZ if contact_hz is None else contact_hz
    b.add_material("ground", friction, restitution, hz, contact_zeta)
    b.add_plane("floor", (0, 0, 1), 0.0, "ground", color=(0.4, 0.7, 0.3))
    b.add_sphere("ball", radius, (0.0, 0.0, height), inertia=inertia, color=(1, 1, 1))
    b.add_contact_sphere("ball", radius)
    b.set_velocity("ball", velocity, angular_velocity)
    return b.build(dtype)
