"""The nonzeros of a combination's matrices, so that the engine's sums follow them and not the matrices' sizes.

When masses stick a chain splits into pieces that do not couple: the event
map W, V^-1, V^-1 B, V and Z are then mostly exact zeros.  A pattern is an
int32 array whose row r lists the nonzeros of one matrix row (or column):
``pat[r, 0]`` of them, at ``pat[r, 1:1 + pat[r, 0]]`` in index order.  A sum
over them adds the dense sum's terms in its order less its exact zeros
(0 x finite adds +-0, which leaves a sum's bits), so the results are the
dense loops' bit for bit.

A combination's pattern (:func:`combo_pattern`, the Combo's ``nz``) stacks
the blocks below after a header row: ``nz[0, B]`` is the first row of block B.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: blocks of a combination's pattern: W's rows (one per event slot; none for an inactive slot: its function is
#: never evaluated), V's rows, Z's columns (the coordinates each uses), R's columns, HE's rows and the columns any
#: row of HE uses (one row).  (V^-1, V^-1 B and D are used once per phase, about as often as a combination is
#: built: a pattern of them costs as much as it saves.)
W, V, ZC, RC, HE, NEED = range(6)
N_BLOCKS = 6


@njit(cache=True, inline="always")
def rows_from(a, a0, pat, first, start, stop):
    """Rows ``first`` + i of ``pat``, ``start`` <= i < ``stop``: the columns c where a[i, a0 + c] is nonzero (without
    branches: the column is written at every step and kept by the count)."""
    for i in range(start, stop):
        r, c = first + i, 0
        for x in range(a.shape[1] - a0):
            pat[r, 1 + c] = x
            c += a[i, a0 + x] != 0
        pat[r, 0] = c


@njit(cache=True, inline="always")
def rows_into(a, pat, first):
    """Rows ``first``, ... of ``pat``: the nonzero columns of each row of ``a``."""
    rows_from(a, 0, pat, first, 0, a.shape[0])


@njit(cache=True, inline="always")
def columns_into(a, pat, first):
    """Rows ``first``, ... of ``pat``: the rows where each column of ``a`` is nonzero (as :func:`rows_from`)."""
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
    return add_dot(0.0, a, i, pat, r, x)


@njit(cache=True, inline="always")
def add_dot(s, a, i, pat, r, x):
    """``s`` + a[i, b] x[b] added one by one over pattern row ``r``: a dense loop's sum from ``s`` on, its bits."""
    for p in range(pat[r, 0]):
        b = pat[r, 1 + p]
        s += a[i, b] * x[b]
    return s


@njit(cache=True)
def combo_pattern(active, w, v, z, r, he):
    """A combination's pattern (the module's docstring) from its active event slots and matrices."""
    k, nr, ns = w.shape[0], z.shape[1], r.shape[1]
    first = (1, 1 + k, 1 + k + v.shape[0], 1 + k + v.shape[0] + nr, 1 + k + v.shape[0] + nr + ns,
             1 + k + v.shape[0] + nr + 2 * ns)
    pat = new_pattern(first[NEED] + 1, max(N_BLOCKS, w.shape[1], v.shape[1], z.shape[0]))
    for b in range(N_BLOCKS):
        pat[0, b] = first[b]
    for e in range(k):
        if active[e]:
            rows_from(w, 0, pat, first[W], e, e + 1)
    rows_into(v, pat, first[V])
    columns_into(z, pat, first[ZC])
    columns_into(r, pat, first[RC])
    rows_into(he, pat, first[HE])
    used_columns(he, pat, first[NEED])
    return pat
