"""Errors the pipeline raises on purpose, each naming what went wrong and where."""

from __future__ import annotations


class ConfigError(ValueError):
    """A profile configuration breaks the schema (names the key and what is allowed)."""


class SimulationDiverged(RuntimeError):
    """A simulation produced a non-finite value; no result may be written.

    Args:
        experiment: registry key of the experiment, e.g. ``"ch7/ball"``.
        seed: the seed of the run that diverged.
        step: the simulation step (or optimisation iteration) where it was detected.
        what: which quantity was non-finite.
    """

    def __init__(self, experiment: str, seed: int, step: int, what: str = "state"):
        self.experiment = experiment
        self.seed = int(seed)
        self.step = int(step)
        self.what = what
        super().__init__(
            f"simulation diverged: experiment={experiment} seed={self.seed} "
            f"step={self.step} ({what} is not finite); no result written"
        )


class MissingInputError(FileNotFoundError):
    """An experiment's input (data file, earlier result) does not exist."""
