"""Tab. 7.1 in the report: thesis, engine and the MJX / MuJoCo C peers side by side."""

import numpy as np
import xarray as xr

from thesis.report.chapters import ch7
from thesis.report.model import NOT_RUN

DIMS = ("device", "batch", "n_params", "gradient")
COORDS = {"device": ["cpu"], "batch": [1, 128], "n_params": [1296, 1147904], "gradient": [0, 1]}


def _ours(value):
    return xr.Dataset({"seconds": (DIMS, np.full((1, 2, 2, 2), value))}, coords=COORDS)


def _peers(mjx, c):
    sec = np.stack([np.full((1, 2, 2, 2), mjx), np.full((1, 2, 2, 2), c)])
    sec[1, ..., 1] = np.nan  # MuJoCo C has no gradient
    fin = np.zeros((2, 1, 2, 2, 2))
    return xr.Dataset({"seconds": (("engine", *DIMS), sec),
                       "gradient_finite": (("engine", *DIMS), fin)},
                      coords={"engine": ["mjx", "mujoco_c"], **COORDS})


def test_peers_beside_the_engine_with_the_ratio():
    t = ch7.table7_1_table({"ch7/table7_1": _ours(2.0), "ch7/table7_1_peers": _peers(1.0, 3.0)})
    assert t.id == "table7_1" and len(t.rows) == 8
    first = t.rows[0]  # 1 robot, 1,296 parameters, no gradient
    assert first[:4] == ["1", "1,296", "no", "1.06"]  # the thesis's CPU column
    assert first[4:] == ["2", "1", "0.50", "3"]
    grad = t.rows[1]  # MJX's gradient is not finite: marked, and no ratio
    assert grad[5] == "1 (diverged: gradient not finite)" and grad[6] == "— (MJX diverged)"
    assert grad[7] == "—"


def test_a_peer_whose_rollout_diverged_is_marked_and_has_no_ratio():
    peers = _peers(1.0, 3.0)
    peers["distance_finite"] = xr.ones_like(peers["seconds"])
    peers["distance_finite"].loc[dict(engine="mjx", batch=1, n_params=1296, gradient=0)] = 0.0
    peers["distance_finite"].loc[dict(engine="mujoco_c", batch=128, n_params=1296,
                                      gradient=0)] = 0.0
    t = ch7.table7_1_table({"ch7/table7_1": _ours(2.0), "ch7/table7_1_peers": peers})
    rows = {(r[0], r[1], r[2]): r for r in t.rows}
    bad = rows[("1", "1,296", "no")]
    assert bad[5] == "1 (diverged: distance not finite)" and bad[6] == "— (MJX diverged)"
    assert bad[7] == "3"  # MuJoCo C of that cell stayed finite
    c_bad = rows[("128", "1,296", "no")]
    assert c_bad[5] == "1" and c_bad[6] == "0.50"
    assert c_bad[7] == "3 (diverged: distance not finite)"
    sane = rows[("1", "1,147,904", "no")]
    assert sane[5:] == ["1", "0.50", "3"]


def test_without_peers_the_peer_cells_say_not_run():
    t = ch7.table7_1_table({"ch7/table7_1": _ours(2.0)})
    assert all(r[5] == NOT_RUN and r[6] == NOT_RUN for r in t.rows)
    assert all(r[4] == "2" for r in t.rows)
