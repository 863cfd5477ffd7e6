"""The Puppy II's convergence table (thesis.modelcheck.puppy_convergence, ``thesis validate
puppy``): its per-trial measurements and its follow-up stage on recordings whose answer is
known. The table's layout on real recordings is checked on the smoke pipeline's result
(``tests/pipeline/layouts_model.py``). No test asserts whether the current model converges
(that is what the table reports)."""

from __future__ import annotations

import logging
from types import SimpleNamespace

import numpy as np
import pytest

from thesis import seeding
from thesis.config import load_config
from thesis.modelcheck import convergence_rule as CR
from thesis.modelcheck import puppy_convergence as PC
from thesis.report import validation as RV
from thesis.ch5 import gaits as G
from thesis.ch5 import recordings as R
from thesis.ch5 import sensors as S


def _recordings(tracks, touch_std):
    """Recordings of trials moving along ``tracks`` [(start xy, end xy, samples)] with
    paw forces alternating around 3 N by +-``touch_std``."""
    sig, off, length = [], [], []
    for (a, b, n), sd in zip(tracks, touch_std):
        x = np.zeros((n, len(S.NAMES)), np.float32)
        x[:, [S.NAMES.index("pos_x"), S.NAMES.index("pos_y")]] = np.linspace(a, b, n)
        x[:, [S.NAMES.index(t) for t in S.TOUCH]] = 3.0 + sd * (-1.0) ** np.arange(n)[:, None]
        off.append(sum(length))
        length.append(n)
        sig.append(x)
    k = len(tracks)
    return R.Recordings(signals=np.concatenate(sig), offset=np.array(off),
                        length=np.array(length), terrain=np.zeros(k, int), gait=np.zeros(k, int),
                        frequency=np.ones(k), names=S.NAMES)


def test_trial_speed_is_the_camera_displacement_over_the_trial_duration():
    recs = _recordings([((0, 0), (3, 4), 251), ((1, 1), (1, 1), 51), ((0, 0), (0, 0), 1)],
                       [0.5, 0.0, 0.0])
    sp = PC.trial_speeds(recs, 50.0)
    assert sp[0] == pytest.approx(5.0 / 5.0, rel=1e-6)  # 5 m in 250 / 50 = 5 s
    assert sp[1] == 0.0 and np.isnan(sp[2])
    np.testing.assert_allclose(PC.touch_fluctuation(recs)[:2], [0.5, 0.0], atol=1e-4)


def _fake_generate(calls):
    """A stand-in for :func:`recordings.generate`: each trial walks straight at 0.3 m/s, the
    turn-left cells on Styrofoam at 0.3 m/s x (1 + 0.3 N(0, 1)) drawn from the trial's own
    stream (the same at every setting) and 4 % faster at dt / 2: unpaired too noisy to tell,
    paired a 4 % change."""
    def generate(cfg, root_seed, *, log=None, experiment="x"):
        table = R.trial_table(cfg, seeding.rng(root_seed, experiment + "/trials"))
        calls.append((experiment, cfg["model"]["dt"], len(table),
                      sorted({(t["gait"], t["terrain"], t["frequency"]) for t in table})))
        half = cfg["model"]["dt"] < 0.004
        sig, off, length, gait, terr, freq = [], [], [], [], [], []
        for i, t in enumerate(table):
            n = t["length"]
            v = 0.3
            if (t["gait"], t["terrain"]) == ("turn_left", "S"):
                v *= 1.0 + 0.3 * seeding.rng(root_seed, experiment + "/trial", i).normal()
                v *= 1.04 if half else 1.0
            x = np.zeros((n, len(S.NAMES)), np.float32)
            x[:, S.NAMES.index("pos_x")] = np.linspace(0.0, v * (n - 1) / 50.0, n)
            off.append(sum(length))
            length.append(n)
            sig.append(x)
            gait.append(G.GAITS.index(t["gait"]))
            terr.append(R.TERRAINS.index(t["terrain"]))
            freq.append(t["frequency"])
        recs = R.Recordings(signals=np.concatenate(sig), offset=np.array(off),
                            length=np.array(length), terrain=np.array(terr),
                            gait=np.array(gait), frequency=np.array(freq), names=S.NAMES)
        return recs, dict(wall_seconds=0.0, planned_length=length)
    return generate


def test_followup_reruns_only_the_undecided_cells(monkeypatch):
    calls = []
    monkeypatch.setattr(PC.R, "generate", _fake_generate(calls))
    config = load_config("smoke", overrides={"physics": {"puppy_convergence": dict(
        samples=20, trials_per_cell=20, followup_trials=40, speed_tolerance=0.10)}})
    ctx = SimpleNamespace(full_config=config, root_seed=int(config["root_seed"]),
                          key="model/puppy_convergence", log=logging.getLogger("test"))
    ds = PC.convergence(ctx)
    noisy = {("turn_left", "S", f) for (g, t), counts in R.TAB5_1.items()
             for f, n in zip(R.FREQUENCIES, counts) if n and (g, t) == ("turn_left", "S")}
    # the table: three settings of every cell, then the follow-up's three of the noisy only
    assert [c[0] for c in calls] == [PC.EXPERIMENT] * 3 + [PC.EXPERIMENT + "/followup"] * 3
    assert all(set(c[3]) == noisy and c[2] == 40 * len(noisy) for c in calls[3:])
    # unpaired, the noisy cells are undecided at both settings (even where nothing moved)
    assert ds["stage1_verdict"].values.tolist() == [CR.INCONCLUSIVE, CR.INCONCLUSIVE]
    followed = {(str(ds["case_gait"].values[c]), str(ds["case_terrain"].values[c]),
                 float(ds["case_frequency"].values[c])) for c in ds["followed_case"].values}
    assert followed == noisy and ds.attrs["followup_ran"] == 1
    # paired, the 4 % change is inside the tolerance: converged at both settings
    np.testing.assert_allclose(ds["followup_speed_change"].sel(refined="dt/2").values, 0.04,
                               atol=1e-6)
    assert ds["verdict"].values.tolist() == [CR.CONVERGED, CR.CONVERGED]
    assert ds.attrs["verdict"] == CR.CONVERGED
    assert float(ds["max_speed_change"].sel(refined="dt/2")) == pytest.approx(0.04, abs=1e-6)
    t = RV.puppy_convergence_table({"model/puppy_convergence": ds})
    assert "Follow-up stage" in t.note
    assert any("40 pairs" in str(cell) for row in t.rows for cell in row)
    # at the schema's 3 % the same paired 4 % change is beyond the tolerance
    strict = load_config("smoke", overrides={"physics": {"puppy_convergence": dict(
        samples=20, trials_per_cell=20, followup_trials=40)}})
    assert strict["physics"]["puppy_convergence"]["speed_tolerance"] == 0.03
    ds = PC.convergence(SimpleNamespace(**{**vars(ctx), "full_config": strict}))
    assert ds["verdict"].values.tolist() == [CR.NOT_CONVERGED, CR.CONVERGED]
