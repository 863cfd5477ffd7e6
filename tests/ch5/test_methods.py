"""The pipelines on synthetic two-terrain data whose answer is known."""

import numpy as np

from thesis.ch5 import methods as M
from thesis.ch5 import protocol as P
from thesis.ch5 import tuning as T


def _parts(seed, n_parts=12, T_=60, noise=1.0):
    """Terrain 0 and 1 differ in amplitude of a 1 Hz oscillation in input 0 (an energy
    feature); inputs 1-2 are noise."""
    rng = np.random.default_rng(seed)
    x = rng.normal(0, noise, (n_parts, T_, 3))
    label = np.arange(n_parts) % 2
    t = np.arange(T_) / 10.0
    for i in range(n_parts):
        x[i, :, 0] += (1 + 2 * label[i]) * np.sin(2 * np.pi * t + rng.uniform(0, 6))
    return P.Parts(x=x, length=np.full(n_parts, T_), label=label, trial=np.arange(n_parts))


def _harmonic_parts(seed, n_parts=12, T_=60):
    """Terrain 0 and 1 differ only in the sign of a second harmonic in input 1 that is
    phase-locked to a 1 Hz oscillation in input 0: every input is zero-mean with the same
    spectrum in both terrains, so a linear readout of low-passed inputs is at chance, while
    the cubic terms of a tanh layer (sin^2 * cos 2) have a class-dependent mean."""
    rng = np.random.default_rng(seed)
    x = rng.normal(0, 0.3, (n_parts, T_, 3))
    label = np.arange(n_parts) % 2
    t = np.arange(T_) / 10.0
    for i in range(n_parts):
        phase = 2 * np.pi * t + rng.uniform(0, 6)
        x[i, :, 0] += np.sin(phase)
        x[i, :, 1] += (1 - 2 * label[i]) * np.cos(2 * phase)
    return P.Parts(x=x, length=np.full(n_parts, T_), label=label, trial=np.arange(n_parts))


def test_reservoir_and_elm_learn_a_nonlinear_feature_lr_cannot():
    train, test = _harmonic_parts(0), _harmonic_parts(1)
    d = M.draw(np.random.default_rng(2), 50, 3)
    base = dict(pca_rate=1.0, leak=0.5, input_scaling=1.0, spectral_radius=0.5)
    _, (rc,) = M.evaluate("rc", base, d, train, [test], 2)
    _, (elm,) = M.evaluate("elm", base, d, train, [test], 2)
    _, (lr,) = M.evaluate("lr", dict(pca_rate=1.0, leak=0.5), None, train, [test], 2)
    assert P.accuracy(rc, test.labels()) > 85
    assert P.accuracy(elm, test.labels()) > 80
    assert P.accuracy(lr, test.labels()) < 65


def test_unsupervised_pipelines_beat_chance():
    """RC-SFA and ELM-SFA find the cubic feature of the harmonic data; SFA2's quadratic
    expansion cannot (degree 2), but finds the energy feature of the amplitude data."""
    train, test = _harmonic_parts(3, n_parts=20, T_=100), _harmonic_parts(4, n_parts=20, T_=100)
    d = M.draw(np.random.default_rng(5), 40, 3)
    p = dict(pca_rate=1.0, leak=0.05, input_scaling=1.0, spectral_radius=0.5)
    for method in ("rc_sfa", "elm_sfa"):
        _, (pred,) = M.evaluate(method, p, d, train, [test], 2, n_slow=2)
        assert P.accuracy(pred, test.labels()) > 85, method
    train, test = _parts(3, n_parts=20, T_=100), _parts(4, n_parts=20, T_=100)
    _, (pred,) = M.evaluate("sfa2", dict(pca_rate=1.0, leak=0.5), None, train, [test], 2,
                            n_slow=2)
    assert pred.shape == (test.n_samples,)
    assert P.accuracy(pred, test.labels()) > 65


def test_elm_and_rc_share_input_weights():
    d = M.draw(np.random.default_rng(0), 10, 5)
    f_elm = M.fit("elm", dict(pca_rate=0.6, leak=0.5, input_scaling=2.0), d, _parts(0), 2)
    f_rc = M.fit("rc", dict(pca_rate=0.6, leak=0.5, input_scaling=2.0, spectral_radius=1.0),
                 d, _parts(0), 2)
    np.testing.assert_array_equal(f_elm.w_in, f_rc.w_in)
    k = f_elm.pca.n_components_
    assert f_elm.w_in.shape == (10, k) and k < 3
    np.testing.assert_array_equal(f_elm.w_in, 2.0 * d.w_in[:, :k])


def test_cma_tuning_finds_a_known_optimum():
    res = T.tune(lambda p: -(p["pca_rate"] - 0.7) ** 2 - (p["spectral_radius"] - 1.2) ** 2,
                 ("pca_rate", "spectral_radius"),
                 {"pca_rate": (0.1, 1.0), "spectral_radius": (0.0, 1.5)}, seed=3,
                 generations=30)
    assert T.popsize(2) == 6 and T.popsize(4) == 8
    assert abs(res["best"]["pca_rate"] - 0.7) < 0.05
    assert abs(res["best"]["spectral_radius"] - 1.2) < 0.05


def test_decode_is_log_for_leak():
    p = T.decode([0.0, 1.0, 0.5], ("leak", "input_scaling", "pca_rate"),
                 {"leak": (0.001, 1.0), "input_scaling": (0.01, 1.0), "pca_rate": (0.0, 1.0)})
    assert abs(p["leak"] - 0.001) < 1e-12 and abs(p["input_scaling"] - 1.0) < 1e-12
    assert p["pca_rate"] == 0.5


def test_logcosh_contrast_is_sklearns_logcosh_to_single_precision():
    from sklearn.decomposition._fastica import _logcosh

    x = np.random.default_rng(0).normal(0, 3, (4, 5000))
    g, dg = M.logcosh_contrast(x)
    g_ref, dg_ref = _logcosh(x.copy(), {"alpha": 1.0})
    assert g.dtype == np.float64 and g.shape == x.shape and dg.shape == (4,)
    np.testing.assert_allclose(g, g_ref, atol=2e-7)
    np.testing.assert_allclose(dg, dg_ref, atol=2e-7)
    g2, dg2 = M.logcosh_contrast(x, alpha=1.5)
    np.testing.assert_allclose(g2, np.tanh(1.5 * x), atol=2e-7)
    np.testing.assert_allclose(dg2, (1.5 * (1 - np.tanh(1.5 * x) ** 2)).mean(-1), atol=3e-7)


def test_fastica_with_the_single_precision_contrast_unmixes_like_the_default():
    """Same sources, same seed: the unmixing matrix equals sklearn's own log cosh run."""
    from sklearn.decomposition import FastICA

    rng = np.random.default_rng(1)
    t = np.linspace(0, 40, 8000)
    s = np.c_[np.sign(np.sin(1.3 * t)), np.sin(2.1 * t), rng.laplace(size=t.size)]
    x = s @ rng.normal(size=(3, 3))
    ref = FastICA(3, whiten="unit-variance", random_state=0, max_iter=1000).fit(x)
    ours = FastICA(3, whiten="unit-variance", random_state=0, max_iter=1000,
                   fun=M.logcosh_contrast).fit(x)
    np.testing.assert_allclose(ours.components_, ref.components_, atol=1e-4)
    corr = np.abs(np.corrcoef(ours.transform(x).T, s.T)[:3, 3:])
    assert np.all(corr.max(axis=1) > 0.99)
