"""``thesis bench chirpz-widths``: per-digit error against CPU time for a few network widths.

One cell of Tab. 2.2 (``ch2.width_pilot.model`` / ``transform`` /
``d``, by default FFN-SPN bilinear d = 2) and one seed is trained at every width of
``ch2.width_pilot.widths`` (the localisation and classifier widths of Tab. 2.1's
networks) for every run length of ``ch2.width_pilot.steps`` (one run per length, each
with the profile's learning-rate schedule fitted to its own length, so that a row is what
a run of that length gives, not a checkpoint of a longer one).

Data: the first ``n_train`` training sequences of the profile's cluttered MNIST
(:func:`thesis.ch2.data.synthesise` with the streams of ``ch2/cluttered_mnist``, so they
are the same sequences as the first ``n_train`` of the profile's file) and ``n_eval``
sequences of each evaluation split, synthesised in memory (stored as uint8 as the file).
Every run is evaluated, with its final parameters, on

- ``test``: held-out canvases of test-pool digits (the digits Tab. 2.2's test error reads);
- ``train_pool``: held-out canvases of train-pool digits (the validation split's pool):
  beside ``test`` it measures what the digit pool costs (with the embedded digits, 4 000
  train-pool digits; item 5);
- ``train_seen``: the first ``n_eval`` training canvases (seen in training), beside
  ``train_pool`` the cost of the canvases themselves.

Time: the CPU time of the process (all threads) and the wall time of each run,
compilation and the three evaluations included; ``step_cpu_seconds`` is the CPU time per
update from the difference of two run lengths of one width, which removes the fixed
costs. Diagnostic (item 4): ``inside_fraction`` is the mean fraction of the transform's
sampling grid that lies on the canvas over the test sequences (1 = on the canvas; a grid
that has left it samples zeros, :func:`thesis.ch2.transforms.inside_fraction`), and
``failed`` flags a run whose train-pool error stayed at or above
:data:`thesis.ch2.train.FAILED_ERROR`.
"""

from __future__ import annotations

import json
import time

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.runctx import RunContext
from thesis.store import WALL_CLOCK

__all__ = ["width_pilot", "SPLITS", "WIDTH_KEYS"]

#: evaluation splits of the pilot, in the dataset's ``split`` order (module docstring)
SPLITS = ("test", "train_pool", "train_seen")

#: the width keys of one ``ch2.width_pilot.widths`` entry (Tab. 2.1's FFN-SPN widths;
#: RNN-SPN reads ``gru_units`` in place of ``loc_dense``)
WIDTH_KEYS = ("loc_filters", "loc_dense", "cls_filters", "cls_dense")


def _width_label(w: dict) -> str:
    return f"loc {w['loc_filters']}/{w['loc_dense']}, cls {w['cls_filters']}/{w['cls_dense']}"


def _pilot_data(cfg: dict, root_seed: int, n_train: int, n_eval: int) -> tuple[dict, str]:
    """The pilot's splits {"train", "valid", "test", "train_seen"}: (Canvases, int32
    labels), and the digit source."""
    from thesis.ch2 import data as D

    dcfg = cfg["data"]
    name = "ch2/cluttered_mnist"  # the generator's streams: the profile's own sequences
    pools = D.load_pools(dcfg, seeding.rng(root_seed, name + "/pools"))
    layout = {k: dcfg[k] for k in ("canvas", "n_digits", "n_clutter", "clutter_size",
                                   "max_slope_deg")}
    out = {}
    for split, n in (("train", n_train), ("valid", n_eval), ("test", n_eval)):
        x, y = D.synthesise(pools.images[split], pools.labels[split], n,
                            seeding.rng(root_seed, f"{name}/{split}"), **layout)
        out[split] = (D.Canvases(D.quantise(x)), y.astype(np.int32))
        del x
    xtr, ytr = out["train"]
    out["train_seen"] = (D.Canvases(xtr.stored[:n_eval]), ytr[:n_eval])
    return out, pools.source


def width_pilot(ctx: RunContext) -> xr.Dataset:
    """Error against CPU time of one Tab. 2.2 cell at several widths and run lengths.

    Dimensions width x steps (x split); see the module docstring. Reads
    ``ch2.width_pilot``, the training settings of ``ch2.train`` (optimiser, learning rate
    and schedule, batch, warm-up, localisation scale), ``ch2.data`` and
    ``ch2.chirpz_output``.
    """
    import jax
    import jax.numpy as jnp

    from thesis.ch2.experiments import _spec
    from thesis.ch2.nets import localise
    from thesis.ch2.train import (_make_steps, optimizer_settings, per_digit_error, train)
    from thesis.ch2.transforms import inside_fraction

    cfg = ctx.config
    pcfg = cfg["width_pilot"]
    model, tname, d, seed = pcfg["model"], pcfg["transform"], int(pcfg["d"]), int(pcfg["seed"])
    widths = [dict(w) for w in pcfg["widths"]]
    steps = [int(s) for s in pcfg["steps"]]
    bs = int(cfg["train"]["batch_size"])
    data, source = _pilot_data(cfg, ctx.root_seed, int(pcfg["n_train"]), int(pcfg["n_eval"]))
    canvas, n_digits = data["train"][0].shape[-1], data["train"][1].shape[-1]
    shape = (len(widths), len(steps))
    err = np.full(shape + (len(SPLITS),), np.nan)
    cpu, wall, loss = np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, np.nan)
    inside = np.full(shape, np.nan)
    failed = np.zeros(shape, bool)
    nparams = np.full(len(widths), np.nan)
    for wi, w in enumerate(widths):
        missing = [k for k in WIDTH_KEYS if k not in w and not (k == "loc_dense" and model == "rnn_spn")]
        if missing:
            raise ValueError(f"ch2.width_pilot.widths[{wi}] lacks {missing}; each entry "
                             f"sets {', '.join(WIDTH_KEYS)}")
        wcfg = {**cfg, model: {**w, "gru_units": w.get("gru_units", w.get("loc_dense", 0))}}
        spec = _spec(wcfg, model, tname, d, canvas, n_digits)
        # compile the width's programs once, untimed (one update), so that every timed run
        # pays the same fixed costs and step_cpu_seconds is free of compilation
        warm = {**cfg["train"], "max_epochs": 1, "epoch_sequences": bs, "patience": 1}
        train(spec, data, warm, seeding.key(ctx.root_seed, "ch2/width_pilot/warm-up"),
              seeding.rng(ctx.root_seed, "ch2/width_pilot/warm-up"))
        for si, n_steps in enumerate(steps):
            # one epoch of exactly n_steps updates; its validation is the train-pool error
            tcfg = {**cfg["train"], "max_epochs": 1, "epoch_sequences": n_steps * bs,
                    "patience": 1}
            stream = f"ch2/width_pilot/{model}/{tname}/d={d}"
            key = seeding.key(ctx.root_seed, stream, seed)
            rng = seeding.rng(ctx.root_seed, stream + "/shuffle", seed)
            c0, t0 = time.process_time(), time.perf_counter()
            r = train(spec, data, tcfg, key, rng, log=None)
            _, _, errors = _make_steps(spec, optimizer_settings(tcfg))
            seen = per_digit_error(errors, r.params, *data["train_seen"], bs)
            cpu[wi, si] = time.process_time() - c0
            wall[wi, si] = time.perf_counter() - t0
            err[wi, si] = (r.test_error, float(r.valid_error[-1]), seen)
            loss[wi, si] = float(r.train_loss[-1])
            failed[wi, si] = r.failed
            nparams[wi] = r.n_params
            if spec.transform.n_params:
                xt = jnp.asarray(data["test"][0][: min(500, len(data["test"][0]))])
                theta = localise(r.params, spec, xt).reshape(-1, spec.transform.n_params)
                inside[wi, si] = float(jnp.mean(inside_fraction(
                    spec.transform, theta, canvas, spec.out_size)))
            ctx.log.info("%s, %d steps: test %.4f, train pool %.4f, seen %.4f, loss %.3f, "
                         "inside %.3f, %.0f s CPU (%.0f s wall)", _width_label(w), n_steps,
                         *err[wi, si], loss[wi, si], inside[wi, si], cpu[wi, si], wall[wi, si])
        jax.clear_caches()  # free the compiled programs of the finished width
    step_cpu = np.full(len(widths), np.nan)
    if len(steps) > 1:
        step_cpu = (cpu[:, -1] - cpu[:, 0]) / (steps[-1] - steps[0])
    labels = [_width_label(w) for w in widths]
    ds = xr.Dataset(
        {
            "error": (("width", "steps", "split"), err, {"units": "1", "long_name":
                      "per-digit error of the final parameters"}),
            "train_loss": (("width", "steps"), loss, {"units": "nat", "long_name":
                           "mean training cross-entropy per digit over the run"}),
            "cpu_seconds": (("width", "steps"), cpu, {"units": "s", "long_name":
                            "CPU time of the process (all threads) for the run, compilation "
                            "and evaluations included", **WALL_CLOCK}),
            "wall_seconds": (("width", "steps"), wall, {"units": "s", "long_name":
                             "wall time of the run, compilation and evaluations included",
                             **WALL_CLOCK}),
            "step_cpu_seconds": (("width",), step_cpu, {"units": "s", "long_name":
                                 "CPU time per update (difference of the longest and shortest "
                                 "runs over their difference in steps)", **WALL_CLOCK}),
            "inside_fraction": (("width", "steps"), inside, {"units": "1", "long_name":
                                "mean fraction of the sampling grid on the canvas (test)"}),
            "failed": (("width", "steps"), failed.astype(np.int8), {"units": "1", "long_name":
                       "1: the run never left chance (train-pool error >= FAILED_ERROR)"}),
            "n_params": (("width",), nparams, {"units": "1", "long_name":
                         "number of trainable parameters"}),
        },
        coords={"width": labels, "steps": steps, "split": list(SPLITS)},
    )
    ds["steps"].attrs.update(units="1", long_name="training updates of the run")
    ds["width"].attrs.update(long_name="localisation and classifier widths (filters/dense)")
    ds["split"].attrs.update(long_name="evaluation canvases (thesis.ch2.width_pilot)")
    ds.attrs.update(
        thesis_ref="§2.5, Tab. 2.1, Tab. 2.2", seeds=[seed], model=model, transform=tname,
        d=d, n_train=int(pcfg["n_train"]), n_eval=int(pcfg["n_eval"]), digit_source=source,
        widths=json.dumps(widths), batch_size=bs,
        train=json.dumps({k: v for k, v in cfg["train"].items()}, sort_keys=True, default=str),
        backend=jax.default_backend(), device=str(jax.devices()[0]))
    return ds
