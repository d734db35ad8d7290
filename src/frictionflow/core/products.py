"""Matrix-vector products into given room, for kernels compiled without numba's runtime (:data:`.options.NO_RUNTIME`).

``a @ x`` allocates its result and ``np.dot(a, x, out)`` takes the runtime;
the matrices here are the size of a structure's coordinates (a few to a few
hundred), where a loop costs less than a BLAS call.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True, inline="always")
def add_product(a, x, sign, out):
    """``out += sign a @ x`` by rows, each row's sum in index order (``sign`` +-1; an empty ``a`` adds nothing)."""
    for i in range(a.shape[0]):
        s = 0.0
        for j in range(a.shape[1]):
            s += a[i, j] * x[j]
        out[i] += sign * s


@njit(cache=True, inline="always")
def matvec(a, x, out):
    """``out[:] = a @ x`` (:func:`add_product` into zeros)."""
    for i in range(a.shape[0]):
        out[i] = 0.0
    add_product(a, x, 1.0, out)
