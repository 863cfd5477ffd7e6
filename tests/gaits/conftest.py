"""Standard NumPy promotion for the gait tests (an explicit exception to tests/conftest.py).

The gait functions (``thesis.gaits.leg``, ``thesis.gaits.trajectories``) are documented
as broadcasting their joint-angle and time arguments NumPy-style over leading
dimensions; that broadcasting is their contract, so the strict rank promotion that
guards the engine would reject correct calls here. Strict settings stay on for every
other test folder.
"""

from __future__ import annotations

import jax
import pytest


@pytest.fixture(autouse=True)
def _standard_promotion():
    with jax.numpy_rank_promotion("allow"), jax.numpy_dtype_promotion("standard"):
        yield
