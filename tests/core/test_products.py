"""core.products.matvec: a @ x into given room, from a kernel compiled without numba's runtime."""

import numpy as np
import pytest
from numba import njit

from frictionflow.core.options import NO_RUNTIME
from frictionflow.core.products import matvec


@njit(**NO_RUNTIME)
def _into(a, x, out):
    matvec(a, x, out)


@pytest.mark.parametrize("rows, cols", [(1, 1), (3, 2), (7, 7), (10, 31), (0, 4), (4, 0)])
def test_matvec_against_numpy(rows, cols):
    rng = np.random.default_rng(rows * 100 + cols)
    a, x = rng.standard_normal((rows, cols)), rng.standard_normal(cols)
    out = np.full(rows, np.nan)  # every entry written, none read: an empty a gives zeros
    _into(a, x, out)
    np.testing.assert_allclose(out, a @ x, rtol=1e-14, atol=1e-14 * (np.abs(a).sum() + 1.0))


def test_matvec_sums_in_index_order():
    """Each entry is the left-to-right sum: (1e16 + 1) - 1e16 = 0 in that order, 1 in another."""
    out = np.empty(1)
    _into(np.array([[1e16, 1.0, -1e16]]), np.ones(3), out)
    assert out[0] == (1e16 + 1.0) - 1e16
