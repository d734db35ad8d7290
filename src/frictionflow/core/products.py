"""Matrix-vector products into given room, for kernels compiled without numba's runtime (:data:`.options.NO_RUNTIME`).

``a @ x`` allocates its result and ``np.dot(a, x, out)`` takes the runtime;
the matrices here are the size of a structure's coordinates (a few to a few
hundred), where a loop costs less than a BLAS call.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True, inline="always")
def matvec(a, x, out):
    """``out[:] = a @ x`` for float64 arrays, by rows, summed in index order (an empty ``a`` gives zeros)."""
    for i in range(a.shape[0]):
        s = 0.0
        for j in range(a.shape[1]):
            s += a[i, j] * x[j]
        out[i] = s
