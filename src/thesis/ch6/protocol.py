"""The training and test protocol of §6.4 as a timeline of per-step signals.

Phases of one run (seconds from the start of the simulation, robot standing in its build
pose):

0. ``settle``: the teacher's commands ease from the build pose into the gait's pose
   (:func:`thesis.gaits.runner.protocol_commands`); not a thesis phase, it keeps the
   first command from jumping.
1. ``normalisation``: the teacher drives the motors; the mean and standard deviation of
   each encoder are recorded (§6.4 "This stage takes 5 s").
2. ``stage1``: first training; the teacher drives, RLS learns, Gaussian noise of
   standard deviation ``input_noise`` is added to the normalised inputs.
3. ``stage2``: second training; the motors receive ``s y + (1 - s) y_hat`` with the
   teacher's share s ramped linearly from 1 to 0 ("reduced over time until it becomes
   zero"); RLS still learns, noise still added.
4. ``running``: RLS off, no noise, the controller alone drives the motors (§6.4 "run
   stably for 30 seconds").
5. ``off``: the servos' maximal torque is 0 (motors powered off), the controller keeps
   running; then the torque is restored.
6. ``recovery``: controller alone; does the gait come back?

The rollout (:mod:`thesis.ch6.loop`) reads the timeline as arrays, one value per
controller step k at time t_k = k Δt: the teacher's share of the motor command, the
servo torque scale, whether RLS learns (and noise is added) and whether the
normalisation statistics accumulate. A phase-1-only run (§6.4 ablation) has
``stage2 = 0``; an open-loop run (the teacher screen) has the teacher's share 1
throughout and never learns.
"""

from __future__ import annotations

import dataclasses

import numpy as np

#: Names of the phase boundaries in time order (see :meth:`Schedule.bounds`).
PHASES = ("settle", "normalisation", "stage1", "stage2", "running", "off", "recovery")


@dataclasses.dataclass(frozen=True)
class Schedule:
    """Durations [s] of the phases of one run (see the module docstring)."""

    settle: float
    normalisation: float
    stage1: float
    stage2: float
    running: float
    off: float
    recovery: float

    def bounds(self) -> dict[str, tuple[float, float]]:
        """Phase name -> (start, end) [s]."""
        out, t = {}, 0.0
        for name in PHASES:
            d = float(getattr(self, name))
            out[name] = (t, t + d)
            t += d
        return out

    @property
    def total(self) -> float:
        """Length of the whole run [s]."""
        return self.bounds()["recovery"][1]


def n_steps(seconds: float, dt: float) -> int:
    """Number of controller steps that cover ``seconds`` at period ``dt`` (rounded up)."""
    return int(np.ceil(seconds / dt - 1e-9))


def signals(schedule: Schedule, dt: float, steps: int, open_loop: bool = False):
    """Per-step protocol signals of one run, each (steps,) float32.

    Returns a dict:
        ``share``: teacher's share of the motor command (1, the stage-2 ramp, then 0);
        ``torque``: servo torque scale (0 while the motors are off, else 1);
        ``learn``: 1 while RLS learns and noise is added (stages 1 and 2);
        ``stats``: 1 while the encoder statistics accumulate (normalisation).
    Steps beyond the schedule's end continue the recovery phase.
    """
    t = np.arange(steps) * dt
    b = schedule.bounds()
    inside = lambda name: (t >= b[name][0] - 1e-9) & (t < b[name][1] - 1e-9)  # noqa: E731
    a, e = b["stage2"]
    ramp = np.clip(1.0 - (t - a) / max(e - a, 1e-12), 0.0, 1.0)
    share = np.where(t < a - 1e-9, 1.0, ramp)
    if open_loop:
        share = np.ones_like(t)
    learn = (inside("stage1") | inside("stage2")) & (not open_loop)
    return dict(share=share.astype(np.float32),
                torque=np.where(inside("off"), 0.0, 1.0).astype(np.float32),
                learn=learn.astype(np.float32),
                stats=inside("normalisation").astype(np.float32))


def window(schedule: Schedule, name: str, dt: float, last: float | None = None,
           skip: float = 0.0) -> slice:
    """Controller steps of phase ``name``: its last ``last`` seconds (None: all of it),
    starting no earlier than ``skip`` seconds into the phase."""
    start, end = schedule.bounds()[name]
    lo = start + skip if last is None else max(start + skip, end - last)
    return slice(n_steps(lo, dt), n_steps(end, dt))
