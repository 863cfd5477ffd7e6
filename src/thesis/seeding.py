"""Explicit, named random streams derived from the profile's root seed.

Every random number of the pipeline comes from here: a stream is identified by the
root seed of the profile, a name (usually the experiment key, e.g. ``"ch2/table2_2"``)
and a per-run seed index. Names are hashed (SHA-256) so streams of different
experiments never overlap, and adding an experiment never changes another one's numbers.
"""

from __future__ import annotations

import hashlib

import numpy as np


def _name_word(name: str) -> int:
    return int.from_bytes(hashlib.sha256(name.encode()).digest()[:4], "little")


def seed_sequence(root_seed: int, name: str, seed: int = 0) -> np.random.SeedSequence:
    """NumPy ``SeedSequence`` for stream ``(root_seed, name, seed)``."""
    return np.random.SeedSequence([int(root_seed), _name_word(name), int(seed)])


def rng(root_seed: int, name: str, seed: int = 0) -> np.random.Generator:
    """NumPy generator (PCG64) for stream ``(root_seed, name, seed)``."""
    return np.random.default_rng(seed_sequence(root_seed, name, seed))


def int_seed(root_seed: int, name: str, seed: int = 0) -> int:
    """A 31-bit integer seed for libraries that take one (``cma``, scikit-learn)."""
    return int(seed_sequence(root_seed, name, seed).generate_state(1)[0] & 0x7FFFFFFF)


def key(root_seed: int, name: str, seed: int = 0):
    """JAX PRNG key for stream ``(root_seed, name, seed)``."""
    import jax

    return jax.random.key(int_seed(root_seed, name, seed))
