"""``thesis bench chirpz-train``: what one training step of the Tab. 2.2 networks costs.

For every model x transform x d of ``ch2.train_bench`` this times one
training step (forward, backward and optimiser update, the jitted step of
:func:`thesis.ch2.train.train`) and its parts, each a separately jitted function:

- ``localisation``: forward and backward of :func:`thesis.ch2.nets.localise` (the
  gradient of a random linear function of the transform parameters with respect to the
  localisation network's parameters; the canvas is data, not differentiated);
- ``transform``: forward and backward of :func:`thesis.ch2.nets.transform_stage`
  (gradient with respect to the transform parameters only, as in training);
- ``classifier``: forward and backward of :func:`thesis.ch2.nets.classify` and the
  cross-entropy (gradient with respect to the classifier's parameters and, when there is
  a transform, its input image, through which the localisation network learns);
- ``update``: the optimiser update of every parameter (clipping, RMSprop/Adam, scales).

``step`` is the whole training step and ``forward`` the loss alone. The parts are
compiled apart, so XLA cannot fuse across their borders and their sum is not exactly
``step``; they say where the step's time goes. A part that a cell does not have (the
transform "none" has no localisation network and no transform) is 0.

Workload: the profile's widths (``ch2.ffn_spn``, ``ch2.rnn_spn``), its optimiser
(``ch2.train``), the canvas side and sequence length of ``ch2.data``; a batch of
``ch2.train_bench.batch`` canvases of uniform random pixels in [0, 1) with random labels
(the cost of every operation here is independent of the pixel values), parameters as
:func:`thesis.ch2.nets.init_net` draws them with the transform parameters moved off the
identity (a random localisation output layer), training mode (dropout as configured).

Work: ``step_flops`` is XLA's count of the floating-point operations of the lowered
training step (:func:`step_flops`; shapes only), the same on every device; with
``ch2.train_bench.timed`` false only it is computed (seconds NaN), which is how the work
of the Tab. 2.1 networks is counted on a machine too slow to time them (the gpu profile's
sizing, config/gpu.yaml, names this count).

Timing: every function of a cell is compiled and run once untimed, then the functions run
in turn ``repeats`` times (interleaved, so that load from other processes falls on all of
them alike), each call ended by ``block_until_ready``; the median is reported. Wall time
and the process's CPU time (all threads) are both recorded: on a shared machine other
processes inflate wall times more than the CPU time the step itself needs.
"""

from __future__ import annotations

import json
import time

import numpy as np
import xarray as xr

from thesis import seeding
from thesis.runctx import RunContext
from thesis.store import WALL_CLOCK

#: The timed functions of a cell, in the dataset's ``part`` order.
PARTS = ("step", "forward", "localisation", "transform", "classifier", "update")


def _cell_functions(spec, tcfg: dict, batch: int, rng: np.random.Generator):
    """The jitted functions of one cell and their arguments: {part: (fn, args)}."""
    import jax
    import jax.numpy as jnp
    import optax

    from thesis.ch2 import nets
    from thesis.ch2.train import _loss, _make_steps, localisation_labels, optimizer_settings

    optimizer, train_step, _ = _make_steps(spec, optimizer_settings(tcfg))
    params = nets.init_net(jax.random.key(int(rng.integers(2**31))), spec)
    if "loc_out" in params:  # transforms off the identity: a cell as it is mid-training
        w = params["loc_out"]["w"]
        params["loc_out"]["w"] = jnp.asarray(0.01 * rng.standard_normal(w.shape), w.dtype)
    opt_state = optimizer.init(params)
    s = spec.canvas
    x = jnp.asarray(rng.random((batch, s, s)), jnp.float32)
    y = jnp.asarray(rng.integers(0, 10, (batch, spec.n_digits)), jnp.int32)
    key = jax.random.key(int(rng.integers(2**31)))
    labels = localisation_labels(params)
    loc = {k: v for k, v in params.items() if labels[k] == "loc"}
    rest = {k: v for k, v in params.items() if labels[k] == "rest"}

    def loss(p, x, y, k):
        return _loss(p, spec, x, y, k)

    fns = {
        "step": (train_step, (params, opt_state, x, y, key)),
        "forward": (jax.jit(loss), (params, x, y, key)),
    }
    # the cell's inputs are computed by compiled functions too: op by op, the default
    # widths' gradient alone takes longer than every timed call of the cell together
    theta = jax.jit(lambda p, x: nets.localise(p, spec, x))(params, x)
    if theta is not None:
        ct_theta = jnp.asarray(rng.standard_normal(theta.shape), theta.dtype)

        def loc_obj(lp, rp, x, ct):
            return jnp.sum(nets.localise({**lp, **rp}, spec, x) * ct)

        fns["localisation"] = (jax.jit(jax.grad(loc_obj)), (loc, rest, x, ct_theta))
        xt = jax.jit(lambda x, th: nets.transform_stage(spec, x, th))(x, theta)
        ct_xt = jnp.asarray(rng.standard_normal(xt.shape), xt.dtype)

        def tr_obj(th, x, ct):
            return jnp.sum(nets.transform_stage(spec, x, th) * ct)

        fns["transform"] = (jax.jit(jax.grad(tr_obj)), (theta, x, ct_xt))
        argnums = (0, 2)  # classifier parameters and its input (the localisation's signal)
    else:
        xt = x
        argnums = 0

    def cls_obj(rp, lp, xt, y, k):
        logits = nets.classify({**lp, **rp}, spec, xt, k, train=True)
        logp = jax.nn.log_softmax(logits, axis=-1)
        return -jnp.mean(jnp.take_along_axis(logp, y[..., None], axis=-1))

    fns["classifier"] = (jax.jit(jax.grad(cls_obj, argnums=argnums)), (rest, loc, xt, y, key))

    grads = jax.jit(jax.grad(loss))(params, x, y, key)

    @jax.jit
    def update(p, state, g):
        with jax.numpy_dtype_promotion("standard"):  # as the training step
            upd, state = optimizer.update(g, state, p)
        return optax.apply_updates(p, upd), state

    fns["update"] = (update, (params, opt_state, grads))
    n_params = int(sum(v.size for v in jax.tree_util.tree_leaves(params)))
    return fns, n_params


def step_flops(spec, tcfg: dict, batch: int) -> float:
    """Floating-point operations of one training step of ``spec`` on ``batch`` sequences,
    as XLA's cost analysis of the lowered step counts them (forward, backward and update;
    shapes only, nothing is computed). A device-independent measure of the work of a step,
    from which the time on another device is estimated (``thesis.ch2.train_bench``)."""
    import jax
    import jax.numpy as jnp

    from thesis.ch2 import nets
    from thesis.ch2.train import _make_steps, optimizer_settings

    optimizer, train_step, _ = _make_steps(spec, optimizer_settings(tcfg))
    key = jax.random.key(0)
    params = jax.eval_shape(lambda k: nets.init_net(k, spec), key)
    opt_state = jax.eval_shape(optimizer.init, params)
    x = jax.ShapeDtypeStruct((batch, spec.canvas, spec.canvas), jnp.float32)
    y = jax.ShapeDtypeStruct((batch, spec.n_digits), jnp.int32)
    cost = train_step.lower(params, opt_state, x, y, key).cost_analysis()
    cost = cost[0] if isinstance(cost, (list, tuple)) else cost
    return float(cost["flops"])


def _time_cell(fns: dict, repeats: int) -> tuple[np.ndarray, np.ndarray]:
    """Wall and CPU seconds (len(PARTS), repeats) of the cell's functions (0 where absent)."""
    import jax

    wall = np.zeros((len(PARTS), repeats))
    cpu = np.zeros((len(PARTS), repeats))
    for fn, args in fns.values():  # compile and warm up
        jax.block_until_ready(fn(*args))
    for r in range(repeats):
        for pi, part in enumerate(PARTS):
            if part not in fns:
                continue
            fn, args = fns[part]
            c0, t0 = time.process_time(), time.perf_counter()
            jax.block_until_ready(fn(*args))
            wall[pi, r] = time.perf_counter() - t0
            cpu[pi, r] = time.process_time() - c0
    return wall, cpu


def train_step(ctx: RunContext) -> xr.Dataset:
    """Per-step time of forward + backward + update of the Tab. 2.2 networks and its split.

    Dimensions model x transform x d x part (x repeat); see the module docstring. Sizes
    from ``ch2.train_bench``; widths, optimiser and canvas from the profile's ch2 sections.
    """
    import jax

    from thesis.ch2.experiments import _spec, _train_cfg

    cfg = ctx.config
    bcfg = cfg["train_bench"]
    models = list(bcfg["models"])
    trs = list(bcfg["transforms"])
    ds_ = [int(d) for d in bcfg["downsample"]]
    batch, repeats = int(bcfg["batch"]), int(bcfg["repeats"])
    canvas, n_digits = int(cfg["data"]["canvas"]), int(cfg["data"]["n_digits"])
    shape = (len(models), len(trs), len(ds_), len(PARTS), repeats)
    wall = np.full(shape, np.nan)
    cpu = np.full(shape, np.nan)
    nparams = np.full(shape[:3], np.nan)
    flops = np.full(shape[:3], np.nan)
    timed = bool(bcfg.get("timed", True))
    for mi, model in enumerate(models):
        tcfg = _train_cfg(cfg, model)
        for ti, tname in enumerate(trs):
            for di, d in enumerate(ds_):
                if tname == "none" and di > 0:  # no down-sampling: the same network for every d
                    wall[mi, ti, di], cpu[mi, ti, di] = wall[mi, ti, 0], cpu[mi, ti, 0]
                    nparams[mi, ti, di] = nparams[mi, ti, 0]
                    flops[mi, ti, di] = flops[mi, ti, 0]
                    continue
                rng = seeding.rng(ctx.root_seed, f"ch2/train_step/{model}/d={d}")
                spec = _spec(cfg, model, tname, d, canvas, n_digits)
                flops[mi, ti, di] = step_flops(spec, tcfg, batch)
                if not timed:  # the work of a step only (train_bench.timed)
                    ctx.log.info("%s %s d=%d: %.3g FLOP per step", model, tname, d,
                                 flops[mi, ti, di])
                    continue
                fns, nparams[mi, ti, di] = _cell_functions(spec, tcfg, batch, rng)
                wall[mi, ti, di], cpu[mi, ti, di] = _time_cell(fns, repeats)
                med = np.median(wall[mi, ti, di], axis=-1) * 1e3
                ctx.log.info("%s %s d=%d: %.3g FLOP per step; " +
                             ", ".join(f"{p} %.1f ms" for p in PARTS),
                             model, tname, d, flops[mi, ti, di], *med)
    dims = ("model", "transform", "d", "part")
    what = f"a batch of {batch} sequences"
    ds = xr.Dataset(
        {
            "seconds": (dims, np.median(wall, axis=-1), {"units": "s", "long_name":
                        f"median wall time per call for {what} (0: the cell has no such part)",
                        **WALL_CLOCK}),
            "cpu_seconds": (dims, np.median(cpu, axis=-1), {"units": "s", "long_name":
                            f"median CPU time of the process (all threads) per call for {what}",
                            **WALL_CLOCK}),
            "seconds_runs": (dims + ("repeat",), wall, {"units": "s", "long_name":
                             "wall time of every timed call", **WALL_CLOCK}),
            "n_params": (("model", "transform", "d"), nparams, {"units": "1", "long_name":
                         "number of trainable parameters (NaN: not timed)"}),
            "step_flops": (("model", "transform", "d"), flops, {"units": "1", "long_name":
                           f"floating-point operations of one training step on {what} "
                           "(XLA cost analysis of the lowered step)"}),
        },
        coords={"model": models, "transform": trs, "d": ds_, "part": list(PARTS),
                "repeat": np.arange(repeats)},
    )
    ds["d"].attrs.update(units="1", long_name="down-sampling factor of the transform layer")
    ds["part"].attrs.update(long_name="timed function (thesis.ch2.train_bench)")
    ds.attrs.update(
        thesis_ref="§2.5, Tab. 2.1", seeds=[0], batch=batch, repeats=repeats, canvas=canvas,
        n_digits=n_digits, chirpz_output=str(cfg["chirpz_output"]),
        widths=json.dumps({m: cfg[m] for m in models}, sort_keys=True),
        optimizer=json.dumps({m: dict(optimizer_settings_of(cfg, m)) for m in models},
                             sort_keys=True),
        backend=jax.default_backend(), device=str(jax.devices()[0]))
    return ds


def optimizer_settings_of(cfg: dict, model: str) -> tuple:
    """The optimiser settings (:func:`thesis.ch2.train.optimizer_settings`) of ``model``."""
    from thesis.ch2.experiments import _train_cfg
    from thesis.ch2.train import optimizer_settings

    return optimizer_settings(_train_cfg(cfg, model))
