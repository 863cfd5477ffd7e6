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
    """An experiment's input (data file, earlier result) does not exist; the message names
    it, its role and the command that makes it (:func:`thesis.store.check_input`)."""


class DamagedFileError(OSError):
    """A result or input file exists but cannot be used: unreadable, truncated, empty, of a
    foreign format, or holding another artifact's dataset (:func:`thesis.store.open_result`,
    :func:`thesis.store.check_input`).

    The message is one line: the path, its role, the cause and the command that remakes it.

    Args:
        path: the damaged file, as it was given or found.
        role: what the file is to the pipeline, e.g. ``"result ch3/table3_1 (chapter 3,
            profile default)"`` or ``"input 'teacher' of experiment ch6/trot"``.
        cause: what is wrong, e.g. ``"truncated: 20000 of 61234 bytes on disk"``.
        remake: the shell command that remakes it (a Snakemake target).
    """

    def __init__(self, path, role: str, cause: str, remake: str):
        self.path = str(path)
        self.role = role
        self.cause = " ".join(str(cause).split())  # one line, whatever the library wrote
        self.remake = remake
        super().__init__(f"{self.path} ({role}) cannot be used: {self.cause}; "
                         f"remake it with: {remake}")

    def to_dict(self) -> dict[str, str]:
        """``path``, ``role``, ``cause``, ``remake`` and the one-line ``message`` (JSON)."""
        return {"path": self.path, "role": self.role, "cause": self.cause,
                "remake": self.remake, "message": str(self)}
