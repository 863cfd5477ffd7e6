"""The recordings file: Tab. 5.1's trial table, and corrupt or mismatched files stop the
classifiers with the file and trial named."""

import h5py
import numpy as np
import pytest

from thesis.ch5 import recordings as R
from thesis.ch5 import sensors as S


def test_trial_table_has_the_counts_of_tab5_1():
    cfg = {"recordings": {"samples": {"default": [3000, 6500]}}}
    table = R.trial_table(cfg, np.random.default_rng(0))
    assert len(table) == sum(sum(c) for c in R.TAB5_1.values())
    assert sum(t["gait"] == "random" for t in table) == 11
    assert all(3000 <= t["length"] <= 6500 for t in table)
    capped = R.trial_table({"recordings": {"samples": {"default": [100, 100]},
                                           "max_trials_per_cell": 1}},
                           np.random.default_rng(0))
    assert len(capped) == sum(sum(1 for n in c if n) for c in R.TAB5_1.values())
    exact = R.trial_table({"recordings": {"samples": {"default": [100, 100]},
                                          "trials_per_frequency": 4,
                                          "max_trials_per_cell": 1}},
                          np.random.default_rng(0))
    assert len(exact) == 4 * len(capped)  # 4 per non-empty cell, whatever Tab. 5.1 says
    assert {(t["gait"], t["terrain"], t["frequency"]) for t in exact} \
        == {(t["gait"], t["terrain"], t["frequency"]) for t in capped}


def _recs(n_trials=3, length=50):
    rng = np.random.default_rng(0)
    return R.Recordings(
        signals=rng.normal(size=(n_trials * length, len(S.NAMES))).astype(np.float32),
        offset=np.arange(n_trials) * length, length=np.full(n_trials, length),
        terrain=np.arange(n_trials) % 5, gait=np.zeros(n_trials, int),
        frequency=np.ones(n_trials), names=S.NAMES)


def test_round_trip(tmp_path):
    path = tmp_path / "rec.h5"
    R.write(path, _recs(), {"stopped_trials": [1]})
    got = R.load(path)
    np.testing.assert_array_equal(got.signals, _recs().signals)
    assert got.n_trials == 3 and got.stopped_trials == (1,) and got.path == str(path)


def test_nan_names_file_and_trial(tmp_path):
    recs = _recs()
    recs.signals[120, 7] = np.nan  # trial 2 (samples 100-149)
    path = tmp_path / "nan.h5"
    R.write(path, recs, {})
    with pytest.raises(R.RecordingError, match=r"nan\.h5: trial 2 .*sample 20"):
        R.load(path)


def test_wrong_shape_and_missing_file(tmp_path):
    path = tmp_path / "narrow.h5"
    R.write(path, _recs(), {})
    with h5py.File(path, "a") as f:
        del f["signals"]
        f.create_dataset("signals", data=np.zeros((150, 10), np.float32))
    with pytest.raises(R.RecordingError, match=r"narrow\.h5: signals have shape \(150, 10\)"):
        R.load(path)
    path = tmp_path / "short.h5"
    recs = _recs()
    R.write(path, R.Recordings(**{**recs.__dict__, "length": np.array([50, 50, 80])}), {})
    with pytest.raises(R.RecordingError, match=r"short\.h5: trial 2 spans"):
        R.load(path)
    with pytest.raises(R.RecordingError, match="no such recordings file"):
        R.load(tmp_path / "absent.h5")
    (tmp_path / "junk.h5").write_bytes(b"not hdf5")
    with pytest.raises(R.RecordingError, match=r"junk\.h5: not a valid recordings file"):
        R.load(tmp_path / "junk.h5")


def test_fsr_clips_at_its_range_reads_nothing_below_actuation_and_more_while_unloading():
    """The paw force sensor as the FSR 402 of docs/sources.md#ch5-touch: 0 below the
    actuation force, clipped at the range, +hysteresis while the force falls, a per-sample
    gain error of sd ``repeatability``."""
    touch = dict(actuation=0.1, range=10.0, repeatability=0.0, hysteresis=0.1)
    rng = np.random.default_rng(0)
    f = np.array([0.05, 2.0, 4.0, 12.0, 3.0, 0.0])[:, None] * np.ones((1, 4))
    r = R.fsr(f, touch, rng)
    np.testing.assert_allclose(r[:, 0], [0.0, 2.0, 4.0, 10.0, 3.3, 0.0])
    touch["repeatability"] = 0.02
    steady = np.full((20000, 4), 5.0)
    r = R.fsr(steady, touch, rng)
    assert abs(np.std(r / 5.0 - 1.0) - 0.02) < 0.001
    assert abs(np.mean(r) - 5.0) < 0.01
