"""The 64 recorded signals of the simulated Puppy II and the sensor groups of Tab. 5.2.

The thesis names the groups and their sizes (useful 55, reduced 21, minimal 18, leg 12,
agt 10, imu 9, joints 8, touch 4; "64 available in the dataset") and what each contains
(Tab. 5.2): tactile 4, joint angles 8, accelerometer and gyroscope 6, velocity,
compass and distance to wall 1 each, magnetometer 3, "other/derivative sensors". It does
not list the other/derivative signals nor the 9 signals outside every group; this module
fixes them (a declared choice) so that the counts match:

* other/derivative (31): the per-sample differences of the 8 joint angles, the 4 paw
  forces, the accelerometer, gyroscope and magnetometer (3 each); the 4 hip commands and
  their differences; the differences of velocity and compass (wrapped) -- 8 + 4 + 9 + 8
  + 2;
* outside every group (9): camera position x, y, z, the trunk orientation as a
  quaternion (4), the camera's lateral velocity and the trial time.

Order of :data:`NAMES` is the column order of the recordings.
"""

from __future__ import annotations

import numpy as np

__all__ = ["NAMES", "GROUPS", "GROUP_DIMS", "columns"]

_LEGS = ("LF", "RF", "LH", "RH")
_XYZ = ("x", "y", "z")

TOUCH = tuple(f"touch_{leg}" for leg in _LEGS)
JOINTS = tuple(f"hip_{leg}" for leg in _LEGS) + tuple(f"knee_{leg}" for leg in _LEGS)
ACC = tuple(f"acc_{a}" for a in _XYZ)
GYRO = tuple(f"gyro_{a}" for a in _XYZ)
MAG = tuple(f"mag_{a}" for a in _XYZ)
VELOCITY, COMPASS, WALL = ("velocity",), ("compass",), ("wall_distance",)
COMMANDS = tuple(f"command_{leg}" for leg in _LEGS)
OTHER = (tuple(f"d_{n}" for n in JOINTS + TOUCH + ACC + GYRO + MAG) + COMMANDS
         + tuple(f"d_{n}" for n in COMMANDS) + ("d_velocity", "d_compass"))
UNGROUPED = ("pos_x", "pos_y", "pos_z", "quat_w", "quat_x", "quat_y", "quat_z",
             "lateral_velocity", "time")

NAMES: tuple[str, ...] = (TOUCH + JOINTS + ACC + GYRO + MAG + VELOCITY + COMPASS + WALL
                          + OTHER + UNGROUPED)

_MINIMAL = TOUCH + JOINTS + ACC + GYRO
#: Tab. 5.2: group -> signal names.
GROUPS: dict[str, tuple[str, ...]] = {
    "useful": _MINIMAL + VELOCITY + COMPASS + WALL + MAG + OTHER,
    "reduced": _MINIMAL + VELOCITY + COMPASS + WALL,
    "minimal": _MINIMAL,
    "leg": TOUCH + JOINTS,
    "agt": ACC + GYRO + TOUCH,
    "imu": ACC + GYRO + MAG,
    "joints": JOINTS,
    "touch": TOUCH,
}
#: Tab. 5.2 "Number of dimensions".
GROUP_DIMS = {g: len(v) for g, v in GROUPS.items()}


def columns(group: str) -> np.ndarray:
    """Column indices of ``group``'s signals in the recordings."""
    if group not in GROUPS:
        raise KeyError(f"unknown sensor group {group!r}; one of {tuple(GROUPS)}")
    return np.array([NAMES.index(n) for n in GROUPS[group]], int)
