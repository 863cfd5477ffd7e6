"""The classification pipelines of chapter 5 (§5.2, Fig. 5.1): PCA -> expansion -> readout.

=========  ==================================  ==============================
method     expansion of the PCA outputs         readout
=========  ==================================  ==============================
``lr``     EMA (eq. 5.2)                        least squares (eq. 5.1)
``elm``    leaky ELM (§5.2.2)                   least squares
``rc``     leaky ESN (§5.2.3)                   least squares
``sfa2``   EMA, then quadratic expansion        SFA -> FastICA -> naive Bayes
``elm_sfa`` leaky ELM                           SFA -> FastICA -> naive Bayes
``rc_sfa`` leaky ESN                            SFA -> FastICA -> naive Bayes
=========  ==================================  ==============================

PCA comes first in every pipeline "with the dimension reduction rate as a parameter"
(§5.4.1.1): it keeps ``max(1, round(pca_rate * D))`` of the D inputs' principal
components, fitted on the training set (``sklearn.decomposition.PCA``). The
unsupervised pipelines fit SFA (``n_slow`` slowest features) and FastICA
(``sklearn.decomposition.FastICA``, ``whiten="unit-variance"``, as many components)
without labels; only the naive-Bayes readout sees them (§5.3.2). FastICA's contrast is
its default log cosh, whose derivative tanh is evaluated in single precision
(:func:`logcosh_contrast`): the fixed-point iteration spends most of its time in that
tanh, single precision is ~4x faster, and its 1e-7 relative error is far below the
iteration's tolerance (1e-4). SFA2 gets the same
EMA low-pass as LR in front of its expansion (a choice: the thesis is silent on it and
filters every other method's noisy inputs).

Hyper-parameters (tuned by :mod:`thesis.ch5.tuning`): ``pca_rate`` (all), ``leak``
(all), ``input_scaling`` (ELM, RC and their SFA variants), ``spectral_radius`` (RC,
RC-SFA). Random weights come in a :class:`Draw` (one per seed and node count), so that
ELM and RC of the same seed share ``W_in``.

Evaluation runs in chunks of parts (every stage is causal within a part), so memory
stays bounded for the whole test set.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from thesis.ch5 import readout, reservoir, sfa
from thesis.ch5.protocol import Parts, flat

__all__ = ["METHODS", "PARAMS", "SUPERVISED", "Draw", "draw", "fit", "predict",
           "evaluate", "logcosh_contrast", "expand_raw"]

#: Hyper-parameters of each method, in CMA-ES order.
PARAMS: dict[str, tuple[str, ...]] = {
    "lr": ("pca_rate", "leak"),
    "elm": ("pca_rate", "leak", "input_scaling"),
    "rc": ("pca_rate", "leak", "input_scaling", "spectral_radius"),
    "sfa2": ("pca_rate", "leak"),
    "elm_sfa": ("pca_rate", "leak", "input_scaling"),
    "rc_sfa": ("pca_rate", "leak", "input_scaling", "spectral_radius"),
}
METHODS = tuple(PARAMS)
SUPERVISED = ("lr", "elm", "rc")
_HIDDEN = {"elm": "elm", "rc": "esn", "elm_sfa": "elm", "rc_sfa": "esn"}
#: Largest float count of one evaluation chunk (P_chunk x T x features).
CHUNK_FLOATS = 2e7


@dataclass(frozen=True)
class Draw:
    """Random weights of one seed: ``w_in`` (N, D_max) on {-1, 0, 1}, ``w_res`` (N, N)
    with spectral radius 1. A pipeline with K PCA components uses ``w_in[:, :K]``."""

    w_in: np.ndarray
    w_res: np.ndarray


def draw(rng: np.random.Generator, n_nodes: int, max_inputs: int) -> Draw:
    """Draw the hidden layer of a seed (§5.2.2-5.2.3)."""
    return Draw(w_in=reservoir.input_weights(rng, n_nodes, max_inputs),
                w_res=reservoir.reservoir_weights(rng, n_nodes))


@dataclass
class Fitted:
    """A pipeline fitted on a training set (internal)."""

    method: str
    params: dict
    pca: Any
    w_in: np.ndarray | None
    w_res: np.ndarray | None
    lin: np.ndarray | None = None
    sfa: Any = None
    ica: Any = None
    bayes: Any = None


def logcosh_contrast(x: np.ndarray, alpha: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """FastICA's log-cosh contrast for ``sklearn.decomposition.FastICA(fun=...)``.

    G(u) = log cosh(alpha u) / alpha (Hyvarinen's FastICA, sklearn's ``"logcosh"``): returns
    g(u) = tanh(alpha u), (k, n) in float64 from a float32 tanh, and the mean over the
    samples of g'(u) = alpha (1 - g(u)^2), (k,). Args: x (k, n) projections W X.
    """
    g = np.tanh(np.asarray(x, np.float32) * np.float32(alpha)).astype(np.float64)
    return g, float(alpha) * (1.0 - g * g).mean(axis=-1)


def _pca_project(pca, x: np.ndarray) -> np.ndarray:
    p, t, d = x.shape
    return pca.transform(x.reshape(-1, d)).reshape(p, t, -1)


def _expand(f: Fitted, x: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """(P, T, F) expansion of padded PCA outputs ``x``."""
    leak = float(f.params["leak"])
    kind = _HIDDEN.get(f.method)
    if kind is None:
        z = reservoir.ema(x, leak)
        return sfa.quadratic_expansion(z) if f.method == "sfa2" else z
    if kind == "elm":
        return reservoir.elm_states(x, f.w_in, leak)
    return reservoir.esn_states(x, lengths, f.w_in, f.w_res, leak)


def _chunks(parts: Parts, width: int):
    per = max(1, int(CHUNK_FLOATS // max(1, parts.x.shape[1] * width)))
    for a in range(0, len(parts.length), per):
        yield parts.take(slice(a, a + per))


def _features(f: Fitted, parts: Parts) -> np.ndarray:
    """(n_samples, F) expansion of every valid step of ``parts``."""
    z = _pca_project(f.pca, parts.x)
    return flat(_expand(f, z, parts.length), parts.length)


def fit(method: str, params: dict, weights: Draw | None, train: Parts, n_classes: int, *,
        n_slow: int = 4, n_bins: int = 20, ica_seed: int = 0,
        ica_max_iter: int = 1000) -> Fitted:
    """Fit ``method`` with hyper-parameters ``params`` on ``train``.

    Args:
        weights: the seed's hidden layer (None for LR and SFA2).
        n_slow: SFA outputs and ICA components (unsupervised methods).
        n_bins: histogram bins of the naive-Bayes readout.
        ica_seed: FastICA's random_state.
    """
    from sklearn.decomposition import PCA, FastICA

    if method not in PARAMS:
        raise ValueError(f"unknown method {method!r}; one of {METHODS}")
    d = train.x.shape[2]
    k = max(1, min(d, int(round(float(params["pca_rate"]) * d))))
    pca = PCA(n_components=k, svd_solver="covariance_eigh").fit(flat(train.x, train.length))
    f = Fitted(method=method, params=dict(params), pca=pca,
               **_scaled_weights(method, params, weights, k))
    z = _pca_project(pca, train.x)
    h = _expand(f, z, train.length)
    labels = train.labels()
    if method in SUPERVISED:
        f.lin = readout.fit_linear(flat(h, train.length), labels, n_classes)
        return f
    f.sfa = sfa.fit_sfa(h, train.length, n_slow)
    slow = flat(f.sfa.transform(h), train.length)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # FastICA convergence warnings: max_iter is ours
        f.ica = FastICA(n_components=slow.shape[1], whiten="unit-variance", random_state=ica_seed,
                        max_iter=ica_max_iter, fun=logcosh_contrast).fit(slow)
    f.bayes = readout.fit_bayes(f.ica.transform(slow), labels, n_classes, n_bins)
    return f


def _scaled_weights(method: str, params: dict, weights: Draw | None, n_inputs: int) -> dict:
    """``w_in`` (the first ``n_inputs`` input columns times the input scaling) and
    ``w_res`` (times the spectral radius) of a hidden-layer method; None where unused."""
    w_in = w_res = None
    if method in _HIDDEN:
        w_in = weights.w_in[:, :n_inputs] * float(params["input_scaling"])
        if _HIDDEN[method] == "esn":
            w_res = weights.w_res * float(params["spectral_radius"])
    return dict(w_in=w_in, w_res=w_res)


def predict(f: Fitted, parts: Parts) -> np.ndarray:
    """(n_samples,) predicted terrain of every valid step of ``parts`` (flat order)."""
    k = int(f.pca.n_components_)
    width = f.w_in.shape[0] if f.w_in is not None else (k * (k + 1) // 2 if
                                                         f.method == "sfa2" else k)
    out = []
    for chunk in _chunks(parts, max(width, parts.x.shape[2], 1)):
        h = _features(f, chunk)
        if f.lin is not None:
            out.append(readout.predict_linear(f.lin, h))
        else:
            out.append(readout.predict_bayes(f.bayes, f.ica.transform(f.sfa.transform(h))))
    return np.concatenate(out) if out else np.zeros((0,), int)


def expand_raw(method: str, params: dict, weights: Draw | None, parts: Parts) -> np.ndarray:
    """(n_samples, F) expansion of ``method`` (§5.2, Fig. 5.1 without PCA) of every valid
    step of ``parts`` (flat order): the EMA (LR, SFA2's quadratic expansion on it), leaky
    ELM or leaky ESN applied to all D inputs of ``parts`` (``w_in[:, :D]`` times the input
    scaling). Fitting nothing, it is the same for every training set: the separability
    measurement (:mod:`thesis.ch5.separability`) computes it once per trial."""
    if method not in PARAMS:
        raise ValueError(f"unknown method {method!r}; one of {METHODS}")
    d = parts.x.shape[2]
    f = Fitted(method=method, params=dict(params), pca=None,
               **_scaled_weights(method, params, weights, d))
    w_in = f.w_in
    width = w_in.shape[0] if w_in is not None else (d * (d + 1) // 2 if method == "sfa2"
                                                    else d)
    out = [flat(_expand(f, c.x, c.length), c.length) for c in _chunks(parts, max(width, d))]
    return np.concatenate(out) if out else np.zeros((0, width))


def evaluate(method: str, params: dict, weights: Draw | None, train: Parts,
             tests: list[Parts], n_classes: int, **kwargs) -> tuple[np.ndarray, list]:
    """Fit on ``train``; predictions on ``train`` and on each of ``tests``."""
    f = fit(method, params, weights, train, n_classes, **kwargs)
    return predict(f, train), [predict(f, t) for t in tests]
