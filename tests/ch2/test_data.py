"""Tests of the cluttered MNIST sequence synthesiser (§2.5) and the IDX reader."""

import gzip

import h5py
import numpy as np
import pytest

from thesis.ch2.data import (DIGIT, INTENSITY_SCALE, Canvases, DigitPools, dequantise,
                                load_pools,
                                open_split, quantise, read_split, synthesise, synthesise_h5,
                                training_memory_mb, write_h5)
from thesis.config import load_config
from thesis.errors import ConfigError
from thesis.ch2.idx import read_idx, write_idx


def _fake_digits(n=40, seed=0):
    rng = np.random.default_rng(seed)
    digits = np.zeros((n, 28, 28), np.float32)
    digits[:, 4:24, 6:22] = rng.uniform(0.5, 1.0, (n, 20, 16))  # a bright block per digit
    return digits, np.arange(n) % 10


def test_layout_rules_on_generated_samples():
    digits, labels = _fake_digits()
    rng = np.random.default_rng(1)
    x, y, layouts = synthesise(digits, labels, 300, rng, return_layout=True)
    assert x.shape == (300, 100, 100) and x.dtype == np.float32
    assert y.shape == (300, 3)
    assert x.min() >= 0.0 and x.max() <= 1.0
    slopes = []
    for s, lay in enumerate(layouts):
        assert lay.digit_xy.shape == (3, 2)
        assert len(lay.clutter_xy) == 8  # 8 clutter patches
        xs, ys = lay.digit_xy[:, 0], lay.digit_xy[:, 1]
        assert np.all(np.diff(xs) == DIGIT)  # side by side, no overlap
        assert xs.min() >= 0 and xs.max() + DIGIT <= 100  # sequence fits on the canvas
        assert ys.min() >= 0 and ys.max() + DIGIT <= 100
        dy = np.diff(ys)
        assert np.all(np.abs(dy) <= DIGIT)  # slope within +-45 degrees
        assert abs(lay.slope_deg) <= 45.0
        assert np.all(np.abs(dy - DIGIT * np.tan(np.radians(lay.slope_deg))) <= 1.0)
        assert lay.clutter_xy.min() >= 0 and lay.clutter_xy.max() <= 100 - 9
        slopes.append(lay.slope_deg)
        # the digits are on the canvas where the layout says
        for (dx, dyy), lab in zip(lay.digit_xy, y[s]):
            assert x[s, dyy + 4 : dyy + 24, dx + 6 : dx + 22].min() >= 0.5
    assert set(np.unique(y)) == set(range(10))
    assert min(slopes) < -30 and max(slopes) > 30  # the whole slope range is used


def test_clutter_count_and_size_on_empty_digits():
    """With digits that are zero except one marked patch, the clutter is exactly visible."""
    digits = np.ones((5, 28, 28), np.float32)
    x, _, layouts = synthesise(digits, np.zeros(5, int), 20, np.random.default_rng(2),
                               n_digits=0, return_layout=True)
    for img, lay in zip(x, layouts):
        mask = np.zeros((100, 100), bool)
        for px, py in lay.clutter_xy:
            mask[py : py + 9, px : px + 9] = True
        np.testing.assert_array_equal(img > 0, mask)  # 8 patches of 9 x 9, nothing else


def test_synthesis_is_seeded():
    digits, labels = _fake_digits()
    a = synthesise(digits, labels, 5, np.random.default_rng(3))
    b = synthesise(digits, labels, 5, np.random.default_rng(3))
    c = synthesise(digits, labels, 5, np.random.default_rng(4))
    np.testing.assert_array_equal(a[0], b[0])
    assert np.abs(a[0] - c[0]).max() > 0


def test_idx_roundtrip_and_gzip(tmp_path):
    imgs = np.random.default_rng(0).integers(0, 256, (7, 28, 28)).astype(np.uint8)
    labs = np.arange(7, dtype=np.uint8)
    write_idx(tmp_path / "imgs", imgs)
    raw = (tmp_path / "imgs").read_bytes()
    assert raw[:4] == bytes([0, 0, 0x08, 3])
    assert int.from_bytes(raw[4:8], "big") == 7
    np.testing.assert_array_equal(read_idx(tmp_path / "imgs"), imgs)
    with gzip.open(tmp_path / "labs.gz", "wb") as f:
        f.write(bytes([0, 0, 0x08, 1]) + (7).to_bytes(4, "big") + labs.tobytes())
    np.testing.assert_array_equal(read_idx(tmp_path / "labs.gz"), labs)
    f32 = np.linspace(-1, 1, 6, dtype=np.float32).reshape(2, 3)
    write_idx(tmp_path / "f", f32)
    np.testing.assert_array_equal(read_idx(tmp_path / "f"), f32)
    (tmp_path / "bad").write_bytes(b"\x01\x02\x08\x01" + bytes(8))
    with pytest.raises(ValueError):
        read_idx(tmp_path / "bad")
    (tmp_path / "short").write_bytes(raw[:-5])
    with pytest.raises(ValueError):
        read_idx(tmp_path / "short")


def test_idx_pools(tmp_path):
    rng = np.random.default_rng(0)
    paths = {}
    for split, n in (("train", 30), ("test", 12)):
        write_idx(tmp_path / f"{split}-images", rng.integers(0, 256, (n, 28, 28)).astype(np.uint8))
        write_idx(tmp_path / f"{split}-labels", (np.arange(n) % 10).astype(np.uint8))
        paths[f"{split}_images"] = str(tmp_path / f"{split}-images")
        paths[f"{split}_labels"] = str(tmp_path / f"{split}-labels")
    pools = load_pools({"mnist_idx": paths, "idx_valid_pool": 10}, np.random.default_rng(0))
    assert len(pools.images["train"]) == 20 and len(pools.images["valid"]) == 10
    assert len(pools.images["test"]) == 12
    assert pools.images["train"].max() <= 1.0
    assert "IDX" in pools.source


def test_embedded_pools_are_disjoint():
    pools = load_pools({"mnist_idx": None, "embedded_test_fraction": 0.2}, np.random.default_rng(0))
    tr = pools.images["train"].reshape(len(pools.images["train"]), -1)
    te = pools.images["test"].reshape(len(pools.images["test"]), -1)
    assert len(tr) == 4000 and len(te) == 1000
    assert np.bincount(pools.labels["test"]).tolist() == [100] * 10
    tr_set = {r.tobytes() for r in tr}
    assert sum(r.tobytes() in tr_set for r in te) <= 2  # MNIST has a few exact duplicates at most
    np.testing.assert_array_equal(pools.images["valid"], pools.images["train"])  # valid from train pool


def test_h5_roundtrip(tmp_path):
    digits, labels = _fake_digits()
    x, y = synthesise(digits, labels, 4, np.random.default_rng(0))
    write_h5(tmp_path / "d.h5", {"train": (x, y)}, {"seed": 3})
    xr_, yr = read_split(tmp_path / "d.h5", "train")
    np.testing.assert_allclose(xr_, x, atol=0.5 / 255 + 1e-7)
    np.testing.assert_array_equal(yr, y)


def _old_stored_and_seen(x):
    """The reference quantisation, written out independently of the module: uint8
    round(clip(x) * 255), read back as a whole split as float32 q * (1 / 255)."""
    q = np.round(np.clip(x, 0, 1) * 255).astype(np.uint8)
    return q, q.astype(np.float32) * np.float32(1.0 / 255.0)


def test_uint8_round_trip_gives_the_values_training_saw(tmp_path):
    """The file holds uint8; every way of reading it (whole split, slices, index arrays of
    a mini-batch) gives bit for bit the reference's float32 values."""
    digits, labels = _fake_digits()
    x, y = synthesise(digits, labels, 40, np.random.default_rng(5))
    x[0, :3, :3] = [[-0.2, 1.3, 0.5], [1 / 255, 0.5 / 255, 254.5 / 255], [1.0, 0.0, 0.999]]
    q_old, seen_old = _old_stored_and_seen(x)
    np.testing.assert_array_equal(quantise(x), q_old)
    write_h5(tmp_path / "d.h5", {"train": (x, y)}, {})
    with h5py.File(tmp_path / "d.h5") as f:
        assert f["train/images"].dtype == np.uint8
        np.testing.assert_array_equal(f["train/images"][:], q_old)
        assert f.attrs["intensity_scale"] == INTENSITY_SCALE
    whole, yw = read_split(tmp_path / "d.h5", "train")
    assert whole.dtype == np.float32
    assert whole.tobytes() == seen_old.tobytes()  # bit-identical, not merely close
    canv, yc = open_split(tmp_path / "d.h5", "train")
    assert isinstance(canv, Canvases) and canv.stored.dtype == np.uint8
    assert canv.shape == x.shape and len(canv) == 40 and canv.dtype == np.float32
    idx = np.sort(np.random.default_rng(0).permutation(40)[:7])  # a mini-batch, as train()
    assert canv[idx].dtype == np.float32
    assert canv[idx].tobytes() == seen_old[idx].tobytes()
    assert canv[10:25].tobytes() == seen_old[10:25].tobytes()
    assert np.asarray(canv).tobytes() == seen_old.tobytes()
    np.testing.assert_array_equal(yc, y)
    np.testing.assert_array_equal(yw, y)
    assert dequantise(q_old).tobytes() == seen_old.tobytes()
    assert seen_old.min() == 0.0 and seen_old.max() == 1.0


def test_canvases_refuse_float_storage():
    with pytest.raises(TypeError, match="uint8"):
        Canvases(np.zeros((2, 4, 4), np.float32))


@pytest.mark.parametrize("block", [1, 3, 7, 256, 10_000])
def test_blockwise_synthesis_writes_the_same_file_contents(tmp_path, block):
    """synthesise_h5 block by block = one synthesise() over each split, written by write_h5."""
    digits, labels = _fake_digits()
    pools = DigitPools(images={"train": digits, "test": digits[:20]},
                       labels={"train": labels, "test": labels[:20]}, source="fake")
    sizes = {"train": 11, "test": 5}
    layout = dict(canvas=90, n_clutter=4)
    whole = {s: synthesise(pools.images[s], pools.labels[s], n, np.random.default_rng(i),
                           **layout) for i, (s, n) in enumerate(sizes.items())}
    write_h5(tmp_path / "whole.h5", whole, {"a": 1})
    rngs = {s: np.random.default_rng(i) for i, s in enumerate(sizes)}
    synthesise_h5(tmp_path / "blocks.h5", pools, sizes, rngs, {"a": 1}, block=block, **layout)
    with h5py.File(tmp_path / "whole.h5") as a, h5py.File(tmp_path / "blocks.h5") as b:
        assert dict(a.attrs) == dict(b.attrs)
        for s in sizes:
            for k in ("images", "labels"):
                assert a[s][k].dtype == b[s][k].dtype == np.uint8
                assert a[s][k].chunks == b[s][k].chunks
                np.testing.assert_array_equal(a[s][k][:], b[s][k][:])
            assert a[s].attrs["n"] == b[s].attrs["n"] == sizes[s]


@pytest.mark.parametrize("key,value", [("n_train", 0), ("n_valid", -5), ("n_test", 0),
                                       ("n_train", 1.5), ("canvas", 50)])
def test_bad_data_size_is_named_by_the_schema(key, value):
    with pytest.raises(ConfigError, match=rf"ch2\.data\.{key}"):
        load_config("default", overrides={"ch2": {"data": {key: value}}})


@pytest.mark.parametrize("value", [0, -1, "many"])
def test_bad_epoch_sequences_is_named_by_the_schema(value):
    with pytest.raises(ConfigError, match=r"ch2\.train\.epoch_sequences"):
        load_config("smoke", overrides={"ch2": {"train": {"epoch_sequences": value}}})


def test_training_memory_covers_the_canvases_held_in_memory():
    # the splits are held as uint8 (1 byte per pixel); with float32 canvases (11 500
    # sequences, 460 MB) RNN-SPN was measured at 1.1 GB resident
    small = {"n_train": 10000, "n_valid": 500, "n_test": 1000, "canvas": 100}
    big = {**small, "n_train": 60000, "n_valid": 10000, "n_test": 10000}
    assert training_memory_mb(small) >= 1100 + 460
    # grows with the data (twice the uint8 canvases), not a constant
    assert training_memory_mb(big) - training_memory_mb(small) == pytest.approx(
        2 * (80000 - 11500) * 100 * 100 / 1e6, abs=1)
    assert training_memory_mb(big) < 1500 + 80000 * 100 * 100 * 4 / 1e6  # not float32
