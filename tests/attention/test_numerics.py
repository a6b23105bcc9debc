"""The compiled building blocks of ``attention._numerics`` against numpy."""

import numpy as np
from numba import njit

from attentive_gym.attention._numerics import shaped


@njit
def _shaped_2d(flat, rows, cols):
    return shaped(flat, (rows, cols))


@njit
def _shaped_3d(flat, a, b, c):
    return shaped(flat, (a, b, c))


def test_shaped_is_reshape_as_a_view_of_the_same_data():
    buffer = np.arange(40.0)
    flat = buffer[4:28]
    for view, expected in (
        (_shaped_2d(flat, 6, 4), flat.reshape(6, 4)),
        (_shaped_3d(flat, 2, 3, 4), flat.reshape(2, 3, 4)),
    ):
        assert view.shape == expected.shape and view.strides == expected.strides
        assert view.flags.c_contiguous
        np.testing.assert_array_equal(view, expected)
        assert np.shares_memory(view, buffer)
    _shaped_2d(flat, 6, 4)[1, 2] = -1.0
    assert buffer[4 + 1 * 4 + 2] == -1.0


def test_shaped_keeps_the_element_type():
    flat = np.arange(12, dtype=np.int64)
    view = _shaped_2d(flat, 3, 4)
    assert view.dtype == np.int64
    np.testing.assert_array_equal(view, flat.reshape(3, 4))
