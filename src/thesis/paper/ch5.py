"""Chapter 5 (terrain classification on Puppy II): Tab. 5.3, 5.4, 5.5, 5.6 and prose numbers.

All accuracies are percentages of correctly classified time steps, stored as printed with
unit ``"percent"``. Keys: ``table5_3/selection=<group>/split=<train|test>/method=<m>/accuracy``
with methods ``lr``, ``rc`` (Tab. 5.3), ``sfa2``, ``rc_sfa`` (Tab. 5.5), ``elm_sfa`` and
``rc_sfa`` with ``nodes`` 50, 100, 200 (Tab. 5.6). Chapter-5 experiments are not built yet.

Transcription notes: Tab. 5.4 is an image in thesis.txt; only its caption survives, so it is
recorded with value ``None``. The headers of Tab. 5.5 ("TI RAIN ſ TEST") and the row labels
of Tab. 5.6 ("Z", "RA", "H" / "Ē", "FES", "L '") are garbled vertical labels TRAIN and TEST;
the SFA2 row of Tab. 5.6 prints one value across the node columns (no hidden layer) and
equals the ``minimal`` row of Tab. 5.5.
"""

from __future__ import annotations

from thesis.paper.types import PaperValue, entry

_SELECTIONS = ("useful", "reduced", "minimal", "leg", "agt", "imu", "joints", "touch")

#: selection -> (row as printed, (train LR, train RC, test LR, test RC))
_T53 = {
    "useful": ("useful\t89.06\t95.16\t\t71.53\t76.30", (89.06, 95.16, 71.53, 76.30)),
    "reduced": ("reduced\t79.66\t96.27\t\t64.08\t79.36", (79.66, 96.27, 64.08, 79.36)),
    "minimal": ("minimal\t82.28\t95.96\t\t67.36\t81.62", (82.28, 95.96, 67.36, 81.62)),
    "leg": ("leg\t75.70\t95.42\t\t63.63\t81.53", (75.70, 95.42, 63.63, 81.53)),
    "agt": ("agt\t73.36\t95.68\t\t66.69\t82.84", (73.36, 95.68, 66.69, 82.84)),
    "imu": ("imu\t53.35\t91.47\t\t43.98\t72.25", (53.35, 91.47, 43.98, 72.25)),
    "joints": ("joints\t59.85\t91.99\t\t47.52\t74.12", (59.85, 91.99, 47.52, 74.12)),
    "touch": ("touch\t64.45\t93.84\t\t57.89\t84.69", (64.45, 93.84, 57.89, 84.69)),
}

#: selection -> (row as printed, (train SFA2, train RC-SFA, test SFA2, test RC-SFA))
_T55 = {
    "useful": ("useful\t58.11\t79.75\t38.94\t51.69", (58.11, 79.75, 38.94, 51.69)),
    "reduced": ("reduced\t60.98\t81.03\t36.27\t58.28", (60.98, 81.03, 36.27, 58.28)),
    "minimal": ("minimal\t61.72\t79.26\t37.90\t57.29", (61.72, 79.26, 37.90, 57.29)),
    "leg": ("leg\t53.71\t72.25\t33.82\t58.33", (53.71, 72.25, 33.82, 58.33)),
    "agt": ("agt\t51.49\t75.21\t26.99\t52.75", (51.49, 75.21, 26.99, 52.75)),
    "imu": ("imu\t44.45\t70.83\t29.16\t55.29", (44.45, 70.83, 29.16, 55.29)),
    "joints": ("joints\t38.22\t71.15\t27.50\t54.58", (38.22, 71.15, 27.50, 54.58)),
    "touch": ("touch\t48.09\t75.53\t35.97\t50.29", (48.09, 75.53, 35.97, 50.29)),
}


def _two_method_table(table: str, artifact: str, rows, methods, headers) -> list[PaperValue]:
    out = []
    cells = (("train", methods[0]), ("train", methods[1]), ("test", methods[0]),
             ("test", methods[1]))
    for selection in _SELECTIONS:
        source, values = rows[selection]
        for i, ((split, method), value) in enumerate(zip(cells, values)):
            out.append(entry(
                table=table, artifact=artifact, variable="accuracy",
                coords=(("selection", selection), ("split", split), ("method", method)),
                value=value, unit="percent", source=source, pos=i, row=selection,
                column=f"{split.upper()} {headers[method]}",
            ))
    return out


#: (split, method, row as printed, {nodes: value})
_T56 = (
    ("train", "sfa2", "Z\tSFA2\t\t61.72\t", {None: 61.72}),
    ("train", "elm_sfa", "RA\tELM-SFA\t81.92\t82.93\t86.24", {50: 81.92, 100: 82.93, 200: 86.24}),
    ("train", "rc_sfa", "H\tRC-SFA\t83.97\t82.71\t86.60", {50: 83.97, 100: 82.71, 200: 86.60}),
    ("test", "sfa2", "Ē\tSFA2\t\t37.90\t", {None: 37.90}),
    ("test", "elm_sfa", "FES\tELM-SFA\t63.16\t70.31\t72.64", {50: 63.16, 100: 70.31, 200: 72.64}),
    ("test", "rc_sfa", "L '\tRC-SFA\t65.64\t68.62\t71.92", {50: 65.64, 100: 68.62, 200: 71.92}),
)


def _table5_6() -> list[PaperValue]:
    out = []
    for split, method, source, values in _T56:
        for i, (nodes, value) in enumerate(values.items()):
            coords = (("selection", "minimal"), ("split", split), ("method", method))
            note = "bound right gait at all frequencies"
            if nodes is None:
                note += "; printed once across the 50N/100N/200N columns (no hidden layer)"
            else:
                coords = (*coords, ("nodes", nodes))
            out.append(entry(
                table="Tab. 5.6", artifact="table5_6", variable="accuracy", coords=coords,
                value=value, unit="percent", source=source, pos=i,
                row=f"{split.upper()} {source.split(chr(9))[1]}",
                column=f"{nodes}N" if nodes else "all", note=note,
            ))
    return out


_TAB54 = entry(
    table="Tab. 5.4", artifact="table5_4", variable="accuracy", value=None, unit="percent",
    source="Tab. 5.4: Train and test results for comparison of RC and ELM with varying number "
           "of nodes in the hidden layer (in percentage, more is better). Signal selections "
           "touch and minimal are tested, using the entire dataset.",
    pos=None, row="all", column="all",
    note="the table is an image in the thesis text: its numbers are unavailable; only the "
         "prose of §5.4.1.2 quotes it (LR > 10 % more misclassifications, RC beats ELM by "
         "about 10 % on touch)",
)

_PROSE = (
    entry(table="§5.4.1.2", artifact="table5_4", variable="lr_extra_misclassification",
          coords=(("nodes", 100),), value=10.0, unit="percent", pos=1,
          row="LR vs any other technique with 100 hidden nodes (lower bound)",
          source="From the results in Table 5.4 it is clear that the non-linearities introduced "
                 "by expanding the input sensors are necessary for a good result, as linear "
                 "regression has over 10% more misclassifications then any other technique "
                 "with 100 hidden nodes.",
          note="'over 10%': a lower bound; percent or percentage points is not stated"),
    entry(table="§5.4.1.2", artifact="table5_4", variable="rc_minus_elm_accuracy",
          coords=(("selection", "touch"),), value=10.0, unit="percent", pos=0,
          row="RC vs ELM on the touch selection",
          source="roughly 10%, and at the same time achieves the best result overall, even "
                 "while having less input information.",
          note="continues 'as RC outperforms ELM' across a figure; 'roughly'"),
    entry(table="§5.4.1.2", artifact="sec5.4.1.2", variable="minimal_dimensions", value=18.0,
          unit="1", pos=0, row="signals in the minimal selection",
          source="The results also show that given enough input signals (minimal: 18 "
                 "dimensions), RC and ELM achieve virtually the same performance."),
    entry(table="§5.4.2.1", artifact="table5_5", variable="random_sensor_accuracy", value=25.0,
          unit="percent", pos=0, row="chance level quoted",
          source="SFA2 performs relatively close to a random terrain sensor (25%), while RC-SFA "
                 "performs about 10 to 20% better.",
          note="the dataset has five terrains, so uniform chance would be 20 %"),
    entry(table="§5.4.2.1", artifact="table5_5", variable="rc_sfa_gain_low", value=10.0,
          unit="percent", pos=1, row="RC-SFA over SFA2, lower end",
          source="SFA2 performs relatively close to a random terrain sensor (25%), while RC-SFA "
                 "performs about 10 to 20% better."),
    entry(table="§5.4.2.1", artifact="table5_5", variable="rc_sfa_gain_high", value=20.0,
          unit="percent", pos=2, row="RC-SFA over SFA2, upper end",
          source="SFA2 performs relatively close to a random terrain sensor (25%), while RC-SFA "
                 "performs about 10 to 20% better."),
    entry(table="§5.4.1.1", artifact="sec5.4.1.1", variable="available_signals", value=64.0,
          unit="1", pos=2, row="signals in the dataset",
          source="We test the eight different sensor combinations ranging from 4 to 55 signals "
                 "out of 64 available in the dataset."),
)

_S531_DATA = ("The trials have a varying length, many between 3000 and 6500 samples with a "
              "sampling rate of 50Hz.")
_S531_SEL = ("Then we select a total of 3000 samples for each terrain type and do this five "
             "times.")
_S531_PARTS = ("We split all trials into parts as a final step, with lengths varying from 281 "
               "to 562 samples.")
_SETUP = (
    entry(table="§5.3.1", artifact="sec5.3.1", variable="sample_rate", value=50.0, unit="Hz",
          pos=2, row="sampling rate", source=_S531_DATA),
    entry(table="§5.3.1", artifact="sec5.3.1", variable="trial_samples_min", value=3000.0,
          unit="1", pos=0, row="trial length, lower end", source=_S531_DATA,
          note="'many between': not every trial"),
    entry(table="§5.3.1", artifact="sec5.3.1", variable="trial_samples_max", value=6500.0,
          unit="1", pos=1, row="trial length, upper end", source=_S531_DATA),
    entry(table="§5.3.1", artifact="sec5.3.1", variable="samples_per_selection", value=3000.0,
          unit="1", pos=0, row="samples per terrain in a selection", source=_S531_SEL),
    entry(table="§5.3.1", artifact="sec5.3.1", variable="part_samples_min", value=281.0,
          unit="1", pos=0, row="part length, shortest", source=_S531_PARTS),
    entry(table="§5.3.1", artifact="sec5.3.1", variable="part_samples_max", value=562.0,
          unit="1", pos=1, row="part length, longest", source=_S531_PARTS),
    entry(table="§5.3.1", artifact="sec5.3.1", variable="part_samples_typical", value=375.0,
          unit="1", pos=0, row="part length, most", source="about 375 samples long (7.5s).",
          note="the sentence 'Most of these are about 375 samples long' is split by Tab. 5.2 "
               "in the text"),
) + tuple(
    entry(table="Tab. 5.2", artifact="table5_2", variable="dimensions",
          coords=(("selection", g),), value=float(d), unit="1", pos=i,
          row="Number of dimensions", column=g,
          source="Number of dimensions\t55\t21\t18\t12\t10\t9\t8\t4")
    for i, (g, d) in enumerate(zip(_SELECTIONS, (55, 21, 18, 12, 10, 9, 8, 4))))

ENTRIES: tuple[PaperValue, ...] = (
    *_two_method_table("Tab. 5.3", "table5_3", _T53, ("lr", "rc"), {"lr": "LR", "rc": "RC"}),
    _TAB54,
    *_two_method_table("Tab. 5.5", "table5_5", _T55, ("sfa2", "rc_sfa"),
                       {"sfa2": "SFA2", "rc_sfa": "RC-SFA"}),
    *_table5_6(),
    *_PROSE,
    *_SETUP,
)
