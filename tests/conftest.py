"""Strict JAX settings for every test (STYLE "What our project should absorb", point 7).

* ``jax_numpy_rank_promotion = "raise"``: no silent broadcasting between arrays of
  different ranks (scalars excepted), so shape bugs fail loudly;
* ``jax_numpy_dtype_promotion = "strict"``: no silent float32 -> float64 promotion;
* the ``x64`` fixture runs a test in float64 (gradient and finite-difference checks).
Tests never assert wall-clock time; long ones carry the ``slow`` marker.

``make test`` runs pytest on two workers (pytest-xdist, ``--dist loadfile``): the tests
that read the smoke pipeline live in one module (``tests/pipeline/test_smoke.py``), so they
share one worker and its session fixture runs once; they come first, because the pipeline
is the longest job of the suite, and the other pipeline module (the real changes,
``tests/pipeline/test_smoke_changes.py``, which reads only the committed references) goes
to the other worker while the pipeline runs.
"""

from __future__ import annotations

# thesis first: its import pins numpy's and OpenBLAS's CPU code paths (thesis.cpupins),
# which they read when they load, and jax loads numpy
import thesis  # noqa: F401, I001

import jax
import pytest

jax.config.update("jax_numpy_rank_promotion", "raise")
jax.config.update("jax_numpy_dtype_promotion", "strict")


@pytest.fixture
def x64():
    """Enable float64 for the duration of one test, then restore the previous setting."""
    previous = jax.config.jax_enable_x64
    jax.config.update("jax_enable_x64", True)
    try:
        yield
    finally:
        jax.config.update("jax_enable_x64", previous)


def pytest_collection_modifyitems(config, items):
    """The smoke pipeline's tests first (see module docstring); the sort is stable."""
    items.sort(key=lambda item: item.get_closest_marker("pipeline") is None)
