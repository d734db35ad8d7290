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

#: blocks of a combination's pattern: W's rows (one per event slot), V^-1's and V^-1 B's rows (one per mode),
#: Z^T's rows, V's rows, Z's columns (the coordinates each uses), R's rows and columns, HE's rows, the columns any
#: row of HE uses (one row), D's rows (column a when D[e, a] or D[e, n + a] is nonzero), the rows of C and K_eff
#: together and the stuck contacts' directions
W, VI, VB, ZT, V, ZC, RR, RC, HE, NEED, D, HELD, ES = range(13)
N_BLOCKS = 13


@njit(cache=True, inline="always")
def union_rows(a, b, a0, b0, ncols, pat, first):
    """Rows ``first``, ... of ``pat``: the columns c < ``ncols`` where a[i, a0 + c] or b[i, b0 + c] is nonzero."""
    for i in range(a.shape[0]):
        c = 0
        for x in range(ncols):
            if a[i, a0 + x] != 0 or b[i, b0 + x] != 0:
                c += 1
                pat[first + i, c] = x
        pat[first + i, 0] = c


@njit(cache=True, inline="always")
def rows_into(a, pat, first):
    """Rows ``first``, ... of ``pat``: the nonzero columns of each row of ``a``."""
    union_rows(a, a, 0, 0, a.shape[1], pat, first)


@njit(cache=True, inline="always")
def columns_into(a, pat, first):
    """Rows ``first``, ... of ``pat``: the rows where each column of ``a`` is nonzero."""
    for x in range(a.shape[1]):
        c = 0
        for i in range(a.shape[0]):
            if a[i, x] != 0:
                c += 1
                pat[first + x, c] = i
        pat[first + x, 0] = c


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


@njit(cache=True, inline="always")
def add_rows(a, pat, first, x, sign, out):
    """``out += sign a @ x`` over the pattern rows ``first``, ... of ``a`` (:func:`..products.add_product`'s bits)."""
    for i in range(a.shape[0]):
        out[i] += sign * sparse_dot(a, i, pat, first + i, x)


@njit(cache=True)
def combo_pattern(asm, stuck, w, vi, vb, zt, v, z, r, he, d, keff):
    """A combination's pattern (the module's docstring) from its matrices and the Assembly ``asm``."""
    n, ns, nr, m, k = z.shape[0], len(stuck), z.shape[1], vi.shape[0], w.shape[0]
    sizes = (k, m, m, nr, v.shape[0], nr, n, ns, ns, 1, d.shape[0], n, ns)
    width = max(N_BLOCKS, w.shape[1], vi.shape[1], vb.shape[1], n, v.shape[1], ns)
    starts = np.empty(N_BLOCKS, dtype=np.int32)
    row = 1
    for b in range(N_BLOCKS):
        starts[b] = row
        row += sizes[b]
    pat = new_pattern(row, width)
    pat[0, :N_BLOCKS] = starts
    rows_into(w, pat, starts[W])
    rows_into(vi, pat, starts[VI])
    rows_into(vb, pat, starts[VB])
    rows_into(zt, pat, starts[ZT])
    rows_into(v, pat, starts[V])
    columns_into(z, pat, starts[ZC])
    rows_into(r, pat, starts[RR])
    columns_into(r, pat, starts[RC])
    rows_into(he, pat, starts[HE])
    used_columns(he, pat, starts[NEED])
    union_rows(d, d, 0, n, n, pat, starts[D])
    union_rows(asm.damping, keff, 0, 0, n, pat, starts[HELD])
    rows_into(asm.contact_dir[stuck], pat, starts[ES])
    return pat
