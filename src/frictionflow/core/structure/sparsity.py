"""The nonzeros of a combination's Z and R, so that the phase's sums through them follow the nonzeros.

When masses stick, Z selects the free coordinates (one nonzero per column) and
R = M^-1 E_S^T G touches the stuck ones and their neighbours: mostly exact
zeros, over which the phase start and the state would loop.  A pattern is an
int32 array whose row r lists the nonzeros of one matrix row (or column):
``pat[r, 0]`` of them, at ``pat[r, 1:1 + pat[r, 0]]`` in index order.  A sum
over them adds the dense sum's terms in its order less its exact zeros
(0 x finite adds +-0, which leaves a sum's bits), so the results are the
dense loops' bit for bit.

A combination's pattern (:func:`combo_pattern`, the Combo's ``nz``, made
once per combination) stacks the blocks below after a header row: ``nz[0, B]``
is the first row of block B.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: blocks of a combination's pattern: Z's and R's columns (the coordinates each uses) and R's nonzero rows (one
#: row: R u0 and R b_S are zero elsewhere, so a product with them takes only those columns).  (V^-1, V^-1 B, V and
#: W are used once or a few times per phase, and most phases of a long chain start a combination not met before: a
#: pattern of them costs about as much as it saves, and the walk's sums over W's nonzeros measured slower than its
#: dense loops up to ten masses.)
ZC, RC, RU = range(3)
N_BLOCKS = 3


@njit(cache=True, inline="always")
def columns_into(a, pat, first):
    """Rows ``first``, ... of ``pat``: the rows where each column of ``a`` is nonzero (without branches: the row is
    written at every step and kept by the count)."""
    for x in range(a.shape[1]):
        r, c = first + x, 0
        for i in range(a.shape[0]):
            pat[r, 1 + c] = i
            c += a[i, x] != 0
        pat[r, 0] = c


@njit(cache=True, inline="always")
def used_columns(a, pat, r):
    """Row ``r`` of ``pat``: the columns where any row of ``a`` is nonzero."""
    c = 0
    for x in range(a.shape[1]):
        for i in range(a.shape[0]):
            if a[i, x] != 0:
                c += 1
                pat[r, c] = x
                break
    pat[r, 0] = c


@njit(cache=True)
def new_pattern(rows, n):
    """An empty pattern of ``rows`` rows of up to ``n`` nonzeros."""
    return np.zeros((rows, n + 1), dtype=np.int32)


@njit(cache=True, inline="always")
def sparse_dot(a, i, pat, r, x):
    """a[i] . x over pattern row ``r`` (a[i]'s nonzeros in index order): the dense sum's bits without its zeros."""
    s = 0.0
    for p in range(pat[r, 0]):
        b = pat[r, 1 + p]
        s += a[i, b] * x[b]
    return s


@njit(cache=True)
def combo_pattern(z, r):
    """A combination's pattern (the module's docstring) from its Z and R."""
    n, nr, ns = z.shape[0], z.shape[1], r.shape[1]
    first = (1, 1 + nr, 1 + nr + ns)
    pat = new_pattern(first[RU] + 1, max(N_BLOCKS, n))
    for b in range(N_BLOCKS):
        pat[0, b] = first[b]
    columns_into(z, pat, first[ZC])
    columns_into(r, pat, first[RC])
    used_columns(r.T, pat, first[RU])
    return pat
