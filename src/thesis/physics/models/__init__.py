"""Robot and scene models of chapter 7 built with the engine's builder.

Each constructor takes keyword overrides (time step, solver iterations, servo limits,
camera pixels, dtype ...) so profiles can change them, and returns ``(Model, State)``.
Every number cites its source: the thesis section, or docs/sources.md (the original engine's robot
files: #tpx-ball, #tpx-arm, #tpx-quadruped, #tpx-pendulum).
"""

from thesis.physics.models.arm4 import arm4 as arm4
from thesis.physics.models.ball import ball as ball
from thesis.physics.models.cartpole import cartpole as cartpole
from thesis.physics.models.oncilla import oncilla as oncilla
from thesis.physics.models.quadruped import quadruped as quadruped

#: name -> constructor
MODELS = {"ball": ball, "arm4": arm4, "quadruped": quadruped, "cartpole": cartpole,
          "oncilla": oncilla}

__all__ = ["ball", "arm4", "quadruped", "cartpole", "oncilla", "MODELS"]
