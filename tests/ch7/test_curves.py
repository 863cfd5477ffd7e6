"""NaN padding of learning curves of unequal length."""

import numpy as np

from thesis.ch7.curves import pad_curves


def test_pad_curves_pads_with_nan_and_truncates():
    out = pad_curves([[1.0, 2.0, 3.0], [4.0]])
    assert out.shape == (2, 3)
    np.testing.assert_array_equal(out[0], [1.0, 2.0, 3.0])
    assert out[1, 0] == 4.0 and np.isnan(out[1, 1:]).all()
    assert pad_curves([[1.0, 2.0, 3.0]], 2).tolist() == [[1.0, 2.0]]
    assert pad_curves([], None).shape == (0, 0)
