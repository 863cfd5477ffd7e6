"""The Oncilla gait library shared by chapters 3, 4 and 6 and the model checks (a library
like :mod:`thesis.physics`, not a chapter: the chapters' experiments live in
:mod:`thesis.ch3`, :mod:`thesis.ch4` and :mod:`thesis.ch6`).

Modules: leg kinematics of the pantographic leg (:mod:`.leg`), the sine / half-ellipse /
Bézier trot families (:mod:`.trajectories`), smooth gait transitions
(:mod:`.transitions`), the batched gait simulation and its speed and fall terms
(:mod:`.runner`), and the environments of §4.6 as model changes (:mod:`.conditions`, also
the model checks' flat and untethered Oncilla)."""

from thesis.gaits import leg as leg
from thesis.gaits import trajectories as trajectories
from thesis.gaits import transitions as transitions
from thesis.gaits.leg import JOINTS as JOINTS
from thesis.gaits.leg import LEGS as LEGS
from thesis.gaits.leg import LegGeometry as LegGeometry
from thesis.gaits.leg import forward as forward
from thesis.gaits.leg import forward3d as forward3d
from thesis.gaits.leg import inverse as inverse
from thesis.gaits.leg import inverse3d as inverse3d
from thesis.gaits.leg import oncilla_geometry as oncilla_geometry
from thesis.gaits.leg import reach_boundary as reach_boundary
from thesis.gaits.leg import reachable as reachable
from thesis.gaits.trajectories import COMMAND_DT as COMMAND_DT
from thesis.gaits.trajectories import FAMILIES as FAMILIES
from thesis.gaits.trajectories import TROT_PHASE as TROT_PHASE
from thesis.gaits.trajectories import WALK_PHASE as WALK_PHASE
from thesis.gaits.trajectories import EllipseGait as EllipseGait
from thesis.gaits.trajectories import SineGait as SineGait
from thesis.gaits.trajectories import SplineGait as SplineGait
from thesis.gaits.trajectories import command_series as command_series
from thesis.gaits.trajectories import theoretical_speed as theoretical_speed
from thesis.gaits.transitions import schedule_commands as schedule_commands
from thesis.gaits.transitions import schedule_state as schedule_state
from thesis.gaits.transitions import transition_commands as transition_commands
from thesis.gaits.transitions import transition_state as transition_state

__all__ = [
    "COMMAND_DT", "FAMILIES", "JOINTS", "LEGS", "TROT_PHASE", "WALK_PHASE", "EllipseGait", "LegGeometry", "SineGait",
    "SplineGait", "command_series", "forward", "forward3d", "inverse", "inverse3d", "leg", "oncilla_geometry",
    "reach_boundary", "reachable", "schedule_commands", "schedule_state", "theoretical_speed",
    "trajectories", "transition_commands", "transition_state", "transitions",
]
