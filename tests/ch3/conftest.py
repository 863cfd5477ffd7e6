"""Standard NumPy promotion for this chapter's gait tests, as for the shared gait library's
(tests/gaits/conftest.py says why: the gait functions broadcast NumPy-style by contract)."""

from ..gaits.conftest import _standard_promotion  # noqa: F401  (autouse fixture)
