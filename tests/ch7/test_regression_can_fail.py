"""A deliberately broken engine fails the smoke regression.

The ch7 ball experiment is run in-process at the smoke profile with the sign of the
engine's gravity flipped, and must not agree with the committed reference
``tests/regression/smoke/ch7/ball.json``; that the unbroken experiment agrees with it is
``tests/pipeline/test_smoke.py::test_smoke_numbers_match_references`` (the same
experiment, configuration and comparison, run by the pipeline). Slow: one smoke-sized
run of the experiment (compilation included).
"""

from __future__ import annotations

import functools
import json
import logging
from pathlib import Path

import jax
import pytest

from thesis import regression
from thesis.config import load_config
from thesis.runctx import RunContext

pytestmark = pytest.mark.slow

REFERENCE = Path(__file__).resolve().parents[1] / "regression" / "smoke" / "ch7" / "ball.json"


def _smoke_ball():
    from thesis.ch7.ball import ball

    cfg = load_config("smoke")
    ctx = RunContext(key="ch7/ball", profile="smoke", config=cfg["ch7"], full_config=cfg,
                     log=logging.getLogger("test"))
    with jax.numpy_dtype_promotion("standard"):  # optax mixes int and float internally
        return ball(ctx)


def test_flipped_gravity_fails_the_ball_regression(monkeypatch):
    import thesis.ch7.ball as ball_mod

    ref = json.loads(REFERENCE.read_text())
    flipped = functools.partial(ball_mod.ball_model, gravity=(0.0, 0.0, 9.81))
    monkeypatch.setattr(ball_mod, "ball_model", flipped)
    problems = regression.compare(_smoke_ball(), ref)
    assert problems, "a ball falling upwards passed the smoke regression"
    # the simulated losses themselves move, not only bookkeeping
    assert any("'gradient_loss'" in p or "'cmaes_loss'" in p for p in problems), problems
