"""Layouts of the smoke profile's chapter-2 results, checked on the datasets the smoke
pipeline wrote; see ``layouts_ch7``."""

from __future__ import annotations

import numpy as np

from thesis.store import check_result


def chirpz_scaling(ds, cfg):
    check_result(ds)
    assert ds["seconds"].dims == ("layer", "pass", "size")
    assert list(ds["size"].values) == cfg["ch2"]["bench"]["sizes"]
    assert np.all(ds["seconds"].values > 0)
    assert np.all(np.isfinite(ds["exponent_n2logn"].values))
    assert ds.attrs["thesis_ref"] == "§2.4"


CHECKS = {"ch2/chirpz_scaling": chirpz_scaling}
