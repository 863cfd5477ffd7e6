"""FFN-SPN and RNN-SPN of Tab. 2.1 in plain JAX (parameters as pytrees, explicit keys).

Both networks are: localisation network -> P transform parameters (P = 4 or 6, linear
dense layer initialised at W = 0, b = identity, as [RSTN]) -> spatial transform layer
(:mod:`thesis.ch2.transforms`, output side N // d) -> classification network.

- FFN-SPN: localisation = [2x2 maxpool, 3x3 conv (loc_filters), 2x2 maxpool, 3x3 conv,
  2x2 maxpool, 3x3 conv, dense (loc_dense)]; classifier = [3x3 conv (cls_filters), 2x2
  maxpool, dropout, 3x3 conv, 2x2 maxpool, dropout, 3x3 conv, dropout, dense (cls_dense),
  dense 3 x 10 + softmax per digit] (one transform, three heads).
- RNN-SPN: the same localisation convolutions, their features repeated at every step of
  a GRU (gru_units), one dense P per step -> one transform per digit; the classifier
  (filters cls_filters) and its dense 10 + softmax are shared over the steps. Optionally
  (``step_shift`` != 0, not in the thesis) step t's x translation is offset by a constant
  so that the steps start on different crops instead of the same identity crop.
- With the transform ``none`` there is no localisation network and no down-sampling:
  the classifier sees the whole canvas (approach 4 of §2.5); the FFN has three heads
  and the RNN applies its shared classifier to the same image at every step, with the
  step's GRU state (driven by the classifier features) selecting the digit.

Convolutions are 'valid' with ReLU, pools floor the size (Lasagne defaults,
docs/sources.md#rstn-training); weights are Glorot-uniform, biases zero. Images are
(B, S, S) in [0, 1]; logits are (B, n_digits, 10).
"""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
from jax import lax

from thesis.ch2.transforms import Transform

__all__ = ["NetSpec", "init_net", "apply_net", "localise", "transform_stage", "classify",
           "conv2d", "maxpool2", "maxpool2_reference", "first_max_mask", "gru_step"]


@dataclass(frozen=True)
class NetSpec:
    """Static description of one network (hashable, usable as a jit static argument).

    Attributes:
        model: "ffn_spn" or "rnn_spn".
        transform: the spatial transform layer.
        canvas: input side S [px]; d: down-sampling factor; n_digits: sequence length.
        loc_filters, loc_dense (FFN), gru_units (RNN), cls_filters, cls_dense: widths.
        dropout: dropout rate of the classifier (0 = none).
        step_shift: RNN-SPN only: fixed x offset (normalised canvas units) of successive
            per-digit transforms, step t adding (t - (n_digits - 1) / 2) x step_shift to
            its x translation; 0 = every step starts at the identity crop ([RSTN]).
    """

    model: str
    transform: Transform
    canvas: int
    d: int
    n_digits: int
    loc_filters: int
    loc_dense: int
    gru_units: int
    cls_filters: int
    cls_dense: int
    dropout: float = 0.0
    step_shift: float = 0.0

    @property
    def out_size(self) -> int:
        return self.transform.out_size(self.canvas, self.d)


def conv2d(x, w, b):
    """'valid' 2-D convolution + bias: x (B, H, W, C), w (3, 3, C, F) -> (B, H-2, W-2, F)."""
    y = lax.conv_general_dilated(x, w, (1, 1), "VALID", dimension_numbers=("NHWC", "HWIO", "NHWC"))
    return y + b[None, None, None, :]


def maxpool2_reference(x):
    """2 x 2 max pooling with stride 2, odd borders dropped: (B, H, W, C) -> (B, H//2, W//2, C).

    XLA's ``reduce_window``; its reverse-mode derivative is XLA's ``select_and_scatter``.
    """
    return lax.reduce_window(x, -jnp.inf, lax.max, (1, 2, 2, 1), (1, 2, 2, 1), "VALID")


def _windows(x):
    """(B, H, W, C) -> (B, H//2, 2, W//2, 2, C): the 2 x 2 pooling windows, odd borders dropped."""
    b, h, w, c = x.shape
    h2, w2 = h // 2, w // 2
    return x[:, : 2 * h2, : 2 * w2].reshape(b, h2, 2, w2, 2, c)


def first_max_mask(x, y):
    """One-hot (B, H//2, 2, W//2, 2, C) mask of the first maximum of each 2 x 2 window.

    "First" in the window's row-major order (top left, top right, bottom left, bottom
    right), the element XLA's ``select_and_scatter`` (``jax.grad`` of
    :func:`maxpool2_reference`) routes the gradient to when several elements tie. A window
    whose maximum is NaN has no element equal to it and an all-false mask.

    Args:
        x: (B, H, W, C) pool input; y: (B, H//2, W//2, C) its pooled maxima.
    """
    xw = _windows(x)
    e00, e01 = xw[:, :, 0, :, 0] == y, xw[:, :, 0, :, 1] == y
    e10, e11 = xw[:, :, 1, :, 0] == y, xw[:, :, 1, :, 1] == y
    f01 = e01 & ~e00
    seen = e00 | e01
    f10 = e10 & ~seen
    f11 = e11 & ~(seen | e10)
    top = jnp.stack([e00, f01], axis=3)  # (B, H2, W2, 2, C)
    bottom = jnp.stack([f10, f11], axis=3)
    return jnp.stack([top, bottom], axis=2)


@jax.custom_jvp
def maxpool2(x):
    """2 x 2 max pooling with stride 2, odd borders dropped: (B, H, W, C) -> (B, H//2, W//2, C).

    The forward pass is :func:`maxpool2_reference`'s. Its derivative is the same linear
    map as that of :func:`maxpool2_reference` (the tangent, or in reverse mode the
    gradient, of each window goes to the window's first maximum, :func:`first_max_mask`),
    written with elementwise comparisons, a select and a sum instead of XLA's
    ``select_and_scatter``, which on CPU dominated the classifier's backward pass (Tab. 2.1
    networks; ``thesis bench chirpz-train``).
    """
    return maxpool2_reference(x)


@maxpool2.defjvp
def _maxpool2_jvp(primals, tangents):
    (x,), (t,) = primals, tangents
    y = maxpool2_reference(x)
    mask = first_max_mask(x, y)
    return y, jnp.sum(jnp.where(mask, _windows(t), jnp.zeros((), t.dtype)), axis=(2, 4))


def _glorot(key, shape, fan_in, fan_out):
    lim = jnp.sqrt(6.0 / (fan_in + fan_out))
    return jax.random.uniform(key, shape, jnp.float32, -lim, lim)


def _conv_init(key, cin, cout):
    return {"w": _glorot(key, (3, 3, cin, cout), 9 * cin, 9 * cout), "b": jnp.zeros(cout)}


def _dense_init(key, nin, nout):
    return {"w": _glorot(key, (nin, nout), nin, nout), "b": jnp.zeros(nout)}


def _conv_out(s: int, pools_before: tuple[bool, ...]) -> int:
    """Side after a stack of [optional pool, conv] blocks."""
    for pool in pools_before:
        if pool:
            s //= 2
        s -= 2
    return s


LOC_STACK = (True, True, True)  # pool before each of the three localisation convs
CLS_STACK = (False, True, True)  # conv, pool+conv, pool+conv (side arithmetic only)


def gru_step(p, h, x):
    """One GRU step (Cho et al. 2014, Lasagne's GRULayer form).

    r = σ(x W_r + h U_r + b_r), u = σ(x W_u + h U_u + b_u),
    c = tanh(x W_c + r ∘ (h U_c) + b_c), h' = (1 - u) ∘ h + u ∘ c.
    Shapes: h (B, H), x (B, I) -> (B, H).
    """
    gx = x @ p["wx"] + p["b"][None, :]
    gh = h @ p["wh"]
    nh = h.shape[-1]
    r = jax.nn.sigmoid(gx[:, :nh] + gh[:, :nh])
    u = jax.nn.sigmoid(gx[:, nh : 2 * nh] + gh[:, nh : 2 * nh])
    c = jnp.tanh(gx[:, 2 * nh :] + r * gh[:, 2 * nh :])
    return (1.0 - u) * h + u * c


def init_net(key, spec: NetSpec):
    """Parameters (a dict pytree of float32 arrays) of the network ``spec``."""
    keys = iter(jax.random.split(key, 16))
    p: dict = {}
    n_out = spec.transform.n_params
    s_in = spec.canvas
    # the classifier input: the transformed image (or the canvas for "none")
    m = spec.out_size
    side = _conv_out(m, CLS_STACK)
    if side < 1:
        raise ValueError(f"classifier input {m} px too small for Tab. 2.1's convolutions")
    cls_feat = side * side * spec.cls_filters
    p["cls_conv"] = [
        _conv_init(next(keys), 1, spec.cls_filters),
        _conv_init(next(keys), spec.cls_filters, spec.cls_filters),
        _conv_init(next(keys), spec.cls_filters, spec.cls_filters),
    ]
    p["cls_dense"] = _dense_init(next(keys), cls_feat, spec.cls_dense)
    heads = spec.n_digits * 10 if spec.model == "ffn_spn" else 10
    p["cls_out"] = _dense_init(next(keys), spec.cls_dense, heads)
    if spec.model == "rnn_spn":
        if n_out:
            loc_side = _conv_out(s_in, LOC_STACK)
            gru_in = loc_side * loc_side * spec.loc_filters
        else:
            gru_in = cls_feat
        h = spec.gru_units
        p["gru"] = {
            "wx": _glorot(next(keys), (gru_in, 3 * h), gru_in, h),
            "wh": _glorot(next(keys), (h, 3 * h), h, h),
            "b": jnp.zeros(3 * h),
        }
        if not n_out:  # "none": the GRU state modulates the shared classifier's dense layer
            p["gru_to_cls"] = _dense_init(next(keys), h, spec.cls_dense)
    if n_out:
        p["loc_conv"] = [
            _conv_init(next(keys), 1, spec.loc_filters),
            _conv_init(next(keys), spec.loc_filters, spec.loc_filters),
            _conv_init(next(keys), spec.loc_filters, spec.loc_filters),
        ]
        loc_side = _conv_out(s_in, LOC_STACK)
        if loc_side < 1:
            raise ValueError(f"canvas {s_in} px too small for the localisation network")
        feat = loc_side * loc_side * spec.loc_filters
        if spec.model == "ffn_spn":
            p["loc_dense"] = _dense_init(next(keys), feat, spec.loc_dense)
            nin = spec.loc_dense
        else:
            nin = spec.gru_units
        p["loc_out"] = {
            "w": jnp.zeros((nin, n_out), jnp.float32),
            "b": jnp.asarray(spec.transform.identity, jnp.float32),
        }
    return p


def _dense(x, layer):
    """Dense layer x @ W + b with explicit broadcasting of b over the leading axes."""
    return x @ layer["w"] + layer["b"].reshape((1,) * (x.ndim - 1) + (-1,))


def _dropout(key, x, rate, train):
    if not train or rate <= 0.0:
        return x
    keep = jax.random.bernoulli(key, 1.0 - rate, x.shape)
    return jnp.where(keep, x / (1.0 - rate), 0.0)


def _loc_features(p, img):
    x = img[..., None]
    for layer in p["loc_conv"]:
        x = jax.nn.relu(conv2d(maxpool2(x), layer["w"], layer["b"]))
    return x.reshape(x.shape[0], -1)


def _cls_features(p, img, key, rate, train):
    """Tab. 2.1 classifier convs: conv, pool, dropout, conv, pool, dropout, conv, dropout."""
    x = img[..., None]
    k = jax.random.split(key, 3)
    c1, c2, c3 = p["cls_conv"]
    x = _dropout(k[0], maxpool2(jax.nn.relu(conv2d(x, c1["w"], c1["b"]))), rate, train)
    x = _dropout(k[1], maxpool2(jax.nn.relu(conv2d(x, c2["w"], c2["b"]))), rate, train)
    x = _dropout(k[2], jax.nn.relu(conv2d(x, c3["w"], c3["b"])), rate, train)
    return x.reshape(x.shape[0], -1)


def localise(p, spec: NetSpec, images):
    """Localisation stage (§2.5, Tab. 2.1): the transform parameters predicted from images.

    Args:
        p: parameters of :func:`init_net`; spec: the network; images: (B, S, S) in [0, 1].

    Returns:
        (B, P) for FFN-SPN, (B, n_digits, P) for RNN-SPN (step t's transform, the
        ``step_shift`` offset included); None for the transform "none".
    """
    t = spec.transform
    if not t.n_params:
        return None
    if spec.model == "ffn_spn":
        h = jax.nn.relu(_dense(_loc_features(p, images), p["loc_dense"]))
        return _dense(h, p["loc_out"])
    nd = spec.n_digits
    g = p["gru"]
    h0 = jnp.zeros((images.shape[0], g["wh"].shape[0]), images.dtype)
    feat = _loc_features(p, images)

    def step(h, _):
        h = gru_step(g, h, feat)
        return h, _dense(h, p["loc_out"])

    _, theta = lax.scan(step, h0, None, length=nd)  # (nd, B, P)
    theta = jnp.swapaxes(theta, 0, 1)  # (B, nd, P)
    if spec.step_shift:
        # fixed per-step x offset of the crop centre (NetSpec.step_shift)
        shift = (jnp.arange(nd, dtype=theta.dtype) - (nd - 1) / 2.0) * spec.step_shift
        theta = theta.at[:, :, 2].add(shift[None, :])
    return theta


def transform_stage(spec: NetSpec, images, theta):
    """Spatial transform stage (§2.5): what the classifier sees.

    Args:
        images: (B, S, S); theta: the output of :func:`localise`.

    Returns:
        (B, M, M) for FFN-SPN, (B * n_digits, M, M) sample-major crops for RNN-SPN (one
        per step, all cut from the same canvas: :meth:`Transform.crops`), M = ``spec.out_size``;
        the images unchanged for the transform "none".
    """
    if theta is None:
        return images
    if spec.model == "ffn_spn":
        return spec.transform(images, theta, spec.out_size)
    return spec.transform.crops(images, theta, spec.out_size)


def classify(p, spec: NetSpec, x, key, train: bool = False):
    """Classification stage (Tab. 2.1): logits (B, n_digits, 10) from the transformed images.

    Args:
        x: the output of :func:`transform_stage` ((B, M, M), or (B * n_digits, M, M) crops
            for RNN-SPN with a transform, or the (B, S, S) canvas for "none").
        key: dropout key (used when ``train`` and ``spec.dropout > 0``).
    """
    rate = spec.dropout
    nd = spec.n_digits
    if spec.model == "ffn_spn":
        f = _cls_features(p, x, key, rate, train)
        f = jax.nn.relu(_dense(f, p["cls_dense"]))
        return (_dense(f, p["cls_out"])).reshape(-1, nd, 10)
    if spec.transform.n_params:
        f = _cls_features(p, x, key, rate, train)
        f = jax.nn.relu(_dense(f, p["cls_dense"]))
    else:
        # "none": the shared classifier sees the canvas at every step; the GRU state,
        # driven by the classifier features, modulates its dense layer
        g = p["gru"]
        feat = _cls_features(p, x, key, rate, train)
        h0 = jnp.zeros((x.shape[0], g["wh"].shape[0]), x.dtype)

        def step(h, _):
            h = gru_step(g, h, feat)
            return h, h

        _, hs = lax.scan(step, h0, None, length=nd)  # (nd, B, H)
        pre = _dense(feat, p["cls_dense"])
        mod = jnp.einsum("tbh,hk->btk", hs, p["gru_to_cls"]["w"]) + p["gru_to_cls"]["b"][None, None, :]
        f = jax.nn.relu(pre[:, None, :] + mod).reshape(x.shape[0] * nd, -1)
    return (_dense(f, p["cls_out"])).reshape(-1, nd, 10)


def apply_net(p, spec: NetSpec, images, key=None, train: bool = False, return_params=False):
    """Logits (B, n_digits, 10) of the network ``spec`` on images (B, S, S).

    The three stages :func:`localise`, :func:`transform_stage` and :func:`classify` in turn.
    ``key`` drives dropout (only used when ``train`` and ``spec.dropout > 0``). With
    ``return_params`` also returns the transform parameters: (B, P) for FFN-SPN,
    (B, n_digits, P) for RNN-SPN (None for "none").
    """
    if key is None:
        key = jax.random.key(0)
    theta = localise(p, spec, images)
    logits = classify(p, spec, transform_stage(spec, images, theta), key, train)
    return (logits, theta) if return_params else logits
