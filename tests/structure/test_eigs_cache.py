"""The run's cache of block eigen-decompositions (combo.Eigs) and of the stick rule's splits.

A block met before is taken from the cache instead of LAPACK: a hit must give the very numbers
the same call would give, and a block that differs in any entry must not hit.  The splits the
stick rule reads from the run's cache are the kept combinations' own numbers.
"""

from __future__ import annotations

import numpy as np

from frictionflow import Coulomb
from frictionflow.core.structure.combo import block_eigh, build, lookup, new_cache, new_eigs
from frictionflow.core.structure.stick import candidate

from .builders import chain


def _chain_tridiagonal(k):
    """A chain's stiffness K (unit springs, ``k`` along the diagonal) with masses 3 and 6 stuck: blocks 0-2, 4-5, 7-8."""
    sym = np.diag(np.full(9, k)) - np.eye(9, k=1) - np.eye(9, k=-1)
    for a in (3, 6):
        sym[a, :], sym[:, a] = 0.0, 0.0
        sym[a, a] = k
    return sym


def test_a_hit_gives_the_numbers_of_the_call_without_the_cache():
    """The second call on the same matrix takes every block from the cache: bit for bit the uncached result, and a
    decomposition (numpy's reassembly) of the matrix."""
    sym, eigs = _chain_tridiagonal(2.0), new_eigs()
    w0, u0 = block_eigh(sym)
    w1, u1 = block_eigh(sym, eigs)
    kept = eigs.used[0]
    w2, u2 = block_eigh(sym, eigs)
    assert kept == 2  # blocks 4-5 and 7-8 are the same matrix: one entry for both (and one for block 0-2) ...
    assert eigs.used[0] == kept  # ... and nothing new is kept on the second call
    for w, u in ((w1, u1), (w2, u2)):
        assert np.array_equal(w, w0) and np.array_equal(u, u0)
    assert np.allclose(u2 @ np.diag(w2) @ u2.T, sym, atol=1e-14, rtol=0)


def test_a_block_with_the_same_coordinates_and_other_entries_does_not_hit():
    """Same blocks (coordinates and pattern), another diagonal: the cache must not answer with the first matrix's
    modes; the result is the uncached one of the new matrix."""
    eigs = new_eigs()
    first = _chain_tridiagonal(2.0)
    block_eigh(first, eigs)
    other = first.copy()
    other[1, 1] = 2.0 + 1e-12  # one entry of one block, by a rounding-sized amount
    w, u = block_eigh(other, eigs)
    w_ref, u_ref = block_eigh(other)
    assert np.array_equal(w, w_ref) and np.array_equal(u, u_ref)
    assert not np.array_equal(w, block_eigh(first)[0])
    kept = eigs.used[0]
    signed = first.copy()
    signed[0, 2] = signed[2, 0] = -0.0  # inside block 0-2 (joined by its other entries): only the sign bit differs
    assert np.array_equal(block_eigh(signed, eigs)[1], block_eigh(signed)[1])
    assert eigs.used[0] == kept + 1  # not a hit: the sign bit is part of the key


def test_builds_with_and_without_the_cache_are_identical():
    """Every combination of a seven-mass chain built through the run's cache (blocks met before reused) equals the
    one built without it, array for array."""
    asm = chain(7, Coulomb(0.2, 0.4), 0.1, c=0.04)
    minv = np.linalg.inv(asm.mass)
    cache = new_cache(asm, minv)
    rng = np.random.default_rng(5)
    asked = [rng.choice(np.array([-1, 0, 1], dtype=np.int8), 7) for _ in range(40)]
    for modes in asked:
        cb, ref = lookup(cache, asm, minv, modes), build(asm, minv, modes)
        for name in ("lam", "V", "Vi", "VB", "W", "WA", "b1", "bh"):
            assert np.array_equal(getattr(cb, name), getattr(ref, name)), name
    runs = 0  # the free stretches of two or more masses (the blocks of size > 1) of the combinations built
    for modes in {tuple(m) for m in asked} | {(0,) * 7}:
        stretches = "".join("x" if m else "." for m in modes).split(".")
        runs += sum(len(s) > 1 for s in stretches)
    assert 0 < cache.eigs.used[0] < runs  # some blocks were taken from the cache


def test_the_stick_rule_reads_the_kept_combinations_numbers():
    """A cached combination's split (same modes, or the same stuck set with other slip directions) holds the numbers
    a fresh build gives."""
    asm = chain(5, Coulomb(0.2, 0.4), 0.1)
    minv = np.linalg.inv(asm.mass)
    cache = new_cache(asm, minv)
    lookup(cache, asm, minv, np.array([0, 1, 0, -1, 1], dtype=np.int8))
    for modes in ([0, 1, 0, -1, 1], [0, -1, 0, 1, 1]):
        modes = np.array(modes, dtype=np.int8)
        sp, ref = candidate(asm, minv, modes, cache), build(asm, minv, modes)
        assert np.array_equal(sp.modes, modes)
        for name in ("stuck", "R", "HE", "keff", "f0"):
            assert np.array_equal(getattr(sp, name), getattr(ref, name)), name
