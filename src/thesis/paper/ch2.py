"""Chapter 2 (spatial chirp-Z transformer networks): Tab. 2.2 and the §2.5 prose number.

Result artifact ``ch2/table2_2``: dims ``model`` (``ffn_spn``, ``rnn_spn``), ``d``
(down-sampling factor 1, 2, 3), ``transform`` (``bilinear``, ``bilinear_no_skew``,
``chirp_z``, ``none``); variable ``test_error`` (per-digit test error). The thesis
prints errors in percent; they are stored as printed with unit ``"percent"``.
"""

from __future__ import annotations

from thesis.paper.types import PaperValue, entry

_T = "Tab. 2.2"
_TRANSFORMS = ("bilinear", "bilinear_no_skew", "chirp_z", "none")
_HEADERS = ("bilinear", "bilinear no skew", "chirp-Z", "no spatial")

#: (model, d) -> (row as printed, errors in percent in the order of _TRANSFORMS).
#: ``None`` marks a ditto mark (") in the "no spatial" column.
_ROWS: dict[tuple[str, int], tuple[str, tuple[float | None, ...]]] = {
    ("ffn_spn", 1): ('FFN-SPN $d=1$\t4.4\t4.5\t5.0\t7.8', (4.4, 4.5, 5.0, 7.8)),
    ("ffn_spn", 2): ('FFN-SPN $d=2$\t2.0\t5.3\t3.3\t"', (2.0, 5.3, 3.3, None)),
    ("ffn_spn", 3): ('FFN-SPN $d=3$\t2.9\t3.6\t4.8\t"', (2.9, 3.6, 4.8, None)),
    ("rnn_spn", 1): ('RNN-SPN $d=1$\t1.8\t4.1\t4.1\t"', (1.8, 4.1, 4.1, None)),
    ("rnn_spn", 2): ('RNN-SPN $d=2$\t1.5\t1.7\t1.8\t"', (1.5, 1.7, 1.8, None)),
    ("rnn_spn", 3): ('RNN-SPN $d=3$\t1.8\t1.5\t2.8\t"', (1.8, 1.5, 2.8, None)),
}

_DITTO_OF = "table2_2/model=ffn_spn/d=1/transform=none/test_error"


def _table2_2() -> list[PaperValue]:
    out = []
    for (model, d), (source, values) in _ROWS.items():
        label = f"{model.upper().replace('_', '-')} d={d}"
        for i, (transform, header, value) in enumerate(zip(_TRANSFORMS, _HEADERS, values)):
            coords = (("model", model), ("d", d), ("transform", transform))
            if value is None:
                out.append(entry(
                    table=_T, artifact="table2_2", variable="test_error", coords=coords,
                    value=7.8, unit="percent", source=source, pos=None, row=label,
                    column=header, same_as=_DITTO_OF,
                    note='printed as a ditto mark ("), repeating 7.8 of row FFN-SPN d=1: '
                         "one no-spatial baseline for every model and d",
                ))
                continue
            out.append(entry(
                table=_T, artifact="table2_2", variable="test_error", coords=coords,
                value=value, unit="percent", source=source, pos=1 + i, row=label,
                column=header,
                note="per-digit test error on cluttered MNIST sequences",
            ))
    return out


ENTRIES: tuple[PaperValue, ...] = (
    *_table2_2(),
    entry(
        table="§2.5", artifact="table2_2", variable="best_test_error",
        coords=(("transform", "chirp_z"),), value=1.8, unit="percent",
        source="Also, we find that our chirp-Z approach performs similarly to the bilinear "
               "approach without skew, being able to achieve a 1.8% error rate.",
        pos=0, row="chirp-Z, best configuration", column="error rate",
        note="the best chirp-Z cell of Tab. 2.2 (RNN-SPN d=2)",
    ),
)
