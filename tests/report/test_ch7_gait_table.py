"""The ch7 gait table shows the hand-tuned trot search beside the thesis's 0.7 m/s."""

import numpy as np
import xarray as xr

from thesis.report.chapters import ch7
from thesis.report.model import NOT_RUN


def _gait(with_trot: bool) -> xr.Dataset:
    ds = xr.Dataset({"speed": (("seed", "evaluation"), np.array([[0.0, 0.1], [0.0, 0.2]])),
                     "final_speed": (("seed",), np.array([0.1, 0.2]))},
                    coords={"seed": [0, 1], "evaluation": [1, 2]},
                    attrs={"evaluations": 2})
    if with_trot:
        ds["trot_is_trot"] = (("trot_torque", "trot"), np.array([[1, 0, 1], [1, 1, 1]], np.int8))
        ds["hand_tuned_speed"] = ((), 0.3456)
        ds["hand_tuned_upright"] = ((), 2)
        ds["hand_tuned_speed_by_torque"] = ("trot_torque", np.array([0.3456, 0.61]))
        ds = ds.assign_coords(trot_torque=[4.0, 40.0])
        ds.attrs["hand_tuned_trot"] = "frequency_hz=1.5"
    return ds


def test_hand_tuned_row_reports_the_search_or_not_run():
    rows = {r[0]: r for r in ch7.gait_table({"ch7/quadruped_gait": _gait(True)}).rows}
    cell = rows["hand-tuned trot [m/s]"][2]
    assert cell.startswith("0.346") and "3 open-loop trots, 2 upright" in cell
    assert "frequency_hz=1.5" in cell
    assert rows["hand-tuned trot [m/s]"][1] != NOT_RUN  # the thesis's 0.7
    note = ch7.gait_table({"ch7/quadruped_gait": _gait(True)}).note
    assert "4 N m 0.346 m/s, 40 N m 0.610 m/s" in note
    old = {r[0]: r for r in ch7.gait_table({"ch7/quadruped_gait": _gait(False)}).rows}
    assert old["hand-tuned trot [m/s]"][2] == NOT_RUN
    assert old["model evaluations"][2] == "2"
