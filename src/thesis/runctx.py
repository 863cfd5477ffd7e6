"""What an experiment function receives: its configuration, inputs, output and logger."""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class RunContext:
    """Everything an experiment may read.

    Attributes:
        key: registry key, e.g. ``"ch2/table2_2"``.
        profile: scale profile name (``smoke``, ``default``, ``paper``).
        config: the experiment's chapter section of the validated configuration.
        full_config: the whole validated configuration.
        inputs: named input files of the Snakemake rule.
        output: the file the result will be written to.
        log: logger writing to the rule's log.
    """

    key: str
    profile: str
    config: dict[str, Any]
    full_config: dict[str, Any]
    inputs: dict[str, Path] = field(default_factory=dict)
    output: Path | None = None
    log: logging.Logger = field(default_factory=lambda: logging.getLogger("thesis"))

    @property
    def root_seed(self) -> int:
        """Root of every random stream (config key ``root_seed``)."""
        return int(self.full_config["root_seed"])

    @property
    def chapter(self) -> str:
        return self.key.split("/", 1)[0]

    def input(self, name: str) -> Path:
        """The input named ``name``; a clear error if the rule did not pass it."""
        if name not in self.inputs:
            raise KeyError(f"experiment {self.key} needs input {name!r} "
                           f"(pass --input {name}=PATH); got {sorted(self.inputs)}")
        return self.inputs[name]
