"""core.blas.gemv: the product ``@`` makes, into given room, from a kernel compiled without numba's runtime."""

import numpy as np
import pytest
from numba import njit

from frictionflow.core.blas import gemv
from frictionflow.core.options import NO_RUNTIME


@njit(**NO_RUNTIME)
def _into(a, x, out):
    gemv(a, x, out)


@njit
def _matmul(a, x):
    return a @ x


@pytest.mark.parametrize("dtype", [np.float64, np.complex128])
@pytest.mark.parametrize("rows, cols", [(1, 1), (3, 2), (7, 7), (10, 31), (0, 4), (4, 0)])
def test_gemv_is_the_product_at_makes(dtype, rows, cols):
    rng = np.random.default_rng(rows * 100 + cols)
    a = rng.standard_normal((rows, cols)).astype(dtype)
    x = rng.standard_normal(cols).astype(dtype)
    if dtype == np.complex128:
        a += 1j * rng.standard_normal((rows, cols))
        x += 1j * rng.standard_normal(cols)
    out = np.full(rows, np.nan, dtype=dtype)
    _into(a, x, out)
    assert np.array_equal(out, _matmul(a, x))  # numba's own product, bit for bit
    np.testing.assert_allclose(out, a @ x, rtol=1e-13, atol=1e-13 * (np.abs(a).sum() + 1.0))


def test_gemv_refuses_a_strided_matrix():
    a = np.ones((4, 6))[:, ::2]
    with pytest.raises(Exception, match="gemv"):
        _into(a, np.ones(3), np.empty(4))
