"""The teacher table of the ch6 report: fixed teachers and a screen say what they are."""

from __future__ import annotations

import numpy as np
import xarray as xr

from thesis.report.chapters import ch6


def _teacher(names, passed, source):
    cd = ("candidate",)
    ds = xr.Dataset(
        dict(candidate_up_seconds=(cd, np.full(len(names), 50.0)),
             candidate_speed=(cd, np.linspace(0.1, 0.4, len(names))),
             candidate_rec_speed=(cd, np.full(len(names), 0.1)),
             candidate_passed=(cd, np.array(passed, float)),
             chosen=(("gait",), np.array([0, len(names) - 1])),
             teacher_passed=(("gait",), np.array([passed[0], passed[-1]], float))),
        coords=dict(candidate=names, gait=["trot", "walk"]))
    ds.attrs["teacher_source"] = source
    return ds


def test_fixed_teachers_that_fail_the_check_are_named_as_such():
    ds = _teacher(["trot/half_ellipse/fixed", "walk/half_ellipse/fixed"], [1, 0], "fixed")
    t = ch6.teacher_table({"ch6/teacher": ds})
    assert [r[-1] for r in t.rows] == ["teacher", "teacher"]
    assert [r[-2] for r in t.rows] == ["yes", "no"]
    assert "fixed trot and walk teachers" in t.note
    assert "The fixed walk teacher did not pass this check" in t.note
    assert "No walk candidate passed" not in t.note and "fixed trot teacher" not in t.note


def test_a_screen_names_its_candidates_and_a_fallback():
    names = ["trot/spline/seed0/stride1", "trot/spline/seed0/stride0.5",
             "walk/spline/seed0/stride1"]
    t = ch6.teacher_table({"ch6/teacher": _teacher(names, [1, 1, 0], "screen")})
    assert "chapter 3's optima" in t.note and "No walk candidate passed" in t.note
    assert [r[-1] for r in t.rows] == ["teacher", "", "teacher"]
