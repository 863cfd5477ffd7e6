"""Training of FFN-SPN / RNN-SPN on cluttered MNIST sequences (thesis §2.5;
docs/sources.md#rstn-training).

As [RSTN]: mini-batches of ``batch_size`` (100); RMSprop (ρ = 0.9, ε = 1e-6, Lasagne's
defaults) with learning rate 5e-4, or Adam; gradients clipped per element to
[-clip_value, clip_value] and then to total norm ``clip_norm``; the learning rate
follows ``lr_schedule`` (:func:`learning_rates`): "step" ([RSTN]) divides it by
``lr_decay_factor`` every ``lr_decay_every`` epochs once past ``lr_decay_start`` epochs;
"hold_decay" holds it for the first ``1 - decay_fraction`` of the run's steps
(``max_epochs`` epochs) and then decays it along a half cosine to ``final_lr_fraction``
of its value at the last step, a schedule that fits a run of a few epochs (a step decay
from epoch 3 of 5 cuts the rate while every curve is still falling); early stopping when the
validation error has not improved for ``patience`` epochs (at most ``max_epochs``); the parameters
of the best validation epoch are evaluated on the test set. Cost: mean cross-entropy over the digits
of a sequence (log-softmax; [RSTN] added 1e-5 inside the log). Error: per-digit error (fraction).

An epoch is one pass over the training split, shuffled anew, unless ``epoch_sequences``
is set: then an epoch is the next ``epoch_sequences`` sequences of a stream of shuffled
passes (a new pass is shuffled when one is used up, and the remainder of a pass carries
over), so that a run shorter than one pass over a large split (the thesis's 60 000
sequences) still validates, stops early and decays its learning rate per
epoch, and every sequence is seen once before any is seen twice.

``loc_lr_scale`` multiplies the optimiser's updates of the localisation network (its
convolutions, dense layers, and for RNN-SPN the GRU that drives it) after RMSprop/Adam.
The thesis and [RSTN] train every layer at one rate (1.0, the paper profile). At the
larger learning rates that the small default profile needs, the transform left the
canvas within ~100 steps: bilinear samples outside read zero, the classifier saw empty
images and the localisation gradients vanished for good (network at chance). A slower
localisation network (e.g. 0.1) keeps the grid on the canvas while the classifier
learns; see ``thesis.ch2.transforms.inside_fraction``.

Runs at chance. A run can stay at chance: when the classifier has not left the uniform
prediction (loss ln 10) by the time the localisation network moves the crop off the canvas,
it sees mostly zeros and predicts one class. Adam normalises each parameter's update, so the
transform parameters move by about (units feeding them) x rate per update however small and
uninformative their gradient is. A classifier wide enough to learn before the crop drifts
keeps the localisation gradient informative: the profile's widths are chosen for it
(``thesis bench chirpz-widths``, departure ``ch2.network_widths``). A run that still fails
is kept and flagged
(:attr:`TrainResult.failed`; Tab. 2.2's ``failed``, ``inside_fraction`` and
``crop_scale`` say which and why), never dropped or rerun with another seed.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np
import optax

from thesis.ch2.nets import NetSpec, apply_net, init_net
from thesis.physics.perturbation import perturb_tree

__all__ = ["TrainResult", "train", "per_digit_error", "make_optimizer", "optimizer_settings",
           "localisation_labels", "learning_rates", "SCHEDULES", "CHANCE_ERROR",
           "FAILED_ERROR"]

#: learning-rate schedules of ``ch2.train.lr_schedule`` (:func:`learning_rates`)
SCHEDULES = ("step", "hold_decay")

#: per-digit error of a uniform (or label-frequency) prediction of 10 classes
CHANCE_ERROR = 0.9

#: a run whose best validation error is at or above this did not learn (``failed``): a
#: network that reads one of three digits right and guesses the others stays below it
#: (1/3 x 0 + 2/3 x 0.9 = 0.6), so it marks runs that never left chance, not slow ones
FAILED_ERROR = 0.8

#: top-level parameter groups of the localisation network (thesis.ch2.nets)
LOC_GROUPS = ("loc_conv", "loc_dense", "loc_out")


@dataclass
class TrainResult:
    """Outcome of one training run.

    Attributes:
        test_error: per-digit test error of the best-validation parameters (fraction).
        valid_error: (epochs_run,) per-digit validation error after each epoch (fraction).
        train_loss: (epochs_run,) mean training cross-entropy of each epoch [nats].
        learning_rate: (epochs_run,) learning rate used in each epoch.
        best_epoch: 1-based epoch of the best validation error.
        failed: the best validation error is at or above :data:`FAILED_ERROR` (the run
            never left chance); such a run is kept and reported, never dropped.
        n_params: number of trainable parameters.
        seconds: wall time of the run [s] (compilation included).
        params: best parameters.
    """

    test_error: float
    valid_error: np.ndarray
    train_loss: np.ndarray
    learning_rate: np.ndarray
    best_epoch: int
    failed: bool
    n_params: int
    seconds: float
    params: dict


def localisation_labels(params: dict) -> dict:
    """Label every top-level parameter group "loc" (localisation network, §2.5 / Tab. 2.1)
    or "rest" (classifier). The RNN-SPN's GRU belongs to the localisation network when a
    transform is present (it only produces the per-step transform parameters) and to the
    classifier with the transform "none" (no ``loc_out``)."""
    has_loc = "loc_out" in params
    return {k: ("loc" if k in LOC_GROUPS or (k == "gru" and has_loc) else "rest")
            for k in params}


def make_optimizer(cfg: dict):
    """optax chain (§2.5, docs/sources.md#rstn-training): per-element clip, global-norm
    clip, RMSprop/Adam with an injectable learning rate, then the localisation updates scaled by
    ``cfg["loc_lr_scale"]`` (default 1.0: one rate for all layers, as the thesis), then a
    linear warm-up of every update over ``cfg["warmup_steps"]`` steps (default 0: none).

    The learning-rate state is element 2 of the chain (``opt_state[2].hyperparams``).
    """
    scale = float(cfg.get("loc_lr_scale", 1.0))
    if cfg["optimizer"] == "rmsprop":
        opt = optax.inject_hyperparams(optax.rmsprop)(
            learning_rate=cfg["learning_rate"], decay=0.9, eps=1e-6)
    elif cfg["optimizer"] == "adam":
        opt = optax.inject_hyperparams(optax.adam)(learning_rate=cfg["learning_rate"])
    else:
        raise ValueError(f"unknown optimizer {cfg['optimizer']!r}")
    loc_scale = optax.multi_transform(
        {"loc": optax.scale(scale), "rest": optax.identity()}, localisation_labels)
    warmup = int(cfg.get("warmup_steps", 0))
    ramp = optax.scale_by_schedule(optax.linear_schedule(1.0 / (warmup + 1), 1.0, warmup)) \
        if warmup else optax.identity()
    return optax.chain(optax.clip(cfg["clip_value"]), optax.clip_by_global_norm(cfg["clip_norm"]),
                       opt, loc_scale, ramp)


def learning_rates(cfg: dict, steps_per_epoch: int) -> np.ndarray:
    """Learning rate of every update of a run of ``cfg["max_epochs"]`` epochs (§2.5).

    Args:
        cfg: the ``ch2.train`` section: ``learning_rate``, ``max_epochs``, ``lr_schedule``
            (:data:`SCHEDULES`, default "step") and its keys (module docstring).
        steps_per_epoch: updates per epoch.

    Returns:
        (max_epochs * steps_per_epoch,) float64: "step" is constant within an epoch and
        divided by ``lr_decay_factor`` at the start of epoch e whenever e >
        ``lr_decay_start`` and e - (epoch of the last decay) > ``lr_decay_every``
        ([RSTN]); "hold_decay" is ``learning_rate`` for the first
        round((1 - decay_fraction) x steps) updates, then a half cosine
        (``optax.cosine_decay_schedule``) that reaches ``final_lr_fraction`` x
        ``learning_rate`` at the last update. The warm-up (``warmup_steps``) is applied
        on top by the optimiser (:func:`make_optimizer`).
    """
    lr0, epochs = float(cfg["learning_rate"]), int(cfg["max_epochs"])
    n = epochs * int(steps_per_epoch)
    kind = cfg.get("lr_schedule", "step")
    if kind == "step":
        per_epoch, lr, last = [], lr0, 0
        for epoch in range(1, epochs + 1):
            if epoch > cfg["lr_decay_start"] and epoch - last > cfg["lr_decay_every"]:
                lr /= float(cfg["lr_decay_factor"])
                last = epoch
            per_epoch.append(lr)
        return np.repeat(np.asarray(per_epoch, np.float64), int(steps_per_epoch))
    if kind == "hold_decay":
        frac = float(cfg.get("decay_fraction", 0.3))
        final = float(cfg.get("final_lr_fraction", 0.05))
        if not 0.0 <= frac <= 1.0 or not 0.0 <= final <= 1.0:
            raise ValueError(f"ch2.train: decay_fraction {frac} and final_lr_fraction {final} "
                             "must lie in [0, 1]")
        n_decay = int(round(frac * n))
        hold = np.full(n - n_decay, lr0)
        if n_decay <= 1:
            return np.concatenate([hold, np.full(n_decay, lr0 * final)])
        cosine = optax.cosine_decay_schedule(lr0, n_decay - 1, alpha=final)
        with jax.numpy_dtype_promotion("standard"):  # optax mixes int counts and floats
            decay = np.asarray(jax.device_get(cosine(jnp.arange(n_decay))), np.float64)
        return np.concatenate([hold, decay])
    raise ValueError(f"ch2.train.lr_schedule {kind!r}: allowed {', '.join(SCHEDULES)}")


def _loss(params, spec, x, y, key):
    logits = apply_net(params, spec, x, key=key, train=True)
    logp = jax.nn.log_softmax(logits, axis=-1)
    nll = -jnp.take_along_axis(logp, y[..., None], axis=-1)[..., 0]
    return jnp.mean(nll)


def optimizer_settings(cfg: dict) -> tuple:
    """The keys of a ``ch2.train`` section that :func:`make_optimizer` reads, as a hashable
    tuple of (name, value) pairs (the schema defaults where a key is absent)."""
    opt_cfg = {k: cfg[k] for k in ("optimizer", "learning_rate", "clip_value", "clip_norm")}
    opt_cfg["loc_lr_scale"] = float(cfg.get("loc_lr_scale", 1.0))  # schema defaults
    opt_cfg["warmup_steps"] = int(cfg.get("warmup_steps", 0))
    return tuple(opt_cfg.items())


@functools.lru_cache(maxsize=64)
def _make_steps(spec: NetSpec, opt_cfg: tuple):
    """Jitted train step and error count for ``spec``; cached so that every seed (and every
    call with the same optimiser settings) reuses the compiled programs."""
    optimizer = make_optimizer(dict(opt_cfg))
    @jax.jit
    def train_step(params, opt_state, x, y, key):
        loss, grads = jax.value_and_grad(_loss)(params, spec, x, y, key)
        with jax.numpy_dtype_promotion("standard"):  # optax's Adam mixes int counts and floats
            updates, opt_state = optimizer.update(grads, opt_state, params)
        return optax.apply_updates(params, updates), opt_state, loss

    @jax.jit
    def errors(params, x, y):
        pred = jnp.argmax(apply_net(params, spec, x, train=False), axis=-1)
        return jnp.sum(pred != y)

    return optimizer, train_step, errors


class _PassStream:
    """Training indices as a stream of shuffled passes over ``n`` sequences: ``take(m)``
    returns the next ``m`` (a new pass is drawn from ``rng`` whenever the current one runs
    out, so no sequence repeats before every one has been used)."""

    def __init__(self, rng: np.random.Generator, n: int):
        self.rng, self.n = rng, int(n)
        self.pending = np.zeros(0, np.int64)

    def take(self, m: int) -> np.ndarray:
        while len(self.pending) < m:
            self.pending = np.concatenate([self.pending, self.rng.permutation(self.n)])
        out, self.pending = self.pending[:m], self.pending[m:]
        return out


def per_digit_error(errors_fn, params, x, y, batch: int) -> float:
    """Fraction of wrongly classified digits over a whole split (full batches + remainder)."""
    wrong = 0
    for i in range(0, len(x), batch):
        wrong += int(errors_fn(params, jnp.asarray(x[i : i + batch]), jnp.asarray(y[i : i +
        batch])))
    return wrong / y.size


def train(spec: NetSpec, data: dict, cfg: dict, key, rng: np.random.Generator, log=None,
          on_nan=None) -> TrainResult:
    """Train ``spec`` on ``data`` = {split: (images (n,S,S) float32, labels (n,3) int32)}.

    The images may be any array-like whose slices and index arrays are float32 arrays,
    e.g. :class:`thesis.ch2.data.Canvases` (uint8 in memory, converted per mini-batch).

    Args:
        cfg: the ``ch2.train`` config section (module docstring).
        key: JAX key for initialisation and dropout; rng: NumPy generator for shuffling.
        on_nan: called with the step number when the loss is not finite (should raise).
    """
    t0 = time.perf_counter()
    k_init, k_drop = jax.random.split(key)
    # initial weights moved at the rounding level under thesis --perturb (else as drawn)
    params = perturb_tree(init_net(k_init, spec))
    n_params = int(sum(v.size for v in jax.tree_util.tree_leaves(params)))
    optimizer, train_step, errors = _make_steps(spec, optimizer_settings(cfg))
    opt_state = optimizer.init(params)
    xtr, ytr = data["train"]
    bs = int(cfg["batch_size"])
    epoch_seq = cfg.get("epoch_sequences")
    passes = None if epoch_seq is None else _PassStream(rng, len(xtr))
    n_batches = max((len(xtr) if epoch_seq is None else int(epoch_seq)) // bs, 1)
    schedule = learning_rates(cfg, n_batches)
    best, best_epoch, best_params = np.inf, 0, params
    valid_err, train_loss, lrs = [], [], []
    step = 0
    for epoch in range(1, int(cfg["max_epochs"]) + 1):
        # a whole pass per epoch (no epoch_sequences), or the next part of the stream of
        # passes
        order = rng.permutation(len(xtr)) if passes is None else passes.take(n_batches * bs)
        losses = []
        for b in range(n_batches):
            opt_state[2].hyperparams["learning_rate"] = jnp.asarray(schedule[step], jnp.float32)
            idx = np.sort(order[b * bs : (b + 1) * bs])
            params, opt_state, loss = train_step(
                params, opt_state, jnp.asarray(xtr[idx]), jnp.asarray(ytr[idx]),
                jax.random.fold_in(k_drop, step))
            step += 1
            losses.append(loss)
        lr = float(schedule[step - n_batches : step].mean())
        losses = np.asarray(jax.device_get(losses), np.float64)
        if not np.all(np.isfinite(losses)):
            bad = step - n_batches + int(np.argmax(~np.isfinite(losses)))
            if on_nan is not None:
                on_nan(bad)
            raise FloatingPointError(f"non-finite loss at step {bad}")
        ve = per_digit_error(errors, params, *data["valid"], bs)
        valid_err.append(ve)
        train_loss.append(float(losses.mean()))
        lrs.append(lr)  # the epoch's mean learning rate
        if log is not None:
            log.info("%s/%s d=%d epoch %d: loss %.4f valid error %.4f (lr %.2e)", spec.model,
                     spec.transform.name, spec.d, epoch, train_loss[-1], ve, lr)
        if ve < best:
            best, best_epoch, best_params = ve, epoch, params
        elif epoch - best_epoch >= cfg["patience"]:
            break
    test = per_digit_error(errors, best_params, *data["test"], bs)
    return TrainResult(test, np.asarray(valid_err), np.asarray(train_loss), np.asarray(lrs),
                       best_epoch, bool(best >= FAILED_ERROR), n_params,
                       time.perf_counter() - t0, best_params)
